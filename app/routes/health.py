"""GET /api/health: that the server answers, and which version it is (shown in the page footer)."""

from __future__ import annotations

from fastapi import APIRouter, Request

from .. import schemas

router = APIRouter(prefix="/api", tags=["health"])


@router.get("/health", summary="The server is up: its version", response_model=schemas.Health)
async def health(request: Request):
    return {"status": "ok", "version": request.app.version}
