"""Datasets: upload files (one dataset), read its summary, its records and its spectrum."""

from __future__ import annotations

from fastapi import APIRouter, Depends, File, Form, Query, Request, UploadFile

from .. import payloads, schemas
from ..cache import CachedDataset
from ..loading import band, channel_list, check_files, new_dataset
from .deps import cache, dataset, jobs, read_files

router = APIRouter(prefix="/api/datasets", tags=["datasets"])


async def read_parts(parts: list[UploadFile]) -> list[tuple[str, bytes]]:
    """(name, bytes) of each uploaded part; the name without any folder."""
    files = []
    for part in parts:
        name = (part.filename or "upload").rsplit("/", 1)[-1].rsplit("\\", 1)[-1][:200]
        files.append((name, await part.read()))
    check_files(files)
    return files


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
                 frf_sign: str | None = Form(None, description="auto, + or -: the FRFs' sign convention"),
                 start_sample: int | None = Form(None, ge=0, le=schemas.MAX_INT,
                                                 description="samples skipped at the start of every record "
                                                             "(pre-trigger)"),
                 drop: str | None = Form(None, description="channels left out: positions as read, e.g. 0,3"),
                 forces: str | None = Form(None, description="channels measuring the excitation, e.g. 0"),
                 references: str | None = Form(None, description="NExT reference channels of ambient records"),
                 band_hz: str | None = Form(None, description="the band FRFs are valid in, Hz: low,high (e.g. "
                                                              "65,1000); no mode is chosen outside it")):
    """Multipart parts ``file`` (one or several) and the options the files cannot say themselves (the import step
    of the page uses /api/imports to show what was read first). Returns the dataset: id, outputs, inputs, dt,
    n_samples, units, source (format, conversions, options), defaults, limits."""
    files = await read_parts(file)
    options = dict(dt=dt, format=format, orientation=orientation, variable=variable, group=group, frf_sign=frf_sign,
                   start_sample=start_sample, drop=channel_list(drop, "drop"),
                   forces=channel_list(forces, "forces"), references=channel_list(references, "references"),
                   band_hz=band(band_hz))
    return await read_files(request, files, new_dataset, cache(request), files, kind, options)


@router.get("/{dataset_id}", summary="The summary of a stored dataset", response_model=schemas.Dataset)
async def summary(request: Request, dataset_id: str):
    return cache(request).summary(dataset_id)


@router.get("/{dataset_id}/records", summary="The records of every output for one input, for plotting",
            response_model=schemas.Records)
async def records(request: Request, ds: CachedDataset = Depends(dataset),
                  input: int = Query(0, ge=0, le=schemas.MAX_INT)):
    points = cache(request).settings.max_plot_points
    return await jobs(request).quick(payloads.records_json, ds.data, input, points)


@router.get("/{dataset_id}/spectrum", summary="Complex mode indicator function of the data",
            response_model=schemas.Spectrum)
async def spectrum(request: Request, ds: CachedDataset = Depends(dataset)):
    return await jobs(request).quick(payloads.spectrum_json, ds.data, cache(request).settings.max_plot_points)
