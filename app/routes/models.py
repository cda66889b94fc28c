"""The structure model of a dataset (issue 9): the draft read from its geometry, the stored model (GET), a model
described in the browser (PUT), a model file uploaded (POST .../model/file), and the model's modes beside an
analysis's (MAC). Saving checks the model against the dataset's channels and solves it once; a refused model
leaves the stored one as it was."""

from __future__ import annotations

import time

import numpy as np
from fastapi import APIRouter, Depends, File, HTTPException, Query, Request, UploadFile

import era

from .. import modeling, schemas
from ..cache import Analysis, CachedDataset
from ..errors import NotFound
from ..schemas import ModelRequest, ModelView
from .deps import analysis, cache, dataset, jobs, progress_key, store

router = APIRouter(tags=["structure model"])


async def _save(request: Request, ds: CachedDataset, stored: dict) -> dict:
    files = store(request)

    def work():
        fr, f_hz = modeling.checked(stored["model"], ds.data.outputs, ds.geometry)
        kept = dict(stored, frequency_hz=[float(f) for f in f_hz])
        files.set_model(ds.id, kept)           # only a model that solved is kept, with its frequencies
        return modeling.summary(kept, fr, f_hz)

    return await jobs(request).heavy(work, progress=progress_key(request),
                                     message="Checking the model and computing its lowest modes")


@router.get("/api/datasets/{dataset_id}/model/draft", summary="What the model step starts from: the geometry's "
            "nodes, trace lines as members (grouped by direction) and the channels as sensors",
            response_model=schemas.ModelDraft)
async def draft(ds: CachedDataset = Depends(dataset)):
    return modeling.draft(ds.geometry, ds.data.outputs)


@router.get("/api/datasets/{dataset_id}/model", summary="The dataset's stored structure model",
            response_model=schemas.StructureModel)
async def read(request: Request, ds: CachedDataset = Depends(dataset)):
    stored = store(request).model(ds.id)
    if stored is None:
        raise NotFound("This dataset has no structure model yet: describe it in the Model panel or upload a model "
                       f"file (PUT /api/datasets/{ds.id}/model).")

    def work():
        fr = modeling.frame(stored["model"])
        f_hz = stored.get("frequency_hz") or (     # kept when saved: no solve here; elastic modes, as Save's
            fr.modes(modeling.N_MODES + fr.n_rigid_modes)[0][fr.n_rigid_modes:])
        return modeling.summary(stored, fr, f_hz)

    return await jobs(request).quick(work)


@router.put("/api/datasets/{dataset_id}/model",
            summary="Save the dataset's structure model (era.Frame file format)", response_model=schemas.StructureModel)
async def save(request: Request, body: ModelRequest, ds: CachedDataset = Depends(dataset)):
    """Refused with a sentence (422) when a member goes to a missing node, a section has no material, the model
    is a mechanism, or its sensors are not the dataset's outputs; the stored model is then unchanged."""
    return await _save(request, ds, {"model": body.model, "source": body.source, "name": body.name,
                                     "saved": time.time()})


@router.post("/api/datasets/{dataset_id}/model/file",
             summary="Upload a model file (era.Frame JSON, or TOML named .toml)", response_model=schemas.StructureModel)
async def upload(request: Request, file: UploadFile = File(description="the model file"),
                 ds: CachedDataset = Depends(dataset)):
    name = (file.filename or "model.json").rsplit("/", 1)[-1].rsplit("\\", 1)[-1][:200]
    blob = await file.read(modeling.MAX_MODEL_BYTES + 1)
    model = modeling.read_file(name, blob)
    return await _save(request, ds, {"model": model, "source": "file", "name": name, "saved": time.time()})


@router.post("/api/datasets/{dataset_id}/model/viewer", summary="Show the model being described in the 3-D viewer, "
             "where clicking a node picks it (GET /viser/{key}/picks)", response_model=schemas.ModelViewLink)
async def view(request: Request, body: ModelView, ds: CachedDataset = Depends(dataset)):
    viewer = request.app.state.viewer
    if viewer is None:
        raise HTTPException(503, "The 3-D viewer is not available on this server: pick nodes in the drawing.")
    key = await jobs(request).quick(viewer.publish_model, body.nodes, body.members, body.marks)
    return {"key": key, "url": viewer.iframe_url(key), "picks_url": f"/viser/{key}/picks",
            "look_url": f"/viser/{key}/look", "marks_url": f"/viser/{key}/marks"}


@router.get("/api/analyses/{analysis_id}/model/mac", summary="The dataset's model beside this analysis's modes of "
            "one order: frequencies and MAC at the sensors", response_model=schemas.ModelComparison)
async def mac(request: Request, order: int = Query(ge=1, le=schemas.MAX_INT), modes: str | None = Query(
        None, description="comma-separated indices of the modes to compare (default: every mode of the order)"),
        a: Analysis = Depends(analysis)):
    stored = store(request).model(a.dataset_id)
    if stored is None:
        raise NotFound("This dataset has no structure model yet: describe it in the Model panel or upload a model "
                       "file first.")
    try:
        picked = None if not modes else [int(k) for k in modes.split(",")]
    except ValueError:
        raise era.EraError(f"modes must be comma-separated mode indices, got {modes!r}.") from None
    c = cache(request)

    def work():
        m = c.model(a, order)
        kept = np.arange(m.frequency_hz.size) if picked is None else era.kept_modes(m, picked)
        return modeling.compare(modeling.frame(stored["model"]), m.frequency_hz[kept], m.shapes[:, kept])

    return await jobs(request).heavy(work, progress=progress_key(request),
                                     message="The model's modes beside the test's")
