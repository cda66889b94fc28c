"""Universal File Format through pyuff: 58/58b function records, 15/2411 nodes, 82 trace lines, 55 modes.

pyuff parses; this module checks what pyuff does not (sizes promised by headers, even sampling, finite values,
a file cut short) and assembles records into outputs × references by node and direction.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np
import pyuff

from ..errors import DataError
from ..words import counted, sampling, significant
from ..markov.common import uneven_step
from .records import Records, check_finite, merge_records
from .uff_geometry import (
    build_geometry, geometry_parts, in_global_directions, merge_parts, modes_in_global, unit_factors)

#: Record 6 direction codes: ±1, ±2, ±3 = ±X, ±Y, ±Z translation; 4-6 rotations have no displacement direction.
_DIR_LABEL = {1: "X", 2: "Y", 3: "Z", 4: "RX", 5: "RY", 6: "RZ"}
#: Specific data types of records 8-11 (ordinate / denominator).
_QUANTITY = {8: "displacement", 11: "velocity", 12: "acceleration", 13: "force", 9: "force"}
_FRF_TYPE = {"displacement": "receptance", "velocity": "mobility", "acceleration": "accelerance"}
_TIME_FUNCS = (0, 1)  # general, time response
_FRF_FUNC = 4


def direction_vector(code: int) -> np.ndarray:
    v = np.zeros(3)
    if 1 <= abs(code) <= 3:
        v[abs(code) - 1] = np.sign(code)
    return v


def _dof_label(node: int, code: int) -> str:
    return f"{node}{'+' if code >= 0 else '-'}{_DIR_LABEL.get(abs(code), str(abs(code)))}" if code else str(node)


def _label(value) -> str:
    s = str(value or "").strip()
    return "" if s.upper() == "NONE" else s


def _line_of(path: str, offset: int) -> int:
    """1-based line number of a byte offset; only computed for an error message (it reads the file up to there)."""
    with open(path, "rb") as fh:
        return fh.read(int(offset)).count(b"\n") + 1


def _check_complete(path: str, label: str) -> None:
    """A UFF file ends with a '    -1' delimiter line; anything else means it was cut short."""
    with open(path, "rb") as fh:
        fh.seek(0, os.SEEK_END)
        size = fh.tell()
        fh.seek(max(size - 512, 0))
        tail = fh.read().rstrip(b"\r\n \t\x00")
    if not tail.endswith(b"    -1"):  # in 58b the delimiter follows the binary values directly
        raise DataError(f"{label}: the file does not end with a '    -1' delimiter line: it was cut short (truncated "
                        "upload or copy) inside its last data set. Export or copy it again.")


class _Line:
    """The first line of a data set, counted only when a message prints it (counting reads the file)."""

    def __init__(self, path: str, offset: int):
        self.path, self.offset = path, offset

    def __str__(self) -> str:
        return str(_line_of(self.path, self.offset)) if self.offset >= 0 else "?"


class _Where:
    """'file: data set #i (UFF t, line L)' for messages, formatted only when printed."""

    def __init__(self, label: str, i: int, line: _Line, uff_type: int = 58, suffix: str = ""):
        self.label, self.i, self.line, self.type, self.suffix = label, i, line, uff_type, suffix

    def __str__(self) -> str:
        return f"{self.label}: data set #{self.i + 1} (UFF {self.type}, line {self.line}){self.suffix}"

    def __add__(self, suffix: str) -> "_Where":
        return _Where(self.label, self.i, self.line, self.type, self.suffix + suffix)


def read_sets(path: str, label: str) -> list[tuple[int, "_Line", dict]]:
    """Every supported data set as (index, first line, dict) via pyuff, with errors as DataError."""
    try:
        uff = pyuff.UFF(path)
        types = list(uff.get_set_types())
    except Exception as exc:  # pyuff raises bare Exceptions
        raise DataError(f"{label}: not a readable UFF file ({exc}).") from None
    if not types:
        raise DataError(f"{label}: no UFF data sets found (no '    -1' delimiter lines). Is it a Universal File?")
    _check_complete(path, label)
    blocks = getattr(uff, "_block_ind", None)  # pyuff's byte offsets of each set, for line numbers in messages
    offsets = [int(b[0]) for b in blocks] if blocks is not None else [-1] * len(types)
    lines = [_Line(path, off) for off in offsets]
    out = []
    for i, (t, line) in enumerate(zip(types, lines)):
        if int(t) not in (15, 2411, 82, 55, 58, 18, 2420, 164):
            continue
        try:
            dset = uff.read_sets(i)
        except Exception as exc:
            raise DataError(f"{label}: data set #{i + 1} (UFF {int(t)}) starting at line {line} is corrupt and "
                            f"cannot be parsed (pyuff: {exc}). Export the file again or remove that data set."
                            ) from None
        out.append((i, line, dset))
    return out


def _function_record(i: int, line: _Line, d: dict, label: str) -> dict | None:
    """One 58 record checked: dict(x0, dx, y, domain, ...) or None for function types we do not use."""
    where = _Where(label, i, line)
    func = int(d.get("func_type", 0))
    abscissa = int(d.get("abscissa_spec_data_type", 0))
    if func == _FRF_FUNC or (func == 0 and abscissa == 18):
        domain = "frequency"
    elif func in _TIME_FUNCS and abscissa in (0, 17):
        domain = "time"
    else:
        return None
    y = np.asarray(d.get("data"))
    x = np.asarray(d.get("x"), dtype=float)
    n_promised = int(d.get("num_pts", -1))
    if y.ndim != 1 or y.size != n_promised:
        raise DataError(f"{where}: the header promises {n_promised} values but the record holds {y.size}; the file "
                        "is truncated or corrupt.")
    if y.size < 2:
        raise DataError(f"{where}: {counted(y.size, 'value')}; far too few samples for identification.")
    if domain == "time" and np.iscomplexobj(y):
        raise DataError(f"{where}: a time record with complex values; time histories must be real.")
    check_finite(y, where)
    if int(d.get("abscissa_spacing", 1)) == 1:
        x0, dx = float(d["abscissa_min"]), float(d["abscissa_inc"])
    else:  # uneven abscissa: accept it only if it is in fact even
        check_finite(x, where + " abscissa")
        dx, k = uneven_step(x, 1e-5 * np.abs(x).max())  # ASCII 58 writes the abscissa as E13.5
        x0 = float(x[0])
        if k is not None:
            raise DataError(f"{where}: the abscissa is not evenly spaced (step {x[k + 1] - x[k]:g} after value {k}, "
                            f"typical {dx:g}); ERA needs a constant sampling step.")
    if not (np.isfinite(dx) and dx > 0 and np.isfinite(x0)):
        raise DataError(f"{where}: abscissa increment {dx!r} is not a positive number.")
    num = _QUANTITY.get(int(d.get("ordinate_spec_data_type", 0)), "")
    den = _QUANTITY.get(int(d.get("orddenom_spec_data_type", 0)), "")
    unit = _label(d.get("ordinate_axis_units_lab"))
    den_unit = _label(d.get("orddenom_axis_units_lab"))
    if domain == "time" and den == "force":
        domain = "pulse"  # response per unit force in time: an impulse response
    rsp = (int(d.get("rsp_node", 0)), int(d.get("rsp_dir", 0)))
    ref = (int(d.get("ref_node", 0)), int(d.get("ref_dir", 0)))
    name = _label(d.get("rsp_ent_name")) or _dof_label(*rsp)
    return {"set": i + 1, "line": line, "domain": domain, "x0": x0, "dx": dx, "y": y, "rsp": rsp, "ref": ref,
            "name": name if name != "0" else _label(d.get("id1")) or f"channel {i + 1}",
            "unit": unit or num, "den_unit": den_unit or den, "quantity": num, "den": den,
            "load_case": int(d.get("load_case_id", 0)), "where": where,
            "exp": tuple(int(d.get(f"{axis}_{q}_unit_exp", 0) or 0) for axis in ("abscissa", "ordinate", "orddenom")
                         for q in ("len", "force"))}


def _same_sampling(recs: list[dict], label: str) -> None:
    first = recs[0]
    for r in recs[1:]:
        if r["y"].size != first["y"].size:
            raise DataError(f"{r['where']}: {r['y'].size} samples, but {_first(first, r)} has "
                            f"{first['y'].size}; every function record must have the same length.")
        if abs(r["dx"] - first["dx"]) > 1e-9 * first["dx"] or abs(r["x0"] - first["x0"]) > 1e-6 * first["dx"]:
            raise DataError(f"{r['where']}: sampling step {r['dx']:g} from {r['x0']:g}, but {_first(first, r)} "
                            f"has step {first['dx']:g} from {first['x0']:g}; resample to a common grid first.")


def _first(first: dict, other: dict) -> str:
    """The first record as named from another's message: its set, and its file when that is another one."""
    same = first.get("file") == other.get("file")
    return f"data set #{first['set']}" if same else f"{first['where']}"


