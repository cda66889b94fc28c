"""Where things are on the NASA Langley grid (Juang & Pappa 1985, Fig. 2): its 88 joints at whole feet, its 157
one-foot segments (the members), the nine sensors, the air jet and the two cables, and the joint and segment indices
the grid model (era/examples/grid.py) and its effects use. x runs along the bars (0..10 ft), y up from the bottom
bar (0..7 ft)."""

from __future__ import annotations

import numpy as np

from ..errors import EraError

FT = 0.3048  # m
NX, NY = 11, 8
SENSORS_FT = np.array([(0, 0), (4, 0), (9, 1), (1, 3), (6, 4), (10, 3), (2, 7), (5, 6), (8, 7)], float)
AIR_JET_FT = (10.0, 0.0)
CABLES_FT = ((2.0, 7.0), (8.0, 7.0))


# 157 one-foot segments: 80 horizontal (row by row from the bottom, left to right), then 77 vertical
# (column by column from the left, bottom to top). Joint index = iy * 11 + ix.
_H = [(iy * NX + ix, iy * NX + ix + 1) for iy in range(NY) for ix in range(NX - 1)]
_V = [(iy * NX + ix, (iy + 1) * NX + ix) for ix in range(NX) for iy in range(NY - 1)]
SEGMENT_JOINTS = np.array(_H + _V, int)
N_SEGMENTS = len(SEGMENT_JOINTS)
N_HORIZONTAL = len(_H)
JOINTS_FT = np.array([(ix, iy) for iy in range(NY) for ix in range(NX)], float)


def joint_index(at) -> int:
    """Index 0..87 of the joint at (x_ft, y_ft); integer feet only."""
    try:
        x, y = (float(v) for v in at)
    except (TypeError, ValueError):
        raise EraError(f"A joint location must be (x_ft, y_ft), got {at!r}.") from None
    if not (x.is_integer() and y.is_integer() and 0 <= x < NX and 0 <= y < NY):
        raise EraError(f"({x:g}, {y:g}) ft is not a joint of the grid: joints sit at whole feet, "
                       f"x in 0..{NX - 1}, y in 0..{NY - 1}.")
    return int(y) * NX + int(x)


def segment_index(member) -> int:
    """Index 0..156 (SEGMENT_JOINTS order) of the 1-ft segment between two neighbouring joints
    ((x1, y1), (x2, y2)) in ft, either way round."""
    try:
        a, b = (joint_index(j) for j in member)
    except (TypeError, ValueError):
        raise EraError(f"A member must be its two joints ((x1, y1), (x2, y2)) in ft, got {member!r}.") from None
    hit = np.flatnonzero(((SEGMENT_JOINTS[:, 0] == a) & (SEGMENT_JOINTS[:, 1] == b))
                         | ((SEGMENT_JOINTS[:, 0] == b) & (SEGMENT_JOINTS[:, 1] == a)))
    if hit.size == 0:
        raise EraError(f"{member!r} is not a member of the grid: its two joints must be 1 ft apart along a bar.")
    return int(hit[0])


MEMBERS_FT = tuple((tuple(JOINTS_FT[i].tolist()), tuple(JOINTS_FT[j].tolist())) for i, j in SEGMENT_JOINTS.tolist())
"""The 157 members ((x1, y1), (x2, y2)) ft, in SEGMENT_JOINTS order: the places of member_stiffness."""
