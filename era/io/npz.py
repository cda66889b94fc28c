"""era's own format: one NumPy .npz archive per dataset. :func:`save_npz` / :func:`npz_bytes` write it,
:func:`era.load` (:func:`read_npz`) reads it, and the web app stores its datasets in it.

Arrays of the archive (plain ``.npy`` members; strings are NumPy unicode arrays, never pickles):

========================  =========  =====================================================================
``markov``                (N, p, m)  float64 pulse responses, ``markov[k] = C A^k B`` (output per input unit)
``dt``                    ()         sampling interval Δτ in s
``outputs``               (p,)       output labels; absent: y1..yp
``inputs``                (m,)       input labels; absent: u1..um
``output_units``          (p,)       unit of each output (e.g. "mm"); absent: None (no units given)
``input_units``           (m,)       unit of each input (e.g. "N·s"); absent: None
``input_locations``       (m, d)     the point each input acts at: float (grid joints (x_ft, y_ft)) or str (an
                                     era.Frame's (node id, direction), e.g. ("E", "x"));
                                     ``ResponseData.meta["input_locations"]``, a tuple of m tuples; optional
``output_points``         (p,)       str point label of each output ("" unknown; setups.points), optional  } where the
``output_signs``          (p,)       float ±1, the output's sense along its point's axis, optional      } channels
``input_points``          (m,)       str point label of each input: where it was struck, optional      } are:
``input_signs``           (m,)       float ±1, the force's sense along its point's axis, optional       } meta
``name``                  ()         the dataset's name (e.g. the uploaded file name); optional
``records``               (n_b, N, p, m)  the pulse responses of each record (ResponseData.records); optional
``node_ids``              (n,)       int node labels                                 } the Geometry:
``coordinates``           (n, 3)     float x, y, z in ``geometry_units``             } all five or none
``edges``                 (e, 2)     int trace lines, row indices into ``node_ids``  }
``channel_nodes``         (p,)       int row index of each output's node, -1 unknown }
``channel_directions``    (p, 3)     float unit vector of each output's direction    }
``geometry_units``        ()         length unit of ``coordinates``; absent: "m"
``edge_lines``            (e,)       int trace line of each edge, row into ``line_ids``, -1 unknown } optional,
``line_ids``              (t,)       int trace line numbers as in the source file              } all three
``line_names``            (t,)       trace line descriptions ("" none)                         } or none
========================  =========  =====================================================================

The web app's store wrote a layout of its own before it used this one; :func:`read_npz` reads it too, so old data
folders keep working: the same ``markov``, ``dt``, ``name``, ``outputs``, ``inputs`` and ``input_locations``, the
units always present but meaning None when the 0-d bool ``has_output_units`` / ``has_input_units`` is false, and
the geometry as ``geo_node_ids``, ``geo_coordinates``, ``geo_edges``, ``geo_channel_nodes``,
``geo_channel_directions``, ``geo_units`` when the 0-d bool ``has_geometry`` is true.

Read without pickles, and every array's header is checked against the bytes the archive really holds before
anything is allocated: a header cannot make us reserve memory the file does not back.
"""

from __future__ import annotations

import io
import os
import zipfile

import numpy as np

from ..core.data import ResponseData
from ..errors import DataError
from ..core.geometry import Geometry
from .inflate import Budget

#: Largest array read from an NPZ file, in bytes (uncompressed).
MAX_ARRAY_BYTES = 2 << 30
_LABELS = ("outputs", "inputs", "output_units", "input_units")
_GEOMETRY = ("node_ids", "coordinates", "edges", "channel_nodes", "channel_directions")
#: The old store layout's names for the geometry arrays.
_LEGACY_GEOMETRY = {f"geo_{k}": k for k in _GEOMETRY} | {"geo_units": "geometry_units"}
#: The geometry's trace lines by name (optional; archives written before them have none).
_LINES = ("edge_lines", "line_ids", "line_names")
_FLAGS = ("has_output_units", "has_input_units", "has_geometry")
#: Where the channels are (era.core.points), kept in ResponseData.meta under the same names.
_POINTS = ("output_points", "output_signs", "input_points", "input_signs")
_NAMES = ("markov", "dt", *_LABELS, "input_locations", *_POINTS, "name", "records", *_GEOMETRY, "geometry_units", *_LINES,
          *_FLAGS, *_LEGACY_GEOMETRY)


