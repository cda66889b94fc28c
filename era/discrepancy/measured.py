"""Measured modes for correlation: ERA at several orders, the stable clusters, and their error levels."""

from __future__ import annotations

import numbers
from dataclasses import dataclass, replace

import numpy as np

from ..correlation import real_shapes
from ..data import ResponseData
from ..errors import DataError
from ..realization import Identification, identify
from ..selection import keep_mask, kept_modes
from ..stabilization import StableMode, stabilization


@dataclass(frozen=True, eq=False)
class MeasuredModes:
    """Identified modes with their measurement error levels.

    frequency_hz, frequency_std_hz, damping_ratio, mpc, emac : (k,) means and frequency spread across orders.
    shapes : (p, k) real shapes (principal phase), unit norm; n_orders : (k,) orders each mode was stable in.
    shape_std : (k,) RMS spread of the unit-norm shape components across those orders.
    modal_constants : (p, m, k) or None, the modal constants φ_j(sensor) φ_j(input) in 1/kg of a mass-normalised
        φ, when the data are displacement pulse responses to impulses of known size at known points (see
        :func:`modal_constants`); modal_constant_std : (k,) their relative spread across orders;
        input_locations : (m,) the input points (:func:`input_point`): grid joints (x_ft, y_ft), matching the
        model's node coordinates, or an era.Frame's (node id, direction), e.g. ("E", "x").
    """

    frequency_hz: np.ndarray
    frequency_std_hz: np.ndarray
    damping_ratio: np.ndarray
    mpc: np.ndarray
    emac: np.ndarray
    shapes: np.ndarray
    n_orders: np.ndarray
    shape_std: np.ndarray
    modal_constants: np.ndarray | None = None
    modal_constant_std: np.ndarray | None = None
    input_locations: tuple | None = None

    @property
    def n_modes(self) -> int:
        return int(self.frequency_hz.size)

    def take(self, idx) -> "MeasuredModes":
        idx = np.asarray(idx, dtype=int)
        known = self.modal_constants is not None
        return MeasuredModes(self.frequency_hz[idx], self.frequency_std_hz[idx], self.damping_ratio[idx],
                             self.mpc[idx], self.emac[idx], self.shapes[:, idx], self.n_orders[idx],
                             self.shape_std[idx], self.modal_constants[:, :, idx] if known else None,
                             self.modal_constant_std[idx] if known else None, self.input_locations)


def modes_from_arrays(frequency_hz, shapes, frequency_std_hz=None) -> MeasuredModes:
    """MeasuredModes from plain arrays (frequencies (k,) Hz, shapes (p, k)), e.g. from another identification."""
    f = np.asarray(frequency_hz, dtype=float).reshape(-1)
    s = real_shapes(np.asarray(shapes))
    if s.ndim != 2 or s.shape[1] != f.size:
        raise DataError(f"modes_from_arrays: {f.size} frequencies but shapes of shape {s.shape}; give (p, k).")
    s = s / np.linalg.norm(s, axis=0, keepdims=True)
    sd = np.zeros_like(f) if frequency_std_hz is None else np.asarray(frequency_std_hz, dtype=float).reshape(-1)
    one = np.ones_like(f)
    return MeasuredModes(f, sd, np.zeros_like(f), one, one, s, one.astype(int), np.zeros_like(f))


_TO_METRES = {"m": 1.0, "mm": 1e-3}


def _impulse_inputs(data: ResponseData):
    """(m,) input points and the output-to-metre factor when ``data`` are displacement pulse responses to
    impulses of known size (input units N·s, outputs m or mm, data.meta["input_locations"]); else None."""
    where = (data.meta or {}).get("input_locations")
    if (where is None or len(where) != data.n_inputs or data.input_units is None or data.output_units is None
            or any(u != "N·s" for u in data.input_units) or any(u not in _TO_METRES for u in data.output_units)
            or len(set(data.output_units)) != 1):
        return None
    return tuple(input_point(w, k) for k, w in enumerate(where)), _TO_METRES[data.output_units[0]]


