"""A merged multi-setup test out (app/setups.py's merged document): the modes as CSV and UFF 55, the shapes for
the 3-D viewer. An unknown value (a mode a setup did not see) stays unknown: empty in the CSV, left out of UFF 55
(which needs a value at every node), drawn at rest in the viewer."""

from __future__ import annotations

import csv
import io
from types import SimpleNamespace

import numpy as np

import era

from .reporting import geometry_from_json


def _shapes(merged: dict) -> np.ndarray:
    """(points, modes) complex, NaN where unknown."""
    def arr(key):
        return np.array([[np.nan if v is None else v for v in row] for row in merged[key]], dtype=float)
    return (arr("shapes_re") + 1j * arr("shapes_im")).T.reshape(len(merged["points"]), len(merged["modes"]))


def left_out(merged: dict) -> str:
    """What a UFF 55 export leaves out, in words ("" when every mode is written)."""
    gone = [f"mode {j + 1} ({m['frequency_hz']:.4g} Hz, not measured in setup "
            f"{', '.join(str(k) for k in m['missing_setups'])})" for j, m in enumerate(merged["modes"])
            if not m["complete"]]
    return ("Left out (not known at every point): " + "; ".join(gone) + ".") if gone else ""


def modes_uff(merged: dict) -> bytes:
    """The merged modes known at every point as UFF 55 (era.save_modes_uff), on the merged geometry when there is
    one (else point k is node k + 1): a set keeps its mode's number, so the numbers of :func:`left_out` are gaps."""
    shapes = _shapes(merged)
    points = tuple(merged["points"])
    f_std = np.array([np.nan if m["frequency_std_hz"] is None else m["frequency_std_hz"] for m in merged["modes"]])
    d_std = np.array([np.nan if m["damping_std"] is None else m["damping_std"] for m in merged["modes"]])
    s = np.array(merged["eigenvalue_re"], dtype=float) + 1j * np.array(merged["eigenvalue_im"], dtype=float)
    model = SimpleNamespace(shapes=shapes, eigenvalues=s, frequency_std_hz=f_std, damping_std=d_std, outputs=points,
                            points=points, point_shapes=shapes, uncertainty_source=merged.get("uncertainty_source", ""))
    buf = io.BytesIO()
    era.save_modes_uff(buf, model, geometry_from_json(merged.get("geometry")), name="ERA merged")
    return buf.getvalue()


def modes_csv(merged: dict) -> str:
    """One row per merged mode: frequency, damping and their σ, MPC, in how many setups it was seen, whether its
    shape is known at every point and where it is not, then each point's real and imaginary part (an empty cell
    where the shape is unknown: never 0, which would claim a node)."""
    shapes = _shapes(merged)
    buf = io.StringIO()
    w = csv.writer(buf)
    cols = [f"{_cell(q)} {part}" for q in merged["points"] for part in ("re", "im")]
    w.writerow(["mode", "frequency_hz", "frequency_std_hz", "damping_ratio", "damping_std", "mpc", "seen_in_setups",
                "n_setups", "complete", "unknown_at", *cols])
    for j, m in enumerate(merged["modes"]):
        values = []
        for v in shapes[:, j]:
            values += ["", ""] if not np.isfinite(v) else [repr(float(v.real)), repr(float(v.imag))]
        unknown = " ".join(q for q, v in zip(merged["points"], shapes[:, j]) if not np.isfinite(v))
        w.writerow([j + 1, m["frequency_hz"], _blank(m["frequency_std_hz"]), m["damping_ratio"],
                    _blank(m["damping_std"]), _blank(m["mpc"]), m["seen_in"], len(merged["setups"]),
                    int(m["complete"]), unknown, *values])
    return buf.getvalue()


def _blank(x):
    return "" if x is None else x


def _cell(text: str) -> str:
    """A label safe for spreadsheets: a leading = + - @ would be read as a formula."""
    return "'" + text if text[:1] in ("=", "+", "-", "@") else text


def viewer_scene(merged: dict) -> tuple:
    """(geometry or None, frequency_hz (k,), shapes (q, k) complex, labels) for the 3-D viewer: an unknown value
    is drawn at rest (the viewer needs numbers; the labels say which modes are incomplete)."""
    shapes = _shapes(merged)
    f = [m["frequency_hz"] for m in merged["modes"]]
    labels = [f"{m['frequency_hz']:.3f} Hz, {m['seen']}" + ("" if m["complete"] else " (still where unknown)")
              for m in merged["modes"]]
    return geometry_from_json(merged.get("geometry")), np.array(f), np.where(np.isfinite(shapes), shapes, 0), labels