def _read_member(zf: zipfile.ZipFile, info: zipfile.ZipInfo, label: str, budget: Budget) -> np.ndarray:
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
        buf = budget.read(fh, promised, where)  # claimed before it is inflated, then read in bounded chunks
    if len(buf) != promised:
        raise DataError(f"{where}: the archive ends after {len(buf)} of {promised} bytes; the file is truncated.")
    arr = np.frombuffer(buf, dtype=dtype)
    return arr.reshape(shape, order="F" if fortran else "C")


def read_arrays(raw: bytes, label: str, names, required=(), budget: Budget | None = None) -> dict[str, np.ndarray]:
    """The arrays ``names`` that the .npz bytes ``raw`` hold (absent ones left out), read safely (see above).

    Other members are not read. Raises DataError naming ``label`` for a bad archive or a missing ``required`` array,
    TooLargeError when the members read inflate past ``budget`` (era.io.inflate; their declared sizes are checked
    before anything is inflated).
    """
    budget = Budget(None) if budget is None else budget
    try:
        zf = zipfile.ZipFile(io.BytesIO(raw))
        infos = {i.filename[:-4] if i.filename.endswith(".npy") else i.filename: i for i in zf.infolist()}
    except (zipfile.BadZipFile, OSError, ValueError) as exc:
        raise DataError(f"{label}: not a readable .npz archive ({exc}).") from None
    missing = [k for k in required if k not in infos]
    if missing:
        raise DataError(f"{label}: the archive has no {' and no '.join(map(repr, missing))} array; it needs "
                        f"{' and '.join(required)} (found: {sorted(infos)}).")
    try:
        return {k: _read_member(zf, infos[k], label, budget) for k in names if k in infos}
    except (zipfile.BadZipFile, OSError, EOFError) as exc:  # CRC errors, cut archives
        raise DataError(f"{label}: the archive is corrupt ({exc}).") from None


def _one(arrays: dict, key: str, label: str, what: str):
    value = arrays[key]
    if value.size != 1:
        raise DataError(f"{label}: `{key}` must be {what}, got an array of shape {value.shape}.")
    return value.reshape(-1)[0]


def _from_legacy(arrays: dict) -> dict:
    """The old store layout's arrays under this format's names (units and geometry dropped where flagged absent)."""
    out = {k: v for k, v in arrays.items() if k not in _FLAGS and k not in _LEGACY_GEOMETRY}
    for key in ("output_units", "input_units"):
        if not np.any(arrays.get(f"has_{key}", True)):
            out.pop(key, None)
    if np.any(arrays.get("has_geometry", False)):
        out.update({new: arrays[old] for old, new in _LEGACY_GEOMETRY.items() if old in arrays})
    return out


def read_npz(raw: bytes, label: str, budget: Budget | None = None) -> tuple[ResponseData, Geometry | None,
                                                                           str | None, list[str]]:
    """(ResponseData, Geometry or None, the stored name or None, description) from the bytes of an .npz file.

    Reads this module's format and the store's old layout (module docstring); ``label`` names the file in errors;
    ``budget`` (era.io.inflate.Budget) bounds the uncompressed bytes read.
    """
    arrays = read_arrays(raw, label, _NAMES, required=("markov", "dt"), budget=budget)
    if any(k in arrays for k in _FLAGS):
        arrays = _from_legacy(arrays)
    dt = _one(arrays, "dt", label, "one number (seconds)")
    labels = {k: [str(x) for x in arrays[k].reshape(-1)] for k in _LABELS if k in arrays}
    try:
        data = ResponseData(markov=arrays["markov"], dt=dt, **labels, meta={"conversions": [], "source": "npz"},
                            records=arrays.get("records"))
    except DataError as exc:
        raise DataError(f"{label}: {exc}") from None
    if "input_locations" in arrays:
        where = arrays["input_locations"]
        if where.ndim != 2 or len(where) != data.n_inputs or where.dtype.kind not in "iufU":
            raise DataError(f"{label}: `input_locations` is {where.dtype} of shape {where.shape}; expected numbers or "
                            f"node names of shape (m, d) = ({data.n_inputs}, d), one point per input.")
        data.meta["input_locations"] = tuple(tuple(str(v) if where.dtype.kind == "U" else float(v) for v in row)
                                             for row in where)
    for key in _POINTS:
        if key in arrays:
            value = arrays[key].reshape(-1)
            n = data.n_outputs if key.startswith("output") else data.n_inputs
            if value.size != n or value.dtype.kind not in ("U" if key.endswith("points") else "iuf"):
                raise DataError(f"{label}: `{key}` is {value.dtype} of shape {value.shape}; expected {n} "
                                f"{'labels' if key.endswith('points') else 'signs (±1)'}, one per channel.")
            data.meta[key] = tuple(str(v) if value.dtype.kind == "U" else float(v) for v in value)
    name = str(_one(arrays, "name", label, "one string")) if "name" in arrays else None
    geometry = None
    present = [k for k in _GEOMETRY if k in arrays]
    if present:
        if len(present) != len(_GEOMETRY):
            raise DataError(f"{label}: geometry arrays {present} without {sorted(set(_GEOMETRY) - set(present))}; "
                            "give all five or none.")
        units = str(_one(arrays, "geometry_units", label, "one string")) if "geometry_units" in arrays else "m"
        lines = {k: arrays[k] for k in _LINES if k in arrays}
        if lines and len(lines) != len(_LINES):
            raise DataError(f"{label}: trace line arrays {sorted(lines)} without "
                            f"{sorted(set(_LINES) - set(lines))}; give all three or none.")
        try:
            geometry = Geometry(*(arrays[k] for k in _GEOMETRY), units=units, **lines)
        except DataError as exc:
            raise DataError(f"{label}: {exc}") from None
    return data, geometry, name, [f"{label}: markov {data.markov.shape}, dt = {data.dt:g} s"
                                  + (f", geometry of {geometry.n_nodes} nodes" if geometry else "")]


