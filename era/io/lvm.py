"""LabVIEW Measurement files (.lvm, text): a file header, then segments of a header, a names line and data.

What is read (NI's LVM 1.0/2.0 layout):

- the file header (up to the first ``***End_of_Header***``): ``Separator`` (Tab/Comma), ``Decimal_Separator``,
  ``X_Columns`` (No / One / Multi), ``Time_Pref``;
- each segment's header: one value per data column (the tag sits in the X column's place) of ``Samples``,
  ``Y_Unit_Label`` (channel unit), ``X_Dimension``, ``X0`` (s) and ``Delta_X`` (the sampling interval, s);
  a segment without a header keeps the previous one's;
- the names line (``X_Value``, channel names..., ``Comment``) and the data, up to a blank line or the next header.

The time step comes from the ``X_Value`` column when there is one (it is printed with more digits than
``Delta_X``, e.g. 0.000605469 s against "0.000605"), checked to be even (era.io.timebase) and to agree with
``Delta_X``; otherwise from ``Delta_X``; otherwise from the caller's ``dt``. Segments that continue each other in
time are joined; segments that start again are separate records (several initial conditions). Columns left empty
(channels with 0 samples, the X column of ``X_Columns No``) are dropped.
"""

from __future__ import annotations

import io
import re

import numpy as np

from ..errors import DataError
from ..words import counted, sampling
from .csv import UNIT_IN_NAME, decode
from .records import Records, check_finite, force_channels
from .timebase import UnevenClock, even_step_printed, printed_resolution

MAGIC = "LabVIEW Measurement"
_END = "***End_of_Header***"
_SEPARATORS = {"tab": "\t", "comma": ",", "semicolon": ";", "space": " "}
_NUMBER = re.compile(r"^\s*[+-]?(\d+([.,]\d*)?|[.,]\d+)([eE][+-]?\d+)?\s*$|^\s*[+-]?(nan|inf)\s*$", re.I)


#: Where a data block ends: a newline followed by a blank line, or by a line that cannot start with a value.
_BLOCK_END = re.compile(r"\n(?=[ \t,;]*\r?(?:\n|$)|[^0-9+\-.\t,; \r\n])")
_X_CELL = {"\t": re.compile(r"^([^\t\n]*)", re.M), ",": re.compile(r"^([^,\n]*)", re.M)}


def _numeric(cell: str) -> bool:
    return bool(_NUMBER.match(cell))


def _lines_from(text: str, pos: int, stop: int | None = None):
    """(line, start offset, offset after its newline) from ``pos`` on."""
    stop = len(text) if stop is None else stop
    while pos < stop:
        end = text.find("\n", pos, stop)
        end = stop if end < 0 else end + 1
        yield text[pos:end].rstrip("\r\n"), pos, end
        pos = end


def _file_header(text: str, label: str) -> tuple[dict, int]:
    """The file header's tags and the offset after its ***End_of_Header*** line."""
    header = {}
    for line, _, end in _lines_from(text, 0):
        if line.startswith(_END):
            return header, end
        cells = line.split("\t") if "\t" in line else line.split(",")
        if len(cells) > 1:
            header[cells[0].strip()] = cells[1].strip(" \r")
    raise DataError(f"{label}: the LVM file header has no {_END} line: the file is cut short or not a LabVIEW "
                    "Measurement file. Save it again from LabVIEW.")


class _Segment:
    """One data block: header rows (tag -> cells aligned with data columns), names, data text[a:b] from line."""

    def __init__(self, header: dict, names, a: int, b: int, line: int, index: int, own: bool):
        self.header, self.names, self.a, self.b, self.line, self.index = header, names, a, b, line, index
        self.own = own  # its header was written with it (not kept from an earlier segment)


def _segments(text: str, start: int, sep: str, label: str) -> list[_Segment]:
    out, header, names, fresh = [], {}, None, False
    pending: dict | None = None  # a segment header being read
    pos = start
    while pos < len(text):
        line, a, pos = next(_lines_from(text, pos))
        if not line.strip(sep + " "):
            continue
        cells = line.split(sep)
        tag = cells[0].strip()
        if tag == "***Start_Special***":
            stop = text.find("***End_Special***", pos)
            pos = len(text) if stop < 0 else stop
            continue
        if pending is not None:
            if tag == _END:
                header, pending, fresh = pending, None, True
            else:
                pending[tag] = cells
            continue
        if not _numeric(tag) and not (tag == "" and any(_numeric(c) for c in cells[1:])):
            ahead = [ln.split(sep)[0].strip() for ln, _, _ in _lines_from(text, pos, min(pos + 20000, len(text)))]
            ahead = ahead[:60]
            if _END in ahead and not any(_numeric(x) for x in ahead[:ahead.index(_END)]):
                pending = {tag: cells}  # a new segment header
            else:
                names = [c.strip() for c in cells]
            continue
        m = _BLOCK_END.search(text, a)
        pos = m.start() + 1 if m else len(text)
        out.append(_Segment(header, names, a, pos, text.count("\n", 0, a) + 1, len(out) + 1, fresh))
        fresh = False
    if pending is not None:
        raise DataError(f"{label}: a segment header without its {_END} line at the end of the file: the file is "
                        "cut short. Save it again from LabVIEW.")
    return out


