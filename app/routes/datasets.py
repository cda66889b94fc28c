"""Datasets: upload a file, read its summary, its records and its spectrum."""

from __future__ import annotations

from fastapi import APIRouter, Depends, Form, Query, Request, UploadFile

import era

from .. import payloads, schemas
from ..cache import Dataset
from ..loading import load_upload
from .deps import cache, dataset, jobs, progress_key

router = APIRouter(prefix="/api/datasets", tags=["datasets"])


@router.post("", summary="Upload a file (UFF, CSV, NPZ): pulse responses, free decays, FRFs, input-output or ambient records",
             response_model=schemas.Dataset)
async def upload(request: Request, file: UploadFile,
                 kind: str = Form("auto", description="auto, pulse, decay, frf, io or ambient: what the records are")):
    """Multipart field ``file`` (and optionally ``kind``). Returns the dataset: id, outputs, inputs, dt, n_samples,
    units, source (format, conversions), defaults, limits."""
    name = (file.filename or "upload").rsplit("/", 1)[-1].rsplit("\\", 1)[-1][:200]
    blob = await file.read()
    if not blob:
        raise era.DataError(f"{name!r} is empty: choose a file with pulse responses or free decays.")
    c = cache(request)

    def work():
        data, geometry, source = load_upload(blob, name, kind)
        summary = payloads.dataset_summary(data, geometry, name, c.settings, dict(source, file=name, bytes=len(blob)))
        return c.add_dataset(data, geometry, name, summary)

    if len(blob) <= cache(request).settings.small_upload_bytes:  # cheap: never queued behind SVDs
        return await jobs(request).quick(work)
    return await jobs(request).heavy(work, progress=progress_key(request), message=f"Reading {name}")


@router.get("/{dataset_id}", summary="The summary of a stored dataset", response_model=schemas.Dataset)
async def summary(request: Request, dataset_id: str):
    return cache(request).summary(dataset_id)


@router.get("/{dataset_id}/records", summary="The records of every output for one input, for plotting",
            response_model=schemas.Records)
async def records(request: Request, ds: Dataset = Depends(dataset), input: int = Query(0, ge=0)):
    points = cache(request).settings.max_plot_points
    return await jobs(request).quick(payloads.records_json, ds.data, input, points)


@router.get("/{dataset_id}/spectrum", summary="Complex mode indicator function of the data",
            response_model=schemas.Spectrum)
async def spectrum(request: Request, ds: Dataset = Depends(dataset)):
    return await jobs(request).quick(payloads.spectrum_json, ds.data, cache(request).settings.max_plot_points)
