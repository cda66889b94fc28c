"""The JSON contract of the API: one pydantic model per answer, declared on every route (see /docs).

NaN and ±inf are not JSON: every float the server cannot give is sent as null, so float lists are
``list[float | None]``. Shapes in the descriptions: p outputs, m inputs, k modes, N samples. Answers are built
as plain dicts in app/payloads.py; tests/app/test_schemas.py checks that they carry exactly these fields.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field

Floats = list[float | None]
Matrix = list[list[float | None]]
#: The largest integer a request may carry (2³¹ − 1, far above any sample, channel, shift or order count): larger
#: ones are refused (422) before numpy, which would overflow or wrap them, sees them.
MAX_INT = 2**31 - 1
#: An index, count or shift in a request: 0 ≤ n ≤ MAX_INT.
Index = Annotated[int, Field(ge=0, le=MAX_INT)]


class Schema(BaseModel):
    """Answers of this server: unknown fields are dropped (a stored report may hold more than it shows)."""

    model_config = ConfigDict(extra="ignore")


class Error(Schema):
    """Every refusal and failure (400, 401, 404, 413, 422, 429, 500, 503): no stack trace, a sentence to act on."""

    error: str = Field(description="what is wrong and what to do about it")
    option: str | None = Field(None, description="the option that fixes it (e.g. dt, orientation, forces), when one "
                                                 "does: a form shows the message next to that control")


# ---- datasets ---------------------------------------------------------------------------------------------
class GeometrySummary(Schema):
    n_nodes: int = Field(description="nodes of the test geometry")
    n_edges: int = Field(description="lines between nodes")
    units: str = Field(description="length unit of the coordinates, e.g. 'in', 'm'")


class HankelDefaults(Schema):
    rows: int = Field(description="r, block rows of H(0) suggested for this dataset")
    cols: int = Field(description="s, block columns of H(0) suggested for this dataset")
    max_order: int = Field(description="largest order suggested: min(r·p, s·m, era's 200, ERA_MAX_ORDER)")


class DatasetLimits(Schema):
    rows_plus_cols_max: int = Field(description="rows + cols ≤ N with consecutive shifts (N samples)")
    max_hankel_elements: int = Field(description="largest H(0) rows·p × cols·m, elements (ERA_MAX_HANKEL_ELEMENTS)")
    max_order: int = Field(description="largest order this server realizes (ERA_MAX_ORDER)")
    note: str = Field(description="the limits in words, for the page")


class DatasetSource(Schema):
    """How the records were read. Keys the loader or an example did not set are absent."""

    model_config = ConfigDict(extra="allow")
    file: str | list[str] | None = Field(None, description="uploaded file name")
    bytes: int | None = Field(None, description="size of the upload, bytes")
    format: str | None = Field(None, description="uff, csv, text, npz, lvm, npy, mat, hdf5, tdms or signalcalc")
    options: dict[str, Any] | None = Field(None, description="what the person said the files could not (dt, "
                                                             "orientation, variable, group, frf_sign, format)")
    kind: str | None = Field(None, description="what the records were read as: pulse, decay, frf, io, ambient")
    records: list[str] | None = Field(None, description="what was read, one line per record group")
    conversions: list[str] | None = Field(None, description="conversions applied (FRF → pulse response, …)")
    example: str | None = Field(None, description="name of the built-in example, for examples")


class Dataset(Schema):
    id: str = Field(description="dataset id (144-bit random)")
    sha256: str = Field(description="SHA-256 of the stored (normalised) dataset")
    name: str = Field(description="file name or example title")
    outputs: list[str] = Field(description="(p,) output (sensor) labels")
    inputs: list[str] = Field(description="(m,) input (excitation or initial condition) labels")
    output_units: list[str] | None = Field(description="(p,) output units, or null when the file gave none")
    input_units: list[str] | None = Field(description="(m,) input units, or null")
    dt: float = Field(description="Δτ, sampling interval, s")
    n_samples: int = Field(description="N, samples per record")
    n_outputs: int = Field(description="p")
    n_inputs: int = Field(description="m")
    duration_s: float = Field(description="N·Δτ, s")
    nyquist_hz: float = Field(description="1/(2Δτ), Hz")
    geometry: GeometrySummary | None = Field(description="the test geometry, or null")
    source: DatasetSource
    defaults: HankelDefaults
    limits: DatasetLimits
    band_hz: list[float] | None = Field(None, description="[low, high] Hz, the band FRF records hold (the choice of "
                                                          "modes looks only there); null: 0 to Nyquist")
    has_model: bool = Field(False, description="a structure model is stored (GET /api/datasets/{id}/model answers "
                                               "it; without one that request is a 404, so the page does not send it)")


class ImportOptions(Schema):
    """What the person says about uploaded files that they cannot say themselves (the import step). Channels are
    numbered as read (0-based), before any is dropped."""

    model_config = ConfigDict(extra="forbid")
    kind: Literal["auto", "pulse", "decay", "frf", "io", "ambient"] = Field(
        "auto", description="what the records are: auto (guessed), pulse, decay, frf, io (OKID) or ambient (NExT)")
    dt: float | None = Field(None, gt=0, description="sampling interval, s, when the files carry none")
    format: str | None = Field(None, description="the format when sniffing should not decide, e.g. text")
    orientation: Literal["rows", "columns"] | None = Field(None, description="channels of a headerless table")
    variable: str | None = Field(None, description="the array to read in a MAT or HDF5 file")
    group: str | None = Field(None, description="the TDMS group to read")
    resample: bool | None = Field(None, description="true: put CSV/text records whose time stamps scatter about a "
                                                    "steady rate (no sample missing) onto an even grid at the mean "
                                                    "rate; what was done is written into the dataset's source")
    frf_sign: Literal["auto", "+", "-"] | None = Field(None, description="the FRFs' sign convention")
    start_sample: int | None = Field(None, ge=0, le=MAX_INT, description="samples skipped at the start of every record "
                                                            "(pre-trigger)")
    drop: list[Index] | None = Field(None, description="channels left out")
    forces: list[Index] | None = Field(None, description="channels that measure the excitation (input-output records); "
                                                       "null: as the files' units and names say")
    references: list[Index] | None = Field(None, description="reference channels of ambient records (NExT); null: all")
    band_hz: list[float] | None = Field(None, min_length=2, max_length=2,
                                        description="[low, high] Hz, the band FRFs are valid in (e.g. the analyser's "
                                                    "fMin, fMax): lines outside it are cut and no mode is chosen "
                                                    "there; null: all lines")


class ImportChannel(Schema):
    index: int = Field(description="position in the files, 0-based (what drop/forces/references take)")
    name: str
    unit: str = Field(description="unit as the file gives it ('' when none)")
    node: int | None = Field(description="test-geometry node of the sensor, when the file says")
    direction: str | None = Field(description="+X, -Z, ... (global), when the file says")
    force: bool = Field(description="measures the excitation")
    dropped: bool = Field(description="left out by the person's choice")


class ImportPreview(Schema):
    """What was read, before anything is identified (POST /api/imports)."""

    files: list[str]
    format: str
    domain: str = Field(description="time, pulse (impulse responses) or frequency (FRFs)")
    dt: float | None = Field(description="Δt, s (or Δf, Hz, for FRFs); null when the files carry none")
    sample_rate_hz: float | None = Field(description="1/Δt for time data, Hz")
    start: float = Field(description="abscissa of the first kept sample, s or Hz")
    channels: list[ImportChannel]
    references: list[str] = Field(description="the references (inputs) of FRFs or impulse responses")
    n_records: int = Field(description="records (files, runs or initial conditions)")
    n_samples: list[int] = Field(description="samples of each record after start_sample")
    kind: str = Field(description="what kind=auto would read the records as")
    described: list[str] = Field(description="what was read and done")
    x: Floats = Field(description="abscissa of the plotted points: s, Hz, or sample numbers when dt is null")
    x_label: str
    traces: Matrix = Field(description="(channels, points) first record of every channel, thinned "
                                       "(|FRF| of the first reference)")
    geometry_nodes: int = Field(description="nodes of the test geometry in the files")
    proposed_band_hz: list[float] | None = Field(None, description="[low, high] Hz, the band the test's setup "
                                                 "proposes (a SignalCalc setup.csv's fMin, fMax), or null")


class Import(Schema):
    """An upload waiting for the import step: its files, what was read, and what still stops it."""

    id: str = Field(description="upload id (kept a day unless it becomes a dataset)")
    files: list[str]
    bytes: int
    options: dict[str, Any] = Field(description="the options this preview used")
    preview: ImportPreview | None = Field(description="what was read, or null when nothing could be")
    error: str | None = Field(description="what still stops the import, and what to do")
    option: str | None = Field(description="the option that fixes the error (dt, orientation, variable, group, "
                                           "kind, forces, start_sample, drop, format)")


class Records(Schema):
    time_s: Floats = Field(description="(N',) time of each plotted sample, s (decimated to ≤ 4000 points)")
    input: str = Field(description="label of the input these records respond to")
    outputs: list[str] = Field(description="(p,) output labels, one per series")
    series: Matrix = Field(description="(p, N') response of each output to this input, in the output's unit")


class Spectrum(Schema):
    frequency_hz: Floats = Field(description="(F,) frequency from 0 to Nyquist, Hz")
    values: Matrix = Field(description="(min(p, m), F) CMIF: singular values of the FFT of the records × Δτ, "
                                       "descending at each frequency")


class Example(Schema):
    name: str = Field(description="what to POST to /api/examples/{name}")
    title: str
    description: str
    rows: int | None = Field(description="Hankel rows the example's source uses, or null for the default")
    cols: int | None = Field(description="Hankel columns the example's source uses, or null")


# ---- analyses ---------------------------------------------------------------------------------------------
class Analysis(Schema):
    id: str = Field(description="analysis id (144-bit random)")
    dataset_id: str
    rows: int = Field(description="r, block rows of H(0) (eq. 16)")
    cols: int = Field(description="s, block columns of H(0)")
    row_shifts: list[int] = Field(description="(r-1,) j_1..j_{r-1}, samples")
    col_shifts: list[int] = Field(description="(s-1,) t_1..t_{s-1}, samples")
    max_order: int = Field(description="largest order that can be realized from this SVD")
    requested_max_order: int | None = Field(description="max_order as asked for, or null for the default")
    hankel_shape: list[int] = Field(description="[r·p, s·m], the size of H(0)")
    svd_method: str = Field(description="'dense' or 'randomized'")
    singular_values: Floats = Field(description="d_1 ≥ d_2 ≥ … of H(0) (eqs. 38-39), the leading ones")
    suggested_order: int = Field(description="the order era's choice of modes is read at (era.choose_modes): one of "
                                             "the stabilization diagram's orders, where every chosen mode has a "
                                             "pole; when era chose none, the diagram order nearest noise_floor_order")
    chosen_indices: list[int] | None = Field(None, description="the chosen modes' indices among the modes of "
                                                               "suggested_order (GET /modes), by frequency: what the "
                                                               "table keeps by default (empty when era chose none; "
                                                               "null in reports frozen before the choice existed)")
    noise_floor_order: int | None = Field(None, description="singular values clearly above the noise floor, even "
                                                            "(eqs. 38-39); null in reports frozen before it existed, "
                                                            "whose suggested_order is this")
    has_explanation: bool = Field(False, description="era.explain has run on it and its result is stored (GET "
                                                     "/api/analyses/{id}/explain answers it; otherwise a 404)")


class Modes(Schema):
    order: int = Field(description="n, the model order (state dimension)")
    n_modes: int = Field(description="k: complex pairs count once, real poles once")
    outputs: list[str] = Field(description="(p,) output labels: the rows of each shape")
    inputs: list[str] = Field(description="(m,) input labels")
    frequency_hz: Floats = Field(description="(k,) damped frequency Im(s)/2π, Hz (eq. 41)")
    natural_frequency_hz: Floats = Field(description="(k,) |s|/2π, Hz")
    eigenvalue_re: Floats = Field(description="(k,) Re s, 1/s")
    eigenvalue_im: Floats = Field(description="(k,) Im s, rad/s")
    damping_ratio: Floats = Field(description="(k,) ζ = -Re(s)/|s|, fraction (negative: growing)")
    emac: Floats = Field(description="(k,) γ, modal amplitude coherence (eqs. 42-45), fraction")
    mpc: Floats = Field(description="(k,) μ, modal phase collinearity (eqs. 46-54), fraction")
    frequency_std_hz: Floats | None = Field(None, description="(k,) standard deviation of frequency_hz that the "
                                            "data determine (era.uncertainty), Hz; 95 % interval ± 1.96 σ")
    damping_std: Floats | None = Field(None, description="(k,) standard deviation of ζ from the data, fraction")
    uncertainty_source: str | None = Field(None, description="which scatter the standard deviations come from: "
                                           "\"σ from N records\" (repeated records) or \"σ from one record's "
                                           "residuals\"")
    shape_scatter: Floats | None = Field(None, description="(k,) expected 1 - MAC of each shape against the true "
                                         "one from the data's scatter (era Identification.shape_scatter), fraction; "
                                         "null unless asked for (GET /modes?scatter=true, reports)")
    emac_mpc: Floats = Field(description="(k,) γ·μ, fraction")
    contribution: Floats = Field(description="(k,) Frobenius norm of the mode in H(0), units of the singular values")
    contribution_relative: Floats = Field(description="(k,) contribution / the largest, fraction")
    is_pair: list[bool] = Field(description="(k,) complex-conjugate pair (true) or real pole (false)")
    shapes_re: Matrix = Field(description="(k, p) real part of each shape, largest component 1")
    shapes_im: Matrix = Field(description="(k, p) imaginary part of each shape")
    points: list[str] = Field(default_factory=list, description="(q,) a label per measured or struck point, each "
                              "once (era ModalModel.points): the outputs, and where the inputs' points are known "
                              "(a roving hammer) the struck points too; \"4X\" is node 4 along X")
    point_shapes_re: Matrix = Field(default_factory=list, description="(k, q) real part of each mode's shape at "
                                    "the points (era ModalModel.point_shapes, by reciprocity at struck points), "
                                    "largest component 1")
    point_shapes_im: Matrix = Field(default_factory=list, description="(k, q) imaginary part of the point shapes")
    fit_percent: Matrix | None = Field(description="(p, m) fit 100·(1 - e) of all modes per channel, %; "
                                                   "null when fit=false")


class Reconstruction(Schema):
    output: str = Field(description="label of the output drawn")
    input: str = Field(description="label of the input drawn")
    kept: list[int] = Field(description="indices of the kept modes at this order, ascending")
    time_s: Floats = Field(description="(N',) s, decimated to ≤ 4000 points")
    measured: Floats = Field(description="(N',) measured response of this channel")
    reconstructed: Floats = Field(description="(N',) response of the kept modes (eq. 35)")
    fit_percent: float | None = Field(description="100·(1 - e) over all N samples, % (negative for a bad model)")


class Step(Schema):
    modes: Modes = Field(description="what GET /modes?fit=false answers")
    reconstruction: Reconstruction = Field(description="what GET /reconstruction answers for the same parameters")


class StableMode(Schema):
    frequency_hz: float | None = Field(description="mean damped frequency over the orders it is stable in, Hz")
    frequency_std_hz: float | None = Field(description="its spread over those orders, Hz")
    damping_ratio: float | None = Field(description="mean ζ, fraction")
    damping_std: float | None = Field(description="spread of ζ, fraction")
    data_frequency_std_hz: float | None = Field(None, description="standard deviation of the frequency that the "
                                                "data determine at its highest order (era.uncertainty), Hz")
    data_damping_std: float | None = Field(None, description="the same for ζ, fraction")
    emac: float | None = Field(description="mean γ, fraction")
    mpc: float | None = Field(description="mean μ, fraction")
    orders: list[int] = Field(description="the orders it is stable in")
    pole_indices: list[int] | None = Field(None, description="its poles: indices into the pole arrays (order, "
                                                             "frequency_hz, …)")
    coherent: bool | None = Field(None, description="mean γ·μ ≥ coherent_min: a likely physical mode "
                                                    "(absent in reports frozen before it existed)")
    chosen: bool | None = Field(None, description="era.choose_modes chose it as one of the structure's modes "
                                                  "(null in reports frozen before the choice existed)")
    code: str | None = Field(None, description="'chosen', or why not (era.choice.REASONS): rigid, band, harmonic, "
                                               "damping, uncertain, twin, orders, noise, absent")
    reason: str | None = Field(None, description="why it was not chosen, in words ('' when chosen)")
    mode: int | None = Field(None, description="the chosen mode it is, or of which it is a split twin (index into "
                                               "chosen_indices), else null")


class ChoiceCandidate(Schema):
    """One candidate era.choose_modes judged: a cluster of the diagram (``cluster``: its index in ``modes``), or,
    for noise-free data of exact rank, a mode of the exact realization (``cluster`` null)."""

    frequency_hz: float | None = Field(description="mean damped frequency over its orders, Hz")
    damping_ratio: float | None = Field(description="mean ζ, fraction")
    emac: float | None = Field(description="mean γ, fraction")
    mpc: float | None = Field(description="mean μ, fraction")
    orders: list[int] = Field(description="the orders it is found at")
    pole_indices: list[int] = Field(description="its poles: indices into the pole arrays")
    cluster: int | None = Field(description="its index in modes, or null when it is no cluster of the diagram")
    chosen: bool = Field(description="chosen as one of the structure's modes")
    code: str | None = Field(description="'chosen', or why not (era.choice.REASONS)")
    reason: str | None = Field(description="why it was not chosen, in words ('' when chosen)")
    mode: int | None = Field(description="the chosen mode it is, or of which it is a split twin (index into "
                                         "chosen_indices), else null")
    evidence: dict[str, float | None] | None = Field(description="what the verdict weighed (era's names: orders, "
                                                                 "persistence, coverage, emac_mpc, strength, ...), "
                                                                 "or null when a physical reason decided")


class Stabilization(Schema):
    orders: list[int] = Field(description="the orders computed (2, 4, …)")
    order: list[int] = Field(description="(poles,) each pole's order")
    mode_index: list[int] = Field(description="(poles,) each pole's index among the modes of its order")
    frequency_hz: Floats = Field(description="(poles,) damped frequency, Hz")
    damping_ratio: Floats = Field(description="(poles,) ζ, fraction")
    emac: Floats = Field(description="(poles,) γ, fraction")
    mpc: Floats = Field(description="(poles,) μ, fraction")
    contribution: Floats = Field(description="(poles,) contribution in H(0)")
    frequency_std_hz: Floats | None = Field(None, description="(poles,) standard deviation of the frequency from "
                                            "the data, Hz (null where not computed)")
    damping_std: Floats | None = Field(None, description="(poles,) standard deviation of ζ from the data")
    uncertainty_source: str | None = Field(None, description="which scatter those standard deviations come "
                                           "from: σ from N records, or σ from one record's residuals")
    stable_frequency: list[bool] = Field(description="(poles,) frequency within 1 % of the previous order's pole")
    stable_damping: list[bool] = Field(description="(poles,) damping within 5 %")
    stable_shape: list[bool] = Field(description="(poles,) MAC ≥ 0.98 with it")
    stable: list[bool] = Field(description="(poles,) stable in frequency, damping and shape")
    modes: list[StableMode] = Field(description="suggested modes: poles stable over ≥ 3 orders, by frequency, each "
                                                "with era.choose_modes' verdict")
    coherent_min: float | None = Field(None, description="γ·μ a suggested mode needs to be coherent, fraction")
    candidates: list[ChoiceCandidate] | None = Field(None, description="everything era.choose_modes judged, by "
                                                                       "frequency, with its verdict; null in older "
                                                                       "reports")
    chosen_order: int | None = Field(None, description="the diagram order the chosen modes are read at (the "
                                                       "analysis's suggested_order, which see when none is chosen); "
                                                       "null in older reports")
    chosen_indices: list[int] | None = Field(None, description="the chosen modes' indices among the modes of "
                                                               "chosen_order, by frequency")
    band_hz: list[float] | None = Field(None, description="[low, high] Hz, the band the choice looked in")
    nyquist_hz: float = Field(description="1/(2Δτ), Hz: the frequency axis ends there")
    spectrum: Spectrum = Field(description="CMIF of the records, drawn under the poles")


class ViewerLink(Schema):
    key: str = Field(description="the published modes' key (128-bit random)")
    url: str = Field(description="viser page for an <iframe>")
    mode_url: str = Field(description="POST {index, amplitude?, speed?} here to choose the mode shown")
    n_modes: int = Field(description="modes published")


class StoreUsage(Schema):
    rows: dict[str, int] = Field(description="rows per table: datasets, analyses, reports, explanations")
    bytes: dict[str, int] = Field(description="bytes per folder of the data folder: datasets, reports, explanations")
    free_bytes: int = Field(description="free space on the data folder's disk, bytes")


class Health(Schema):
    status: str = Field(description="ok when the server answers")
    version: str = Field(description="era-modal version of this server (era.__version__)")
    store: str | None = Field(description="the index database: sqlite or postgresql (null: not signed in to a "
                                          "restricted server, as the next three)")
    schema_revision: str | None = Field(description="its migration revision (app/store/migrations)")
    usage: StoreUsage | None = Field(description="what the store holds")
    expire_days: float | None = Field(description="datasets and analyses in no report are deleted after this, days "
                                                  "(0: never)")
    access: str = Field(description="open, or restricted (a team token or a sign-in proxy)")


class Progress(Schema):
    state: str = Field(description="queued, running, done or failed")
    message: str = Field(description="what the job does")
    seconds: float = Field(description="queued or running (or ran) for this long, s")
    queued_ahead: int = Field(description="jobs queued before this one (0 unless queued)")
    running_total: int = Field(description="jobs running on the server now")


# ---- simulation vs test (era.Explanation.as_dict() plus what app/explaining.py adds) ------------------------
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
    """The nominal model an explanation was made with, as it was then (issue 9)."""

    source: Literal["grid", "geometry", "file"] = Field(description="the NASA grid's built-in model, a model described "
                                                                    "in the panel, or a model file")
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
    nominal_params: dict[str, Any] = Field(description="nasa_grid keywords of the nominal model as asked")
    model_hz_before: Floats = Field(description="nominal model frequencies, Hz")
    model_hz_after: Floats = Field(description="updated model frequencies, Hz")
    measured_hz: Floats = Field(description="frequencies of the fitted measured modes, Hz")
    grid_shape: list[int] | None = Field(description="[joints along x, joints along y] (null on a frame)")
    sensors_ft: Matrix | None = Field(description="(p, 2) sensor positions, ft (null on a frame)")
    frame: dict[str, Any] | None = Field(None, description="on a frame: {nodes: {id: [x, y, z] m}, members: "
                                                           "[[i, j]], sensors: [[node, direction]], node_labels: "
                                                           "rows of the expanded shapes (\"7:x\", ...)}")
    model_text: str | None = Field(None, description="on a frame: the model compared, in one line")
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


# ---- reports ----------------------------------------------------------------------------------------------
class ReportCreated(Schema):
    token: str = Field(description="the report's token (144-bit random)")
    url: str = Field(description="the read-only report page, /r/{token}")


class ReportPair(Schema):
    output: str
    input: str
    output_index: int
    input_index: int
    measured: Floats = Field(description="(N',) measured response")
    reconstructed: Floats = Field(description="(N',) response of the kept modes")


class ReportReconstruction(Schema):
    time_s: Floats = Field(description="(N',) s, decimated to ≤ 1500 points")
    pairs: list[ReportPair] = Field(description="channels (output, input), at most 36")


class ReportGeometry(Schema):
    node_ids: list[int]
    coordinates: Matrix = Field(description="(nodes, 3) in units")
    edges: list[list[int]] = Field(description="(lines, 2) node indices")
    channel_nodes: list[int] = Field(description="(p,) node index of each output, -1 if none")
    channel_directions: Matrix = Field(description="(p, 3) unit direction of each output")
    units: str


class FrozenModel(Schema):
    """A dataset's structure model as a report keeps it."""

    model: dict[str, Any] = Field(description="era.Frame's file format, SI units, as described")
    source: str = Field(description="geometry (described in the panel) or file")
    name: str | None = Field(description="the uploaded file's name, or null")
    saved: float | None = Field(description="when it was saved, Unix s")
    text: str = Field(description="the model in one line")


