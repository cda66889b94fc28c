"""GET /api/health: that the server answers, its version (shown in the page footer) and its store."""

from __future__ import annotations

import asyncio

from fastapi import APIRouter, Request

from .. import schemas

router = APIRouter(prefix="/api", tags=["health"])


@router.get("/health", summary="The server is up: its version", response_model=schemas.Health)
async def health(request: Request):
    """The store and its usage are shown to whoever may use the API; on a restricted server others (a monitor, a
    report reader) see only that it is up, its version and that access is restricted."""
    store = request.app.state.store
    settings = request.app.state.settings
    access = request.app.state.access
    out = {"status": "ok", "version": request.app.version, "access": "open" if access.open else "restricted",
           "store": None, "schema_revision": None, "usage": None, "expire_days": None}
    if access.allowed(request):
        out.update(store=store.backend, schema_revision=store.revision, usage=await asyncio.to_thread(store.usage),
                   expire_days=settings.expire_days)
    return out
