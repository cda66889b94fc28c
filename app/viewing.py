"""What the viewer shows for an analysis, built from stored results: the modes of one order, or an explanation's
expanded shapes. The routes publish with these; any other app process rebuilds a key's scene with them from what
the store says the key shows (``resolver``), and the keys' view states are shared through the store
(``SharedStates``), so a browser session may alternate between processes behind one address."""

from __future__ import annotations

import numpy as np

import era

from .cache import Analysis, Cache
from .errors import NotFound


def modes_scene(a: Analysis, model: era.ModalModel) -> tuple:
    """(geometry, frequency_hz (k,), shapes (p, k) complex, labels) of the modes of one order."""
    labels = [f"{f:.3f} Hz, ζ {100 * z:.2f} %" for f, z in zip(model.frequency_hz, model.damping_ratio)]
    return a.geometry, model.frequency_hz, model.shapes, labels


def explain_scene(summary: dict, which: str) -> tuple:
    """(geometry of every grid joint, frequency_hz, shapes (joints, k), labels) of an explanation's measured shapes
    expanded by SEREP (``which`` = "measured") or the updated model's ("model")."""
    from era.examples.grid import nasa_grid

    shapes = np.asarray(summary["expanded_measured" if which == "measured" else "expanded_model"], dtype=float)
    f = np.asarray(summary["measured_hz"] if which == "measured" else
                   [r["updated_hz"] or 0.0 for r in summary["modes"]], dtype=float)
    grid = nasa_grid().geometry()
    n = grid.coordinates.shape[0]
    if shapes.shape[0] != n:
        raise era.DataError(f"The stored shapes have {shapes.shape[0]} joints, the grid {n}.")
    # every joint is a channel (w along +z), so the viewer moves the whole grid from the expanded shapes
    every_joint = era.Geometry(node_ids=grid.node_ids, coordinates=grid.coordinates, edges=grid.edges,
                               channel_nodes=np.arange(n), channel_directions=np.tile([0.0, 0.0, 1.0], (n, 1)),
                               units=grid.units)
    paired = [which == "measured" or r["updated_hz"] is not None for r in summary["modes"]]
    labels = [f"mode {k + 1}: {'measured (SEREP)' if which == 'measured' else 'updated model'} {fk:.3f} Hz"
              if ok else f"mode {k + 1}: no model partner" for k, (fk, ok) in enumerate(zip(f, paired))]
    return every_joint, f, shapes.astype(complex), labels


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
