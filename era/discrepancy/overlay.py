"""Measured against simulated response: the records a model predicts with its own modes, for overlay plots.

A model gives frequencies and shapes but not how hard each mode was excited, nor its damping. The overlay keeps
the model's frequencies and shapes, takes the damping ERA measured for the paired modes, and fits only the
initial modal amplitudes (a linear least squares per input). A model with the wrong frequencies then drifts out
of phase with the record; a model with the wrong shapes cannot match the sensors' relative amplitudes.
"""

from __future__ import annotations

import numpy as np

from ..core.data import ResponseData
from ..errors import DataError


def model_response(data: ResponseData, model, damping_ratio: np.ndarray, n_modes: int | None = None,
                   model_index: np.ndarray | None = None) -> np.ndarray:
    """The free decays (or pulse responses) the model's modes produce, fitted to ``data``: (N, p, m).

    Parameters
    ----------
    data : ResponseData (N, p, m), outputs in model.sensors order.
    model : anything with .modes(n) -> (f_hz (n,), shapes (p, n)).
    damping_ratio : (r,) damping of each model mode used (e.g. ERA's, of the measured partner).
    n_modes : how many model modes to take (default r = len(damping_ratio)); model_index : (r,) which ones.

    y_p(t) = Σ_r φ_pr e^{−ζ_r ω_r t} (a_rm cos ω_dr t + b_rm sin ω_dr t), with f and φ from the model and
    a, b fitted to the record of each input m by least squares.
    """
    zeta = np.asarray(damping_ratio, dtype=float).reshape(-1)
    idx = np.arange(zeta.size) if model_index is None else np.asarray(model_index, dtype=int)
    if idx.size != zeta.size:
        raise DataError("model_response: give one damping ratio per model mode used.")
    f, shapes = model.modes(int(n_modes or (idx.max() + 1 if idx.size else 1)))
    f, phi = np.asarray(f, float)[idx], np.asarray(shapes, float)[:, idx]
    y = data.markov
    n, p, m = y.shape
    if phi.shape[0] < p:
        raise DataError(f"model_response: the model has {phi.shape[0]} sensors, the data {p} outputs.")
    phi = phi[:p]       # explain's struck points are sensors after the outputs': the records are the outputs'
    t = np.arange(n) * data.dt
    w = 2 * np.pi * f
    wd = w * np.sqrt(np.clip(1 - zeta**2, 1e-12, None))
    env = np.exp(-(zeta * w)[None, :] * t[:, None])
    basis = np.concatenate([env * np.cos(wd * t[:, None]), env * np.sin(wd * t[:, None])], axis=1)  # (N, 2r)
    # design: rows (k, p), columns (mode, cos|sin): y[k, p] = Σ_r φ_pr (a_r c_r(k) + b_r s_r(k))
    r = idx.size
    design = (basis.reshape(n, 2, r)[:, None, :, :] * phi[None, :, None, :]).reshape(n * p, 2 * r)
    coef, *_ = np.linalg.lstsq(design, y.reshape(n * p, m), rcond=None)
    return (design @ coef).reshape(n, p, m)


def overlay(result, data: ResponseData) -> dict:
    """Measured, nominal-model and updated-model responses for an :class:`Explanation` and its data.

    Returns {"time_s": (N,), "measured": (N, p, m), "nominal": (N, p, m), "updated": (N, p, m),
    "fit_error_nominal", "fit_error_updated": normalised RMS error (p, m) of each model's fitted response}.
    Damping comes from ERA for the paired modes; the nominal model uses its own partners of the same modes.
    """
    fm = result.measured.take(result.fit_modes)
    out = {"time_s": data.time_s, "measured": np.asarray(data.markov)}
    for key, pairing, mdl in (("nominal", result.pairing_before, result.nominal_model),
                              ("updated", result.pairing_after, result.updated_model)):
        zeta = fm.damping_ratio[pairing.measured_index]
        n_model = int(pairing.model_index.max() + 1) if pairing.n_pairs else 1
        yhat = model_response(data, mdl, zeta, n_model, pairing.model_index)
        out[key] = yhat
        err = np.sqrt(np.mean((data.markov - yhat) ** 2, axis=0) / np.maximum(np.mean(data.markov**2, axis=0), 1e-300))
        out[f"fit_error_{key}"] = err
    return out
