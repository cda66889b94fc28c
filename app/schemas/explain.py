"""Simulation vs test (/api/analyses/{id}/explain): era.Explanation.as_dict() plus what app/explaining.py adds."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from .common import MAX_INT, Floats, Index, Matrix, Schema

class Explained(Schema):
    """Parts of the explanation: fields added by era/ or app/explaining.py later pass through as they are."""

    model_config = ConfigDict(extra="allow")


class Gap(Explained):
    max_abs_freq_error_pct: float | None = Field(description="largest |Δf| between paired modes, %")
    rms_freq_error_pct: float | None = Field(description="rms Δf, %")
    min_mac: float | None = Field(description="smallest MAC of a pair, fraction")
    mean_mac: float | None = Field(description="mean MAC, fraction")
    n_pairs: int = Field(description="paired modes")


#: a place: on the grid a joint (x_ft, y_ft) or a member ((x1, y1), (x2, y2)) ft; on a frame a node id or a
#: member [node i, node j] (["*"]: every member)
Place = list[float] | list[list[float]] | str | list[str]


class NamedEffect(Explained):
    name: str = Field(description="the effect the data support, e.g. point_mass")
    parameters: dict[str, float | None] = Field(description="fitted parameters {keyword: value} (incl. "
                                                            "stiffness_factor), in the keyword's unit")
    uncertainty: dict[str, float | None] = Field(description="1σ of each parameter, same units")
    location: Place | None = Field(description="(x_ft, y_ft) of a located effect on the grid, ((x1, y1), "
                                                "(x2, y2)) of a grid member, ft; on a frame a node id or a member "
                                                "[node i, node j] ([\"*\"]: every member); or null")
    location_probability: float | None = Field(description="posterior of that location, fraction")
    other_locations: list[tuple[Place, float | None]] = Field(description="[place, probability] of "
                                                                        "locations that tie")
    interval: dict[str, list[float | None]] = Field(description="{keyword: [low, high]} 95 % interval of the "
                                                                "effect's parameter; null on an unbounded side")
    probability: float | None = Field(description="posterior probability of the effect, fraction")
    description: str = Field(description="the verdict in one sentence")
    gap_after: Gap | None = Field(None, description="the gap with the effects named up to this one")
    places: list[tuple[Place, float | None]] = Field(default_factory=list, description="[place, probability] of "
                                                     "the places the data cannot tell apart under the model-form "
                                                     "allowance, most probable first (the smallest set holding 90 % "
                                                     "of the posterior over places; one when the place is clear)")
    size_parameter: str | None = Field(None, description="the keyword of the effect's size (its own parameter)")
    size_interval: list[float | None] | None = Field(None, description="[low, high] 95 % interval of the size; null "
                                                                       "on a side the data do not bound")
    cannot_tell: list[str] = Field(default_factory=list, description="what the data cannot distinguish, in words")


class LocatedEvidence(Explained):
    location: Place | None = Field(description="(x_ft, y_ft) or a member ((x1, y1), (x2, y2)), ft; a frame's "
                                                "node id or member")
    log_evidence: float | None
    probability: float | None = Field(description="posterior of this location, fraction")


class RejectedTrial(Explained):
    effect: str = Field(description="the candidate effect whose trial model could not be solved")
    location: Place | None = Field(description="its place (a frame's node id or member, a grid joint), or null")
    reason: str = Field(description="why, in words (a mechanism naming the free node and DOF, a singular model)")


class RankedEffect(Explained):
    name: str
    log_evidence: float | None = Field(description="ln of the Laplace-approximated evidence")
    probability: float | None = Field(description="posterior probability among the candidates, fraction")
    log_bayes_factor: float | None = Field(description="ln Bayes factor against the nominal model")
    parameters: dict[str, float | None] = Field(description="fitted parameters {keyword: value}")
    location: Place | None = Field(description="(x_ft, y_ft) or a member ((x1, y1), (x2, y2)) of the best "
                                               "location, ft (a frame's node id or member), or null")
    chi2: float | None = Field(description="χ² of the fit")
    adequate: bool = Field(description="the fit is consistent with the error levels")
    max_abs_freq_error_pct: float | None = Field(description="largest |Δf| after the fit, %")
    min_mac: float | None = Field(description="smallest MAC after the fit, fraction")
    locations: list[LocatedEvidence] = Field(description="evidence per location (located effects)")
    seconds: float | None = Field(description="time the candidate took, s")
    n_solves: int = Field(description="finite-element solutions it took")
    rejected: list[RejectedTrial] = Field(default_factory=list, description="its trials that could not be solved "
                                          "(no evidence there); on \"none\": candidates rejected everywhere")


class ExplainedMode(Explained):
    mode: int = Field(description="measured mode number, from 1")
    measured_hz: float | None = Field(description="measured frequency, Hz")
    damping_ratio: float | None = Field(description="measured ζ, fraction")
    nearly_repeated: bool
    nominal_hz: float | None = Field(description="the nominal model's partner, Hz (null: unpaired)")
    nominal_error_pct: float | None = Field(description="(nominal − measured)/measured, %")
    nominal_mac: float | None = Field(description="MAC with the nominal partner, fraction")
    updated_hz: float | None = Field(description="the updated model's partner, Hz")
    updated_error_pct: float | None = Field(description="(updated − measured)/measured, %")
    updated_mac: float | None = Field(description="MAC with the updated partner, fraction")


class Overlay(Explained):
    output_index: int
    input_index: int
    time_s: Floats = Field(description="(N',) s")
    measured: Floats = Field(description="(N',) measured response of this output to this input")
    nominal: Floats = Field(description="(N',) the nominal model's response")
    updated: Floats = Field(description="(N',) the updated model's response")


class ExplainBasis(Schema):
    """What an explanation was computed from: this analysis's identification and which of its modes."""

    hankel_rows: int = Field(description="r, block rows of the analysis's H(0)")
    hankel_cols: int = Field(description="s, block columns")
    hankel_shape: list[int] = Field(description="[r·p, s·m] of H(0)")
    orders: list[int] = Field(description="orders the modes were tracked over (their spread is the measurement error)")
    modes: Literal["stable", "kept"] = Field(description="stable: the modes era.choose_modes chose (the table's "
                                                         "default ticks); kept: the modes kept at one order")
    order: int | None = Field(description="the order the modes were read at (the choice's or the kept one)")
    kept: list[int] | None = Field(description="their indices at that order")
    text: str = Field(description="the same in one sentence, as the panel shows it")


