"""era.explain: from test data and a nominal model to the named missing effects (or an honest "don't know").

ERA modes (those era.choose_modes chooses from the diagram, or those a person kept) → pairing with the model
→ every candidate effect fitted and weighed by its evidence → further effects on top of the first while the gap
stays beyond the noise (search.py) → a verdict, the updated model, and the gap before, after each named effect,
and after.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..correlation import Gap, ModePairing, comac, gap, pair_modes, serep, subspace_mac
from ..data import ResponseData
from ..errors import DataError
from ..realization import Identification
from ..structure import Frame
from .effects import describe, nuisance, short_place
from .effects_frame import frame_effects
from .effects_grid import grid_effects
from .frame_model import FrameModel, refit_exact
from .fitting import TRIAL_FAILURES, ErrorLevels, ModeWeights, build_model, profile_interval
from .measured import MeasuredModes, identify_modes, measured_modes
from .ranking import RankedEffect, _js, rank_effects
from .search import Search, search_effects
from .protocol import ExplainModel, Modes, as_explain_model
from .verdict import message_for, too_few_data, verdict_of

VERDICTS = ("explained", "no_significant_discrepancy", "ambiguous", "unexplained")


@dataclass(frozen=True)
class NamedEffect:
    """The effect the data support: name, fitted parameters {keyword: value} (incl. stiffness_factor),
    location (x_ft, y_ft) on the grid, a node id (str) or a member (node i, node j) on an era.Frame, or None;
    posterior probability, a one-sentence description, the 1σ uncertainty
    {keyword: value} of each parameter (Laplace posterior), and for located effects the probability of the
    location given the effect and the other places still in contention (location, probability);
    interval {keyword: (low, high)}: the effect parameter's 95 % profile-posterior interval, None on a side the
    data do not bound (then the description gives a bound, not a value); gap_after : the Gap of the model with
    the effects named up to this one; log_bayes_factor : against the model with the effects named before it;
    step : 1 for the first named, 2 for the second, ...
    With several effects, parameters, uncertainty and interval come from the fit of the whole named set."""

    name: str
    parameters: dict
    location: tuple | None
    probability: float
    description: str
    uncertainty: dict
    location_probability: float | None = None
    other_locations: tuple = ()
    interval: dict = field(default_factory=dict)
    gap_after: Gap | None = None
    log_bayes_factor: float | None = None
    step: int = 1

    def as_dict(self) -> dict:
        loc = self.location

        def js(v):
            return [js(x) for x in v] if isinstance(v, tuple) else (v if isinstance(v, str) else float(v))
        return {"name": self.name, "parameters": self.parameters, "uncertainty": self.uncertainty,
                "location": None if loc is None else js(loc), "location_probability": self.location_probability,
                "other_locations": [[js(loc), q] for loc, q in self.other_locations],
                "interval": {k: list(v) for k, v in self.interval.items()},
                "probability": self.probability, "description": self.description,
                "gap_after": None if self.gap_after is None else self.gap_after.as_dict(),
                "log_bayes_factor": self.log_bayes_factor, "step": self.step}


@dataclass(frozen=True, eq=False)
class Explanation:
    """Result of :func:`explain`.

    verdict : one of VERDICTS; effects : the NamedEffects, most important first (empty unless "explained");
    effect : the first of them or None; message : one paragraph for the report.
    ranking : RankedEffect per candidate, most probable first (step 1: each alone against the nominal);
    rankings : the ranking of every step of the search for several effects (rankings[0] is ranking).
    before, after : Gap of the nominal and of the updated model over the paired modes.
    updated_model : the best-supported model (the named effects fitted, else the nominal with the fitted
        global stiffness factor); nominal_model : the model given.
    measured : every mode ERA found; fit_modes : (k,) indices of those used (paired with some candidate);
    unpaired_measured : indices of measured modes no candidate could pair (set aside).
    pairing_before, pairing_after : ModePairing of the fitted modes with the nominal and the updated model;
    mac_before, mac_after : their MAC matrices (k, n_model); comac_before, comac_after : (p,) per sensor.
    close_modes : (k,) bool, nearly repeated modes (their shapes are compared as a plane, not one by one).
    residual_modes : indices (into fit_modes) where the updated model still misses (|Δf| > 3σ or MAC < 0.9),
        worst first;
    residual_sensors : sensors with COMAC < 0.9 after the update.
    node_xy_ft : (n_nodes, 2) on the grid, (0, 2) on a frame; expanded_measured : (n_rows, k) SEREP expansion of
    the measured shapes with the updated model's paired modes; expanded_model : (n_rows, k) those model modes (NaN
    columns when unpaired); rows: the grid's joints, or a frame's node translations (node_labels "7:x", ...).
    timing_s : wall-clock seconds of each stage.
    """

    verdict: str
    effect: NamedEffect | None
    message: str
    ranking: tuple
    before: Gap
    after: Gap
    updated_model: ExplainModel
    nominal_model: ExplainModel
    measured: MeasuredModes
    fit_modes: np.ndarray
    unpaired_measured: tuple
    pairing_before: ModePairing
    pairing_after: ModePairing
    mac_before: np.ndarray
    mac_after: np.ndarray
    comac_before: np.ndarray
    comac_after: np.ndarray
    close_modes: np.ndarray
    residual_modes: tuple
    residual_sensors: tuple
    node_xy_ft: np.ndarray
    expanded_measured: np.ndarray
    expanded_model: np.ndarray
    timing_s: dict
    node_labels: tuple = ()
    effects: tuple = ()
    rankings: tuple = ()

    @property
    def rejected_trials(self) -> tuple:
        """(effect name, location or None, reason) of every trial model that could not be solved (a change that
        made the model a mechanism, singular or modeless), over every step of the search: no evidence there."""
        seen, out = set(), []
        for ranking in self.rankings or (self.ranking,):
            for r in ranking:
                for name, loc, why in r.rejected:
                    if (name, repr(loc)) not in seen:
                        seen.add((name, repr(loc)))
                        out.append((name, loc, why))
        return tuple(out)

    def candidate(self, name: str) -> RankedEffect:
        """The ranking entry of one candidate, by name."""
        return next(r for r in self.ranking if r.name == name)

    def mode_table(self) -> list:
        """One row per fitted measured mode: measured f (Hz) and ζ, then the nominal and the updated model's
        partner (f Hz, error %, MAC; None when unpaired), and whether the mode is nearly repeated."""
        fm = self.measured.take(self.fit_modes)
        rows = []
        for i in range(fm.n_modes):
            row: dict[str, Any] = {"mode": i + 1, "measured_hz": float(fm.frequency_hz[i]), "damping_ratio": float(fm.damping_ratio[i]),
                   "nearly_repeated": bool(self.close_modes[i])}
            for key, pairing in (("nominal", self.pairing_before), ("updated", self.pairing_after)):
                hit = np.flatnonzero(pairing.measured_index == i)
                k = int(hit[0]) if hit.size else None
                row[f"{key}_hz"] = None if k is None else float(pairing.frequency_model_hz[k])
                row[f"{key}_error_pct"] = None if k is None else float(pairing.frequency_error_pct[k])
                row[f"{key}_mac"] = None if k is None else float(pairing.mac[k])
            rows.append(row)
        return rows

    def as_dict(self) -> dict:
        """JSON-ready summary for the app and the report (no model objects; arrays as lists)."""
        e = self.effect
        return {
            "verdict": self.verdict, "message": self.message,
            "effect": None if e is None else e.as_dict(),
            "effects": [x.as_dict() for x in self.effects],
            "ranking": [r.as_dict() for r in self.ranking],
            "rejected_trials": [{"effect": n, "location": _js(loc), "reason": why}
                                for n, loc, why in self.rejected_trials],
            "before": self.before.as_dict(), "after": self.after.as_dict(),
            "updated_params": {k: (list(v) if isinstance(v, tuple) else v)
                               for k, v in self.updated_model.params.items()},
            "modes": self.mode_table(),
            "unpaired_measured_hz": [float(self.measured.frequency_hz[i]) for i in self.unpaired_measured],
            "mac_before": self.mac_before.tolist(), "mac_after": self.mac_after.tolist(),
            "comac_before": self.comac_before.tolist(), "comac_after": self.comac_after.tolist(),
            "residual_modes": list(self.residual_modes), "residual_sensors": list(self.residual_sensors),
            "node_xy_ft": self.node_xy_ft.tolist(),
            "expanded_measured": self.expanded_measured.tolist(),
            "expanded_model": np.where(np.isfinite(self.expanded_model), self.expanded_model, 0.0).tolist(),
            "timing_s": dict(self.timing_s),
        }


def _pair(model: Modes, measured: MeasuredModes, n_model: int, **kw) -> ModePairing:
    f, shapes = model.modes(n_model)
    return pair_modes(measured.frequency_hz, measured.shapes, f, shapes, **kw)


def _select_modes(nominal: ExplainModel, specs, measured: MeasuredModes, n_model: int) -> np.ndarray:
    """Measured modes that pair (MAC ≥ 0.5, |Δf| ≤ 50 %) with the nominal or any candidate at its prior mean."""
    nu = nuisance(nominal)
    used = set()
    for spec in specs:
        if spec.located:
            continue
        params = (nu,) + tuple(spec.params)
        try:
            model = build_model(nominal, spec, params, [p.prior_mean for p in params])
            used |= set(_pair(model, measured, n_model).measured_index.tolist())
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


def _node_rows(model: ExplainModel, measured: MeasuredModes):
    """Rows of model.node_modes at the sensors and at the measured inputs, or None when the modal constants
    cannot be compared (no known inputs, or an input that is not a model node)."""
    if measured.modal_constants is None:
        return None
    return model.modal_rows(measured.input_locations)


def _close_modes(model: ExplainModel, measured: MeasuredModes, n_model: int, close: float) -> np.ndarray:
    """(k,) True for measured modes with a neighbour within ``close`` (relative), among the measured modes or
    among the nominal model's modes next to their partner: nearly repeated modes."""
    f = measured.frequency_hz
    rel = np.abs(f[:, None] - f[None, :]) / f[:, None]
    np.fill_diagonal(rel, np.inf)
    out = rel.min(axis=1) <= close
    p = _pair(model, measured, n_model, max_freq_error=1.0)
    fa = np.clip(np.nan_to_num(model.modes(n_model)[0]), 0.0, None)
    for i, j in zip(p.measured_index, p.model_index):
        others = np.delete(fa, j)
        if others.size and np.min(np.abs(others - fa[j])) <= close * max(fa[j], 1e-12):
            out[i] = True
    return out


