"""The geometry of UFF files: nodes (15/2411) in global coordinates, trace lines (82), and each channel's
measurement direction turned from its node's displacement system into global X/Y/Z (era/io/uff_cs.py)."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import DataError
from ..core.geometry import Geometry
from .records import Records
from .uff_cs import systems, nodes_to_global


def unit_factors(sets, label: str) -> tuple[float, float]:
    """(length, force) factors of the file's UFF 164 units: a value in file units divided by length^e_L ·
    force^e_F is in SI (m, N). (1, 1) without a data set 164."""
    for i, line, d in sets:
        if d.get("type") == 164:
            factors = (float(d.get("length", 1.0)), float(d.get("force", 1.0)))
            if not all(np.isfinite(v) and v > 0 for v in factors):
                raise DataError(f"{label}: data set #{i + 1} (UFF 164, line {line}) gives unit factors {factors}; "
                                "they must be positive numbers (1 for SI).")
            return factors
    return 1.0, 1.0


def geometry_parts(sets, label: str):
    """(node ids (n,), global coordinates (n, 3), trace lines, measurement axes (n, 3, 3)) of one file, or None."""
    ids, xyz, traces, def_cs, disp_cs = [], [], [], [], []
    for i, line, d in sets:
        if d.get("type") in (15, 2411):
            ids.append(np.asarray(d["node_nums"], dtype=int).reshape(-1))
            cols = [np.asarray(d[k], dtype=float).reshape(-1) for k in "xyz"]
            if any(c.size != ids[-1].size for c in cols):
                raise DataError(f"{label}: data set #{i + 1} (UFF {d['type']}, line {line}) lists {ids[-1].size} nodes "
                                f"but {[c.size for c in cols]} x/y/z coordinates; it is truncated or corrupt.")
            xyz.append(np.stack(cols, axis=1))
            for key, into in (("def_cs", def_cs), ("disp_cs", disp_cs)):
                cs = np.asarray(d.get(key, np.zeros(ids[-1].size)), dtype=float).reshape(-1)
                into.append(cs if cs.size == ids[-1].size else np.zeros(ids[-1].size))
        elif d.get("type") == 82:
            traces.append((i, line, np.asarray(d["nodes"], dtype=int), int(d.get("trace_num", len(traces) + 1)),
                           str(d.get("id", "")).strip()))
    if not ids:
        return None
    ids = np.concatenate(ids)
    xyz, frames, _ = nodes_to_global(ids, np.concatenate(xyz), np.concatenate(def_cs).astype(int),
                               np.concatenate(disp_cs).astype(int), systems(sets, label), label)
    return ids, xyz / unit_factors(sets, label)[0], traces, frames  # coordinates in m


def build_geometry(parts, nodes, directions, label: str) -> Geometry | None:
    """Geometry from nodes, trace lines (node-label sequences, 0 = pen up) and each output's node label/direction."""
    if parts is None:
        return None
    ids, xyz, traces = parts[:3]
    row = {int(n): k for k, n in enumerate(ids)}
    edges, edge_lines = [], []
    for t, (i, line, seq, *_) in enumerate(traces):
        for a, b in zip(seq[:-1], seq[1:]):
            if a and b:
                if a not in row or b not in row:
                    raise DataError(f"{label}: trace line in data set #{i + 1} (UFF 82, line {line}) joins node "
                                    f"{a if a not in row else b}, which the file does not define.")
                edges.append((row[a], row[b]))
                edge_lines.append(t)
    if nodes is None:
        nodes, directions = np.zeros(0, int), np.zeros((0, 3))
    channel_rows = np.array([row.get(int(n), -1) for n in nodes], dtype=int)
    return Geometry(ids, xyz, np.array(edges, dtype=int).reshape(-1, 2), channel_rows, directions,
                    edge_lines=np.array(edge_lines, dtype=int), line_ids=[tr[3] for tr in traces],
                    line_names=[tr[4] for tr in traces])


def merge_parts(parts, labels):
    """The nodes and trace lines of several files as one geometry; a node defined twice must be at one place."""
    present = [(p, lab) for p, lab in zip(parts, labels) if p is not None]
    if len(present) <= 1:
        return present[0][0] if present else None
    where_of: dict[int, tuple[np.ndarray, str]] = {}
    ids, xyz, traces, frames = [], [], [], []
    for (i_, x_, t_, f_), lab in present:
        for node, point, frame in zip(i_, x_, f_):
            if int(node) in where_of:
                if not np.allclose(where_of[int(node)][0], point, rtol=1e-6, atol=1e-9):
                    raise DataError(f"{lab}: node {int(node)} at {point.tolist()} but {where_of[int(node)][1]} puts it "
                                    f"at {where_of[int(node)][0].tolist()}; the files must share one geometry.")
                continue
            where_of[int(node)] = (point, lab)
            ids.append(int(node))
            xyz.append(point)
            frames.append(frame)
        traces += [tr for tr in t_ if not any(np.array_equal(tr[2], seen[2]) for seen in traces)]
    return np.array(ids, dtype=int), np.array(xyz, dtype=float).reshape(-1, 3), traces, np.array(frames)


def in_global_directions(rec: Records, parts) -> Records:
    """``rec`` with each channel's direction (a ±X/Y/Z of its node's displacement system) in global X/Y/Z."""
    ids, _, _, frames = parts
    if np.allclose(frames, np.eye(3)):
        return rec
    row = {int(n): k for k, n in enumerate(ids)}
    directions = np.array([d @ frames[row[int(n)]] if int(n) in row else d for n, d in zip(rec.nodes, rec.directions)])
    return dataclasses.replace(rec, directions=directions, described=rec.described + [
        "measurement directions given in the nodes' own coordinate systems (UFF 18/2420) turned into global X/Y/Z"])


def modes_in_global(modes, parts):
    """``modes`` (a ModeSet, shapes (n, 3, k) in each node's displacement system) with the shapes in global X/Y/Z;
    the same rotation as :func:`in_global_directions` gives the channels."""
    if parts is None:
        return modes
    ids, _, _, frames = parts
    if np.allclose(frames, np.eye(3)):
        return modes
    row = {int(n): k for k, n in enumerate(ids)}
    local = np.stack([frames[row[int(n)]] if int(n) in row else np.eye(3) for n in modes.node_ids])
    return dataclasses.replace(modes, shapes=np.einsum("nak,nab->nbk", modes.shapes, local))
