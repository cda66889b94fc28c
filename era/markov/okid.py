"""OKID: Markov parameters from input-output records (Juang, Phan, Horta & Longman, 1993).

With an observer (Kalman filter) gain G, Ā = A + GC is stable and deadbeat enough that the output is a finite
ARX sum over the past inputs and outputs v(k) = [u(k); y(k)]:

    y(k) = D u(k) + Σ_{j=1..l} Ȳ_j v(k-j),
    Ȳ_j = [C Ā^{j-1}(B + GD), -C Ā^{j-1} G] = [Ȳ_j⁽¹⁾, -Ȳ_j⁽²⁾].

The observer Markov parameters Ȳ come from one least-squares fit; the system Markov parameters follow from

    Y_0 = D,  Y_k = Ȳ_k⁽¹⁾ - Σ_{i=1..k} Ȳ_i⁽²⁾ Y_{k-i}   (Ȳ_k⁽¹⁾ = 0 and Ȳ_i⁽²⁾ = 0 beyond l).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..core.data import ResponseData
from ..errors import DataError
from ..words import counted, listed
from .common import check_dt, kept_records, positive_int, records

#: Rows of the regression factored at once; the QR of each chunk is stacked under the running R factor,
#: so memory stays at chunk × columns whatever the record length.
_CHUNK_ROWS = 20_000


def observer_markov(inputs: list[np.ndarray], outputs: list[np.ndarray], n_observer: int) -> tuple[np.ndarray, float]:
    """Least-squares observer Markov parameters [D, Ȳ_1, ..., Ȳ_l] as a (p, m + l(m+p)) array, and the
    relative residual ||y - ŷ|| / ||y|| of the fit."""
    m, p, l = inputs[0].shape[1], outputs[0].shape[1], n_observer
    n_cols = m + l * (m + p)
    r_factor = np.zeros((0, n_cols + p))
    for u, y in zip(inputs, outputs):
        v = np.hstack([u, y])
        for start in range(l, len(y), _CHUNK_ROWS):
            rows = np.arange(start, min(start + _CHUNK_ROWS, len(y)))
            past = [v[rows - j] for j in range(1, l + 1)]  # v(k-1), ..., v(k-l)
            block = np.hstack([u[rows]] + past + [y[rows]])
            r_factor = scipy.linalg.qr(np.vstack([r_factor, block]), mode="r", check_finite=False)[0]
            r_factor = r_factor[:min(r_factor.shape[0], n_cols + p)]
    r11, r12 = r_factor[:n_cols, :n_cols], r_factor[:n_cols, n_cols:]
    coef, *_ = scipy.linalg.lstsq(r11, r12, cond=1e-12, check_finite=False)
    residual = np.linalg.norm(r_factor[n_cols:, n_cols:]) if r_factor.shape[0] > n_cols else 0.0
    total = np.sqrt(sum(float(np.sum(y[l:] ** 2)) for y in outputs))
    return coef.T, (residual / total if total > 0 else 0.0)


def system_markov(observer: np.ndarray, m: int, p: int, n_markov: int) -> np.ndarray:
    """System Markov parameters Y_0..Y_{n_markov} (n_markov + 1, p, m) from observer ones (see module docstring)."""
    l = (observer.shape[1] - m) // (m + p)
    d = observer[:, :m]
    blocks = observer[:, m:].reshape(p, l, m + p).transpose(1, 0, 2)  # (l, p, m+p): Ȳ_j = [a_j, b_j]
    a, b = blocks[:, :, :m], blocks[:, :, m:]  # a_j = Ȳ_j⁽¹⁾, b_j = -Ȳ_j⁽²⁾
    y = np.zeros((n_markov + 1, p, m))
    y[0] = d
    for k in range(1, n_markov + 1):
        i = np.arange(1, min(k, l) + 1)
        y[k] = (a[k - 1] if k <= l else 0.0) + np.einsum("ipq,iqm->pm", b[i - 1], y[k - i])
    return y


def markov_from_io(inputs, outputs, dt, *, n_observer: int = 40, n_markov: int | None = None,
                   detrend: bool = False, output_names=None, input_names=None, output_units=None,
                   input_units=None) -> ResponseData:
    """Markov parameters of a force-response test (shaker, hammer) by OKID.

    Parameters
    ----------
    inputs : (N, m) array or list of (N_r, m) arrays
        Measured excitation (e.g. force in N); a list holds several records of one test (repeated hits),
        fitted together; records of comparable length (within 10 %) long enough for their own fit are also
        fitted one by one (ResponseData.records: σ from their scatter).
    outputs : (N, p) array or list of (N_r, p) arrays
        Measured responses, same samples as ``inputs``.
    dt : float
        Sampling interval in seconds.
    n_observer : int, optional
        l, the number of observer Markov parameters. l·p must be at least the system order n; with noise,
        larger l approaches the Kalman filter (the paper's recommendation: as large as data allow).
    n_markov : int, optional
        Number of system Markov parameters returned (Y_1..Y_n_markov); default 10·l.
    detrend : bool, optional
        Remove each channel's mean first (sensor offsets). Default False.
    output_names : sequence of str, optional
        The p output labels, for :class:`era.ResponseData`.
    input_names : sequence of str, optional
        The m input labels.
    output_units : sequence of str, optional
        The p output units.
    input_units : sequence of str, optional
        The m input units.

    Returns
    -------
    ResponseData
        markov (n_markov, p, m) = Y_1..Y_n_markov; meta["direct_term"] = D (p, m); meta["fit_residual"]
        is the relative least-squares residual (noise plus model error).

    Raises
    ------
    era.DataError
        When inputs and outputs do not pair up (records, samples), an input channel is silent, or the records
        are too short for ``n_observer``.

    References
    ----------
    Juang, J.-N., Phan, M., Horta, L. G. and Longman, R. W. (1993), Identification of observer/Kalman filter
    Markov parameters: theory and experiments, Journal of Guidance, Control, and Dynamics 16(2), 320-329.

    Examples
    --------
    A 4 Hz mode with 2 % damping driven by a random force, sampled at 100 Hz:

    >>> from scipy.signal import lfilter
    >>> dt = 0.01
    >>> z = np.exp(2 * np.pi * 4.0 / np.sqrt(1 - 0.02**2) * (-0.02 + 1j * np.sqrt(1 - 0.02**2)) * dt)
    >>> force = np.random.default_rng(0).standard_normal(2000)
    >>> response = lfilter([0, 1], [1, -2 * z.real, abs(z) ** 2], force)
    >>> data = era.markov_from_io(force[:, None], response[:, None], dt, n_observer=10, n_markov=200)
    >>> data.markov.shape, bool(data.meta["fit_residual"] < 1e-6)
    ((200, 1, 1), True)
    >>> model = era.identify(data, 80, 80).realize(2)
    >>> print(np.round(model.frequency_hz, 3), np.round(model.damping_ratio, 3))
    [4.] [0.02]
    """
    dt = check_dt(dt)
    us, ys = records(inputs, "inputs"), records(outputs, "outputs")
    if len(us) != len(ys):
        raise DataError(f"{len(us)} input records but {len(ys)} output records; pair each input record with its "
                        "output record.")
    for r, (u, y) in enumerate(zip(us, ys)):
        if len(u) != len(y):
            raise DataError(f"Record {r}: {len(u)} input samples but {len(y)} output samples; inputs and outputs "
                            "must be sampled together.")
    l = positive_int(n_observer, "n_observer")
    n_markov = 10 * l if n_markov is None else positive_int(n_markov, "n_markov")
    m, p = us[0].shape[1], ys[0].shape[1]
    n_rows = sum(len(y) - l for y in ys)
    n_cols = m + l * (m + p)
    if n_rows < 2 * n_cols:
        raise DataError(f"Too few samples for OKID with l = {l}: {n_rows} equations for {n_cols} unknowns per "
                        f"output; use a smaller n_observer (≤ {max(1, (sum(map(len, ys)) // 2 - m) // (m + p + 2))}) "
                        "or longer records.")
    if detrend:
        us = [u - u.mean(axis=0) for u in us]
        ys = [y - y.mean(axis=0) for y in ys]
    scale_u = np.sqrt(np.mean(np.concatenate(us) ** 2, axis=0))
    scale_y = np.sqrt(np.mean(np.concatenate(ys) ** 2, axis=0))
    if np.any(scale_u == 0):
        zero = np.flatnonzero(scale_u == 0).tolist()
        raise DataError(f"{'Input channels' if len(zero) > 1 else 'Input channel'} {listed(zero)} "
                        f"{'are' if len(zero) > 1 else 'is'} all zero; OKID needs the measured excitation.")
    scale_y = np.where(scale_y > 0, scale_y, 1.0)
    # fit in scaled units (conditioning), then undo: Y = diag(s_y) Ŷ diag(1/s_u)
    obs, residual = observer_markov([u / scale_u for u in us], [y / scale_y for y in ys], l)
    y_sys = system_markov(obs, m, p, n_markov) * scale_y[None, :, None] / scale_u[None, None, :]
    # repeated hits of comparable length (within 10 %), each long enough for its own fit: one estimate per
    # record, whose scatter gives the modes' σ (ResponseData.records, era.core.uncertainty.record_covariance)
    lengths = [len(y) - l for y in ys]
    per_record = None
    if len(ys) >= 2 and min(lengths) >= 0.9 * max(lengths) and min(lengths) >= 2 * n_cols:
        each = [system_markov(observer_markov([u / scale_u], [y / scale_y], l)[0], m, p, n_markov)[1:]
                for u, y in zip(us, ys)]
        per_record = kept_records(np.stack(each) * scale_y[None, None, :, None] / scale_u[None, None, None, :])
    return ResponseData(markov=y_sys[1:], dt=dt, outputs=output_names, inputs=input_names,
                        output_units=output_units, input_units=input_units, records=per_record,
                        meta={"direct_term": y_sys[0], "fit_residual": residual, "source": "okid",
                              "conversions": [f"OKID (Juang et al. 1993) with l = {l} observer Markov parameters "
                                              f"from {counted(len(ys), 'record')}, {n_rows} equations; relative "
                                              f"residual "
                                              f"{residual:.3g}; {n_markov} Markov parameters"]})
