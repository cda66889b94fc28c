"""Reading test data: ``era.load`` turns a file (or several) into Markov parameters, geometry and provenance.

This module only recognises the format (:func:`sniff`: content first, then the extension) and dispatches. One
module per format returns what the file holds as :class:`Records` (uff.py, csv.py, lvm.py, ...; npz.py reads era's
own format straight into ResponseData); records.py picks the conversion (era.markov).
"""

from __future__ import annotations

import os
import struct
import tempfile
from contextlib import contextmanager
from dataclasses import dataclass, field, replace

import numpy as np

from ..core.data import ResponseData
from ..errors import DataError, EraError
from ..core.geometry import Geometry
from ..words import listed
from .csv import read_csv
from .hdf5 import read_hdf5
from .inflate import Budget
from .lvm import read_lvm
from .mat import read_mat
from .npy import read_npy
from .npz import npz_bytes, read_arrays, read_npz, save_npz
from .choices import choose, renumber
from .records import Records, merge_records, to_response
from .signalcalc import is_setup, is_signalcalc, read_signalcalc
from .tdms import read_tdms
from .uff import ModeSet, read_modes_uff, read_uff
from .uff_geometry import build_geometry
from .uff_write import save_modes_uff

FORMATS = ("uff", "csv", "text", "npz", "lvm", "npy", "mat", "hdf5", "tdms", "signalcalc")
_EXTENSIONS = {".uff": "uff", ".unv": "uff", ".uf": "uff", ".csv": "csv", ".txt": "csv", ".tsv": "csv",
               ".dat": "csv", ".npz": "npz", ".lvm": "lvm", ".npy": "npy", ".mat": "mat", ".h5": "hdf5",
               ".hdf5": "hdf5", ".hdf": "hdf5", ".he5": "hdf5", ".tdms": "tdms"}
#: Content that names its format, looked for at the start of the file (after a UTF-8 byte-order mark).
_MAGIC = ((b"PK\x03\x04", "npz"), (b"LabVIEW Measurement", "lvm"), (b"\x89HDF\r\n\x1a\n", "hdf5"),
          (b"MATLAB 5.0 MAT-file", "mat"), (b"MATLAB 7.3 MAT-file", "mat"), (b"TDSm", "tdms"),
          (b"\x93NUMPY", "npy"))
#: Readers of time records from one file's bytes: (raw, label, dt, **how) -> Records.
_TIME_READERS = {"csv": read_csv, "text": read_csv, "lvm": read_lvm, "npy": read_npy, "mat": read_mat,
                 "hdf5": read_hdf5, "tdms": read_tdms}
#: Readers of compressed content: they take the read's ``budget`` of uncompressed bytes (era/io/inflate.py).
_INFLATING = ("mat", "hdf5")
#: Readers that take a path on disk themselves (a large binary file is then not copied into memory first).
_PATH_READERS = ("npy", "hdf5", "tdms")
#: Options that say how to read a file (the others go to the conversion), and the formats that take each.
_READER_OPTIONS = {"orientation": ("csv", "text", "npy", "mat", "hdf5"), "variable": ("mat", "hdf5"),
                   "group": ("tdms",), "resample": ("csv", "text")}


@dataclass(frozen=True, eq=False)
class Dataset:
    """What :func:`load` read.

    Attributes
    ----------
    data : ResponseData or None
        The pulse responses; None when the file holds only geometry and/or modes (UFF 15/82/55).
    geometry : Geometry or None
        The test's nodes and trace lines; its channels are the outputs of ``data``.
    source : dict
        For reports: "file", "format", "kind" (conversion used), "records" (what was read), "conversions" (what
        was done to it, in order), "outputs"/"inputs" with units, "channels_read" (every channel as read, before
        any was dropped); for NPZ also "name", the dataset name stored in the file (or None).
    modes : ModeSet or None
        Modes stored in the file (UFF 55), e.g. from a finite-element program.

    Examples
    --------
    >>> import io
    >>> from era.examples import paper_cases
    >>> buffer = io.BytesIO()
    >>> era.save_npz(buffer, paper_cases.case_2())
    >>> dataset = era.load(buffer.getvalue(), name="case2.npz")
    >>> dataset.data.outputs, dataset.geometry, dataset.modes
    (('sensor 1', 'sensor 2'), None, None)
    """

    data: ResponseData | None
    geometry: Geometry | None
    source: dict = field(default_factory=dict)
    modes: ModeSet | None = None


