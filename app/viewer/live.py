"""The live viewer: one ViserServer on 127.0.0.1, one scene per connected browser, one thread that animates them.

How a browser gets its modes: the iframe page /viser/{key}/ opens the websocket /viser/{key} (viser's client derives
the websocket URL from its page URL), the bridge (bridge.py) forwards it to this server keeping the path, and
`on_client_connect` reads the key back from that path (viser hands callbacks no request, so we look the connection up
in the websocket server; viser is pinned exactly, see pyproject.toml).
"""

from __future__ import annotations

import logging
import threading
import time

import viser
from viser import _messages

from . import scene
from .picking import MARK_RGB, PickRegistry, add_pick_nodes
from .record import add_mode_nodes, quiet, update_mode_nodes
from .registry import MAX_AMPLITUDE, MAX_SPEED, Published, Registry, ViewState

log = logging.getLogger(__name__)

LEGEND = ("Colour: still (blue) to largest excursion (red). Dots: sensors; grey: at rest. "
          "*Interpolate* moves unmeasured nodes with a spline through the sensors.")


def disable_sharing(server: viser.ViserServer) -> None:
    """No share button, and a share-URL request from a client (which would open a public tunnel to
    share.viser.studio) does nothing. The control panel starts minimized to its title bar: floating open over a
    viewer some 600 px wide it covered half the structure, and the page has the mode, amplitude and speed already
    (its + opens it: interpolation and the colour legend)."""
    server.gui.configure_theme(show_share_button=False, show_logo=False, control_width="small")
    server.gui.main_panel.minimize()
    for message in (_messages.ShareUrlRequest, _messages.ShareUrlDisconnect):
        server._websock_server.unregister_handler(message)
    server.request_share_url = lambda *args, **kwargs: None


def connection_path(server: viser.ViserServer, client: viser.ClientHandle) -> str:
    """The websocket request path a client connected with ("" if it is gone)."""
    connection = server._websock_server._live_connections.get(client.client_id)
    request = getattr(connection, "request", None)
    return request.path.partition("?")[0] if request is not None else ""


class Session:
    """One browser: its scene handles, its GUI, and the last thing drawn (so a frozen view sends nothing)."""

    def __init__(self, viewer: "LiveViewer", client: viser.ClientHandle, key: str, entry: Published):
        self.client, self.key, self.entry = client, key, entry
        self.revision = -1
        self.drawn: tuple | None = None
        geometry, state = entry.geometry, entry.state
        # any mode, as measured or interpolated, stays in view at the slider's full swing
        motions = list(entry.node_vectors) + list(entry.spline_vectors or [])
        position, look_at = scene.camera_pose(geometry, motions, MAX_AMPLITUDE)
        client.camera.position = position
        client.camera.look_at = look_at
        first = scene.frame(geometry, entry.vectors(state), state.phase, state.amplitude)
        undeformed = scene.frame(geometry, entry.vectors(state), 0.0, 0.0)
        with client.atomic():
            self.lines, self.points, self.surface = add_mode_nodes(client.scene, geometry, first, undeformed)
        note = scene.stand_in_note(geometry)
        if note is not None:  # a lone dot or a row of them says nothing by itself
            below = look_at - (0.0, 0.0, 0.3 * scene.structure_size(geometry))
            client.scene.add_label("/stand-in", note, position=tuple(below), anchor="top-center")
        gui = client.gui
        self.mode = gui.add_dropdown("Mode", entry.labels, initial_value=entry.labels[state.index])
        self.amplitude = gui.add_slider("Amplitude", 0.0, MAX_AMPLITUDE, 0.01, state.amplitude,
                                        hint="Largest displacement drawn, as a fraction of the structure's size")
        self.speed = gui.add_slider("Speed", 0.0, MAX_SPEED, 0.05, state.speed,
                                    hint="Animation cycles per second (0 freezes)")
        self.interpolate = gui.add_checkbox("Interpolate", state.interpolate,
                                            hint="Move unmeasured nodes with a spline through the sensors")
        gui.add_markdown(LEGEND)

        # Only a person's change (event.client set) goes to the key's state; programmatic syncs do not echo back.
        def apply(event, **changes):
            if event.client is None:
                return
            try:
                viewer.set_mode(key, **changes)
            except (KeyError, ValueError):                 # the key expired meanwhile: nothing left to steer
                log.debug("viewer key %s gone", key)

        def on_mode(event):
            apply(event, index=entry.labels.index(self.mode.value))

        def on_amplitude(event):
            apply(event, amplitude=self.amplitude.value)

        def on_speed(event):
            apply(event, speed=self.speed.value)

        def on_interpolate(event):
            apply(event, interpolate=self.interpolate.value)

        self.interpolate.on_update(on_interpolate)
        self.mode.on_update(on_mode)
        self.amplitude.on_update(on_amplitude)
        self.speed.on_update(on_speed)

    def draw(self, state: ViewState, revision: int) -> bool:
        """Show `state`, syncing the GUI when its `revision` is new; returns True if a frame was sent."""
        if revision != self.revision:
            self.revision = revision
            self.mode.value = self.entry.labels[state.index]
            self.amplitude.value = state.amplitude
            self.speed.value = state.speed
            self.interpolate.value = state.interpolate
        now = (state.index, state.amplitude, state.phase, state.interpolate)
        if now == self.drawn:
            return False
        f = scene.frame(self.entry.geometry, self.entry.vectors(state), state.phase, state.amplitude)
        with self.client.atomic():
            update_mode_nodes(self.lines, self.points, f, self.surface)
        self.drawn = now
        return True


