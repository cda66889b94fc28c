"""Uploaded file -> (ResponseData, Geometry | None, source) through era.load (UFF, CSV, NPZ; issue 3)."""

from __future__ import annotations

import io

import era


def load_upload(blob: bytes, filename: str):
    """Parse an uploaded file. Raises an era.EraError (shown to the person as is) for anything malformed."""
    ds = era.load(io.BytesIO(blob), name=filename)
    if ds.data is None:
        raise era.DataError(f"{filename}: the file holds geometry or modes but no response records (UFF 58, CSV "
                            "or NPZ data); upload the measured responses.")
    return ds.data, ds.geometry, dict(ds.source or {})
