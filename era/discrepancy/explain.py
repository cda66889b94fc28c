"""era.explain: from test data and a nominal model to the named missing effects (or an honest "don't know").

ERA modes (those era.choose_modes chooses from the diagram, or those a person kept) → pairing with the model
→ every candidate effect fitted and weighed by its evidence → further effects on top of the first while the gap
stays beyond the noise (search.py) → a verdict, the updated model, and the gap before, after each named effect,
and after (explanation.py).
"""

from __future__ import annotations

import contextlib
import time

import numpy as np

from ..core.blas import single_threaded_blas
from ..core.correlation import ModePairing, comac, gap, serep, subspace_mac
from ..core.data import ResponseData
from ..errors import DataError
from ..models.matrix import MatrixModel
from ..models.nastran.reader import NastranModel
from ..core.realization import Identification
from ..structure import Frame
from ..words import counted
from .effects import describe, nuisance, one_of, places_noun, short_place
from .effects_frame import frame_effects
from .effects_grid import grid_effects
from .explanation import PLACE_COVERAGE, VERDICTS, Explanation, NamedEffect
from .fitting import TRIAL_FAILURES, ErrorLevels, ModeWeights, effect_model, profile_interval
from .effects_matrix import matrix_effects
from .frame_model import FrameModel, refit_exact
from .deck_model import DeckExplainModel
from .effects_deck import deck_effects
from .matrix_model import MatrixExplainModel
from .measured import MeasuredModes, identify_modes, measured_modes, node_direction
from .part_scatter import with_part_scatter
from .protocol import ExplainModel, as_explain_model
from .ranking import credible_places, rank_effects
from .search import Search, search_effects
from .verdict import message_for, modes_the_model_lacks, too_few_data, verdict_of
from .weights import close_modes, node_rows, pair, struck_sensors, with_member_scatter

__all__ = ["VERDICTS", "Explanation", "NamedEffect", "explain"]

#: Models explained as frames are: every candidate fitted in its reduced model and solved steps (not Ritz), every
#: model mode in the tested band paired, the named set re-fitted in the full model (refit_exact).
SOLVED = (FrameModel, MatrixExplainModel, DeckExplainModel)


def _nominal(model, data) -> ExplainModel:
    """The ExplainModel of what explain() was given: an era.Frame, a MatrixModel (seen at its ``sensors``, else
    at the points the data's output labels name, "7x" or "7 x"), or a model of one's own."""
    if isinstance(model, Frame):
        return FrameModel.of(model)
    if isinstance(model, MatrixModel):
        sensors = model.sensors
        labels = getattr(data, "outputs", None) or getattr(getattr(data, "data", None), "outputs", None)
        if not sensors and labels:
            sensors = tuple(node_direction(x) for x in labels)
            if None in sensors:
                raise DataError("explain: the matrix model has no sensors and the data's output labels do not all "
                                "name a node and direction ('7x', '7 -z'); give MatrixModel(..., sensors=...).")
        if isinstance(model, NastranModel) and model.deck is not None:   # a deck: its properties are candidates
            return DeckExplainModel.of(model, sensors)
        return MatrixExplainModel.of(model, sensors)
    return as_explain_model(model)


def _select_modes(nominal: ExplainModel, specs, measured: MeasuredModes, n_model: int) -> np.ndarray:
    """Measured modes that pair (MAC ≥ 0.5, |Δf| ≤ 50 %) with the nominal or any candidate at its prior mean."""
    nu = nuisance(nominal)
    used = set()
    for spec in specs:
        if spec.located:
            continue
        params = (nu,) + tuple(spec.params)
        try:
            model = effect_model(nominal, spec, params, [p.prior_mean for p in params])
            used |= set(pair(model, measured, n_model).measured_index.tolist())
        except TRIAL_FAILURES:     # a candidate that cannot be solved pairs nothing (rank_effects says why)
            continue
    return np.array(sorted(used), dtype=int)


