"""Analyses: one identification (one SVD) per request with its stabilization diagram and era's choice of modes,
then modes of any order, reconstructions, and the mode-shape viewer."""

from __future__ import annotations

import numpy as np
from fastapi import APIRouter, Depends, HTTPException, Query, Request
from fastapi.responses import JSONResponse

import era

from .. import payloads, schemas, viewing
from ..cache import Analysis
from ..choosing import Diagram
from ..schemas import AnalysisRequest, ViewerRequest
from .deps import analysis, cache, find_dataset, jobs, progress_key

router = APIRouter(prefix="/api/analyses", tags=["analyses"])


@router.post("", summary="Identify: build H(0), H(1), take one SVD, and choose the modes from its diagram",
             response_model=schemas.Analysis)
async def create(request: Request, body: AnalysisRequest):
    """The answer's ``suggested_order`` and ``chosen_indices`` are era's choice (era.choose_modes) from the
    stabilization diagram, computed with the SVD (GET /stabilization then answers from memory)."""
    ds = await find_dataset(request, body.dataset_id)
    params = body.model_dump()

    def work():
        c = cache(request)
        a, ident = c.new_analysis(ds, params)
        return payloads.analysis_json(a.id, a.dataset_id, a.params, ident, c.diagram(a))  # nothing explained yet

    shape = f"{body.rows * ds.data.n_outputs} × {body.cols * ds.data.n_inputs}"
    return await jobs(request).heavy(work, progress=progress_key(request),
                                     message=f"Building H(0), H(1), taking the SVD of H(0) ({shape}) and choosing "
                                             "the modes from the stabilization diagram")


async def identified(request: Request, a: Analysis) -> era.Identification:
    """The identification of ``a``; after a restart or an eviction its SVD is recomputed on the heavy pool."""
    c = cache(request)
    if c.is_identified(a):
        return c.identification(a)
    return await jobs(request).heavy(c.identification, a, progress=progress_key(request),
                                     message="Recomputing the SVD of this analysis (first use since a restart)")


async def diagrammed(request: Request, a: Analysis) -> Diagram:
    """The diagram and the chosen modes of ``a``; after a restart or an eviction recomputed on the heavy pool."""
    c = cache(request)
    if c.is_diagrammed(a):
        return c.diagram(a)
    await identified(request, a)
    return await jobs(request).heavy(c.diagram, a, progress=progress_key(request),
                                     message="Realizing every order, tracking the stable poles and choosing the modes")


async def _model(request: Request, a: Analysis, order: int) -> era.ModalModel:
    await identified(request, a)
    return await jobs(request).quick(cache(request).model, a, order)


@router.get("/{analysis_id}", summary="An analysis: parameters, singular values and the chosen order and modes",
            response_model=schemas.Analysis)
async def read(request: Request, a: Analysis = Depends(analysis)):
    ident = await identified(request, a)
    answer = payloads.analysis_json(a.id, a.dataset_id, a.params, ident, await diagrammed(request, a))
    return dict(answer, has_explanation=cache(request).store.has_explanation(a.id))


@router.get("/{analysis_id}/modes", summary="Modes of one order: frequency, damping, γ, μ, contribution, shapes, fit",
            response_model=schemas.Modes)
async def modes(request: Request, a: Analysis = Depends(analysis), order: int = Query(ge=1, le=schemas.MAX_INT),
                fit: bool = Query(True, description="add the fit of all modes per channel (costs a reconstruction)"),
                scatter: bool = Query(False, description="add each shape's scatter from the data, expected 1 - MAC "
                                      "(n pole functionals per mode: 0.03 s at order 20, 1.7 s at 160 on the grid)")):
    model = await _model(request, a, order)
    if not scatter:
        return await jobs(request).quick(payloads.modes_json, model, a.data, fit)
    ident = await identified(request, a)
    return await jobs(request).quick(lambda: payloads.modes_json(model, a.data, fit, ident.shape_scatter(order)))


def parse_modes(modes: str) -> list[int]:
    """Mode indices from "0,2,5" (era.kept_modes checks that they exist). Raises era.EraError otherwise."""
    try:
        return [int(x) for x in modes.split(",") if x.strip()]
    except ValueError:
        raise era.EraError(f"`modes` must be comma-separated mode numbers like 0,2,5; got {modes!r}.") from None


