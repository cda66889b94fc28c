"""The structure model of a dataset: the draft read from its geometry, the stored model (GET), a model
described in the browser (PUT), a model file uploaded (POST .../model/file), and the model's modes beside an
analysis's (MAC). Saving checks the model against the dataset's channels and solves it once; a refused model
leaves the stored one as it was."""

from __future__ import annotations

import hashlib
import time
from pathlib import Path

import numpy as np
from fastapi import APIRouter, Depends, File, HTTPException, Query, Request, UploadFile

import era

from .. import femodel, modeling, schemas
from ..cache import Analysis, CachedDataset
from ..errors import NotFound
from ..schemas import MappingRequest, ModelRequest, ModelView
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

    if stored.get("source") == "fe":
        return femodel.summary(stored, stored["frequency_hz"], modeling.fingerprint(stored["model"]))

    def work():
        fr = modeling.frame_of(stored["model"])
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


def fe_path(request: Request, dataset_id: str, stored: dict) -> Path:
    """Where the store keeps the file of a stored FE model."""
    fe = stored["model"]["fe"]
    return store(request).model_file(dataset_id, fe["sha256"], fe["suffix"])


async def _save_fe(request: Request, ds: CachedDataset, name: str, file: UploadFile) -> dict:
    """An FE model file (a Nastran deck, a .zip of matrices) read with era.load_model, its nominal modes solved,
    the test's outputs matched to its DOFs; kept only when all of that worked."""
    limit = cache(request).settings.max_upload_bytes
    blob = await file.read(limit + 1)
    sha = hashlib.sha256(blob).hexdigest()
    files = store(request)
    path = files.model_file(ds.id, sha, Path(name).suffix.lower())
    before = files.model(ds.id)

    def work():
        try:
            model = femodel.read_upload(name, blob, path, limit)
            try:
                f_hz, _ = femodel.elastic_modes(model, femodel.N_MODES)
            except era.EraError as exc:
                raise era.DataError(f"{name}: the model's modes could not be solved: {exc}") from None
        except BaseException:
            if before is None or before.get("source") != "fe" or before["model"]["fe"]["sha256"] != sha:
                path.unlink(missing_ok=True)
            raise
        points = femodel.test_points(ds.data.outputs, ds.geometry, ds.data.meta)
        stored = {"model": {"fe": femodel.describe(model, name, sha),
                            "mapping": femodel.match(model, ds.data.outputs, points)},
                  "source": "fe", "name": name, "saved": time.time(),
                  "frequency_hz": [float(f) for f in f_hz], "total_mass": float(model.total_mass()),
                  "mass_unit": femodel.mass_unit(model, path)}
        files.set_model(ds.id, stored)
        files.drop_model_files(ds.id, keep=path)
        return femodel.summary(stored, f_hz, modeling.fingerprint(stored["model"]))

    return await jobs(request).heavy(work, progress=progress_key(request),
                                     message="Reading the FE model and computing its lowest modes")


@router.post("/api/datasets/{dataset_id}/model/file",
             summary="Upload a model file: era.Frame JSON (TOML named .toml), a Nastran deck (.bdf, .dat, .nas) or "
                     "a .zip of matrices (K.mtx, M.mtx, dofs.csv)", response_model=schemas.StructureModel)
async def upload(request: Request, file: UploadFile = File(description="the model file"),
                 ds: CachedDataset = Depends(dataset)):
    """An FE model's test points are matched to its nodes by label and direction; ``mapping`` in the answer says
    how, ``unmatched`` which outputs match no model DOF (PUT .../model/mapping corrects it)."""
    name = (file.filename or "model.json").rsplit("/", 1)[-1].rsplit("\\", 1)[-1][:200]
    if femodel.is_fe(name):
        return await _save_fe(request, ds, name, file)
    blob = await file.read(modeling.MAX_MODEL_BYTES + 1)
    model = modeling.read_file(name, blob)
    return await _save(request, ds, {"model": model, "source": "file", "name": name, "saved": time.time()})


@router.put("/api/datasets/{dataset_id}/model/mapping", summary="Match the test's outputs to the FE model's "
            "nodes and directions", response_model=schemas.StructureModel)
async def remap(request: Request, body: MappingRequest, ds: CachedDataset = Depends(dataset)):
    """One [node, direction] (or null) per output, in the outputs' order; refused (422, the stored mapping kept)
    when a pair is not a free DOF of the model."""
    files = store(request)
    stored = files.model(ds.id)
    if stored is None or stored.get("source") != "fe":
        raise era.DataError("Only an uploaded FE model (a Nastran deck or a .zip of matrices) has a mapping of test "
                            "points to model nodes: upload one first (POST .../model/file).")
    path = fe_path(request, ds.id, stored)

    def work():
        model = femodel.load(str(path))
        rows = femodel.checked_mapping(model, ds.data.outputs, body.sensors)
        kept = dict(stored, model=dict(stored["model"], mapping=rows), saved=time.time())
        files.set_model(ds.id, kept)
        return femodel.summary(kept, kept["frequency_hz"], modeling.fingerprint(kept["model"]))

    return await jobs(request).heavy(work, progress=progress_key(request), message="Reading the FE model")


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
    path = fe_path(request, a.dataset_id, stored) if stored.get("source") == "fe" else None

    def work():
        m = c.model(a, order)
        kept = np.arange(m.frequency_hz.size) if picked is None else era.kept_modes(m, picked)
        if path is not None:
            return femodel.compare(femodel.load(str(path)), stored["model"]["mapping"], m.frequency_hz[kept],
                                   m.shapes[:, kept])
        return modeling.compare(modeling.frame_of(stored["model"]), m.frequency_hz[kept], m.shapes[:, kept])

    return await jobs(request).heavy(work, progress=progress_key(request),
                                     message="The model's modes beside the test's")