def _expand(fm: MeasuredModes, pairing: ModePairing, f_model, s_model, w_nodes) -> np.ndarray:
    """SEREP expansion of each measured shape with a local basis: its partner and the model modes nearest to it
    in frequency, p − 2 in all (fewer modes than sensors keeps Φ_s⁺ well conditioned), among the modes the
    sensors see (a frame's out-of-plane modes are zero at in-plane sensors: in Φ_s they would be a singular
    value of 1e-15 that Φ_s⁺ inflates to nonsense off the sensors). (n_nodes, k)."""
    p = fm.shapes.shape[0]
    norm = np.linalg.norm(s_model, axis=0)
    seen = np.flatnonzero(norm > 1e-6 * norm.max())
    n_basis = max(1, min(p - 2, seen.size))
    out = np.zeros((w_nodes.shape[0], fm.n_modes))
    for i in range(fm.n_modes):
        hit = np.flatnonzero(pairing.measured_index == i)
        centre = f_model[pairing.model_index[hit[0]]] if hit.size else fm.frequency_hz[i]
        basis = seen[np.argsort(np.abs(f_model[seen] - centre), kind="stable")[:n_basis]]
        out[:, i] = serep(fm.shapes[:, i], s_model[:, basis], w_nodes[:, basis])
    return out


def _named_effects(model: ExplainModel, found: Search, fm: MeasuredModes, w: ModeWeights, n_model: int, close: float) -> tuple:
    """A NamedEffect per named effect, most important first: its own parameters (and the stiffness factor)
    from the fit of the whole set, their 95 % intervals, its place, and the gap after the step that named it."""
    out, k = [], 1
    fit = found.fit
    assert fit is not None, "only a search that named something has effects to describe"
    for i, (r, spec) in enumerate(zip(found.named, found.specs)):
        idx = range(k, k + len(spec.params))
        k += len(spec.params)
        interval = {}
        for j in idx:
            try:
                iv = profile_interval(model, fit, fm, w, n_model, index=j,     # frames: solved steps, as before
                                      ritz_modes=0 if isinstance(model, SOLVED) else 30)
            except TRIAL_FAILURES:     # a step of the profile cannot be solved: no interval, the σ stands
                iv = None
            if iv is not None:
                interval[fit.params[j].name] = iv
        params = {**found.own(i), "stiffness_factor": fit.parameters["stiffness_factor"]}
        unc = {n: fit.uncertainty[n] for n in params}
        p_loc = r.locations[0][2] if r.locations else None
        others = tuple((loc, q) for loc, _, q in r.locations[1:] if q >= 0.05)
        places = credible_places(r.locations, PLACE_COVERAGE) if r.locations else ()
        size_name, size_iv = _size(spec, params, unc, interval)
        step = fit.model if i == len(found.named) - 1 else r.fit.model.exact
        f_s, s_s = step.modes(n_model)
        pairing = pair(step, fm, n_model, max_freq_error=1.0)
        g = gap(pairing, subspace_mac(pairing, fm.shapes, s_s, f_s, close))
        lead = ("The test data are best explained if" if i == 0 else
                "With that, the rest of the gap is best explained if")
        text = describe(spec, params, r.location, r.probability, unc, interval, lead=lead, places=places)
        if others and len(places) < 2:
            text += (f" The place is not certain ({p_loc:.0%}); also possible: "
                     + ", ".join(f"{short_place(loc)} {q:.0%}" for loc, q in others) + ".")
        text += (f" Gap after this step: max |Δf| {g.max_abs_freq_error_pct:.2f} %, min MAC {g.min_mac:.3f}.")
        out.append(NamedEffect(r.name, params, r.location, r.probability, text, unc, p_loc, others, interval,
                               gap_after=g, log_bayes_factor=r.log_bayes_factor, step=i + 1, places=places,
                               size_parameter=size_name, size_interval=size_iv,
                               cannot_tell=_cannot_tell(spec, places, size_name, size_iv, found.rankings[i], r.name)))
    return tuple(out)


