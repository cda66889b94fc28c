"""Identified modes out as UFF: nodes (15), trace lines (82) and one complex-mode data set (55) per mode."""

from __future__ import annotations

import os
import re
import shutil
import tempfile

import numpy as np
import pyuff

from ..errors import DataError
from ..core.geometry import Geometry


def node_shapes(shapes: np.ndarray, geometry: Geometry | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(node_ids (n,), coordinates (n, 3), displacements (n, 3, modes) complex) for p-channel shapes (p, modes).

    With a geometry, each channel's value is added along its direction at its node (x, y, z sensors of one node
    combine). Without one, channel i is node i + 1 on the x axis, moving in z.
    """
    p, n_modes = shapes.shape
    if geometry is None:
        ids = np.arange(1, p + 1)
        xyz = np.column_stack([np.arange(p, dtype=float), np.zeros(p), np.zeros(p)])
        disp = np.zeros((p, 3, n_modes), complex)
        disp[:, 2, :] = shapes
        return ids, xyz, disp
    if geometry.channel_nodes.size != p:
        raise DataError(f"The geometry places {geometry.channel_nodes.size} channels but the model has {p} outputs; "
                        "use the geometry loaded with the same data.")
    known = geometry.channel_nodes >= 0
    if not known.any():
        raise DataError("No output channel of the geometry is placed on a node; shapes cannot be written at nodes.")
    disp = np.zeros((geometry.n_nodes, 3, n_modes), complex)
    np.add.at(disp, geometry.channel_nodes[known],
              geometry.channel_directions[known][:, :, None] * shapes[known][:, None, :])
    return geometry.node_ids, geometry.coordinates, disp


def written_shapes(model, geometry: Geometry | None) -> tuple[np.ndarray, Geometry | None]:
    """(shapes (q, modes) complex, geometry) to write: the model's ``point_shapes`` with a geometry whose channels
    are its ``points`` (era.core.points.point_geometry; "4X" is node 4 along X) when it has points beyond its outputs
    (a roving hammer's hit points) and the geometry places some of them, or there is no geometry (point k is then
    node k + 1); else its ``shapes`` with ``geometry``."""
    shapes = np.asarray(model.shapes, dtype=complex)
    points = tuple(getattr(model, "points", ()) or ())
    at_points = getattr(model, "point_shapes", None)
    if at_points is None or not points or points == tuple(getattr(model, "outputs", ()) or ()):
        return shapes, geometry
    at_points = np.asarray(at_points, dtype=complex)
    if geometry is None:
        return at_points, None
    from ..core.points import point_geometry
    placed = point_geometry(geometry, points)
    if (placed.channel_nodes >= 0).any():
        return at_points, placed
    return shapes, geometry


def _finite(values, k) -> float | None:
    if values is None:
        return None
    v = float(np.asarray(values, dtype=float)[k])
    return v if np.isfinite(v) else None


def _ascii(text: str) -> str:
    return text.replace("σ", "sigma").encode("ascii", "replace").decode("ascii")


def uncertainty_lines(f_std=None, d_std=None, shape_scatter=None, source: str = "") -> tuple[str, str]:
    """UFF 55 ID lines 3 and 4 (free text, 80 characters) of one mode: "std f 0.00123 Hz, std zeta 0.00045
    (95 %: +-1.96 std)" and "1-MAC 0.0021 (shape scatter), sigma from 8 records"; "NONE" where unknown."""
    id3 = "NONE" if f_std is None or d_std is None else f"std f {f_std:.4g} Hz, std zeta {d_std:.4g} (95 %: +-1.96 std)"
    id4 = "NONE" if shape_scatter is None else f"1-MAC {shape_scatter:.4g} (shape scatter)"
    if source and (id3 != "NONE" or id4 != "NONE"):
        id4 = (f"{id4}, " if id4 != "NONE" else "") + _ascii(source)
    return id3[:80], id4[:80]


def read_uncertainty_lines(id3: str, id4: str) -> dict:
    """The inverse of :func:`uncertainty_lines`: {"frequency_std_hz", "damping_std", "shape_scatter"} (float or
    None) and "source" ("" when absent) from a UFF 55 set's ID lines 3 and 4."""
    f3 = re.match(r"\s*std f (\S+) Hz, std zeta (\S+) ", id3 or "")
    f4 = re.match(r"\s*1-MAC (\S+) \(shape scatter\)", id4 or "")
    source = re.search(r"sigma from [^,]*$", (id4 or "").strip())
    return {"frequency_std_hz": float(f3.group(1)) if f3 else None, "damping_std": float(f3.group(2)) if f3 else None,
            "shape_scatter": float(f4.group(1)) if f4 else None, "source": source.group(0) if source else ""}


def complete_modes(shapes: np.ndarray) -> np.ndarray:
    """(modes,) bool: the columns of ``shapes`` (points, modes) known at every point (no NaN or inf). A mode of a
    multi-setup merge that a setup missed is NaN at that setup's points (era.merge_setups)."""
    return np.all(np.isfinite(np.asarray(shapes)), axis=0)


