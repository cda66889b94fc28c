"""Picking nodes in the viewer: a model being described, drawn in viser with one clickable sphere per node;
a click there is recorded under the scene's key, and the Model panel, which polls ``picks``, takes it as a click on
that node in its own drawing (a support or a mass, and the node's row selected).

viser 1.1.1 reports a click on a scene node to the server (``SceneNodeHandle.on_click``, with the clicked node's
handle as ``event.target``), so each node is its own icosphere named after its row and the callback knows the node
without any ray casting here. The page tells the view where to look (``look``: the camera turned to one node, e.g.
the row chosen in the table) and what each node is (``mark``: its colour).

Scenes and picks live in this process only (the app runs one viser server per process, one uvicorn worker).
"""

from __future__ import annotations

import secrets
from dataclasses import dataclass, field

import numpy as np

from era.errors import DataError
from era.words import listed

from .recent import Recent

#: Colour of a node by what it carries (RGB 0..255): free, fixed, pinned, springs, a lumped mass.
MARK_RGB = {"": (31, 95, 191), "fixed": (179, 38, 30), "pinned": (179, 38, 30), "springs": (200, 80, 160),
            "mass": (154, 103, 0)}
MEMBER_RGB = (120, 128, 140)
#: Largest model shown (nodes), and picks kept per key (the oldest dropped).
MAX_NODES = 2000
MAX_PICKS = 200
#: Sphere radius as a fraction of the structure's size (largest side of its bounding box).
NODE_RADIUS = 0.02


@dataclass
class PickScene:
    """A model to pick nodes in: ids (n,), coordinates (n, 3) m, members as (k, 2) rows, each node's mark, and the
    picks so far [(seq, node id)] (seq counts from 1)."""

    ids: list[str]
    coordinates: np.ndarray
    members: np.ndarray
    marks: dict[str, str]
    picks: list[tuple[int, str]] = field(default_factory=list)
    seq: int = 0

    @property
    def size(self) -> float:
        side = float(np.ptp(self.coordinates, axis=0).max()) if len(self.ids) else 0.0
        return side if side > 0 else 1.0

    def look_from(self, node: str | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(camera position, look_at) facing ``node`` from the three-quarter direction of scene.camera_pose, close
        enough that its sphere is a target; without a node, the whole structure from further away."""
        direction = np.array([0.45, -0.95, 0.75]) / np.linalg.norm([0.45, -0.95, 0.75])
        if node is None:
            centre = (self.coordinates.min(axis=0) + self.coordinates.max(axis=0)) / 2
            return centre + 1.25 * self.size * direction, centre
        at = self.coordinates[self.ids.index(node)]
        return at + 0.5 * self.size * direction, at


def pick_scene(nodes: dict, members: list, marks: dict | None = None) -> PickScene:
    """A PickScene from {node id: (x, y, z) m}, [(node i, node j), ...] and {node id: mark}; era.DataError when a
    coordinate is not a finite 3-vector, a member joins an unknown node, a mark is unknown, or there are more than
    MAX_NODES nodes."""
    if not isinstance(nodes, dict) or not nodes:
        raise DataError("The 3-D view needs the model's nodes: {node id: [x, y, z]} in m.")
    if len(nodes) > MAX_NODES:
        raise DataError(f"The 3-D view shows at most {MAX_NODES} nodes; this model has {len(nodes)}.")
    ids = [str(n) for n in nodes]
    try:
        xyz = np.array([[float(v) for v in nodes[n]] for n in nodes], dtype=float)
    except (TypeError, ValueError):
        xyz = np.full((1, 1), np.nan)
    if xyz.shape != (len(ids), 3) or not np.isfinite(xyz).all():
        raise DataError("Every node of the 3-D view needs three finite coordinates [x, y, z] in m.")
    row = {n: k for k, n in enumerate(ids)}
    pairs = []
    for m in members or []:
        if not isinstance(m, (list, tuple)) or len(m) < 2 or str(m[0]) not in row or str(m[1]) not in row:
            raise DataError(f"A member of the 3-D view, {m!r}, does not join two of its nodes.")
        pairs.append((row[str(m[0])], row[str(m[1])]))
    marks = {str(k): str(v) for k, v in (marks or {}).items()}
    unknown = sorted(set(marks.values()) - set(MARK_RGB))
    if unknown:
        raise DataError(f"Unknown node {'marks' if len(unknown) > 1 else 'mark'} {listed(unknown, quote=True)}; "
                        f"known: {listed(sorted(k for k in MARK_RGB if k), quote=True)}.")
    return PickScene(ids, xyz, np.array(pairs, dtype=int).reshape(-1, 2), marks)


class PickRegistry(Recent):
    """Thread-safe key -> PickScene (the routes publish and poll, viser's threads record clicks); the newest
    ``capacity`` keys are kept."""

    def __init__(self, capacity: int = 64):
        super().__init__(capacity)

    def publish(self, scene: PickScene) -> str:
        return self._put(secrets.token_urlsafe(16), scene)

    def get(self, key: str) -> PickScene | None:
        with self._lock:
            return self._items.get(key)

    def add_pick(self, key: str, node: str) -> None:
        with self._lock:
            s = self._items.get(key)
            if s is None:
                return
            s.seq += 1
            s.picks.append((s.seq, node))
            del s.picks[:-MAX_PICKS]

    def picks(self, key: str, after: int = 0) -> tuple[list[tuple[int, str]], int]:
        """(picks with seq > after, the last seq); KeyError for an unknown key."""
        with self._lock:
            s = self._items[key]
            return [p for p in s.picks if p[0] > after], s.seq

    def set_marks(self, key: str, marks: dict) -> PickScene:
        """Replace the nodes' marks (a mark for a node not shown is kept, unused); KeyError, era.DataError for an
        unknown mark."""
        with self._lock:
            s = self._items[key]
            marks = {str(k): str(v) for k, v in marks.items()}
            bad = sorted(set(marks.values()) - set(MARK_RGB))
            if bad:
                raise DataError(f"Unknown node mark {bad[0]!r}; known: {sorted(k for k in MARK_RGB if k)}.")
            s.marks = marks
            return s


def add_pick_nodes(target, s: PickScene, on_pick) -> dict:
    """Draw a PickScene into a viser scene (members as lines, one clickable icosphere per node, its id as a label);
    ``on_pick(node id)`` runs on a click. Returns {node id: sphere handle}."""
    if s.members.size:
        target.add_line_segments("/model/members", s.coordinates[s.members].astype(np.float32), MEMBER_RGB,
                                 thickness=3.0, thickness_units="screen")
    spheres = {}
    for n, xyz in zip(s.ids, s.coordinates):
        r = NODE_RADIUS * s.size
        h = target.add_icosphere(f"/model/nodes/{len(spheres)}", radius=r, color=MARK_RGB[s.marks.get(n, "")],
                                 subdivisions=2, position=tuple(float(v) for v in xyz))
        h.on_click(lambda event, n=n: on_pick(n))
        # above the sphere, so the label never covers what is clicked
        target.add_label(f"/model/labels/{len(spheres)}", n, anchor="bottom-center",
                         position=tuple(float(v) for v in xyz + (0.0, 0.0, 1.5 * r)))
        spheres[n] = h
    return spheres
