"""Response data: the pulse responses (Markov parameters) that ERA starts from."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import DataError
from ..words import counted


def _labels(given, n: int, what: str, default_prefix: str) -> tuple[str, ...]:
    if given is None:
        return tuple(f"{default_prefix}{i + 1}" for i in range(n))
    labels = tuple(str(x) for x in given)
    if len(labels) != n:
        raise DataError(
            f"{len(labels)} {what} labels were given for {n} {what}s; give one label per {what} "
            f"(the {what} axis of `markov` has length {n}) or none."
        )
    return labels


def _records(value, shape: tuple) -> np.ndarray:
    """The per-record pulse responses, checked against ``markov``'s shape: (n_b, N, p, m), n_b ≥ 2, finite."""
    try:
        rec = np.array(value, dtype=float, order="C")
    except (TypeError, ValueError):
        raise DataError("`records` must be a numeric array of shape (n_b, N, p, m).") from None
    if rec.ndim != 4 or rec.shape[1:] != tuple(shape) or rec.shape[0] < 2:
        raise DataError(f"`records` has shape {rec.shape}; it must be (n_b, {', '.join(map(str, shape))}): at least "
                        "2 records, each shaped like `markov`. Leave it out for a single record.")
    if not np.isfinite(rec).all():
        raise DataError("`records` holds NaN or infinite values; give finite per-record pulse responses or none.")
    rec.setflags(write=False)
    return rec


@dataclass(frozen=True, eq=False)
class ResponseData:
    """Pulse responses or free decays, ready for :func:`era.identify`.

    Parameters
    ----------
    markov : array_like, shape (N, p, m)
        ``markov[k] = C A^k B`` for k = 0..N-1: the pulse response of p outputs to m inputs
        (Markov parameters, with the direct term Y(0) = D dropped), or free decays of p sensors from
        m initial conditions as in the paper (eq. 15). A 1-D array is read as (N, 1, 1) and a 2-D
        array as (N, p, 1). Real, finite values only.
    dt : float
        Sampling interval Δτ in seconds (> 0).
    outputs : sequence of str, optional
        Output channel labels, p of them; default ``y1..yp``.
    inputs : sequence of str, optional
        Input labels (references or initial conditions), m of them; default ``u1..um``.
    output_units : sequence of str, optional
        Unit of each output channel (e.g. ``"m/s^2"``), p of them, for labels and reports.
    input_units : sequence of str, optional
        Unit of each input (e.g. ``"N"``), m of them, for labels and reports.
    meta : dict, optional
        What the readers and builders know about the data, e.g. ``"name"``, ``"band_hz"`` (the band an FRF
        holds, Hz), ``"direct_term"`` (p, m), ``"conversions"``, ``"input_points"``/``"output_points"``
        (era.core.points' labels). Default empty.
    records : array_like, shape (n_b, N, p, m), optional
        Independent estimates of the same pulse responses, one per record of the same test (repeated hits, NExT
        segments), of which ``markov`` is the mean or the pooled estimate. Their scatter gives each mode's
        standard deviation (era.core.uncertainty.record_covariance) when there are at least
        era.core.uncertainty.MIN_RECORDS of them; era.markov's builders fill it when given several comparable
        records.

    Raises
    ------
    era.DataError
        For a complex, non-finite or wrongly shaped ``markov``, a ``dt`` that is not a positive number, labels
        whose count does not match, or ``records`` not shaped (n_b, N, p, m).

    Examples
    --------
    A single-channel free decay of a 2 Hz mode with 1 % damping, sampled at 50 Hz:

    >>> dt = 0.02
    >>> t = np.arange(200) * dt
    >>> y = np.exp(-0.01 * 2 * np.pi * 2 * t) * np.cos(2 * np.pi * 2 * t)
    >>> data = era.ResponseData(y, dt, outputs=["tip"], output_units=["m/s^2"])
    >>> data.markov.shape, data.n_samples, data.outputs, data.inputs
    ((200, 1, 1), 200, ('tip',), ('u1',))
    """

    markov: np.ndarray
    dt: float
    outputs: tuple[str, ...] | None = None
    inputs: tuple[str, ...] | None = None
    output_units: tuple[str, ...] | None = None
    input_units: tuple[str, ...] | None = None
    meta: dict = field(default_factory=dict)
    records: np.ndarray | None = None

    def __post_init__(self):
        y = np.asarray(self.markov)
        if y.dtype == object or not (np.issubdtype(y.dtype, np.number) or y.dtype == bool):
            raise DataError("`markov` must be a numeric array of shape (N, p, m).")
        if np.iscomplexobj(y):
            raise DataError(
                "`markov` is complex; ERA needs real time-domain pulse responses. Convert FRFs with "
                "era.markov_from_frf first."
            )
        if y.ndim == 1:
            y = y[:, None, None]
        elif y.ndim == 2:
            y = y[:, :, None]
        elif y.ndim != 3:
            raise DataError(f"`markov` has {y.ndim} dimensions; expected (N, p, m): samples × outputs × inputs.")
        if min(y.shape) == 0:
            raise DataError(f"`markov` has shape {y.shape}; every axis (samples, outputs, inputs) needs length ≥ 1.")
        y = np.array(y, dtype=float, order="C")  # own, contiguous, read-only copy
        finite = np.isfinite(y)
        if not finite.all():
            k, i, j = np.argwhere(~finite)[0]
            n_bad = int((~finite).sum())
            raise DataError(
                f"`markov` holds {counted(n_bad, 'NaN or infinite value')}, the first at sample {k}, output {i}, "
                f"input {j}; remove or interpolate them before identification."
            )
        y.setflags(write=False)
        try:
            dt = float(self.dt)
        except (TypeError, ValueError):
            raise DataError(f"`dt` must be a number of seconds, got {self.dt!r}.") from None
        if not np.isfinite(dt) or dt <= 0:
            raise DataError(f"`dt` must be a positive, finite sampling interval in seconds, got {self.dt!r}.")
        n, p, m = y.shape
        object.__setattr__(self, "markov", y)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "outputs", _labels(self.outputs, p, "output", "y"))
        object.__setattr__(self, "inputs", _labels(self.inputs, m, "input", "u"))
        if self.output_units is not None:
            object.__setattr__(self, "output_units", _labels(self.output_units, p, "output", ""))
        if self.input_units is not None:
            object.__setattr__(self, "input_units", _labels(self.input_units, m, "input", ""))
        if self.records is not None:
            object.__setattr__(self, "records", _records(self.records, y.shape))

    @property
    def n_records(self) -> int:
        """n_b, the independent records whose scatter is kept (0 without :attr:`records`)."""
        return 0 if self.records is None else self.records.shape[0]

    @property
    def n_samples(self) -> int:
        """N, the number of samples (time steps)."""
        return self.markov.shape[0]

    @property
    def n_outputs(self) -> int:
        """p, the number of outputs (sensors)."""
        return self.markov.shape[1]

    @property
    def n_inputs(self) -> int:
        """m, the number of inputs (references or initial conditions)."""
        return self.markov.shape[2]

    @property
    def time_s(self) -> np.ndarray:
        """Sample times k·Δτ in seconds, shape (N,)."""
        return np.arange(self.n_samples) * self.dt
