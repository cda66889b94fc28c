"""DataPhysics SignalCalc ASCII exports of FRFs: one function per file, a short header, then frequency lines.

The header read::

    Units: Ratio
    Ref Chan:Resp Chan	0-Z:0-Z          the reference and response channels (channel number and direction)
    Channel Name	 : ...
    Frequency	 Real	 Imaginary       (or Magnitude / Phase in degrees)
    Units:
    Hz	(m/s²)(N)	                 the FRF's unit: response unit, then force unit

then one line per frequency (Hz). Several files are one test: when their reference:response pairs differ they
are assembled into outputs × references by those pairs; when every file names the same pair (a roving hammer moved
between points on one channel) the files are the references in the order given, the output the common response.
"""

from __future__ import annotations

import io
import re

import numpy as np

from ..errors import DataError
from ..words import counted
from .csv import decode
from .records import Records, check_finite
from .timebase import even_step_printed

_PAIR = re.compile(r"^Ref Chan:Resp Chan\s+(\S+):(\S+)", re.M)
_FRF_TYPE = {"m/s²": "accelerance", "m/s^2": "accelerance", "m/s2": "accelerance", "g": "accelerance",
             "m/s": "mobility", "mm/s": "mobility", "m": "receptance", "mm": "receptance"}


def is_signalcalc(raw: bytes) -> bool:
    head = raw[:2048].lstrip(b"\xef\xbb\xbf")
    return head.startswith(b"Units:") and b"Ref Chan:Resp Chan" in head


def _read_one(raw: bytes, label: str) -> dict:
    text = decode(raw, label)
    header, pos = [], 0
    while pos < len(text) and len(header) < 200:
        end = text.find("\n", pos)
        end = len(text) if end < 0 else end
        line = text[pos:end].rstrip("\r")
        if re.match(r"^\s*[+-]?\d", line):
            break
        header.append(line)
        pos = end + 1
    first = len(header)  # lines before the first frequency line
    if pos >= len(text) or len(header) >= 200:
        raise DataError(f"{label}: a SignalCalc header but no frequency lines.")
    pair = _PAIR.search("\n".join(header))
    names = next((ln.split() for ln in header if ln.strip().startswith("Frequency")), None)
    if pair is None or names is None:
        raise DataError(f"{label}: not a SignalCalc FRF export (no 'Ref Chan:Resp Chan' or 'Frequency' line in the "
                        "header). Export the FRF as ASCII from SignalCalc again.")
    if names[1:3] not in (["Real", "Imaginary"], ["Magnitude", "Phase"]):
        raise DataError(f"{label}: columns {names}; SignalCalc FRFs are read as Frequency, Real, Imaginary (or "
                        "Magnitude, Phase in degrees). Export the FRF with those columns.")
    unit_line = header[-1].split("\t") if header else []
    unit = unit_line[1].strip() if len(unit_line) > 1 else ""
    m = re.match(r"^\((.*)\)\s*/?\s*\((.*)\)$", unit)
    rsp_unit, ref_unit = (m.group(1), m.group(2)) if m else (unit, "")
    body = text[pos:]
    try:
        table = np.loadtxt(io.StringIO(body), ndmin=2, usecols=(0, 1, 2), comments=None)
    except ValueError as exc:
        for k, ln in enumerate(body.splitlines(), start=first + 1):
            cells = ln.split()
            if len(cells) < 3:
                raise DataError(f"{label}, line {k}: {len(cells)} values where a frequency line holds 3 (a cut-off "
                                "line?).") from None
            for c in cells[:3]:
                try:
                    float(c)
                except ValueError:
                    raise DataError(f"{label}, line {k}: {c!r} is not a number.") from None
        raise DataError(f"{label}: the frequency lines cannot be read ({exc}).") from None
    check_finite(table, label, row_offset=first + 1, row_name="line")
    f = table[:, 0]

    def cells(part=None):
        return [ln.split("\t", 1)[0] for ln in (body.splitlines()[:len(f)] if part is None else part)]

    sample = body[:8000].splitlines()[:200] + body[-8000:].splitlines()[1:][-200:]
    lines_of = np.arange(first + 1, first + 1 + len(f))
    df = even_step_printed(f, cells([ln for ln in sample if ln.strip()]), cells, f"{label}, frequency column",
                           lines_of, "Hz")
    h = (table[:, 1] + 1j * table[:, 2] if names[1] == "Real"
         else table[:, 1] * np.exp(1j * np.deg2rad(table[:, 2])))
    return {"label": label, "f0": float(f[0]), "df": df, "h": h, "ref": pair.group(1), "rsp": pair.group(2),
            "rsp_unit": rsp_unit, "ref_unit": ref_unit}