class ReportDocument(Schema):
    """The frozen report, as stored: everything its page draws."""

    created: str = Field(description="ISO 8601, UTC")
    software: dict[str, str] = Field(description="versions of era-modal, python, numpy, scipy")
    dataset: Dataset
    analysis: Analysis
    order: int
    kept: list[int] = Field(description="kept modes at this order, ascending")
    modes: Modes = Field(description="every mode of this order, with the fit of all of them")
    kept_fit_percent: Matrix = Field(description="(p, m) fit of the kept modes per channel, %")
    reconstruction: ReportReconstruction
    stabilization: Stabilization
    geometry: ReportGeometry | None
    explanation: Explanation | None = Field(description="simulation vs test, when its panel ran before the report")
    structure_model: FrozenModel | None = Field(None, description="the dataset's structure model when the report was "
                                                                  "made (issue 9), or null")
    recordings: dict[str, str] = Field(description="{mode index: file} of the mode-shape recordings (.viser)")


class Report(ReportDocument):
    token: str
    url: str = Field(description="/r/{token}")
    playback: dict[str, str] = Field(description="{mode index: viser player page for its recording}")


class OfflineReport(ReportDocument):
    """window.REPORT_DATA of the downloaded HTML (reporting.standalone_html): no server behind it."""

    token: str
    standalone: bool = Field(description="true: the page has no server (no links to downloads)")
    offline_recordings: dict[str, str] = Field(description="{mode index: .viser recording, base64}")
    viser_marker: str | None = Field(description="what the player page holds where a recording goes, or null")