def _size(spec, params: dict, unc: dict, interval: dict) -> tuple:
    """(keyword, (low, high)) of the effect's size, its own parameter: the 95 % profile interval, else ±1.96σ of
    the Laplace posterior (in ln for log parameters); (None, None) for an effect without a parameter."""
    if not spec.params:
        return None, None
    prm = spec.params[0]
    if prm.name in interval:
        return prm.name, tuple(interval[prm.name])
    v, sd = params.get(prm.name), unc.get(prm.name)
    if v is None or sd is None or not np.isfinite(sd):
        return prm.name, None
    if prm.log and v > 0:
        return prm.name, (float(v * np.exp(-1.96 * sd / v)), float(v * np.exp(1.96 * sd / v)))
    return prm.name, (float(v - 1.96 * sd), float(v + 1.96 * sd))


def _cannot_tell(spec, places: tuple, size_name, size_iv, ranking: tuple, name: str) -> tuple:
    """What the data cannot distinguish, in sentences: which of the places, a size bounded on one side only,
    another candidate of the same step still holding ≥ 5 % of the posterior."""
    out = []
    if len(places) > 1:
        out.append(f"which of {len(places)} {places_noun(spec, places[0][0])} it is ({one_of(spec, places)})")
    if size_name is not None and size_iv is not None:
        label = size_name.removesuffix("_kg").removesuffix("_m").replace("_", " ")
        low, high = size_iv
        if low is None and high is not None:
            out.append(f"how low the {label} is: every value below {high:.2g} fits as well")
        elif high is None and low is not None:
            out.append(f"how high the {label} is: every value above {low:.2g} fits as well")
    for x in ranking:
        if x.name not in (name, "none") and x.probability >= 0.05:
            out.append(f"whether it is {x.name.replace('_', ' ')} instead ({x.probability:.0%})")
    return tuple(out)