def _with_member_scatter(w: ModeWeights, errors: ErrorLevels, model: ExplainModel, fm: MeasuredModes, n_model: int):
    """The weights with the members' stiffness scatter added (ErrorLevels.member_scatter, or the model's
    ``default_member_scatter``), through each measured mode's nominal partner: to its frequency by the partner's
    strain-energy shares, to its shape components by the shape's sensitivity to each member
    (``member_shape_sensitivity``; capped at ``close_shape_sigma``, which already frees a nearly repeated pair),
    and to its modal constants' size (``member_scale_sensitivity``, correlated across modes) when they are fitted."""
    scatter = errors.member_scatter
    if scatter is None:
        scatter = model.default_member_scatter
    share = model.member_energy_fractions(n_model) if scatter else None     # (n_members, n_model)
    if share is None:
        return w
    rel = 0.5 * scatter * np.sqrt(np.sum(share**2, axis=0))          # (n_model,) relative 1σ of each frequency
    pairing = _pair(model, fm, n_model, max_freq_error=1.0)
    per_mode = np.full(fm.n_modes, rel.max())
    per_mode[pairing.measured_index] = rel[pairing.model_index]
    w = dataclasses.replace(w, sigma_f=np.hypot(w.sigma_f, per_mode * fm.frequency_hz))
    d = model.member_shape_sensitivity(n_model)                       # (n_members, p, n_model)
    if d is None:
        return w
    comp = np.minimum(scatter * np.sqrt(np.mean(np.sum(d**2, axis=0), axis=0)), errors.close_shape_sigma)
    per_shape = np.full(fm.n_modes, comp.max())
    per_shape[pairing.measured_index] = comp[pairing.model_index]
    w = dataclasses.replace(w, sigma_s=np.hypot(w.sigma_s, per_shape))
    whitener = w.scale_whitener
    g = None if whitener is None else model.member_scale_sensitivity(w.node_rows, n_model)
    if whitener is None or g is None:                                   # g: (n_members, n_model)
        return w
    # the modal constants' sizes move with the shapes at the sensors and inputs, together across modes (each
    # member's scatter is one draw for all of them): scatter² GᵀG joins their covariance, as the gains' does
    per = np.zeros((g.shape[0], fm.n_modes))
    per[:, pairing.measured_index] = g[:, pairing.model_index]
    unwhite = np.linalg.inv(whitener)
    cov = unwhite @ unwhite.T + scatter**2 * per.T @ per
    return dataclasses.replace(w, scale_whitener=np.linalg.inv(np.linalg.cholesky(cov)))


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
                                      ritz_modes=0 if isinstance(model, FrameModel) else 30)
            except TRIAL_FAILURES:     # a step of the profile cannot be solved: no interval, the σ stands
                iv = None
            if iv is not None:
                interval[fit.params[j].name] = iv
        params = {**found.own(i), "stiffness_factor": fit.parameters["stiffness_factor"]}
        unc = {n: fit.uncertainty[n] for n in params}
        p_loc = r.locations[0][2] if r.locations else None
        others = tuple((loc, q) for loc, _, q in r.locations[1:] if q >= 0.05)
        step = fit.model if i == len(found.named) - 1 else r.fit.model.exact
        f_s, s_s = step.modes(n_model)
        pairing = _pair(step, fm, n_model, max_freq_error=1.0)
        g = gap(pairing, subspace_mac(pairing, fm.shapes, s_s, f_s, close))
        lead = ("The test data are best explained if" if i == 0 else
                "With that, the rest of the gap is best explained if")
        text = describe(spec, params, r.location, r.probability, unc, interval, lead=lead)
        if others:
            text += (f" The place is not certain ({p_loc:.0%}); also possible: "
                     + ", ".join(f"{short_place(loc)} {q:.0%}" for loc, q in others) + ".")
        text += (f" Gap after this step: max |Δf| {g.max_abs_freq_error_pct:.2f} %, min MAC {g.min_mac:.3f}.")
        out.append(NamedEffect(r.name, params, r.location, r.probability, text, unc, p_loc, others, interval,
                               gap_after=g, log_bayes_factor=r.log_bayes_factor, step=i + 1))
    return tuple(out)


