"""Where a multi-setup test's points are: a table of points with coordinates and directions (and the lines between
them), as an engineer types it, turned into an era.Geometry whose channels are the merged model's points.

The table names each point as the merged model does (``model.points``: "ch5", "S2:ch3"), or as a setup's channel,
"S<k>:<channel name>" (k from 1), which works for the references in any setup as well. Points at the same
coordinates are one node (a triaxial sensor: three points, one node).
"""

from __future__ import annotations

import csv
import io
import re
from dataclasses import dataclass

import numpy as np

from .errors import DataError
from .geometry import Geometry

#: A direction as typed: an axis with an optional sign ("x", "-Z", "+y").
_AXIS = re.compile(r"^([+-]?)([xyz])$", re.IGNORECASE)
_UNIT = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


@dataclass(frozen=True)
class PointTable:
    """Points as typed: names (n,), coordinates (n, 3) in ``units``, directions (n, 3) unit vectors, and lines
    ((from, to) name pairs)."""

    names: tuple
    coordinates: np.ndarray
    directions: np.ndarray
    lines: tuple
    units: str = "m"


def parse_points(text: str, units: str = "m") -> PointTable:
    """A CSV ``point,x,y,z,direction`` (a header row, then one row per point; direction "x", "-z" or three numbers
    "dx dy dz"), optionally followed by ``from,to`` rows (a header row ``from,to``, then one line per row).

    Raises era.DataError naming the row that is wrong and what a right one looks like."""
    rows = [r for r in csv.reader(io.StringIO(text)) if r and any(c.strip() for c in r)]
    rows = [[c.strip() for c in r] for r in rows]
    example = "a header point,x,y,z,direction then rows such as P1,0,0,3.5,x"
    if not rows or [c.lower() for c in rows[0][:5]] != ["point", "x", "y", "z", "direction"]:
        raise DataError(f"The points table must start with the header point,x,y,z,direction ({example}).")
    names, xyz, dirs, lines = [], [], [], []
    in_lines = False
    for n, r in enumerate(rows[1:], start=2):
        if [c.lower() for c in r[:2]] == ["from", "to"]:
            in_lines = True
            continue
        if in_lines:
            if len(r) < 2:
                raise DataError(f"Row {n} of the points table: a line is two point names, from,to; got {r}.")
            lines.append((r[0], r[1]))
            continue
        if len(r) < 5:
            raise DataError(f"Row {n} of the points table has {len(r)} values; {example}.")
        try:
            xyz.append([float(v) for v in r[1:4]])
        except ValueError:
            raise DataError(f"Row {n} of the points table: x, y, z must be numbers; got {r[1:4]}.") from None
        dirs.append(_direction(r[4:], n))
        names.append(r[0])
    if not names:
        raise DataError(f"The points table has no point ({example}).")
    if len(set(names)) != len(names):
        twice = next(x for x in names if names.count(x) > 1)
        raise DataError(f"Point {twice} is in the points table twice: give each point once.")
    known = set(names)
    for a, b in lines:
        for x in (a, b):
            if x not in known:
                raise DataError(f"The line {a}-{b} names point {x}, which the points table does not have.")
    return PointTable(tuple(names), np.array(xyz, float), np.array(dirs, float), tuple(lines), units)


def _direction(cells, n: int) -> list[float]:
    m = _AXIS.match(cells[0])
    if m:
        return [(-1.0 if m.group(1) == "-" else 1.0) * v for v in _UNIT[m.group(2).lower()]]
    parts = cells[0].split() if len(cells) == 1 else cells[:3]
    try:
        d = np.array([float(v) for v in parts], float)
    except ValueError:
        d = np.zeros(0)
    if d.shape != (3,) or not np.linalg.norm(d) > 0:
        raise DataError(f"Row {n} of the points table: the direction is an axis (x, -y, z) or three numbers "
                        f"\"dx dy dz\"; got {cells[0]!r}.")
    return list(d / np.linalg.norm(d))


def point_aliases(points, point_setup, point_channel, outputs, references) -> list[set]:
    """(q,) the names each merged point is known by: its label, "S<k>:<channel>" in its setup (a reference: in
    every setup). points : the merged labels; point_setup, point_channel : era.SetupMerge's; outputs : per setup,
    its channel names; references : per setup, the reference indices."""
    out = []
    for q, label in enumerate(points):
        names = {str(label)}
        k, ch = int(point_setup[q]), int(point_channel[q])
        if k >= 0:
            names.add(f"S{k + 1}:{outputs[k][ch]}")
        else:
            r = list(references[0]).index(ch)
            names.update(f"S{j + 1}:{outputs[j][refs[r]]}" for j, refs in enumerate(references))
        out.append(names)
    return out


def points_geometry(table: PointTable, aliases: list) -> Geometry:
    """An era.Geometry of the table's points (one node per distinct position, numbered from 1 in the table's
    order; its lines as edges) whose channels are the merged points (``aliases``, :func:`point_aliases`).

    Raises era.DataError when a merged point is not in the table (naming the points missing, and what they may be
    called), or a table point is no merged point."""
    row_of = {}
    for q, names in enumerate(aliases):
        for x in names:
            row_of[x] = q
    unknown = [x for x in table.names if x not in row_of]
    if unknown:
        what = "which is not a point" if len(unknown) == 1 else "which are not points"
        raise DataError(f"The points table names {', '.join(unknown[:5])}, {what} of this test: name "
                        "each point as the merged modes do, or as S<setup>:<channel> (e.g. S2:ch3).")
    placed = {row_of[x] for x in table.names}
    missing = [min(aliases[q]) for q in range(len(aliases)) if q not in placed]
    if missing:
        raise DataError(f"The points table has no row for {', '.join(missing[:6])}"
                        f"{' …' if len(missing) > 6 else ''}: give every point of the test its coordinates and "
                        "direction.")
    keys = [tuple(np.round(c, 9)) for c in table.coordinates]
    node_of_key: dict = {}
    for key in keys:
        node_of_key.setdefault(key, len(node_of_key))
    nodes = np.array([node_of_key[key] for key in keys])
    coordinates = np.array(list(node_of_key), float).reshape(-1, 3)
    index = {x: i for i, x in enumerate(table.names)}
    edges = np.array([(nodes[index[a]], nodes[index[b]]) for a, b in table.lines], int).reshape(-1, 2)
    channel_nodes = np.full(len(aliases), -1)
    directions = np.zeros((len(aliases), 3))
    for i, x in enumerate(table.names):
        channel_nodes[row_of[x]] = nodes[i]
        directions[row_of[x]] = table.directions[i]
    return Geometry(np.arange(1, coordinates.shape[0] + 1), coordinates, edges, channel_nodes, directions,
                    units=table.units)
