"""MATLAB .mat files: v4/v5/v7 through scipy.io (whosmat lists, loadmat reads only the arrays chosen), v7.3 (HDF5)
through era/io/hdf5.py. Variables are chosen by name (era/io/arrays.py): the data, and ``fs``/``dt``/a time
vector; a struct's fields are read in v7.3 (HDF5 groups), top-level variables in v5.

A v5 file's compressed variables are measured before scipy inflates any: the whole file's uncompressed size (each
compressed element inflated in bounded chunks, nothing kept) and each variable's declared size must fit the read's
``budget`` (era/io/inflate.py).
"""

from __future__ import annotations

import io
import struct
import zlib

import numpy as np

from ..errors import DataError
from .arrays import Var, check_size, records_from_vars
from .inflate import Budget
from .records import Records

MAGIC_V5 = b"MATLAB 5.0 MAT-file"
MAGIC_V73 = b"MATLAB 7.3 MAT-file"
_ITEMSIZE = {"double": 8, "single": 4, "int8": 1, "uint8": 1, "int16": 2, "uint16": 2, "int32": 4, "uint32": 4,
             "int64": 8, "uint64": 8, "logical": 1}
_KIND = {"double": "f", "single": "f", "int8": "i", "int16": "i", "int32": "i", "int64": "i", "uint8": "u",
         "uint16": "u", "uint32": "u", "uint64": "u"}


def is_v73(raw: bytes) -> bool:
    return raw[:19] == MAGIC_V73 or raw[512:520] == b"\x89HDF\r\n\x1a\n"


_MI_COMPRESSED = 15


def _measure_v5(raw: bytes, label: str, limit: int | None) -> None:
    """TooLargeError when the v5 file's compressed elements inflate past ``limit`` bytes in all (measured in
    bounded chunks, stopping at the limit). A malformed file is left for scipy to refuse."""
    if limit is None or len(raw) < 136:
        return
    order = "<" if raw[126:128] == b"IM" else ">"
    measure, pos = Budget(limit), 128
    while pos + 8 <= len(raw):
        mdtype, nbytes = struct.unpack(order + "II", raw[pos:pos + 8])
        pos += 8
        if mdtype == _MI_COMPRESSED:
            try:
                measure.inflate_size(raw[pos:pos + nbytes], f"{label}: the compressed variables")
            except zlib.error:
                return
        pos += nbytes


def read_mat(raw: bytes, label: str, dt: float | None = None, variable=None,
             orientation: str | None = None, budget: Budget | None = None) -> Records:
    """Records ("time") from the bytes of a .mat file; ``variable`` names the data (str or list) when ambiguous;
    ``budget`` (era.io.inflate.Budget) bounds the uncompressed bytes (module docstring)."""
    budget = Budget(None) if budget is None else budget
    if is_v73(raw):
        from .hdf5 import read_hdf5
        return read_hdf5(raw, label, dt, variable, orientation, matlab=True, budget=budget)
    import scipy.io

    _measure_v5(raw, label, budget.limit)

    try:
        listing = scipy.io.whosmat(io.BytesIO(raw))
    except (ValueError, TypeError, OSError, EOFError, IndexError, KeyError, MemoryError, NotImplementedError,
            UnicodeDecodeError) as exc:
        raise DataError(f"{label}: not a readable MATLAB file ({type(exc).__name__}: {exc}). Save it again with "
                        "save(..., '-v7') or '-v7.3'.") from None

    def reader(name: str, shape, cls: str):
        def read():
            check_size(shape, _ITEMSIZE.get(cls, 8), len(raw), f"{label}: variable {name!r}", compressed=True)
            budget.claim(int(np.prod(shape, dtype=np.float64)) * _ITEMSIZE.get(cls, 8), f"{label}: variable {name!r}")
            try:
                value = scipy.io.loadmat(io.BytesIO(raw), variable_names=[name], squeeze_me=False,
                                         mat_dtype=False)[name]
            except (ValueError, TypeError, OSError, EOFError, IndexError, KeyError, MemoryError) as exc:
                raise DataError(f"{label}: variable {name!r} cannot be read ({type(exc).__name__}: {exc}); the file "
                                "is truncated or corrupt.") from None
            a = np.asarray(value)
            return a.reshape(-1) if a.ndim == 2 and 1 in a.shape else a
        return read

    vars_ = []
    for name, shape, cls in listing:
        shape = tuple(int(x) for x in shape)
        squeezed = tuple(x for x in shape if x != 1) if len(shape) == 2 and 1 in shape else shape
        vars_.append(Var(name, squeezed if squeezed else (1,), _KIND.get(cls, "?"), reader(name, shape, cls)))
    return records_from_vars(vars_, label, "MATLAB .mat (v5)", dt, variable, orientation)
