"""Measured modes for correlation: the modes era chooses from the stabilization diagram (era.choose_modes, the one
rule the app and era.analyse follow), or the modes a person kept at one order, with their error levels."""

from __future__ import annotations

import numbers
import re
from dataclasses import dataclass, replace

import numpy as np

from ..choice.analysis import analyse, diagram_and_choice, diagram_orders
from ..core.blas import single_threaded_blas
from ..choice.choose import ModeChoice
from ..core.correlation import real_shapes
from ..core.data import ResponseData
from ..errors import DataError
from ..core.points import channel_points, point_shapes
from ..core.realization import Identification
from ..core.selection import keep_mask, kept_modes
from ..core.stabilization import Stabilization, StableMode, stabilization
from ..words import listed

#: A kept mode below this frequency (Hz) is refused: a pole that slow is drift, not a vibration mode to compare.
KEPT_MIN_FREQUENCY_HZ = 0.05
#: ... and above this fraction of Nyquist: the anti-alias region, where ERA fits the filter, not the structure.
KEPT_MAX_NYQUIST = 0.95


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
    struck_points : (e,) labels of the struck points (``data.meta["input_points"]``) not among the outputs' points,
        or None; struck_shapes : (p + e, k) real unit-norm shapes at the outputs and then those points (the
        input-side shapes scaled through a driving point, by reciprocity: era.core.points), None when no point is
        both measured and struck; struck_shape_std : (k,) their spread across orders. See :meth:`with_struck`.
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
    struck_points: tuple | None = None
    struck_shapes: np.ndarray | None = None
    struck_shape_std: np.ndarray | None = None

    @property
    def n_modes(self) -> int:
        return int(self.frequency_hz.size)

    def take(self, idx) -> "MeasuredModes":
        idx = np.asarray(idx, dtype=int)
        q, q_std = self.modal_constants, self.modal_constant_std
        return MeasuredModes(self.frequency_hz[idx], self.frequency_std_hz[idx], self.damping_ratio[idx],
                             self.mpc[idx], self.emac[idx], self.shapes[:, idx], self.n_orders[idx],
                             self.shape_std[idx], None if q is None else q[:, :, idx],
                             None if q_std is None else q_std[idx], self.input_locations, self.struck_points,
                             None if self.struck_shapes is None else self.struck_shapes[:, idx],
                             None if self.struck_shape_std is None else self.struck_shape_std[idx])

    def with_struck(self, keep) -> "MeasuredModes":
        """These modes with the struck points ``keep`` (indices into struck_points) as extra shape rows after the
        outputs' (unit norm again; the spread of the extended shapes), the struck fields cleared."""
        if self.struck_shapes is None or self.struck_shape_std is None:
            raise DataError("with_struck: these modes have no shapes at struck points (no driving point).")
        p = self.shapes.shape[0]
        rows = list(range(p)) + [p + int(i) for i in keep]
        s = self.struck_shapes[rows]
        return replace(self, shapes=s / np.linalg.norm(s, axis=0, keepdims=True), shape_std=self.struck_shape_std,
                       struck_points=None, struck_shapes=None, struck_shape_std=None)


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
    out: list[str | float] = []
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
    with single_threaded_blas():  # tens of small eigensolutions: BLAS threads only contend (10× slower on 2 cores)
        models = {o: ident.model(o, uncertainty=False) for o in orders}  # the spread across orders is the error
    out, spread = [], []
    for md in chosen:
        per_order = []
        for pole in md.pole_indices:
            mdl, k = models[int(stab.order[pole])], int(stab.mode_index[pole])
            wd = 2 * np.pi * mdl.frequency_hz[k]
            per_order.append((2j * wd * np.outer(mdl.shapes[:, k], mdl.amplitudes[k, :])).real * to_metres * unweight)
        each = np.array(per_order)
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


