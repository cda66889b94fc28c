"""UFF coordinate systems (data sets 18 and 2420) applied to node coordinates and measurement directions.

A node (UFF 15/2411) gives its coordinates in its *definition* system and its measurement directions (the ±X/Y/Z
codes of a 58 record) in its *displacement* system. Test software writes one displacement system per node when a
sensor sits skewed (Simcenter Testlab writes one per node, data set 18). Here both become global:

- UFF 18 (method 1): a system by its origin, a point on its x axis and a point in its xz plane, in a reference
  system (0 = global; references are followed);
- UFF 2420: rows 1-3 of the transformation matrix are the system's x, y, z axes in global coordinates, row 4 its
  origin;
- Cartesian and cylindrical (r, θ in degrees, z) systems; label 0, and label 1 when no data set defines it, are
  the global system. Spherical systems and undefined labels are refused, naming the node.
"""

from __future__ import annotations

import numpy as np

from ..errors import DataError


class System:
    """One coordinate system: kind 0 Cartesian, 1 cylindrical, 2 spherical; axes (3, 3), rows = local x, y, z in
    global coordinates; origin (3,) global."""

    def __init__(self, kind: int, axes: np.ndarray, origin: np.ndarray):
        self.kind, self.axes, self.origin = int(kind), np.asarray(axes, float), np.asarray(origin, float)

    def point(self, local: np.ndarray) -> np.ndarray:
        """Global coordinates of a point given in this system (cylindrical: r, θ in degrees, z)."""
        if self.kind == 1:
            r, theta, z = local
            local = np.array([r * np.cos(np.radians(theta)), r * np.sin(np.radians(theta)), z])
        return self.origin + local @ self.axes

    def frame(self, point: np.ndarray) -> np.ndarray:
        """(3, 3) the directions of this system's 1, 2, 3 (X, Y, Z or r, θ, z) at a global point, as rows."""
        if self.kind != 1:
            return self.axes
        rel = (point - self.origin) @ self.axes.T  # local Cartesian
        theta = np.arctan2(rel[1], rel[0])
        radial = np.array([np.cos(theta), np.sin(theta), 0.0])
        tangential = np.array([-np.sin(theta), np.cos(theta), 0.0])
        return np.stack([radial, tangential, [0.0, 0.0, 1.0]]) @ self.axes


GLOBAL = System(0, np.eye(3), np.zeros(3))


def _unit(v: np.ndarray, where: str) -> np.ndarray:
    n = float(np.linalg.norm(v))
    if not np.isfinite(n) or n < 1e-12:
        raise DataError(f"{where}: its defining points coincide or lie on one line; the system has no axes.")
    return v / n


def systems(sets, label: str) -> dict[int, System]:
    """The coordinate systems of data sets 18 and 2420 by label."""
    out: dict[int, System] = {}
    pending = []
    for i, line, d in sets:
        if d.get("type") == 2420:
            matrices = list(d.get("CS_matrices", []))
            for lab, kind, m in zip(d.get("CS_sys_labels", []), d.get("CS_types", []), matrices):
                m = np.asarray(m, dtype=float)
                where = f"{label}: data set #{i + 1} (UFF 2420, line {line}), system {int(lab)}"
                if m.shape != (4, 3) or not np.all(np.isfinite(m)):
                    raise DataError(f"{where}: a transformation matrix of shape {m.shape}; expected 4 rows of 3.")
                out[int(lab)] = System(int(kind), m[:3], m[3])
        elif d.get("type") == 18:
            for k, lab in enumerate(np.asarray(d.get("cs_num", []), dtype=int)):
                pending.append((i, line, int(lab), int(d["cs_type"][k]), int(d["ref_cs_num"][k]),
                                np.asarray(d["ref_o"][k], float), np.asarray(d["x_point"][k], float),
                                np.asarray(d["xz_point"][k], float)))
    for _ in range(len(pending) + 1):  # references may point forwards: resolve until nothing changes
        left = []
        for i, line, lab, kind, ref, o, x, xz in pending:
            if ref != 0 and ref not in out:
                left.append((i, line, lab, kind, ref, o, x, xz))
                continue
            where = f"{label}: data set #{i + 1} (UFF 18, line {line}), system {lab}"
            base = out.get(ref, GLOBAL)
            o_g, x_g, xz_g = base.point(o), base.point(x), base.point(xz)
            ex = _unit(x_g - o_g, where)
            v = xz_g - o_g
            ez = _unit(v - (v @ ex) * ex, where)
            out[lab] = System(kind, np.stack([ex, np.cross(ez, ex), ez]), o_g)
        if len(left) == len(pending):
            break
        pending = left
    if pending:
        i, line, lab, _, ref, *_ = pending[0]
        raise DataError(f"{label}: data set #{i + 1} (UFF 18, line {line}) defines system {lab} in system {ref}, "
                        "which the file does not define (or the references form a loop).")
    return out


def lookup(table: dict[int, System], cs: int, node: int, label: str, what: str) -> System:
    if cs == 0 or (cs == 1 and 1 not in table):
        return GLOBAL
    if cs not in table:
        raise DataError(f"{label}: node {node} gives its {what} in coordinate system {cs}, which no data set 18 or "
                        "2420 of the file defines. Export the file with its coordinate systems.")
    if table[cs].kind == 2:
        raise DataError(f"{label}: node {node} uses spherical coordinate system {cs}; only Cartesian and "
                        "cylindrical systems are read. Export the geometry in Cartesian coordinates.")
    return table[cs]


def nodes_to_global(ids, xyz, def_cs, disp_cs, table, label: str) -> tuple[np.ndarray, np.ndarray, bool]:
    """(global coordinates (n, 3), each node's measurement axes (n, 3, 3) as rows, whether anything changed)."""
    xyz = np.array(xyz, dtype=float)
    frames = np.tile(np.eye(3), (len(ids), 1, 1))
    changed = False
    for k, node in enumerate(ids):
        dc, pc = int(def_cs[k]), int(disp_cs[k])
        if dc or pc:
            system = lookup(table, dc, int(node), label, "coordinates")
            if system is not GLOBAL:
                xyz[k] = system.point(xyz[k])
                changed = True
            frame = lookup(table, pc, int(node), label, "measurement directions")
            if frame is not GLOBAL:
                frames[k] = frame.frame(xyz[k])
                changed = True
    return xyz, frames, changed