def read_signalcalc(raws: list[bytes], labels: list[str], setup: tuple | None = None) -> tuple[Records, tuple | None]:
    """(Records ("frequency", (K, p, m) complex), geometry parts or None) from the bytes of one or several SignalCalc
    FRF files; ``setup`` the (bytes, label) of the test's setup table (:func:`read_setup`): then the inputs and
    outputs are placed at its hammer points and accelerometers (Records.points) and its points drawn as a line or
    a scatter."""
    funcs = [_read_one(raw, lab) for raw, lab in zip(raws, labels)]
    first = funcs[0]
    for fn in funcs[1:]:
        if len(fn["h"]) != len(first["h"]):
            raise DataError(f"{fn['label']}: {len(fn['h'])} frequency lines but {first['label']} has "
                            f"{len(first['h'])}; export every FRF with the same lines.")
        if abs(fn["df"] - first["df"]) > 1e-6 * first["df"] or abs(fn["f0"] - first["f0"]) > 1e-6 * first["df"]:
            raise DataError(f"{fn['label']}: lines every {fn['df']:g} Hz from {fn['f0']:g}, but {first['label']} "
                            f"every {first['df']:g} Hz from {first['f0']:g}; export every FRF on the same lines.")
        if (fn["rsp_unit"], fn["ref_unit"]) != (first["rsp_unit"], first["ref_unit"]):
            raise DataError(f"{fn['label']}: unit ({fn['rsp_unit']})/({fn['ref_unit']}) but {first['label']} has "
                            f"({first['rsp_unit']})/({first['ref_unit']}); export every FRF in the same units.")
    pairs = [(fn["rsp"], fn["ref"]) for fn in funcs]
    if len(funcs) > 1 and len(set(pairs)) == 1:  # one hammer channel moved between points: files are references
        outs = [first["rsp"]]
        refs = [f"{fn['label'].rsplit('.', 1)[0]}:{fn['ref']}" for fn in funcs]  # file:channel, one per hammer point
        values = np.stack([fn["h"] for fn in funcs], axis=1)[:, None, :]
        how = f"the same channels {first['ref']}:{first['rsp']} in every file: the files are the references"
    else:
        if len(set(pairs)) != len(pairs):
            dup = next(p for p in pairs if pairs.count(p) > 1)
            raise DataError(f"{', '.join(fn['label'] for fn in funcs if (fn['rsp'], fn['ref']) == dup)}: the same "
                            f"reference:response {dup[1]}:{dup[0]}, while other files name other channels; remove "
                            "the repeated one.")
        outs = list(dict.fromkeys(fn["rsp"] for fn in funcs))
        refs = list(dict.fromkeys(fn["ref"] for fn in funcs))
        values = np.zeros((len(first["h"]), len(outs), len(refs)), complex)
        filled = np.zeros((len(outs), len(refs)), bool)
        for fn in funcs:
            i, j = outs.index(fn["rsp"]), refs.index(fn["ref"])
            values[:, i, j], filled[i, j] = fn["h"], True
        if not filled.all():
            i, j = np.argwhere(~filled)[0]
            raise DataError(f"{', '.join(labels)}: no FRF of response {outs[i]} to reference {refs[j]}; the "
                            f"{len(outs)} × {len(refs)} matrix of outputs × references must be complete.")
        how = f"{counted(len(outs), 'response')} × {counted(len(refs), 'reference')} by their channels"
    unit = f"{first['rsp_unit']}/{first['ref_unit']}".strip("/")
    frf_type = _FRF_TYPE.get(first["rsp_unit"]) if first["ref_unit"] in ("N", "lbf") else None
    points = parts = nodes = directions = None
    placed = []
    if setup is not None:
        got = read_setup(*setup)
        points, parts = setup_points(got, len(outs), len(refs), setup[1])
        if got["band_hz"] is not None:
            points["proposed_band_hz"] = got["band_hz"]
        nodes = np.array([int(p[:-1]) for p in points["output_points"]])
        directions = got["accel_dir"] / np.linalg.norm(got["accel_dir"], axis=1, keepdims=True)
        placed = [f"{setup[1]}: {counted(len(refs), 'hammer point')} and {counted(len(outs), 'accelerometer')} placed "
                  f"on {counted(len(parts[0]), 'node')}"
                  + (f"; band {got['band_hz'][0]:g}-{got['band_hz'][1]:g} Hz proposed" if got["band_hz"] else "")]
    return Records(domain="frequency", values=[values], step=first["df"], start=first["f0"],
                   outputs=tuple(f"resp {o}" for o in outs), output_units=(unit,) * len(outs),
                   inputs=tuple(r if len(set(pairs)) == 1 and len(funcs) > 1 else f"ref {r}" for r in refs),
                   input_units=(first["ref_unit"],) * len(refs),
                   frf_type=frf_type, nodes=nodes, directions=directions, points=points,
                   described=[f"{counted(len(funcs), 'SignalCalc FRF file')}, {len(first['h'])} lines every "
                              f"{first['df']:.9g} Hz from {first['f0']:g} Hz, {unit}"
                              + (f" ({frf_type})" if frf_type else "") + f": {how}"] + placed), parts


