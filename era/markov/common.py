"""Checks shared by the pulse-response builders: time records in, finite real 2-D arrays out."""

from __future__ import annotations

import numpy as np

from ..errors import DataError
from ..words import counted


def records(value, name: str) -> list[np.ndarray]:
    """One (N, c) record or a list of them (several tests of one structure) as a list of float (N_r, c) arrays."""
    items = list(value) if isinstance(value, (list, tuple)) else [value]
    if not items:
        raise DataError(f"`{name}` is empty; give an (N, channels) array or a list of them.")
    out = []
    for r, item in enumerate(items):
        a = np.asarray(item)
        if a.dtype == object or not np.issubdtype(a.dtype, np.number) or np.iscomplexobj(a):
            raise DataError(f"`{name}` record {r}: expected real numbers, got {a.dtype}.")
        if a.ndim == 1:
            a = a[:, None]
        if a.ndim != 2 or min(a.shape) == 0:
            raise DataError(f"`{name}` record {r} has shape {a.shape}; expected (N samples, channels).")
        a = np.asarray(a, dtype=float)
        bad = ~np.isfinite(a)
        if bad.any():
            k, c = np.argwhere(bad)[0]
            raise DataError(f"`{name}` record {r} holds {counted(bad.sum(), 'NaN or infinite value')}, the first at "
                            f"sample {k}, channel {c}; remove or interpolate them first.")
        out.append(a)
    widths = {a.shape[1] for a in out}
    if len(widths) > 1:
        raise DataError(f"`{name}` records have different channel counts {sorted(widths)}; every record must hold "
                        "the same channels.")
    return out


def check_dt(dt) -> float:
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise DataError(f"`dt` must be a number of seconds, got {dt!r}.") from None
    if not np.isfinite(dt) or dt <= 0:
        raise DataError(f"`dt` must be a positive, finite sampling interval in seconds, got {dt!r}.")
    return dt


def positive_int(value, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise DataError(f"`{name}` must be a positive integer, got {value!r}.")
    return int(value)


def uneven_step(x: np.ndarray, resolution: float = 0.0) -> tuple[float, int | None]:
    """The sampling step of an abscissa (time or frequency) and the index of the first step that breaks it.

    ``resolution`` is how finely the values were written (e.g. 1e-6 s for times printed with 6 decimals): steps may
    jitter by that much, and by 1e-4 of a step, around the line x0 + k·h. Anything more is a gap, a repeat or a
    restart. Returns (h, None) for an even abscissa, (typical step, i) when step x[i+1] - x[i] is the first bad one.
    """
    steps = np.diff(x)
    typical = float(np.median(steps))
    if typical <= 0:
        return typical, int(np.argmax(steps <= 0))
    tol = max(1e-4 * typical, float(resolution))
    # two rounded values make a step, and the median step is rounded too: steps may differ by 2 resolutions
    bad = np.flatnonzero(np.abs(steps - typical) > 2 * tol)
    if bad.size:
        return typical, int(bad[0])
    h = float(x[-1] - x[0]) / (len(x) - 1)  # the fit through the ends: rounding errors average out
    drift = np.abs(x - (x[0] + h * np.arange(len(x))))
    if drift.max() > tol:
        return typical, max(int(np.argmax(drift)) - 1, 0)
    return h, None


#: at most this many per-record estimates are kept (ResponseData.records): more records are averaged in groups
#: (batch means, whose scatter estimates the same covariance of the overall mean with fewer degrees of freedom),
#: which bounds the memory and the cost of σ (each kept estimate is one more error set in era.core.uncertainty).
MAX_KEPT_RECORDS = 20
#: and at most this many values in all (40 MB of float64).
MAX_KEPT_VALUES = 5_000_000


def kept_records(estimates: np.ndarray) -> np.ndarray | None:
    """The per-record estimates (n_b, N, p, m) to keep beside their mean: as given, or averaged over
    consecutive groups of records (sizes differing by at most one) so that at most MAX_KEPT_RECORDS estimates
    and MAX_KEPT_VALUES values are kept; None when fewer than era.core.uncertainty.MIN_RECORDS would remain (too few
    for σ: the residual blocks are used then)."""
    from ..core.uncertainty import MIN_RECORDS

    n_b = estimates.shape[0]
    each = int(np.prod(estimates.shape[1:]))
    groups = min(n_b, MAX_KEPT_RECORDS, MAX_KEPT_VALUES // max(each, 1))
    if groups < MIN_RECORDS:
        return None
    if groups == n_b:
        return estimates
    return np.stack([part.mean(axis=0) for part in np.array_split(estimates, groups)])
