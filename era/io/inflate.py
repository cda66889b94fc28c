"""How far a file may inflate: the uncompressed bytes one read may produce (NPZ members, HDF5 datasets, MATLAB
v5 compressed variables), checked by the size the file declares before anything is allocated and by the size it
really inflates to, read in bounded chunks that stop at the limit.

A :class:`Budget` is shared by every file of one :func:`era.load` (or :func:`era.io.read`) call, so a hundred
files each just under the limit are refused as well. ``Budget(None)`` only counts (the library's default: the
readers' own 2 GiB per array still apply).
"""

from __future__ import annotations

import zlib

from ..errors import TooLargeError

#: Bytes inflated per step: at most this much is held beyond what the limit allows.
CHUNK = 1 << 20


def _mb(n: int) -> str:
    return f"{n / 2**20:,.1f} MB"


class Budget:
    """The uncompressed bytes left to the files of one read; ``limit`` None: no limit."""

    def __init__(self, limit: int | None):
        self.limit = None if limit is None else int(limit)
        self.used = 0

    def claim(self, nbytes: int, where: str) -> None:
        """Count ``nbytes`` about to be allocated for ``where``; TooLargeError when they pass the limit."""
        self.used += int(nbytes)
        if self.limit is not None and self.used > self.limit:
            before = self.used - int(nbytes)
            raise TooLargeError(f"{where} inflates to {_mb(int(nbytes))} uncompressed"
                                + (f" (after {_mb(before)} already read)" if before else "")
                                + f", above the limit of {_mb(self.limit)} for the uncompressed content of one "
                                  "upload. Send fewer channels or samples, or a file that is not compressed.")

    def read(self, fh, nbytes: int, where: str) -> bytes:
        """Exactly ``nbytes`` (claimed first) from the binary stream ``fh``, in chunks of at most CHUNK; fewer
        when the stream ends early (the caller says that is truncated). Never reads past ``nbytes``."""
        self.claim(nbytes, where)
        parts, left = [], int(nbytes)
        while left > 0:
            part = fh.read(min(CHUNK, left))
            if not part:
                break
            parts.append(part)
            left -= len(part)
        return b"".join(parts)

    def inflate_size(self, compressed: bytes, where: str) -> int:
        """The size ``compressed`` (a zlib stream) inflates to, measured chunk by chunk without keeping the output;
        it stops (TooLargeError) as soon as the budget is passed, so a bomb costs at most the limit in CPU."""
        d = zlib.decompressobj()
        total, data = 0, compressed
        room = None if self.limit is None else self.limit - self.used
        while True:
            out = d.decompress(data, CHUNK)
            total += len(out)
            if room is not None and total > room:
                raise TooLargeError(f"{where} inflate to more than {_mb(self.limit)} uncompressed, the limit for the "
                                    "uncompressed content of one upload. Send fewer channels or samples, or a file "
                                    "that is not compressed.")
            data = d.unconsumed_tail
            if not out and not data:
                break
        self.used += total
        return total
