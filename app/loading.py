"""Uploaded files -> (ResponseData, Geometry | None, source) through era.load: every format era/io reads, one file
or several read as one dataset, with what the files cannot say given as options (dt, orientation, variable, ...)."""

from __future__ import annotations

import io

import era

#: What the records are, as the person may say it (era.io.records.to_response); "auto" lets the loader guess.
KINDS = ("auto", "pulse", "decay", "frf", "io", "ambient")
#: Files in one upload at most (one per hammer hit or reference; a roving test of 64 points fits).
MAX_FILES = 256


def load_upload(files: list[tuple[str, bytes]], kind: str = "auto", **options):
    """Parse uploaded files (name, bytes) as one dataset. ``options`` go to era.load (dt, format, orientation,
    variable, group, frf_sign; None means not given). Raises an era.EraError (shown to the person as is)."""
    if kind not in KINDS:
        raise era.DataError(f"`kind` must be one of {', '.join(KINDS)}, got {kind!r}.")
    if not files:
        raise era.DataError("No file in the upload: add at least one file part named `file`.")
    if len(files) > MAX_FILES:
        raise era.DataError(f"{len(files)} files in one upload; at most {MAX_FILES} are read as one dataset.")
    sources = []
    for name, blob in files:
        src = io.BytesIO(blob)
        src.name = name  # era.load names the file in its messages
        sources.append(src)
    given = {k: v for k, v in options.items() if v is not None}
    ds = era.load(sources if len(sources) > 1 else sources[0], name=files[0][0] if len(files) == 1 else None,
                  kind=kind, **given)
    if ds.data is None:
        raise era.DataError(f"{files[0][0]}: the file holds geometry or modes but no response records; upload the "
                            "measured responses.")
    return ds.data, ds.geometry, dict(ds.source or {})
