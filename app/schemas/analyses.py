"""Analyses (/api/analyses): the identification, modes of one order, reconstructions, the stabilization
diagram with era's choice of modes, and the viewer link."""

from __future__ import annotations

from pydantic import BaseModel, Field

from .common import MAX_INT, Floats, Index, Matrix, Schema
from .datasets import Spectrum

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
                                            "data determine (era.core.uncertainty), Hz; 95 % interval ± 1.96 σ")
    damping_std: Floats | None = Field(None, description="(k,) standard deviation of ζ from the data, fraction")
    uncertainty_source: str | None = Field(None, description="which scatter the standard deviations come from: "
                                           "\"σ from N records\" (repeated records) or \"σ from one record's "
                                           "residuals\"")
    std_group: list[list[int] | None] | None = Field(None, description="(k,) the modes (indices) sharing each mode's "
                                                     "± (a repeated cluster: poles closer than their scatter each "
                                                     "carry the cluster's largest σ; app.payloads.std_groups), or "
                                                     "null for a mode with its own")
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
                                                "data determine at its highest order (era.core.uncertainty), Hz")
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
    code: str | None = Field(None, description="'chosen', or why not (choose.REASONS): rigid, band, harmonic, "
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
    code: str | None = Field(description="'chosen', or why not (choose.REASONS)")
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
                                           "from: σ from N records, σ from N segments of the record (one "
                                           "ambient record), or σ from one record's residuals")
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


# ---- requests -----------------------------------------------------------------------------------------------
class AnalysisRequest(BaseModel):
    dataset_id: str = Field(min_length=1, max_length=100)
    rows: int = Field(ge=1, le=MAX_INT, description="r, block rows of H(0) (eq. 16)")
    cols: int = Field(ge=1, le=MAX_INT, description="s, block columns of H(0)")
    row_shifts: list[Index] | None = Field(None, description="j_1..j_{r-1}, increasing; default 1..r-1")
    col_shifts: list[Index] | None = Field(None, description="t_1..t_{s-1}, increasing; default 1..s-1")
    max_order: int | None = Field(None, ge=1, le=MAX_INT, description="largest order kept from the SVD")


class ViewerRequest(BaseModel):
    order: int = Field(ge=1, le=MAX_INT)