def _unique(names: list[str]) -> tuple[str, ...]:
    seen: dict[str, int] = {}
    out = []
    for n in names:
        seen[n] = seen.get(n, 0) + 1
        out.append(n if seen[n] == 1 else f"{n} ({seen[n]})")
    return tuple(out)


def _matrix(recs: list[dict], domain: str, label: str) -> Records:
    """FRFs or impulse responses arranged as outputs × references by response and reference node/direction."""
    outs, refs = [], []
    for r in recs:
        outs += [r["rsp"]] if r["rsp"] not in outs else []
        refs += [r["ref"]] if r["ref"] not in refs else []
    values = np.zeros((recs[0]["y"].size, len(outs), len(refs)), complex if domain == "frequency" else float)
    filled = np.zeros((len(outs), len(refs)), bool)
    first = {}
    for r in recs:
        i, j = outs.index(r["rsp"]), refs.index(r["ref"])
        if filled[i, j]:
            raise DataError(f"{r['where']}: a second record for response {_dof_label(*r['rsp'])} and reference "
                            f"{_dof_label(*r['ref'])} (the first is {_first(first[i, j], r)}); remove one.")
        values[:, i, j] = r["y"]
        filled[i, j] = True
        first[i, j] = r
    if not filled.all():
        i, j = np.argwhere(~filled)[0]
        raise DataError(f"{label}: no record for response {_dof_label(*outs[i])} and reference {_dof_label(*refs[j])}; "
                        f"the {len(outs)} × {len(refs)} matrix of outputs × references must be complete.")
    q = {r["quantity"] for r in recs}
    frf_type = _FRF_TYPE.get(q.pop()) if len(q) == 1 and {r["den"] for r in recs} == {"force"} else None
    return Records(domain=domain, values=[values], step=recs[0]["dx"], start=recs[0]["x0"],
                   outputs=_unique([first[i, 0]["name"] for i in range(len(outs))]),
                   output_units=tuple(f"{first[i, 0]['unit']}/{first[i, 0]['den_unit']}".strip("/")
                                      for i in range(len(outs))),
                   inputs=tuple(f"ref {_dof_label(*k)}" for k in refs),
                   input_units=tuple(first[0, j]["den_unit"] for j in range(len(refs))),
                   nodes=np.array([k[0] for k in outs]), directions=np.array([direction_vector(k[1]) for k in outs]),
                   frf_type=frf_type, points=_points(outs, refs),
                   described=[f"{len(recs)} UFF 58 {'FRF' if domain == 'frequency' else 'impulse response'} records "
                              f"(sets {recs[0]['set']}..{recs[-1]['set']}) as {counted(len(outs), 'output')} × "
                              f"{counted(len(refs), 'reference')}" + (f", {frf_type}" if frf_type else "")
                              + (f", {len(values)} lines every {significant(recs[0]['dx'])} Hz"
                                 if domain == "frequency" else f", {len(values)} samples, {sampling(recs[0]['dx'])}")])


