"""The mode shape at every point that was measured or struck: ``ModalModel.points``, ``point_shapes``.

A test names where its channels are in ``ResponseData.meta`` (the readers fill it: the SignalCalc ``setup.csv``,
UFF 58 response and reference node/direction, NPZ arrays):

=======================  =====  ================================================================================
``output_points``        (p,)   a point label per output ("" unknown), e.g. "4X" (node 4, X axis)
``output_signs``         (p,)   +1 or -1: the channel reads the point's motion along +axis or -axis (default +1)
``input_points``         (m,)   a point label per input: where it was struck ("" unknown)
``input_signs``          (m,)   +1 or -1: the force along +axis or -axis (default +1)
=======================  =====  ================================================================================

Without ``input_points``, ``meta["input_locations"]`` (era's simulated tests) names the inputs' points: a frame's
(node, direction) as "node direction" (its sensors' labels), a grid joint (x_ft, y_ft) as "w(x,y) ft" (the grid's).
Without ``output_points`` the outputs' points are their labels.

Reciprocity. For a structure whose mass, damping and stiffness are symmetric (Maxwell-Betti), the residue of mode j
between output point i and input point k is ψ_i ψ_k / a_j, one complex constant a_j per mode and the same ψ on both
sides. ERA's factorisation gives the residue as c_ij b_jk (``shapes`` · ``amplitudes``), so the amplitudes row b_j
is ψ (at the inputs' points) times an unknown complex factor: the input-side shape. It is not conjugated: the
residue of the pole with Im z > 0 is ψ ψ^T / a, not ψ ψ^H / a (a conjugated copy belongs to the other member of the
pair). Sensor and force signs are undone (channel value × sign) before shapes are compared.

Scaling. The outputs' shapes are consistent with each other (one column of the residue matrix), and so are the
inputs' (one row). The complex factor between the two sides is found through the points that are both measured and
struck (driving points): the least-squares α minimising Σ |c_i - α b_i| over them. With no driving point, the side
with more points is kept alone (with one fixed sensor not at a hammer point, the sensor's own value cannot be
separated from the modal constant a_j, so the shape is the hammer points'). Each column is then scaled so that its
largest component is 1, like ``shapes``.
"""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np

#: A point label made of a node number and an axis ("4X", "12Z", "3RX"): see :func:`point_label`.
_NODE_AXIS = re.compile(r"^(-?\d+)(X|Y|Z|RX|RY|RZ)$")
_AXES = ("X", "Y", "Z")


def point_label(node: int, axis: str) -> str:
    """The label of a point on a node along an axis (X, Y, Z; RX, RY, RZ): "4X"."""
    return f"{int(node)}{axis.upper()}"


def axis_and_sign(direction) -> tuple[str, float]:
    """(axis, sign) of a direction vector (3,) along a global axis: (1, 0, 0) -> ("X", 1), (0, 0, -1) -> ("Z", -1).
    ("", 1) for a zero vector; an oblique one is named by its largest component."""
    d = np.asarray(direction, dtype=float).reshape(3)
    k = int(np.argmax(np.abs(d)))
    if d[k] == 0:
        return "", 1.0
    return _AXES[k], float(np.sign(d[k]))


def channel_points(meta: dict, side: str, labels: tuple) -> tuple[tuple, np.ndarray]:
    """(labels (n,), signs (n,)) of the points of one side ("output" or "input") of a test, "" where unknown."""
    meta = meta or {}
    n = len(labels)
    named = meta.get(f"{side}_points")
    if named is None and side == "input":
        where = meta.get("input_locations")
        named = None if where is None else tuple(_location_label(w) for w in where)
    if named is None:
        named = tuple(labels) if side == "output" else ("",) * n
    if side == "output" and len(named) == n:  # an output of unknown point is its own point
        named = tuple(str(x) or str(lab) for x, lab in zip(named, labels))
    signs = meta.get(f"{side}_signs")
    signs = np.ones(n) if signs is None else np.asarray(signs, dtype=float).reshape(-1)
    if len(named) != n or signs.size != n:
        return ("",) * n, np.ones(n)
    return tuple(str(x) for x in named), signs


def _location_label(where) -> str:
    """The point label of an ``input_locations`` entry: strings joined ("E x"), two numbers as the grid's joint."""
    if all(isinstance(v, str) for v in where):
        return " ".join(where)
    if len(where) == 2:
        return f"w({float(where[0]):g},{float(where[1]):g}) ft"
    return ""