class UsedModel(Schema):
    """The nominal model an explanation was made with, as it was then (an era.Frame or a matrix model)."""

    source: Literal["grid", "geometry", "file", "fe"] = Field(description="the NASA grid's built-in model, a model "
                                                                          "described in the panel, a model file, or "
                                                                          "an FE model (a deck or matrices)")
    name: str | None = Field(description="the model file's name, or null")
    saved: float | None = Field(description="when that model was saved, Unix s (null for the grid)")
    fingerprint: str | None = Field(description="the model's fingerprint (StructureModel.fingerprint); null for "
                                                "the grid")
    text: str = Field(description="the model in one line")


class Explanation(Explained):
    """The simulation-vs-test result stored with an analysis (POST/GET /api/analyses/{id}/explain)."""

    basis: ExplainBasis | None = Field(None, description="what was compared (null for results stored before it "
                                                         "was recorded)")
    verdict: str = Field(description="explained, no_significant_discrepancy, ambiguous or unexplained")
    message: str = Field(description="the verdict in words")
    effect: NamedEffect | None = Field(description="the named effect (the first when several), or null")
    effects: list[NamedEffect] = Field(default_factory=list, description="every named effect, most important "
                                                                         "first (empty unless explained)")
    ranking: list[RankedEffect] = Field(description="every candidate, most probable first")
    rejected_trials: list[RejectedTrial] = Field(default_factory=list, description="trial models that could not "
                                                 "be solved (a change made the model a mechanism, singular or "
                                                 "modeless): rejected, no evidence for those places")
    before: Gap = Field(description="test against the nominal model")
    after: Gap = Field(description="test against the updated model")
    updated_params: dict[str, Any] = Field(description="nasa_grid keywords of the updated model")
    modes: list[ExplainedMode] = Field(description="one row per fitted measured mode")
    unpaired_measured_hz: Floats = Field(description="measured modes with no model partner, Hz")
    mac_before: Matrix = Field(description="(measured, model) MAC against the nominal model")
    mac_after: Matrix = Field(description="(measured, model) MAC against the updated model")
    comac_before: Floats = Field(description="(sensors,) COMAC against the nominal model")
    comac_after: Floats = Field(description="(sensors,) COMAC against the updated model")
    residual_modes: list[int] = Field(description="modes the update leaves off")
    residual_sensors: list[int] = Field(description="sensors the update leaves off")
    node_xy_ft: Matrix = Field(description="(joints, 2) joint positions, ft")
    expanded_measured: Matrix = Field(description="(joints, modes) measured shapes expanded by SEREP")
    expanded_model: Matrix = Field(description="(joints, modes) the updated model's shapes")
    timing_s: dict[str, float | None] = Field(description="era_s, ranking_s, report_s, total_s, s")
    model_form: dict[str, float] | None = Field(None, description="the model-form allowance the evidence used: "
                                                                 "{frequency: relative 1σ, shape: 1σ per unit-shape "
                                                                 "component} (null for results stored before it)")
    nominal_params: dict[str, Any] = Field(description="nasa_grid keywords of the nominal model as asked")
    model_hz_before: Floats = Field(description="nominal model frequencies, Hz")
    model_hz_after: Floats = Field(description="updated model frequencies, Hz")
    measured_hz: Floats = Field(description="frequencies of the fitted measured modes, Hz")
    grid_shape: list[int] | None = Field(description="[joints along x, joints along y] (null on a frame)")
    sensors_ft: Matrix | None = Field(description="(p, 2) sensor positions, ft (null on a frame)")
    frame: dict[str, Any] | None = Field(None, description="on a frame: {nodes: {id: [x, y, z] m}, members: "
                                                           "[[i, j]], sensors: [[node, direction]], node_labels: "
                                                           "rows of the expanded shapes (\"7:x\", ...)}")
    model_text: str | None = Field(None, description="on a frame or an FE model: the model compared, in one line")
    fe_model: bool = Field(False, description="compared with the engineer's FE model (a Nastran deck or matrices)")
    mesh: dict[str, Any] | None = Field(None, description="on an FE model with node coordinates: {nodes: {id: [x, y, "
                                                          "z]} (the shapes' nodes, and element nodes held still), "
                                                          "members: [[i, j]] (bars and shell edges), faces: [[i, j, "
                                                          "k]] (the shells as triangles), node_labels: the expanded "
                                                          "shapes' rows} for the 3-D viewer")
    model_used: UsedModel | None = Field(None, description="the model this result was made with (null for results "
                                                           "stored before it was recorded)")
    stale: str | None = Field(None, description="why this result no longer matches the dataset's model (it changed "
                                                "since), in words; null while it does")
    outputs: list[str] = Field(description="(p,) output labels")
    inputs: list[str] = Field(description="(m,) input labels")
    overlay_fit_percent: dict[str, Matrix] = Field(description="{nominal, updated}: (p, m) fit of the simulated "
                                                               "responses to the measured ones, %")
    seconds: float = Field(description="time era.explain took, s")
    overlay: Overlay | None = Field(None, description="one output's responses (the API's answers)")
    overlays: list[Overlay] | None = Field(None, description="every output's responses (in a report)")


