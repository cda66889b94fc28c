"""NumPy .npy: one array, samples × channels (or channels × samples); the sampling interval comes from a first
channel that is a time axis (era/io/arrays.py), else from ``dt``.

The header is checked against the bytes the file holds before anything is allocated; object arrays (pickles) are
refused. era/io/arrays.py turns the array into records.
"""

from __future__ import annotations

import io
import os
from dataclasses import replace

import numpy as np

from ..errors import DataError
from .arrays import Var, check_size, records_from_vars
from .records import Records

MAGIC = b"\x93NUMPY"


def read_npy(raw, label: str, dt: float | None = None, orientation: str | None = None) -> Records:
    """Records ("time") from an .npy file's bytes, or its path (read in place); ``dt`` in s (an .npy file carries
    no sampling)."""
    with (open(raw, "rb") if isinstance(raw, str) else io.BytesIO(raw)) as fh:
        size = fh.seek(0, os.SEEK_END)
        fh.seek(0)
        try:
            version = np.lib.format.read_magic(fh)
            shape, fortran, dtype = (np.lib.format.read_array_header_1_0(fh) if version == (1, 0)
                                     else np.lib.format.read_array_header_2_0(fh))
        except (ValueError, SyntaxError, TypeError) as exc:
            raise DataError(f"{label}: no valid .npy header ({exc}).") from None
        if dtype.hasobject:
            raise DataError(f"{label}: the array holds Python objects; only plain numbers are read (no pickles, for "
                            "safety). Save it with a numeric dtype.")
        offset = fh.tell()
        check_size(shape, dtype.itemsize, size - offset, f"{label}: array")
        count = int(np.prod(shape, dtype=np.int64))
        if count * dtype.itemsize != size - offset:
            raise DataError(f"{label}: the header promises shape {shape} of {dtype} ({count * dtype.itemsize} bytes) "
                            f"but the file holds {size - offset}; the file is truncated or corrupt.")

        def read():
            a = (np.fromfile(fh, dtype=dtype, count=count) if isinstance(raw, str)
                 else np.frombuffer(raw, dtype=dtype, count=count, offset=offset))
            return a.reshape(shape, order="F" if fortran else "C")

        name = os.path.splitext(label)[0] or "array"
        rec = records_from_vars([Var(name, tuple(shape), dtype.kind if dtype.fields is None else "?", read)],
                                label, "NumPy .npy", dt, None, orientation)
        return replace(rec, named=False)  # the names come from the file's name: several files match by position