#: Bytes read from the start of a file on disk to recognise its format.
_SNIFF_BYTES = 1 << 16


def _read_bytes(src, name: str | None) -> tuple[bytes, str]:
    """The content (or, for a file on disk, its first bytes: UFF is parsed from the path) and a label."""
    if isinstance(src, (bytes, bytearray, memoryview)):
        return bytes(src), name or "uploaded data"
    if hasattr(src, "read"):
        raw = src.read()
        if isinstance(raw, str):
            raise DataError("Open the file in binary mode ('rb') or pass bytes.")
        return raw, name or os.path.basename(str(getattr(src, "name", "uploaded file")))
    path = os.fspath(src)
    if not os.path.isfile(path):
        raise DataError(f"{path}: no such file.")
    with open(path, "rb") as fh:
        return fh.read(_SNIFF_BYTES), name or os.path.basename(path)


def _whole(raw: bytes, src) -> bytes:
    """All of a file whose first bytes _read_bytes took."""
    if isinstance(src, (str, os.PathLike)) and len(raw) == _SNIFF_BYTES:
        with open(os.fspath(src), "rb") as fh:
            return fh.read()
    return raw


def sniff(raw: bytes, name: str) -> str:
    """The format from the content (magic bytes, the UFF delimiter), then the file name's extension."""
    if not raw.strip():
        raise DataError(f"{name}: the file is empty.")
    head = raw[3:] if raw.startswith(b"\xef\xbb\xbf") else raw
    for magic, fmt in _MAGIC:
        if head.startswith(magic):
            return fmt
    if is_signalcalc(raw):
        return "signalcalc"
    head = raw.lstrip(b"\r\n\t ")[:8]
    if head.startswith(b"-1") and raw.lstrip(b"\r\n")[:6] == b"    -1":
        return "uff"
    ext = os.path.splitext(name)[1].lower()
    if ext in _EXTENSIONS and _EXTENSIONS[ext] != "npz":
        return _EXTENSIONS[ext]
    sample = raw[:4096]
    if b"\x00" in sample or sum(b < 9 or 13 < b < 32 for b in sample) > 0.01 * len(sample):
        raise DataError(f"{name}: binary content that is none of the formats read: UFF (58/58b, 15, 82, 55), CSV/text, "
                        "LabVIEW LVM, NumPy .npy/.npz, MATLAB .mat, HDF5 and NI TDMS.")
    return "csv"