# ---- campaigns (app/campaigns.py) -------------------------------------------------------------------------
class CampaignAnalysis(Schema):
    kind: str = Field(description="how each record became Markov parameters: auto, ambient (NExT), decay, ...")
    dt: float | None = Field(description="sampling interval given for files without a time column, s, or null")
    orders: list[int] = Field(description="model orders of each record's stabilization diagram")


class CampaignRecord(Schema):
    record: int = Field(description="position of the record among the campaign's files (0-based)")
    name: str = Field(description="its file name")
    time: str | float = Field(description="ISO 8601 date-time from the file name, or the record's position when "
                                          "not every file name holds one")


class CampaignMode(Schema):
    mode: int = Field(description="the tracked mode's number")
    reference_frequency_hz: float | None = Field(description="frequency where it was defined, Hz")
    reference_damping_ratio: float | None = Field(description="damping where it was defined, fraction")
    origin: str = Field(description="reference (a mode of the first record) or new (appeared later and persisted)")
    first_record: int = Field(description="the record that defined it (-1 for a given reference)")
    n_found: int = Field(description="records that show it")


class CampaignSeries(Schema):
    mode: int
    frequency_hz: Floats = Field(description="one per analysed record, in time order; null where it is missing")
    damping_ratio: Floats = Field(description="fraction, one per analysed record")
    mac_to_reference: Floats = Field(description="MAC of the record's mode with the reference shape")


