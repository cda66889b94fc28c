"""Plain HDF5 (.h5, .hdf5) and MATLAB v7.3 files through h5py.

The layout read (every name case-insensitive; era/io/arrays.py does the choosing):

- **data**: a real numeric dataset, 2-D samples × channels (channels × samples is recognised by its shape, or say
  ``orientation``), or several 1-D datasets of one length (one per channel), anywhere in the file. With more than
  one candidate, ``variable="path/to/dataset"`` (or a list of paths) chooses;
- **sampling**: a time vector dataset ``t``/``time`` (s), or a scalar dataset or attribute ``dt`` (s) or
  ``fs``/``sample_rate`` (Hz), on the data dataset, its group or the file's root;
- **labels**: attribute ``channels`` (one string per channel) and ``units`` (one string, or one per channel) on
  the data dataset;
- **points**: attribute ``points`` (one string per channel, "" unknown) on the data dataset: where each channel is
  ("4X": node 4 along X; era.core.points). A force channel's point is where the structure was struck or driven, a
  response's where it was measured; the import step's point column replaces them.

For example ``h5py.File("test.h5", "w")`` with ``f["acc"] = y`` (N × 3), ``f["acc"].attrs["units"] = "m/s^2"``,
``f.attrs["fs"] = 2048.0``. MATLAB v7.3 files are the same with MATLAB's transposition undone (an N × 3 MATLAB array
is stored 3 × N) and only numeric ``MATLAB_class`` datasets considered; a struct's fields are datasets in a group.

Before a dataset is read, its shape is checked against the bytes stored for it (uncompressed: all of them; filtered:
at most 1032:1), against the file's size and against the uncompressed bytes one read may produce (``budget``,
era/io/inflate.py; h5py fills an array of exactly the declared size, so no dataset inflates past it); virtual
datasets and external storage (other files) are refused, and external links are not followed.
"""

from __future__ import annotations

import io
import os

import numpy as np

from ..errors import DataError
from .arrays import DT_NAMES, FS_NAMES, Var, check_size, records_from_vars
from .inflate import Budget
from .records import Records

MAGIC = b"\x89HDF\r\n\x1a\n"
_MATLAB_NUMERIC = {b"double", b"single", b"int8", b"uint8", b"int16", b"uint16", b"int32", b"uint32", b"int64",
                   b"uint64"}
_LABELS = {"channels": "channels", "channel_names": "channels", "names": "channels", "units": "units",
           "unit": "units", "unit_string": "units", "points": "points"}


def _text(value):
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    if isinstance(value, np.ndarray) and value.dtype.kind in "SO":
        return [v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v) for v in value.reshape(-1)]
    return value


def _attrs(obj, label: str) -> dict:
    out = {}
    try:
        items = list(obj.attrs.items())
    except (OSError, KeyError, TypeError, ValueError):
        return out
    for key, value in items:
        k = key.lower()
        if k in _LABELS:
            out[_LABELS[k]] = _text(value)
        elif k in DT_NAMES or k in FS_NAMES:
            out[k] = value
    return out


def read_hdf5(raw, label: str, dt: float | None = None, variable=None, orientation: str | None = None,
              matlab: bool = False, budget: Budget | None = None) -> Records:
    """Records ("time") from an HDF5 (or MATLAB v7.3, ``matlab=True``) file's bytes or path; module docstring.
    ``budget`` (era.io.inflate.Budget) bounds the uncompressed bytes of the datasets read."""
    import h5py

    budget = Budget(None) if budget is None else budget
    size = os.path.getsize(raw) if isinstance(raw, str) else len(raw)
    try:
        f = h5py.File(raw if isinstance(raw, str) else io.BytesIO(raw), "r")
    except (OSError, ValueError, KeyError, RuntimeError) as exc:
        raise DataError(f"{label}: not a readable HDF5 file ({exc}).") from None
    with f:
        root = _attrs(f, label)
        vars_ = []

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and not name.startswith("#refs#"):
                vars_.append(_var(obj, name, root, size, label, matlab, budget))

        try:
            f.visititems(visit)
        except (OSError, KeyError, RuntimeError, ValueError) as exc:
            raise DataError(f"{label}: the HDF5 structure is corrupt ({exc}).") from None
        return records_from_vars(vars_, label, "MATLAB .mat (v7.3)" if matlab else "HDF5", dt, variable,
                                 orientation)


def _var(ds, name: str, root: dict, file_size: int, label: str, matlab: bool, budget: Budget) -> Var:
    where = f"{label}: dataset {name!r}"
    attrs = dict(root)
    parent = ds.parent
    if parent.name != "/":
        attrs.update(_attrs(parent, label))
    attrs.update(_attrs(ds, label))
    shape = tuple(int(x) for x in (ds.shape or ()))
    kind = ds.dtype.kind if ds.dtype.fields is None else "?"
    if matlab:
        cls = ds.attrs.get("MATLAB_class", b"")
        cls = cls if isinstance(cls, bytes) else str(cls).encode()
        if cls not in _MATLAB_NUMERIC or ds.attrs.get("MATLAB_empty", 0):
            kind = "?"
        shape = shape[::-1]  # MATLAB writes column-major: an N × 3 array is stored 3 × N
    if len(shape) == 2 and 1 in shape:
        shape = (max(shape),)

    def read():
        if ds.is_virtual or ds.external:
            raise DataError(f"{where} refers to data in other files (virtual or external storage); copy the data "
                            "into the file.")
        stored = int(ds.id.get_storage_size())
        filtered = bool(ds.compression) or bool(getattr(ds, "_filters", None))
        if stored > file_size:
            raise DataError(f"{where}: {stored} bytes stored in a file of {file_size}; the file is truncated.")
        check_size(ds.shape or (1,), ds.dtype.itemsize, stored, where, compressed=filtered)
        budget.claim(int(np.prod(ds.shape or (1,), dtype=np.float64)) * ds.dtype.itemsize, where)
        try:
            a = ds[()]
        except (OSError, ValueError, TypeError, RuntimeError) as exc:
            raise DataError(f"{where} cannot be read ({exc}); the file is truncated or corrupt.") from None
        a = np.asarray(a)
        if matlab:
            a = a.T
        return a.reshape(-1) if a.ndim == 2 and 1 in a.shape else a

    return Var(name, shape, kind, read, attrs)
