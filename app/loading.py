"""Uploaded file -> (ResponseData, Geometry | None, source) through era.load (UFF, CSV, NPZ; issue 3)."""

from __future__ import annotations

import io

import era


#: What the records are, as the person may say it (era.io.records.to_response); "auto" lets the loader guess.
KINDS = ("auto", "pulse", "decay", "frf", "io", "ambient")


def load_upload(blob: bytes, filename: str, kind: str = "auto"):
    """Parse an uploaded file. Raises an era.EraError (shown to the person as is) for anything malformed."""
    if kind not in KINDS:
        raise era.DataError(f"`kind` must be one of {', '.join(KINDS)}, got {kind!r}.")
    ds = era.load(io.BytesIO(blob), name=filename, kind=kind)
    if ds.data is None:
        raise era.DataError(f"{filename}: the file holds geometry or modes but no response records (UFF 58, CSV "
                            "or NPZ data); upload the measured responses.")
    return ds.data, ds.geometry, dict(ds.source or {})
