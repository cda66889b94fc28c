"""Resuming a campaign: each finished record's modes stored in a folder, under a key of its content and settings.

A record's key is the SHA-256 of the campaign's settings (:meth:`CampaignSettings.fingerprint`) and of the file's
bytes, so a changed file or setting is analysed again, and a renamed or moved file is not. Entries are small JSON files
(no pickles: a cache folder must not be able to run code) written atomically (a temporary file, then
``os.replace``), so a campaign killed mid-write leaves no half entry. Only records that were analysed are
stored; failures are tried again on the next run.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile

import numpy as np

from .record import DiagramPoles, RecordModes

_ARRAYS = ("frequency_hz", "frequency_std_hz", "damping_ratio", "damping_std", "emac", "mpc")
#: 3: with the diagram's poles (2: the modes era.choose_modes chose, at one order, with the data's σ; 1: the
#: campaign's own rule)
_VERSION = 3
_POLE_ARRAYS = ("order", "frequency_hz", "damping_ratio", "emac", "mpc", "cluster")


def record_key(source, fingerprint: str) -> str:
    """Hex key of one record: its content (bytes, or the file a path names) and the campaign's settings.

    A path this process cannot read (a file only the cluster's workers see) is keyed by its absolute path."""
    h = hashlib.sha256(f"era-campaign {_VERSION} {fingerprint}\n".encode())
    if isinstance(source, (bytes, bytearray, memoryview)):
        h.update(bytes(source))
        return h.hexdigest()
    path = os.fspath(source)
    try:
        with open(path, "rb") as fh:
            for chunk in iter(lambda: fh.read(1 << 20), b""):
                h.update(chunk)
    except OSError:
        h.update(f"path:{os.path.abspath(path)}".encode())
    return h.hexdigest()


def to_json(rec: RecordModes) -> dict:
    out = {k: np.asarray(getattr(rec, k)).tolist() for k in _ARRAYS}
    out.update(version=_VERSION, index=rec.index, name=rec.name, time=None if rec.time is None else str(rec.time),
               n_orders=rec.n_orders.tolist(), shapes_re=rec.shapes.real.tolist(),
               shapes_im=rec.shapes.imag.tolist(), outputs=list(rec.outputs), kind=rec.kind, rows=rec.rows,
               cols=rec.cols, n_samples=rec.n_samples, p=int(rec.shapes.shape[0]), order=rec.order,
               rejected=[list(r) for r in rec.rejected],
               spares=[list(sp[:7]) + [sp[7].real.tolist(), sp[7].imag.tolist()] for sp in rec.spares])
    if rec.poles is not None:
        out["poles"] = {k: np.asarray(getattr(rec.poles, k)).tolist() for k in _POLE_ARRAYS}
        out["poles"].update(shapes_re=rec.poles.shapes.real.tolist(), shapes_im=rec.poles.shapes.imag.tolist())
    return out


def _poles(d: dict | None, p: int):
    if d is None:
        return None
    shapes = (np.array(d["shapes_re"], float) + 1j * np.array(d["shapes_im"], float)).reshape(p, -1)
    return DiagramPoles(**{k: np.array(d[k], int if k in ("order", "cluster") else float) for k in _POLE_ARRAYS},
                        shapes=shapes)


def from_json(d: dict, index: int, name: str) -> RecordModes:
    """The stored record, placed at ``index`` with ``name`` (the same content may sit elsewhere this time)."""
    p = int(d["p"])
    shapes = (np.array(d["shapes_re"], float) + 1j * np.array(d["shapes_im"], float)).reshape(p, -1)
    return RecordModes(index=index, name=name, time=None if d["time"] is None else np.datetime64(d["time"], "s"),
                       **{k: np.array(d[k], float) for k in _ARRAYS}, n_orders=np.array(d["n_orders"], int),
                       shapes=shapes, outputs=tuple(d["outputs"]), kind=d["kind"], rows=int(d["rows"]),
                       cols=int(d["cols"]), n_samples=int(d["n_samples"]), order=int(d["order"]),
                       rejected=tuple((float(f), str(c), str(r)) for f, c, r in d["rejected"]),
                       spares=tuple(tuple(float(x) for x in sp[:6]) + (int(sp[6]),
                                    np.array(sp[7], float) + 1j * np.array(sp[8], float))
                                    for sp in d.get("spares", [])),
                       poles=_poles(d.get("poles"), p))


def load_entry(folder, key: str, index: int, name: str) -> RecordModes | None:
    """The stored result of ``key``, or None when there is none (or it cannot be read: it is then recomputed)."""
    path = os.path.join(os.fspath(folder), f"{key}.json")
    try:
        with open(path, encoding="utf-8") as fh:
            d = json.load(fh)
        if d.get("version") != _VERSION:
            return None
        return from_json(d, index, name)
    except (OSError, ValueError, KeyError, TypeError):
        return None


def store_entry(folder, key: str, rec: RecordModes) -> None:
    """Write one record's result atomically (temporary file in the same folder, then os.replace)."""
    folder = os.fspath(folder)
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{key[:16]}-", suffix=".part", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            json.dump(to_json(rec), fh)
        os.replace(tmp, os.path.join(folder, f"{key}.json"))
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
