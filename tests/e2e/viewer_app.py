"""A tiny FastAPI app that mounts only the mode viewer, for the browser tests (run: uvicorn viewer_app:app).

It publishes three analytic plate modes on an 11 × 8 grid with 9 sensors (the layout of the paper's 7 ft × 10 ft
grid) and serves a page embedding the live viewer, a recorded cycle, and a page playing that recording back.
"""

from __future__ import annotations

from contextlib import asynccontextmanager

import numpy as np
from fastapi import FastAPI
from fastapi.responses import HTMLResponse, Response

from app.viewer import ModeViewer
from era.core.geometry import Geometry

SENSOR_XY = [(x, y) for y in (1, 4, 6) for x in (1, 5, 9)]


def grid_geometry() -> Geometry:
    """11 × 8 joints 1 ft apart (x 0..10, y 0..7), bars between neighbours, 9 sensors measuring +z."""
    xs, ys = np.arange(11.0), np.arange(8.0)
    xy = np.array([(x, y) for y in ys for x in xs])
    node = {(x, y): k for k, (x, y) in enumerate(xy)}
    edges = [(node[x, y], node[x + 1, y]) for y in ys for x in xs[:-1]]
    edges += [(node[x, y], node[x, y + 1]) for y in ys[:-1] for x in xs]
    return Geometry(
        node_ids=np.arange(1, xy.shape[0] + 1), coordinates=np.column_stack([xy, np.zeros(len(xy))]),
        edges=np.array(edges), channel_nodes=np.array([node[float(x), float(y)] for x, y in SENSOR_XY]),
        channel_directions=np.tile([0.0, 0.0, 1.0], (len(SENSOR_XY), 1)), units="ft")


def plate_modes() -> tuple[np.ndarray, np.ndarray]:
    """(frequency_hz (3,), shapes (9, 3) complex): first bending, first torsion-like, and a complex mode."""
    x, y = np.array(SENSOR_XY, dtype=float).T
    bend = np.sin(np.pi * x / 10) * np.sin(np.pi * y / 7)
    twist = np.sin(2 * np.pi * x / 10) * np.sin(np.pi * y / 7)
    shapes = np.column_stack([bend, twist, bend + 0.5j * twist]).astype(complex)
    return np.array([10.1, 21.7, 33.3]), shapes


viewer = ModeViewer()
GEOMETRY = grid_geometry()
FREQUENCY_HZ, SHAPES = plate_modes()
KEY = viewer.publish(GEOMETRY, FREQUENCY_HZ, SHAPES, None)


@asynccontextmanager
async def lifespan(_: FastAPI):
    viewer.start()
    try:
        yield
    finally:
        viewer.stop()


app = FastAPI(lifespan=lifespan)
app.include_router(viewer.router)


@app.get("/test/key")
def key() -> dict:
    state = viewer.registry.get(KEY).state
    return {"key": KEY, "iframe_url": viewer.iframe_url(KEY), "frames_sent": viewer.frames_sent,
            "sessions": viewer.session_count(KEY), "index": state.index, "amplitude": state.amplitude}


@app.get("/test/page")
def page() -> HTMLResponse:
    return HTMLResponse(f"<!doctype html><title>viewer test</title><h1>Mode shapes</h1>"
                        f"<iframe id=viewer src='{viewer.iframe_url(KEY)}' width=800 height=500></iframe>")


@app.get("/test/mode{number}.viser")
def recording(number: int) -> Response:
    return Response(viewer.record(GEOMETRY, FREQUENCY_HZ, SHAPES, number - 1, frames=30, amplitude=0.3),
                    media_type="application/octet-stream")


@app.get("/test/playback")
def playback() -> HTMLResponse:
    return HTMLResponse(f"<!doctype html><title>playback test</title>"
                        f"<iframe id=viewer src='{viewer.playback_url('/test/mode1.viser')}' "
                        f"width=800 height=500></iframe>")


@app.get("/test/standalone")
def standalone() -> HTMLResponse:
    return HTMLResponse(viewer.standalone_html(viewer.record(GEOMETRY, FREQUENCY_HZ, SHAPES, 1, amplitude=0.3)))
