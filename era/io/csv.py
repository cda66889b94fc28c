"""Delimited text: a time column and one column per channel, names (and units) in the header.

Delimiter (comma, semicolon, tab, blanks) and decimal comma are sniffed. Units come from a second header row or
from the names ("acc1 [m/s^2]", "acc1 (g)"). A column named test/run/record/case splits the rows into several
records (initial conditions or repeated tests).
"""

from __future__ import annotations

import io
import re

import numpy as np

from ..errors import DataError
from ..words import counted, sampling
from .records import Records, force_channels, hammer_channel
from .text import read_headerless
from .timebase import UnevenClock, even_step_printed, resample as resample_onto

_TIME_NAMES = re.compile(r"^(t|time|times|zeit|temps|tiempo|tempo|sec|seconds|x_value|elapsed time)$", re.I)
#: Time units in s; a time column's unit comes from (...)/[...], a units row or a suffix such as time_ms.
_TIME_UNITS = {"s": 1.0, "sec": 1.0, "secs": 1.0, "second": 1.0, "seconds": 1.0, "ms": 1e-3, "msec": 1e-3,
               "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "usec": 1e-6, "ns": 1e-9, "min": 60.0}
_SUFFIX_UNIT = re.compile(r"^(.*?)[_ ](s|sec|ms|msec|us|µs|μs|ns)$", re.I)
_TEST_NAMES = {"test", "run", "record", "case", "ic", "reference", "ref", "trial"}
UNIT_IN_NAME = re.compile(r"^(.*?)\s*[\[(]\s*([^\])]*)\s*[\])]\s*$")
#: A channel unit as a name's suffix, as spreadsheets write it: tip_acc_g, force_N, F_lbf, drive_mV.
_UNIT_SUFFIX = re.compile(r"^(.+?)_(g|N|kN|lbf|V|mV|m/s2|m/s\^2|ms2|mps2)$")
_NUMBER = re.compile(r"^[+-]?(\d+([.,]\d*)?|[.,]\d+)([eE][+-]?\d+)?$|^[+-]?(nan|inf|infinity)$", re.I)


def decode(raw: bytes, label: str) -> str:
    if b"\x00" in raw[:65536]:
        raise DataError(f"{label}: binary content (NUL bytes) where delimited text was expected; is this a CSV file?")
    for enc in ("utf-8-sig", "cp1252", "latin-1"):
        try:
            return raw.decode(enc)
        except UnicodeDecodeError:
            continue
    raise DataError(f"{label}: not readable as text.")  # latin-1 decodes anything; kept for clarity


def _split(line: str, delim: str | None) -> list[str]:
    return [c.strip().strip('"') for c in (line.split(delim) if delim else line.split())]


def _is_data(cells: list[str]) -> bool:
    """A data line is mostly numbers (a test-name column may hold words); header lines are mostly words."""
    cells = cells[:200]  # a bare matrix of channels in rows has lines of a million values
    return sum(bool(_NUMBER.match(c)) for c in cells) > len(cells) / 2


#: A complex number as Python or MATLAB print it: (a+bj), a+bi.
_COMPLEX = re.compile(r"\(?[-+]?[\d.]+(?:e[-+]?\d+)?[-+][\d.]+(?:e[-+]?\d+)?[ij]\)?", re.IGNORECASE)


def _sniff_delimiter(lines: list[str]) -> str | None:
    for delim in ("\t", ";", ","):
        counts = {ln.count(delim) for ln in lines}
        if len(counts) == 1 and counts.pop() > 0:
            return delim
    return None


def read_csv(raw: bytes, label: str, dt: float | None = None, orientation: str | None = None,
             resample: bool = False) -> Records:
    """Records ("time" domain) from the bytes of one delimited text file.

    dt : s, used only when the file has no time column. orientation : "rows" or "columns" for a file without a
    header (era.io.text; default: from its shape). resample : True to put records whose time stamps scatter about
    a steady rate onto an even grid at the mean rate (era.io.timebase.resample; said in ``conversions``).
    """
    text = decode(raw, label)
    lines = text.splitlines()
    numbered = [(k + 1, ln) for k, ln in enumerate(lines) if ln.strip() and not ln.lstrip().startswith("#")]
    if not numbered:
        raise DataError(f"{label}: the file is empty (no data lines).")
    delim = _sniff_delimiter([ln for _, ln in numbered[-20:]] if len(numbered) > 2 else [numbered[-1][1]])
    trailing = delim is not None and all(ln.rstrip().endswith(delim) for _, ln in numbered[-20:])
    if trailing:  # every row ends in a delimiter (phone apps, some loggers): an empty last cell, not a channel
        numbered = [(k, ln.rstrip()[:-1] if ln.rstrip().endswith(delim) else ln) for k, ln in numbered]
    if trailing and delim == ",":
        delim = _sniff_delimiter([ln for _, ln in numbered[-20:]] if len(numbered) > 2 else [numbered[-1][1]])
    header = []
    while numbered and not _is_data(_split(numbered[0][1][:8000], delim)):
        header.append(_split(numbered.pop(0)[1], delim))
    if not numbered:
        first = header[0][0] if header and header[0] else ""
        if _COMPLEX.fullmatch(first.strip()):
            raise DataError(f"{label}: complex numbers ({first.strip()!r} ...): FRFs without a frequency axis, which "
                            "text files cannot give era. Write them as UFF 58 with their frequency axis (pyuff's "
                            "write_sets, as its README shows); text is read as real time records.")
        raise DataError(f"{label}: a header but no numeric data lines.")
    if not header:
        body = "\n".join(ln for _, ln in numbered)
        comma = delim != "," and "," in body and re.search(r"\d,\d", body) is not None
        notes = (", decimal comma" if comma else "") + (f", delimiter {delim!r}" if delim else ", blank-separated") \
            + (", a delimiter ending every line" if trailing else "")
        return read_headerless(numbered, lambda ln: _split(ln.replace(",", ".") if comma else ln, delim),
                               body.replace(",", ".") if comma else body, delim, label, dt, orientation, notes,
                               resample)
    if orientation is not None:
        raise DataError(f"{label}: `orientation` is for text without a header; this file has a header line, so its "
                        "columns are the channels. Leave orientation out.", option="orientation")
    first_line = numbered[0][0]
    n_cols = len(_split(numbered[0][1], delim))
    names = header[0] if header else [f"c{i + 1}" for i in range(n_cols)]
    if len(names) != n_cols:
        raise DataError(f"{label}: the header names {len(names)} columns but line {first_line} holds {n_cols} values.")
    units = header[1] if len(header) > 1 and len(header[1]) == n_cols else [""] * n_cols
    for i, nm in enumerate(names):
        m = UNIT_IN_NAME.match(nm)
        if m and not units[i]:
            names[i], units[i] = m.group(1).strip(), m.group(2).strip()
        m = _UNIT_SUFFIX.match(names[i])
        if m and not units[i] and not _TIME_NAMES.match(m.group(1)):  # tip_acc_g, hammer_N: keep the name whole
            units[i] = m.group(2)
    test_col = next((i for i, nm in enumerate(names) if nm.lower() in _TEST_NAMES), None)
    body = "\n".join(ln for _, ln in numbered)
    decimal_comma = delim != "," and "," in body and re.search(r"\d,\d", body) is not None
    if decimal_comma:
        body = body.replace(",", ".")
    numeric = [i for i in range(n_cols) if i != test_col]
    try:
        table = np.loadtxt(io.StringIO(body), delimiter=delim, usecols=numeric, ndmin=2, dtype=float,
                           comments=None)
        tests = (np.loadtxt(io.StringIO(body), delimiter=delim, usecols=[test_col], dtype=str, ndmin=1,
                            comments=None) if test_col is not None else None)
    except ValueError as exc:
        raise DataError(_first_bad_line(numbered, delim, decimal_comma, numeric, n_cols, label) or
                        f"{label}: {exc}") from None
    line_of = np.array([k for k, _ in numbered])
    _finite(table, label, line_of)
    names = [names[i] for i in numeric]
    units = [units[i] for i in numeric]
    tc, scale = _time_column(names, units, label)
    if tc is None and units[0].lower() in _TIME_UNITS and dt is None:  # unnamed, but its unit says time
        tc, scale = 0, _TIME_UNITS[units[0].lower()]
    if tc is None and dt is None:
        raise DataError(f"no sampling interval in {label}: no time column (the columns are {names[:6]}"
                        f"{'…' if len(names) > 6 else ''}); name one 'time', 't', 'time_s', 'Time (s)' or 't [ms]', "
                        "or give the sample rate (dt=...).")
    t = table[:, tc] * scale if tc is not None else None
    if tc is not None:
        keep = [i for i in range(len(names)) if i != tc]
        time_name = names[tc]
        table, names, units = table[:, keep], [names[i] for i in keep], [units[i] for i in keep]
    if table.shape[1] == 0:
        raise DataError(f"{label}: a time column but no channel columns.")
    groups = [np.arange(len(table))] if tests is None else [np.flatnonzero(tests == v)
                                                            for v in dict.fromkeys(tests.tolist())]
    values, step, start, conversions = [], None, 0.0, []
    for g in groups:
        if t is not None:
            if len(g) < 2:
                raise DataError(f"{label}: record at line {line_of[g[0]]} has a single sample.")
            column = numeric[tc] if tc is not None else 0

            def cells(rows, column=column):
                return [_split(numbered[r][1], delim)[column] for r in rows]

            block = table[g]
            try:
                h = even_step_printed(t[g], cells(np.r_[g[:200], g[-200:]]), lambda: cells(g), label, line_of[g])
            except UnevenClock as clock:
                if not resample:
                    raise
                h = clock.step
                block, done = resample_onto(t[g], table[g], clock.step)
                conversions.append(f"{label}" + (f", record at line {line_of[g[0]]}" if len(groups) > 1 else "")
                                   + f": {done}")
            h_unit = h / scale
            if step is not None and abs(h - step) > 1e-6 * step:
                raise DataError(f"{label}, line {line_of[g[0]]}: this record is sampled every {h:g} s, the first "
                                f"every {step:g} s; every record must share the sampling step.")
            step, start = (h, float(t[g][0])) if step is None else (step, start)
            values.append(block)
        else:
            values.append(table[g])
    if step is None:
        step = float(dt)
        timing = f", {sampling(step)} given"
    else:
        timing = f", time column {time_name!r}" + (f" in units of {scale:g} s" if scale != 1 else "") + \
            f", {sampling(step)}" + (f", {h_unit:.6g} in the file's unit" if scale != 1 else "")
    force = force_channels(names, units)
    pulse = None if force.any() else _pulse_channel(values, units)
    if pulse is not None:  # generic names (t,ch1,ch2; time,a,b): the values show the hammer
        force[pulse] = True
        timing += (f"; {names[pulse]!r} proposed as the force (a short pulse: 99 % of its energy within "
                   f"{max(len(values[0]) // 100, 1)} samples, the others ring on)")
    return Records(domain="time", values=values, step=step, start=start, outputs=tuple(names),
                   output_units=tuple(units), force=force, nodes=None, directions=None, conversions=conversions,
                   described=[f"{label}: {len(table)} lines × {counted(len(names), 'channel')}"
                              + (f" in {len(values)} records (column {tests is not None and 'test'})" if len(values) > 1
                                 else "") + timing + (", decimal comma" if decimal_comma else "")
                              + (f", delimiter {delim!r}" if delim else ", blank-separated")
                              + (", a delimiter ending every line" if trailing else "")])


#: Units a force transducer's channel may be written in besides force units: none, or its raw voltage.
_RAW_UNITS = {"", "v", "mv"}


def _pulse_channel(values: list[np.ndarray], units: list[str]) -> int | None:
    """The channel that is a hammer's short pulse in every record (era.io.records.hammer_channel) when its unit
    does not say it is something else (a response in g or m/s²); else None. values: records, each (N, c)."""
    found = {hammer_channel(v) for v in values}
    pulse = found.pop() if len(found) == 1 else None
    return pulse if pulse is not None and units[pulse].strip().lower() in _RAW_UNITS else None


def _time_column(names: list[str], units: list[str], label: str) -> tuple[int | None, float]:
    """The index of the time column among ``names`` and its unit in s: 'time', 't', 'Zeit', 'time_s', 'Time (s)'
    (units already split off into ``units``), 't [ms]', 'time_ms', ...; (None, 1.0) when there is none."""
    for i, (nm, unit) in enumerate(zip(names, units)):
        base, suffix = nm.strip(), ""
        m = _SUFFIX_UNIT.match(base)
        if not _TIME_NAMES.match(base) and m and _TIME_NAMES.match(m.group(1).strip(" _")):
            base, suffix = m.group(1).strip(" _"), m.group(2)
        if _TIME_NAMES.match(base):
            unit = (unit or suffix or "s").strip().lower()
            if unit not in _TIME_UNITS:
                raise DataError(f"{label}: the time column {nm!r} is in {unit!r}; give times in s, ms, µs or ns "
                                "(clock times such as hh:mm:ss cannot give a sampling step).")
            return i, _TIME_UNITS[unit]
    return None, 1.0


def _first_bad_line(numbered, delim, decimal_comma, numeric, n_cols, label) -> str | None:
    """The message for the first data line that does not parse (only called after loadtxt failed)."""
    for k, ln in numbered:
        cells = _split(ln.replace(",", ".") if decimal_comma else ln, delim)
        if len(cells) != n_cols:
            return (f"{label}, line {k}: {len(cells)} values where the file has {n_cols} columns; every data line "
                    "must hold the same columns (a cut-off or merged line?).")
        for c in numeric:
            try:
                float(cells[c])
            except ValueError:
                return f"{label}, line {k}, column {c + 1}: {cells[c]!r} is not a number."
    return None


def _finite(table: np.ndarray, label: str, line_of: np.ndarray) -> None:
    bad = ~np.isfinite(table)
    if bad.any():
        k, c = np.argwhere(bad)[0]
        raise DataError(f"{label}, line {line_of[k]}, column {c + 1}: NaN or infinite value ({int(bad.sum())} in "
                        "all). Remove or interpolate them, then load again.")
