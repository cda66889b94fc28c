"""Datasets: upload a file, read its summary, its records and its spectrum."""

from __future__ import annotations

from fastapi import APIRouter, Form, Query, Request, UploadFile

import era

from .. import engine as eng
from ..loading import load_upload
from .deps import engine, jobs, progress_key

router = APIRouter(prefix="/api/datasets", tags=["datasets"])


@router.post("", summary="Upload a file (UFF, CSV, NPZ): pulse responses, free decays, FRFs, input-output or ambient records")
async def upload(request: Request, file: UploadFile,
                 kind: str = Form("auto", description="auto, pulse, decay, frf, io or ambient: what the records are")):
    """Multipart field ``file`` (and optionally ``kind``). Returns the dataset: id, outputs, inputs, dt, n_samples,
    units, source (format, conversions), defaults, limits."""
    name = (file.filename or "upload").rsplit("/", 1)[-1].rsplit("\\", 1)[-1][:200]
    blob = await file.read()
    if not blob:
        raise era.DataError(f"{name!r} is empty: choose a file with pulse responses or free decays.")

    def work():
        data, geometry, source = load_upload(blob, name, kind)
        return engine(request).add_dataset(data, geometry, name, dict(source, file=name, bytes=len(blob)))

    return await jobs(request).heavy(work, progress=progress_key(request), message=f"Reading {name}")


@router.get("/{dataset_id}", summary="The summary of a stored dataset")
async def summary(request: Request, dataset_id: str):
    return engine(request).summary(dataset_id)


@router.get("/{dataset_id}/records", summary="The records of every output for one input, for plotting")
async def records(request: Request, dataset_id: str, input: int = Query(0, ge=0)):
    e = engine(request)

    def work():
        data = e.dataset(dataset_id)[0]
        if input >= data.n_inputs:
            raise era.EraError(f"`input` must be 0..{data.n_inputs - 1} (this dataset has {data.n_inputs} inputs).")
        return eng.records_json(data, e.settings, input)

    return await jobs(request).quick(work)


@router.get("/{dataset_id}/spectrum", summary="Complex mode indicator function of the data")
async def spectrum(request: Request, dataset_id: str):
    e = engine(request)
    return await jobs(request).quick(lambda: eng.spectrum_json(e.dataset(dataset_id)[0], e.settings))
