"""The files of one FE model, read within limits: a folder or a zip (Files), Matrix Market matrices and the
small CSV tables beside them (dofs.csv, coordinates.csv).

Limits (a zip bomb or a runaway file is refused before it is inflated or parsed): at most ``max_bytes``
(MAX_BYTES, 2 GiB) of uncompressed content over every file one load_model call reads, counted from the sizes a
folder's files and a zip's members declare and again while a member inflates (era.io.inflate.Budget); at most
MAX_MEMBERS entries in a zip; at most MAX_DOFS rows in a matrix, and a dense ("array") Matrix Market file no
larger than the byte limit allows.
"""

from __future__ import annotations

import io
import zipfile
from pathlib import Path, PurePosixPath

import scipy.io

from ..errors import DataError, TooLargeError
from ..io.inflate import Budget
from ..words import counted

MAX_BYTES = 2 * 1024**3      # uncompressed bytes one load_model call may read
MAX_MEMBERS = 10_000         # entries of a zip
MAX_DOFS = 5_000_000         # rows of a matrix


class Files:
    """The files of one model: a folder or a zip, read within one byte budget. Names are POSIX paths relative to
    the model's folder (a zip whose every member sits in one top folder is read from inside it)."""

    def __init__(self, path: Path, budget: Budget):
        self.path, self.budget = path, budget
        self.zip: zipfile.ZipFile | None = None
        if path.is_dir():
            self.names = {}
            for p in path.rglob("*"):       # a model's folder, not a disk: stop counting past the limit
                if p.is_file():
                    self.names[p.relative_to(path).as_posix()] = p
                    if len(self.names) > MAX_MEMBERS:
                        raise TooLargeError(f"{path.name} holds more than {MAX_MEMBERS:,} files; give the folder "
                                            "that holds the model's files only.")
            self.names = dict(sorted(self.names.items()))
        else:
            try:
                self.zip = zipfile.ZipFile(path)
            except (zipfile.BadZipFile, OSError) as exc:
                raise DataError(f"{path.name} is not a readable zip file ({exc}); zip the folder with K.mtx, "
                                "M.mtx and dofs.csv again.") from None
            infos = [i for i in self.zip.infolist() if not i.is_dir()]
            if len(infos) > MAX_MEMBERS:
                raise TooLargeError(f"{path.name} holds {len(infos):,} files, more than the {MAX_MEMBERS:,} a model "
                                    "zip may hold.")
            names = [i.filename for i in infos if "__MACOSX" not in i.filename]
            tops = {PurePosixPath(n).parts[0] for n in names}
            strip = len(tops) == 1 and all(len(PurePosixPath(n).parts) > 1 for n in names)
            self.names = {(str(PurePosixPath(*PurePosixPath(i.filename).parts[1:])) if strip else i.filename): i
                          for i in infos if "__MACOSX" not in i.filename}

    @property
    def label(self) -> str:
        return self.path.name

    def find(self, name: str) -> str | None:
        """The stored name matching ``name`` without regard to case, or None."""
        low = name.lower()
        return next((n for n in self.names if n.lower() == low), None)

    def read(self, name: str) -> bytes:
        """The bytes of ``name``, claimed from the budget before they are read."""
        where = f"{name} in {self.label}"
        entry = self.names[name]
        if isinstance(entry, zipfile.ZipInfo):
            assert self.zip is not None
            try:
                with self.zip.open(entry) as fh:
                    raw = self.budget.read(fh, entry.file_size, where)
            except (zipfile.BadZipFile, OSError, RuntimeError, NotImplementedError) as exc:
                raise DataError(f"{where} cannot be unzipped ({exc}); zip the model again.") from None
            if len(raw) != entry.file_size:
                raise DataError(f"{where} is truncated; zip the model again.")
            return raw
        self.budget.claim(entry.stat().st_size, where)
        return entry.read_bytes()

    def text(self, name: str) -> str:
        raw = self.read(name)
        try:
            return raw.decode("utf-8-sig")
        except UnicodeDecodeError:
            return raw.decode("latin-1")


def read_mtx(files: Files, name: str, what: str):
    """A Matrix Market file as a sparse matrix (coordinate) or array, its declared size checked first."""
    raw = files.read(name)
    where = f"{name} in {files.label}"
    try:
        rows, cols, entries, fmt, field, _ = scipy.io.mminfo(io.BytesIO(raw))
    except (ValueError, OSError, IndexError) as exc:
        raise DataError(f"{where} is not a Matrix Market file ({exc}); {what} must start with a "
                        "'%%MatrixMarket matrix coordinate real ...' header (scipy.io.mmwrite writes it).") from None
    if max(rows, cols) > MAX_DOFS:
        raise TooLargeError(f"{where} declares {rows:,} × {cols:,}, more than the {MAX_DOFS:,} DOFs a model may have.")
    if fmt == "array" and rows * cols * 8 > (files.budget.limit or MAX_BYTES):
        raise TooLargeError(f"{where} is a dense {rows:,} × {cols:,} matrix, too large to hold; write it in "
                            "coordinate (sparse) form.")
    if field == "complex":
        raise DataError(f"{where} holds complex numbers; {what} must be real.")
    try:
        return scipy.io.mmread(io.BytesIO(raw))
    except (ValueError, OSError, IndexError, TypeError) as exc:
        raise DataError(f"{where} cannot be read as Matrix Market ({exc}); check its header (rows, columns, "
                        "entries) against its lines.") from None


def _rows(text: str, name: str, width: int, header: tuple) -> list[list[str]]:
    """The rows of a small CSV (comma, semicolon, tab or spaces between fields), the header line skipped when it
    names the columns; each row has ``width`` fields."""
    out = []
    for k, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        for sep in (",", ";", "\t"):
            if sep in line:
                fields = [f.strip() for f in line.split(sep)]
                break
        else:
            fields = line.split()
        if not out and [f.lower() for f in fields[:len(header)]] == list(header):
            continue
        if len(fields) < width:
            raise DataError(f"{name} line {k} has {counted(len(fields), 'field')}, {line!r}; give "
                            f"{','.join(header)} on each line.")
        out.append(fields[:width])
    return out


def read_dofs(files: Files, name: str) -> list[tuple[str, str]]:
    return [(n, d) for n, d in _rows(files.text(name), name, 2, ("node", "direction"))]


def read_coordinates(files: Files, name: str) -> dict:
    out = {}
    for k, (node, *xyz) in enumerate(_rows(files.text(name), name, 4, ("node", "x", "y", "z")), start=1):
        try:
            out[node] = tuple(float(v) for v in xyz)
        except ValueError:
            raise DataError(f"{name} row {k} (node {node}): x, y, z must be numbers, got {xyz}.") from None
    return out
