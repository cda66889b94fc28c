"""Evenly sampled or refused: the sampling step of a time column (or X column) as a file prints it.

A printed value is the true time rounded to the digits shown, so two printed values may differ from the true
step by at most half a digit each. :func:`printed_resolution` finds each value's own last digit (a value whose
trailing zeros were dropped, such as "0" or "0.1" among "0.09", "0.11", borrows its neighbours' digit: a "0" does
not make the whole column coarse). :func:`even_step` then accepts a column only when every step and every sample's
distance from the straight line through the ends stays within that rounding: a gap, a repeat, a restart or a drift
of the rate is an error naming the line and the step, whatever the precision printed.
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

    Rounded to a digit r, the steps of an even column take at most two values one digit apart, so every step must
    lie within r of the median step (and within half a step: a column printed more coarsely than half its step
    cannot show a dropped sample, and is refused); then no sample may stray from the line through the ends by more
    than its rounding (a sampling rate that changes slowly).
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
    digit = np.maximum(np.maximum(res[:-1], res[1:]), float(np.median(res)))
    tol = np.minimum(digit, 0.5 * typical) * (1 + 1e-9) + _RELATIVE * typical
    off = np.abs(steps - typical) > tol
    if off.any():
        k = int(np.argmax(off))
        coarse = " (the times are printed too coarsely to tell)" if np.median(res) > 0.5 * typical else ""
        what = "time step" if unit == "s" else "line spacing"
        raise DataError(f"{where}, {place(k)}: the {what} is {steps[k]:.6g} {unit} where the typical step is "
                        f"{typical:.6g} {unit} (from {t[k]:.10g} to {t[k + 1]:.10g}){coarse}; samples must be evenly "
                        "spaced (no gaps, no repeats, one sampling rate). Resample the record, or load the part "
                        "before that line.")
    h = float(t[-1] - t[0]) / (n - 1)
    k = np.arange(n) - (n - 1) / 2
    fitted = float(k @ (t - t.mean()) / (k @ k))  # least squares: the rounding averages out over all samples
    drift = np.abs(t - (t[0] + h * np.arange(n)))
    allowed = (res / 2 + (res[0] + res[-1]) / 2) * (1 + 1e-9) + 2 * _RELATIVE * h
    if np.any(drift > allowed):
        k = max(int(np.argmax(drift - allowed)) - 1, 0)
        raise DataError(f"{where}, {place(k)}: the samples drift {drift[k + 1]:.3g} {unit} off an even step of "
                        f"{h:.6g} {unit}: the sampling rate changes within the record. Resample it first.")
    return fitted


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