def _points(outs: list, refs: list) -> dict | None:
    """Where the responses and references are (era.core.points): node and axis from each record's node and direction
    code ("4X"; "" when node or direction is 0), the code's sign apart. None when no reference is placed."""
    def side(keys):
        pts = tuple(f"{n}{_DIR_LABEL[abs(c)]}" if n and abs(c) in _DIR_LABEL else "" for n, c in keys)
        return pts, tuple(-1.0 if c < 0 else 1.0 for _, c in keys)

    (op, os_), (ip, is_) = side(outs), side(refs)
    if not any(ip):
        return None
    return {"output_points": op, "output_signs": os_, "input_points": ip, "input_signs": is_}


def _channels(recs: list[dict], label: str) -> Records:
    """Time records as channels; several load cases with the same channels become several records (tests)."""
    cases = sorted({r["load_case"] for r in recs})
    groups = [[r for r in recs if r["load_case"] == c] for c in cases]
    layout = [tuple(r["rsp"] for r in g) for g in groups]
    if len(groups) > 1 and len(set(layout)) != 1:
        groups = [recs]  # not a repeated test: one record of all channels
    g0 = groups[0]
    values = []
    for g in groups:  # one copy into column-major storage: each channel is one contiguous column
        v = np.empty((g[0]["y"].size, len(g)), order="F")
        for c, r in enumerate(g):
            v[:, c] = r["y"]
        values.append(v)
    return Records(domain="time", values=values, step=g0[0]["dx"], start=g0[0]["x0"],
                   outputs=_unique([r["name"] for r in g0]), output_units=tuple(r["unit"] for r in g0),
                   force=np.array([r["quantity"] == "force" or r["unit"].lower() in ("n", "lbf", "kn") for r in g0]),
                   nodes=np.array([r["rsp"][0] for r in g0]),
                   directions=np.array([direction_vector(r["rsp"][1]) for r in g0]),
                   described=[f"{len(recs)} UFF 58 time records (sets {recs[0]['set']}..{recs[-1]['set']}) as "
                              f"{counted(len(g0), 'channel')} × {counted(len(groups), 'record')} of "
                              f"{g0[0]['y'].size} samples, {sampling(g0[0]['dx'])}"])


