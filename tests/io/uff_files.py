"""Writing UFF test files with pyuff, the way acquisition software exports them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyuff

# record 8-11 specific data types
TIME, FREQUENCY, DISPLACEMENT, VELOCITY, ACCELERATION, FORCE = 17, 18, 8, 11, 12, 13


def record58(data, x0, dx, rsp, ref=(0, 0), *, func_type=1, ordinate=ACCELERATION, denominator=0,
             unit="m/s^2", den_unit="NONE", binary=0, load_case=0, name=None) -> dict:
    """A UFF 58 record: rsp/ref are (node, direction code)."""
    data = np.asarray(data)
    return {"type": 58, "binary": binary, "func_type": func_type, "rsp_node": rsp[0], "rsp_dir": rsp[1],
            "ref_node": ref[0], "ref_dir": ref[1], "load_case_id": load_case,
            "rsp_ent_name": name or "NONE", "id1": name or "record",
            "data": data, "x": x0 + dx * np.arange(len(data)), "abscissa_spacing": 1,
            "abscissa_spec_data_type": FREQUENCY if func_type == 4 else TIME,
            "abscissa_axis_units_lab": "Hz" if func_type == 4 else "s",
            "ordinate_spec_data_type": ordinate, "ordinate_axis_units_lab": unit,
            "orddenom_spec_data_type": denominator, "orddenom_axis_units_lab": den_unit}


def nodes15(ids, xyz) -> dict:
    xyz = np.asarray(xyz, dtype=float)
    n = len(ids)
    return pyuff.prepare_15(node_nums=list(ids), def_cs=[0] * n, disp_cs=[0] * n, color=[1] * n,
                            x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2])


def trace82(node_sequence) -> dict:
    # built by hand: pyuff.prepare_82 insists on a list, its writer on an array
    return {"type": 82, "trace_num": 1, "n_nodes": len(node_sequence), "color": 1, "id": "line",
            "nodes": np.asarray(node_sequence, dtype=int)}


def write(path, sets) -> None:
    """A new file. (Appending: pyuff 2.4's "overwrite" mode truncates a binary 58b set's header when it reopens
    the file in binary mode.)"""
    path = Path(path)
    path.unlink(missing_ok=True)
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