def identify_modes(data: ResponseData, *, orders=None, rows: int | None = None, cols: int | None = None,
                   balance_inputs: bool = True) -> MeasuredModes:
    """The modes era chooses from ``data`` by its default path (:func:`era.analyse`: Hankel size, one SVD, the
    stabilization diagram with the data's uncertainty, :func:`era.choose_modes`), with their error levels.

    orders : the diagram's orders (default era.analyse's: every even order from 2 to 160 within the rank);
    rows, cols : block rows and columns of H(0) (default era.analyse's, era.core.suggest.hankel_size).
    balance_inputs : scale each input's records to unit RMS first (:func:`input_weights`), so that small
    decays (e.g. dwells at higher modes) are not buried under the noise of large ones; modal constants are
    scaled back. The choice's noise level is then each input's alike: unbalanced, a dwell test's higher modes
    sink below the noise of the largest decay and the choice keeps the first two or three.
    """
    weights = input_weights(data.markov) if balance_inputs else None
    weighted = data if weights is None else replace(
        data, markov=data.markov * weights[None, None, :],
        records=None if data.records is None else data.records * weights[None, None, None, :])
    found = analyse(weighted, rows=rows, cols=cols, orders=orders)
    return _from_choice(found.identification, found.stabilization, found.choice, weights)


def measured_modes(ident: Identification, orders=None, *, kept: tuple | None = None,
                   input_weights=None) -> MeasuredModes:
    """The measured modes of an identification, with error levels from their spread across ``orders``.

    era.stabilization over ``orders`` (every order from the same SVD; default era.analyse's: every even order
    from 2 to 160 within the identification's max_order). Then either

    - ``kept=None``: the modes :func:`era.choose_modes` chooses from that diagram (in the band of
      ``data.meta["band_hz"]``, else 0 to Nyquist), each with its track's means over its orders (frequency,
      damping, γ, μ, unit shape); or
    - ``kept=(order, indices)``: exactly the modes a person kept at one order (indices into
      ``ident.model(order)``), with that order's frequency, damping, γ, μ and shape. Their spread is that of the
      stable track they belong to (0 and one order when the pole is stable nowhere else).

    input_weights : (m,) factors the records were multiplied by before ERA (:func:`input_weights`), undone in the
    modal constants. Modal constants are computed when the data are impulse responses of known size at known
    points (see :func:`modal_constants`).
    """
    orders = {int(o) for o in (diagram_orders(ident.max_order) if orders is None else orders)}
    if kept is None:
        stab, picked = diagram_and_choice(ident, sorted(orders), _band(ident.data))
        return _from_choice(ident, stab, picked, input_weights)
    order, indices = int(kept[0]), np.asarray(kept[1], dtype=int).reshape(-1)
    stab = stabilization(ident, sorted(orders | {order}))
    chosen = _kept_modes(ident, stab, order, indices)
    if not chosen:
        raise DataError(f"No mode was kept at order {order}: keep at least one mode to compare with the model.")
    return _measured(ident, stab, chosen, input_weights)


def _band(data: ResponseData) -> tuple[float, float] | None:
    """The band the records hold (``data.meta["band_hz"]`` of FRF data), as era.analyse reads it; else None."""
    band = (data.meta or {}).get("band_hz")
    return None if band is None else (float(band[0]), float(band[1]))


def _from_choice(ident: Identification, stab: Stabilization, choice: ModeChoice, weights) -> MeasuredModes:
    """MeasuredModes of the chosen clusters: each chosen Candidate's track in the diagram (its means, spread,
    orders and poles); a mode of an exact realization (noise-free data: no cluster, ``diagram_index`` -1) as
    the model of the choice's order has it."""
    if not choice.n_modes:
        best = max(choice.rejected, key=lambda c: len(c.orders), default=None)
        said = "" if best is None else (f" (of its {len(choice.rejected)} clusters the longest-lived, "
                                        f"{best.frequency_hz:.4g} Hz in {len(best.orders)} orders, is left out: "
                                        f"{best.reason})")
        raise DataError(f"era chose no mode of the structure from the stabilization diagram{said}; check the data "
                        "(units, sampling, a record long enough to hold several periods of the lowest mode), or "
                        "keep modes at an order yourself.")
    tracks = [stab.modes[c.diagram_index] if c.diagram_index >= 0 else _pole_modes(ident, stab, choice.order, [k])[0]
              for c, k in zip(choice.chosen, choice.indices.tolist())]
    return _measured(ident, stab, tracks, weights, mean_shapes=True)