# ---- the test's setup (ModeLAB's setup.csv) --------------------------------------------------------------------
#: Rows of a setup file: a name, then one value per hammer point (or per accelerometer, or per mode).
_SETUP_ROWS = ("xHammer", "yHammer", "zHammer", "FxHammer", "FyHammer", "FzHammer", "xAccel", "yAccel", "zAccel",
               "axAccel", "ayAccel", "azAccel")


def is_setup(raw: bytes) -> bool:
    """True for a roving-hammer test's setup table (rows xHammer, yHammer, zHammer, ..., xAccel, ...; ModeLAB)."""
    head = raw[:4096].lstrip(b"\xef\xbb\xbf").decode("utf-8", "replace")
    names = {ln.split(",", 1)[0].strip() for ln in head.splitlines()}
    return {"xHammer", "zHammer", "xAccel"} <= names


def read_setup(raw: bytes, label: str) -> dict:
    """The setup of a roving-hammer test from its table (ModeLAB's ``setup.csv``): one row per quantity, a name then
    values::

        xHammer,0,0,...   yHammer,...   zHammer,0.1,0.25,...     hammer point coordinates (one column per point)
        FxHammer,1,1,...  FyHammer,...  FzHammer,...             the force's direction at each point
        xAccel,0  yAccel,0  zAccel,0.5  axAccel,-1  ayAccel,0  azAccel,0   accelerometer position and direction
        fMin,65   fMax,1000                                      the band of interest, Hz

    Returns {"hammer_xyz": (m, 3), "hammer_dir": (m, 3), "accel_xyz": (p, 3), "accel_dir": (p, 3),
    "band_hz": (fMin, fMax) or None}. Rows it does not know (iHammer, fLMode, ...) are left alone.
    """
    text = decode(raw, label)
    rows = {}
    for k, line in enumerate(text.splitlines(), start=1):
        cells = [c.strip() for c in line.split(",")]
        if not cells[0]:
            continue
        values = []
        for c in cells[1:]:
            if c == "":
                continue
            try:
                values.append(float(c))
            except ValueError:
                raise DataError(f"{label}, line {k}: {c!r} in row {cells[0]!r} is not a number.") from None
        rows[cells[0]] = np.array(values)
    missing = [r for r in _SETUP_ROWS if r not in rows]
    if missing:
        raise DataError(f"{label}: a roving-hammer setup needs the rows {', '.join(_SETUP_ROWS)}; "
                        f"{', '.join(missing)} missing.")

    def table(names, what):
        cols = [rows[n] for n in names]
        if len({c.size for c in cols}) != 1 or cols[0].size == 0:
            raise DataError(f"{label}: rows {', '.join(names)} hold {[c.size for c in cols]} values; give one per "
                            f"{what} in each.")
        return np.stack(cols, axis=1)

    h_xyz, h_dir = table(_SETUP_ROWS[0:3], "hammer point"), table(_SETUP_ROWS[3:6], "hammer point")
    a_xyz, a_dir = table(_SETUP_ROWS[6:9], "accelerometer"), table(_SETUP_ROWS[9:12], "accelerometer")
    if len(h_xyz) != len(h_dir) or len(a_xyz) != len(a_dir):
        raise DataError(f"{label}: {len(h_xyz)} hammer points with {len(h_dir)} force directions, {len(a_xyz)} "
                        f"accelerometers with {len(a_dir)} directions; give one direction per point.")
    for what, d in (("force", h_dir), ("accelerometer", a_dir)):
        if np.any(np.linalg.norm(d, axis=1) == 0):
            raise DataError(f"{label}: a {what} direction of (0, 0, 0); give each a direction such as 1,0,0.")
    band = None
    if "fMin" in rows and "fMax" in rows and rows["fMin"].size and rows["fMax"].size:
        band = (float(rows["fMin"][0]), float(rows["fMax"][0]))
    return {"hammer_xyz": h_xyz, "hammer_dir": h_dir, "accel_xyz": a_xyz, "accel_dir": a_dir, "band_hz": band}


