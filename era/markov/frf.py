"""Frequency response functions -> pulse response (Markov parameters) by inverse FFT.

The FRF H(f) of a hammer or shaker test is the Fourier transform of the continuous impulse response h(t).
Sampled on f_k = k·Δf from 0 to f_max, its inverse real FFT over N = 2(K-1) points is h(t)·Δτ at t = kΔτ,
Δτ = 1/(2 f_max): exactly the pulse response of the sampled system to a unit pulse, i.e. the Markov
parameters Y(k) of eq. 15 (Y(0) = D, the direct term, dropped).
"""

from __future__ import annotations

import numpy as np

from ..core.data import ResponseData
from ..errors import DataError
from ..words import counted
from .common import uneven_step

#: Power of iω that turns displacement into each quantity: receptance (x/F), mobility (v/F), accelerance (a/F).
FRF_TYPES = {"receptance": 0, "mobility": 1, "accelerance": 2}
QUANTITY_OF_TYPE = {"receptance": "displacement", "mobility": "velocity", "accelerance": "acceleration"}
_POWER_OF_QUANTITY = {"displacement": 0, "velocity": 1, "acceleration": 2}


def _as_frf(frf) -> np.ndarray:
    h = np.asarray(frf)
    if h.dtype == object or not np.issubdtype(h.dtype, np.number):
        raise DataError("`frf` must be a numeric (complex) array of shape (n_freq, p, m).")
    if h.ndim == 1:
        h = h[:, None, None]
    elif h.ndim == 2:
        h = h[:, :, None]
    elif h.ndim != 3:
        raise DataError(f"`frf` has {h.ndim} dimensions; expected (n_freq, p, m): frequency lines × outputs × "
                        "inputs.")
    h = h.astype(complex)
    bad = ~np.isfinite(h)
    if bad.any():
        k, i, j = np.argwhere(bad)[0]
        raise DataError(f"`frf` holds {counted(bad.sum(), 'NaN or infinite value')}, the first at frequency line {k}, "
                        f"output {i}, input {j}; remove or interpolate them first.")
    return h


def frequency_grid(frequencies_hz, n_lines: int) -> tuple[float, int]:
    """Check that the frequencies are evenly spaced and return (Δf in Hz, index of the first line from 0 Hz).

    Frequencies may start above 0 Hz at a whole multiple of Δf (the missing low lines are filled with zeros).
    """
    f = np.asarray(frequencies_hz, dtype=float).reshape(-1)
    if f.size != n_lines:
        raise DataError(f"{f.size} frequencies for {n_lines} FRF lines; give one frequency per line of `frf`.")
    if f.size < 3:
        raise DataError(f"Only {f.size} frequency lines; an FRF needs many lines (hundreds) to give a pulse response.")
    if not np.isfinite(f).all():
        raise DataError("`frequencies_hz` holds NaN or infinite values.")
    df, worst = uneven_step(f, 1e-6 * abs(f[-1]))  # frequencies printed with 7 significant digits or more
    if worst is not None:
        raise DataError(f"Frequencies are not evenly spaced: the step after line {worst} ({f[worst]:g} Hz) is "
                        f"{f[worst + 1] - f[worst]:g} Hz, the typical step {df:g} Hz. Resample the FRF on an even "
                        "grid first.")
    first = f[0] / df
    if f[0] < -1e-9 * df or abs(first - round(first)) > 1e-3:
        raise DataError(f"The first frequency {f[0]:g} Hz is not a whole multiple of the step {df:g} Hz; the inverse "
                        "FFT needs lines at 0, Δf, 2Δf, ... Hz.")
    return df, int(round(first))