def save_modes_uff(path, model, geometry: Geometry | None = None, *, name: str = "ERA",
                   shape_scatter=None) -> tuple[int, ...]:
    """Write a ModalModel's modes as UFF 55 complex modes, with the nodes and trace lines of ``geometry``.

    The modes are analysis type 3, eigenvalue s in rad/s; the nodes are UFF 15 and the trace lines UFF 82.
    Only modes known at every point are written (:func:`complete_modes`; a UFF 55 set has a value at each of its
    nodes, and pyuff reads no NaN). Each written set keeps its mode's number in the model (``mode_n`` and ID line 1
    "ERA mode 4"), so a gap says which is missing.

    Parameters
    ----------
    path : str, os.PathLike or binary file object
        Where to write (a file object is written from its current position).
    model : ModalModel
        Its shapes (p, modes) as identified (largest component 1), or its point_shapes at every measured or struck
        point (:func:`written_shapes`) when it has points beyond its outputs. Its frequency_std_hz and damping_std
        (where finite) go to each set's ID line 3.
    geometry : Geometry, optional
        The nodes, trace lines and where each channel measures; without it the shapes are written at one node per
        channel.
    name : str, optional
        The label of every set's ID lines (default "ERA").
    shape_scatter : array_like, shape (modes,), optional
        Expected 1 - MAC of each shape (Identification.shape_scatter), written with the model's
        uncertainty_source to ID line 4 (:func:`uncertainty_lines`; :func:`read_uncertainty_lines` reads them
        back).

    Returns
    -------
    tuple of int
        The indices (0-based, in the model) of the modes left out.

    Raises
    ------
    era.DataError
        When the model has no modes or no mode is complete.

    Examples
    --------
    The paper's Case II (a repeated pair, two sensors) written at the two ends of a bar and read back:

    >>> import os, tempfile
    >>> from era.examples import paper_cases
    >>> model = era.identify(paper_cases.case_2(), 40, 40).realize(10)
    >>> bar = era.Geometry(node_ids=[1, 2], coordinates=[[0, 0, 0], [1, 0, 0]], edges=[[0, 1]],
    ...                    channel_nodes=[0, 1], channel_directions=[[0, 0, 1], [0, 0, 1]])
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "modes.uff")
    ...     left_out = era.save_modes_uff(path, model, bar, name="case 2")
    ...     modes = era.read_modes_uff(path)
    >>> left_out, modes.shapes.shape, modes.names[0]
    ((), (2, 3, 5), 'case 2 mode 1')
    """
    shapes, geometry = written_shapes(model, geometry)
    if shapes.ndim != 2 or shapes.shape[1] == 0:
        raise DataError("The model has no modes to write; realize a model (and select modes) first.")
    whole = complete_modes(shapes)
    if not whole.any():
        raise DataError(f"None of the {shapes.shape[1]} modes is known at every point (each was missed by a setup of "
                        "the test), so no UFF 55 set can be written; export them as CSV, where an unknown value is "
                        "an empty cell.")
    shapes = np.where(np.isfinite(shapes), shapes, 0)  # only the whole columns are written
    ids, xyz, disp = node_shapes(shapes, geometry)
    sets = [pyuff.prepare_15(node_nums=[int(i) for i in ids], def_cs=[0] * len(ids), disp_cs=[0] * len(ids),
                             color=[1] * len(ids), x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2])]
    if geometry is not None and geometry.edges.size:
        # one trace line per line of the geometry, under its number and name; segments of no known line last
        numbers = [int(n) for n in geometry.line_ids] + [int(geometry.line_ids.max(initial=0)) + 1]
        names = [n or "NONE" for n in geometry.line_names] + ["NONE"]
        for t in np.unique(geometry.edge_lines):
            seq = []
            for a, b in geometry.edges[geometry.edge_lines == t]:
                seq += [int(ids[a]), int(ids[b]), 0]
            # a plain dict: pyuff.prepare_82 insists on a list of nodes, its writer on an array
            sets.append({"type": 82, "trace_num": numbers[t], "n_nodes": len(seq), "color": 1, "id": names[t],
                         "nodes": np.asarray(seq, dtype=int)})
    f_std, d_std = getattr(model, "frequency_std_hz", None), getattr(model, "damping_std", None)
    source = getattr(model, "uncertainty_source", "") or ""
    for k, s in enumerate(np.asarray(model.eigenvalues, dtype=complex)):
        if not whole[k]:
            continue
        id3, id4 = uncertainty_lines(_finite(f_std, k), _finite(d_std, k), _finite(shape_scatter, k), source)
        sets.append(pyuff.prepare_55(
            id1=f"{name} mode {k + 1}", id2=f"{abs(s) / 2 / np.pi:.6g} Hz, zeta {-s.real / abs(s):.4g}",
            id3=id3, id4=id4, id5="NONE", model_type=1, analysis_type=3, data_ch=2, spec_data_type=8,
            data_type=5, n_data_per_node=3, r1=disp[:, 0, k], r2=disp[:, 1, k], r3=disp[:, 2, k],
            node_nums=[int(i) for i in ids], load_case=1, mode_n=k + 1, eig=complex(s), modal_a=0j, modal_b=0j))
    if hasattr(path, "write"):
        with tempfile.TemporaryDirectory() as tmp:
            tmp_path = os.path.join(tmp, "modes.uff")
            pyuff.UFF(tmp_path).write_sets(sets, mode="overwrite")
            with open(tmp_path, "rb") as fh:
                shutil.copyfileobj(fh, path)
    else:
        pyuff.UFF(os.fspath(path)).write_sets(sets, mode="overwrite")
    return tuple(int(k) for k in np.flatnonzero(~whole))
