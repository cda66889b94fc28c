"""GET /api/health: that the server answers, its version (shown in the page footer) and its store."""

from __future__ import annotations

import asyncio

from fastapi import APIRouter, Request

from .. import schemas

router = APIRouter(prefix="/api", tags=["health"])


@router.get("/health", summary="The server is up: its version", response_model=schemas.Health)
async def health(request: Request):
    store = request.app.state.store
    settings = request.app.state.settings
    return {"status": "ok", "version": request.app.version, "store": store.backend, "schema_revision": store.revision,
            "usage": await asyncio.to_thread(store.usage), "expire_days": settings.expire_days,
            "access": "open" if request.app.state.access.open else "restricted"}