class CampaignFailure(Schema):
    record: int
    name: str = Field(description="the file name")
    reason: str = Field(description="why the record could not be analysed, for a person")


class CampaignResult(Schema):
    """campaigns/{id}/campaign.json: everything the campaign page draws."""

    id: str
    name: str
    engine: str = Field(description="where the records ran: the Dask scheduler's address or local processes")
    analysis: CampaignAnalysis
    seconds: float = Field(description="wall time of the campaign, s")
    n_records: int = Field(description="records (files) in the campaign, analysed or failed")
    time_axis: Literal["date", "record"] = Field(description="what the records' time is")
    records: list[CampaignRecord] = Field(description="the analysed records, in time order")
    modes: list[CampaignMode]
    series: list[CampaignSeries] = Field(description="one per tracked mode")
    failed: list[CampaignFailure]


class Campaign(Schema):
    id: str = Field(description="the campaign's id (144-bit random): its link is the secret")
    name: str
    url: str = Field(description="the campaign's page and report link, /c/{id}")
    state: Literal["queued", "running", "done", "failed"]
    done: int = Field(description="records finished so far (analysed or failed)")
    total: int = Field(description="records in the campaign")
    message: str | None = Field(description="why the campaign failed as a whole, or a warning; null otherwise")
    engine: str = Field(description="where the records run")
    result: CampaignResult | None = Field(description="once done")


