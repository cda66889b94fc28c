"""The app's own format: NumPy .npz with `markov` (N, p, m) and `dt`, optional labels and geometry arrays.

Read without pickles, and every array's header is checked against the bytes the archive really holds before
anything is allocated: a header cannot make us reserve memory the file does not back.
"""

from __future__ import annotations

import io
import zipfile

import numpy as np

from ..data import ResponseData
from ..errors import DataError
from ..geometry import Geometry

#: Largest array read from an NPZ file, in bytes (uncompressed).
MAX_ARRAY_BYTES = 2 << 30
_LABELS = ("outputs", "inputs", "output_units", "input_units")
_GEOMETRY = ("node_ids", "coordinates", "edges", "channel_nodes", "channel_directions")


def _read_member(zf: zipfile.ZipFile, info: zipfile.ZipInfo, label: str) -> np.ndarray:
    where = f"{label}: array {info.filename!r}"
    with zf.open(info) as fh:
        try:
            version = np.lib.format.read_magic(fh)
            shape, fortran, dtype = (np.lib.format.read_array_header_1_0(fh) if version == (1, 0)
                                     else np.lib.format.read_array_header_2_0(fh))
        except ValueError as exc:
            raise DataError(f"{where} has no valid .npy header ({exc}).") from None
        if dtype.hasobject:
            raise DataError(f"{where} holds Python objects; only plain numeric or string arrays are read (no "
                            "pickles, for safety).")
        header_len = fh.tell()
        promised = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
        held = info.file_size - header_len
        if promised != held:
            raise DataError(f"{where}: the header promises shape {shape} of {dtype} ({promised} bytes) but the file "
                            f"holds {held} bytes; the file is truncated or corrupt.")
        if promised > MAX_ARRAY_BYTES:
            raise DataError(f"{where}: {promised / 2**30:.1f} GiB is above the "
                            f"{MAX_ARRAY_BYTES / 2**30:.0f} GiB limit.")
        buf = fh.read(promised)
    if len(buf) != promised:
        raise DataError(f"{where}: the archive ends after {len(buf)} of {promised} bytes; the file is truncated.")
    arr = np.frombuffer(buf, dtype=dtype)
    return arr.reshape(shape, order="F" if fortran else "C")


def read_npz(raw: bytes, label: str) -> tuple[ResponseData, Geometry | None, list[str]]:
    """(ResponseData, Geometry or None, description) from the bytes of an .npz file."""
    try:
        zf = zipfile.ZipFile(io.BytesIO(raw))
        infos = {i.filename[:-4] if i.filename.endswith(".npy") else i.filename: i for i in zf.infolist()}
    except (zipfile.BadZipFile, OSError, ValueError) as exc:
        raise DataError(f"{label}: not a readable .npz archive ({exc}).") from None
    missing = [k for k in ("markov", "dt") if k not in infos]
    if missing:
        raise DataError(f"{label}: the archive has no {' and no '.join(map(repr, missing))} array; an era .npz holds "
                        f"markov (N, p, m) and dt (found: {sorted(infos)}).")
    try:
        arrays = {k: _read_member(zf, infos[k], label) for k in ("markov", "dt", *_LABELS, *_GEOMETRY, "geometry_units")
                  if k in infos}
    except (zipfile.BadZipFile, OSError, EOFError) as exc:  # CRC errors, cut archives
        raise DataError(f"{label}: the archive is corrupt ({exc}).") from None
    dt = arrays["dt"]
    if dt.size != 1:
        raise DataError(f"{label}: `dt` must be one number (seconds), got shape {dt.shape}.")
    labels = {k: [str(x) for x in arrays[k].reshape(-1)] for k in _LABELS if k in arrays}
    try:
        data = ResponseData(markov=arrays["markov"], dt=float(dt.reshape(-1)[0]), **labels,
                            meta={"conversions": [], "source": "npz"})
    except DataError as exc:
        raise DataError(f"{label}: {exc}") from None
    geometry = None
    present = [k for k in _GEOMETRY if k in arrays]
    if present:
        if len(present) != len(_GEOMETRY):
            raise DataError(f"{label}: geometry arrays {present} without {sorted(set(_GEOMETRY) - set(present))}; "
                            "give all five or none.")
        units = str(arrays["geometry_units"].reshape(-1)[0]) if "geometry_units" in arrays else "m"
        try:
            geometry = Geometry(*(arrays[k] for k in _GEOMETRY), units=units)
        except DataError as exc:
            raise DataError(f"{label}: {exc}") from None
    return data, geometry, [f"{label}: markov {data.markov.shape}, dt = {data.dt:g} s"
                            + (f", geometry of {geometry.n_nodes} nodes" if geometry else "")]


def save_npz(path, data: ResponseData, geometry: Geometry | None = None) -> None:
    """Write ResponseData (and geometry) in the format :func:`era.load` reads back. path: str or binary file."""
    arrays = {"markov": data.markov, "dt": np.array(data.dt)}
    for k in _LABELS:
        if getattr(data, k) is not None:
            arrays[k] = np.array(getattr(data, k), dtype=str)
    if geometry is not None:
        arrays.update({k: getattr(geometry, k) for k in _GEOMETRY})
        arrays["geometry_units"] = np.array(geometry.units)
    np.savez_compressed(path, **arrays)
