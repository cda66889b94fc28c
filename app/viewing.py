"""What the viewer shows for an analysis, built from stored results: the modes of one order, or an explanation's
expanded shapes. The routes publish with these; any other app process rebuilds a key's scene with them from what
the store says the key shows (``resolver``), and the keys' view states are shared through the store
(``SharedStates``), so a browser session may alternate between processes behind one address."""

from __future__ import annotations

import numpy as np

import era
from era.core import point_geometry

from .cache import Analysis, Cache
from .errors import NotFound
from .viewer.scene import SurfaceGeometry


def modes_scene(a: Analysis, model: era.ModalModel) -> tuple:
    """(geometry, frequency_hz (k,), shapes (q, k) complex, labels) of the modes of one order: the shape at every
    measured or struck point (ModalModel.point_shapes) when the geometry places those points or there is
    no geometry (the points then in a row), else at the sensors."""
    labels = [f"{f:.3f} Hz, ζ {100 * z:.2f} %" for f, z in zip(model.frequency_hz, model.damping_ratio)]
    if tuple(model.points) != tuple(model.outputs):
        if a.geometry is None:  # the points in a row (app.viewer.scene.geometry_for)
            return None, model.frequency_hz, model.point_shapes, labels
        placed = point_geometry(a.geometry, model.points)
        if (placed.channel_nodes >= 0).any():
            return placed, model.frequency_hz, model.point_shapes, labels
    return a.geometry, model.frequency_hz, model.shapes, labels


def explain_scene(summary: dict, which: str) -> tuple:
    """(geometry of every grid joint or frame node, frequency_hz, shapes (rows, k), labels) of an explanation's
    measured shapes expanded by SEREP (``which`` = "measured") or the updated model's ("model")."""
    if summary.get("fe_model") and not summary.get("mesh"):
        raise era.DataError("This FE model has no node coordinates, so the 3-D viewer cannot draw it: add "
                            "coordinates.csv (node,x,y,z) to the matrices' zip, or compare the shapes by the MAC.")
    shapes = np.asarray(summary["expanded_measured" if which == "measured" else "expanded_model"], dtype=float)
    f = np.asarray(summary["measured_hz"] if which == "measured" else
                   [r["updated_hz"] or 0.0 for r in summary["modes"]], dtype=float)
    drawn = summary.get("mesh") or summary.get("frame")     # an FE model's mesh, a frame, else the grid
    every_joint = _frame_geometry(drawn) if drawn else _grid_geometry()
    n = len(drawn["node_labels"]) if drawn else every_joint.channel_nodes.size
    if shapes.shape[0] != n:
        raise era.DataError(f"The stored shapes have {shapes.shape[0]} rows, the structure {n} node translations.")
    # the mesh's nodes without a row (an FE model's held nodes) carry a channel each that stays at zero
    shapes = np.vstack([shapes, np.zeros((every_joint.channel_nodes.size - n, shapes.shape[1]))])
    paired = [which == "measured" or r["updated_hz"] is not None for r in summary["modes"]]
    labels = [f"mode {k + 1}: {'measured (SEREP)' if which == 'measured' else 'updated model'} {fk:.3f} Hz"
              if ok else f"mode {k + 1}: no model partner" for k, (fk, ok) in enumerate(zip(f, paired))]
    return every_joint, f, shapes.astype(complex), labels


def _grid_geometry() -> era.Geometry:
    """The grid with every joint a channel (w along +z), so the viewer moves the whole grid."""
    from era.examples.grid import nasa_grid

    grid = nasa_grid().geometry()
    n = grid.coordinates.shape[0]
    return era.Geometry(node_ids=grid.node_ids, coordinates=grid.coordinates, edges=grid.edges,
                        channel_nodes=np.arange(n), channel_directions=np.tile([0.0, 0.0, 1.0], (n, 1)),
                        units=grid.units)


def _frame_geometry(frame: dict) -> era.Geometry:
    """A frame's nodes (m) and members (an FE model's mesh: also its shells' faces, scene.SurfaceGeometry), with a
    channel per row of its expanded shapes ("node:x", ...), then one (z, held at zero by explain_scene) per node
    that has no row, so the viewer keeps it still rather than moving it by the spline through the others."""
    ids = list(frame["nodes"])
    index = {n: k for k, n in enumerate(ids)}
    rows = [label.rsplit(":", 1) for label in frame["node_labels"]]
    moving = {n for n, _ in rows}
    rows += [(n, "z") for n in ids if n not in moving]
    common = dict(node_ids=np.arange(1, len(ids) + 1), coordinates=[frame["nodes"][n] for n in ids],
                  edges=[[index[i], index[j]] for i, j in frame["members"]],
                  channel_nodes=[index[n] for n, _ in rows],
                  channel_directions=[np.eye(3)["xyz".index(a)] for _, a in rows], units="m")
    if frame.get("faces"):
        return SurfaceGeometry(**common, faces=[[index[n] for n in f] for f in frame["faces"]])
    return era.Geometry(**common)


def resolver(cache: Cache):
    """key -> the scene of a key published by any process (from the store), or None for an unknown key."""
    def resolve(key: str):
        found = cache.store.viewer_key(key)
        if found is None:
            return None
        analysis_id, spec = found
        try:
            a = cache.analysis(analysis_id)
        except NotFound:  # expired meanwhile
            return None
        if spec["kind"] == "modes":
            return modes_scene(a, cache.model(a, int(spec["order"])))
        summary = cache.store.explanation(analysis_id)
        return None if summary is None else explain_scene(summary, spec["which"])
    return resolve


class SharedStates:
    """The viewer keys' view states in the store (what ModeViewer.states expects)."""

    def __init__(self, store):
        self.store = store

    def save(self, key: str, state: dict) -> None:
        self.store.set_viewer_state(key, state)

    def load(self, keys) -> dict:
        return self.store.viewer_states(keys)