def load(source, format: str | None = None, *, name: str | None = None, kind: str = "auto",
         dt: float | None = None, start_sample: int | None = None, drop=None, forces=None, points=None,
         max_bytes: int | None = None, **options) -> Dataset:
    r"""Read test data and turn it into Markov parameters for :func:`era.identify`.

    Parameters
    ----------
    source : path, bytes, binary file object, or a list of them
        A list is read as one dataset: UFF files (one per hammer hit or shaker reference) assembled into
        outputs × references by node and direction; SignalCalc FRF files by their channels, or in the order given
        when they all name the same channels (a roving hammer); time files (CSV, LVM, MAT, TDMS, ...) as one
        record each (several initial conditions or runs).
    format : str, optional
        One of FORMATS ("uff", "csv", "text", "npz", "lvm", "npy", "mat", "hdf5", "tdms", "signalcalc"); None
        (default): sniffed from the content, then the extension of ``name``/the path.
    name : str, optional
        The original file name of an upload (for sniffing and messages).
    kind : str, optional
        "auto" (default) or the conversion ("frf", "pulse", "decay", "io", "ambient"); see
        era.io.records.to_response.
    dt : float, optional
        Sampling interval in s, used only when a file carries none (text without a time column, an LVM file
        without X_Value column or Delta_X, .npy, .mat/HDF5 without fs/dt/time, TDMS without wf_increment).
    start_sample : int, optional
        Samples skipped at the start of every record (pre-trigger): the person's choice
        (era.io.choices.choose).
    drop : sequence of str or int, optional
        Channels left out (names or 0-based positions as read).
    forces : sequence of str or int, optional
        The channels that measure the excitation (names or 0-based positions).
    points : dict, optional
        Where time channels are, {channel (name or 0-based position as read): point label ("4X")}: a force
        channel's point is where the structure was struck (``ResponseData.meta["input_points"]``), a response's
        where it was measured (``output_points``); era.core.points then gives the shape at every such point.
    max_bytes : int, optional
        The uncompressed bytes all the files together may inflate to (NPZ members, HDF5 datasets, MATLAB
        variables), checked before anything is inflated and while it is (era/io/inflate.py); TooLargeError above
        it. None (default): no such limit (each array still at most 2 GiB).
    **options
        For the readers: ``orientation`` ("rows" or "columns": where the channels are in headerless text, .npy,
        .mat and HDF5 arrays; default from the shape, the longer side is time), ``variable`` (the .mat
        variable(s) or HDF5 dataset path(s) holding the data, when the file has several candidates), ``group``
        (the TDMS group to read, when groups hold different channels), ``resample`` (True to resample CSV/text
        records whose time stamps scatter about a steady rate onto an even grid at the mean rate, by linear
        interpolation; without it such a file is refused, never resampled silently). The others go to the
        conversion (e.g. ``band_hz``, ``n_observer``, ``references``, ``n_lags``).

    Returns
    -------
    Dataset
        The pulse responses, the geometry and the modes the files hold, and what was done to them.

    Raises
    ------
    era.DataError
        Naming the file, record or line and what is wrong (``option`` names the parameter that fixes it, when
        one does).
    era.TooLargeError
        When the files would inflate past ``max_bytes``.

    Examples
    --------
    A CSV file of a free decay at two sensors, read from bytes:

    >>> t = np.arange(500) * 0.01
    >>> y = np.exp(-0.02 * 2 * np.pi * 3 * t) * np.cos(2 * np.pi * 3 * t)
    >>> text = "time,tip,root\n" + "\n".join(f"{a:.2f},{b:.6f},{b / 2:.6f}" for a, b in zip(t, y))
    >>> dataset = era.load(text.encode(), name="decay.csv", kind="decay")
    >>> dataset.data.markov.shape, dataset.data.outputs, round(dataset.data.dt, 6)
    ((499, 2, 1), ('tip', 'root'), 0.01)
    >>> dataset.source["format"], dataset.source["kind"], dataset.geometry
    ('csv', 'decay', None)
    """
    how = {k: options.pop(k) for k in list(options) if k in _READER_OPTIONS}
    got = read(source, format, name=name, dt=dt, max_bytes=max_bytes, **how)
    return convert(got, kind=kind, start_sample=start_sample, drop=drop, forces=forces, points=points, **options)


def convert(got: "Read", *, kind: str = "auto", start_sample: int | None = None, drop=None, forces=None,
            points=None, **options) -> Dataset:
    """The second half of :func:`load`: the person's choices and the conversion to Markov parameters of files
    already read (:func:`read`, or a preview's ``read``), so a preview and the dataset made after it read the
    files once. ``kind``, ``start_sample``, ``drop``, ``forces``, ``points`` and ``options`` as in :func:`load`;
    ``got`` is not changed, so it may be converted again with other choices."""
    if got.npz is not None:
        if start_sample or drop or forces is not None or points:
            raise DataError(f"{got.labels[0]}: an NPZ file holds era's pulse responses; start_sample, drop, forces "
                            "and points apply to records as measured. Leave them out.")
        return got.npz
    rec = got.records
    if rec is not None:
        if options.get("references") is not None:  # NExT references are named as read, like drop and forces
            options["references"] = renumber(rec, drop, options["references"], "references")
        rec = _guarded(got, lambda: choose(rec, start_sample=start_sample, drop=drop, forces=forces, points=points))
    out = _guarded(got, lambda: _convert(rec, got.parts, got.modes, got.labels, got.format, kind, options))
    if got.records is not None:
        out.source["channels_read"] = list(got.records.outputs)  # what drop/forces/references positions name
    return out


