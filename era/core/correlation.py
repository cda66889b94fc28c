"""Test-analysis correlation: pair measured and model modes, MAC, COMAC, frequency errors, SEREP expansion.

Pairing uses frequency and shape together (one assignment on a combined cost), never frequency order: a model
whose modes 4 and 5 have swapped places, or a measured spurious mode between two real ones, still pairs right.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from ..errors import DataError
from .indicators import mac


def real_shapes(shapes: np.ndarray) -> np.ndarray:
    """Real shapes from complex ones: each column rotated to its principal phase, then its real part.

    The rotation is the angle that makes the shape most nearly real (largest ‖Re(e^{-iθ} φ)‖), found in closed
    form from Σ φ_k²; the sign is fixed so that the largest component is positive.

    Parameters
    ----------
    shapes : array_like, shape (p, k) or (p,)
        Mode shapes, real or complex, one per column.

    Returns
    -------
    float ndarray
        Same shape as ``shapes``.

    Examples
    --------
    >>> era.real_shapes(np.array([1j, 2j, -0.5j]))
    array([ 1. ,  2. , -0.5])
    >>> print(np.round(era.real_shapes(np.array([[1 + 1j, 1], [-1 - 1j, 2]])), 3))
    [[ 1.414  1.   ]
     [-1.414  2.   ]]
    """
    c = np.asarray(shapes)
    one = c.ndim == 1
    c = np.atleast_2d(c.T).T if one else c
    c = c.astype(complex)
    theta = 0.5 * np.angle(np.sum(c * c, axis=0))
    r = (c * np.exp(-1j * theta)[None, :]).real
    big = np.argmax(np.abs(r), axis=0)
    r = r * np.where(r[big, np.arange(r.shape[1])] < 0, -1.0, 1.0)[None, :]
    return r[:, 0] if one else r


@dataclass(frozen=True, eq=False)
class ModePairing:
    """Measured modes paired with model modes.

    Made by :func:`era.pair_modes`.

    Attributes
    ----------
    measured_index : int ndarray, shape (k,)
        Column index of each pair into the measured mode set, sorted by measured frequency.
    model_index : int ndarray, shape (k,)
        Column index of each pair into the model mode set.
    frequency_measured_hz : ndarray, shape (k,)
        The measured frequency of each pair, Hz.
    frequency_model_hz : ndarray, shape (k,)
        The model frequency of each pair, Hz.
    frequency_error_pct : ndarray, shape (k,)
        100 (f_model - f_measured) / f_measured.
    mac : ndarray, shape (k,)
        MAC of each pair.
    mac_matrix : ndarray, shape (n_measured, n_model)
        MAC between every measured and every model mode.
    unpaired_measured : tuple of int
        Measured modes with no acceptable partner (set aside and reported, never forced).
    unpaired_model : tuple of int
        Model modes with no acceptable partner.
    n_pairs : int
        k, the number of pairs.

    Examples
    --------
    >>> measured = np.array([[1.0, 1.0], [0.5, -1.0], [0.2, 0.4]])
    >>> model = np.array([[1.0, 0.9, 0.0], [0.55, -1.0, 1.0], [0.2, 0.5, -0.9]])
    >>> pairing = era.pair_modes([2.0, 5.1], measured, [2.1, 5.0, 8.0], model)
    >>> pairing.n_pairs, pairing.model_index.tolist(), pairing.unpaired_model
    (2, [0, 1], (2,))
    >>> print(np.round(pairing.frequency_error_pct, 2), pairing.mac_matrix.shape)
    [ 5.   -1.96] (2, 3)
    """

    measured_index: np.ndarray
    model_index: np.ndarray
    frequency_measured_hz: np.ndarray
    frequency_model_hz: np.ndarray
    frequency_error_pct: np.ndarray
    mac: np.ndarray
    mac_matrix: np.ndarray
    unpaired_measured: tuple
    unpaired_model: tuple

    @property
    def n_pairs(self) -> int:
        return int(self.measured_index.size)


def pairing_cost(f_measured, shapes_measured, f_model, shapes_model, *, freq_scale: float = 0.1) -> tuple:
    """Cost of pairing every measured mode with every model mode, and the MAC matrix.

    cost_ij = (1 - MAC_ij) + 0.1 · min(|f_j - f_i| / (f_i · freq_scale), 10): a relative frequency error of
    ``freq_scale`` costs as much as a MAC loss of 0.1, and the frequency term is capped at 1 (a shape with
    nothing in common), so a model mode at 0 Hz can still pair by its shape.

    Returns (cost (n_measured, n_model), mac (n_measured, n_model)).
    """
    fm = np.asarray(f_measured, dtype=float).reshape(-1)
    fa = np.clip(np.nan_to_num(np.asarray(f_model, dtype=float).reshape(-1)), 0.0, None)
    m = mac(shapes_measured, shapes_model)
    rel = np.abs(fa[None, :] - fm[:, None]) / np.maximum(fm[:, None], 1e-12)
    cost = (1.0 - m) + 0.1 * np.minimum(rel / freq_scale, 10.0)
    return cost, m


def pair_modes(f_measured, shapes_measured, f_model, shapes_model, *, freq_scale: float = 0.1,
               min_mac: float = 0.5, max_freq_error: float = 0.5) -> ModePairing:
    """Pair measured modes with model modes by frequency and MAC together.

    One optimal assignment (Hungarian method, ``scipy.optimize.linear_sum_assignment``) on the combined cost of
    :func:`pairing_cost`; a pair whose MAC is below ``min_mac`` or whose relative frequency error exceeds
    ``max_freq_error`` is refused and both modes are reported unpaired.

    Parameters
    ----------
    f_measured : array_like, shape (n_measured,)
        Measured frequencies, Hz.
    shapes_measured : array_like, shape (p, n_measured)
        Measured shapes, real or complex.
    f_model : array_like, shape (n_model,)
        Model frequencies, Hz.
    shapes_model : array_like, shape (p, n_model)
        Model shapes at the same p sensors in the same order.
    freq_scale : float, optional
        The relative frequency error that costs as much as a MAC loss of 0.1 (default 0.1).
    min_mac : float, optional
        The least MAC of an accepted pair (default 0.5).
    max_freq_error : float, optional
        The largest relative frequency error of an accepted pair (default 0.5).

    Returns
    -------
    ModePairing

    Raises
    ------
    era.DataError
        When the shapes are not (p, modes) arrays at the same sensors, or the frequencies do not match them.

    Examples
    --------
    >>> measured = np.array([[1.0, 1.0], [0.5, -1.0], [0.2, 0.4]])
    >>> model = np.array([[1.0, 0.9, 0.0], [0.55, -1.0, 1.0], [0.2, 0.5, -0.9]])
    >>> pairing = era.pair_modes([2.0, 5.1], measured, [2.1, 5.0, 8.0], model)
    >>> pairing.measured_index.tolist(), pairing.model_index.tolist()
    ([0, 1], [0, 1])
    >>> print(np.round(pairing.mac, 3))
    [0.998 0.991]
    """
    fm = np.asarray(f_measured, dtype=float).reshape(-1)
    fa = np.asarray(f_model, dtype=float).reshape(-1)
    sm = np.asarray(shapes_measured)
    sa = np.asarray(shapes_model)
    if sm.ndim != 2 or sa.ndim != 2 or sm.shape[0] != sa.shape[0]:
        raise DataError(f"pair_modes: measured shapes {sm.shape} and model shapes {sa.shape} must be (p, modes) "
                        "arrays at the same p sensors.")
    if sm.shape[1] != fm.size or sa.shape[1] != fa.size:
        raise DataError("pair_modes: give one frequency per shape column, for both the measured and the model set.")
    cost, m = pairing_cost(fm, sm, fa, sa, freq_scale=freq_scale)
    if fm.size == 0 or fa.size == 0:
        rows = cols = np.zeros(0, dtype=int)
    else:
        rows, cols = linear_sum_assignment(cost)
    fa_safe = np.clip(np.nan_to_num(fa), 0.0, None)
    rel = np.abs(fa_safe[cols] - fm[rows]) / np.maximum(fm[rows], 1e-12)
    ok = (m[rows, cols] >= min_mac) & (rel <= max_freq_error)
    rows, cols = rows[ok], cols[ok]
    order = np.argsort(fm[rows], kind="stable")
    rows, cols = rows[order], cols[order]
    err = 100.0 * (fa_safe[cols] - fm[rows]) / fm[rows]
    return ModePairing(
        measured_index=rows, model_index=cols, frequency_measured_hz=fm[rows], frequency_model_hz=fa_safe[cols],
        frequency_error_pct=err, mac=m[rows, cols], mac_matrix=m,
        unpaired_measured=tuple(int(i) for i in np.setdiff1d(np.arange(fm.size), rows)),
        unpaired_model=tuple(int(j) for j in np.setdiff1d(np.arange(fa.size), cols)),
    )


def comac(shapes_measured: np.ndarray, shapes_model: np.ndarray) -> np.ndarray:
    """Coordinate MAC of each sensor over k paired modes (columns in pair order).

    COMAC_r = (Σ_j |φ_rj ψ_rj|)² / (Σ_j φ_rj² Σ_j ψ_rj²) with each shape first scaled to unit norm and the
    model shape sign-aligned with the measured one; a low value marks a sensor where test and model disagree.

    Parameters
    ----------
    shapes_measured : array_like, shape (p, k)
        The measured shapes of the pairs (real or complex; made real with :func:`real_shapes`).
    shapes_model : array_like, shape (p, k)
        The model shapes of the same pairs, at the same sensors.

    Returns
    -------
    ndarray, shape (p,)
        COMAC per sensor, in [0, 1].

    Raises
    ------
    era.DataError
        When the two arrays are not (p, k) of the same shape.

    Examples
    --------
    >>> measured = np.array([[1.0, 1.0], [0.5, -1.0], [0.2, 0.4]])
    >>> model = np.array([[1.0, 0.9], [0.55, -1.0], [0.2, -0.5]])
    >>> print(np.round(era.comac(measured, model), 3))
    [0.999 0.999 0.261]
    """
    a = real_shapes(np.asarray(shapes_measured))
    b = real_shapes(np.asarray(shapes_model))
    if a.shape != b.shape or a.ndim != 2:
        raise DataError(f"comac: measured {a.shape} and model {b.shape} shapes must be (p, k) arrays of paired modes.")
    a = a / np.maximum(np.linalg.norm(a, axis=0, keepdims=True), 1e-300)
    b = b / np.maximum(np.linalg.norm(b, axis=0, keepdims=True), 1e-300)
    b = b * np.sign(np.sum(a * b, axis=0) + 1e-300)[None, :]
    num = np.sum(a * b, axis=1) ** 2
    den = np.sum(a * a, axis=1) * np.sum(b * b, axis=1)
    out = np.zeros(a.shape[0])
    np.divide(num, den, out=out, where=den > 0)
    return np.clip(out, 0.0, 1.0)


def serep(shapes_sensors: np.ndarray, model_sensors: np.ndarray, model_nodes: np.ndarray) -> np.ndarray:
    """SEREP expansion of sensor shapes to every model node.

    x_nodes = Φ_n Φ_s⁺ x_s, with Φ_s the model's shapes at the sensors and Φ_n the same modes at all nodes.
    The expanded shape is the model-mode combination closest (least squares) to the measured one at the sensors.

    Parameters
    ----------
    shapes_sensors : array_like, shape (p, j) or (p,)
        Real shapes at the p sensors (e.g. measured, from :func:`real_shapes`).
    model_sensors : array_like, shape (p, k)
        Model mode shapes at the sensors, k ≤ p (more modes than sensors is not determined).
    model_nodes : array_like, shape (n, k)
        The same k model modes at all n nodes.

    Returns
    -------
    ndarray, shape (n, j) or (n,)
        The shapes at every node (1-D for a 1-D ``shapes_sensors``).

    Raises
    ------
    era.DataError
        When the shapes do not fit together.

    References
    ----------
    O'Callahan, J., Avitabile, P. and Riemer, R. (1989), System equivalent reduction expansion process (SEREP),
    Proceedings of the 7th International Modal Analysis Conference.

    Examples
    --------
    Two model modes at four nodes, measured at nodes 1 and 2:

    >>> nodes = np.array([[0.0, 0.0], [0.5, 1.0], [1.0, 0.0], [0.5, -1.0]])
    >>> print(np.round(era.serep(np.array([[1.0], [0.9]]), nodes[[1, 2]], nodes), 3))
    [[ 0. ]
     [ 1. ]
     [ 0.9]
     [-0.1]]
    """
    xs = np.asarray(shapes_sensors, dtype=float)
    one = xs.ndim == 1
    xs = xs[:, None] if one else xs
    ps = np.asarray(model_sensors, dtype=float)
    pn = np.asarray(model_nodes, dtype=float)
    if ps.ndim != 2 or pn.ndim != 2 or ps.shape[1] != pn.shape[1] or ps.shape[0] != xs.shape[0]:
        raise DataError(f"serep: sensor shapes {xs.shape}, model sensor shapes {ps.shape} and model node shapes "
                        f"{pn.shape} must be (p, j), (p, k), (n, k).")
    if ps.shape[1] > ps.shape[0]:
        raise DataError(f"serep: {ps.shape[1]} model modes for {ps.shape[0]} sensors; use at most as many modes "
                        "as sensors (e.g. only the paired ones).")
    out = pn @ (np.linalg.pinv(ps) @ xs)
    return out[:, 0] if one else out


@dataclass(frozen=True)
class Gap:
    """How far a model is from the test over the paired modes (frequencies in %, MAC in [0, 1]).

    Made by :func:`era.gap`.

    Attributes
    ----------
    max_abs_freq_error_pct : float
        The largest |frequency error| of a pair, %.
    rms_freq_error_pct : float
        The RMS frequency error over the pairs, %.
    min_mac : float
        The smallest MAC of a pair.
    mean_mac : float
        The mean MAC of the pairs.
    n_pairs : int
        The number of pairs (0: every other field is NaN).

    Examples
    --------
    >>> era.Gap(5.0, 3.5, 0.97, 0.99, 3).as_dict()["n_pairs"]
    3
    """

    max_abs_freq_error_pct: float
    rms_freq_error_pct: float
    min_mac: float
    mean_mac: float
    n_pairs: int

    def as_dict(self) -> dict:
        return {"max_abs_freq_error_pct": self.max_abs_freq_error_pct, "rms_freq_error_pct": self.rms_freq_error_pct,
                "min_mac": self.min_mac, "mean_mac": self.mean_mac, "n_pairs": self.n_pairs}


def subspace_mac(pairing: ModePairing, shapes_measured, shapes_model, f_model, close: float = 0.03) -> np.ndarray:
    """MAC of each pair, a nearly repeated model mode replaced by the span of its group.

    A model mode with neighbours closer than ``close`` (relative frequency) is replaced by the span of that group:
    MAC = ‖P φ‖² / ‖φ‖², P the projector onto the group's shapes. The individual shapes of a nearly repeated pair
    are not defined (a small perturbation rotates them within their plane), so the measured shape is compared with
    the plane; isolated modes keep the ordinary MAC.

    Parameters
    ----------
    pairing : ModePairing
        The pairs, from :func:`pair_modes` on these shapes.
    shapes_measured : array_like, shape (p, n_measured)
        The measured shapes (real or complex).
    shapes_model : array_like, shape (p, n_model)
        The model shapes, real, at the same sensors.
    f_model : array_like, shape (n_model,)
        The model frequencies, Hz.
    close : float, optional
        The relative frequency difference within which model modes are one group (default 0.03).

    Returns
    -------
    ndarray, shape (k,)
        MAC per pair, in [0, 1].

    Examples
    --------
    The second measured shape is a mix of two model modes 2 % apart:

    >>> measured = np.array([[1.0, 1.0], [0.5, -1.0], [0.2, 0.4]])
    >>> model = np.array([[1.0, 0.7, 0.7], [0.5, -0.7, -0.7], [0.2, 0.0, 0.6]])
    >>> pairing = era.pair_modes([2.0, 5.0], measured, [2.05, 4.95, 5.05], model)
    >>> print(np.round(pairing.mac, 3), np.round(era.subspace_mac(pairing, measured, model, [2.05, 4.95, 5.05]), 3))
    [1.    0.929] [1. 1.]
    """
    fa = np.clip(np.nan_to_num(np.asarray(f_model, dtype=float)), 0.0, None)
    sm = real_shapes(np.asarray(shapes_measured))
    sa = np.asarray(shapes_model, dtype=float)
    out = pairing.mac.copy()
    for n, (i, j) in enumerate(zip(pairing.measured_index, pairing.model_index)):
        group = np.flatnonzero(np.abs(fa - fa[j]) <= close * max(fa[j], 1e-12))
        if group.size > 1:
            q, _ = np.linalg.qr(sa[:, group])
            phi = sm[:, i]
            out[n] = float(np.sum((q.T @ phi) ** 2) / max(phi @ phi, 1e-300))
    return np.clip(out, 0.0, 1.0)


def gap(pairing: ModePairing, mac_values=None) -> Gap:
    """Summary of a pairing: max and RMS |frequency error| (%) and min and mean MAC; NaN when nothing paired.

    Parameters
    ----------
    pairing : ModePairing
        The pairs, from :func:`pair_modes`.
    mac_values : array_like, shape (k,), optional
        MAC per pair to use instead of ``pairing.mac`` (e.g. :func:`subspace_mac`).

    Returns
    -------
    Gap

    Examples
    --------
    >>> measured = np.array([[1.0, 1.0], [0.5, -1.0], [0.2, 0.4]])
    >>> model = np.array([[1.0, 0.9, 0.0], [0.55, -1.0, 1.0], [0.2, 0.5, -0.9]])
    >>> summary = era.gap(era.pair_modes([2.0, 5.1], measured, [2.1, 5.0, 8.0], model))
    >>> print(f"{summary.max_abs_freq_error_pct:.2f} % {summary.min_mac:.3f} {summary.n_pairs}")
    5.00 % 0.991 2
    """
    if pairing.n_pairs == 0:
        return Gap(float("nan"), float("nan"), float("nan"), float("nan"), 0)
    e = pairing.frequency_error_pct
    m = pairing.mac if mac_values is None else np.asarray(mac_values, dtype=float)
    return Gap(float(np.max(np.abs(e))), float(np.sqrt(np.mean(e**2))), float(np.min(m)),
               float(np.mean(m)), pairing.n_pairs)
