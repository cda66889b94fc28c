"""HTTP side of the viewer: viser's shipped browser client, the websocket bridge, and the mode-selection route.

URL scheme (one port serves everything):
  GET  /viser/                   the client page; with ?playbackPath=<url> it plays a .viser recording, no server
  GET  /viser/{key}/             the client page for a published key (the iframe)
  WS   /viser/{key}              bridged to the internal viser server at ws://127.0.0.1:{port}/viser/{key}
  POST /viser/{key}/mode         {index, amplitude?, speed?, phase_deg?, interpolate?}: what the key's clients show
  GET  /viser/{key}/picks?after=n   nodes clicked since pick n in the views of a model (ModeViewer.publish_model)
  POST /viser/{key}/look         {node}: turn those views to one node; POST /viser/{key}/marks {marks}: colours

viser's client opens its websocket at its own page URL with http -> ws and the query string and trailing slash
dropped, so the page /viser/{key}/ connects to /viser/{key}: the key travels in the websocket path.
"""

from __future__ import annotations

import asyncio
import gzip
import logging
import re
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

import viser
import websockets
from fastapi import APIRouter, HTTPException, Query, Request, WebSocket
from fastapi.responses import HTMLResponse, RedirectResponse, Response
from pydantic import BaseModel, Field
from starlette.websockets import WebSocketDisconnect

from .registry import MAX_AMPLITUDE, MAX_SPEED

if TYPE_CHECKING:
    from . import ModeViewer

log = logging.getLogger(__name__)

KEY_PATTERN = re.compile(r"[A-Za-z0-9_-]{1,64}")      # secrets.token_urlsafe alphabet
_closing: set[asyncio.Task] = set()        # upstream closes still in progress (a reference keeps them alive)

CLIENT_HTML = Path(viser.__file__).resolve().parent / "client" / "build" / "index.html"


@lru_cache(maxsize=1)
def client_page() -> tuple[bytes, bytes]:
    """viser's single-file client build (scripts, styles and assets inlined: works offline), plain and gzipped."""
    if not CLIENT_HTML.is_file():
        raise RuntimeError(f"viser's browser client is missing from the installed package ({CLIENT_HTML}); "
                           "reinstall viser==1.1.1.")
    raw = CLIENT_HTML.read_bytes()
    return raw, gzip.compress(raw, 6)


# The page may only talk to its own origin (its websocket, same-origin .viser files: a crafted ?playbackPath= cannot
# pull a scene from elsewhere) and only this app may frame it. data:/blob: are the client's own inlined assets.
CSP = "connect-src 'self' data: blob:; frame-ancestors 'self'; object-src 'none'; base-uri 'none'"


def page_response(request: Request) -> Response:
    raw, packed = client_page()
    headers = {"Cache-Control": "no-cache", "X-Content-Type-Options": "nosniff", "Vary": "Accept-Encoding",
               "Content-Security-Policy": CSP}
    if "gzip" in request.headers.get("accept-encoding", ""):
        headers["Content-Encoding"] = "gzip"
        return Response(packed, media_type="text/html; charset=utf-8", headers=headers)
    return Response(raw, media_type="text/html; charset=utf-8", headers=headers)


class LookAt(BaseModel):
    node: str = Field(max_length=200, description="the node to turn the view to")


class NodeMarks(BaseModel):
    marks: dict[str, str] = Field(description="{node id: fixed | pinned | springs | mass | \"\"} (the colour)")


class ViewerMode(BaseModel):
    """What a key's viewers show."""

    index: int = Field(ge=0, description="Mode to show (column of the published shapes, from 0)")
    amplitude: float | None = Field(None, ge=0, le=MAX_AMPLITUDE,
                                    description="Largest displacement drawn, as a fraction of the structure's size")
    speed: float | None = Field(None, ge=0, le=MAX_SPEED, description="Animation cycles per second; 0 freezes")
    phase_deg: float | None = Field(None, ge=-3600, le=3600,
                                    description="Set the phase of the cycle (degrees), e.g. to freeze at a peak")
    interpolate: bool | None = Field(None, description="Move unmeasured nodes with a spline through the sensors")


async def pump_to_browser(upstream, browser: WebSocket) -> None:
    async for message in upstream:
        if isinstance(message, bytes):
            await browser.send_bytes(message)
        else:
            await browser.send_text(message)


async def pump_to_viser(browser: WebSocket, upstream) -> None:
    while True:
        message = await browser.receive()
        if message["type"] == "websocket.disconnect":
            return
        if message.get("bytes") is not None:
            await upstream.send(message["bytes"])
        elif message.get("text") is not None:
            await upstream.send(message["text"])


