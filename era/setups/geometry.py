"""Where a multi-setup test's points are: a table of points with coordinates and directions (and the lines between
them), as an engineer types it, turned into an era.Geometry whose channels are the merged model's points.

The table names each point as the merged model does (``model.points``: "ch5", "S2:ch3"), or as a setup's channel,
"S<k>:<channel name>" (k from 1), which works for the references in any setup as well. Points at the same
coordinates are one node (a triaxial sensor: three points, one node).

The coordinates may come from a UFF file's nodes (UFF 15, with its trace lines, UFF 82, read by era.load): the table
then reads ``point,node,direction`` and puts each point on a node of that file; the drawing keeps every node and
line of the file.
"""

from __future__ import annotations

import csv
import io
import re
from dataclasses import dataclass

import numpy as np

from ..errors import DataError
from ..core.geometry import Geometry

#: A direction as typed: an axis with an optional sign ("x", "-Z", "+y").
_AXIS = re.compile(r"^([+-]?)([xyz])$", re.IGNORECASE)
_UNIT = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


@dataclass(frozen=True)
class PointTable:
    """Points as typed: names (n,), coordinates (n, 3) in ``units``, directions (n, 3) unit vectors, and lines
    ((from, to) name pairs). With a UFF file's nodes (a table ``point,node,direction``): ``nodes`` (n,) the node id
    each point is on and ``base`` the file's era.Geometry (its nodes and lines)."""

    names: tuple
    coordinates: np.ndarray
    directions: np.ndarray
    lines: tuple
    units: str = "m"
    nodes: tuple = ()
    base: Geometry | None = None


def parse_points(text: str, units: str = "m", nodes: Geometry | None = None) -> PointTable:
    """A CSV ``point,x,y,z,direction`` (a header row, then one row per point; direction "x", "-z" or three numbers
    "dx dy dz"), optionally followed by ``from,to`` rows (a header row ``from,to``, then one line per row).

    nodes : an era.Geometry of a UFF file's nodes (``era.load(uff).geometry``): the table may then read
        ``point,node,direction``, each point on a node id of that file (its coordinates, in the file's units).

    Raises era.DataError naming the row that is wrong and what a right one looks like."""
    rows = [r for r in csv.reader(io.StringIO(text)) if r and any(c.strip() for c in r)]
    rows = [[c.strip() for c in r] for r in rows]
    if rows and [c.lower() for c in rows[0][:3]] == ["point", "node", "direction"]:
        return _on_nodes(rows, nodes)
    example = "a header point,x,y,z,direction then rows such as P1,0,0,3.5,x"
    if not rows or [c.lower() for c in rows[0][:5]] != ["point", "x", "y", "z", "direction"]:
        raise DataError(f"The points table must start with the header point,x,y,z,direction ({example}), or "
                        "point,node,direction with a UFF file of the nodes (UFF 15).")
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
    _check_names(names, lines, example)
    return PointTable(tuple(names), np.array(xyz, float), np.array(dirs, float), tuple(lines), units)


def _check_names(names, lines, example: str) -> None:
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


def _on_nodes(rows, base: Geometry | None) -> PointTable:
    """A table ``point,node,direction`` (then optional ``from,to`` rows) on the nodes of ``base``."""
    example = "a header point,node,direction then rows such as P1,12,x"
    if base is None or base.node_ids.size == 0:
        raise DataError("The points table names nodes (point,node,direction): give the UFF file that defines them "
                        "(UFF 15 nodes, with its trace lines), or give coordinates (point,x,y,z,direction).")
    row_of = {int(n): i for i, n in enumerate(base.node_ids)}
    names, on, dirs, lines = [], [], [], []
    in_lines = False
    for n, r in enumerate(rows[1:], start=2):
        if [c.lower() for c in r[:2]] == ["from", "to"]:
            in_lines = True
        elif in_lines:
            if len(r) < 2:
                raise DataError(f"Row {n} of the points table: a line is two point names, from,to; got {r}.")
            lines.append((r[0], r[1]))
        elif len(r) < 3:
            raise DataError(f"Row {n} of the points table has {len(r)} values; {example}.")
        else:
            try:
                node = int(r[1])
            except ValueError:
                raise DataError(f"Row {n} of the points table: the node is a node number of the UFF file; got "
                                f"{r[1]!r}.") from None
            if node not in row_of:
                shown = ", ".join(str(int(x)) for x in base.node_ids[:8])
                raise DataError(f"Row {n} of the points table: node {node} is not in the UFF file (its nodes: "
                                f"{shown}{' …' if base.node_ids.size > 8 else ''}).")
            names.append(r[0])
            on.append(node)
            dirs.append(_direction(r[2:], n))
    _check_names(names, lines, example)
    xyz = base.coordinates[[row_of[x] for x in on]]
    return PointTable(tuple(names), xyz, np.array(dirs, float), tuple(lines), base.units, tuple(on), base)


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
    if table.base is not None:
        return _on_base(table, row_of, len(aliases))
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


def _on_base(table: PointTable, row_of: dict, n_points: int) -> Geometry:
    """The points of a ``point,node,direction`` table on its UFF file's geometry: every node and trace line of the
    file, the table's own lines added."""
    base = table.base
    node_row = {int(n): i for i, n in enumerate(base.node_ids)}
    at = {x: node_row[n] for x, n in zip(table.names, table.nodes)}
    edges = np.concatenate([base.edges.reshape(-1, 2), np.array([(at[a], at[b]) for a, b in table.lines],
                                                                 int).reshape(-1, 2)]).astype(int)
    channel_nodes = np.full(n_points, -1)
    directions = np.zeros((n_points, 3))
    for i, x in enumerate(table.names):
        channel_nodes[row_of[x]] = at[x]
        directions[row_of[x]] = table.directions[i]
    edge_lines = None
    if base.edge_lines is not None:  # the table's own lines belong to no trace line of the file (-1)
        edge_lines = np.concatenate([np.asarray(base.edge_lines, int), np.full(len(table.lines), -1)])
    return Geometry(base.node_ids, base.coordinates, edges, channel_nodes, directions, units=base.units,
                    edge_lines=edge_lines, line_ids=base.line_ids, line_names=base.line_names)