def setup_points(setup: dict, n_outputs: int, n_inputs: int, label: str) -> tuple[dict, tuple]:
    """(meta points, geometry parts) of a roving-hammer test: each distinct position a node (the hammer points
    first, numbered 1, 2, ...), the inputs at the hammer points, the outputs at the accelerometers (era.core.points);
    the nodes joined in a line when they lie on one (the ModeLAB beam), else left as a scatter of points."""
    from ..core.points import axis_and_sign, point_label
    h_xyz, a_xyz = setup["hammer_xyz"], setup["accel_xyz"]
    if len(h_xyz) != n_inputs or len(a_xyz) != n_outputs:
        raise DataError(f"{label}: {counted(len(h_xyz), 'hammer point')} and {counted(len(a_xyz), 'accelerometer')}, "
                        f"but the FRF files hold {counted(n_inputs, 'reference')} and "
                        f"{counted(n_outputs, 'response')}; the setup must list one hammer point per file (in the "
                        "files' order) and one accelerometer per response.")
    xyz, node_of = [], []
    scale = max(float(np.ptp(np.vstack([h_xyz, a_xyz]), axis=0).max()), 1e-300)
    for p in np.vstack([h_xyz, a_xyz]):
        near = [k for k, q in enumerate(xyz) if np.linalg.norm(q - p) <= 1e-9 * scale]
        if not near:
            xyz.append(p)
            near = [len(xyz) - 1]
        node_of.append(near[0] + 1)
    xyz = np.array(xyz)
    ids = np.arange(1, len(xyz) + 1)

    def side(nodes, dirs):
        got = [axis_and_sign(d) for d in dirs]
        return tuple(point_label(n, a) for n, (a, _) in zip(nodes, got)), tuple(s for _, s in got)

    in_pts, in_signs = side(node_of[:len(h_xyz)], setup["hammer_dir"])
    out_pts, out_signs = side(node_of[len(h_xyz):], setup["accel_dir"])
    meta = {"input_points": in_pts, "input_signs": in_signs, "output_points": out_pts, "output_signs": out_signs}
    traces = []
    centred = xyz - xyz.mean(axis=0)
    if len(xyz) >= 2:
        _, sv, vt = np.linalg.svd(centred, full_matrices=False)
        if sv.size < 2 or sv[1] <= 1e-9 * max(sv[0], 1e-300):  # on one line: join them in order along it
            order = np.argsort(centred @ vt[0])
            traces = [(0, 0, [int(ids[k]) for k in order], 1, "line through the points")]
    parts = (ids, xyz, traces, np.tile(np.eye(3), (len(ids), 1, 1)))
    return meta, parts
