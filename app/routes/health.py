"""GET /api/health: that the server answers, its version (shown in the page footer) and its store."""

from __future__ import annotations

from fastapi import APIRouter, Request

from .. import schemas

router = APIRouter(prefix="/api", tags=["health"])


@router.get("/health", summary="The server is up: its version", response_model=schemas.Health)
async def health(request: Request):
    store = request.app.state.store
    return {"status": "ok", "version": request.app.version, "store": store.backend, "schema_revision": store.revision}
