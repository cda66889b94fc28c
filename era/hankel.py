"""The generalized block Hankel matrix of eq. 16, with arbitrary row and column shifts."""

from __future__ import annotations

import numpy as np

from .blas import single_threaded_blas
from .errors import HankelError

#: Largest H(0) built, in matrix elements (8 bytes each): 2e8 elements is 1.6 GB, and H(1) is as large.
MAX_HANKEL_ELEMENTS = 200_000_000


def shifts(count: int, given, name: str) -> np.ndarray:
    """The shift sequence (0, j_1, ..., j_{count-1}) of eq. 16 as an int array of length ``count``.

    ``given`` holds the ``count - 1`` shifts after the leading 0 (the paper's j_i or t_i);
    None means the consecutive default j_i = i. ``count`` is a validated positive integer.
    """
    if given is None:
        return np.arange(count)
    arr = np.asarray(given)
    if arr.ndim != 1 or (arr.size and not np.issubdtype(arr.dtype, np.integer)):
        if arr.ndim == 1 and arr.size and np.all(np.mod(arr, 1) == 0):
            arr = arr.astype(int)
        else:
            raise HankelError(f"`{name}` must be a 1-D list of integers (sample counts), got {given!r}.")
    if arr.size != count - 1:
        raise HankelError(
            f"`{name}` has {arr.size} entries but {count - 1} are needed: one per block after the first "
            f"(the first block has shift 0)."
        )
    full = np.concatenate([[0], arr.astype(int)])
    if np.any(np.diff(full) <= 0):
        bad = int(np.argmax(np.diff(full) <= 0))
        raise HankelError(
            f"`{name}` must be strictly increasing positive integers; entry {bad} ({full[bad + 1]}) does not "
            f"exceed the one before it ({full[bad]})."
        )
    return full


def samples_needed(row_shifts: np.ndarray, col_shifts: np.ndarray) -> int:
    """Samples N that H(0) and H(1) need: Y(k) for k up to j_{r-1} + t_{s-1} + 1."""
    return int(row_shifts[-1] + col_shifts[-1] + 2)


def block_hankel(markov: np.ndarray, row_shifts: np.ndarray, col_shifts: np.ndarray, k: int = 0) -> np.ndarray:
    """H(k) of eq. 16: block (i, j) is Y(k + j_i + t_j).

    Parameters
    ----------
    markov : ndarray, shape (N, p, m)
        Y(0..N-1).
    row_shifts, col_shifts : int ndarray, shapes (r,) and (s,)
        (0, j_1, ..., j_{r-1}) and (0, t_1, ..., t_{s-1}).
    k : int
        The time shift (0 for H(0), 1 for H(1)).

    Returns
    -------
    ndarray, shape (r p, s m)
        A new C-contiguous array (the one copy the SVD needs).
    """
    n, p, m = markov.shape
    r, s = len(row_shifts), len(col_shifts)
    idx = k + row_shifts[:, None] + col_shifts[None, :]
    if idx.max() >= n:
        raise HankelError(f"H({k}) needs Y({idx.max()}) but only {n} samples are given.")
    out = np.empty((r, p, s, m))
    # One gather per block row writes straight into the output: no (r, s, p, m) temporary.
    for i in range(r):
        out[i] = markov[idx[i]].transpose(1, 0, 2)
    return out.reshape(r * p, s * m)


def check_size(n_samples: int, p: int, m: int, row_shifts: np.ndarray, col_shifts: np.ndarray) -> None:
    """Raise a HankelError that says what fits when the data or the memory limit cannot hold H(0), H(1)."""
    need = samples_needed(row_shifts, col_shifts)
    r, s = len(row_shifts), len(col_shifts)
    if need > n_samples:
        room = n_samples - 2  # j_{r-1} + t_{s-1} may be at most N - 2
        hint = ""
        if r > 1 and s > 1 and room >= 2 and row_shifts[-1] == r - 1 and col_shifts[-1] == s - 1:
            hint = f" With consecutive shifts, rows + cols may be at most {room + 2} (e.g. rows={(room + 2) // 2}, cols={(room + 2) - (room + 2) // 2})."
        raise HankelError(
            f"The Hankel matrices need {need} samples (largest row shift {row_shifts[-1]} + largest column "
            f"shift {col_shifts[-1]} + 2) but the data have {n_samples}. Use fewer rows/columns or smaller "
            f"shifts, or give longer records.{hint}"
        )
    elements = r * p * s * m
    if elements > MAX_HANKEL_ELEMENTS:
        raise HankelError(
            f"H(0) would be {r * p} × {s * m} = {elements:.3g} elements, above the limit of "
            f"{MAX_HANKEL_ELEMENTS:.3g} ({MAX_HANKEL_ELEMENTS * 8 / 1e9:.1f} GB each for H(0) and H(1)). "
            f"Reduce rows or cols so that rows·p × cols·m stays below it."
        )