def explain(data: ResponseData | Identification | MeasuredModes, model, *, effects: tuple | None = None,
            errors: ErrorLevels = ErrorLevels(), orders=None, kept: tuple | None = None,
            min_probability: float = 0.9,
            min_log_bayes: float = float(np.log(100.0)), refine_locations: int = 4,
            extra_model_modes: int = 6, max_effects: int = 3, adequacy_test: dict | None = None) -> Explanation:
    """Find which candidate physical effect, missing from ``model``, the test data support.

    ERA's modes are paired with the model's, every candidate effect of a library is fitted (the nominal plus a
    global stiffness nuisance plus the effect's parameters) and the candidates are compared by Bayesian evidence;
    an effect is named only when it is clearly the best and the updated model is adequate.

    Parameters
    ----------
    data : ResponseData, Identification or MeasuredModes
        A ResponseData (N, p, m) with one output per model sensor, in model.sensors order (ERA then takes
        era.analyse's default path on the balanced inputs, :func:`identify_modes`); or an era.Identification of
        such data (a person's own Hankel size: its SVD is used as it is); or MeasuredModes already identified.
        Pulse responses to impulses (input_units "N·s", outputs in m or mm) whose points are given as
        data.meta["input_locations"] ((x_ft, y_ft) joints, as era.examples.grid_simulation records them) also
        contribute their modal constants, which fix the absolute mass; other data are fitted by frequencies and
        shapes only. With an era.Frame, the struck points of data.meta["input_points"] (era.core.points' labels,
        "4Z" or "E x") that name a node and direction of the frame are sensors for the comparison too, after the
        outputs (their input-side shapes scaled through a driving point, a point both measured and struck);
        others are said and left out. So are they with a matrix model, where a point is compared when it names a
        free DOF.
    model : Frame, MatrixModel or model
        The nominal model: an era.Frame (wrapped in :class:`FrameModel`, its mesh kept for every candidate), an
        era.MatrixModel (wrapped in MatrixExplainModel, seen at its ``sensors`` or else at the points the data's
        output labels name), ``era.examples.grid.nasa_grid(...)``, or anything with .modes(n), .node_modes(n),
        .params, .with_params(**changes), .sensors and the candidate places of located effects
        (EffectSpec.locations, or .joints_ft).
    effects : sequence of EffectSpec, optional
        The candidates, "none" first (default: :func:`frame_effects` for a Frame,
        :func:`era.discrepancy.effects_matrix.matrix_effects` for a matrix model,
        :func:`era.discrepancy.effects_grid.grid_effects` otherwise).
    errors : ErrorLevels, optional
        Error levels (model-form floors); ERA's spread across ``orders`` adds the measurement part.
    orders : iterable of int, optional
        The stabilization diagram's orders: era.choose_modes chooses the modes from it, and the modes are tracked
        over it (their spread); default era.analyse's (every even order from 2 to 160).
    kept : (int, sequence of int), optional
        (order, indices) with an Identification: compare exactly the modes a person kept at that order (see
        :func:`measured_modes`) instead of the modes era chooses.
    min_probability : float, optional
        Naming threshold on the posterior probability (default 0.9), against the nominal (+ stiffness factor), and
        for a further effect against the model with the effects named before it.
    min_log_bayes : float, optional
        Naming threshold on the log Bayes factor (default ln 100), likewise. The named set must also pass the χ²
        adequacy test (ranking.adequacy) or nothing is named.
    refine_locations : int, optional
        Located effects get a full fit at this many best-screened places (default 4).
    extra_model_modes : int, optional
        Model modes computed beyond the number measured, so a mode that moved can still pair (default 6).
    max_effects : int, optional
        At most this many effects are named (era.discrepancy.search; default 3).
    adequacy_test : dict, optional
        Keyword arguments of ranking.adequacy (its levels), None for its defaults.

    Returns
    -------
    Explanation
        Verdict "explained" names ``result.effects`` (``result.effect`` the first).

    Raises
    ------
    era.DataError
        When the data and the model do not fit together (sensors, channels), with what to change.

    References
    ----------
    Beck, J. L. and Yuen, K.-V. (2004), Model selection using response measurements: Bayesian probabilistic
    approach, Journal of Engineering Mechanics 130(2), 192-203 (the evidence of each candidate, here by Laplace's
    approximation).

    Examples
    --------
    A chain of six 1 kg masses on 100 kN/m springs; the tested one carries 0.5 kg more at node 4:

    >>> from era.discrepancy import modes_from_arrays
    >>> k = 1e5 * (2 * np.eye(6) - np.eye(6, k=1) - np.eye(6, k=-1))  # six 1 kg masses on springs of 100 kN/m
    >>> k[-1, -1] = 1e5  # the top is free; below node 1 the chain is fixed to ground
    >>> dofs = [(str(i + 1), "z") for i in range(6)]
    >>> model = era.MatrixModel(k, np.eye(6), dofs, sensors=dofs)
    >>> heavier = np.eye(6)
    >>> heavier[3, 3] = 1.5  # the test article carries 0.5 kg at node 4, which the model does not know
    >>> frequency_hz, shapes = model.with_matrices(mass=heavier).modes(4)
    >>> measured = modes_from_arrays(frequency_hz, shapes, 0.002 * frequency_hz)
    >>> result = era.explain(measured, model)
    >>> result.verdict, result.effect.name, result.effect.location
    ('explained', 'point_mass', '4')
    >>> low, high = result.effect.size_interval
    >>> print(f"{low:.2f} to {high:.2f} kg; gap {result.before.max_abs_freq_error_pct:.1f} % before, "
    ...       f"{result.after.max_abs_freq_error_pct:.1f} % after")
    0.40 to 0.60 kg; gap 7.3 % before, 0.0 % after
    """
    t0 = time.perf_counter()
    timing = {}
    nominal: ExplainModel = _nominal(model, data)
    model = nominal
    errors = errors.for_model(model)     # the model's own member scatter and model-form allowance where not given
    if kept is not None and not isinstance(data, Identification):
        raise DataError("explain: `kept` (order, mode indices) names modes of an identification; pass the "
                        "era.Identification they were kept from as `data`.")
    if isinstance(data, MeasuredModes):
        measured = data
    elif isinstance(data, (ResponseData, Identification)):
        p = data.n_outputs if isinstance(data, ResponseData) else data.data.n_outputs
        if p != len(model.sensors):
            raise DataError(f"explain: the data have {p} outputs but the model has {len(model.sensors)} "
                            "sensors; give one output per model sensor, in model.sensors order.")
        measured = (identify_modes(data, orders=orders) if isinstance(data, ResponseData)
                    else measured_modes(data, orders, kept=kept))
    else:
        raise DataError(f"explain: `data` must be an era.ResponseData, Identification or MeasuredModes, got "
                        f"{type(data).__name__}.")
    struck_words = ""
    if isinstance(model, FrameModel) and measured.struck_points:   # struck points: sensors for the comparison too
        frame, measured, struck_words = struck_sensors(model.frame, measured)
        model = nominal = model if frame is model.frame else FrameModel.of(frame)
    elif isinstance(model, MatrixExplainModel) and measured.struck_points:
        matrices, measured, struck_words = struck_sensors(model.model.with_sensors(model.sensors), measured)
        model = nominal = MatrixExplainModel.of(matrices, matrices.sensors)
    elif isinstance(model, DeckExplainModel) and measured.struck_points:
        deck, measured, struck_words = struck_sensors(model.deck_model.with_sensors(model.sensors), measured)
        model = nominal = DeckExplainModel.of(deck, deck.sensors)
    timing["era_s"] = time.perf_counter() - t0
    if effects is not None:
        specs = tuple(effects)
    else:
        specs = (frame_effects(model) if isinstance(model, FrameModel) else
                 deck_effects(model) if isinstance(model, DeckExplainModel) else
                 matrix_effects(model) if isinstance(model, MatrixExplainModel) else grid_effects(model))
    n_model = measured.n_modes + extra_model_modes
    fit_modes = _select_modes(model, specs, measured, n_model)
    if fit_modes.size < 2:
        raise DataError(f"explain: only {fit_modes.size} of the {measured.n_modes} measured modes look like any "
                        "model mode (MAC ≥ 0.5 within 50 % in frequency); check the sensor order and units.")
    unpaired = tuple(int(i) for i in np.setdiff1d(np.arange(measured.n_modes), fit_modes))
    fm = measured.take(fit_modes)
    n_model = fm.n_modes + extra_model_modes
    frames = isinstance(model, SOLVED)
    if frames:   # a frame's sensors miss many modes (out of plane, torsion): every model mode in the tested band
        f_nominal = model.modes(n_model + 8)[0]
        n_model = max(n_model, int(np.searchsorted(f_nominal, 1.2 * fm.frequency_hz.max())) + 2)
    close = close_modes(model, fm, n_model, errors.close)
    weights = errors.weights(fm, close, node_rows(model, fm))
    # an FE model's few parts: their scatter moves every mode together (a correlated error); a frame's members as before
    weights = (with_part_scatter(weights, errors, model, fm, n_model)
               or with_member_scatter(weights, errors, model, fm, n_model))
    t1 = time.perf_counter()
    joints = np.asarray(model.joints_ft, float)
    # a matrix model's trials are small dense eigenproblems, which a threaded BLAS slows 10-50 times on a busy
    # machine (0.6 ms against 30 ms for order 40 measured with the other core loaded)
    with single_threaded_blas() if isinstance(model, (MatrixExplainModel, DeckExplainModel)) else \
            contextlib.nullcontext():
        ranking = rank_effects(model, specs, nuisance(model), fm, weights, n_model, joints,
                               refine=refine_locations, fine_scan=frames, test=adequacy_test)
        found = search_effects(model, specs, nuisance(model), fm, weights, n_model, joints, first=ranking,
                               min_probability=min_probability, min_log_bayes=min_log_bayes,
                               max_effects=max_effects, refine=refine_locations, fine_scan=frames,
                               test=adequacy_test)
        if frames:    # ranked and searched in the reduced model: the named set's parameters from the full model
            found = refit_exact(model, found, nuisance(model), fm, weights, n_model)
    timing["ranking_s"] = time.perf_counter() - t1
    verdict, why = verdict_of(ranking, found, min_probability, min_log_bayes)
    if verdict == "explained":
        why = too_few_data(fm, found)
        if why:
            verdict = "ambiguous"
    if verdict == "explained" and found.fit is not None:
        why = modes_the_model_lacks(found.fit.model.exact, measured, n_model, close=errors.close)
        if why:
            verdict = "unexplained"
    t2 = time.perf_counter()           # the report: the named parameters' intervals, pairings, expansion
    none = next(r for r in ranking if r.name == "none")
    chosen = found.fit if verdict == "explained" and found.fit is not None else none.fit
    updated = chosen.model.exact     # a frame's full model, not its reduced one
    effects = _named_effects(model, found, fm, weights, n_model, errors.close) if verdict == "explained" else ()
    effect = effects[0] if effects else None
    before = pair(model, fm, n_model, max_freq_error=1.0)
    after = pair(updated, fm, n_model, max_freq_error=1.0)
    fa, sa = model.modes(n_model)
    fb, sb = updated.modes(n_model)
    badness = np.abs(chosen.freq_residual) + np.where(close, 0.0, (1 - chosen.mac) / 0.1 * 3.0)
    miss = np.flatnonzero((np.abs(chosen.freq_residual) > 3.0) | ((chosen.mac < 0.9) & ~close))
    miss = miss[np.argsort(-badness[miss], kind="stable")]
    comac_b = comac(fm.shapes[:, before.measured_index], sa[:, before.model_index]) if before.n_pairs else np.zeros(0)
    comac_a = comac(fm.shapes[:, after.measured_index], sb[:, after.model_index]) if after.n_pairs else np.zeros(0)
    f_nodes, w_nodes = updated.node_modes(n_model)
    expanded = _expand(fm, after, fb, sb, w_nodes)
    model_nodes = np.full((w_nodes.shape[0], fm.n_modes), np.nan)
    model_nodes[:, after.measured_index] = w_nodes[:, after.model_index]
    timing["report_s"] = time.perf_counter() - t2
    timing["total_s"] = time.perf_counter() - t0
    g_b = gap(before, subspace_mac(before, fm.shapes, sa, fa, errors.close))
    g_a = gap(after, subspace_mac(after, fm.shapes, sb, fb, errors.close))
    message = message_for(verdict, effects, ranking, found, g_b, g_a, miss, fm, chosen, comac_a, unpaired)
    if why:
        message = why + " " + message
    if struck_words:
        message += " " + struck_words
    rejected = [x for ranking in found.rankings for r in ranking for x in r.rejected]
    if rejected:       # rejected trials: no evidence for those places, said so (the first reason as an example)
        name, loc, reason = rejected[0]
        at = "" if loc is None else f" at {short_place(loc)}"
        message += (f" {counted(len(rejected), 'trial model')} could not be solved and "
                    f"{'counts' if len(rejected) == 1 else 'count'} as no evidence for "
                    f"{'its' if len(rejected) == 1 else 'their'} "
                    f"place, e.g. {name}{at}: {reason}")
    return Explanation(
        verdict=verdict, effect=effect, message=message, ranking=ranking, before=g_b, after=g_a,
        updated_model=updated, nominal_model=model, measured=measured, fit_modes=fit_modes, unpaired_measured=unpaired,
        pairing_before=before, pairing_after=after, mac_before=before.mac_matrix, mac_after=after.mac_matrix,
        comac_before=comac_b, comac_after=comac_a, close_modes=close, residual_modes=tuple(int(i) for i in miss),
        residual_sensors=tuple(int(i) for i in np.flatnonzero(comac_a < 0.9)),
        node_xy_ft=joints, expanded_measured=expanded, expanded_model=model_nodes,
        timing_s=timing, node_labels=tuple(model.node_labels), effects=effects,
        rankings=found.rankings, model_form=(errors.model_form or 0.0, errors.model_form_shape or 0.0))