@dataclass(frozen=True, eq=False)
class Read:
    """What the files hold before any choice or conversion (:func:`read`).

    labels : the file names; format : the format read; records : Records or None (a UFF file of geometry/modes
    only); parts, modes : UFF geometry parts and mode sets (or None); npz : the Dataset of an NPZ file (era's own
    format holds Markov parameters already), else None.
    """

    labels: list
    format: str
    records: Records | None = None
    parts: object = None
    modes: ModeSet | None = None
    npz: Dataset | None = None


def read(source, format: str | None = None, *, name: str | None = None, dt: float | None = None,
         max_bytes: int | None = None, **how) -> Read:
    """Read files as they are: the first half of :func:`load` (same ``source``, ``format``, ``name``, ``dt``,
    ``max_bytes`` and reader options ``orientation``, ``variable``, ``group``), for a preview before anything is
    converted."""
    unknown = set(how) - set(_READER_OPTIONS)
    if unknown:
        raise DataError(f"Unknown reading {'options' if len(unknown) > 1 else 'option'} "
                        f"{listed(sorted(unknown), quote=True)}; the readers take "
                        f"{listed(sorted(_READER_OPTIONS), quote=True)}.")
    how = {k: v for k, v in how.items() if v is not None and v is not False}
    sources = list(source) if isinstance(source, (list, tuple)) else [source]
    if not sources:
        raise DataError("No file given.")
    raws = [_read_bytes(s, name if len(sources) == 1 else None) for s in sources]
    setup = None
    if len(raws) > 1 and (format is None or format.lower() == "signalcalc"):  # a roving-hammer test's setup table
        at = [k for k, (raw, _) in enumerate(raws) if is_setup(raw)]
        if len(at) > 1:
            raise DataError(f"{', '.join(raws[k][1] for k in at)}: several setup tables; give the test's one.")
        if at:
            k = at[0]
            setup = (_whole(raws[k][0], sources[k]), raws[k][1])
            raws, sources = raws[:k] + raws[k + 1:], sources[:k] + sources[k + 1:]
            if not is_signalcalc(raws[0][0]):
                raise DataError(f"{setup[1]}: a roving-hammer setup table, read with SignalCalc FRF files only; "
                                f"{raws[0][1]} is not one.")
    labels = [lab for _, lab in raws]
    fmt = format.lower() if format else sniff(raws[0][0], labels[0])
    if fmt not in FORMATS:
        raise DataError(f"`format` must be one of {FORMATS} or None, got {format!r}.", option="format")
    for raw, lab in raws:
        if not raw.strip():
            raise DataError(f"{lab}: the file is empty.")
    for k in how:
        if fmt not in _READER_OPTIONS[k]:
            raise DataError(f"{labels[0]}: `{k}` applies to {'/'.join(_READER_OPTIONS[k]).upper()} files, not to "
                            f"{fmt.upper()}; leave it out.", option=k)
    if len(raws) > 1 and fmt == "npz":
        raise DataError(f"{', '.join(labels)}: NPZ files hold a whole dataset each; load them one by one.")
    if len(raws) > 1 and format is None:
        for raw, lab in raws[1:]:
            other = sniff(raw, lab)
            if other != fmt and {other, fmt} != {"csv", "text"}:
                raise DataError(f"{lab} is {other.upper()} but {labels[0]} is {fmt.upper()}; the files of one "
                                "dataset must share one format.")
    got = Read(labels, fmt)
    budget = Budget(max_bytes)  # shared by every file of this read
    if fmt == "npz":
        data, geometry, stored_name, described = read_npz(_whole(raws[0][0], sources[0]), labels[0], budget)
        return replace(got, npz=Dataset(data, geometry, dict(_source(labels, fmt, "markov", described, data),
                                                             name=stored_name), None))

    def records():
        if fmt in _TIME_READERS:
            reader = _TIME_READERS[fmt]
            more = dict(how, budget=budget) if fmt in _INFLATING else how
            return replace(got, records=merge_records([reader(_payload(fmt, raw, src), lab, dt, **more)
                                               for (raw, lab), src in zip(raws, sources)], labels))
        if fmt == "signalcalc":
            rec, parts = read_signalcalc([_whole(raw, src) for (raw, _), src in zip(raws, sources)], labels, setup)
            return replace(got, records=rec, parts=parts)
        with _on_disk([r for r, _ in raws], sources) as paths:  # messages may count lines until the end
            rec, parts, modes = read_uff(paths if len(paths) > 1 else paths[0],
                                         labels if len(paths) > 1 else labels[0])
        return replace(got, records=rec, parts=parts, modes=modes)

    return _guarded(got, records)


