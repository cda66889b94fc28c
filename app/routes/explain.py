"""Simulation vs test (issues 5, 9): run era.explain on an analysis (its identification, and the modes era chose
from its diagram, or the modes kept when asked) against its dataset's structure model (app/routes/models.py) or,
without one, the NASA grid model, read the stored result back, and show the measured (SEREP-expanded) and model
shapes in the viewer."""

from __future__ import annotations

from fastapi import APIRouter, Depends, HTTPException, Query, Request

import era

from .. import compute, explaining, femodel, modeling, schemas, viewing
from ..cache import Analysis
from ..errors import NotFound
from ..schemas import ExplainRequest, ExplainViewerRequest
from .analyses import diagrammed, identified
from .deps import analysis, cache, jobs, progress_key, store

router = APIRouter(prefix="/api/analyses", tags=["simulation vs test"])


def _stored(request: Request, analysis_id: str) -> dict:
    summary = store(request).explanation(analysis_id)
    if summary is None:
        raise NotFound("Simulation vs test has not run on this analysis yet: press Run in its panel "
                       f"(POST /api/analyses/{analysis_id}/explain).")
    return summary


def _overlay(request: Request, analysis_id: str, output: int, input: int) -> dict:
    stored = store(request).explanation_responses(analysis_id)
    if stored is None:
        raise NotFound("The responses of this analysis's simulation vs test are missing: run it again.")
    return explaining.overlay_json(*stored, output, input)


@router.post("/{analysis_id}/explain",
             summary="Simulation vs test: name the effect the model is missing, update it, show the gap",
             response_model=schemas.Explanation)
async def run(request: Request, body: ExplainRequest, a: Analysis = Depends(analysis)):
    """Runs era.explain on this analysis (its Hankel size and SVD; the modes era chose from its diagram at the
    choice's order, the ones the page ticks by default, or the modes kept at ``order``; their spread over
    ``orders``, by default the diagram's) against the dataset's structure model, or, without one, the NASA grid
    (then the dataset must have the grid's nine sensors in order). Stores the result with the analysis; ``basis``
    in the answer says what was used."""
    stored = store(request).model(a.dataset_id)     # the dataset's own structure model, else the grid's
    described = None if stored is None else stored["model"]
    if stored is None:
        model = explaining.nominal_model(body.nominal)  # bad parameters: 422 now, not after the queue
    elif stored.get("source") == "fe":                  # an FE model: every output matched, else 422 now
        model = None
        femodel.sensors_of(stored["model"]["mapping"])
        fe = stored["model"]["fe"]
        described = dict(stored["model"], path=str(store(request).model_file(a.dataset_id, fe["sha256"],
                                                                             fe["suffix"])))
    else:
        model = None                                     # built from stored["model"] in the worker
        await jobs(request).quick(modeling.check_channels_of, stored["model"], a.data.outputs, a.geometry)
    kept = None
    if body.modes == "kept":
        if body.order is None or body.kept is None:
            raise era.EraError("modes = kept needs `order` and `kept` (the indices of the modes kept at that "
                               "order); or send modes = stable.")
        kept = (body.order, body.kept)
    c, files = cache(request), store(request)
    ident = await identified(request, a)
    diagram = await diagrammed(request, a)
    if kept is None:   # the modes era chose, at its order: what the page ticks by default
        kept = explaining.chosen_modes(diagram.choice)
    tracked = explaining.orders_for(ident, diagram.stabilization.orders, body.orders, kept[0])

    def work():
        compared = (kept[0], era.kept_modes(c.model(a, kept[0]), kept[1]).tolist())
        nominal = body.nominal if stored is None else {}
        summary, responses = compute.run(explaining.run_explain, ident, a.geometry, model, nominal, orders=tracked,
                                         kept=compared, chosen=body.modes == "stable", described=described,
                                         workers=c.settings.heavy_workers)
        summary["model_used"] = modeling.used(stored)      # so a later model change shows this result as stale
        files.add_explanation(a.id, summary, responses, a.data.dt)
        return summary, responses

    summary, responses = await jobs(request).heavy(
        work, progress=progress_key(request),
        message="Simulation vs test: the analysis's modes tracked over its diagram, then fitting and weighing "
                "every candidate effect")
    return dict(summary, stale=modeling.stale(summary, store(request).model(a.dataset_id)),
                overlay=explaining.overlay_json(responses, a.data.dt, body.output, body.input))


@router.get("/{analysis_id}/explain", summary="The stored simulation-vs-test result of an analysis",
            response_model=schemas.Explanation | schemas.ExplanationOverlay)
async def read(request: Request, a: Analysis = Depends(analysis),
               output: int = Query(0, ge=0, le=schemas.MAX_INT), input: int = Query(0, ge=0, le=schemas.MAX_INT),
               overlay_only: bool = Query(False, description="only the overlay of this output and input")):
    summary = None if overlay_only else _stored(request, a.id)
    overlay = await jobs(request).quick(_overlay, request, a.id, output, input)
    if overlay_only:
        return {"overlay": overlay}
    return dict(summary, stale=modeling.stale(summary, store(request).model(a.dataset_id)), overlay=overlay)


@router.post("/{analysis_id}/explain/viewer",
             summary="Publish the expanded measured shapes, or the updated model's, to the viser viewer",
             response_model=schemas.ViewerLink)
async def publish(request: Request, body: ExplainViewerRequest, a: Analysis = Depends(analysis)):
    summary = _stored(request, a.id)
    viewer = request.app.state.viewer
    if viewer is None:
        raise HTTPException(503, "The mode-shape viewer is not available on this server.")
    scene = viewing.explain_scene(summary, body.which)
    key = await jobs(request).quick(viewer.publish, *scene)
    store(request).add_viewer_key(key, a.id, {"kind": "explain", "which": body.which})
    return {"key": key, "url": viewer.iframe_url(key), "mode_url": f"/viser/{key}/mode", "n_modes": int(scene[1].size)}
