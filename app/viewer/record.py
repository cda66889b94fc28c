"""One cycle of a mode as a .viser recording, for read-only reports played back by viser's shipped client.

Each recording gets its own short-lived ViserServer on 127.0.0.1 (about 60 ms to start): the scene serializer records
a server's broadcast scene, so using the live server would flash the recording on every connected viewer, and a
throw-away server leaves no stale scene behind for the next recording.
"""

from __future__ import annotations

import base64
import contextlib
import io
import threading
from pathlib import Path

import numpy as np
import viser

from era.errors import DataError
from era import Geometry

from . import scene
from .registry import MAX_AMPLITUDE

_quiet_lock = threading.Lock()


@contextlib.contextmanager
def quiet():
    """viser prints a banner on start and a line on stop; keep them out of the app's log."""
    with _quiet_lock, contextlib.redirect_stdout(io.StringIO()):
        yield


def add_mode_nodes(target: viser.SceneApi, geometry: Geometry, first: scene.SceneFrame,
                   undeformed: scene.SceneFrame):
    """Add the surfaces (an FE model's shells, scene.SurfaceGeometry), the undeformed trace lines, the moving lines
    and the sensor points to a scene; return the handles that each frame updates: (lines, or None when the geometry
    has no trace lines; points; surface, or None without faces)."""
    size = scene.structure_size(geometry)
    faces = scene.faces_of(geometry)
    surface = None
    if faces.shape[0]:
        surface = target.add_mesh_simple("/mode/surface", first.positions.astype(np.float32),
                                         faces.astype(np.uint32), color=scene.SURFACE_RGB, side="double",
                                         opacity=0.75, cast_shadow=False, receive_shadow=False)
    lines = None
    if geometry.edges.shape[0]:
        target.add_line_segments("/undeformed", undeformed.segments, scene.UNDEFORMED_RGB,
                                 thickness=1.5, thickness_units="screen")
        lines = target.add_line_segments("/mode/lines", first.segments, first.segment_colours,
                                         thickness=4.0, thickness_units="screen")
    points = target.add_point_cloud("/mode/sensors", first.sensor_points, first.sensor_colours,
                                    point_size=0.025 * size, point_shape="circle", precision="float32")
    return lines, points, surface


def update_mode_nodes(lines, points, f: scene.SceneFrame, surface=None) -> None:
    """Move the handles from `add_mode_nodes` to frame `f` (call inside `atomic()` so a frame lands at once)."""
    if surface is not None:
        surface.vertices = f.positions.astype(np.float32)
    if lines is not None:
        lines.points = f.segments
        lines.colors = f.segment_colours
    points.points = f.sensor_points
    points.colors = f.sensor_colours


def record_mode(geometry: Geometry | None, frequency_hz, shapes, mode_index: int, frames: int = 30,
                amplitude: float = 0.15, period_s: float = 2.0, interpolate: bool = True) -> bytes:
    """One cycle of mode `mode_index` as .viser bytes (viser's scene serializer, zstd-compressed msgpack).

    Parameters
    ----------
    geometry : era.Geometry or None (None: `scene.default_geometry` of the p channels)
    frequency_hz : (modes,) damped frequencies in Hz (shown in the label)
    shapes : (p, modes) complex mode shapes
    mode_index : which column of `shapes` to record
    frames : frames per cycle (≥ 2); the playback loops the cycle
    amplitude : largest displacement as a fraction of the structure's size
    period_s : duration of the recorded cycle in seconds (playback speed can be changed in the player)
    interpolate : move unmeasured nodes with the spline through the sensors (scene.py), else they stay put
    """
    psi = np.asarray(shapes, dtype=complex)
    geometry = scene.geometry_for(geometry, psi.shape[0] if psi.ndim else 0)
    f, psi = scene.check_modes(geometry, frequency_hz, psi)
    if isinstance(mode_index, bool) or int(mode_index) != mode_index or not 0 <= int(mode_index) < f.size:
        raise DataError(f"Mode index {mode_index!r} is out of range: choose 0 to {f.size - 1}.")
    if int(frames) != frames or frames < 2:
        raise DataError(f"A recording needs at least 2 frames per cycle, got {frames!r}.")
    if not 0.0 <= amplitude <= MAX_AMPLITUDE or not period_s > 0:
        raise DataError(f"Amplitude must be in 0..{MAX_AMPLITUDE} and the period positive.")
    mode_index, frames = int(mode_index), int(frames)
    vectors = scene.node_modal_vectors(geometry, psi[:, mode_index], interpolate=interpolate)
    undeformed = scene.frame(geometry, vectors, 0.0, 0.0)
    with quiet():
        server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        position, look_at = scene.camera_pose(geometry, [vectors], amplitude)
        server.initial_camera.position = position
        server.initial_camera.look_at = look_at
        lines, points, surface = add_mode_nodes(server.scene, geometry,
                                                scene.frame(geometry, vectors, 0.0, amplitude), undeformed)
        top = geometry.coordinates[:, 2].max() + amplitude * scene.structure_size(geometry)
        server.scene.add_label("/title", f"Mode {mode_index + 1} · {f[mode_index]:.4g} Hz",
                               position=(look_at[0], look_at[1], top), anchor="bottom-center")
        note = scene.stand_in_note(geometry)
        if note is not None:  # as in the live viewer (live.py): a lone dot or a row of them is explained
            below = look_at - (0.0, 0.0, 0.3 * scene.structure_size(geometry))
            server.scene.add_label("/stand-in", note, position=tuple(below), anchor="top-center")
        serializer = server.get_scene_serializer()
        dt = period_s / frames
        for k in range(1, frames):
            serializer.insert_sleep(dt)
            with server.atomic():
                update_mode_nodes(lines, points, scene.frame(geometry, vectors, k / frames, amplitude), surface)
        serializer.insert_sleep(dt)
        return serializer.serialize()
    finally:
        with quiet():
            server.stop()


def standalone_html(recording: bytes) -> str:
    """A self-contained HTML page (viser's client, about 0.8 MB, with the recording inlined) that plays a .viser
    recording from `record_mode` with no server at all: for downloadable reports. Same injection as viser's
    `StateSerializer.as_html`, which needs the live serializer; this takes the stored bytes."""
    client = (Path(viser.__file__).resolve().parent / "client" / "build" / "index.html").read_text(encoding="utf-8")
    data = base64.b64encode(recording).decode("ascii")
    script = f'<script>window.__VISER_EMBED_DATA__="{data}";window.__VISER_EMBED_CONFIG__={{darkMode:false}};</script>'
    head_end = client.index("</head>")
    return client[:head_end] + script + client[head_end:]
