"""Coordinate frames (CORD2R/C/S, CORD1R/C/S), the basic positions of grids and the axes of their DOFs.

A frame's coordinates of a point are (x, y, z) in a rectangular frame, (R, θ, z) in a cylindrical one and
(R, θ, φ) in a spherical one, angles in degrees (Nastran's convention: x = R cos θ, y = R sin θ; x = R sin θ cos φ,
y = R sin θ sin φ, z = R cos θ). A grid whose displacement frame CD is curvilinear has its DOFs along the frame's
local directions at the grid: cylindrical (radial, tangential θ, axial z), spherical (radial, meridian θ, azimuth
φ); on the polar axis (R sin θ = 0) the angle θ (cylindrical) or φ (spherical) is taken as 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import DataError

KINDS = {"R": "rectangular", "C": "cylindrical", "S": "spherical"}


@dataclass(frozen=True, eq=False)
class CoordFrame:
    """A frame resolved in basic: kind "R", "C" or "S", origin (3,) and axes (3, 3) whose columns are its
    rectangular unit x, y, z (the z axis of a cylindrical frame, the polar axis of a spherical one)."""

    kind: str
    origin: np.ndarray
    axes: np.ndarray

    def local(self, p) -> np.ndarray:
        """The rectangular local coordinates (3,) of a point given by the frame's coordinates ``p`` (3,)."""
        p = np.asarray(p, float)
        if self.kind == "C":
            t = np.radians(p[1])
            return np.array([p[0] * np.cos(t), p[0] * np.sin(t), p[2]])
        if self.kind == "S":
            t, f = np.radians(p[1]), np.radians(p[2])
            return p[0] * np.array([np.sin(t) * np.cos(f), np.sin(t) * np.sin(f), np.cos(t)])
        return p

    def to_basic(self, p) -> np.ndarray:
        """A point given by the frame's coordinates ``p`` (3,), in basic (3,)."""
        return self.origin + self.axes @ self.local(p)

    def directions(self, x) -> np.ndarray:
        """(3, 3) in basic, columns the frame's unit directions 1, 2, 3 at the basic point ``x`` (3,)."""
        if self.kind == "R":
            return self.axes
        q = self.axes.T @ (np.asarray(x, float) - self.origin)
        azimuth = np.arctan2(q[1], q[0]) if np.hypot(q[0], q[1]) > 1e-12 * (1 + np.linalg.norm(q)) else 0.0
        c, s = np.cos(azimuth), np.sin(azimuth)
        radial, around = np.array([c, s, 0.0]), np.array([-s, c, 0.0])
        if self.kind == "C":
            local = np.column_stack([radial, around, [0.0, 0.0, 1.0]])
        else:
            polar = np.arctan2(np.hypot(q[0], q[1]), q[2])
            st, ct = np.sin(polar), np.cos(polar)
            local = np.column_stack([st * radial + [0, 0, ct], ct * radial - [0, 0, st], around])
        return self.axes @ local


def _frame_from_points(a: np.ndarray, b: np.ndarray, c: np.ndarray, kind: str, card) -> CoordFrame:
    """The frame with origin a, z axis towards b and x-z plane through c (all in basic)."""
    z = b - a
    y = np.cross(z, c - a)
    if np.linalg.norm(z) < 1e-12 * (1 + np.linalg.norm(a)) or np.linalg.norm(y) < 1e-12 * (
            1 + np.linalg.norm(z) ** 2):
        raise card.error("its points A, B and C do not define a frame (A = B, or C on the z axis)")
    z = z / np.linalg.norm(z)
    y = y / np.linalg.norm(y)
    return CoordFrame(kind, a, np.column_stack([np.cross(y, z), y, z]))


class _Resolver:
    """Frames and grid positions resolved on demand: a CORD2 frame needs its reference frame, a CORD1 frame its
    three grids, a grid its CP frame; a circle among them is an error naming the cards."""

    def __init__(self, grids: dict, frames: dict):
        self.grids, self.frames = grids, frames
        self.resolved = {0: CoordFrame("R", np.zeros(3), np.eye(3))}
        self.positions: dict = {}

    def frame(self, cid: int, trail: tuple, card) -> CoordFrame:
        if cid in self.resolved:
            return self.resolved[cid]
        if cid not in self.frames:
            raise card.error(f"frame {cid} is not a coordinate frame (CORD1R/C/S, CORD2R/C/S) of the deck")
        f = self.frames[cid]
        if ("frame", cid) in trail:
            raise f.card.error("the frames and grids refer to each other in a circle "
                               f"({' -> '.join(f'{k} {i}' for k, i in trail + (('frame', cid),))})")
        trail += (("frame", cid),)
        if f.grids is not None:
            points = [self.position(g, trail, f.card) for g in f.grids]
        else:
            ref = self.frame(f.rid, trail, f.card)
            points = [ref.to_basic(p) for p in (f.a, f.b, f.c)]
        self.resolved[cid] = _frame_from_points(*points, f.kind, f.card)
        return self.resolved[cid]

    def position(self, gid: int, trail: tuple, card) -> np.ndarray:
        if gid in self.positions:
            return self.positions[gid]
        g = require(self.grids, gid, "GRID", card)
        if ("grid", gid) in trail:
            raise g.card.error("the frames and grids refer to each other in a circle")
        self.positions[gid] = self.frame(g.cp, trail + (("grid", gid),), g.card).to_basic(g.xyz)
        return self.positions[gid]


def resolve(grids: dict, frames: dict) -> tuple[dict[int, CoordFrame], dict[int, np.ndarray]]:
    """({frame id: CoordFrame}, {grid id: position (3,) in basic}) of every frame (0: basic) and grid of a deck
    (``frames`` {id: CoordCard}, ``grids`` {id: GridCard}).

    Raises DataError (naming the card) when a frame or grid refers to a missing frame or grid, to itself through
    others, or a frame's three points do not span a frame."""
    r = _Resolver(grids, frames)
    for cid in frames:
        r.frame(cid, (), frames[cid].card)
    for gid in grids:
        r.position(gid, (), grids[gid].card)
    return r.resolved, r.positions


def displacement_axes(grids: dict, frames: dict, positions: dict) -> dict[int, np.ndarray]:
    """{grid id: (3, 3)} the directions (columns, in basic) of each grid's DOFs 1-3 (and 4-6 about them), for the
    grids whose displacement frame CD is not basic; ``frames`` {id: CoordFrame}, ``positions`` {id: (3,) basic}."""
    out = {}
    for gid, g in grids.items():
        if g.cd == 0:
            continue
        if g.cd not in frames:
            raise g.card.error(f"its displacement frame CD {g.cd} is not a coordinate frame of the deck")
        out[gid] = frames[g.cd].directions(positions[gid])
    return out


def rectangular(frames: dict, cid: int, card) -> CoordFrame:
    """CoordFrame ``cid`` of ``frames`` ({id: CoordFrame}), which a card (CONM2, CBUSH) needs rectangular; DataError
    naming ``card`` when it is missing or curvilinear."""
    if cid not in frames:
        raise card.error(f"its frame CID {cid} is not a coordinate frame of the deck")
    if frames[cid].kind != "R":
        raise card.error(f"its frame CID {cid} is {KINDS[frames[cid].kind]}; give it in a rectangular frame "
                         "(CORD1R, CORD2R or basic)")
    return frames[cid]


def require(table: dict, key: int, what: str, card) -> object:
    """table[key], or DataError naming ``card`` when the deck has no such ``what`` (e.g. "GRID")."""
    if key not in table:
        raise DataError(f"{card.where()}: {what} {key} is not in the deck. Add it or correct the reference.")
    return table[key]