def npz_bytes(data: ResponseData, geometry: Geometry | None = None, *, name: str | None = None) -> bytes:
    """The .npz archive (module docstring) of ``data``, its ``geometry`` and ``name``, which :func:`read_npz` reads.

    Units given as None are left out (and read back as None); ``data.meta["input_locations"]``, (m, d) points, is
    kept. Uncompressed: measured responses hardly compress, and the app reads them back often.
    """
    arrays = {"markov": data.markov, "dt": np.array(data.dt)}
    arrays.update({k: np.array(getattr(data, k), dtype=str) for k in _LABELS if getattr(data, k) is not None})
    where = (data.meta or {}).get("input_locations")
    if where is not None:  # era.explain's residue term needs the input points
        named = any(isinstance(v, str) for row in where for v in row)
        where = np.array(where, dtype=str if named else float)
        if where.ndim != 2 or len(where) != data.n_inputs:
            raise DataError(f"data.meta['input_locations'] has shape {where.shape}; give one point per input, shape "
                            f"(m, d) = ({data.n_inputs}, d), or remove it.")
        arrays["input_locations"] = where
    for key in _POINTS:  # where the channels are: the point shapes (era.core.points) need them
        value = (data.meta or {}).get(key)
        if value is not None:
            arrays[key] = np.array(value, dtype=str if key.endswith("points") else float)
    if name is not None:
        arrays["name"] = np.array(str(name))
    if data.records is not None:  # the records' scatter gives σ (era.core.uncertainty)
        arrays["records"] = data.records
    if geometry is not None:
        arrays.update({k: getattr(geometry, k) for k in _GEOMETRY})
        arrays["geometry_units"] = np.array(geometry.units)
        if geometry.line_ids.size:
            arrays.update(edge_lines=geometry.edge_lines, line_ids=geometry.line_ids,
                          line_names=np.array(geometry.line_names, dtype=str))
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def save_npz(path, data: ResponseData, geometry: Geometry | None = None, *, name: str | None = None) -> None:
    """Write the pulse responses (and geometry) as an NPZ file, for :func:`era.load` to read back.

    The content is :func:`npz_bytes`.

    Parameters
    ----------
    path : str, os.PathLike or binary file object
        Where to write.
    data : ResponseData
        The pulse responses, their labels, units and records.
    geometry : Geometry, optional
        The test's nodes, trace lines and channel placement.
    name : str, optional
        A dataset name stored in the file (``Dataset.source["name"]`` when read back).

    Examples
    --------
    >>> import io
    >>> from era.examples import paper_cases
    >>> buffer = io.BytesIO()
    >>> era.save_npz(buffer, paper_cases.case_1(), name="Case I")
    >>> dataset = era.load(buffer.getvalue(), name="case1.npz")
    >>> dataset.data.markov.shape, dataset.source["name"], dataset.source["format"]
    ((200, 1, 1), 'Case I', 'npz')
    """
    blob = npz_bytes(data, geometry, name=name)
    if hasattr(path, "write"):
        path.write(blob)
        return
    with open(os.fspath(path), "wb") as fh:
        fh.write(blob)