class CampaignFolder(Schema):
    name: str = Field(description="a folder under ERA_CAMPAIGN_ROOT ('.' is the root itself)")
    n_files: int


class CampaignFolders(Schema):
    enabled: bool = Field(description="whether this server runs campaigns on its own folders (ERA_CAMPAIGN_ROOT)")
    folders: list[CampaignFolder]
    engine: str = Field(description="where campaigns run on this server")
    max_records: int = Field(description="records in one campaign at most (ERA_MAX_CAMPAIGN_RECORDS)")


# ---- the structure model of a dataset (issue 9: simulation vs test on the engineer's own structure) ----------------
class ModelDraft(Schema):
    """GET /api/datasets/{id}/model/draft: what the model step starts from, read from the dataset's geometry."""

    nodes: dict[str, list[float]] = Field(description="{node id: [x, y, z]} in m (the geometry's labels)")
    members: list[list[str]] = Field(description="[node i, node j, group] per trace line segment; the group is "
                                                 "the trace line's name, or for an unnamed one its direction: "
                                                 "vertical, along x, along y, inclined")
    sensors: list[list[Any]] = Field(description="[node, direction] per output, in the outputs' order")
    outputs: list[str] = Field(description="(p,) output labels")
    units: str = Field(description="always m")
    groups: list[str] = Field(description="the groups the members fall into")
    materials: list[str] = Field(description="materials the section helpers know")
    shapes: list[str] = Field(description="section shapes: rectangle, tube, square_tube, circle")


