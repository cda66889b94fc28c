"""Datasets: upload files (one dataset), read its summary, its records and its spectrum."""

from __future__ import annotations

from fastapi import APIRouter, Depends, File, Form, Query, Request, UploadFile

import era

from .. import payloads, schemas
from ..cache import Dataset
from ..loading import load_upload
from .deps import cache, dataset, jobs, progress_key

router = APIRouter(prefix="/api/datasets", tags=["datasets"])


@router.post("", summary="Upload one or several files (UFF, CSV, text, LVM, MAT, HDF5, TDMS, NPY, NPZ, SignalCalc) as "
             "one dataset: pulse responses, free decays, FRFs, input-output or ambient records",
             response_model=schemas.Dataset)
async def upload(request: Request, file: list[UploadFile] = File(description="one part per file; several are read "
                                                                             "as one dataset"),
                 kind: str = Form("auto", description="auto, pulse, decay, frf, io or ambient: what the records are"),
                 dt: float | None = Form(None, gt=0, description="sampling interval, s, when the files carry none"),
                 format: str | None = Form(None, description="the format when sniffing should not decide, e.g. text"),
                 orientation: str | None = Form(None, description="rows or columns: channels of a headerless table"),
                 variable: str | None = Form(None, description="the array to read in a MAT or HDF5 file"),
                 group: str | None = Form(None, description="the TDMS group to read"),
                 frf_sign: str | None = Form(None, description="auto, + or -: the FRFs' sign convention")):
    """Multipart parts ``file`` (one or several) and the options the files cannot say themselves. Returns the
    dataset: id, outputs, inputs, dt, n_samples, units, source (format, conversions, options), defaults, limits."""
    files = []
    for part in file:
        name = (part.filename or "upload").rsplit("/", 1)[-1].rsplit("\\", 1)[-1][:200]
        blob = await part.read()
        if not blob:
            raise era.DataError(f"{name!r} is empty: choose a file with pulse responses or free decays.")
        files.append((name, blob))
    name = files[0][0] if len(files) == 1 else f"{files[0][0]} + {len(files) - 1} more"
    size = sum(len(b) for _, b in files)
    options = dict(dt=dt, format=format, orientation=orientation, variable=variable, group=group, frf_sign=frf_sign)
    c = cache(request)

    def work():
        data, geometry, source = load_upload(files, kind, **options)
        given = {k: v for k, v in options.items() if v is not None}
        source = dict(source, file=name if len(files) == 1 else [n for n, _ in files], bytes=size, options=given)
        summary = payloads.dataset_summary(data, geometry, name, c.settings, source)
        return c.add_dataset(data, geometry, name, summary)

    if size <= c.settings.small_upload_bytes:  # cheap: never queued behind SVDs
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