def keep_rule(modes: str | None = Query(None, description="kept modes, e.g. 0,2,5 (wins over thresholds)"),
              min_emac: float | None = Query(None, description="keep modes with γ ≥ this, fraction"),
              min_mpc: float | None = Query(None, description="keep modes with μ ≥ this, fraction"),
              min_contribution: float | None = Query(None, description="fraction of the largest contribution"),
              physical_only: bool = Query(False, description="keep decaying complex pairs only (0 < ζ < 1)")):
    """Which modes a reconstruction keeps: ``modes`` if given, else those passing the thresholds (if any given),
    else all (None). Shared by /reconstruction and /step so the table and the curve follow one rule; the rule
    itself is era.kept_modes."""
    named = None if modes is None else parse_modes(modes)
    thresholds = dict(min_emac=min_emac, min_mpc=min_mpc, min_contribution=min_contribution,
                      physical_only=physical_only)

    def kept(model: era.ModalModel) -> np.ndarray | None:
        if named is not None:
            return era.kept_modes(model, named)
        if physical_only or (min_emac, min_mpc, min_contribution) != (None, None, None):
            return era.kept_modes(model, **thresholds)
        return None
    return kept


@router.get("/{analysis_id}/reconstruction", summary="Measured against reconstructed response for kept modes",
            response_model=schemas.Reconstruction)
async def reconstruction(request: Request, a: Analysis = Depends(analysis),
                         order: int = Query(ge=1, le=schemas.MAX_INT), kept=Depends(keep_rule),
                         output: int = Query(0, ge=0, le=schemas.MAX_INT),
                         input: int = Query(0, ge=0, le=schemas.MAX_INT)):
    """The answer names the kept modes in ``kept``, so the page can mark its table from the same rule."""
    model = await _model(request, a, order)
    points = cache(request).settings.max_plot_points
    return await jobs(request).quick(lambda: payloads.reconstruction_json(model, a.data, kept(model), output, input,
                                                                          points))


@router.get("/{analysis_id}/step", summary="One order-slider step: the modes of one order and the reconstruction",
            responses={200: {"model": schemas.Step}})
async def step(request: Request, a: Analysis = Depends(analysis), order: int = Query(ge=1, le=schemas.MAX_INT),
               kept=Depends(keep_rule), output: int = Query(0, ge=0, le=schemas.MAX_INT),
               input: int = Query(0, ge=0, le=schemas.MAX_INT)):
    """``{"modes": …, "reconstruction": …}``: what GET /modes?fit=false and GET /reconstruction answer for the
    same parameters, in one request and one realization. The page sends one per slider step: one round trip
    instead of two, and the answer goes out as JSON directly (its lists are JSON-safe already), not through
    FastAPI's response validation (tests/app/test_schemas.py checks it against schemas.Step)."""
    model = await _model(request, a, order)
    points = cache(request).settings.max_plot_points

    def work():
        return {"modes": payloads.modes_json(model, a.data, False),
                "reconstruction": payloads.reconstruction_json(model, a.data, kept(model), output, input, points)}

    return JSONResponse(await jobs(request).quick(work))


@router.get("/{analysis_id}/stabilization", summary="Poles of every order, their stability, the stable clusters "
            "with era's verdict on each (chosen, or why not), the chosen order and modes",
            response_model=schemas.Stabilization)
async def stabilization(request: Request, a: Analysis = Depends(analysis)):
    c = cache(request)

    def work():
        return payloads.stabilization_json(c.diagram(a), a.data, c.settings.max_plot_points)

    if c.is_diagrammed(a):  # computed with the identification (the page asks right after it): not queued behind SVDs
        return await jobs(request).quick(work)
    return await jobs(request).heavy(work, progress=progress_key(request),
                                     message="Realizing every order, tracking the stable poles and choosing the modes")


@router.post("/{analysis_id}/viewer", summary="Publish the modes of one order to the viser viewer",
             response_model=schemas.ViewerLink)
async def publish(request: Request, body: ViewerRequest, a: Analysis = Depends(analysis)):
    viewer = request.app.state.viewer
    if viewer is None:
        raise HTTPException(503, "The mode-shape viewer is not available on this server.")
    model = await _model(request, a, body.order)
    key = await jobs(request).quick(viewer.publish, *viewing.modes_scene(a, model))
    cache(request).store.add_viewer_key(key, a.id, {"kind": "modes", "order": body.order})
    return {"key": key, "url": viewer.iframe_url(key), "mode_url": f"/viser/{key}/mode", "n_modes": model.n_modes}
