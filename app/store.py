"""Persistence: SQLite (WAL mode) for the index, and files in the data folder written atomically.

A file is written to a temporary name, fsynced, and renamed over its final name (then the folder is fsynced),
so a reader sees the old file or the new one, never half of one. Rows are inserted after their files, so a
row always points at a complete file. Datasets are stored in era's own NPZ format (era/io/npz.py, which
also reads the layout this store wrote before), not as the upload, so an analysis can be recomputed after a
restart without the loader, and ``era.load`` opens a stored dataset with its geometry and input locations.

Layout of the data folder: ``era.sqlite3``; ``datasets/{id}.npz``; ``reports/{token}/report.json`` and side
files; ``explanations/{analysis_id}.npz`` (dt and the measured / nominal / updated responses) and ``.json``.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import re
import secrets
import sqlite3
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

import era
from era.io.npz import npz_bytes, read_arrays, read_npz

#: Random ids and report tokens: 18 bytes = 144 bits, URL-safe (24 characters).
TOKEN_BYTES = 18

_SCHEMA = """
CREATE TABLE IF NOT EXISTS datasets (
    id TEXT PRIMARY KEY, name TEXT NOT NULL, sha256 TEXT NOT NULL, created REAL NOT NULL, summary TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS analyses (
    id TEXT PRIMARY KEY, dataset_id TEXT NOT NULL REFERENCES datasets(id), params TEXT NOT NULL, created REAL NOT NULL);
CREATE TABLE IF NOT EXISTS reports (
    token TEXT PRIMARY KEY, analysis_id TEXT NOT NULL, created REAL NOT NULL);
CREATE TABLE IF NOT EXISTS explanations (
    analysis_id TEXT PRIMARY KEY, created REAL NOT NULL);
"""
#: The responses an explanation keeps, each (N, p, m) in the dataset's output units.
EXPLANATION_RESPONSES = ("measured", "nominal", "updated")
#: What a random id looks like (new_token's alphabet): nothing else becomes a file name.
_ID = re.compile(r"[A-Za-z0-9_-]{1,64}")


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


class Store:
    """The SQLite index and the files of one data folder. Thread-safe (one connection behind a lock)."""

    def __init__(self, data_dir: Path):
        self.root = Path(data_dir)
        self.root.mkdir(parents=True, exist_ok=True)
        self._lock = threading.Lock()
        self._explaining = threading.Lock()  # one explanation written at a time: its two files stay a pair
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
        blob = npz_bytes(data, geometry, name=name)
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
        """(data, geometry or None, name) of a stored dataset, or None for an unknown id."""
        row = self._one("SELECT name FROM datasets WHERE id = ?", (dataset_id,))
        if row is None:
            return None
        path = self.dataset_path(dataset_id)
        data, geometry, name, _ = read_npz(path.read_bytes(), f"stored dataset {path}")
        return data, geometry, row[0] if name is None else name

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

    # ---- explanations (era.explain on an analysis) ------------------------------------------------------
    def _explanation_paths(self, analysis_id: str) -> tuple[Path, Path] | None:
        """(summary .json, responses .npz) of an analysis's explanation; None for a string that is no id."""
        if not _ID.fullmatch(analysis_id):
            return None
        folder = self.root / "explanations"
        return folder / f"{analysis_id}.json", folder / f"{analysis_id}.npz"

    def _stored_explanation(self, analysis_id: str) -> tuple[Path, Path] | None:
        """The files of an explanation, or None: indexed, or written before the index existed (files, no row)."""
        paths = self._explanation_paths(analysis_id)
        if paths is None:
            return None
        if self._one("SELECT 1 FROM explanations WHERE analysis_id = ?", (analysis_id,)) is not None:
            return paths
        return paths if paths[0].is_file() and paths[1].is_file() else None

    def add_explanation(self, analysis_id: str, summary: dict, responses: dict[str, np.ndarray], dt: float) -> None:
        """Keep the result of era.explain on an analysis, replacing an earlier one.

        summary : the JSON the API returns. responses : "measured", "nominal", "updated", each (N, p, m), in the
        dataset's output units. dt : their sampling interval in s. Responses first, then the summary, then the row:
        a summary on disk always has its responses.
        """
        missing = [k for k in EXPLANATION_RESPONSES if k not in responses]
        if missing:
            raise ValueError(f"add_explanation needs the responses {list(EXPLANATION_RESPONSES)}; {missing} missing.")
        paths = self._explanation_paths(analysis_id)
        if paths is None:
            raise ValueError(f"{analysis_id!r} is not an analysis id (letters, digits, '-' and '_' only).")
        arrays = {k: np.asarray(responses[k], dtype=float) for k in EXPLANATION_RESPONSES}
        buf = io.BytesIO()
        np.savez(buf, dt=np.array(float(dt)), **arrays)
        with self._explaining:
            write_atomic(paths[1], buf.getvalue())
            write_atomic(paths[0], json.dumps(summary, separators=(",", ":")).encode())
            self._insert("INSERT OR REPLACE INTO explanations (analysis_id, created) VALUES (?, ?)",
                         (analysis_id, time.time()))

    def explanation(self, analysis_id: str) -> dict | None:
        """The stored explanation summary of an analysis, or None when era.explain has not run on it."""
        paths = self._stored_explanation(analysis_id)
        return None if paths is None else json.loads(paths[0].read_bytes())

    def explanation_responses(self, analysis_id: str) -> tuple[dict[str, np.ndarray], float] | None:
        """({"measured", "nominal", "updated": (N, p, m)}, dt in s) of an analysis's explanation, or None.

        The file is read once per call: ask once, then slice every output and input from the arrays.
        """
        paths = self._stored_explanation(analysis_id)
        if paths is None:
            return None
        arrays = read_arrays(paths[1].read_bytes(), f"stored explanation {paths[1]}", ("dt", *EXPLANATION_RESPONSES),
                             required=("dt", *EXPLANATION_RESPONSES))
        return {k: arrays[k] for k in EXPLANATION_RESPONSES}, float(arrays["dt"].reshape(-1)[0])