def explain(data: ResponseData | Identification | MeasuredModes, model, *, effects: tuple | None = None,
            errors: ErrorLevels = ErrorLevels(), orders=None, kept: tuple | None = None,
            min_probability: float = 0.9,
            min_log_bayes: float = float(np.log(100.0)), refine_locations: int = 4,
            extra_model_modes: int = 6, max_effects: int = 3, adequacy_test: dict | None = None) -> Explanation:
    """Find which candidate physical effect, missing from ``model``, the test data support.

    Parameters
    ----------
    data : era.ResponseData (N, p, m) with one output per model sensor, in model.sensors order (ERA then takes
        era.analyse's default path on the balanced inputs, :func:`identify_modes`); or an era.Identification of
        such data (a person's own Hankel size: its SVD is used as it is); or MeasuredModes already identified. Pulse
        responses to impulses (input_units "N·s", outputs in m or mm) whose points are given as
        data.meta["input_locations"] ((x_ft, y_ft) joints, as era.examples.grid_simulation records them) also contribute their
        modal constants, which fix the absolute mass; other data are fitted by frequencies and shapes only.
    model : the nominal model: an era.Frame (wrapped in :class:`FrameModel`, its mesh kept for every candidate),
        ``era.examples.grid.nasa_grid(...)``, or anything with .modes(n), .node_modes(n), .params,
        .with_params(**changes), .sensors and the candidate places of located effects (EffectSpec.locations, or
        .joints_ft).
    effects : candidate EffectSpecs, "none" first (default: :func:`frame_effects` for a Frame,
        :func:`era.discrepancy.effects_grid.grid_effects` otherwise).
    errors : error levels (model-form floors); ERA's spread across ``orders`` adds the measurement part.
    orders : the stabilization diagram's orders: era.choose_modes chooses the modes from it, and the modes are
        tracked over it (their spread); default era.analyse's (every even order from 2 to 160).
    kept : (order, indices) with an Identification: compare exactly the modes a person kept at that order
        (see :func:`measured_modes`) instead of the modes era chooses.
    min_probability, min_log_bayes : naming thresholds — posterior ≥ 0.9 and Bayes factor ≥ 100 against the
        nominal (+ stiffness factor), and for a further effect against the model with the effects named before
        it; the named set must also pass the χ² adequacy test (ranking.adequacy) or nothing is named.
    max_effects : at most this many effects are named (era.discrepancy.search).
    adequacy_test : keyword arguments of ranking.adequacy (its levels), None for its defaults.
    refine_locations : located effects get a full fit at this many best-screened joints.
    extra_model_modes : model modes computed beyond the number measured, so a mode that moved can still pair.

    Returns
    -------
    Explanation (see its docstring); verdict "explained" names ``result.effects`` (``result.effect`` the first).
    """
    t0 = time.perf_counter()
    timing = {}
    nominal: ExplainModel = FrameModel.of(model) if isinstance(model, Frame) else as_explain_model(model)
    model = nominal
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
    timing["era_s"] = time.perf_counter() - t0
    if effects is not None:
        specs = tuple(effects)
    else:
        specs = frame_effects(model) if isinstance(model, FrameModel) else grid_effects(model)
    n_model = measured.n_modes + extra_model_modes
    fit_modes = _select_modes(model, specs, measured, n_model)
    if fit_modes.size < 2:
        raise DataError(f"explain: only {fit_modes.size} of the {measured.n_modes} measured modes look like any "
                        "model mode (MAC ≥ 0.5 within 50 % in frequency); check the sensor order and units.")
    unpaired = tuple(int(i) for i in np.setdiff1d(np.arange(measured.n_modes), fit_modes))
    fm = measured.take(fit_modes)
    n_model = fm.n_modes + extra_model_modes
    frames = isinstance(model, FrameModel)
    if frames:   # a frame's sensors miss many modes (out of plane, torsion): every model mode in the tested band
        f_nominal = model.modes(n_model + 8)[0]
        n_model = max(n_model, int(np.searchsorted(f_nominal, 1.2 * fm.frequency_hz.max())) + 2)
    close = _close_modes(model, fm, n_model, errors.close)
    weights = _with_member_scatter(errors.weights(fm, close, _node_rows(model, fm)), errors, model, fm, n_model)
    t1 = time.perf_counter()
    joints = np.asarray(model.joints_ft, float)
    ranking = rank_effects(model, specs, nuisance(model), fm, weights, n_model, joints, refine=refine_locations,
                           fine_scan=frames, test=adequacy_test)
    found = search_effects(model, specs, nuisance(model), fm, weights, n_model, joints, first=ranking,
                           min_probability=min_probability, min_log_bayes=min_log_bayes, max_effects=max_effects,
                           refine=refine_locations, fine_scan=frames, test=adequacy_test)
    if frames:    # ranked and searched in the reduced model: the named set's parameters from the full model
        found = refit_exact(model, found, nuisance(model), fm, weights, n_model)
    timing["ranking_s"] = time.perf_counter() - t1
    verdict, why = verdict_of(ranking, found, min_probability, min_log_bayes)
    if verdict == "explained":
        why = too_few_data(fm, found)
        if why:
            verdict = "ambiguous"
    t2 = time.perf_counter()           # the report: the named parameters' intervals, pairings, expansion
    none = next(r for r in ranking if r.name == "none")
    chosen = found.fit if verdict == "explained" and found.fit is not None else none.fit
    updated = chosen.model.exact     # a frame's full model, not its reduced one
    effects = _named_effects(model, found, fm, weights, n_model, errors.close) if verdict == "explained" else ()
    effect = effects[0] if effects else None
    before = _pair(model, fm, n_model, max_freq_error=1.0)
    after = _pair(updated, fm, n_model, max_freq_error=1.0)
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
    rejected = [x for ranking in found.rankings for r in ranking for x in r.rejected]
    if rejected:       # rejected trials: no evidence for those places, said so (the first reason as an example)
        name, loc, reason = rejected[0]
        at = "" if loc is None else f" at {short_place(loc)}"
        message += (f" {len(rejected)} trial model(s) could not be solved and count as no evidence for their "
                    f"place, e.g. {name}{at}: {reason}")
    return Explanation(
        verdict=verdict, effect=effect, message=message, ranking=ranking, before=g_b, after=g_a,
        updated_model=updated, nominal_model=model, measured=measured, fit_modes=fit_modes, unpaired_measured=unpaired,
        pairing_before=before, pairing_after=after, mac_before=before.mac_matrix, mac_after=after.mac_matrix,
        comac_before=comac_b, comac_after=comac_a, close_modes=close, residual_modes=tuple(int(i) for i in miss),
        residual_sensors=tuple(int(i) for i in np.flatnonzero(comac_a < 0.9)),
        node_xy_ft=joints, expanded_measured=expanded, expanded_model=model_nodes,
        timing_s=timing, node_labels=tuple(model.node_labels), effects=effects,
        rankings=found.rankings)