class LiveViewer:
    """The viser server, the sessions and the animation thread (`ModeViewer` adds the HTTP side)."""

    def __init__(self, registry: Registry, fps: float = 30.0, pickable: PickRegistry | None = None):
        self.registry = registry
        self.pickable = pickable if pickable is not None else PickRegistry()
        self._pickers: dict[int, tuple[str, viser.ClientHandle, dict]] = {}   # client -> (key, client, spheres)
        self.fps = fps
        self.frames_sent = 0                       # all sessions, since start (for measuring the frame rate)
        self._server: viser.ViserServer | None = None
        self._sessions: dict[int, Session] = {}
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        #: called with the shown keys on every frame (ModeViewer.follow_states: states chosen in other processes)
        self.on_tick = None

    @property
    def port(self) -> int:
        if self._server is None:
            raise RuntimeError("The mode viewer is not running: call ModeViewer.start() in the app's lifespan.")
        return self._server.get_port()

    @property
    def running(self) -> bool:
        return self._server is not None

    def start(self) -> None:
        if self._server is not None:
            return
        with quiet():
            server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
        disable_sharing(server)
        server.on_client_connect(self._connect)
        server.on_client_disconnect(self._disconnect)
        self._server = server
        self._stop.clear()
        self._thread = threading.Thread(target=self._animate, name="mode-viewer", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        if self._server is None:
            return
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=5.0)
        with quiet():
            self._server.stop()
        self._server, self._thread = None, None
        with self._lock:
            self._sessions.clear()

    def set_mode(self, key: str, **changes) -> ViewState:
        """Change what a key's clients show (see registry.updated_state); KeyError / ValueError."""
        return self.registry.set_state(key, **changes)

    def session_count(self, key: str | None = None) -> int:
        with self._lock:
            return sum(1 for s in self._sessions.values() if key is None or s.key == key)

    def _connect(self, client: viser.ClientHandle) -> None:
        key = connection_path(self._server, client).rstrip("/").rpartition("/")[2]
        picking = self.pickable.get(key)
        if picking is not None:                    # a model to pick nodes in (picking.py), not a mode set
            client.camera.position, client.camera.look_at = picking.look_from()   # position first (see look)
            with client.atomic():
                spheres = add_pick_nodes(client.scene, picking, lambda n: self.pickable.add_pick(key, n))
            client.gui.add_markdown("Click a node: the Model panel takes it as a click in its drawing.")
            with self._lock:
                self._pickers[client.client_id] = (key, client, spheres)
            return
        entry = self.registry.get(key)
        if entry is None:
            client.gui.add_markdown("**Unknown or expired viewer link.** Reload the page to show the modes again.")
            return
        session = Session(self, client, key, entry)
        with self._lock:
            self._sessions[client.client_id] = session

    def _disconnect(self, client: viser.ClientHandle) -> None:
        with self._lock:
            self._sessions.pop(client.client_id, None)
            self._pickers.pop(client.client_id, None)

    def _picking(self, key: str) -> list[tuple[viser.ClientHandle, dict]]:
        with self._lock:
            return [(c, spheres) for k, c, spheres in self._pickers.values() if k == key]

    def look(self, key: str, node: str) -> int:
        """Turn every view of pick scene ``key`` to ``node`` (picking.PickScene.look_from); the views turned.
        KeyError for an unknown key or node."""
        s = self.pickable.get(key)
        if s is None or node not in s.ids:
            raise KeyError(node)
        position, look_at = s.look_from(node)
        views = self._picking(key)
        for client, _ in views:
            client.camera.position = position      # position first: viser moves look_at along with it
            client.camera.look_at = look_at
        return len(views)

    def mark(self, key: str, marks: dict) -> None:
        """Colour the nodes of pick scene ``key`` by their marks in every view; KeyError, era.DataError."""
        s = self.pickable.set_marks(key, marks)
        for client, spheres in self._picking(key):
            with client.atomic():
                for n, h in spheres.items():
                    h.color = MARK_RGB[s.marks.get(n, "")]

    def _animate(self) -> None:
        """Advance each shown key's phase by the elapsed time and draw every session, `fps` times a second."""
        period = 1.0 / self.fps
        last = time.monotonic()
        while not self._stop.wait(max(0.0, last + period - time.monotonic())):
            now = time.monotonic()
            elapsed, last = now - last, now
            with self._lock:
                sessions = list(self._sessions.items())
            keys = {s.key for _, s in sessions}
            if self.on_tick is not None and keys:
                try:
                    self.on_tick(keys)
                except Exception:  # following other processes is best effort; the animation goes on
                    log.debug("viewer state sync failed", exc_info=True)
            states = {key: self.registry.advance(key, elapsed) for key in keys}
            for client_id, session in sessions:
                current = states[session.key]
                try:
                    if current is not None and session.draw(*current):
                        self.frames_sent += 1
                except Exception:                  # a client that vanished mid-frame; viser reports the disconnect
                    log.debug("dropping viewer session %s", client_id, exc_info=True)
                    with self._lock:
                        self._sessions.pop(client_id, None)
