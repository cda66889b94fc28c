"""Persistence: SQLite (WAL mode) for the index, and files in the data folder written atomically.

A file is written to a temporary name, fsynced, and renamed over its final name (then the folder is fsynced),
so a reader sees the old file or the new one, never half of one. Rows are inserted after their files, so a
row always points at a complete file. Datasets are stored in a normalised NPZ (not the upload), so an
analysis can be recomputed after a restart without the loader.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import secrets
import sqlite3
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

import era

#: Random ids and report tokens: 18 bytes = 144 bits, URL-safe (24 characters).
TOKEN_BYTES = 18

_SCHEMA = """
CREATE TABLE IF NOT EXISTS datasets (
    id TEXT PRIMARY KEY, name TEXT NOT NULL, sha256 TEXT NOT NULL, created REAL NOT NULL, summary TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS analyses (
    id TEXT PRIMARY KEY, dataset_id TEXT NOT NULL REFERENCES datasets(id), params TEXT NOT NULL, created REAL NOT NULL);
CREATE TABLE IF NOT EXISTS reports (
    token TEXT PRIMARY KEY, analysis_id TEXT NOT NULL, created REAL NOT NULL);
"""


def new_token() -> str:
    return secrets.token_urlsafe(TOKEN_BYTES)


def write_atomic(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` so that the file is either absent/old or complete, and durable on return."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    dir_fd = os.open(path.parent, os.O_RDONLY)
    try:
        os.fsync(dir_fd)
    finally:
        os.close(dir_fd)


def _strings(values) -> np.ndarray:
    return np.array([] if values is None else [str(v) for v in values], dtype=str)


def dataset_to_npz(data: era.ResponseData, geometry: era.Geometry | None, name: str) -> bytes:
    """The normalised stored form of a dataset: pulse responses, labels, units and the geometry if any."""
    arrays = dict(markov=data.markov, dt=np.array(data.dt), name=np.array(name), outputs=_strings(data.outputs),
                  inputs=_strings(data.inputs), has_output_units=np.array(data.output_units is not None),
                  output_units=_strings(data.output_units), has_input_units=np.array(data.input_units is not None),
                  input_units=_strings(data.input_units), has_geometry=np.array(geometry is not None))
    where = (data.meta or {}).get("input_locations")
    if where is not None:  # the input points (e.g. joints in ft): era.explain's residue term needs them
        arrays["input_locations"] = np.asarray(where, dtype=float)
    if geometry is not None:
        arrays.update(geo_node_ids=geometry.node_ids, geo_coordinates=geometry.coordinates, geo_edges=geometry.edges,
                      geo_channel_nodes=geometry.channel_nodes, geo_channel_directions=geometry.channel_directions,
                      geo_units=np.array(geometry.units))
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def dataset_from_npz(blob: bytes) -> tuple[era.ResponseData, era.Geometry | None, str]:
    with np.load(io.BytesIO(blob), allow_pickle=False) as z:
        data = era.ResponseData(
            markov=z["markov"], dt=float(z["dt"]), outputs=tuple(z["outputs"].tolist()),
            inputs=tuple(z["inputs"].tolist()),
            output_units=tuple(z["output_units"].tolist()) if bool(z["has_output_units"]) else None,
            input_units=tuple(z["input_units"].tolist()) if bool(z["has_input_units"]) else None,
            meta={"input_locations": [tuple(x) for x in z["input_locations"].tolist()]}
            if "input_locations" in z.files else {})
        geometry = None
        if bool(z["has_geometry"]):
            geometry = era.Geometry(node_ids=z["geo_node_ids"], coordinates=z["geo_coordinates"],
                                    edges=z["geo_edges"], channel_nodes=z["geo_channel_nodes"],
                                    channel_directions=z["geo_channel_directions"], units=str(z["geo_units"]))
        return data, geometry, str(z["name"])


class Store:
    """The SQLite index and the files of one data folder. Thread-safe (one connection behind a lock)."""

    def __init__(self, data_dir: Path):
        self.root = Path(data_dir)
        self.root.mkdir(parents=True, exist_ok=True)
        self._lock = threading.Lock()
        self._db = sqlite3.connect(self.root / "era.sqlite3", check_same_thread=False, isolation_level=None)
        self._db.execute("PRAGMA journal_mode=WAL")
        self._db.execute("PRAGMA synchronous=FULL")  # a committed report survives a power cut
        self._db.executescript(_SCHEMA)

    def close(self) -> None:
        with self._lock:
            self._db.close()

    def _one(self, sql: str, args: tuple):
        with self._lock:
            return self._db.execute(sql, args).fetchone()

    def _insert(self, sql: str, args: tuple) -> None:
        with self._lock:
            self._db.execute("BEGIN IMMEDIATE")
            try:
                self._db.execute(sql, args)
                self._db.execute("COMMIT")
            except BaseException:
                self._db.execute("ROLLBACK")
                raise

    # ---- datasets ----------------------------------------------------------------------------------
    def dataset_path(self, dataset_id: str) -> Path:
        return self.root / "datasets" / f"{dataset_id}.npz"

    def add_dataset(self, data: era.ResponseData, geometry: era.Geometry | None, name: str, summary: dict) -> str:
        """Store a dataset; returns its new random id. ``summary`` is the JSON the API returns for it."""
        blob = dataset_to_npz(data, geometry, name)
        dataset_id = new_token()
        sha = hashlib.sha256(blob).hexdigest()
        summary = dict(summary, id=dataset_id, sha256=sha)
        write_atomic(self.dataset_path(dataset_id), blob)
        self._insert("INSERT INTO datasets (id, name, sha256, created, summary) VALUES (?, ?, ?, ?, ?)",
                     (dataset_id, name, sha, time.time(), json.dumps(summary)))
        return dataset_id

    def dataset_summary(self, dataset_id: str) -> dict | None:
        row = self._one("SELECT summary FROM datasets WHERE id = ?", (dataset_id,))
        return None if row is None else json.loads(row[0])

    def load_dataset(self, dataset_id: str) -> tuple[era.ResponseData, era.Geometry | None, str] | None:
        if self._one("SELECT 1 FROM datasets WHERE id = ?", (dataset_id,)) is None:
            return None
        return dataset_from_npz(self.dataset_path(dataset_id).read_bytes())

    # ---- analyses ----------------------------------------------------------------------------------
    def add_analysis(self, dataset_id: str, params: dict) -> str:
        analysis_id = new_token()
        self._insert("INSERT INTO analyses (id, dataset_id, params, created) VALUES (?, ?, ?, ?)",
                     (analysis_id, dataset_id, json.dumps(params), time.time()))
        return analysis_id

    def analysis(self, analysis_id: str) -> tuple[str, dict] | None:
        """(dataset_id, params) of an analysis, or None."""
        row = self._one("SELECT dataset_id, params FROM analyses WHERE id = ?", (analysis_id,))
        return None if row is None else (row[0], json.loads(row[1]))

    # ---- reports -----------------------------------------------------------------------------------
    def report_dir(self, token: str) -> Path:
        return self.root / "reports" / token

    def add_report(self, token: str, analysis_id: str, payload: dict, files: dict[str, bytes]) -> None:
        """Write the frozen report (JSON and side files such as .viser recordings), then index it."""
        folder = self.report_dir(token)
        for name, blob in files.items():
            write_atomic(folder / name, blob)
        write_atomic(folder / "report.json", json.dumps(payload, separators=(",", ":")).encode())
        self._insert("INSERT INTO reports (token, analysis_id, created) VALUES (?, ?, ?)",
                     (token, analysis_id, time.time()))

    def report(self, token: str) -> dict | None:
        if self._one("SELECT 1 FROM reports WHERE token = ?", (token,)) is None:
            return None
        return json.loads((self.report_dir(token) / "report.json").read_bytes())

    def report_file(self, token: str, name: str) -> Path | None:
        """A side file of a report, or None (the name must be one the report wrote: no path tricks)."""
        if self._one("SELECT 1 FROM reports WHERE token = ?", (token,)) is None:
            return None
        if not name or "/" in name or "\\" in name or name.startswith("."):
            return None
        path = self.report_dir(token) / name
        return path if path.is_file() else None