def _measured(ident: Identification, stab: Stabilization, chosen: list[StableMode], weights,
              mean_shapes: bool = False) -> MeasuredModes:
    """MeasuredModes of tracks of ``stab`` (StableModes, by frequency): their shapes, spreads and modal constants.

    mean_shapes : each shape is the mean of its track's unit shapes (real, signs aligned) instead of the
    StableMode's own (its highest order's, or a kept order's): over a diagram up to order 160 the highest order's
    shape is the noisiest (the grid's 9.84 Hz mode: 1 - MAC with the truth 0.048 at order 160, 0.0003 for the
    mean), as the frequency is a mean too.
    """
    data = ident.data
    shapes = real_shapes(np.stack([md.shape for md in chosen], axis=1))
    shapes = shapes / np.linalg.norm(shapes, axis=0, keepdims=True)
    spread = []
    for k, md in enumerate(chosen):
        each = real_shapes(stab.shapes[:, list(md.pole_indices)])
        each = each / np.linalg.norm(each, axis=0, keepdims=True)
        each = each * np.where(each.T @ shapes[:, k] < 0, -1.0, 1.0)[None, :]
        if mean_shapes:
            shapes[:, k] = each.mean(axis=1) / np.linalg.norm(each.mean(axis=1))
        spread.append(float(np.sqrt(np.mean(np.var(each, axis=1)))))
    constants = constant_std = None
    impulses = _impulse_inputs(data)
    if impulses is not None:
        constants, constant_std = modal_constants(ident, stab, chosen, impulses[1], weights)
    struck = struck_shapes(ident, stab, chosen, weights)
    return MeasuredModes(
        frequency_hz=np.array([md.frequency_hz for md in chosen]),
        frequency_std_hz=np.array([md.frequency_std_hz for md in chosen]),
        damping_ratio=np.array([md.damping_ratio for md in chosen]),
        mpc=np.array([md.mpc for md in chosen]), emac=np.array([md.emac for md in chosen]),
        shapes=shapes, n_orders=np.array([len(md.orders) for md in chosen]), shape_std=np.array(spread),
        modal_constants=constants, modal_constant_std=constant_std,
        input_locations=None if impulses is None else impulses[0], struck_points=struck[0], struck_shapes=struck[1],
        struck_shape_std=struck[2])


def struck_shapes(ident, stab, chosen, weights=None) -> tuple:
    """(labels (e,), shapes (p + e, k), spread (k,)) of the struck points of ``ident.data`` that are not among its
    outputs' points: each chosen mode's shape at the outputs (as the channels read it, the rows of ``shapes``) and
    at those points, from every pole of its track (:func:`era.core.points.point_shapes`: reciprocity, scaled through
    the driving points), real, unit norm, averaged like the shapes. (None, None, None) without
    ``data.meta["input_points"]``; (labels, None, None) when no point is both measured and struck.
    weights : (m,) the factors the records were multiplied by before ERA (:func:`input_weights`), undone."""
    data = ident.data
    meta = data.meta or {}
    if not any(str(x) for x in (meta.get("input_points") or ())):
        return None, None, None
    out_labels, out_signs = channel_points(meta, "output", data.outputs or ("",) * data.n_outputs)
    in_labels, in_signs = channel_points(meta, "input", data.inputs or ("",) * data.n_inputs)
    key = lambda pt: " ".join(node_direction(pt) or (pt,))     # noqa: E731  "4Z" and "4 z": one point
    out_pts, in_pts = tuple(key(pt) for pt in out_labels), tuple(key(pt) for pt in in_labels)
    extra = tuple(dict.fromkeys(pt for pt in in_pts if pt and pt not in out_pts))
    labels = tuple(in_labels[in_pts.index(pt)] for pt in extra) or None
    if not extra or not (set(out_pts) & set(in_pts)) - {""}:
        return labels, None, None
    unweight = 1.0 if weights is None else 1.0 / np.asarray(weights, dtype=float)[None, :]
    orders = sorted({int(stab.order[i]) for md in chosen for i in md.pole_indices})
    with single_threaded_blas():
        models = {o: ident.model(o, uncertainty=False) for o in orders}
    shapes, spread = [], []
    for md in chosen:
        rows = []
        for pole in md.pole_indices:
            mdl, k = models[int(stab.order[pole])], int(stab.mode_index[pole])
            pts, vals = point_shapes(mdl.shapes[:, [k]], mdl.amplitudes[[k], :] * unweight, out_pts, in_pts,
                                     out_signs, in_signs)
            at = {pt: i for i, pt in enumerate(pts)}
            rows.append([vals[at[pt], 0] * sg for pt, sg in zip(out_pts, out_signs)]
                        + [vals[at[pt], 0] for pt in extra])
        each = real_shapes(np.array(rows).T)
        each = each / np.linalg.norm(each, axis=0, keepdims=True)
        each = each * np.where(each.T @ each[:, 0] < 0, -1.0, 1.0)[None, :]
        mean = each.mean(axis=1)
        shapes.append(mean / np.linalg.norm(mean))
        spread.append(float(np.sqrt(np.mean(np.var(each, axis=1)))))
    return labels, np.stack(shapes, axis=1), np.array(spread)


