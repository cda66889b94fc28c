"""A simulated impact test of a small era.Frame written as UFF with its geometry, the way a test engineer brings one:
UFF 15 nodes (mm), UFF 82 trace lines (the members, one trace line per section, named after it), UFF 58 pulse responses at the sensors (m per N·s).

The truth is era.examples.frame_simulation.truth_model (2 % member scatter, twice the mesh, the hidden effect);
the records are the sum of its lowest modes' impulse responses with 1 % modal damping and a little noise.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyuff

from era.examples.frame_simulation import truth_model

AXIS_CODE = {"x": 1, "y": 2, "z": 3, "-x": -1, "-y": -2, "-z": -3}     # UFF 58 direction codes


def node_numbers(frame) -> dict:
    """UFF node numbers (1, 2, ...) of the frame's node ids, in frame order."""
    return {n: k + 1 for k, n in enumerate(frame.nodes)}


def pulse_responses(frame, params: dict, *, inputs=(0,), n_samples: int = 400, n_modes: int = 8,
                    zeta: float = 0.01, noise: float = 1e-3, seed: int = 0) -> tuple[np.ndarray, float]:
    """(y (N, p, m) m per N·s, dt s): impulses at the given sensors (indices), the truth's lowest n_modes."""
    model, _ = truth_model(frame, dict(params), rng=np.random.default_rng(seed))
    f, s = model.modes(n_modes)                        # (n,), (p, n) mass-normalised at the sensors
    w = 2 * np.pi * f
    dt = 1.0 / (2.5 * f.max())
    t = np.arange(n_samples) * dt
    wd = w * np.sqrt(1 - zeta**2)
    h = np.exp(-zeta * w * t[:, None]) * np.sin(wd * t[:, None]) / wd          # (N, n)
    y = np.einsum("tn,pn,mn->tpm", h, s, s[list(inputs)])
    rng = np.random.default_rng(seed + 1)
    y = y + noise * np.abs(y).max() * rng.standard_normal(y.shape)
    return y, dt


def write_uff(path: Path, frame, params: dict | None = None, *, inputs=(0,), **kw) -> Path:
    """The frame's test as one UFF file: nodes in mm (UFF 164 + 15), one trace line per section (82, its members
    pen-up apart, named after the section), one pulse response per (sensor, input) (58)."""
    y, dt = pulse_responses(frame, params or {}, inputs=inputs, **kw)
    num = node_numbers(frame)
    ids = list(num.values())
    xyz = np.array([frame.nodes[n] for n in num]) * 1000.0
    sets = [pyuff.prepare_164(units_code=5, units_description="mm", temp_mode=1, length=1000.0, force=1.0,
                              temp=1.0, temp_offset=273.15),
            pyuff.prepare_15(node_nums=ids, def_cs=[0] * len(ids), disp_cs=[0] * len(ids), color=[1] * len(ids),
                             x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2])]
    for k, name in enumerate(dict.fromkeys(m[2] for m in frame.members)):   # one named trace line per section
        seq = [n for i, j, sec, *_ in frame.members if sec == name for n in (num[i], num[j], 0)]
        sets.append({"type": 82, "trace_num": k + 1, "n_nodes": len(seq), "color": 1, "id": name,
                     "nodes": np.array(seq, dtype=int)})
    for m, a in enumerate(inputs):
        ref = frame.sensors[a]
        for p, (node, d) in enumerate(frame.sensors):
            sets.append({"type": 58, "binary": 0, "func_type": 1, "rsp_node": num[node], "rsp_dir": AXIS_CODE[d],
                         "ref_node": num[ref[0]], "ref_dir": AXIS_CODE[ref[1]], "load_case_id": 0,
                         "rsp_ent_name": f"{node}{d}", "id1": f"pulse {node}{d}/{ref[0]}{ref[1]}",
                         "data": y[:, p, m], "x": dt * np.arange(y.shape[0]), "abscissa_spacing": 1,
                         "abscissa_spec_data_type": 17, "abscissa_axis_units_lab": "s",
                         "ordinate_spec_data_type": 8, "ordinate_axis_units_lab": "m",
                         "orddenom_spec_data_type": 13, "orddenom_axis_units_lab": "N s"})
    path = Path(path)
    path.unlink(missing_ok=True)
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path

