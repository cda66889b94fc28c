"""The result of era.explain: the named effects (:class:`NamedEffect`) and the whole explanation
(:class:`Explanation`: the verdict, the ranking, the gap before and after, the pairings, the expanded shapes)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..core.correlation import Gap, ModePairing
from .effects import as_json_location
from .measured import MeasuredModes
from .protocol import ExplainModel
from .ranking import RankedEffect

#: The set of places a named effect reports holds this share of the posterior over its places (NamedEffect.places).
PLACE_COVERAGE = 0.9
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
    places : ((location, probability), ...) the places the data cannot tell apart under the model-form
        allowance: the smallest set, most probable first, holding PLACE_COVERAGE (90 %) of the place posterior
        (normalised over the places in contention); one entry when the place is clear, empty when not located;
    size_parameter : the keyword of the effect's size (its own parameter, e.g. "point_mass_kg"); size_interval :
        its 95 % interval (low, high), None on a side the data do not bound;
    cannot_tell : sentences saying what the data cannot distinguish (which of the places, a bound instead of a
        value, another candidate still probable).
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
    places: tuple = ()
    size_parameter: str | None = None
    size_interval: tuple | None = None
    cannot_tell: tuple = ()

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
                "log_bayes_factor": self.log_bayes_factor, "step": self.step,
                "places": [[js(loc), q] for loc, q in self.places], "size_parameter": self.size_parameter,
                "size_interval": None if self.size_interval is None else list(self.size_interval),
                "cannot_tell": list(self.cannot_tell)}


@dataclass(frozen=True, eq=False)
class Explanation:
    """Result of :func:`explain`.

    Attributes
    ----------
    verdict : str
        One of VERDICTS ("explained", "no_significant_discrepancy", "ambiguous", "unexplained").
    effect : NamedEffect or None
        The first of ``effects``, or None.
    message : str
        One paragraph for the report.
    ranking : tuple of RankedEffect
        One per candidate, most probable first (step 1: each alone against the nominal).
    before : Gap
        The gap of the nominal model over the paired modes.
    after : Gap
        The gap of the updated model over the paired modes.
    updated_model : model
        The best-supported model (the named effects fitted, else the nominal with the fitted global stiffness
        factor).
    nominal_model : model
        The model given.
    measured : MeasuredModes
        Every mode ERA found.
    fit_modes : int ndarray, shape (k,)
        Indices of the measured modes used (paired with some candidate).
    unpaired_measured : tuple of int
        Indices of measured modes no candidate could pair (set aside).
    pairing_before : ModePairing
        The fitted modes paired with the nominal model.
    pairing_after : ModePairing
        The fitted modes paired with the updated model.
    mac_before : ndarray, shape (k, n_model)
        MAC matrix of the fitted modes with the nominal model's.
    mac_after : ndarray, shape (k, n_model)
        MAC matrix with the updated model's.
    comac_before : ndarray, shape (p,)
        COMAC per sensor with the nominal model.
    comac_after : ndarray, shape (p,)
        COMAC per sensor with the updated model.
    close_modes : bool ndarray, shape (k,)
        Nearly repeated modes (their shapes are compared as a plane, not one by one).
    residual_modes : tuple of int
        Indices (into fit_modes) where the updated model still misses (|Δf| > 3σ or MAC < 0.9), worst first.
    residual_sensors : tuple of int
        Sensors with COMAC < 0.9 after the update.
    node_xy_ft : ndarray, shape (n_nodes, 2)
        The grid's joints in ft; (0, 2) on a frame or a matrix model.
    expanded_measured : ndarray, shape (n_rows, k)
        SEREP expansion of the measured shapes with the updated model's paired modes; rows: the grid's joints, or
        a model's node translations (``node_labels``).
    expanded_model : ndarray, shape (n_rows, k)
        Those model modes (NaN columns when unpaired).
    timing_s : dict
        Wall-clock seconds of each stage.
    node_labels : tuple of str
        The label of each row of the expansions ("7:x", ...).
    effects : tuple of NamedEffect
        The named effects, most important first (empty unless "explained").
    rankings : tuple
        The ranking of every step of the search for several effects (rankings[0] is ranking).
    model_form : (float, float)
        (relative frequency 1σ, shape-component 1σ) of the model-form allowance the evidence used
        (ErrorLevels.model_form, model_form_shape, or the model's default).

    Examples
    --------
    >>> from era.discrepancy import modes_from_arrays
    >>> k = 1e5 * (2 * np.eye(6) - np.eye(6, k=1) - np.eye(6, k=-1))  # six 1 kg masses on springs of 100 kN/m
    >>> k[-1, -1] = 1e5  # the top is free; below node 1 the chain is fixed to ground
    >>> dofs = [(str(i + 1), "z") for i in range(6)]
    >>> model = era.MatrixModel(k, np.eye(6), dofs, sensors=dofs)
    >>> heavier = np.eye(6)
    >>> heavier[3, 3] = 1.5  # the test article carries 0.5 kg at node 4, which the model does not know
    >>> frequency_hz, shapes = model.with_matrices(mass=heavier).modes(4)
    >>> measured = modes_from_arrays(frequency_hz, shapes, 0.002 * frequency_hz)
    >>> result = era.explain(measured, model, refine_locations=1)  # one place fitted in full: faster
    >>> [(entry.name, round(entry.probability, 2)) for entry in result.ranking[:2]]
    [('point_mass', 1.0), ('distributed_mass', 0.0)]
    >>> result.fit_modes.tolist(), result.unpaired_measured, result.as_dict()["verdict"]
    ([0, 1, 2, 3], (), 'explained')
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
    model_form: tuple = (0.0, 0.0)

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
        """The ranking entry of one candidate, by name.

        Parameters
        ----------
        name : str
            The candidate's name (EffectSpec.name), e.g. "point_mass".
        """
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
            "rejected_trials": [{"effect": n, "location": as_json_location(loc), "reason": why}
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
            "model_form": {"frequency": float(self.model_form[0]), "shape": float(self.model_form[1])},
        }
