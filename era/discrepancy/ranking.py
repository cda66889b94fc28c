"""Ranking the candidate effects: fit each, marginalise located ones over their locations, posterior probabilities.

Located effects (a point mass, a loose joint) are screened first: one model solve per candidate joint at a trial
size gives the direction in which that effect moves the residuals; a linearised two-parameter least squares
(effect size ≥ 0 along that direction, plus the global stiffness factor) scores every joint, and only the best
few are fitted in full. Their evidence is averaged over all joints (uniform location prior), so an effect that
fits only at one joint pays ln(n_joints) for not knowing where; joints not refined count as zero in that average
(a lower bound, tight when the screening has found the joints that matter).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.special import logsumexp

from .effects import EffectSpec, Param, as_json_location, as_location
from .fitting import TRIAL_FAILURES, Fit, ModeWeights, effect_model, fit_effect, mode_residuals, trial_failure
from .measured import MeasuredModes
from .protocol import ExplainModel


@dataclass(frozen=True, eq=False)
class RankedEffect:
    """One candidate in the ranking.

    name; log_evidence (marginalised over locations for located effects, up to a common constant);
    probability (posterior, with the candidates' prior odds EffectSpec.prior_log_odds); log_bayes_factor
    (the data's alone) against "none" (the
    reference: the nominal, or the effects already named); parameters {name: value} and location of the best
    fit; chi2 (data misfit at the best fit); adequate (the χ² test of :func:`adequacy` passes);
    max_abs_freq_error_pct, min_mac at the best fit; fit (the Fit record); test (the Adequacy record);
    locations : for located effects, the fully fitted places as (location, log_evidence, probability of
        the location given the effect), best first; a location is (x_ft, y_ft) on the grid, a node id (str) or
        a member (node i, node j) on an era.Frame.
    screen : located effects screened at every place: (n_places, n_r) the change each place makes at the trial
        size (screen_locations), for a later step's pre-screening; else None.
    seconds : wall-clock time spent on this candidate (screening + fits); n_solves : model evaluations it took (a solve, or a
        Rayleigh-Ritz approximation in a solved model's modes).
    rejected : the trials that could not be solved (the change made the model a mechanism, singular or modeless),
        as (effect name, location or None, reason): no evidence for those places. A candidate rejected at every
        place, or a place-less one whose fit failed, is left out of the ranking and listed on the reference
        ("none").
    """

    name: str
    log_evidence: float
    probability: float
    log_bayes_factor: float
    parameters: dict
    location: tuple | None
    chi2: float
    adequate: bool
    max_abs_freq_error_pct: float
    min_mac: float
    fit: Fit
    locations: tuple = ()
    seconds: float = 0.0
    n_solves: int = 0
    test: Adequacy | None = None
    screen: np.ndarray | None = None
    rejected: tuple = ()

    def as_dict(self) -> dict:
        return {"name": self.name, "log_evidence": self.log_evidence, "probability": self.probability,
                "log_bayes_factor": self.log_bayes_factor, "parameters": dict(self.parameters),
                "location": self.location, "chi2": self.chi2, "adequate": self.adequate,
                "max_abs_freq_error_pct": self.max_abs_freq_error_pct, "min_mac": self.min_mac,
                "locations": [{"location": loc, "log_evidence": le, "probability": p} for loc, le, p in self.locations],
                "seconds": self.seconds, "n_solves": self.n_solves,
                "chi2_freq": None if self.test is None else self.test.chi2_freq,
                "chi2_shape": None if self.test is None else self.test.chi2_shape,
                "rejected": [{"effect": n, "location": as_json_location(loc), "reason": why} for n, loc, why in self.rejected]}


@dataclass(frozen=True)
class Adequacy:
    """Is a fitted model's misfit consistent with the measurement error? A χ² test on the normalised residuals.

    The frequency residuals r_f = (f_model − f_meas)/σ_f (k,) and the shape residuals (ψ̂ − φ̂)/σ_s of the unit
    shapes (k, p) — |ψ̂ − φ̂|² = 2(1 − √MAC), so these are the MAC residuals — use the error levels of
    ErrorLevels.weights: ERA's spread across orders plus the floors. Under the hypothesis that the model is right,
    Σ r_f² ~ χ²(k) and Σ r_s² ~ χ²(k (p − 1)); the largest |r_f| is the Bonferroni-corrected normal extreme.

    chi2_freq, chi2_shape : the two sums; p_freq, p_shape : their upper-tail probabilities; max_freq_sigma :
    max |r_f|; ok : all three within the levels of :func:`adequacy`; clean : also within a looser level
    (tail probabilities ≥ 0.05, max |r_f| ≤ 3): when a model passes ``ok`` but not ``clean``, something more may
    be there and the search for a further effect goes on (naming it still needs its evidence);
    off_modes : indices of the modes whose frequency residual or shape χ² alone fails its own test, worst first.
    """

    chi2_freq: float
    chi2_shape: float
    p_freq: float
    p_shape: float
    max_freq_sigma: float
    ok: bool
    off_modes: tuple
    clean: bool = True


def adequacy(fit: Fit, w: ModeWeights, alpha: float = 0.01, max_sigma: float = 4.0,
             shape_scale: float = 1.0) -> Adequacy:
    """The χ² adequacy test of a fit (see :class:`Adequacy`) at significance ``alpha`` (per test);
    ``max_sigma``: the largest |r_f| allowed (no lower than the Bonferroni extreme of k normal residuals);
    ``shape_scale``: the shape errors σ_s are trusted only to this factor (a model-form allowance: the truth's
    scattered bars bend the shapes by more than ERA's spread across orders shows).

    Calibration (tests/bench/bench_explain_matrix.py, seeds 0-5, 108 cases): every right single or paired fit
    had p_freq ≥ 0.25 and max |r_f| ≤ 2.6; the best sets for out-of-library truths (a ground spring, a damaged
    bar) had p_freq ≤ 0.023, most below 1e-7; in seeds 0-1 a distributed mass named while a loose joint hid
    beside it had p_freq = 1.0e-3. α = 0.01 rejects those and keeps every right one."""
    from scipy.stats import chi2, norm
    k = fit.freq_residual.size
    r_f = np.asarray(fit.freq_residual, float)
    r_s = fit.shape_residual.reshape(k, -1) / shape_scale
    c_f, c_s = float(r_f @ r_f), float(np.sum(r_s**2))
    n_s = r_s.size - k
    p_f, p_s = float(chi2.sf(c_f, k)), float(chi2.sf(c_s, max(n_s, 1)))
    limit = max(max_sigma, float(norm.isf(alpha / (2 * k))))
    per_mode_s = np.sum(r_s**2, axis=1)
    off_s = chi2.sf(per_mode_s, max(r_s.shape[1] - 1, 1)) < alpha / k
    off = np.flatnonzero((np.abs(r_f) > limit) | off_s)
    off = off[np.argsort(-(np.abs(r_f[off]) / limit + per_mode_s[off] / max(r_s.shape[1], 1)), kind="stable")]
    worst = float(np.max(np.abs(r_f)))
    ok = p_f >= alpha and p_s >= alpha and worst <= limit
    clean = ok and p_f >= 0.05 and p_s >= 0.05 and worst <= 3.0
    return Adequacy(c_f, c_s, p_f, p_s, worst, bool(ok), tuple(int(i) for i in off), bool(clean))


def screen_locations(nominal: ExplainModel, spec: EffectSpec, nuisance: Param, base: Fit, measured: MeasuredModes,
                     w: ModeWeights, n_model: int, locations, with_prior: bool = False,
                     ritz_modes: int = 0, prior: np.ndarray | None = None, keep: int = 12) -> tuple:
    """Linearised misfit χ² of the effect at every candidate location (n_loc,), from one solve per location,
    and the size a (n_loc,) of the effect, relative to its trial size, that the linearised fit wants.

    r(a, b) ≈ r₀ + a Δ_ℓ + b J_sf, with r₀ the residual of the fitted reference ``base`` (the nominal, or the
    effects already named), Δ_ℓ the change the effect makes at its trial size at location ℓ, J_sf the
    sensitivity to the stiffness factor; a ≥ 0 (the effect cannot act backwards), of either sign for a
    factor that may be off either way (EffectSpec.either_way). with_prior: the stiffness
    factor's prior enters as one more residual (frames: the group of every member is a pure scaling, which the
    bare linearisation would score as a perfect, free fit). ritz_modes > 0: on models with a ``ritz`` method,
    each place's modes come from the reference's lowest ``ritz_modes`` modes (Rayleigh-Ritz) instead of a solve.

    prior : (n_loc, n_r) the changes Δ_ℓ of an earlier screening of the same effect and places against another
        reference (the search's first step); they pre-screen every place against this reference, and only the
        best ``keep`` are screened again (a solve or Ritz each); the others score +inf (not fitted).
    Returns (χ² (n_loc,), a (n_loc,), Δ (n_loc, n_r): the changes, NaN rows where not screened here, and the
    places whose trial model could not be solved, ((location, reason), ...): they score +inf).
    """
    u_sf = base.u[0]
    trial_u = [p.u(spec.trial[p.name]) for p in spec.params[len(spec.start):]]

    def resid(model):
        return mode_residuals(model, measured, w, n_model)[0]

    r0 = resid(base.model)
    n_r = r0.size
    nudge = np.zeros(base.u.size)
    nudge[0] = 1e-3
    j_sf = (resid(effect_model(nominal, base.spec, base.params, base.u + nudge, base.location)) - r0) / 1e-3
    either_way = spec.either_way
    out = np.full(len(locations), np.inf)
    size = np.zeros(len(locations))
    changes = np.full((len(locations), n_r), np.nan)
    if with_prior:   # the stiffness factor's prior as one more residual: a pure scaling is not free
        r0 = np.r_[r0, (u_sf - nuisance.prior_mean) / nuisance.prior_std]
        j_sf = np.r_[j_sf, 1.0 / nuisance.prior_std]

    def score(d):
        if with_prior:
            d = np.r_[d, 0.0]
        A = np.column_stack([d, j_sf])
        coef, *_ = np.linalg.lstsq(A, -r0, rcond=None)
        if coef[0] < 0 and not either_way:  # only the stiffness factor then
            coef = np.array([0.0, -(j_sf @ r0) / max(j_sf @ j_sf, 1e-300)])
        return float(np.sum((r0 + A @ coef) ** 2)), coef[0]

    todo: range | np.ndarray = range(len(locations))
    if prior is not None and prior.shape == changes.shape and np.isfinite(prior).all() and len(locations) > keep:
        todo = np.argsort([score(d)[0] for d in prior], kind="stable")[:keep]
    # models that offer it (GridModel.ritz) screen in the span of the reference's modes: no solve per place
    ritz = bool(ritz_modes) and base.model.has_ritz
    rejected = []
    for i in todo:
        u = [*base.u, *trial_u]
        try:
            trial = effect_model(nominal, spec, (nuisance,) + tuple(spec.params), u, locations[i])
            approx = trial.screening_ritz(base.model, ritz_modes) if ritz else None
            change = resid(trial if approx is None else approx) - r0[:n_r]
            if not np.all(np.isfinite(change)):
                raise FloatingPointError("its modes are not finite")
        except TRIAL_FAILURES as exc:      # a mechanism, a singular or modeless model: no evidence here
            rejected.append((as_location(locations[i]), trial_failure(exc)))
            continue
        changes[i] = change
        out[i], size[i] = score(changes[i])
    return out, size, changes, tuple(rejected)


def _start(spec: EffectSpec, base: Fit, size: float) -> np.ndarray:
    """Start of a located fit from the screening: the reference's fitted values, then the new effect's trial size
    scaled by the linearised size a (within ±3σ); a factor off the other way (a < 0, EffectSpec.either_way) starts
    as far on the other side of its prior mean in ln θ as the linearised size says."""
    p = spec.params[-1]
    if size < 0 and spec.either_way:
        u = p.prior_mean + size * (p.u(spec.trial[p.name]) - p.prior_mean)
    else:
        u = p.u(spec.trial[p.name]) + (spec.trial_power * np.log(max(size, 1e-3)) if p.log else 0.0)
    return np.array([*base.u, np.clip(u, p.prior_mean - 3 * p.prior_std, p.prior_mean + 3 * p.prior_std)])


def place_posterior(spec: EffectSpec, fitted_at: list, places, chi2: np.ndarray) -> tuple:
    """The posterior over a located effect's places: ((location, log evidence, probability), ...), best first.

    fitted_at : [(Fit, index into places)] the places fitted in full, best first; chi2 : (n_places,) the
    screening's linearised misfit (inf where not screened). A fitted place's log evidence is its fit's; a place
    screened but not fitted gets the best fitted place's evidence less half its screened misfit above that
    place's (the data's say, linearised), so a place the data cannot tell from the best stays in contention
    though it was not fitted. Probabilities ∝ exp(log evidence / T) (T = spec.place_temperature), normalised over
    the places within e^{-12} of the best (the others hold less than a millionth each)."""
    best, i_best = fitted_at[0]
    rows = [(f.location, f.log_evidence) for f, _ in fitted_at]
    done = {i for _, i in fitted_at}
    if np.isfinite(chi2[i_best]):
        for i in np.flatnonzero(np.isfinite(chi2)):
            le = best.log_evidence - 0.5 * float(chi2[i] - chi2[i_best])
            if int(i) not in done and le > best.log_evidence - 12.0 * spec.place_temperature:
                rows.append((as_location(places[i]), min(le, best.log_evidence)))
    les = np.array([le for _, le in rows])
    q = np.exp(les / spec.place_temperature - logsumexp(les / spec.place_temperature))
    order = np.argsort(-les, kind="stable")
    return tuple((rows[k][0], float(les[k]), float(q[k])) for k in order)


def credible_places(locations: tuple, coverage: float = 0.9) -> tuple:
    """The smallest set of places, most probable first, whose probabilities add up to ``coverage``:
    ((location, probability), ...) from RankedEffect.locations ((location, log evidence, probability), ...)."""
    out, total = [], 0.0
    for loc, _, q in sorted(locations, key=lambda x: -x[2]):
        out.append((loc, float(q)))
        total += q
        if total >= coverage:
            break
    return tuple(out)


def _near_best(spec: EffectSpec, places, chi2: np.ndarray, n_best: int) -> tuple:
    """The places of spec.nearby around the ``n_best`` best screened ``places`` (those the full fits would
    consider: within the fits' misfit margin of the best), not among ``places``, each once, nearest the best
    first; () when the places are not thinned."""
    if not spec.nearby:
        return ()
    best = np.argsort(chi2, kind="stable")[:n_best]
    best = best[np.isfinite(chi2[best])]
    if not best.size:
        return ()
    best = best[chi2[best] - chi2[best[0]] <= max(25.0, 0.5 * chi2[best[0]])]
    seen = set(places)
    out = []
    for i in best:
        for p in spec.nearby.get(places[i], ()):
            if p not in seen:
                seen.add(p)
                out.append(p)
    return tuple(out)


def rank_effects(nominal: ExplainModel, specs: tuple, nuisance: Param, measured: MeasuredModes, w: ModeWeights,
                 n_model: int, locations: np.ndarray, refine: int = 4, test: dict | None = None,
                 fine_scan: bool = False, ritz_modes: int = 30, base: Fit | None = None,
                 screens: dict | None = None) -> tuple:
    """Fit every candidate, marginalise located ones, and return RankedEffects by decreasing probability.

    locations : candidate places of located effects whose spec gives none (the grid's joints, (n_loc, 2) x_ft,
        y_ft); a spec's own ``locations`` (node ids, members) take precedence.
    refine : how many of the best-screened locations get a full nonlinear fit.
    test : keyword arguments of :func:`adequacy` (its levels).
    ritz_modes : screen places in the span of this many of the reference's modes, on models that can
        (screen_locations); 0: a solve per place.
    base : the fit of specs[0] when the caller has it (the search's last step), else it is fitted here.
    screens : {effect name: (n_places, n_r) changes} of an earlier step's screening (RankedEffect.screen):
        they pre-screen the places, and only the best dozen are screened again against this step's reference.
    A located effect whose places were thinned (EffectSpec.nearby) is screened a second time at the places of
    the full set near its ``refine`` best screened ones; the full fits then go to the best of both passes, and
    its evidence is averaged over every place screened.
    fine_scan : (frames) start every fit from a finer scan of its parameter (located: about the screened size),
        and screen with the stiffness factor's prior as a residual; False keeps the grid's path as it was.
    The first spec must be "none", the reference (the nominal plus the nuisance, or the :func:`combined` effects
    already named): every Bayes factor is taken against it.
    """
    if not specs or specs[0].name != "none":
        raise ValueError("rank_effects: the first candidate must be 'none' (nominal + stiffness factor).")
    t0 = time.perf_counter()
    fit_ritz = 0 if fine_scan else ritz_modes      # frames keep their solved fits (fine_scan)
    base_evals = 0
    if base is None:
        base = fit_effect(nominal, specs[0], nuisance, measured, w, n_model, ritz_modes=fit_ritz)
        base_evals = base.n_evals
    rows: list[tuple] = []  # (spec, log_evidence, best fit, locations, seconds, solves, screen, rejected)
    dropped: list[tuple] = []  # (name, location, reason) of candidates rejected everywhere: listed on the reference's row

    def fitted(spec, **kw):
        try:
            return fit_effect(nominal, spec, nuisance, measured, w, n_model, scan=fine_scan, ritz_modes=fit_ritz,
                              **kw), None
        except TRIAL_FAILURES as exc:     # a mechanism, a singular or modeless model: a rejected trial
            return None, trial_failure(exc)

    for spec in specs:
        t = time.perf_counter()
        if spec.name == "none":
            rows.append((spec, base.log_evidence, base, (), t - t0, base_evals, None, ()))
        elif not spec.located:
            f, why = fitted(spec)
            if f is None:
                dropped.append((spec.name, None, why))
                continue
            rows.append((spec, f.log_evidence, f, (), time.perf_counter() - t, f.n_evals, None, ()))
        else:
            places = locations if spec.locations is None else spec.locations
            chi2, size, changes, bad = screen_locations(nominal, spec, nuisance, base, measured, w, n_model,
                                                        places, with_prior=fine_scan, ritz_modes=ritz_modes,
                                                        prior=(screens or {}).get(spec.name))
            rejected = [(spec.name, loc, why) for loc, why in bad]
            screened = int(np.isfinite(chi2).sum())
            screen = changes if screened == len(places) else None
            finer = _near_best(spec, places, chi2, refine)
            if finer:     # a thinned mesh: the places left out near the best screened ones, screened as well
                more = screen_locations(nominal, spec, nuisance, base, measured, w, n_model, finer,
                                        with_prior=fine_scan, ritz_modes=ritz_modes)
                places = tuple(places) + finer
                chi2, size = np.r_[chi2, more[0]], np.r_[size, more[1]]
                screened += int(np.isfinite(more[0]).sum())
                rejected += [(spec.name, loc, why) for loc, why in more[3]]
            top = np.argsort(chi2, kind="stable")[:refine]
            # places the linearised misfit puts far behind the best are not worth a full fit: their evidence
            # is below the best's by more than e^{-12}, well within the marginal's rounding
            top = top[np.isfinite(chi2[top])]
            top = top[chi2[top] - chi2[top[0]] <= max(25.0, 0.5 * chi2[top[0]])] if top.size else top
            fitted_at = []
            for i in top:
                f, why = fitted(spec, location=places[i], u0=_start(spec, base, size[i]))
                if f is not None and spec.either_way and not adequacy(f, w, **(test or {})).ok:
                    # a factor either way whose fit from the screening's start misses: the linearised size may
                    # have pointed to another valley (a part 44 % stiffer screened from a trial 30 % softer);
                    # fitted again from its prior, the better fit kept
                    g, _ = fitted(spec, location=places[i])
                    f = g if g is not None and g.log_evidence > f.log_evidence else f
                if f is None:
                    rejected.append((spec.name, as_location(places[i]), why))
                else:
                    fitted_at.append((f, int(i)))
            if not fitted_at:
                dropped += rejected or [(spec.name, None, "no place could be screened")]
                continue
            fitted_at.sort(key=lambda x: -x[0].log_evidence)
            fits = [f for f, _ in fitted_at]
            les = np.array([f.log_evidence for f in fits])
            log_ev = float(logsumexp(les) - np.log(len(places)))
            locs = place_posterior(spec, fitted_at, places, chi2)
            rows.append((spec, log_ev, fits[0], locs, time.perf_counter() - t,
                         screened + 2 + sum(f.n_evals for f in fits), screen, tuple(rejected)))
    rows[0] = rows[0][:7] + (tuple(dropped),)
    log_post = np.array([r[1] + r[0].prior_log_odds for r in rows])
    prob = np.exp(log_post - logsumexp(log_post))
    out = []
    for (spec, le, f, locs, sec, solves, screen, no_place), p in zip(rows, prob):
        test_f = adequacy(f, w, **(test or {}))
        out.append(RankedEffect(
            name=spec.name, log_evidence=float(le), probability=float(p),
            log_bayes_factor=float(le - rows[0][1]),
            parameters={k: v for k, v in f.parameters.items()}, location=f.location, chi2=f.chi2,
            adequate=test_f.ok, test=test_f,
            max_abs_freq_error_pct=float(np.max(np.abs(f.freq_error_pct))), min_mac=float(np.min(f.mac)),
            fit=f, locations=locs, seconds=float(sec), n_solves=int(solves), screen=screen, rejected=no_place))
    out.sort(key=lambda r: -r.probability)
    return tuple(out)
