"""Uploads waiting for the import step: the files as they came, kept until the person says how to read them.

One folder per upload under ``<data folder>/imports/<id>/``: the files (numbered, so names never clash) and
``files.json`` (their original names), written last; an upload without it is incomplete and not found. Staged
uploads are read again at every preview, from any app process, and deleted a day after they came (IMPORT_TTL_S)
or as soon as they became a dataset.
"""

from __future__ import annotations

import json
import re
import shutil
import time
from pathlib import Path

from .files import write_atomic

#: Seconds a staged upload is kept when it is not turned into a dataset.
IMPORT_TTL_S = 86400.0
_ID = re.compile(r"[A-Za-z0-9_-]{1,64}")


class Staging:
    """Staged uploads below ``root`` (the data folder's ``imports``)."""

    def __init__(self, root: Path):
        self.root = Path(root)

    def _dir(self, upload_id: str) -> Path | None:
        return self.root / upload_id if _ID.fullmatch(upload_id or "") else None

    def add(self, upload_id: str, files: list[tuple[str, bytes]]) -> None:
        """Keep ``files`` ((name, bytes), in order) as upload ``upload_id``."""
        folder = self._dir(upload_id)
        for k, (_, blob) in enumerate(files):
            write_atomic(folder / f"{k:04d}.bin", blob)
        write_atomic(folder / "files.json", json.dumps([name for name, _ in files]).encode())

    def names(self, upload_id: str) -> list[str] | None:
        """The original names of a staged upload's files, or None when there is no such (complete) upload."""
        folder = self._dir(upload_id)
        try:
            return json.loads((folder / "files.json").read_text()) if folder else None
        except (FileNotFoundError, NotADirectoryError):
            return None

    def files(self, upload_id: str) -> list[tuple[str, bytes]] | None:
        """The staged files (name, bytes) in their order, or None."""
        names = self.names(upload_id)
        if names is None:
            return None
        folder = self._dir(upload_id)
        try:
            return [(name, (folder / f"{k:04d}.bin").read_bytes()) for k, name in enumerate(names)]
        except FileNotFoundError:  # deleted meanwhile (committed or expired by another process)
            return None

    def size(self, upload_id: str) -> int:
        folder = self._dir(upload_id)
        return sum(p.stat().st_size for p in folder.glob("*.bin")) if folder and folder.is_dir() else 0

    def remove(self, upload_id: str) -> None:
        folder = self._dir(upload_id)
        if folder is not None:
            shutil.rmtree(folder, ignore_errors=True)

    def expire(self, before: float | None = None) -> int:
        """Delete the uploads staged before ``before`` (Unix s; default a day ago). Returns how many."""
        before = time.time() - IMPORT_TTL_S if before is None else before
        gone = 0
        for folder in self.root.glob("*") if self.root.is_dir() else ():
            try:
                if folder.stat().st_mtime < before:
                    shutil.rmtree(folder, ignore_errors=True)
                    gone += 1
            except FileNotFoundError:
                continue
        return gone
