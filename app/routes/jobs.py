"""Progress of heavy work: GET /api/jobs/{key} for a request sent with the header X-Progress-Key: {key}."""

from __future__ import annotations

from fastapi import APIRouter, Request

from .. import schemas
from ..errors import NotFound
from .deps import jobs

router = APIRouter(prefix="/api/jobs", tags=["jobs"])


@router.get("/{key}", summary="State of a heavy request: queued (behind how many), running (for how long), done",
            response_model=schemas.Progress)
async def progress(request: Request, key: str):
    state = jobs(request).progress(key)
    if state is None:
        raise NotFound(f"No computation is known under the key {key!r} (it may not have started yet).")
    return state
