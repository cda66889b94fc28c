"""Rectangular coordinate frames (CORD2R, also defined in one another) and the basic positions of grids."""

from __future__ import annotations

import numpy as np

from ...errors import DataError


def frame_axes(frames: dict) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """{frame id: (origin (3,), axes (3, 3))} in basic for every CORD2R of ``frames`` ({id: CoordCard}) and
    frame 0 (basic); axes' columns are the frame's unit x, y, z, so a point p of the frame is origin + axes @ p.

    Raises DataError (naming the card) when a frame refers to a missing frame, to itself through others, or its
    three points do not span a frame."""
    out = {0: (np.zeros(3), np.eye(3))}

    def resolve(cid: int, trail: tuple) -> tuple[np.ndarray, np.ndarray]:
        if cid in out:
            return out[cid]
        f = frames[cid]
        if f.rid in trail:
            raise f.card.error(f"the frames refer to each other in a circle ({' -> '.join(map(str, trail))})")
        if f.rid not in frames and f.rid != 0:
            raise f.card.error(f"its reference frame RID {f.rid} is not a CORD2R of the deck")
        o, r = resolve(f.rid, trail + (cid,))
        a, b, c = (o + r @ p for p in (f.a, f.b, f.c))
        z = b - a
        y = np.cross(z, c - a)
        if np.linalg.norm(z) < 1e-12 * (1 + np.linalg.norm(a)) or np.linalg.norm(y) < 1e-12 * (
                1 + np.linalg.norm(z) ** 2):
            raise f.card.error("its points A, B and C do not define a frame (A = B, or C on the z axis)")
        z /= np.linalg.norm(z)
        y /= np.linalg.norm(y)
        out[cid] = (a, np.column_stack([np.cross(y, z), y, z]))
        return out[cid]

    for cid in frames:
        resolve(cid, ())
    return out


def basic_positions(grids: dict, axes: dict) -> dict[int, np.ndarray]:
    """{grid id: position (3,) in basic} from each GRID's CP frame."""
    out = {}
    for gid, g in grids.items():
        if g.cp not in axes:
            raise g.card.error(f"its frame CP {g.cp} is not a CORD2R of the deck (cylindrical and spherical "
                               "frames are not read); give the coordinates in basic or in a CORD2R")
        o, r = axes[g.cp]
        out[gid] = o + r @ g.xyz
    return out


def displacement_axes(grids: dict, axes: dict) -> dict[int, np.ndarray]:
    """{grid id: axes (3, 3)} of each grid's displacement frame (CD) in basic, for grids whose CD is not basic."""
    out = {}
    for gid, g in grids.items():
        if g.cd == 0:
            continue
        if g.cd not in axes:
            raise g.card.error(f"its displacement frame CD {g.cd} is not a CORD2R of the deck")
        out[gid] = axes[g.cd][1]
    return out


def require(table: dict, key: int, what: str, card) -> object:
    """table[key], or DataError naming ``card`` when the deck has no such ``what`` (e.g. "GRID")."""
    if key not in table:
        raise DataError(f"{card.where()}: {what} {key} is not in the deck. Add it or correct the reference.")
    return table[key]