def _guarded(got: Read, work):
    """``work()``, with a malformed file's stray exception turned into a DataError naming the file."""
    try:
        return work()
    except EraError:
        raise
    except MemoryError:
        raise DataError(f"{got.labels[0]}: too large to read into memory; load a part of it.") from None
    except (ValueError, TypeError, IndexError, KeyError, OverflowError, struct.error, OSError, EOFError,
            RuntimeError) as exc:
        # last resort: a malformed file that slipped past the checks must still not surface as a stack trace
        raise DataError(f"{got.labels[0]}: cannot be read as {got.format.upper()} ({type(exc).__name__}: {exc}).") \
            from None


def _convert(rec, parts, modes, labels, fmt, kind, options) -> Dataset:
    if rec is None:
        if parts is None and modes is None:
            raise DataError(f"{labels[0]}: no function records (UFF 58), nodes (15/2411) or modes (55) in this file.")
        geometry = build_geometry(parts, None, None, labels[0])
        return Dataset(None, geometry, _source(labels, fmt, None, ["geometry/modes only"], None), modes)
    try:
        data, used = to_response(rec, kind, **options)
    except TypeError as exc:  # an option the conversion does not take
        raise DataError(f"{labels[0]}: {exc}") from None
    geometry = None
    if rec.nodes is not None:
        keep = ~rec.force if used == "io" and rec.force is not None else np.ones(len(rec.nodes), bool)
        geometry = build_geometry(parts, rec.nodes[keep], rec.directions[keep], labels[0])
    out = Dataset(data, geometry, _source(labels, fmt, used, rec.described, data), modes)
    out.source["conversions"][:0] = rec.conversions  # what the reader did comes first
    return out


def _payload(fmt: str, raw: bytes, src):
    """What a reader gets: the path of a file on disk for the readers that open it themselves, else all its bytes."""
    if fmt in _PATH_READERS and isinstance(src, (str, os.PathLike)):
        return os.fspath(src)
    return _whole(raw, src)


@contextmanager
def _on_disk(raws: list[bytes], sources: list):
    """Paths to the files for pyuff: the caller's own, or temporary copies of uploaded bytes."""
    with tempfile.TemporaryDirectory() as tmp:
        paths = []
        for k, (raw, src) in enumerate(zip(raws, sources)):
            if isinstance(src, (str, os.PathLike)):
                paths.append(os.fspath(src))
                continue
            paths.append(os.path.join(tmp, f"upload{k}.uff"))
            with open(paths[-1], "wb") as fh:
                fh.write(raw)
        yield paths


def _source(labels, fmt, kind, described, data) -> dict:
    out = {"file": labels[0] if len(labels) == 1 else labels, "format": fmt, "kind": kind, "records": described,
           "conversions": list(data.meta.get("conversions", [])) if data is not None else []}
    if data is not None:
        out.update(outputs=list(data.outputs), inputs=list(data.inputs), output_units=data.output_units,
                   input_units=data.input_units, dt_s=data.dt, shape=list(data.markov.shape))
    return out


__all__ = ["load", "read", "convert", "Read", "choose", "Dataset", "ModeSet", "Records", "read_modes_uff", "save_modes_uff",
           "save_npz", "npz_bytes", "read_npz", "read_arrays",
           "sniff"]