@dataclass(frozen=True, eq=False)
class ModeSet:
    """Modes from UFF 55 (e.g. from a finite-element program), for comparison with identified ones.

    Read by :func:`era.read_modes_uff` (or :func:`era.load`, ``Dataset.modes``).

    Attributes
    ----------
    frequency_hz : ndarray, shape (modes,)
        Natural frequency of each mode, Hz.
    damping_ratio : ndarray, shape (modes,)
        Damping ratio of each mode (0 for normal modes).
    node_ids : int ndarray, shape (n,)
        The nodes' labels.
    shapes : complex ndarray, shape (n, 3, modes)
        Translations along global X, Y, Z at each node, in m (the file's UFF 164 length unit and its nodes'
        displacement systems, UFF 18/2420, applied).
    names : tuple of str, (modes,)
        The sets' id lines.

    Examples
    --------
    >>> modes = era.ModeSet(frequency_hz=np.array([1.5]), damping_ratio=np.zeros(1), node_ids=np.array([1, 2]),
    ...                     shapes=np.array([[[0], [0], [0.5]], [[0], [0], [1.0]]]), names=("FE mode 1",))
    >>> modes.shapes[:, 2, 0].tolist(), modes.names
    ([0.5, 1.0], ('FE mode 1',))
    """

    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    node_ids: np.ndarray
    shapes: np.ndarray
    names: tuple


def _modes(sets: list[tuple[int, int, dict]], label: str) -> ModeSet | None:
    modes = [(i, line, d) for i, line, d in sets if d.get("type") == 55 and int(d.get("analysis_type", 0)) in (2, 3, 7)]
    if not modes:
        return None
    nodes = np.asarray(modes[0][2]["node_nums"], dtype=int)
    freq, zeta, shapes, names = [], [], [], []
    for i, line, d in modes:
        where = _Where(label, i, line, 55)
        if not np.array_equal(np.asarray(d["node_nums"], dtype=int), nodes):
            raise DataError(f"{where}: its nodes differ from those of the first mode; every mode must list the same "
                            "nodes.")
        if int(d["analysis_type"]) == 2:
            f, z = float(d["freq"]), float(d.get("modal_damp_vis", 0.0))
        else:
            s = complex(d["eig"])
            f, z = abs(s) / 2 / np.pi, (-s.real / abs(s) if s else 0.0)
        columns = [np.asarray(d.get(f"r{k}", np.zeros(nodes.size)), dtype=complex).reshape(-1) for k in (1, 2, 3)]
        if any(c.size != nodes.size for c in columns):
            raise DataError(f"{where}: {[c.size for c in columns]} x/y/z values for {nodes.size} nodes; the data "
                            "set is truncated or corrupt.")
        shape = np.stack(columns, 1) / unit_factors(sets, label)[0]  # displacements in the file's length unit -> m
        check_finite(shape, where, row_name="node row")
        freq.append(f)
        zeta.append(z)
        shapes.append(shape)
        names.append(_label(d.get("id1")) or f"mode {len(names) + 1}")
    return ModeSet(np.array(freq), np.array(zeta), nodes, np.stack(shapes, axis=2), tuple(names))


