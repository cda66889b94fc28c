"""The mode-shape viewer: viser 1.1.1 embedded in the page on the app's own port.

    viewer = ModeViewer()
    app.include_router(viewer.router)            # and viewer.start() / viewer.stop() in the lifespan
    key = viewer.publish(geometry, frequency_hz, shapes, labels)
    <iframe src="{viewer.iframe_url(key)}">     # POST /viser/{key}/mode {index, amplitude?, speed?} selects the mode
    data = viewer.record(geometry, frequency_hz, shapes, mode_index)  # .viser bytes for a report
    <iframe src="{viewer.playback_url('/files/mode1.viser')}">      # plays it with no live Python session
    html = viewer.standalone_html(data)                              # or as one self-contained file, no server
    key = viewer.publish_model(nodes, members, marks)  # a model to pick nodes in: GET /viser/{key}/picks?after=n

Modules: scene.py (geometry + shape -> lines and colours, pure numpy), registry.py (keys and view state),
live.py (viser server, per-browser scenes, animation thread), bridge.py (HTTP/websocket routes), record.py (.viser),
picking.py (a model's nodes as clickable spheres, the clicks kept per key).
One viser server per process: run the app with one uvicorn worker.
"""

from __future__ import annotations

import time

from urllib.parse import quote

import numpy as np

from era import Geometry

from .bridge import make_router
from .live import LiveViewer
from .picking import pick_scene
from .record import record_mode, standalone_html
from .registry import Registry

__all__ = ["ModeViewer"]


class ModeViewer:
    """Publish mode sets under random keys and show them, animated, in viser iframes served by `router`."""

    def __init__(self, fps: float = 30.0, capacity: int = 256):
        self.registry = Registry(capacity)
        self._live = LiveViewer(self.registry, fps=fps)
        self._live.on_tick = self.follow_states
        self.router = make_router(self)
        #: key -> (geometry, frequency_hz, shapes, labels) of a key another process published, or None (set by the
        #: app: it rebuilds the scene from stored results)
        self.resolver = None
        #: where view states are shared between processes: .save(key, state dict), .load(keys) -> {key: (state,
        #: revision)} (set by the app; None: this process only)
        self.states = None
        self._followed: dict[str, int] = {}
        self._last_sync = 0.0

    def ensure(self, key: str) -> bool:
        """The key is shown here: published in this process, or rebuilt through ``resolver``. Blocking."""
        if key in self.registry or key in self._live.pickable:
            return True
        built = self.resolver(key) if self.resolver is not None else None
        if built is None:
            return False
        self.registry.publish(*built, key=key)
        return True

    def follow_states(self, keys, every_s: float = 0.5) -> None:
        """Apply view states chosen through other processes (newer stored revisions) to the shown ``keys``."""
        now = time.monotonic()
        if self.states is None or now - self._last_sync < every_s:
            return
        self._last_sync = now
        for key, (state, revision) in self.states.load(keys).items():
            if revision > self._followed.get(key, 0):
                self._followed[key] = revision
                self.registry.follow(key, state)

    def start(self) -> None:
        """Start the internal viser server (127.0.0.1, a free port) and the animation thread."""
        self._live.start()

    def stop(self) -> None:
        self._live.stop()

    @property
    def running(self) -> bool:
        return self._live.running

    @property
    def port(self) -> int:
        """Internal port of the viser server (only the bridge talks to it)."""
        return self._live.port

    @property
    def frames_sent(self) -> int:
        """Animation frames sent to all browsers since start (to measure the frame rate)."""
        return self._live.frames_sent

    def publish(self, geometry: Geometry | None, frequency_hz, shapes, labels=None) -> str:
        """Register modes to show; returns a random key (128 bits, URL-safe).

        geometry : era.Geometry, or None for the p sensors in a row (scene.geometry_for: also when the geometry
            places no channel; a channel with unknown direction measures +z)
        frequency_hz : (modes,) Hz; shapes : (p, modes) complex; labels : one string per mode or None
        Raises era.DataError when the sizes do not match."""
        return self.registry.publish(geometry, frequency_hz, shapes, labels)

    def set_mode(self, key: str, index=None, amplitude=None, speed=None, phase_deg=None, interpolate=None):
        """What every client of `key` shows (same as POST /viser/{key}/mode); KeyError, ValueError."""
        state = self._live.set_mode(key, index=index, amplitude=amplitude, speed=speed, phase_deg=phase_deg,
                                    interpolate=interpolate)
        if self.states is not None:
            self.states.save(key, {"index": state.index, "amplitude": state.amplitude, "speed": state.speed,
                                   "interpolate": state.interpolate})
        return state

    def publish_model(self, nodes: dict, members: list, marks: dict | None = None) -> str:
        """Show a model to pick nodes in (picking.py): {node id: (x, y, z) m}, [(node i, node j)], {node id:
        "fixed" | "pinned" | "springs" | "mass" | ""}; returns its key. era.DataError for a malformed model."""
        return self._live.pickable.publish(pick_scene(nodes, members, marks))

    def picks(self, key: str, after: int = 0) -> tuple[list[tuple[int, str]], int]:
        """Nodes clicked in the views of ``key`` since pick ``after``: ([(seq, node id)], last seq); KeyError."""
        return self._live.pickable.picks(key, after)

    def look(self, key: str, node: str) -> int:
        """Turn the views of ``key`` to ``node``; the number of views turned. KeyError."""
        return self._live.look(key, node)

    def mark(self, key: str, marks: dict) -> None:
        """Colour the nodes of ``key`` by their marks; KeyError, era.DataError."""
        self._live.mark(key, marks)

    def session_count(self, key: str | None = None) -> int:
        """Browsers currently showing `key` (all keys if None)."""
        return self._live.session_count(key)

    def iframe_url(self, key: str) -> str:
        """Page for an <iframe>; its websocket path /viser/{key} carries the key."""
        return f"/viser/{quote(key, safe='')}/"

    def record(self, geometry: Geometry | None, frequency_hz, shapes, mode_index: int, frames: int = 30,
               amplitude: float = 0.15, period_s: float = 2.0, interpolate: bool = True) -> bytes:
        """One cycle of one mode as .viser bytes (see record.record_mode); needs no running server."""
        return record_mode(geometry, np.asarray(frequency_hz), shapes, mode_index, frames=frames,
                           amplitude=amplitude, period_s=period_s, interpolate=interpolate)

    @staticmethod
    def standalone_html(recording: bytes) -> str:
        """One HTML file (about 0.8 MB plus the recording) that plays `record()`'s bytes with no server, e.g. in a
        downloaded report (as its own file, or in an <iframe srcdoc>)."""
        return standalone_html(recording)

    def playback_url(self, file_url: str) -> str:
        """Page for an <iframe> that plays the .viser file at `file_url` (same origin) in viser's shipped client."""
        return "/viser/?playbackPath=" + quote(file_url, safe="/")
