"""Starting points for a person choosing ERA's parameters: a Hankel size from the data's shape, and a model
order from the singular values (the δ test of eqs. 38-39, with a noise floor estimated from the spectrum)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import DataError


@dataclass(frozen=True)
class HankelChoice:
    """Suggested rows r and columns s (consecutive shifts) and the largest order worth realizing."""

    rows: int
    cols: int
    max_order: int


def order_cap(rows: int, cols: int, n_outputs: int, n_inputs: int, limit: int | None = None) -> int:
    """The largest order a Hankel matrix of ``rows`` × ``cols`` blocks can realize, min(r·p, s·m), and at most
    ``limit`` (e.g. a server's ERA_MAX_ORDER) when given. The rank of H(0) is no larger."""
    cap = min(int(rows) * int(n_outputs), int(cols) * int(n_inputs))
    return int(cap if limit is None else min(cap, int(limit)))


def hankel_size(n_samples: int, n_outputs: int, n_inputs: int, *, max_side: int = 800,
                max_elements: int = 25_000_000, max_order: int = 200) -> HankelChoice:
    """Rows and columns that use most of the record without an oversized matrix.

    About 45 % of the N samples go to each side (consecutive shifts need r + s ≤ N), capped so that H(0)
    (r p × s m) has at most ``max_side`` rows and columns and ``max_elements`` elements. For the paper's
    Case I (N = 200, p = m = 1) this gives r = s = 90, the paper's choice.
    """
    n, p, m = int(n_samples), int(n_outputs), int(n_inputs)
    if n < 3 or p < 1 or m < 1:
        raise DataError(f"{n} samples of {p} outputs × {m} inputs are too few for a Hankel matrix (need N ≥ 3).")
    rows = max(1, min(int(0.45 * n), max_side // p))
    cols = max(1, min(int(0.45 * n), max_side // m, n - rows))
    while rows * p * cols * m > max_elements and (rows > 1 or cols > 1):
        if rows * p >= cols * m and rows > 1:
            rows -= max(1, rows // 10)
        else:
            cols -= max(1, cols // 10)
    return HankelChoice(rows=rows, cols=cols, max_order=order_cap(rows, cols, p, m, max_order))


def order_from_singular_values(singular_values, max_order: int | None = None, *, noise_factor: float = 10.0) -> int:
    """A model order n: the number of singular values clearly above the noise floor (eqs. 38-39).

    The floor is the median of the smaller half of the singular values (what noise and round-off leave);
    d_i counts when d_i > noise_factor × floor and d_i > 1e-12 d_1. The result is rounded up to an even
    number (modes come as conjugate pairs) and kept within [1, max_order].

    Parameters
    ----------
    singular_values : (k,) descending
    max_order : int, optional
        The largest order that can be realized.
    """
    d = np.asarray(singular_values, dtype=float).reshape(-1)
    cap = d.size if max_order is None else int(min(max_order, d.size))
    if d.size == 0 or d[0] <= 0 or cap < 1:
        return 1
    floor = float(np.median(d[d.size // 2:])) if d.size >= 4 else 0.0
    n = int(np.count_nonzero((d > noise_factor * floor) & (d > 1e-12 * d[0])))
    n += n % 2
    return int(min(max(n, 1), cap))
