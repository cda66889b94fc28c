"""Persistence: one store layer, the only one. An index database (SQLite in the data folder by default, PostgreSQL
or any SQLAlchemy URL when configured; schema by Alembic migrations) and files in the data folder written
atomically (files.py).

Rows are inserted after their files, so a row always points at complete files. Datasets are stored in era's own
NPZ format (era/io/npz.py, which also reads the layout this store wrote before), not as the upload, so an analysis
can be recomputed after a restart without the loader, and ``era.load`` opens a stored dataset with its geometry and
input locations. Nothing a request needs lives only in one process: any app process on the same database and
data folder can serve any dataset, analysis, report or explanation.

Layout of the data folder: ``era.sqlite3`` (the default database); ``datasets/{id}.npz``;
``reports/{token}/report.json`` and side files; ``explanations/{analysis_id}.npz`` (dt and the measured / nominal /
updated responses) and ``.json``; ``campaigns/{id}/campaign.json`` and ``table.csv``; ``models/{dataset_id}.json``
(the structure model of a dataset, app/modeling.py: the file itself is the commit point, so it has no table).
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import re
import secrets
import shutil
import threading
import time
from pathlib import Path

import numpy as np
import sqlalchemy as sa

import era
from era.io import npz_bytes, read_arrays, read_npz

from . import database
from .files import LOCKED_TMP, abandoned, holding, unborn, write_atomic
from .staging import Staging
from .tables import analyses, campaigns, datasets, explanations, reports, viewer_keys

__all__ = ["Store", "new_token", "write_atomic", "EXPLANATION_RESPONSES", "TOKEN_BYTES"]

#: Random ids and report tokens: 18 bytes = 144 bits, URL-safe (24 characters).
TOKEN_BYTES = 18
#: The responses an explanation keeps, each (N, p, m) in the dataset's output units.
EXPLANATION_RESPONSES = ("measured", "nominal", "updated")
#: What a random id looks like (new_token's alphabet): nothing else becomes a file name.
_ID = re.compile(r"[A-Za-z0-9_-]{1,64}")
#: The lock file in a report folder while its report is written (files.holding): held until the report is indexed.
WRITING = ".writing.lock"
#: The folders of the data folder that atomic writes put temporary files in.
#: Every folder of the data folder the store's writers use (write_atomic): swept of leftover temporary files and
#: counted in usage(). ``setups``: the multi-setup tests (app/setups.py).
FOLDERS = ("datasets", "reports", "explanations", "imports", "models", "campaigns", "setups")


def new_token() -> str:
    return secrets.token_urlsafe(TOKEN_BYTES)


class Store:
    """The index database and the files of one data folder. Thread-safe; several processes may share both.

    data_dir : the folder of the files (and of the default SQLite database).
    database_url : an SQLAlchemy URL (e.g. ``postgresql+psycopg://user:pw@host/db``); default SQLite in data_dir.
    The schema is migrated to the newest revision on opening (database.migrate).
    """

    def __init__(self, data_dir: Path, database_url: str | None = None):
        self.root = Path(data_dir)
        self.root.mkdir(parents=True, exist_ok=True)
        self.url = database_url or database.default_url(self.root)
        self._engine = database.connect(self.url)
        self.revision = database.migrate(self._engine)
        self._explaining = threading.Lock()  # one explanation written at a time here: its two files stay a pair
        self.staging = Staging(self.root / "imports")  # uploads waiting for the import step

    @property
    def backend(self) -> str:
        """"sqlite" or "postgresql" (the SQLAlchemy dialect)."""
        return self._engine.dialect.name

    def close(self) -> None:
        self._engine.dispose()

    def _one(self, query):
        with self._engine.connect() as conn:
            return conn.execute(query).first()

    def _insert(self, table: sa.Table, **row) -> None:
        with self._engine.begin() as conn:
            conn.execute(table.insert().values(**row))

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
        self._insert(datasets, id=dataset_id, name=name, sha256=sha, created=time.time(), summary=json.dumps(summary))
        return dataset_id

    def dataset_summary(self, dataset_id: str) -> dict | None:
        row = self._one(sa.select(datasets.c.summary).where(datasets.c.id == dataset_id))
        return None if row is None else json.loads(row[0])

    def load_dataset(self, dataset_id: str) -> tuple[era.ResponseData, era.Geometry | None, str] | None:
        """(data, geometry or None, name) of a stored dataset, or None for an unknown id.

        The NPZ format does not carry the band FRF records hold (``data.meta["band_hz"]``, which the choice of
        modes needs); the summary keeps it (payloads.dataset_summary) and it is put back here."""
        row = self._one(sa.select(datasets.c.name, datasets.c.summary).where(datasets.c.id == dataset_id))
        if row is None:
            return None
        path = self.dataset_path(dataset_id)
        data, geometry, name, _ = read_npz(path.read_bytes(), f"stored dataset {path}")
        band = json.loads(row[1]).get("band_hz")
        if band is not None and data.meta.get("band_hz") is None:
            data.meta["band_hz"] = (float(band[0]), float(band[1]))
        return data, geometry, row[0] if name is None else name

    # ---- structure models (one per dataset, replaced when saved again) ------------------------------------
    def _model_path(self, dataset_id: str) -> Path | None:
        return self.root / "models" / f"{dataset_id}.json" if _ID.fullmatch(dataset_id) else None

    def set_model(self, dataset_id: str, stored: dict) -> None:
        """Keep a dataset's structure model ({"model": era.frame table, "source", "name", "saved"}), replacing the
        one before in one atomic write (a reader sees the old model or the new one)."""
        path = self._model_path(dataset_id)
        if path is None:
            raise ValueError(f"{dataset_id!r} is not a dataset id.")
        write_atomic(path, json.dumps(stored, separators=(",", ":")).encode())

    def model_file(self, dataset_id: str, sha256: str, suffix: str) -> Path:
        """Where a dataset's uploaded FE model file is kept (app/femodel.py: its name carries its hash, so a file
        being replaced is never read half-written under the old name)."""
        if not _ID.fullmatch(dataset_id):
            raise ValueError(f"{dataset_id!r} is not a dataset id.")
        if not re.fullmatch(r"[0-9a-f]{16,64}", sha256) or not re.fullmatch(r"\.[a-z]{1,4}", suffix):
            raise ValueError("a model file's hash and suffix")
        return self.root / "models" / f"{dataset_id}.{sha256[:16]}{suffix}"

    def drop_model_files(self, dataset_id: str, keep: Path | None = None) -> None:
        """Remove a dataset's uploaded FE model files, but ``keep``."""
        if _ID.fullmatch(dataset_id):
            for path in (self.root / "models").glob(f"{dataset_id}.*"):
                if path.suffix != ".json" and path != keep:
                    path.unlink(missing_ok=True)

    def has_model(self, dataset_id: str) -> bool:
        """Whether the dataset has a stored structure model (without reading it)."""
        path = self._model_path(dataset_id)
        return bool(path is not None and path.is_file())

    def model(self, dataset_id: str) -> dict | None:
        """The stored structure model of a dataset, or None."""
        path = self._model_path(dataset_id)
        return json.loads(path.read_bytes()) if path is not None and path.is_file() else None

    # ---- analyses ----------------------------------------------------------------------------------
    def add_analysis(self, dataset_id: str, params: dict) -> str:
        analysis_id = new_token()
        self._insert(analyses, id=analysis_id, dataset_id=dataset_id, params=json.dumps(params), created=time.time())
        return analysis_id

    def analysis(self, analysis_id: str) -> tuple[str, dict] | None:
        """(dataset_id, params) of an analysis, or None."""
        row = self._one(sa.select(analyses.c.dataset_id, analyses.c.params).where(analyses.c.id == analysis_id))
        return None if row is None else (row[0], json.loads(row[1]))

    # ---- reports -----------------------------------------------------------------------------------
    def report_dir(self, token: str) -> Path:
        return self.root / "reports" / token

    def add_report(self, token: str, analysis_id: str, payload: dict, files: dict[str, bytes]) -> None:
        """Write the frozen report (JSON and side files such as .viser recordings), then index it."""
        folder = self.report_dir(token)
        with holding(folder / WRITING):  # a sweeper leaves the folder alone while this process lives
            for name, blob in files.items():
                write_atomic(folder / name, blob)
            write_atomic(folder / "report.json", json.dumps(payload, separators=(",", ":")).encode())
            self._insert(reports, token=token, analysis_id=analysis_id, created=time.time())

    def _has_report(self, token: str) -> bool:
        return self._one(sa.select(reports.c.token).where(reports.c.token == token)) is not None

    def report(self, token: str) -> dict | None:
        if not self._has_report(token):
            return None
        return json.loads((self.report_dir(token) / "report.json").read_bytes())

    def report_file(self, token: str, name: str) -> Path | None:
        """A side file of a report, or None (the name must be one the report wrote: no path tricks)."""
        if not self._has_report(token):
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
        if self._one(sa.select(explanations.c.analysis_id).where(explanations.c.analysis_id == analysis_id)):
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
            with self._engine.begin() as conn:  # replace an earlier one: delete and insert in one transaction
                conn.execute(explanations.delete().where(explanations.c.analysis_id == analysis_id))
                conn.execute(explanations.insert().values(analysis_id=analysis_id, created=time.time()))

    def has_explanation(self, analysis_id: str) -> bool:
        """Whether era.explain has run on the analysis and its result is stored (without reading it)."""
        return self._stored_explanation(analysis_id) is not None

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

    # ---- viewer keys (what a published key shows, and its view state, for every app process) ------------------
    def add_viewer_key(self, key: str, analysis_id: str, spec: dict) -> None:
        """Remember what ``key`` shows: ``spec`` {"kind": "modes", "order": n} or {"kind": "explain", "which": ...}."""
        self._insert(viewer_keys, key=key, analysis_id=analysis_id, spec=json.dumps(spec), state=None, revision=0,
                     created=time.time())

    def viewer_key(self, key: str) -> tuple[str, dict] | None:
        """(analysis_id, spec) of a published key, or None."""
        row = self._one(sa.select(viewer_keys.c.analysis_id, viewer_keys.c.spec).where(viewer_keys.c.key == key))
        return None if row is None else (row[0], json.loads(row[1]))

    def set_viewer_state(self, key: str, state: dict) -> None:
        """Store a key's view state and bump its revision (other processes follow the newer revision)."""
        with self._engine.begin() as conn:
            conn.execute(viewer_keys.update().where(viewer_keys.c.key == key)
                         .values(state=json.dumps(state), revision=viewer_keys.c.revision + 1))

    def viewer_states(self, keys) -> dict[str, tuple[dict, int]]:
        """{key: (state, revision)} of the keys that have a stored state."""
        keys = list(keys)
        if not keys:
            return {}
        with self._engine.connect() as conn:
            rows = conn.execute(sa.select(viewer_keys.c.key, viewer_keys.c.state, viewer_keys.c.revision)
                                .where(viewer_keys.c.key.in_(keys), viewer_keys.c.state.is_not(None)))
            return {k: (json.loads(st), int(rev)) for k, st, rev in rows}

    # ---- campaigns (app/campaigns.py runs them; the row is their state, the files their result) ---------------
    def campaign_dir(self, campaign_id: str) -> Path | None:
        """The folder of a campaign's result files; None for a string that is no id."""
        return self.root / "campaigns" / campaign_id if _ID.fullmatch(campaign_id) else None

    def add_campaign(self, campaign_id: str, name: str, total: int) -> None:
        now = time.time()
        self._insert(campaigns, id=campaign_id, name=name, state="queued", done=0, total=int(total), message=None,
                     created=now, updated=now)

    def set_campaign(self, campaign_id: str, **values) -> None:
        """Update a campaign's state, done, total or message (and its ``updated`` time)."""
        with self._engine.begin() as conn:
            conn.execute(campaigns.update().where(campaigns.c.id == campaign_id).values(updated=time.time(), **values))

    def campaign(self, campaign_id: str) -> dict | None:
        """The campaign's row {id, name, state, done, total, message, created, updated}, or None."""
        row = self._one(sa.select(campaigns).where(campaigns.c.id == campaign_id))
        return None if row is None else dict(row._mapping)

    # ---- housekeeping -----------------------------------------------------------------------------------
    def expire(self, before: float) -> dict:
        """Delete the analyses made before ``before`` (Unix s) that no report uses, with their explanations, then
        the datasets made before it that no analysis uses any more. Rows first, then files (a file without a row
        is only garbage; a row without its file would be a broken link). Returns {"analyses": n, "datasets": n}."""
        with self._engine.begin() as conn:
            used = sa.select(reports.c.analysis_id)
            gone = [r[0] for r in conn.execute(sa.select(analyses.c.id).where(analyses.c.created < before,
                                                                              analyses.c.id.not_in(used)))]
            if gone:
                conn.execute(explanations.delete().where(explanations.c.analysis_id.in_(gone)))
                conn.execute(viewer_keys.delete().where(viewer_keys.c.analysis_id.in_(gone)))
                conn.execute(analyses.delete().where(analyses.c.id.in_(gone)))
            dropped = [r[0] for r in conn.execute(sa.select(datasets.c.id).where(
                datasets.c.created < before, datasets.c.id.not_in(sa.select(analyses.c.dataset_id))))]
            if dropped:
                conn.execute(datasets.delete().where(datasets.c.id.in_(dropped)))
        for analysis_id in gone:
            for path in self._explanation_paths(analysis_id) or ():
                path.unlink(missing_ok=True)
        for dataset_id in dropped:
            self.dataset_path(dataset_id).unlink(missing_ok=True)
            self._model_path(dataset_id).unlink(missing_ok=True)
            self.drop_model_files(dataset_id)
        return {"analyses": len(gone), "datasets": len(dropped)}

    def sweep_orphans(self, before: float) -> int:
        """Remove what a killed process (kill -9 in the middle of a write) left: report folders with no indexed
        report (the index row is written last) and the temporary files of atomic writes (app/store/files.py).
        A write in progress holds an flock (on the temporary file, on the report folder's WRITING file): what is
        locked is another live process's and stays; what was locked by a process now dead goes at once, and so does
        a report folder killed before its lock was in place (files.unborn: empty but for the lock's temporary name).
        What else carries no lock (written by an older version) goes only when last changed before ``before``
        (Unix s). Safe with several processes sweeping and writing at once. Returns how
        many folders and files were removed."""
        removed = 0
        folder = self.root / "reports"
        for path in folder.iterdir() if folder.is_dir() else ():
            try:
                if not path.is_dir() or self._has_report(path.name):
                    continue
                dead = abandoned(path / WRITING)
                if dead is False or (dead is None and not unborn(path, WRITING) and _last_change(path) >= before):
                    continue
            except FileNotFoundError:  # removed meanwhile by another sweeper
                continue
            if not self._has_report(path.name):  # indexed meanwhile: its writer finished and let the lock go
                shutil.rmtree(path, ignore_errors=True)
                removed += 1
        for name in FOLDERS:  # os.walk, not rglob: a folder removed meanwhile is skipped, not an error
            found = (Path(top) / f for top, _, names in os.walk(self.root / name) for f in names)
            for tmp in (p for p in found if p.name.startswith(".") and p.name.endswith(".tmp")):
                try:
                    if not tmp.is_file():
                        continue
                    gone = abandoned(tmp) if tmp.name.endswith(LOCKED_TMP) else tmp.stat().st_mtime < before
                    if gone:
                        tmp.unlink()
                        removed += 1
                except FileNotFoundError:  # renamed into place or removed meanwhile
                    pass
        return removed

    def usage(self) -> dict:
        """What the store holds: rows per table, bytes per folder of the data folder, and the disk's free bytes."""
        with self._engine.connect() as conn:
            rows = {t.name: conn.execute(sa.select(sa.func.count()).select_from(t)).scalar_one()
                    for t in (datasets, analyses, reports, explanations)}
        folders = {name: _folder_bytes(self.root / name) for name in FOLDERS}
        return {"rows": rows, "bytes": folders, "free_bytes": shutil.disk_usage(self.root).free}


def _last_change(folder: Path) -> float:
    """The latest modification time of a folder and the files directly in it (Unix s)."""
    times = [folder.stat().st_mtime]
    for p in folder.iterdir():
        try:
            times.append(p.stat().st_mtime)
        except FileNotFoundError:
            pass
    return max(times)


def _folder_bytes(folder: Path) -> int:
    """Bytes of the files below ``folder`` (0 when it does not exist yet)."""
    total = 0
    stack = [folder]
    while stack:
        try:
            entries = list(os.scandir(stack.pop()))
        except FileNotFoundError:
            continue
        for e in entries:
            if e.is_dir(follow_symlinks=False):
                stack.append(e.path)
            elif e.is_file(follow_symlinks=False):
                total += e.stat(follow_symlinks=False).st_size
    return total