class ExplanationOverlay(Schema):
    """GET /explain?overlay_only=true: only the responses of one output and input."""

    model_config = ConfigDict(extra="forbid")
    overlay: Overlay


# ---- requests -----------------------------------------------------------------------------------------------
class ExplainRequest(BaseModel):
    nominal: dict = Field(default_factory=dict,
                          description="keywords of era.grid.nasa_grid for the nominal model, e.g. {\"gravity\": false}")
    modes: Literal["stable", "kept"] = Field("stable", description="stable: the modes era chose from the analysis's "
                                                                   "diagram (era.choose_modes, ticked by default) "
                                                                   "at its order; kept: exactly the modes `kept` at "
                                                                   "`order`")
    order: int | None = Field(None, ge=1, le=MAX_INT,
                              description="the order the modes were kept at (modes = kept)")
    kept: list[Index] | None = Field(None, description="indices of the kept modes at `order` (modes = kept)")
    orders: list[Index] | None = Field(None, min_length=1, max_length=200,
                                       description="orders the modes are tracked over (their spread is the "
                                                   "measurement error); default the analysis's diagram orders")
    output: int = Field(0, ge=0, le=MAX_INT, description="output of the response overlay")
    input: int = Field(0, ge=0, le=MAX_INT, description="input of the response overlay")


class ExplainViewerRequest(BaseModel):
    which: str = Field(pattern="^(measured|model)$",
                       description="measured: the test shapes expanded to all joints (SEREP); model: the updated model's")
