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
from .csv import _decode
from .records import Records, check_finite
from .timebase import even_step_printed

_PAIR = re.compile(r"^Ref Chan:Resp Chan\s+(\S+):(\S+)", re.M)
_FRF_TYPE = {"m/s²": "accelerance", "m/s^2": "accelerance", "m/s2": "accelerance", "g": "accelerance",
             "m/s": "mobility", "mm/s": "mobility", "m": "receptance", "mm": "receptance"}


def is_signalcalc(raw: bytes) -> bool:
    head = raw[:2048].lstrip(b"\xef\xbb\xbf")
    return head.startswith(b"Units:") and b"Ref Chan:Resp Chan" in head


def _read_one(raw: bytes, label: str) -> dict:
    text = _decode(raw, label)
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


def read_signalcalc(raws: list[bytes], labels: list[str]) -> Records:
    """Records ("frequency", (K, p, m) complex) from the bytes of one or several SignalCalc FRF files."""
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
        outs, refs = [first["rsp"]], [fn["label"] for fn in funcs]
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
        how = f"{len(outs)} response(s) × {len(refs)} reference(s) by their channels"
    unit = f"{first['rsp_unit']}/{first['ref_unit']}".strip("/")
    frf_type = _FRF_TYPE.get(first["rsp_unit"]) if first["ref_unit"] in ("N", "lbf") else None
    return Records(domain="frequency", values=[values], step=first["df"], start=first["f0"],
                   outputs=tuple(f"resp {o}" for o in outs), output_units=(unit,) * len(outs),
                   inputs=tuple(f"ref {r}" for r in refs), input_units=(first["ref_unit"],) * len(refs),
                   frf_type=frf_type,
                   described=[f"{len(funcs)} SignalCalc FRF file(s), {len(first['h'])} lines every "
                              f"{first['df']:.9g} Hz from {first['f0']:g} Hz, {unit}"
                              + (f" ({frf_type})" if frf_type else "") + f": {how}"])