def read_uff(path, label):
    """(Records or None, geometry parts, ModeSet or None) from a UFF file, or from several (``path`` and ``label``
    lists: one file per hammer hit or shaker reference, read as one test).

    Several files: FRF or impulse-response records of all files are assembled into outputs × references by their
    node/direction fields; time records are one record per file (several initial conditions or runs). The files
    must share the sampling, the length and the units of their records; the nodes they define are merged.
    """
    paths, labels = ([path], [label]) if isinstance(path, (str, os.PathLike)) else (list(path), list(label))
    per_file = [read_sets(os.fspath(p), lab) for p, lab in zip(paths, labels)]
    funcs, skipped = [], 0
    for sets, lab in zip(per_file, labels):
        found = [_function_record(i, line, d, lab) for i, line, d in sets if d.get("type") == 58]
        skipped += sum(f is None for f in found)
        factors = unit_factors(sets, lab)
        funcs += [_in_si(dict(f, file=lab), factors) for f in found if f is not None]
    records = None
    if funcs:
        domains = {f["domain"] for f in funcs}
        if len(domains) > 1:
            first = {d: next(f for f in funcs if f["domain"] == d) for d in domains}
            raise DataError(f"{' and '.join(str(first[d]['where']) for d in sorted(domains))}: "
                            f"{' and '.join(sorted(domains))} records mixed; load one kind of record at a time.")
        _same_sampling(funcs, labels[0])
        if len(paths) > 1:
            _same_units(funcs)
        domain = domains.pop()
        if domain != "time":
            records = _matrix(funcs, domain, ", ".join(labels))
        elif len(paths) == 1:
            records = _channels(funcs, labels[0])
        else:
            records = merge_records([_channels([f for f in funcs if f["file"] == lab], lab) for lab in labels
                             if any(f["file"] == lab for f in funcs)], labels)
        if len(paths) > 1:
            records.described.insert(0, f"{len(paths)} UFF files read as one test: {', '.join(labels)}")
        if any(f.get("si") for f in funcs):
            records.described.append("values converted to SI units with the files' UFF 164 unit factors")
        if skipped:
            records.described.append(f"{counted(skipped, 'other UFF 58 record')} (spectra, coherence, ...) not used")
    parts = merge_parts([geometry_parts(sets, lab) for sets, lab in zip(per_file, labels)], labels)
    if records is not None and records.nodes is not None and parts is not None:
        records = in_global_directions(records, parts)
    modes = [m for m in (_modes(sets, lab) for sets, lab in zip(per_file, labels)) if m is not None]
    if len(modes) > 1:
        raise DataError(f"{', '.join(labels)}: mode shapes (UFF 55) in more than one file; read mode files one by one "
                        "(era.read_modes_uff).")
    return records, parts, modes_in_global(modes[0], parts) if modes else None


_SI_LABEL = {"displacement": "m", "velocity": "m/s", "acceleration": "m/s^2", "force": "N"}


def _in_si(f: dict, factors: tuple[float, float]) -> dict:
    """A function record in SI units: values divided by length^e_L · force^e_F of its file's UFF 164 factors (the
    exponents of records 8-10), unit labels made SI; unchanged when the file is in SI or says no units."""
    length, force = factors
    if (length, force) == (1.0, 1.0):
        return f
    xl, xf, nl, nf, dl, df = f["exp"]
    scale = length ** (nl - dl) * force ** (nf - df)
    abscissa = length ** xl * force ** xf
    out = dict(f, y=f["y"] / scale if scale != 1 else f["y"], x0=f["x0"] / abscissa, dx=f["dx"] / abscissa,
               si=(scale != 1))
    if scale != 1:
        out["unit"] = _SI_LABEL.get(f["quantity"], f"{f['unit']} (SI)")
        out["den_unit"] = _SI_LABEL.get(f["den"], f["den_unit"]) if f["den_unit"] else ""
    return out


def _same_units(funcs: list[dict]) -> None:
    """Files of one test measure the same quantities: every record's units must be those of the first file's."""
    first = funcs[0]
    for f in funcs[1:]:
        if (f["unit"], f["den_unit"]) != (first["unit"], first["den_unit"]):
            raise DataError(f"{f['where']}: units {f['unit']}/{f['den_unit']} but {first['where']} has "
                            f"{first['unit']}/{first['den_unit']}; the files of one test must use the same units "
                            "(export them again with the same unit settings).")


def read_modes_uff(path) -> ModeSet:
    """The modes (UFF 55) in a file, in m along global X/Y/Z.

    Parameters
    ----------
    path : str or os.PathLike
        A universal file holding UFF 55 sets (and the UFF 15 nodes and UFF 164 units they refer to).

    Returns
    -------
    ModeSet

    Raises
    ------
    era.DataError
        When the file holds no modes.

    Examples
    --------
    >>> import os, tempfile
    >>> from era.examples import paper_cases
    >>> model = era.identify(paper_cases.case_1(), 40, 40).realize(10)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "modes.uff")
    ...     _ = era.save_modes_uff(path, model)
    ...     modes = era.read_modes_uff(path)
    >>> print(np.round(modes.frequency_hz, 3), modes.shapes.shape)
    [0.159 0.318 0.477 0.637 0.796] (1, 3, 5)
    """
    label = os.path.basename(str(path))
    sets = read_sets(str(path), label)
    modes = _modes(sets, label)
    if modes is None:
        raise DataError(f"{label}: no UFF 55 mode shapes (normal or complex modes) in this file.")
    return modes_in_global(modes, geometry_parts(sets, label))
