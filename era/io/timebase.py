"""Evenly sampled or refused: the sampling step of a time column (or X column) as a file prints it.

A printed value is the true time rounded to the digits shown, so two printed values may differ from the true
step by at most half a digit each. :func:`printed_resolution` finds each value's own last digit (a value whose
trailing zeros were dropped, such as "0" or "0.1" among "0.09", "0.11", borrows its neighbours' digit: a "0" does
not make the whole column coarse). :func:`even_step` then accepts a column only when every sample lies within its
printed digit of the least-squares line through all of them (the step is estimated over the whole record, not from
its ends): a gap or a repeat is an error naming the line, whatever the precision printed; stamps that scatter about
a steady rate with no sample missing (a jittered or wandering clock) raise :class:`UnevenClock`, which a reader may
answer with :func:`resample` when the caller asked for it, and never otherwise.
"""

from __future__ import annotations

import numpy as np

from ..errors import DataError

#: Relative jitter always allowed (a float column computed as k·Δt carries round-off of this order).
_RELATIVE = 1e-6


def printed_resolution(cells) -> np.ndarray:
    """(n,) the last printed digit of each time value, in its unit: 1e-6 for '0.000391', 1e-9 for '3.906e-06'.

    Printers that drop trailing zeros (%g, shortest repr) print '2.99' for 2.99000: a value is taken to be as
    precise as the finest value of its decade (1 ≤ |t| < 10, ...), and a zero as precise as its neighbours.
    """
    text = np.char.lower(np.char.strip(np.asarray(cells, dtype=str)))
    if text.size == 0:
        return np.zeros(0)
    mantissa, _, exponent = np.char.partition(text, "e").T
    dot = np.char.find(mantissa, ".")
    dot = np.where(dot < 0, np.char.find(mantissa, ","), dot)
    decimals = np.where(dot < 0, 0, np.char.str_len(mantissa) - dot - 1)
    power = np.zeros(len(text))
    given = np.char.str_len(exponent) > 0
    try:
        power[given] = exponent[given].astype(float)
        value = np.char.replace(mantissa, ",", ".").astype(float) * 10.0 ** power
    except ValueError:  # not numbers at all: the parse of the values reports them
        return 10.0 ** (power - decimals)
    res = 10.0 ** (power - decimals)
    with np.errstate(divide="ignore"):
        decade = np.floor(np.log10(np.abs(value)))
    for d in np.unique(decade[np.isfinite(decade)]):
        members = decade == d
        res[members] = res[members].min()
    zero = ~np.isfinite(decade)
    if zero.any() and len(res) > 1:
        finite = np.flatnonzero(~zero)
        if finite.size:
            nearest = finite[np.clip(np.searchsorted(finite, np.flatnonzero(zero)), 0, finite.size - 1)]
            res[zero] = np.minimum(res[zero], res[nearest])
    return res


def binary_resolution(t: np.ndarray) -> np.ndarray:
    """(n,) the rounding of a stored binary time vector: a few units in the last place of its dtype."""
    t = np.asarray(t)
    dtype = t.dtype if np.issubdtype(t.dtype, np.floating) else np.float64
    return 4 * np.spacing(np.abs(t).astype(dtype)).astype(float)