def input_point(where, k: int = 0) -> tuple:
    """One input point as a tuple: numbers as floats (a grid joint (x_ft, y_ft)), names as str (an era.Frame's
    (node id, direction), e.g. ("E", "x"): node ids such as "E" or "12" stay names, not numbers)."""
    items = (where,) if isinstance(where, (str, bytes)) else where
    try:
        items = tuple(items)
    except TypeError:
        items = (where,)
    out = []
    for v in items:
        if isinstance(v, bytes):
            v = v.decode()
        if isinstance(v, str):
            out.append(v.strip())
        elif isinstance(v, numbers.Real) and not isinstance(v, bool) and np.isfinite(float(v)):
            out.append(float(v))
        else:
            raise DataError(f"data.meta['input_locations'][{k}] is {where!r}: give each input's point as numbers "
                            "(a grid joint (x_ft, y_ft)) or as a frame's (node id, direction), e.g. ('E', 'x').")
    return tuple(out)


def modal_constants(ident, stab, chosen, to_metres: float, weights=None):
    """Modal constants of each chosen mode from ERA's residues, averaged over the orders it was stable in.

    A displacement pulse response to a unit impulse is y(t) = Σ_j φ_j(i) φ_j(k) e^{−ζωt} sin(ω_d t)/ω_d for
    mass-normalised φ, so each pole's residue (eq. 35: Y(k) = Σ c_j z_j^k b_j + c.c.) is c_j b_jᵀ =
    φ_j φ_jᵀ/(2i ω_d): Re(2i ω_d c_j b_jᵀ) estimates φ_j(sensor) φ_j(input) in 1/kg, an absolute (mass) scale
    that frequencies and unit-norm shapes lack. Returns (p, m, k) and (k,) relative spread across orders.
    ident : the Identification ``stab`` was computed from (each pole's model is ``ident.model(order)``).
    weights : (m,) the factors the records were multiplied by before ERA (see :func:`input_weights`); they
    scale the columns of B, so the residues are divided by them again.
    """
    unweight = 1.0 if weights is None else 1.0 / np.asarray(weights, dtype=float)[None, :]
    orders = sorted({int(stab.order[i]) for md in chosen for i in md.pole_indices})
    models = {o: ident.model(o, uncertainty=False) for o in orders}  # the spread across orders is the error
    out, spread = [], []
    for md in chosen:
        each = []
        for pole in md.pole_indices:
            mdl, k = models[int(stab.order[pole])], int(stab.mode_index[pole])
            wd = 2 * np.pi * mdl.frequency_hz[k]
            each.append((2j * wd * np.outer(mdl.shapes[:, k], mdl.amplitudes[k, :])).real * to_metres * unweight)
        each = np.array(each)
        mean = each.mean(axis=0)
        rel = np.einsum("opm,pm->o", each, mean) / max(np.sum(mean**2), 1e-300)
        out.append(mean)
        spread.append(float(rel.std()))
    return np.stack(out, axis=2), np.array(spread)


def input_weights(markov: np.ndarray) -> np.ndarray:
    """(m,) factors 1 / RMS of each input's records (over samples and outputs) for markov (N, p, m).

    Scaling column j of every Y[k] scales column j of B only (Y[k] = C A^k B): poles, shapes and damping are
    unchanged, but every input's records then weigh alike in the SVD of the Hankel matrix. Without it, decays
    of very different size (the dwell test: a resonant swing mode at 0.36 Hz is ~500× the 6.5 Hz decay, as
    the response goes as 1/ω²) share one noise floor set by the largest record's noise, and the small
    records' modes sink below it. Records that are all zero keep weight 1.
    """
    rms = np.sqrt(np.mean(np.asarray(markov, dtype=float) ** 2, axis=(0, 1)))
    return np.where(rms > 0, 1.0 / np.where(rms > 0, rms, 1.0), 1.0)


