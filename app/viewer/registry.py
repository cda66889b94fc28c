"""Published mode sets, one per random key, and what each key's viewers are told to show.

A key is the only handle to its data (it sits in the websocket path of the viewer iframe), so it is random and
unguessable. The registry keeps the newest `capacity` keys (least recently used dropped first) so a long-running
server does not grow without bound; a dropped key's iframe shows "unknown key" and the page publishes again.
"""

from __future__ import annotations

import secrets
from dataclasses import dataclass, field, replace

import numpy as np

from era import Geometry

from . import scene
from .recent import Recent

MAX_AMPLITUDE = 0.5       # fraction of the structure size
MAX_SPEED = 2.0           # animation cycles per second (display speed, not the mode's frequency)


@dataclass(frozen=True)
class ViewState:
    """What a key's clients show: mode index, amplitude (fraction of structure size), speed (cycles/s, 0 freezes),
    the current phase (fraction of a cycle) and whether unmeasured nodes follow the spline (scene.py)."""

    index: int = 0
    amplitude: float = 0.15
    speed: float = 0.5
    phase: float = 0.0
    interpolate: bool = True


@dataclass
class Published:
    """One published mode set (immutable data) and its mutable view state."""

    geometry: Geometry
    frequency_hz: np.ndarray
    shapes: np.ndarray
    labels: list[str]
    node_vectors: list[np.ndarray]          # per mode, (n_nodes, 3) complex, measured nodes only
    spline_vectors: list[np.ndarray]        # per mode, unmeasured nodes interpolated (scene.node_modal_vectors)
    state: ViewState = field(default_factory=ViewState)
    revision: int = 0                        # bumped on every state change clients must follow (not phase ticks)

    @property
    def n_modes(self) -> int:
        return self.frequency_hz.size

    def vectors(self, state: ViewState) -> np.ndarray:
        """(n_nodes, 3) complex node vectors of the mode `state` shows."""
        return (self.spline_vectors if state.interpolate else self.node_vectors)[state.index]


def updated_state(state: ViewState, n_modes: int, index=None, amplitude=None, speed=None,
                  phase_deg=None, interpolate=None) -> ViewState:
    """Validated new state. Selecting another mode restarts its cycle at phase 0 unless a phase is given.

    Raises ValueError with a message for the user when a value is out of range."""
    new = state
    if index is not None:
        if isinstance(index, bool) or int(index) != index or not 0 <= int(index) < n_modes:
            raise ValueError(f"Mode index {index!r} is out of range: choose 0 to {n_modes - 1}.")
        new = replace(new, index=int(index), phase=0.0 if int(index) != state.index else new.phase)
    if amplitude is not None:
        if not 0.0 <= float(amplitude) <= MAX_AMPLITUDE:
            raise ValueError(f"Amplitude {amplitude!r} is out of range: choose 0 to {MAX_AMPLITUDE} "
                             "(a fraction of the structure's size).")
        new = replace(new, amplitude=float(amplitude))
    if speed is not None:
        if not 0.0 <= float(speed) <= MAX_SPEED:
            raise ValueError(f"Speed {speed!r} is out of range: choose 0 (frozen) to {MAX_SPEED} cycles per second.")
        new = replace(new, speed=float(speed))
    if phase_deg is not None:
        if not np.isfinite(float(phase_deg)):
            raise ValueError("Phase must be a finite number of degrees.")
        new = replace(new, phase=(float(phase_deg) / 360.0) % 1.0)
    if interpolate is not None:
        new = replace(new, interpolate=bool(interpolate))
    return new


class Registry(Recent):
    """Thread-safe map key -> Published (the FastAPI threads publish, viser's threads and the animator read)."""

    def __init__(self, capacity: int = 256):
        super().__init__(capacity)

    def publish(self, geometry: Geometry | None, frequency_hz, shapes, labels=None, key: str | None = None) -> str:
        psi = np.asarray(shapes, dtype=complex)
        geometry = scene.geometry_for(geometry, psi.shape[0] if psi.ndim else 0)
        f, psi = scene.check_modes(geometry, frequency_hz, psi)
        entry = Published(
            geometry=geometry, frequency_hz=f, shapes=psi, labels=scene.mode_labels(f, labels),
            node_vectors=[scene.node_modal_vectors(geometry, psi[:, j]) for j in range(f.size)],
            spline_vectors=[scene.node_modal_vectors(geometry, psi[:, j], interpolate=True) for j in range(f.size)],
        )
        # 128 bits; a given key: rebuilt from what another process published
        return self._put(key or secrets.token_urlsafe(16), entry)

    def get(self, key: str) -> Published | None:
        with self._lock:
            entry = self._items.get(key)
            if entry is not None:
                self._items.move_to_end(key)
            return entry

    def set_state(self, key: str, **changes) -> ViewState:
        """Apply user changes (index, amplitude, speed, phase_deg, interpolate); KeyError if unknown, ValueError."""
        with self._lock:
            entry = self._items[key]
            entry.state = updated_state(entry.state, entry.n_modes, **changes)
            entry.revision += 1
            return entry.state

    def follow(self, key: str, state: dict) -> None:
        """Take a view state chosen through another process (mode, amplitude, speed, interpolate; the phase runs on
        here); unknown keys are ignored."""
        with self._lock:
            entry = self._items.get(key)
            if entry is None:
                return
            changes = {k: state[k] for k in ("index", "amplitude", "speed", "interpolate") if k in state}
            if state.get("index") != entry.state.index:
                changes["phase"] = 0.0
            entry.state = replace(entry.state, **changes)
            entry.revision += 1

    def advance(self, key: str, dt_s: float) -> tuple[ViewState, int] | None:
        """Move the key's phase on by speed × dt (one animation tick); (state, revision), or None if the key is gone.

        Both come from one moment, so a client that follows `revision` never pairs it with an older state."""
        with self._lock:
            entry = self._items.get(key)
            if entry is None:
                return None
            s = entry.state
            if s.speed > 0:
                entry.state = replace(s, phase=(s.phase + s.speed * dt_s) % 1.0)
            return entry.state, entry.revision

    def __len__(self) -> int:
        with self._lock:
            return len(self._items)
