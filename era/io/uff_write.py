"""Identified modes out as UFF: nodes (15), trace lines (82) and one complex-mode data set (55) per mode."""

from __future__ import annotations

import os
import shutil
import tempfile

import numpy as np
import pyuff

from ..errors import DataError
from ..geometry import Geometry


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


def save_modes_uff(path, model, geometry: Geometry | None = None, *, name: str = "ERA") -> None:
    """Write a ModalModel's modes as UFF 55 complex modes (analysis type 3, eigenvalue s in rad/s), with the nodes
    (UFF 15) and trace lines (UFF 82) of ``geometry``.

    path : str, os.PathLike, or a binary file object (written from its current position).
    model : era.ModalModel; shapes (p, modes) as identified (largest component 1).
    """
    shapes = np.asarray(model.shapes, dtype=complex)
    if shapes.ndim != 2 or shapes.shape[1] == 0:
        raise DataError("The model has no modes to write; realize a model (and select modes) first.")
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
    for k, s in enumerate(np.asarray(model.eigenvalues, dtype=complex)):
        sets.append(pyuff.prepare_55(
            id1=f"{name} mode {k + 1}", id2=f"{abs(s) / 2 / np.pi:.6g} Hz, zeta {-s.real / abs(s):.4g}",
            id3="NONE", id4="NONE", id5="NONE", model_type=1, analysis_type=3, data_ch=2, spec_data_type=8,
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
