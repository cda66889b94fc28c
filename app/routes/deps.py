"""What the routes share: the app-wide objects set up in the lifespan, and the lookups of a request's dataset or
analysis (once per request, 404 for an unknown id)."""

from __future__ import annotations

from fastapi import Request

from ..cache import Analysis, Cache, CachedDataset
from ..jobs import Jobs
from ..store import Store


def cache(request: Request) -> Cache:
    return request.app.state.cache


def store(request: Request) -> Store:
    return request.app.state.store


def jobs(request: Request) -> Jobs:
    return request.app.state.jobs


def progress_key(request: Request) -> str | None:
    """The client's name for this request's progress (GET /api/jobs/{key}), from the X-Progress-Key header."""
    return request.headers.get("x-progress-key")


async def find_dataset(request: Request, dataset_id: str) -> CachedDataset:
    """The dataset with this id (NotFound → 404); a dataset not in memory is read on the quick pool."""
    c = cache(request)
    return c.cached_dataset(dataset_id) or await jobs(request).quick(c.dataset, dataset_id)


async def find_analysis(request: Request, analysis_id: str) -> Analysis:
    """The analysis with this id and its dataset (NotFound → 404): one SQL read, and the dataset from memory or,
    when it is not there, read on the quick pool."""
    c = cache(request)
    row = c.analysis_row(analysis_id)
    if c.cached_dataset(row[0]) is None:
        return await jobs(request).quick(c.analysis, analysis_id, row)
    return c.analysis(analysis_id, row)


async def analysis(request: Request, analysis_id: str) -> Analysis:
    """Dependency: the analysis named by the path's {analysis_id}."""
    return await find_analysis(request, analysis_id)


async def dataset(request: Request, dataset_id: str) -> CachedDataset:
    """Dependency: the dataset named by the path's {dataset_id}."""
    return await find_dataset(request, dataset_id)


async def read_files(request: Request, files: list[tuple[str, bytes]], fn, *args):
    """``fn(*args)`` reading uploaded ``files``: small uploads on the quick pool (never queued behind SVDs), large
    ones queued on the heavy pool with progress."""
    if sum(len(b) for _, b in files) <= cache(request).settings.small_upload_bytes:
        return await jobs(request).quick(fn, *args)
    return await jobs(request).heavy(fn, *args, progress=progress_key(request), message=f"Reading {files[0][0]}")