def identify_modes(data: ResponseData, *, orders=range(20, 61, 4), rows: int | None = None,
                   balance_inputs: bool = True, **rules) -> MeasuredModes:
    """Run ERA on ``data`` at several orders and keep the modes that stay stable across them.

    One Hankel matrix and one SVD (era.identify) of a size chosen here, then :func:`measured_modes` over
    ``orders`` (``rules``: its min_orders, min_mpc, min_emac, max_damping, min_frequency_hz).

    balance_inputs : scale each input's records to unit RMS first (:func:`input_weights`), so that small
    decays (e.g. dwells at higher modes) are not buried under the noise of large ones; modal constants are
    scaled back. Balanced, weak poles (e.g. the lesser of a close pair) also rise above the noise floor; the
    EMAC floor of 0.7 keeps out those whose amplitude history is inconsistent with their pole (their shapes
    then pair at MAC ≈ 0.9, not ≥ 0.95).
    rows : block rows r of H(0) (default: enough for the largest order, r p ≥ 2 max order, at most N/3);
    the columns take most of the remaining samples, capped so H(0) stays a few hundred wide.
    """
    n, p, m = data.markov.shape
    top = max(int(o) for o in orders)
    if rows is None:
        rows = int(min(max(np.ceil(2 * top / p), 8), n // 3))
    cols = int(min(max(n - rows - 2, 1), max(4 * rows * p // max(m, 1), 200)))
    if n < rows + cols + 2 or rows < 2:
        raise DataError(f"identify_modes: {n} samples are too few for ERA up to order {top}; record longer.")
    weights = input_weights(data.markov) if balance_inputs else None
    weighted = data if weights is None else replace(
        data, markov=data.markov * weights[None, None, :],
        records=None if data.records is None else data.records * weights[None, None, None, :])
    return measured_modes(identify(weighted, rows, cols), orders, input_weights=weights, **rules)


def measured_modes(ident: Identification, orders=range(20, 61, 4), *, kept: tuple | None = None,
                   input_weights=None, min_orders: int = 4, min_mpc: float = 0.7, min_emac: float = 0.7,
                   max_damping: float = 0.1, min_frequency_hz: float = 0.05) -> MeasuredModes:
    """The measured modes of an identification, with error levels from their spread across ``orders``.

    era.stabilization over ``orders`` (every order from the same SVD). Then either

    - ``kept=None``: every mode stable in at least ``min_orders`` orders that passes the keep rule
      (:func:`era.selection.keep_mask`: γ ≥ min_emac, μ ≥ min_mpc, decaying pair with ζ ≤ max_damping) and lies
      between ``min_frequency_hz`` and 95 % of Nyquist; frequency, damping, γ, μ are means over its orders; or
    - ``kept=(order, indices)``: exactly the modes a person kept at one order (indices into
      ``ident.model(order)``), with that order's frequency, damping, γ, μ and shape. Their spread is that of the
      stable track they belong to (0 and one order when the pole is stable nowhere else).

    input_weights : (m,) factors the records were multiplied by before ERA (:func:`input_weights`), undone in the
    modal constants. Modal constants are computed when the data are impulse responses of known size at known
    points (see :func:`modal_constants`).
    """
    data = ident.data
    orders = {int(o) for o in orders}
    if kept is not None:
        order, indices = int(kept[0]), np.asarray(kept[1], dtype=int).reshape(-1)
        orders.add(order)
    stab = stabilization(ident, sorted(orders), min_orders=min_orders)
    if kept is None:
        chosen = _stable_modes(stab, min_mpc, min_emac, max_damping, min_frequency_hz, 0.5 / data.dt)
    else:
        chosen = _kept_modes(ident, stab, order, indices, min_frequency_hz, 0.5 / data.dt)
    if not chosen:
        raise DataError("ERA found no mode that is stable across orders; check the data (units, sampling, a "
                        "record long enough to hold several periods of the lowest mode)." if kept is None else
                        f"No mode was kept at order {kept[0]}: keep at least one mode to compare with the model.")
    shapes = real_shapes(np.stack([md.shape for md in chosen], axis=1))
    shapes = shapes / np.linalg.norm(shapes, axis=0, keepdims=True)
    spread = []
    for k, md in enumerate(chosen):
        each = real_shapes(stab.shapes[:, list(md.pole_indices)])
        each = each / np.linalg.norm(each, axis=0, keepdims=True)
        each = each * np.where(each.T @ shapes[:, k] < 0, -1.0, 1.0)[None, :]
        spread.append(float(np.sqrt(np.mean(np.var(each, axis=1)))))
    constants = constant_std = None
    impulses = _impulse_inputs(data)
    if impulses is not None:
        constants, constant_std = modal_constants(ident, stab, chosen, impulses[1], input_weights)
    return MeasuredModes(
        frequency_hz=np.array([md.frequency_hz for md in chosen]),
        frequency_std_hz=np.array([md.frequency_std_hz for md in chosen]),
        damping_ratio=np.array([md.damping_ratio for md in chosen]),
        mpc=np.array([md.mpc for md in chosen]), emac=np.array([md.emac for md in chosen]),
        shapes=shapes, n_orders=np.array([len(md.orders) for md in chosen]), shape_std=np.array(spread),
        modal_constants=constants, modal_constant_std=constant_std,
        input_locations=None if impulses is None else impulses[0])


def _stable_modes(stab, min_mpc, min_emac, max_damping, min_frequency_hz, nyquist_hz) -> list[StableMode]:
    """The suggested modes that pass the keep rule and the band; two tracks of one physical mode (drift with
    order) would pair twice, so of modes within 0.5 % the longer-lived one stays. Sorted by frequency."""
    modes = stab.modes
    f = np.array([md.frequency_hz for md in modes])
    ok = keep_mask([md.emac for md in modes], [md.mpc for md in modes], min_emac=min_emac, min_mpc=min_mpc,
                   damping_ratio=[md.damping_ratio for md in modes], is_pair=np.ones(len(modes), bool),
                   physical_only=True, max_damping=max_damping)
    ok &= (f >= min_frequency_hz) & (f <= 0.95 * nyquist_hz)
    chosen = []
    for md in sorted((md for md, good in zip(modes, ok) if good), key=lambda md: -len(md.orders)):
        if all(abs(md.frequency_hz - c.frequency_hz) > 0.005 * md.frequency_hz for c in chosen):
            chosen.append(md)
    return sorted(chosen, key=lambda md: md.frequency_hz)


def _kept_modes(ident, stab, order: int, indices: np.ndarray, min_frequency_hz: float,
                nyquist_hz: float) -> list[StableMode]:
    """The modes kept at one order, each with the track (stable mode) its pole belongs to, if any. Only decaying
    vibration modes can be compared with a model: a real or growing pole, or one outside the band, is refused."""
    model = ident.model(order)
    indices = kept_modes(model, indices)
    f = model.frequency_hz[indices]
    vibrating = keep_mask(model.emac[indices], model.mpc[indices], damping_ratio=model.damping_ratio[indices],
                          is_pair=model.is_pair[indices], physical_only=True)
    bad = indices[~vibrating | (f < min_frequency_hz) | (f > 0.95 * nyquist_hz)]
    if bad.size:
        raise DataError(f"Mode(s) {', '.join(str(int(k)) for k in bad)} at order {order} are not decaying vibration "
                        f"modes between {min_frequency_hz:g} Hz and 95 % of Nyquist ({0.95 * nyquist_hz:.3g} Hz): "
                        "real or growing poles, or at the band's edge. Untick them, or compare the stable modes.")
    track = {pole: md for md in stab.modes for pole in md.pole_indices}
    out = []
    for k in indices.tolist():
        pole = int(np.flatnonzero((stab.order == order) & (stab.mode_index == k))[0])
        md = track.get(pole)
        out.append(StableMode(
            frequency_hz=float(model.frequency_hz[k]), frequency_std_hz=md.frequency_std_hz if md else 0.0,
            damping_ratio=float(model.damping_ratio[k]), damping_std=md.damping_std if md else 0.0,
            emac=float(model.emac[k]), mpc=float(model.mpc[k]), orders=md.orders if md else (order,),
            pole_indices=md.pole_indices if md else (pole,), shape=model.shapes[:, k].copy()))
    return out
