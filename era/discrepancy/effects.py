"""Candidate physical effects: what each one changes in the model, and its prior (the libraries of the two
model families sit beside this module: effects_grid.grid_effects for the NASA grid, effects_frame.frame_effects
for an era.Frame); where an effect sits and how it is said in words.

An effect is a set of model keywords (``model.with_params(**changes)``) driven by a few parameters. Parameters are
fitted in a transformed space u (log for positive quantities) where a Gaussian prior N(mean, std²) is sensible;
the prior width is what the Occam factor of the evidence weighs the fit against.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Param:
    """One fitted parameter.

    name : the model keyword it sets (``model.with_params(name=value)``).
    log : True when fitted as u = ln(value) (positive quantities), else u = value.
    prior_mean, prior_std : Gaussian prior of u.
    unit : for reports, e.g. "N·m/rad".
    model_form : relative 1σ error of the value that the candidate's idealisation itself carries (the data
        cannot shrink it), added in quadrature to the posterior σ when the uncertainty is reported.
    """

    name: str
    log: bool
    prior_mean: float
    prior_std: float
    unit: str = ""
    model_form: float = 0.0

    def value(self, u: float) -> float:
        return float(np.exp(u)) if self.log else float(u)

    def u(self, value: float) -> float:
        return float(np.log(value)) if self.log else float(value)


@dataclass(frozen=True)
class EffectSpec:
    """A candidate effect.

    name : identifier (e.g. "joint_flexibility"); "none" is the nominal model with the nuisance only.
    params : the effect's own parameters (the global ``stiffness_factor`` nuisance is added to every candidate).
    fixed : keywords always set with this effect (e.g. {"gravity": True}).
    location_keyword : keyword that takes the location, for located effects; None otherwise.
    locations : the candidate places of a located effect (node ids, (node i, node j) members, ...); None: the
        model's default places (the grid's joints, (x_ft, y_ft)).
    trial : effect parameter values (by name) used to screen locations (one model solve per location).
    trial_power : how the effect's size scales with its (single) parameter when screening: +1 when the
        residual change grows with the value (a mass), −1 when it grows with its inverse (a joint's compliance).
    summary : a phrase for descriptions, e.g. "the riveted joints are semi-rigid".
    caveat : a sentence appended to the description when the effect is named (what the data cannot tell).
    prior_log_odds : ln of the candidate's prior probability relative to the others' (0: equal odds); the
        posterior probabilities use it, the Bayes factors (the data's say) do not.
    start : transformed values u of the leading parameters to start every fit from (the fitted values of the
        effects already named, see :func:`combined`); the others start at their prior means.
    place_temperature : the places' probabilities given the effect are ∝ exp(log evidence / T): T > 1 when the
        candidate idealises the truth's form (a crack is not one member's E and G scaled together), whose
        misfit then shifts between neighbouring places by a few nats; T = 2 is the error variance doubled for
        comparing places. The effect's evidence (summed over places) is not tempered.
    nearby : for places thinned from a larger set (a big mesh's nodes), {place: (the places of the full set near
        it that ``locations`` leaves out)}: the ranking screens those near the best screened places too, so the
        place named is the set's own, not only the nearest thinned one. None: ``locations`` is every place.
    either_way : the effect's size is a factor on something modelled, as likely over as under (a part stiffer or
        softer, heavier or lighter, a property off either way): its change at the trial size points one way and
        the structure may differ the other way, so the screening lets the linearised size take either sign. An
        effect that is there or not (a mass, a spring) or a factor whose prior leans one way (a member less
        stiff than drawn) acts one way only (False).
    """

    name: str
    params: tuple = ()
    fixed: dict = field(default_factory=dict)
    location_keyword: str | None = None
    locations: tuple | None = None
    trial: dict = field(default_factory=dict)
    trial_power: float = 1.0
    summary: str = ""
    caveat: str = ""
    start: tuple = ()
    prior_log_odds: float = 0.0
    place_temperature: float = 1.0
    nearby: dict | None = None
    either_way: bool = False

    @property
    def located(self) -> bool:
        return self.location_keyword is not None


def combined(named: tuple, spec: EffectSpec) -> EffectSpec:
    """``spec`` on top of effects already named: their parameters fitted again with its own, their places kept.

    named : ((EffectSpec, location, u), ...) the named effects, their places (None when not located) and their
        fitted transformed parameters (the effect's own, without the stiffness factor), most important first.
    The result carries spec's name, place keyword and places; its parameters are the named effects' then spec's
    (so the evidence weighs every parameter against its own prior), and its fits start from the named values.
    """
    fixed, params, start = {}, [], []
    for s, loc, u in named:
        fixed.update(s.fixed)
        if s.location_keyword is not None:
            fixed[s.location_keyword] = as_location(loc)
        params += list(s.params)
        start += [float(x) for x in u]
    fixed.update(spec.fixed)
    return EffectSpec(spec.name, tuple(params) + tuple(spec.params), fixed, spec.location_keyword, spec.locations,
                      spec.trial, spec.trial_power, spec.summary, spec.caveat, tuple(start), spec.prior_log_odds,
                      spec.place_temperature, spec.nearby, spec.either_way)


def member_stiffness(locations, prior_factor: float, prior_std: float, summary: str,
                     prior_log_odds: float = 0.0) -> EffectSpec:
    """The member_stiffness candidate (docs/effects.md): one member's element stiffness (E and G together)
    scaled by a factor θ, fitted as ln θ with prior N(ln prior_factor, prior_std²), at any of ``locations``
    (model keywords member_at, member_factor; the grid and era.Frame models both take them). Its places are
    compared at T = 2 (EffectSpec.place_temperature): a blind crack (EI × 0.1-0.3, GJ × its root) in a grid
    member was fitted better one parallel member over, by 3.3 nats (tests/bench/bench_explain_matrix.py, member +
    torsion, seed 5), which untempered read as 96 % for the wrong member."""
    return EffectSpec("member_stiffness", (Param("member_factor", True, np.log(prior_factor), prior_std, ""),),
                      location_keyword="member_at", locations=tuple(locations),
                      trial={"member_factor": prior_factor}, trial_power=-1.0, summary=summary,
                      prior_log_odds=prior_log_odds, place_temperature=2.0)


def nuisance(model, prior_std: float = 0.015) -> Param:
    """The global stiffness factor every candidate may adjust: E of the aluminium known to ±1.5 % (1σ).

    A uniform added mass scales the elastic stiffness-to-mass ratio exactly as a lower E does (the geometric and
    cable stiffnesses grow with the weight, so ω² = [sf K_e / (1 + δ) + K_g + K_c] / M): from frequencies and
    shapes alone distributed mass is told from a softer material only through this prior. Modal constants from
    known impulse inputs (mass-normalised, see measured.modal_constants) add the absolute mass scale.
    """
    s0 = float(model.params.get("stiffness_factor", 1.0))
    return Param("stiffness_factor", True, np.log(s0), prior_std, "")


def as_location(loc):
    """A location as stored in results: a node id (str), a tuple of node ids (a member), a tuple of floats
    (the grid's joint (x_ft, y_ft)) or a pair of such tuples (the grid's member ((x1, y1), (x2, y2)))."""
    if loc is None or isinstance(loc, str):
        return loc
    loc = tuple(loc)
    if all(isinstance(v, str) for v in loc):
        return loc
    if all(np.ndim(v) == 1 for v in loc):
        return tuple(tuple(float(x) for x in v) for v in loc)
    return tuple(float(v) for v in loc)


def as_json_location(loc):
    """A location as JSON: a node id, or lists of node ids or of floats (None stays None)."""
    if loc is None or isinstance(loc, str):
        return loc
    return [as_json_location(x) for x in loc] if isinstance(loc, (tuple, list)) else float(loc)


#: The directions of a DOF place "node:direction" (a matrix model's spring to ground).
_DOF_DIRECTIONS = ("x", "y", "z", "rx", "ry", "rz")


def _text_place(loc: str, short: bool) -> str:
    """A matrix model's place in words: "part:deck" (a part), "7:x" (a DOF), "property:PSHELL 3 T" (a deck's
    property: "in T of PSHELL 3") or a node label."""
    if loc.startswith("part:"):
        return f"{'' if short else 'on '}part {loc[5:]}"
    if loc.startswith("property:") and len(loc[9:].split()) == 3:     # a deck's card: "PSHELL 3 T"
        card, pid, what = loc[9:].split()
        return f"{'' if short else 'in '}{what} of {card} {pid}"
    node, _, d = loc.rpartition(":")
    if node and d in _DOF_DIRECTIONS:
        return f"{'' if short else 'at '}node {node} in {d}"
    return f"{'' if short else 'at '}node {loc}"


def place(loc) -> str:
    """Where, in words: "at node 7", "on member 3-4", "at joint (x = 2 ft, y = 7 ft)",
    "on the member (4, 0)-(5, 0) ft", "at node 7 in x" (a DOF), "on part deck"."""
    loc = as_location(loc)
    if isinstance(loc, str):
        return _text_place(loc, short=False)
    if loc == ("*",):
        return "on every member"
    if all(isinstance(v, str) for v in loc):
        return f"on member {'-'.join(loc)}"
    if isinstance(loc[0], tuple):
        return f"on the member ({loc[0][0]:g}, {loc[0][1]:g})-({loc[1][0]:g}, {loc[1][1]:g}) ft"
    return f"at joint (x = {loc[0]:g} ft, y = {loc[1]:g} ft)"


def short_place(loc) -> str:
    """Where, briefly, for lists of alternatives: "(2, 7) ft", "(4, 0)-(5, 0) ft", "node 7", "member 3-4"."""
    loc = as_location(loc)
    if isinstance(loc, str):
        return _text_place(loc, short=True)
    if all(isinstance(v, str) for v in loc):
        return "every member" if loc == ("*",) else f"member {'-'.join(loc)}"
    if isinstance(loc[0], tuple):
        return f"({loc[0][0]:g}, {loc[0][1]:g})-({loc[1][0]:g}, {loc[1][1]:g}) ft"
    return f"({loc[0]:g}, {loc[1]:g}) ft"


def places_noun(spec: EffectSpec, loc) -> str:
    """What the places of a located effect are, in the plural: "members", "supports", "joints" or "nodes"."""
    key = spec.location_keyword or ""
    if key == "member_at":
        return "members"
    if key in ("part_at", "part_mass_at"):
        return "parts"
    if key == "property_at":
        return "properties"
    if key == "spring_at":
        return "DOFs"
    if key == "support_at":
        return "supports"
    if "joint" in key or not isinstance(as_location(loc), str):
        return "joints"
    return "nodes"


def one_of(spec: EffectSpec, places) -> str:
    """ "one of these members: member 3-4 55 %, member 4-5 30 %, member 2-3 15 %" from ((place, probability),
    ...) best first (the first eight, then how many more)."""
    shown = ", ".join(f"{short_place(loc)} {100 * q:.0f} %" for loc, q in places[:8])
    more = f" and {len(places) - 8} more" if len(places) > 8 else ""
    return f"one of these {places_noun(spec, places[0][0])}: {shown}{more}"


def describe(spec: EffectSpec, parameters: dict, location, probability: float, uncertainty=None,
             interval=None, lead: str = "The test data are best explained if", places=()) -> str:
    """A sentence an engineer understands: what is missing, how big (± 1σ and the 95 % interval), where, and how
    sure.

    interval : {name: (low, high)} 95 % posterior interval, None on a side the data do not bound; a one-sided
    interval is reported as a bound ("≤ high"), not as a value ± σ the data cannot support.
    places : ((place, probability), ...) the places the data cannot tell apart (the credible set); with two or
    more the sentence says "on one of these members: A 55 %, B 30 %" instead of one place.
    """
    shown = []
    for prm in spec.params:
        v = parameters.get(prm.name)
        if v is not None:
            sd = (uncertainty or {}).get(prm.name)
            pm = f" ± {sd:.2g}" if sd is not None and np.isfinite(sd) else ""
            label = prm.name.removesuffix("_kg").removesuffix("_m").replace("_", " ")
            unit = (' ' + prm.unit) if prm.unit else ''
            low, high = (interval or {}).get(prm.name, (0.0, 0.0))
            if low is None and high is not None:
                shown.append(f"{label} ≤ {high:.2g}{unit} (95 %; the data cannot tell lower values apart)")
            elif high is None and low is not None:
                shown.append(f"{label} ≥ {low:.2g}{unit} (95 %; the data cannot tell higher values apart)")
            elif low is not None and high is not None and (low, high) != (0.0, 0.0):
                shown.append(f"{label} = {v:.4g}{pm}{unit}, 95 % {low:.3g} to {high:.3g}")
            else:
                shown.append(f"{label} = {v:.4g}{pm}{unit}")
    sf = parameters.get("stiffness_factor")
    where = f" {place(location)}" if location is not None else ""
    if len(places) > 1:
        on = spec.location_keyword in ("member_at", "part_at", "part_mass_at")
        where = " " + ("on " if on else "at ") + one_of(spec, places)
    size = f" ({', '.join(shown)})" if shown else ""
    extra = f"; global stiffness factor {sf:.3f}" if sf is not None else ""
    return (f"{lead} {spec.summary}{where}{size}{extra}; "
            f"posterior probability {probability:.0%}." + (f" {spec.caveat}" if spec.caveat else ""))