class StructureModel(Schema):
    """A dataset's stored structure model (GET/PUT /api/datasets/{id}/model, POST .../model/file)."""

    model: dict[str, Any] = Field(description="the model in era.Frame's file format (SI units), as described")
    source: Literal["geometry", "file"] = Field(description="built from the geometry in the panel, or uploaded")
    name: str | None = Field(description="the uploaded file's name, or null")
    saved: float | None = Field(description="when it was saved, Unix s")
    fingerprint: str = Field(description="a hash of the model as described: an explanation made with another "
                                         "fingerprint is stale")
    n_nodes: int
    n_members: int
    n_sensors: int
    total_mass_kg: float = Field(description="members plus lumped masses, kg")
    frequency_hz: Floats = Field(description="the model's lowest frequencies, Hz")
    text: str = Field(description="the model in one line")


class ModelViewLink(Schema):
    """POST /api/datasets/{id}/model/viewer: the model being described, in the 3-D viewer, its nodes clickable."""

    key: str = Field(description="the view's key (random)")
    url: str = Field(description="the viewer page for an <iframe>")
    picks_url: str = Field(description="GET ?after=n: the nodes clicked there since pick n")
    look_url: str = Field(description="POST {node}: turn the view to a node")
    marks_url: str = Field(description="POST {marks: {node: fixed | pinned | springs | mass}}: the nodes' colours")


class BestPartner(Schema):
    model_mode: int = Field(description="index of the model mode with the largest MAC, from 0")
    mac: float | None = Field(description="that MAC, fraction")
    frequency_error_pct: float | None = Field(description="(model − test)/test, %")


class ModelComparison(Schema):
    """GET /api/analyses/{id}/model/mac: the dataset's model beside the test's modes, at the sensors."""

    test_hz: Floats = Field(description="(k,) the test modes compared, Hz")
    model_hz: Floats = Field(description="(n,) the model's lowest modes, Hz")
    mac: Matrix = Field(description="(k, n) MAC of each test mode with each model mode")
    best: list[BestPartner | None] = Field(description="(k,) each test mode's model partner (frequency and MAC "
                                                      "together, as explain pairs them), null when none fits")