def gram(markov: np.ndarray, row_shifts: np.ndarray, col_shifts: np.ndarray, h0: np.ndarray) -> np.ndarray:
    """The Gram matrix of the shorter side of H(0) = ``h0``: H H^T (r p × r p) when r p ≤ s m, else H^T H.

    With consecutive shifts (the default) it is built by the Hankel recursion instead of a product: block
    (i + 1, j + 1) of H H^T is block (i, j) plus Y(i + s) Y(j + s)^T minus Y(i) Y(j)^T (the window of column
    shifts slides by one sample), so only the first block row is a product (p × s m times s m × r p) and each
    further block row costs two products of rank m: r p · r p · m work instead of (r p)² s m / 2 for the
    product (about 1/100 of it for H(0) 900 × 2392). Its round-off, r additions of terms no larger than the
    entries, is of the order of the product's. Upper triangle computed, mirrored (exactly symmetric).
    Other shifts: ``h0 @ h0.T`` (or ``h0.T @ h0``).

    Returns
    -------
    (min(shape), min(shape)) symmetric ndarray.
    """
    rows, cols = h0.shape
    consecutive = np.array_equal(row_shifts, np.arange(len(row_shifts))) and \
        np.array_equal(col_shifts, np.arange(len(col_shifts)))
    if not consecutive:
        return h0 @ h0.T if rows <= cols else h0.T @ h0
    with single_threaded_blas():   # a thin product and rank-m updates: slower with 2 threads (era.blas)
        if rows <= cols:
            return _sliding_gram(markov, len(row_shifts), len(col_shifts), h0[:markov.shape[1]] @ h0.T)
        # H^T is the block Hankel matrix of the transposed blocks Y(k)^T with the roles of rows and columns swapped
        return _sliding_gram(markov.transpose(0, 2, 1), len(col_shifts), len(row_shifts),
                             h0[:, :markov.shape[2]].T @ h0)


def _sliding_gram(y: np.ndarray, r: int, s: int, first: np.ndarray) -> np.ndarray:
    """H H^T for H with consecutive shifts (block (i, k) = Y(i + k), r × s blocks of p × m) from its first block
    row ``first`` (p, r p) by G_{i+1, j+1} = G_{i, j} + Y(i + s) Y(j + s)^T - Y(i) Y(j)^T."""
    p, m = y.shape[1], y.shape[2]
    g = np.empty((r * p, r * p))
    g[:p] = first
    for i in range(r - 1):
        later = y[i + s:r - 1 + s].transpose(2, 0, 1).reshape(m, -1)  # [Y(j + s)^T]_j for j = i..r-2
        early = y[i:r - 1].transpose(2, 0, 1).reshape(m, -1)
        g[(i + 1) * p:(i + 2) * p, (i + 1) * p:] = (g[i * p:(i + 1) * p, i * p:(r - 1) * p]
                                                     + y[i + s] @ later - y[i] @ early)
    return _mirror_upper(g)


def _mirror_upper(g: np.ndarray, block: int = 64) -> np.ndarray:
    """``g`` (a, a) made exactly symmetric from its upper triangle, in place, by square tiles (a transposed
    copy of the upper triangle in one fancy-indexed step is 3× slower at a = 900)."""
    a = g.shape[0]
    for i in range(0, a, block):
        g[i + block:, i:i + block] = g[i:i + block, i + block:].T
        tile = g[i:i + block, i:i + block]
        lower = np.tril_indices(tile.shape[0], -1)
        tile[lower] = tile.T[lower]
    return g