def _value(seg: _Segment, tag: str, column: int, shift: int) -> str:
    cells = seg.header.get(tag)
    return cells[column + shift].strip() if cells is not None and column + shift < len(cells) else ""


def _number(text: str, decimal: str, where: str, tag: str) -> float | None:
    if not text:
        return None
    try:
        return float(text.replace(decimal, "."))
    except ValueError:
        raise DataError(f"{where}: {tag} is {text!r}, not a number.") from None


def read_lvm(raw: bytes, label: str, dt: float | None = None) -> Records:
    """Records ("time" domain, one (N_r, c) array per record) from the bytes of an .lvm file; module docstring."""
    text = decode(raw, label)
    if not text.lstrip("\ufeff").startswith(MAGIC):
        raise DataError(f"{label}: does not start with '{MAGIC}'; not an LVM file.")
    fh, start = _file_header(text, label)
    sep = _SEPARATORS.get(fh.get("Separator", "Tab").strip().lower())
    if sep is None:
        raise DataError(f"{label}: Separator {fh['Separator']!r} in the file header; LVM files use Tab or Comma.")
    decimal = fh.get("Decimal_Separator", ".").strip() or "."
    segments = _segments(text, start, sep, label)
    if not segments:
        raise DataError(f"{label}: an LVM header but no data lines.")
    parts = [_read_segment(text, seg, sep, decimal, label, dt) for seg in segments]
    absolute = fh.get("Time_Pref", "Relative").strip().lower() == "absolute"
    values, first = [parts[0]["y"]], parts[0]
    joined = 0
    for prev, part in zip(parts[:-1], parts[1:]):
        where = f"{label}, segment {part['segment']} (line {part['line']})"
        if part["names"] != first["names"]:
            raise DataError(f"{where}: channels {part['names']} differ from those of segment 1 {first['names']}; "
                            "every segment must hold the same channels.")
        if abs(part["dt"] - first["dt"]) > 1e-6 * first["dt"]:
            raise DataError(f"{where}: sampled every {part['dt']:.6g} s, segment 1 every {first['dt']:.6g} s; every "
                            "segment must share the sampling step.")
        expected = prev["t0"] + len(prev["y"]) * prev["dt"]
        if part["t0"] is not None and prev["t0"] is not None and abs(part["t0"] - expected) < 0.5 * first["dt"]:
            values[-1] = np.concatenate([values[-1], part["y"]])  # one acquisition written in several calls
            joined += 1
        else:
            values.append(part["y"])
    names, units = first["names"], first["units"]
    force = force_channels(names, units)
    segmented = f"{counted(len(segments), 'segment')} as " if len(segments) > 1 else ""
    described = (f"{label}: LabVIEW LVM, {segmented}{counted(len(values), 'record')} of "
                 f"{', '.join(str(len(v)) for v in values[:6])}{'…' if len(values) > 6 else ''} samples × "
                 f"{counted(len(names), 'channel')}, {sampling(first['dt'], first['dt_from'])}"
                 + (f"; {counted(first['dropped'], 'empty column')} dropped" if first["dropped"] else ""))
    return Records(domain="time", values=values, step=first["dt"],
                   start=0.0 if absolute or first["t0"] is None else float(first["t0"]),
                   outputs=tuple(names), output_units=tuple(units), force=force, described=[described])


