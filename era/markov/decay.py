"""Free decays and measured impulse responses: choose where the pulse response starts.

A recorded free decay or impulse response holds samples before the event (pre-trigger) and during it (the hammer
still in contact). ERA needs Y(k) = C A^k B from the first sample of free motion on (eq. 15).
"""

from __future__ import annotations

import numpy as np

from ..core.data import ResponseData
from ..errors import DataError
from ..words import counted, listed
from .common import check_dt


def start_after_peak(y: np.ndarray) -> int:
    """Index of the sample after the largest |y| over all channels and columns: where free decay begins after an
    impact (the excitation is over once the response has peaked, to within one sample)."""
    energy = np.abs(y).reshape(len(y), -1).max(axis=1)
    return int(np.argmax(energy)) + 1


def markov_from_decay(responses, dt, *, start="peak", n_samples: int | None = None, outputs=None, inputs=None,
                      output_units=None, input_units=None) -> ResponseData:
    """Free decays or impulse responses, cut at their start, as Markov parameters.

    Parameters
    ----------
    responses : (N,), (N, p) or (N, p, m) real
        p sensors, m initial conditions (or references of an impulse response).
    dt : float
        Sampling interval in seconds.
    start : "peak", int, or sequence of m ints, optional
        First sample kept: "peak" = the sample after the largest response (impact free decays); an int = that
        sample (e.g. the sample after t = 0 of an impulse response, dropping Y(0) = D); one per column to align
        several initial conditions that were triggered at different samples.
    n_samples : int, optional
        Samples kept after the start; default all that every column has.
    outputs : sequence of str, optional
        The p output labels, for :class:`era.ResponseData`.
    inputs : sequence of str, optional
        The m input labels.
    output_units : sequence of str, optional
        The p output units.
    input_units : sequence of str, optional
        The m input units.

    Returns
    -------
    ResponseData
        markov (n_samples, p, m) from the start on; meta["start_samples"] and meta["conversions"] say where.

    Raises
    ------
    era.DataError
        For complex or wrongly shaped responses, or a ``start`` that is not "peak" or sample indices.

    Examples
    --------
    A struck 3 Hz mode (2 % damping) recorded with 0.5 s of pre-trigger at 100 Hz:

    >>> t = np.arange(-50, 500) * 0.01
    >>> y = np.where(t >= 0, np.exp(-0.02 * 2 * np.pi * 3 * t) * np.sin(2 * np.pi * 3 * t), 0.0)
    >>> data = era.markov_from_decay(y, 0.01, start="peak")
    >>> data.markov.shape, data.meta["start_samples"]
    ((491, 1, 1), [59])
    """
    dt = check_dt(dt)
    y = np.asarray(responses, dtype=float) if not np.iscomplexobj(responses) else None
    if y is None:
        raise DataError("`responses` are complex; free decays are real time histories (FRFs: markov_from_frf).")
    y = y.reshape(y.shape + (1,) * (3 - y.ndim)) if y.ndim < 3 else y
    if y.ndim != 3:
        raise DataError(f"`responses` has shape {np.shape(responses)}; expected (N, p, m).")
    m = y.shape[2]
    if isinstance(start, str):
        if start != "peak":
            raise DataError(f"`start` must be 'peak', a sample index or one index per column, got {start!r}.")
        starts = [start_after_peak(y[:, :, j]) for j in range(m)]
    else:
        starts = np.broadcast_to(np.asarray(start), (m,)).tolist()
        if any(isinstance(s, float) and not float(s).is_integer() for s in starts):
            raise DataError(f"`start` must hold whole sample indices, got {start!r}.")
        starts = [int(s) for s in starts]
    if any(s < 0 or s >= len(y) for s in starts):
        outside = [s for s in starts if s < 0 or s >= len(y)]
        raise DataError(f"{'Start samples' if len(outside) > 1 else 'Start sample'} {listed(outside)} "
                        f"{'lie' if len(outside) > 1 else 'lies'} outside the record of {len(y)} samples.")
    available = min(len(y) - s for s in starts)
    n_keep = available if n_samples is None else min(int(n_samples), available)
    if n_keep < 4:
        raise DataError(f"Only {counted(available, 'sample')} {'remains' if available == 1 else 'remain'} after the "
                        f"start sample {max(starts)}; too few for any identification. Choose an earlier start or a "
                        "longer record.")
    out = np.stack([y[s:s + n_keep, :, j] for j, s in enumerate(starts)], axis=2)
    return ResponseData(markov=out, dt=dt, outputs=outputs, inputs=inputs, output_units=output_units,
                        input_units=input_units,
                        meta={"start_samples": starts, "source": "decay",
                              "conversions": [f"free decay from {'samples' if len(starts) > 1 else 'sample'} "
                                              f"{listed(starts)} (t = {', '.join(f'{s * dt:g}' for s in starts)} s), "
                                              f"{n_keep} samples"]})
