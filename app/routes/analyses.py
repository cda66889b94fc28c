"""Analyses: one identification (one SVD) per request, then modes of any order, the stabilization diagram,
reconstructions, and the mode-shape viewer."""

from __future__ import annotations

import time

from fastapi import APIRouter, Depends, HTTPException, Query, Request
from fastapi.responses import JSONResponse
from pydantic import BaseModel, Field

from .. import engine as eng
from .deps import engine, jobs, progress_key

router = APIRouter(prefix="/api/analyses", tags=["analyses"])


class AnalysisRequest(BaseModel):
    dataset_id: str = Field(min_length=1, max_length=100)
    rows: int = Field(ge=1, description="r, block rows of H(0) (eq. 16)")
    cols: int = Field(ge=1, description="s, block columns of H(0)")
    row_shifts: list[int] | None = Field(None, description="j_1..j_{r-1}, increasing; default 1..r-1")
    col_shifts: list[int] | None = Field(None, description="t_1..t_{s-1}, increasing; default 1..s-1")
    max_order: int | None = Field(None, ge=1, description="largest order kept from the SVD")


class ViewerRequest(BaseModel):
    order: int = Field(ge=1)


@router.post("", summary="Identify: build H(0), H(1) and take one SVD")
async def create(request: Request, body: AnalysisRequest):
    e = engine(request)
    params = body.model_dump()

    def work():
        analysis_id, ident = e.new_analysis(body.dataset_id, params)
        return eng.analysis_json(analysis_id, body.dataset_id, params, ident)

    ds = e.summary(body.dataset_id)
    shape = f"{body.rows * ds['n_outputs']} × {body.cols * ds['n_inputs']}"
    return await jobs(request).heavy(work, progress=progress_key(request),
                                     message=f"Building H(0), H(1) and taking the SVD of H(0) ({shape})")


@router.get("/{analysis_id}", summary="An analysis: parameters and singular values")
async def read(request: Request, analysis_id: str):
    e = engine(request)
    dataset_id, params = e.analysis(analysis_id)
    if e.is_cached(analysis_id):
        ident = await jobs(request).quick(e.identification, analysis_id)
    else:
        ident = await jobs(request).heavy(e.identification, analysis_id, progress=progress_key(request),
                                          message="Recomputing the SVD of this analysis")
    return eng.analysis_json(analysis_id, dataset_id, params, ident)


async def _model(request: Request, analysis_id: str, order: int):
    e = engine(request)
    e.analysis(analysis_id)  # 404
    if not e.is_cached(analysis_id):  # after a restart: recompute the SVD on the heavy pool first
        await jobs(request).heavy(e.identification, analysis_id, progress=progress_key(request),
                                  message="Recomputing the SVD of this analysis (first use since a restart)")
    return await jobs(request).quick(e.model, analysis_id, order)


@router.get("/{analysis_id}/modes", summary="Modes of one order: frequency, damping, γ, μ, contribution, shapes, fit")
async def modes(request: Request, analysis_id: str, order: int = Query(ge=1),
                fit: bool = Query(True, description="add the fit of all modes per channel (costs a reconstruction)")):
    t0 = time.perf_counter()
    e = engine(request)
    model = await _model(request, analysis_id, order)
    data = e.dataset(e.analysis(analysis_id)[0])[0]
    out = await jobs(request).quick(eng.modes_json, model, data, fit)
    out["compute_ms"] = round((time.perf_counter() - t0) * 1e3, 2)
    return out


def keep_rule(modes: str | None = Query(None, description="kept modes, e.g. 0,2,5 (wins over thresholds)"),
              min_emac: float | None = Query(None, description="keep modes with γ ≥ this"),
              min_mpc: float | None = Query(None, description="keep modes with μ ≥ this"),
              min_contribution: float | None = Query(None, description="fraction of the largest"),
              physical_only: bool = Query(False, description="keep decaying complex pairs only (0 < ζ < 1)")):
    """Which modes a reconstruction keeps: ``modes`` if given, else those passing the thresholds (if any given),
    else all. Shared by /reconstruction and /step so the table and the curve follow one rule."""
    def kept(model):
        chosen = eng.parse_modes(modes, model.n_modes)
        if chosen is None and ((min_emac, min_mpc, min_contribution) != (None, None, None) or physical_only):
            chosen = eng.kept_by_thresholds(model, min_emac or 0.0, min_mpc or 0.0, min_contribution or 0.0,
                                            physical_only)
        return chosen
    return kept


@router.get("/{analysis_id}/reconstruction", summary="Measured against reconstructed response for kept modes")
async def reconstruction(request: Request, analysis_id: str, order: int = Query(ge=1), kept=Depends(keep_rule),
                         output: int = Query(0, ge=0), input: int = Query(0, ge=0)):
    """The answer names the kept modes in ``kept``, so the page can mark its table from the same rule."""
    e = engine(request)
    model = await _model(request, analysis_id, order)
    data = e.dataset(e.analysis(analysis_id)[0])[0]
    return await jobs(request).quick(eng.reconstruction_json, model, data, kept(model), output, input, e.settings)


@router.get("/{analysis_id}/step", summary="One order-slider step: the modes of one order and the reconstruction")
async def step(request: Request, analysis_id: str, order: int = Query(ge=1), kept=Depends(keep_rule),
               output: int = Query(0, ge=0), input: int = Query(0, ge=0)):
    """``{"modes": …, "reconstruction": …}``: what GET /modes?fit=false and GET /reconstruction answer for the
    same parameters, in one request and one realization. The page sends one per slider step: one round trip
    instead of two, and the answer goes out as JSON directly (its lists are JSON-safe already), not through
    FastAPI's generic encoder."""
    t0 = time.perf_counter()
    e = engine(request)
    model = await _model(request, analysis_id, order)
    data = e.dataset(e.analysis(analysis_id)[0])[0]
    chosen = kept(model)

    def work():
        return {"modes": eng.modes_json(model, data, False),
                "reconstruction": eng.reconstruction_json(model, data, chosen, output, input, e.settings)}

    out = await jobs(request).quick(work)
    out["modes"]["compute_ms"] = round((time.perf_counter() - t0) * 1e3, 2)
    return JSONResponse(out)


@router.get("/{analysis_id}/stabilization", summary="Poles of every order, their stability, suggested modes")
async def stabilization(request: Request, analysis_id: str):
    e = engine(request)
    e.analysis(analysis_id)

    def work():
        ident = e.identification(analysis_id)
        out = eng.stabilization_json(e.stabilization(analysis_id), ident)
        out["spectrum"] = eng.spectrum_json(ident.data, e.settings)
        return out

    return await jobs(request).heavy(work, progress=progress_key(request),
                                     message="Realizing every order and tracking the stable poles")


@router.post("/{analysis_id}/viewer", summary="Publish the modes of one order to the viser viewer")
async def publish(request: Request, analysis_id: str, body: ViewerRequest):
    e = engine(request)
    e.analysis(analysis_id)  # 404 first
    viewer = request.app.state.viewer
    if viewer is None:
        raise HTTPException(503, "The mode-shape viewer is not available on this server.")
    model = await _model(request, analysis_id, body.order)
    _, geometry, _ = e.dataset(e.analysis(analysis_id)[0])
    labels = [f"{f:.3f} Hz, ζ {100 * z:.2f} %" for f, z in zip(model.frequency_hz, model.damping_ratio)]
    key = await jobs(request).quick(viewer.publish, geometry, model.frequency_hz, model.shapes, labels)
    return {"key": key, "url": viewer.iframe_url(key), "mode_url": f"/viser/{key}/mode", "n_modes": model.n_modes}