def _read_segment(text: str, seg: _Segment, sep: str, decimal: str, label: str, dt) -> dict:
    where = f"{label}, segment {seg.index} (line {seg.line})"
    body = text[seg.a:seg.b]
    first_cells = body[:body.find("\n") if "\n" in body else None].rstrip("\r").split(sep)
    names = seg.names or [f"X_Value" if c == 0 else f"channel {c}" for c in range(len(first_cells))]
    if names and names[-1] == "Comment":
        names = names[:-1]
    shift = 0 if names and names[0] == "X_Value" else 1  # header cell (tag at 0) of data column j
    if len(first_cells) < len(names) and seg.names is not None:
        missing = [i for i in range(len(first_cells), len(names))]
        first_cells += [""] * len(missing)
    used = [j for j in range(len(names)) if first_cells[j].strip()]
    dropped = len(names) - len(used)
    x_cols = [j for j in used if names[j] == "X_Value"]
    y_cols = [j for j in used if names[j] != "X_Value"]
    if not y_cols:
        raise DataError(f"{where}: no channel columns with values.")
    dimension = _value(seg, "X_Dimension", y_cols[0], shift)
    if dimension and dimension.lower() not in ("time", "samples", ""):
        raise DataError(f"{where}: X_Dimension is {dimension!r}; ERA reads time records. Export the time data "
                        "(X_Dimension Time).")
    if decimal == "," and sep != ",":
        body = body.replace(",", ".")
    try:
        table = np.loadtxt(io.StringIO(body), delimiter=sep, usecols=used, ndmin=2, dtype=float, comments=None)
    except ValueError:
        raise DataError(_bad_line(body.splitlines(), seg.line, sep, decimal, used, names, label)) from None
    line_of = np.arange(seg.line, seg.line + len(table))
    check_finite(table, where, row_offset=seg.line, row_name="line")
    header_dt = _number(_value(seg, "Delta_X", y_cols[0], shift), decimal, where, "Delta_X")
    x0 = _number(_value(seg, "X0", y_cols[0], shift), decimal, where, "X0")
    for j in y_cols[1:]:
        other = _number(_value(seg, "Delta_X", j, shift), decimal, where, "Delta_X")
        if other is not None and header_dt is not None and abs(other - header_dt) > 1e-9 * header_dt:
            raise DataError(f"{where}: channel {names[j]!r} has Delta_X {other:g} s, channel {names[y_cols[0]]!r} "
                            f"{header_dt:g} s; load channels with different sampling rates separately.")
    y = table[:, [used.index(j) for j in y_cols]]
    if x_cols:
        t = table[:, used.index(x_cols[0])]
        for j in x_cols[1:]:
            if np.abs(table[:, used.index(j)] - t).max() > 1e-6 * max(np.abs(t).max(), 1e-30):
                raise DataError(f"{where}: the X_Value columns differ between channels; the channels were not "
                                "sampled together. Load them separately.")
        def cells(text=body):
            return (_X_CELL[sep].findall(text) if x_cols[0] == 0 and sep in _X_CELL
                    else [ln.split(sep)[x_cols[0]] for ln in text.splitlines()])[:len(t)]

        sample = cells(body[:4000]) + cells(body[-4000:])[1:]  # the first and last lines (one may be cut)
        try:
            step = even_step_printed(t, sample, cells, f"{where}, X_Value column", line_of)
        except UnevenClock as clock:  # LVM takes no resample option: said without naming one
            raise DataError(str(clock)) from None
        if header_dt is not None:
            digit = printed_resolution([_value(seg, "Delta_X", y_cols[0], shift)])[0]
            if abs(step - header_dt) > digit + 1e-6 * step:
                raise DataError(f"{where}: the X_Value column steps {step:.9g} s but the header's Delta_X is "
                                f"{header_dt:g} s; the file contradicts itself. Check the acquisition settings.")
        t0, dt_from = float(t[0]), "from the X_Value column"
    elif header_dt is not None:
        step, t0, dt_from = header_dt, x0 if x0 is not None else 0.0, "from Delta_X"
    elif dt is not None:
        step, t0, dt_from = float(dt), None, "given"
    else:
        raise DataError(f"no sampling interval in {label}: give the sample rate (dt=...).", option="dt")
    if not (np.isfinite(step) and step > 0):
        raise DataError(f"{where}: the sampling interval {step!r} is not a positive number.")
    samples = _number(_value(seg, "Samples", y_cols[0], shift), decimal, where, "Samples")
    if seg.own and samples is not None and samples > 0 and len(table) % int(samples):
        raise DataError(f"{where}: the header promises {int(samples)} samples per write but the segment holds "
                        f"{len(table)} lines: the file is cut short. Save it again from LabVIEW.")
    units = []
    chan_names = []
    for j in y_cols:
        nm, unit = names[j] or f"channel {j}", _value(seg, "Y_Unit_Label", j, shift)
        m = UNIT_IN_NAME.match(nm)
        if m:
            nm, unit = m.group(1).strip(), unit or m.group(2).strip()
        chan_names.append(nm)
        units.append(unit)
    return {"segment": seg.index, "line": seg.line, "y": y, "dt": float(step), "t0": t0, "dt_from": dt_from,
            "names": _unique(chan_names), "units": units, "dropped": dropped}


def _unique(names: list[str]) -> list[str]:
    seen: dict[str, int] = {}
    out = []
    for nm in names:
        seen[nm] = seen.get(nm, 0) + 1
        out.append(nm if seen[nm] == 1 else f"{nm} ({seen[nm]})")
    return out


def _bad_line(block, first, sep, decimal, used, names, label) -> str:
    """The message for the first data line that does not parse (only called after loadtxt failed)."""
    for k, ln in enumerate(block):
        cells = ln.split(sep)
        for j in used:
            if j >= len(cells) or not cells[j].strip():
                return (f"{label}, line {first + k}: no value in column {j + 1} ({names[j]!r}); every data line "
                        "must hold every channel (a cut-off line?).")
            try:
                float(cells[j].replace(decimal, "."))
            except ValueError:
                return f"{label}, line {first + k}, column {j + 1}: {cells[j]!r} is not a number."
    return f"{label}: the data lines cannot be read as numbers."