def point_shapes(shapes: np.ndarray, amplitudes: np.ndarray, output_points, input_points, output_signs=None,
                 input_signs=None) -> tuple[tuple, np.ndarray]:
    """The mode shape at every measured or struck point (module docstring: reciprocity and scaling).

    Parameters
    ----------
    shapes : (p, modes) complex, the outputs' shapes; amplitudes : (modes, m) complex, the input-side participation
    output_points, input_points : (p,), (m,) point labels, "" unknown; output_signs, input_signs : (p,), (m,) ±1

    Returns
    -------
    (points, values): the labels, each once (those of the side with more points first, in its order: a roving
    hammer's hit points; then the other side's not among them), and
    (n_points, modes) complex, largest component of each column 1. Without any known input point, the outputs'.
    """
    shapes = np.asarray(shapes, dtype=complex)
    amplitudes = np.asarray(amplitudes, dtype=complex)
    p, modes = shapes.shape
    m = amplitudes.shape[1]
    so = np.ones(p) if output_signs is None else np.asarray(output_signs, dtype=float)
    si = np.ones(m) if input_signs is None else np.asarray(input_signs, dtype=float)
    out_pts = [str(x) for x in output_points]
    in_pts = [str(x) for x in input_points]
    c = shapes * so[:, None]                       # the outputs' points' motion along +axis
    b = amplitudes.T * si[:, None]                 # (m, modes): the inputs' points, times a_j-dependent factors
    out_at = _first_of(out_pts)
    in_at = _first_of(in_pts)
    if not any(in_pts):
        return tuple(out_at), _unit_largest(c[list(out_at.values())])
    common = [pt for pt in out_at if pt and pt in in_at]
    if common:
        ci = np.array([c[out_at[pt]] for pt in common])   # (k, modes)
        bi = np.array([b[in_at[pt]] for pt in common])
        den = np.sum(np.abs(bi) ** 2, axis=0)
        alpha = np.where(den > 0, np.sum(np.conj(bi) * ci, axis=0) / np.where(den > 0, den, 1), 0)
        struck = [pt for pt in in_at if pt]
        value = {pt: alpha * b[in_at[pt]] for pt in struck} | {pt: c[out_at[pt]] for pt in out_at}
        # in the order of the side with more points (a roving hammer's hit points), the other side's after them
        first, then = (struck, list(out_at)) if len(struck) > len(out_at) else (list(out_at), struck)
        pts = first + [pt for pt in then if pt not in first]
        vals = [value[pt] for pt in pts]
    elif len([pt for pt in in_at if pt]) > len(out_at):
        pts = [pt for pt in in_at if pt]
        vals = [b[in_at[pt]] for pt in pts]
    else:
        return tuple(out_at), _unit_largest(c[list(out_at.values())])
    return tuple(pts), _unit_largest(np.array(vals).reshape(len(pts), modes))


def _first_of(labels) -> dict:
    """{label: first index} in order (a point measured twice is taken once, at its first channel)."""
    out = {}
    for k, lab in enumerate(labels):
        if lab not in out:
            out[lab] = k
    return out


def _unit_largest(values: np.ndarray) -> np.ndarray:
    if not values.size:
        return values
    big = values[np.argmax(np.abs(values), axis=0), np.arange(values.shape[1])]
    return values / np.where(np.abs(big) > 0, big, 1.0)


def with_points(model, meta: dict):
    """``model`` with its ``points`` and ``point_shapes`` from the channels' points named in ``meta`` (the
    ResponseData's): unchanged when no input's point is known."""
    out_pts, out_signs = channel_points(meta, "output", model.outputs)
    in_pts, in_signs = channel_points(meta, "input", model.inputs)
    if not any(in_pts) and not (meta or {}).get("output_points"):
        return model
    pts, vals = point_shapes(model.shapes, model.amplitudes, out_pts, in_pts, out_signs, in_signs)
    return replace(model, points=pts, point_shapes=vals)


def point_geometry(geometry, points):
    """A Geometry whose channels are ``points`` (labels "4X": node 4 of ``geometry``, the X axis): the nodes and
    lines of ``geometry``, each point at its node along +axis; -1 / zeros where the label names no node of it.
    None without a geometry."""
    if geometry is None:
        return None
    from .geometry import Geometry
    row = {int(n): k for k, n in enumerate(geometry.node_ids)}
    nodes, dirs = [], []
    for pt in points:
        hit = _NODE_AXIS.match(str(pt))
        k = row.get(int(hit.group(1)), -1) if hit else -1
        axis = hit.group(2) if hit else ""
        nodes.append(k if axis in _AXES else -1)
        dirs.append(np.eye(3)[_AXES.index(axis)] if k >= 0 and axis in _AXES else np.zeros(3))
    return Geometry(geometry.node_ids, geometry.coordinates, geometry.edges, np.array(nodes, dtype=int),
                    np.array(dirs).reshape(-1, 3), units=geometry.units, edge_lines=geometry.edge_lines,
                    line_ids=geometry.line_ids, line_names=geometry.line_names)
