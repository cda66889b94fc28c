"""Fitting one candidate effect to measured modes, and its Bayesian evidence by the Laplace approximation.

Beck & Yuen (2004), "Model selection using response measurements: Bayesian probabilistic approach", J. Eng.
Mech. 130(2): for a model class M with parameters θ, prior p(θ|M) and Gaussian prediction errors,

    ln p(D|M) ≈ ln p(D|θ̂, M) + ln p(θ̂|M) + (k/2) ln 2π − ½ ln det H(θ̂),

θ̂ the most probable parameters and H the Hessian of −ln[p(D|θ) p(θ)] there (Gauss-Newton: JᵀJ of the
stacked data and prior residuals). With Gaussian priors of widths σ_θ this is, up to constants common to every
candidate (same data, same error levels),

    ln p(D|M) ≈ −½ χ²_data(θ̂) − ½ χ²_prior(θ̂) − ½ ln det(diag(σ_θ) H diag(σ_θ)),

the best fit plus the Occam factor (the last term: how much the data shrink the prior volume; every extra
parameter the data pin down costs about ln(σ_prior/σ_posterior)).

The data D are the paired frequencies and unit-norm shapes and, when the inputs were impulses of known size at
known points, each mode's modal-constant scale (measured.modal_constants): mass-normalised, so they see the
absolute mass that frequencies and shapes cannot (only E/ρ moves those).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares, linear_sum_assignment

from ..core.correlation import pairing_cost
from ..errors import EraError
from .correlated import CorrelatedErrors
from .effects import EffectSpec, Param, as_location
from .measured import MeasuredModes
from .protocol import ExplainModel, Modes


# What a trial model may fail with: a change that makes it a mechanism, singular or modeless (era.fem's DataError
# naming the free DOF, LinAlgError from a factorisation or an eigensolver, ValueError from least squares on a
# residual that is not finite). Such a trial is rejected, with its reason; it is never the end of an explanation.
TRIAL_FAILURES = (EraError, np.linalg.LinAlgError, ValueError, FloatingPointError)


def trial_failure(exc: BaseException) -> str:
    """One line saying why a trial model was rejected."""
    text = str(exc).strip() or type(exc).__name__
    return text if isinstance(exc, EraError) else f"the model could not be solved ({type(exc).__name__}: {text})"


@dataclass(frozen=True)
class ErrorLevels:
    """Prediction-error levels: measurement spread from ERA plus a floor for model-form error.

    freq_floor : relative frequency error floor (0.0015 = 0.15 %), added in quadrature to ERA's spread across orders.
    shape_floor : standard deviation of each component of a unit-norm shape (sensor gains, noise, mesh), added
        in quadrature to ERA's spread of the shape across orders.
    emac_freq, emac_shape : extra error per unit of (1 − EMAC) (the paper's modal amplitude coherence γ): a
        weakly excited mode whose history is not a clean decay (γ well below 1) can be biased beyond its spread
        across orders; relative frequency error emac_freq·(1 − γ), shape component error emac_shape·(1 − γ).
    scale_floor : relative error of each mode's modal-constant scale (noise, ERA's bias), added in quadrature to
        its spread across orders; emac_scale : extra relative scale error per unit of (1 − EMAC) (weakly coherent
        modes carry residues biased by several per cent).
    gain_std : relative calibration error of each sensor (1σ); it enters every mode's scale weighted by that
        sensor's share of the mode's modal constants, so it is correlated across modes, and its mean over the
        sensors is what limits the absolute mass scale.
    close : modes closer than this relative frequency to a neighbour (measured or model) form a nearly repeated
        pair whose individual shapes are not defined (any rotation within the pair is as good); their shapes get
        ``close_shape_sigma``, so only their frequencies count.
    member_scatter : relative 1σ to which each member's stiffness is known (a drawn model's members scatter by a
        few per cent); mode j's frequency then carries ½ · scatter · √(Σ_e w_ej²), w_ej member e's share of the
        mode's strain energy (model.member_energy_fractions). None: the model's own default (2 % for an
        era.Frame, whose few members do not average out; 0 for the grid, whose 157 bars do, in freq_floor).
    model_form, model_form_shape : the model-form allowance: the relative 1σ of each frequency, and the 1σ of each
        unit-shape component, by which a nominal FE model misses the real structure it describes (element
        formulation and mesh, joint details, sections and materials a few per cent off), added in quadrature to
        the levels above, so it enters every fit's evidence: effects and places the data cannot tell apart at
        this allowance stay apart, and a further effect is named only when it pays for itself under it. None:
        the model's own (ExplainModel.default_model_form; docs/explain-accuracy.md says how it was calibrated).
    thickness_scatter, support_scatter : relative 1σ of a deck's PSHELL thicknesses and of its springs to ground
        (None: part_scatter's THICKNESS_SCATTER 2 % and SUPPORT_SCATTER 10 %). On an FE model with parts (matrices
        or a deck) these and ``member_scatter`` (each part's stiffness) are correlated errors marginalised in every
        fit (part_scatter.with_part_scatter), not per-mode levels.
    """

    freq_floor: float = 0.0015
    shape_floor: float = 0.015
    emac_freq: float = 0.02
    emac_shape: float = 0.1
    scale_floor: float = 0.006
    emac_scale: float = 3.0
    gain_std: float = 0.02
    close: float = 0.03
    close_shape_sigma: float = 0.3
    member_scatter: float | None = None
    model_form: float | None = None
    model_form_shape: float | None = None
    thickness_scatter: float | None = None
    support_scatter: float | None = None

    def for_model(self, model: ExplainModel) -> "ErrorLevels":
        """These levels with the model's defaults put in for those left None (member scatter, model form)."""
        freq, shape = model.default_model_form
        return dataclasses.replace(
            self, member_scatter=model.default_member_scatter if self.member_scatter is None else self.member_scatter,
            model_form=freq if self.model_form is None else self.model_form,
            model_form_shape=shape if self.model_form_shape is None else self.model_form_shape)

    def weights(self, measured: MeasuredModes, close_mask=None, node_rows=None) -> "ModeWeights":
        """Per-mode error levels for ``measured``; close_mask (k,) marks nearly repeated modes.

        node_rows : (sensor rows (p,), input rows (m,)) of the model's node_modes, to compare the measured modal
        constants (when ``measured`` has them) with the model's mass-normalised shapes; None leaves them out.
        """
        weak = np.clip(1.0 - measured.emac, 0.0, 1.0)
        f = measured.frequency_hz
        form_f, form_s = self.model_form or 0.0, self.model_form_shape or 0.0
        sf = np.sqrt(measured.frequency_std_hz**2 + (self.freq_floor * f) ** 2 + (self.emac_freq * weak * f) ** 2
                     + (form_f * f) ** 2)
        ss = np.sqrt(measured.shape_std**2 + self.shape_floor**2 + (self.emac_shape * weak) ** 2 + form_s**2)
        if close_mask is not None:
            ss = np.where(close_mask, np.maximum(ss, self.close_shape_sigma), ss)
        whiten = None
        q_std = measured.modal_constant_std
        if node_rows is not None and measured.modal_constants is not None and q_std is not None:
            sc = np.sqrt(q_std**2 + self.scale_floor**2 + (self.emac_scale * weak) ** 2)
            if close_mask is not None:
                sc = np.where(close_mask, np.maximum(sc, self.close_shape_sigma), sc)
            # a sensor's gain error enters mode j's scale with that sensor's share of |Q_j|²: errors shared
            # between modes (all of them for the mean gain, which no amount of modes can average away)
            q2 = np.sum(measured.modal_constants**2, axis=1)
            share = q2 / np.maximum(q2.sum(axis=0, keepdims=True), 1e-300)          # (p, k)
            cov = np.diag(sc**2) + self.gain_std**2 * share.T @ share
            whiten = np.linalg.inv(np.linalg.cholesky(cov))
        return ModeWeights(sf, ss, whiten, None if whiten is None else tuple(np.asarray(r, int) for r in node_rows))


@dataclass(frozen=True, eq=False)
class ModeWeights:
    """Per-mode error levels: sigma_f (k,) Hz of each frequency, sigma_s (k,) of each unit-norm shape component;
    scale_whitener (k, k) L⁻¹ of the covariance of the log modal-constant scales (per-mode errors plus the
    common gain error), and node_rows (sensor rows, input rows) of the model's node_modes; None without them;
    correlated : errors shared across modes (the parts' stiffness scatter, part_scatter.with_part_scatter) that
    whiten the residuals normalised by the levels above, None without them."""

    sigma_f: np.ndarray
    sigma_s: np.ndarray
    scale_whitener: np.ndarray | None = None
    node_rows: tuple | None = None
    correlated: CorrelatedErrors | None = None


@dataclass(frozen=True, eq=False)
class Fit:
    """One candidate fitted to the measured modes.

    spec : the effect; location : (x_ft, y_ft) or None; params : (k,) the Param records fitted (nuisance first);
    u : (k,) the most probable transformed parameters; parameters : {name: physical value};
    uncertainty : {name: 1σ of the physical value} from the Laplace posterior covariance H⁻¹ (value × σ_u for
    log parameters) and the parameter's model-form error (Param.model_form), in quadrature;
    log_evidence : ln p(D|M) up to a constant common to all candidates (Laplace);
    chi2 : data misfit Σ r² at θ̂; chi2_prior; occam : −½ ln det(diag(σ_prior)² H) (≤ 0 when data inform);
    freq_residual : (n,) (f_model − f_measured)/σ_f at θ̂; shape_residual : (n·p,) (ψ̂ − φ̂)/σ_s, mode-major;
    freq_error_pct : (n,); mac : (n,);
    model_index : (n,) the model mode paired with each measured mode; model : the fitted model; n_evals : solves.
    """

    spec: EffectSpec
    location: tuple | None
    params: tuple
    u: np.ndarray
    parameters: dict
    uncertainty: dict
    log_evidence: float
    chi2: float
    chi2_prior: float
    occam: float
    freq_residual: np.ndarray
    shape_residual: np.ndarray
    freq_error_pct: np.ndarray
    mac: np.ndarray
    model_index: np.ndarray
    model: ExplainModel
    n_evals: int


def effect_model(nominal: ExplainModel, spec: EffectSpec, params: tuple, u, location=None) -> ExplainModel:
    """The nominal model with the effect switched on at parameters u (transformed, nuisance first)."""
    changes = dict(spec.fixed)
    changes.update({p.name: p.value(x) for p, x in zip(params, u)})
    if spec.location_keyword is not None:
        changes[spec.location_keyword] = as_location(location)
    return nominal.with_params(**changes)


def mode_residuals(model: Modes, measured: MeasuredModes, w: ModeWeights, n_model: int):
    """Normalised residuals of a model against the measured modes.

    Each measured mode is paired (frequency and MAC together, one assignment, no refusal) with a model mode.
    Returns r (n + n p [+ n],): frequency residuals (f_model − f_meas)/σ_f, shape residuals (ψ̂ − φ̂)/σ_s of
    unit-norm, sign-aligned shapes, and, when w has a scale_whitener, the whitened log scales ln s_j of the
    measured modal constants Q_j against the model's φ_j(sensors) φ_j(inputs)ᵀ = P_j, s_j = ‖Q_j‖/‖P_j‖
    (1 when the model's mass is right); and (f_model (n,), mac (n,), model_index (n,)). With w.correlated (an FE
    model's parts, thicknesses and supports scattered) r is whitened against those shared errors as well. The scale is the
    constants' size only: their pattern is the shape, which the shape residuals already compare (a projection
    ⟨Q_j, P_j⟩/⟨P_j, P_j⟩ counted a shape misfit twice, and collapsed for a partner whose shape is far off, such
    as a nominal's crossed modes, which made the linearised screening of places miss the right one).
    """
    whiten, at, Q = w.scale_whitener, w.node_rows, measured.modal_constants
    if whiten is None or at is None or Q is None:      # ErrorLevels.weights sets them together
        whiten = at = Q = None
        f, shapes = model.modes(n_model)
    else:
        f, nodes = model.node_modes(n_model)
        shapes = nodes[at[0]]
    f = np.clip(np.nan_to_num(np.asarray(f, dtype=float)), 0.0, None)
    cost, m = pairing_cost(measured.frequency_hz, measured.shapes, f, shapes)
    rows, cols = linear_sum_assignment(cost)
    idx = np.empty(measured.n_modes, dtype=int)
    idx[rows] = cols
    fa = f[idx]
    psi = np.asarray(shapes, dtype=float)[:, idx]
    psi = psi / np.maximum(np.linalg.norm(psi, axis=0, keepdims=True), 1e-300)
    psi = psi * np.where(np.sum(psi * measured.shapes, axis=0) < 0, -1.0, 1.0)[None, :]
    r_f = (fa - measured.frequency_hz) / w.sigma_f
    r_s = ((psi - measured.shapes) / w.sigma_s[None, :]).T.reshape(-1)
    parts = [r_f, r_s]
    if whiten is not None and at is not None and Q is not None:
        P = np.einsum("pk,mk->pmk", nodes[at[0]][:, idx], nodes[at[1]][:, idx])
        pp = np.maximum(np.einsum("pmk,pmk->k", P, P), 1e-300)
        s = np.maximum(np.sqrt(np.einsum("pmk,pmk->k", Q, Q) / pp), 1e-300)
        parts.append(whiten @ np.log(s))
    r = np.concatenate(parts)
    if w.correlated is not None:
        r = w.correlated.whiten(r)
    return r, (fa, m[np.arange(measured.n_modes), idx], idx)


def _prior_residuals(params, u):
    return np.array([(x - p.prior_mean) / p.prior_std for p, x in zip(params, u)])


def fit_effect(nominal: ExplainModel, spec: EffectSpec, nuisance: Param, measured: MeasuredModes, w: ModeWeights,
               n_model: int, location=None, u0=None, max_nfev: int = 60, scan: bool = False,
               ritz_modes: int = 0) -> Fit:
    """Most probable parameters of one candidate (least squares on data + prior residuals) and its evidence.

    The parameters are the nuisance stiffness factor followed by the effect's own (for a :func:`combined` spec,
    the named effects' then the new one's); the start is ``u0`` or the prior means (spec.start for the named
    effects' parameters), the new effect's one parameter taken from the best of a coarse scan over its prior
    (±2σ), so broad priors do not trap the fit in the wrong valley; ``scan`` makes that scan finer (steps of
    σ/2) and, with a ``u0``, centres it on u0 (frames, whose modes can cross as a parameter moves, making the
    misfit valley-rich).

    ritz_modes > 0, on models with a ``ritz`` method (GridModel.ritz): the trials (the scan, the least-squares
    steps and their finite-difference Jacobian) are Rayleigh-Ritz approximations in the lowest ``ritz_modes``
    modes of one solved model (plus its attachment modes where the change is local), re-solved at the point
    reached and the least squares repeated from there until a round moves the parameters by less than a
    tenth of their posterior σ (at most 3 rounds); the fit's misfit, evidence and model then come from a full
    solve at the final parameters, and only its Jacobian (the Occam factor, the σ) from the last round's
    approximations about a solved model at or next to them. About 3 solves a fit instead of 15-25.
    """
    params = (nuisance,) + tuple(spec.params)
    lo = np.array([p.prior_mean - 5 * p.prior_std for p in params])
    hi = np.array([p.prior_mean + 5 * p.prior_std for p in params])
    n_evals = 0
    ritz = ritz_modes > 0 and nominal.has_ritz
    ref = [None]          # the solved model the trials are approximated about (ritz), else None

    def solved(u):
        m = effect_model(nominal, spec, params, u, location)
        m.node_modes(max(ritz_modes, n_model))
        return m

    def total(u):
        nonlocal n_evals
        n_evals += 1
        m = effect_model(nominal, spec, params, u, location)
        approx = m.ritz(ref[0], ritz_modes) if ref[0] is not None else None
        r, _ = mode_residuals(m if approx is None else approx, measured, w, n_model)
        if approx is None and ref[0] is not None:   # too far for the approximation: solved, the next trials
            m.node_modes(ritz_modes)                # (a Jacobian's steps about it) approximate about it
            ref[0] = m
        return np.concatenate([r, _prior_residuals(params, u)])

    k = len(params) - 1                       # the scanned parameter: the last, when it is the only new one
    one_new = len(spec.params) - len(spec.start) == 1
    if u0 is None or (scan and one_new):
        start = u0
        if start is None:
            u0 = np.array([p.prior_mean for p in params])
            u0[1:1 + len(spec.start)] = spec.start
        else:
            u0 = np.asarray(start, dtype=float)
        if one_new:  # coarse scan of the new effect's parameter, the others fixed
            if ritz:
                ref[0] = solved(np.clip(u0, lo, hi))
            best = None if start is None else (float(np.sum(total(u0) ** 2)), u0)
            for step in (np.arange(-2.0, 2.01, 0.5) if scan else (-2.0, -1.0, 0.0, 1.0, 2.0)):
                trial = u0.copy()
                trial[k] = params[k].prior_mean + step * params[k].prior_std
                if start is not None:   # about the screened start, over the prior's width
                    trial[k] = np.clip(start[k] + step * params[k].prior_std, lo[k], hi[k])
                c = float(np.sum(total(trial) ** 2))
                if best is None or c < best[0]:
                    best = (c, trial)
            assert best is not None
            u0 = best[1]
    u0 = np.clip(np.asarray(u0, dtype=float), lo + 1e-9, hi - 1e-9)
    for _ in range(3 if ritz else 1):
        if ritz:
            ref[0] = solved(u0)
        sol = least_squares(total, u0, bounds=(lo, hi), diff_step=1e-3, x_scale=[p.prior_std for p in params],
                            max_nfev=max_nfev, ftol=1e-5, xtol=1e-5)
        if not ritz:
            break
        # the exact residual where the approximations led: one Gauss-Newton step from it (their Jacobian, the
        # bounds kept) shorter than 0.1 posterior σ means the approximate optimum is the solved one
        r = np.concatenate([mode_residuals(solved(sol.x), measured, w, n_model)[0],
                            _prior_residuals(params, sol.x)])
        H = sol.jac.T @ sol.jac
        step = np.clip(sol.x - np.linalg.lstsq(sol.jac, r, rcond=None)[0], lo, hi) - sol.x
        u0 = sol.x
        if float(step @ H @ step) <= 0.01:
            break
        u0 = np.clip(sol.x + step, lo + 1e-9, hi - 1e-9)
    u = sol.x
    J = sol.jac
    H = J.T @ J
    prior_sd = np.array([p.prior_std for p in params])
    sign, logdet = np.linalg.slogdet(H * np.outer(prior_sd, prior_sd))
    occam = -0.5 * logdet if sign > 0 else 0.0
    sd_u = np.sqrt(np.clip(np.diag(np.linalg.pinv(H)), 0.0, None))
    sd_u = np.hypot(sd_u, [p.model_form * (1.0 if p.log else abs(p.value(x))) for p, x in zip(params, u)])
    unc = {p.name: (p.value(x) * s if p.log else s) for p, x, s in zip(params, u, sd_u)}
    model = effect_model(nominal, spec, params, u, location)
    r, (fa, mac_pair, idx) = mode_residuals(model, measured, w, n_model)
    chi2 = float(np.sum(r**2))
    chi2_prior = float(np.sum(_prior_residuals(params, u) ** 2))
    loc = as_location(location)
    return Fit(spec=spec, location=loc, params=params, u=u,
               parameters={p.name: p.value(x) for p, x in zip(params, u)}, uncertainty=unc,
               log_evidence=float(-0.5 * chi2 - 0.5 * chi2_prior + occam), chi2=chi2, chi2_prior=chi2_prior,
               occam=float(occam), freq_residual=r[: measured.n_modes],
               shape_residual=r[measured.n_modes: measured.n_modes * (1 + measured.shapes.shape[0])],
               freq_error_pct=100 * (fa / measured.frequency_hz - 1),
               mac=mac_pair, model_index=idx, model=model, n_evals=n_evals + 1)


def profile_interval(nominal: ExplainModel, fit: Fit, measured: MeasuredModes, w: ModeWeights, n_model: int,
                     n_points: int = 15, span: float = 3.0, index: int | None = None,
                     ritz_modes: int = 0) -> tuple | None:
    """The 95 % posterior interval (low, high) of one effect parameter: fit.params[index] (default: the only
    effect parameter; None when the fit has several and no index is given, or none).

    low or high is None on a side the data do not bound: the data misfit stays within 4 (e^{-2} in likelihood)
    of its best out to the edge of the profile, so only the prior limits the value there and the report gives a
    one-sided bound (a loose joint's stiffness: "≤ 60 N·m/rad", a hinge fits as well).

    The parameter is stepped over its prior mean ± ``span`` prior σ (transformed space u); at each step the
    other parameters (the stiffness factor, the other named effects') are re-optimised by one Gauss-Newton step
    from their fitted values (their sensitivities from one extra solve each), so this is the profile posterior,
    exp(−½ χ²_data − ½ χ²_prior), normalised on the grid (the fitted value added to it). The Laplace σ of the
    Fit assumes a parabola; a parameter whose effect saturates (a joint looser than the bars can feel) has a
    posterior that is flat on one side, which this shows. About ``n_points`` + 12 + (number of other
    parameters) model solves. The interval is the data's (with the priors); the model-form error of
    Param.model_form is not in it. ritz_modes > 0 (models with ``ritz``): each step's modes are Rayleigh-Ritz
    approximations in the fitted model's lowest ``ritz_modes`` modes and attachment modes (exact at the fit,
    upper bounds away from it) instead of solves.
    """
    if index is None:
        if len(fit.params) != 2:
            return None
        index = 1
    params = fit.params
    prm = params[index]
    others = [i for i in range(len(params)) if i != index]
    spec, loc = fit.spec, fit.location

    ritz = ritz_modes > 0 and fit.model.has_ritz

    def resid(u):
        m = effect_model(nominal, spec, params, u, loc)
        approx = m.ritz(fit.model, ritz_modes) if ritz else None
        r, _ = mode_residuals(m if approx is None else approx, measured, w, n_model)
        return r

    d = 1e-3
    r0 = resid(fit.u)
    J = np.column_stack([(resid(fit.u + d * np.eye(len(params))[i]) - r0) / d for i in others])
    sd_o = np.array([params[i].prior_std for i in others])
    mu_o = np.array([params[i].prior_mean for i in others])
    lo, hi = prm.prior_mean - span * prm.prior_std, prm.prior_mean + span * prm.prior_std
    sd = fit.uncertainty[prm.name] / (fit.parameters[prm.name] if prm.log else 1.0)
    # a coarse grid over the prior, and a fine one over ±4 Laplace σ where a well-pinned posterior lives
    grid_u = np.union1d(np.linspace(lo, hi, n_points), np.clip(fit.u[index] + sd * np.linspace(-4, 4, 11), lo, hi))
    chi_list, post_list = [], []
    for x in grid_u:
        u = fit.u.copy()
        u[index] = x
        r = resid(u)
        # one Gauss-Newton step on the other parameters, their priors included
        uo = fit.u[others]
        g = J.T @ r + (uo - mu_o) / sd_o**2
        h = J.T @ J + np.diag(1.0 / sd_o**2)
        step = -np.linalg.solve(h, g)
        r = r + J @ step
        c = float(r @ r)
        chi_list.append(c)
        post_list.append(-0.5 * c - 0.5 * float(np.sum(((uo + step - mu_o) / sd_o) ** 2))
                        - 0.5 * ((x - prm.prior_mean) / prm.prior_std) ** 2)
    chi_data, log_post = np.array(chi_list), np.array(post_list)
    p = np.exp(log_post - log_post.max())
    # cumulative posterior by the trapezoid rule in u, the quantiles by linear interpolation
    cdf = np.concatenate([[0.0], np.cumsum(0.5 * (p[1:] + p[:-1]) * np.diff(grid_u))])
    cdf /= cdf[-1]
    q_lo, q_hi = np.interp([0.025, 0.975], cdf, grid_u)
    open_lo = chi_data[0] - chi_data.min() < 4.0
    open_hi = chi_data[-1] - chi_data.min() < 4.0
    return (None if open_lo else prm.value(q_lo), None if open_hi else prm.value(q_hi))