def markov_from_frf(frequencies_hz, frf, *, frf_type: str | None = None, to: str | None = None,
                    band_hz: tuple[float, float] | None = None, taper_hz: float | None = None,
                    n_samples: int | None = None, outputs=None, inputs=None, output_units=None,
                    input_units=None) -> ResponseData:
    """Pulse response (Markov parameters) from FRFs by inverse FFT.

    Parameters
    ----------
    frequencies_hz : (K,) float
        Evenly spaced lines f_k = k Δf in Hz from 0 Hz (or from a whole multiple of Δf; lower lines are zero).
    frf : (K,), (K, p) or (K, p, m) complex
        H(f_k) of p outputs to m inputs, Fourier sign convention e^{-iωt} (that of numpy.fft and of every
        analyser we know of). Units e.g. (m/s²)/N.
    frf_type : "accelerance", "mobility", "receptance" or None
        What the FRF measures (acceleration, velocity or displacement per force). Needed only with ``to``.
    to : "acceleration", "velocity", "displacement" or None
        Convert the pulse response to this quantity by multiplying by (iω)^k. Dividing by iω amplifies low-
        frequency noise: give a band with it. None (default) keeps the measured quantity.
    band_hz : (f_lo, f_hi), optional
        The band where the FRF is valid. Lines below f_lo are zeroed (with a raised-cosine taper of width
        ``taper_hz`` inside the band, so the cut does not ring); the spectrum is cut at f_hi, which becomes
        the Nyquist frequency: Δτ = 1/(2 f_hi). Modes outside the band are not in the result.
    taper_hz : float, optional
        Width of the low-edge taper; default 5 % of f_lo (0 for a sharp cut).
    n_samples : int, optional
        Markov parameters returned; default K_hi - 1, the causal half of the circular inverse FFT.
    outputs : sequence of str, optional
        The p output labels, passed to :class:`era.ResponseData`.
    inputs : sequence of str, optional
        The m input labels.
    output_units : sequence of str, optional
        The p output units.
    input_units : sequence of str, optional
        The m input units.

    Returns
    -------
    ResponseData
        markov (n_samples, p, m) with markov[k] = Y(k+1) (Y(0) = D dropped), dt = 1/(2 f_hi) s;
        meta["direct_term"] (p, m) = Y(0) and meta["conversions"] describe what was done.

    Raises
    ------
    era.DataError
        For FRFs with NaN, unevenly spaced or too few lines, a band outside the lines, or a conversion ``to``
        without ``frf_type``.

    Examples
    --------
    The receptance of a 5 Hz mode with 2 % damping, 0-50 Hz in steps of 0.05 Hz, kept up to 20 Hz:

    >>> f = np.arange(0, 50.01, 0.05)
    >>> w, wn = 2 * np.pi * f, 2 * np.pi * 5.0
    >>> frf = 1 / (wn**2 - w**2 + 2j * 0.02 * wn * w)
    >>> data = era.markov_from_frf(f, frf, frf_type="receptance", band_hz=(0, 20))
    >>> data.markov.shape, data.dt, data.meta["band_hz"]
    ((399, 1, 1), 0.025, (0.0, 20.0))
    >>> model = era.analyse(data, max_order=20).model
    >>> print(np.round(model.frequency_hz, 3), np.round(model.damping_ratio, 3))
    [4.999] [0.02]
    """
    h = _as_frf(frf)
    df, first = frequency_grid(frequencies_hz, h.shape[0])
    conversions = []
    if first:
        h = np.concatenate([np.zeros((first,) + h.shape[1:], complex), h])
        conversions.append(f"filled {counted(first, 'missing line')} below {first * df:g} Hz with zeros")
    f = np.arange(h.shape[0]) * df
    f_lo, f_hi = 0.0, float(f[-1])
    if band_hz is not None:
        f_lo, f_hi = (float(x) for x in band_hz)
        if not (0 <= f_lo < f_hi) or f_hi > f[-1] + 0.5 * df:
            raise DataError(f"`band_hz` = {band_hz} must satisfy 0 ≤ f_lo < f_hi ≤ {f[-1]:g} Hz (the last line).")
    k_hi = int(np.floor(f_hi / df + 1e-9))
    if k_hi < 4:
        raise DataError(f"The band up to {f_hi:g} Hz holds only {k_hi + 1} lines of Δf = {df:g} Hz; too few.")
    h = h[:k_hi + 1].copy()
    f = f[:k_hi + 1]
    if k_hi < len(f) - 1 or band_hz is not None:
        conversions.append(f"band {f_lo:g}-{f[-1]:g} Hz kept, Nyquist set to {f[-1]:g} Hz")
    if to is not None:
        if frf_type not in FRF_TYPES:
            raise DataError(f"To convert to {to!r}, say what the FRF measures: frf_type one of {sorted(FRF_TYPES)}, "
                            f"got {frf_type!r}.")
        if to not in _POWER_OF_QUANTITY:
            raise DataError(f"`to` must be one of {sorted(_POWER_OF_QUANTITY)}, got {to!r}.")
        power = _POWER_OF_QUANTITY[to] - FRF_TYPES[frf_type]
        if power:
            iw = 2j * np.pi * f
            with np.errstate(divide="ignore", invalid="ignore"):
                factor = iw ** power
            factor[0] = 0.0 if power < 0 else factor[0]  # 1/(i·0): no static information survives
            h *= factor[:, None, None]
            conversions.append(f"{frf_type} converted to {to} by (iω)^{power}")
            if output_units is not None:  # (iω)^k carries units of s^-k
                output_units = [f"({u})·s^{-power}" for u in output_units]
    if f_lo > 0:
        width = 0.05 * f_lo if taper_hz is None else float(taper_hz)
        gain = np.clip((f - f_lo) / width, 0.0, 1.0) if width > 0 else (f >= f_lo).astype(float)
        gain = 0.5 - 0.5 * np.cos(np.pi * gain)
        h *= gain[:, None, None]
        conversions.append(f"lines below {f_lo:g} Hz zeroed (cosine taper {width:g} Hz)")
    n_fft = 2 * k_hi
    y = np.fft.irfft(h, n=n_fft, axis=0)  # h(t)·Δτ, the pulse response (see module docstring)
    dt = 1.0 / (n_fft * df)
    n_keep = k_hi - 1 if n_samples is None else int(n_samples)
    if not 1 <= n_keep <= n_fft - 1:
        raise DataError(f"`n_samples` = {n_samples} must lie in 1..{n_fft - 1} for this FRF.")
    conversions.append(f"inverse FFT over {n_fft} points, Δτ = {dt:g} s; first {n_keep} Markov parameters kept, "
                       "Y(0) (direct term) dropped")
    return ResponseData(markov=y[1:n_keep + 1], dt=dt, outputs=outputs, inputs=inputs, output_units=output_units,
                        input_units=input_units,
                        meta={"direct_term": y[0], "conversions": conversions, "source": "frf",
                              "band_hz": (f_lo, float(f[-1])), "df_hz": df})