def even_step(t: np.ndarray, resolution, where: str, lines=None, unit: str = "s") -> float:
    """The sampling step of ``t`` (n,), or DataError when the samples are not evenly spaced.

    resolution : scalar or (n,) rounding of each value (see :func:`printed_resolution`, :func:`binary_resolution`).
    where : the file (and column) for messages; lines : (n,) line number of each value in the file, or None
    (samples are then counted from 0). Returns the least-squares step through all values (the rounding of the
    printed digits averages out).

    A step more than half a step off the median is a missing (or misplaced) sample: refused, naming the line.
    Otherwise the column is even when no sample strays from the least-squares line through all of them by more
    than its printed digit (times saved with 7 significant digits are even to within that digit; a column printed
    more coarsely than half its step cannot show a dropped sample, and is refused). Stamps that scatter further,
    with no sample missing, raise :class:`UnevenClock` (option "resample"): a jittered or wandering clock, which
    the caller may resample onto an even grid at the mean rate (:func:`resample`), never silently.
    """
    t = np.asarray(t, dtype=float)
    n = len(t)
    if n < 2:
        raise DataError(f"{where}: a single sample; a time axis needs at least two.")
    # a value parsed into a float is also rounded to the float (seconds since 1904 keep ~0.5 µs)
    res = np.maximum(np.broadcast_to(np.asarray(resolution, dtype=float), (n,)), 2 * np.spacing(np.abs(t)))
    steps = np.diff(t)

    def place(k):  # the line (or sample) where step k ends
        return f"line {lines[k + 1]}" if lines is not None else f"sample {k + 1}"

    bad_order = np.flatnonzero(steps <= 0)
    if bad_order.size:
        k = int(bad_order[0])
        axis = "time" if unit == "s" else "abscissa"
        raise DataError(f"{where}, {place(k)}: the {axis} goes from {t[k]:.10g} to {t[k + 1]:.10g} {unit} (a repeat or "
                        "a restart); samples must be evenly spaced and increasing. Split the file at that point or "
                        "remove the repeated samples.")
    typical = float(np.median(steps))
    k = np.arange(n) - (n - 1) / 2
    fitted = float(k @ (t - t.mean()) / (k @ k))  # least squares: the rounding averages out over all samples
    skipped = np.flatnonzero(np.abs(steps - typical) > 0.5 * typical)
    if skipped.size:  # a missing sample (a step of two) or a stamp out of place: never resampled over
        k = int(skipped[0])
        what = "time step" if unit == "s" else "line spacing"
        missing = round(steps[k] / typical) - 1
        why = (f"{missing} sample{'s are' if missing > 1 else ' is'} missing" if missing >= 1 and
               abs(steps[k] / typical - round(steps[k] / typical)) < 0.25 else "a sample out of place")
        raise DataError(f"{where}, {place(k)}: the {what} is {steps[k]:.6g} {unit} where the typical step is "
                        f"{typical:.6g} {unit} (from {t[k]:.10g} to {t[k + 1]:.10g}): {why}; samples must be evenly "
                        "spaced (no gaps, no repeats, one sampling rate). Load the part before that line, or fill "
                        "the gap.")
    digit = np.maximum(np.maximum(res[:-1], res[1:]), float(np.median(res)))
    tol = np.minimum(digit, 0.5 * typical) * (1 + 1e-9) + _RELATIVE * typical
    off = np.abs(steps - typical) > tol
    # evenness is judged against the line through all samples, within each stamp's printed digit (and its neighbours'
    # median: a short value borrows theirs); a step estimate from the ends alone carries the ends' rounding
    line = t.mean() + fitted * k
    scatter = np.abs(t - line)
    allowed = np.maximum(res, float(np.median(res))) * (1 + 1e-9) + 2 * _RELATIVE * abs(fitted)
    coarse = np.median(res) > 0.5 * typical
    if not np.any(scatter > allowed) and not (coarse and off.any()):
        return fitted
    if unit != "s" or coarse:
        j = int(np.argmax(off)) if off.any() else max(int(np.argmax(scatter - allowed)) - 1, 0)
        coarse = " (the times are printed too coarsely to tell)" if coarse else ""
        raise DataError(f"{where}, {place(j)}: the line spacing is {steps[j]:.6g} {unit} where the typical step is "
                        f"{typical:.6g} {unit} (from {t[j]:.10g} to {t[j + 1]:.10g}){coarse}; samples must be evenly "
                        "spaced. Resample the record, or load the part before that line.")
    # no sample missing or repeated: a clock that stamps with jitter, or whose rate wanders (a phone's sensors)
    if off.any():
        j = int(np.argmax(off))
        head = (f"{where}, {place(j)}: the time step is {steps[j]:.6g} s where the typical step is {typical:.6g} s "
                f"(from {t[j]:.10g} to {t[j + 1]:.10g})")
    else:
        j = max(int(np.argmax(scatter - allowed)) - 1, 0)
        head = (f"{where}, {place(j)}: the samples drift {scatter[j + 1]:.3g} s off an even step of {fitted:.6g} s: "
                "the sampling rate changes within the record")
    raise UnevenClock(f"{head}. No sample is missing or repeated: the time stamps scatter up to "
                      f"{float(scatter.max()) * 1e6:.3g} µs about a steady rate of {1 / fitted:.6g} Hz "
                      f"(Δt = {fitted:.6g} s). Resample onto an even grid at that rate, or load an evenly sampled "
                      "record.", option="resample", step=fitted)


class UnevenClock(DataError):
    """Time stamps that scatter about a steady rate, no sample missing or repeated: the record may be resampled
    onto an even grid (:func:`resample`). step : the mean step (least squares, s)."""

    def __init__(self, *args, option: str | None = None, step: float = 0.0):
        super().__init__(*args, option=option)
        self.step = step

    def __reduce__(self):
        return _rebuild_clock, (self.args, self.option, self.step)


def _rebuild_clock(args, option, step):
    return UnevenClock(*args, option=option, step=step)


def resample(t: np.ndarray, y: np.ndarray, step: float) -> tuple[np.ndarray, str]:
    """(y on the even grid t[0] + k·step over the span of t, what was done): y (n, c) sampled at t (n,) s,
    linearly interpolated (the grid stays inside the stamps, so nothing is extrapolated)."""
    t = np.asarray(t, dtype=float)
    first = float(t[0])
    n = int(np.floor((float(t[-1]) - first) / step * (1 + 1e-12))) + 1
    grid = first + step * np.arange(n)
    out = np.column_stack([np.interp(grid, t, y[:, c]) for c in range(y.shape[1])]) if y.shape[1] else \
        np.zeros((n, 0))
    worst = float(np.max(np.abs(t[: min(len(t), n)] - grid[: min(len(t), n)])))
    return out, (f"resampled onto an even grid at the mean rate {1 / step:.6g} Hz (Δt = {step:.6g} s, least squares "
                 f"over {len(t)} time stamps; linear interpolation, the stamps were up to {worst * 1e6:.3g} µs off "
                 f"it): {len(t)} → {n} samples")


def even_step_printed(t: np.ndarray, sample_cells: list[str], all_cells, where: str, lines=None,
                      unit: str = "s") -> float:
    """:func:`even_step` of a printed column, reading every value's digits only when needed.

    sample_cells : the printed first and last values (a few hundred); all_cells : () -> every printed value.
    A column that is even to the finest digit of the sample is even to its own digits (printed magnitudes grow
    along a time column, so no value is printed more finely than both ends); only a column that fails this cheap
    test has its verdict, and its message, taken from every value's own digits.
    """
    try:
        return even_step(t, float(printed_resolution(sample_cells).min()), where, lines, unit)
    except DataError:
        return even_step(t, printed_resolution(all_cells()), where, lines, unit)