_NODE_DIRECTION = re.compile(r"^(\S+?)\s*(-?[xyz])$", re.IGNORECASE)


def node_direction(label) -> tuple | None:
    """(node, direction) a point label names: "4X", "4 x" -> ("4", "x"); "E -z" -> ("E", "-z") (era.core.points' "node
    axis" labels, a frame's sensor names "node direction"); None for any other label (e.g. "4RX", a rotation)."""
    hit = _NODE_DIRECTION.match(str(label).strip())
    if hit is None or re.fullmatch(r"-?\d+R", hit.group(1), re.IGNORECASE):
        return None
    return hit.group(1), hit.group(2).lower()


def _kept_modes(ident, stab, order: int, indices: np.ndarray) -> list[StableMode]:
    """The modes kept at one order, each with the track (stable mode) its pole belongs to, if any. Only decaying
    vibration modes can be compared with a model: a real or growing pole, or one outside the band, is refused."""
    model = ident.model(order)
    indices = kept_modes(model, indices)
    min_frequency_hz, top_hz = KEPT_MIN_FREQUENCY_HZ, KEPT_MAX_NYQUIST * 0.5 / ident.dt
    f = model.frequency_hz[indices]
    vibrating = keep_mask(model.emac[indices], model.mpc[indices], damping_ratio=model.damping_ratio[indices],
                          is_pair=model.is_pair[indices], physical_only=True)
    bad = indices[~vibrating | (f < min_frequency_hz) | (f > top_hz)]
    if bad.size:
        raise DataError(f"{'Modes' if bad.size > 1 else 'Mode'} {listed(int(k) for k in bad)} at order {order} "
                        f"{'are not decaying vibration modes' if bad.size > 1 else 'is not a decaying vibration mode'} "
                        f"between {min_frequency_hz:g} Hz and {100 * KEPT_MAX_NYQUIST:g} % of Nyquist "
                        f"({top_hz:.3g} Hz): real or growing poles, or at the band's edge. Untick them, or compare "
                        "the modes era chooses.")
    return _pole_modes(ident, stab, order, indices)


def _pole_modes(ident, stab, order: int, indices) -> list[StableMode]:
    """Modes ``indices`` of ``ident.model(order)`` with that order's frequency, damping, γ, μ and shape, and the
    spread and orders of the track (stable mode) each one's pole belongs to: 0 and that order alone when none."""
    model = ident.model(order)
    track = {pole: md for md in stab.modes for pole in md.pole_indices}
    out = []
    for k in np.asarray(indices, dtype=int).tolist():
        pole = int(np.flatnonzero((stab.order == order) & (stab.mode_index == k))[0])
        md = track.get(pole)
        out.append(StableMode(
            frequency_hz=float(model.frequency_hz[k]), frequency_std_hz=md.frequency_std_hz if md else 0.0,
            damping_ratio=float(model.damping_ratio[k]), damping_std=md.damping_std if md else 0.0,
            emac=float(model.emac[k]), mpc=float(model.mpc[k]), orders=md.orders if md else (order,),
            pole_indices=md.pole_indices if md else (pole,), shape=model.shapes[:, k].copy()))
    return out
