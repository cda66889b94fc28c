"""The import step: upload files, see what was read, say what the files could not, then make the dataset."""

from __future__ import annotations

from fastapi import APIRouter, File, Form, Request, UploadFile

import era

from .. import schemas
from ..errors import NotFound
from ..importing import given, import_json, in_page_words
from ..loading import channel_list, new_dataset
from ..store import new_token
from .datasets import read_parts
from .deps import cache, jobs, read_files, store

router = APIRouter(prefix="/api/imports", tags=["datasets"])


def _staged(request: Request, upload_id: str) -> list[tuple[str, bytes]]:
    files = store(request).staging.files(upload_id)
    if files is None:
        raise NotFound(f"No upload {upload_id!r} waiting to be imported (uploads are kept a day, and only until they "
                       "become a dataset); drop the files again.")
    return files


@router.post("", summary="Upload files for the import step: they are kept and shown as read, not yet a dataset",
             response_model=schemas.Import)
async def upload(request: Request, file: list[UploadFile] = File(description="one part per file; several are read "
                                                                             "as one dataset"),
                 dt: float | None = Form(None, gt=0, description="sampling interval, s, when the files carry none"),
                 format: str | None = Form(None, description="the format when sniffing should not decide"),
                 orientation: str | None = Form(None, description="rows or columns: channels of a headerless table"),
                 variable: str | None = Form(None, description="the array to read in a MAT or HDF5 file"),
                 group: str | None = Form(None, description="the TDMS group to read"),
                 start_sample: int | None = Form(None, ge=0, le=schemas.MAX_INT,
                                                 description="samples skipped at the start of records"),
                 drop: str | None = Form(None, description="channels left out: positions as read, e.g. 0,3")):
    """Multipart parts ``file``; optional first options. Returns the upload's id and what was read (or what stops
    reading it, with the option that fixes it). The files are kept a day for POST /api/imports/{id}/preview and
    POST /api/imports/{id}/dataset."""
    files = await read_parts(file)
    options = dict(dt=dt, format=format, orientation=orientation, variable=variable, group=group,
                   start_sample=start_sample, drop=channel_list(drop, "drop"))
    upload_id = new_token()
    await jobs(request).quick(store(request).staging.add, upload_id, files)
    settings = cache(request).settings
    try:
        return await read_files(request, files, import_json, upload_id, files, options, settings.max_plot_points,
                                settings.max_upload_bytes, cache(request).reads)
    except era.TooLargeError:  # 413: files that inflate past the limit are not kept for another try
        await jobs(request).quick(store(request).staging.remove, upload_id)
        raise


@router.post("/{upload_id}/preview", summary="Read the staged files again with the person's options",
             response_model=schemas.Import)
async def preview(request: Request, upload_id: str, options: schemas.ImportOptions):
    files = _staged(request, upload_id)
    settings = cache(request).settings
    return await read_files(request, files, import_json, upload_id, files, options.model_dump(),
                            settings.max_plot_points, settings.max_upload_bytes, cache(request).reads)


@router.post("/{upload_id}/dataset", summary="Make the dataset from the staged files with the person's options",
             response_model=schemas.Dataset)
async def commit(request: Request, upload_id: str, options: schemas.ImportOptions):
    """The dataset (as POST /api/datasets returns it); its summary keeps the options. The staged files are then
    deleted. A refusal (422) names the option that fixes it in ``option``; the files stay staged."""
    files = _staged(request, upload_id)
    said = {k: v for k, v in given(options.model_dump()).items() if k != "kind"}
    try:
        summary = await read_files(request, files, new_dataset, cache(request), files, options.kind, said, upload_id)
    except era.TooLargeError:
        raise
    except era.EraError as exc:  # said next to the control, in the page's words
        raise in_page_words(exc) from None
    store(request).staging.remove(upload_id)
    return summary