def make_router(viewer: "ModeViewer") -> APIRouter:
    router = APIRouter(tags=["viewer"])

    @router.get("/viser/", include_in_schema=False)
    def viser_client(request: Request) -> Response:
        """The viewer page with no live session: used with ?playbackPath= for recordings."""
        return page_response(request)

    @router.get("/viser/{key}/", include_in_schema=False)
    def viser_client_for_key(key: str, request: Request) -> Response:
        if not KEY_PATTERN.fullmatch(key) or not viewer.ensure(key):  # published here, or rebuilt from the store
            return HTMLResponse("<p>Unknown or expired viewer link: reload the page to show the modes again.</p>",
                                status_code=404)
        return page_response(request)

    @router.get("/viser/{key}", include_in_schema=False)
    def viser_client_slash(key: str) -> RedirectResponse:
        return RedirectResponse(viewer.iframe_url(key), status_code=307)

    @router.post("/viser/{key}/mode")
    def select_mode(key: str, choice: ViewerMode) -> dict:
        """Select the mode, amplitude and speed that every viewer of this key shows."""
        try:
            if not KEY_PATTERN.fullmatch(key) or not viewer.ensure(key):
                raise KeyError(key)
            state = viewer.set_mode(key, index=choice.index, amplitude=choice.amplitude, speed=choice.speed,
                                    phase_deg=choice.phase_deg, interpolate=choice.interpolate)
        except KeyError:
            raise HTTPException(404, "Unknown or expired viewer key: publish the modes again.") from None
        except ValueError as exc:
            raise HTTPException(422, str(exc)) from None
        return {"index": state.index, "amplitude": state.amplitude, "speed": state.speed,
                "phase_deg": state.phase * 360.0, "interpolate": state.interpolate}

    @router.get("/viser/{key}/picks")
    def picks(key: str, after: int = Query(0, ge=0, description="the last pick seen (its seq)")) -> dict:
        """Nodes clicked in the views of a model published with ModeViewer.publish_model since pick ``after``."""
        try:
            got, last = viewer.picks(key, after)
        except KeyError:
            raise HTTPException(404, "Unknown or expired 3-D view: open it again.") from None
        return {"picks": [{"seq": seq, "node": node} for seq, node in got], "last": last}

    @router.post("/viser/{key}/look")
    def look(key: str, body: LookAt) -> dict:
        """Turn the views of a model to one node (the row chosen in the node table)."""
        try:
            return {"views": viewer.look(key, body.node)}
        except KeyError:
            raise HTTPException(404, f"Unknown 3-D view, or no node {body.node!r} in it.") from None

    @router.post("/viser/{key}/marks")
    def marks(key: str, body: NodeMarks) -> dict:
        """Colour a model's nodes by what they carry (support, springs, mass) in every view."""
        try:
            viewer.mark(key, body.marks)
        except KeyError:
            raise HTTPException(404, "Unknown or expired 3-D view: open it again.") from None
        return {"nodes": len(body.marks)}

    @router.websocket("/viser/{key}")
    async def viser_socket(browser: WebSocket, key: str) -> None:
        """Forward the browser's websocket to the internal viser server, both ways, until either side closes."""
        # An unknown key still reaches viser, which tells the user to reload (an open page after a server restart
        # would otherwise retry forever behind a "reconnecting" badge); a key that cannot be one is refused.
        if not KEY_PATTERN.fullmatch(key) or not viewer.running:
            await browser.close(code=1008, reason="Not a viewer key" if viewer.running else "Viewer not running")
            return
        await asyncio.to_thread(viewer.ensure, key)  # a key another process published: rebuilt before viser asks
        offered = [p for p in browser.scope.get("subprotocols", []) if p.startswith("viser-v")]
        try:
            upstream = await websockets.connect(
                f"ws://127.0.0.1:{viewer.port}/viser/{key}", subprotocols=offered or None,
                max_size=None, compression=None, open_timeout=5, ping_interval=None)
        except (OSError, websockets.WebSocketException, asyncio.TimeoutError) as exc:
            log.warning("viewer bridge could not reach viser: %s", exc)
            await browser.close(code=1011, reason="Viewer unavailable")
            return
        await browser.accept(subprotocol=upstream.subprotocol)
        to_browser = asyncio.create_task(pump_to_browser(upstream, browser))
        to_viser = asyncio.create_task(pump_to_viser(browser, upstream))
        try:
            await asyncio.wait([to_browser, to_viser], return_when=asyncio.FIRST_COMPLETED)
        finally:
            for task in (to_browser, to_viser):
                task.cancel()
            await asyncio.gather(to_browser, to_viser, return_exceptions=True)
        if to_viser.done() and not to_viser.cancelled() and to_viser.exception() is None:
            # The browser left: close the viser side in the background (its closing handshake need not hold
            # this handler open).
            closing = asyncio.create_task(upstream.close())
            _closing.add(closing)
            closing.add_done_callback(_closing.discard)
            return
        await upstream.close()
        # viser closed first: pass its close code on (1002 = client/server version mismatch, shown by the client).
        code = upstream.close_code if upstream.close_code not in (None, 1005, 1006) else 1000
        try:
            await browser.close(code=code, reason=(upstream.close_reason or "")[:120])
        except (RuntimeError, WebSocketDisconnect):
            pass                                    # the browser left meanwhile

    return router
