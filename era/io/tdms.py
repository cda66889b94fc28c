"""NI TDMS files through npTDMS: groups of channels, ``wf_increment`` (s), ``unit_string``.

The channels of one group are the record's channels; several groups holding the same channels are several records
(repeated tests, several initial conditions), otherwise ``group="..."`` chooses one. The sampling comes from the
channels' ``wf_increment`` (they must agree), or a channel named ``Time``/``t``, or the caller's ``dt``
(era/io/arrays.py does the choosing). Each channel's length is checked against the file's size before it is read.
"""

from __future__ import annotations

import io
import struct

import numpy as np

from ..errors import DataError
from .arrays import Var, check_size, records_from_vars
from .records import Records, merge_records

MAGIC = b"TDSm"
_UNIT_KEYS = ("unit_string", "NI_UnitDescription", "unit")


def read_tdms(raw, label: str, dt: float | None = None, group: str | None = None) -> Records:
    """Records ("time", one per group) from a .tdms file's bytes or path; module docstring."""
    from nptdms import TdmsFile

    with (open(raw, "rb") if isinstance(raw, str) else io.BytesIO(raw)) as fh:
        size = _check_segments(fh, label)
    try:
        tdms = TdmsFile.read(raw if isinstance(raw, str) else io.BytesIO(raw))  # segments checked above
        groups = {g.name: [c for c in g.channels()] for g in tdms.groups()}
    except (ValueError, KeyError, IndexError, TypeError, OSError, EOFError, struct.error, UnicodeDecodeError,
            MemoryError, OverflowError) as exc:
        raise DataError(f"{label}: not a readable TDMS file ({type(exc).__name__}: {exc}).") from None
    with tdms:
        groups = {name: chans for name, chans in groups.items() if chans}
        if not groups:
            raise DataError(f"{label}: no channels in any group.")
        if group is not None:
            if group not in groups:
                raise DataError(f"{label}: no group {group!r} with channels; the file has {sorted(groups)}.", option="group")
            chosen = [group]
        elif len({tuple(c.name for c in chans) for chans in groups.values()}) == 1:
            chosen = list(groups)  # the same channels in every group: repeated runs
        else:
            listing = "; ".join(f"{g!r}: {[c.name for c in chans][:6]}" for g, chans in groups.items())
            raise DataError(f"{label}: groups with different channels ({listing}); choose one with "
                            f"group={next(iter(groups))!r}.", option="group")
        records = [records_from_vars([_var(c, size, label, g) for c in groups[g]], f"{label} [{g}]", "NI TDMS",
                                     dt) for g in chosen]
    return merge_records(records, [f"{label} [{g}]" for g in chosen]) if len(records) > 1 else records[0]


def _check_segments(fh, label: str) -> int:
    """Every segment's lead-in (28 bytes: 'TDSm', ToC mask, version, next-segment offset, raw-data offset) must
    announce a segment that the file holds: npTDMS reads a cut file silently as shorter channels. Returns the size."""
    end = fh.seek(0, io.SEEK_END)
    pos, k = 0, 0
    while pos < end:
        k += 1
        fh.seek(pos)
        lead = fh.read(28)
        if len(lead) < 28 or lead[:4] != MAGIC:
            raise DataError(f"{label}: segment {k} at byte {pos} has no 'TDSm' lead-in; the file is truncated or "
                            "corrupt. Copy or export it again.")
        endian = ">" if struct.unpack("<I", lead[4:8])[0] & (1 << 6) else "<"
        size = struct.unpack(endian + "Q", lead[12:20])[0]
        if size == 0xFFFFFFFFFFFFFFFF or pos + 28 + size > end:
            raise DataError(f"{label}: segment {k} at byte {pos} announces {size} bytes but the file ends "
                            f"{end - pos - 28} bytes later: it was cut short (the acquisition did not close it, or "
                            "the copy is incomplete). Copy or export it again.")
        pos += 28 + size
    return end


def _var(channel, file_size: int, label: str, group: str) -> Var:
    where = f"{label}: group {group!r}, channel {channel.name!r}"
    props = dict(channel.properties)
    attrs = {"units": next((str(props[k]) for k in _UNIT_KEYS if props.get(k)), "")}
    if "wf_increment" in props:
        attrs["wf_increment"] = props["wf_increment"]
    try:
        n, dtype = int(len(channel)), np.dtype(channel.dtype)
    except (TypeError, ValueError) as exc:
        raise DataError(f"{where}: no readable data type ({exc}).") from None
    kind = dtype.kind if dtype.kind in "fiu" else "?"

    def read():
        check_size((n,), dtype.itemsize, file_size, where)
        try:
            return np.asarray(channel[:])
        except (ValueError, KeyError, IndexError, TypeError, OSError, EOFError, struct.error, MemoryError) as exc:
            raise DataError(f"{where} cannot be read ({type(exc).__name__}: {exc}); the file is truncated or "
                            "corrupt.") from None

    return Var(channel.name, (n,), kind, read, attrs)
