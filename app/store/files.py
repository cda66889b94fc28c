"""Files of the data folder written atomically: a reader sees the old file or the new one, never half of one.

Every write in progress is marked by an ``fcntl.flock`` its writer holds: on the temporary file itself
(``.name.XXXXXXXX.lock.tmp``) and, for a report folder, on a lock file inside it (``holding``). The kernel drops a
lock when its process ends, ``kill -9`` included, so a sweeper that can take the lock at once (``abandoned``) knows
the writer is dead and may remove what it left, while another live process's work in progress stays locked. A file
is locked before it gets its locked name (a temporary name first, then a rename), so a sweeper never finds a locked
name that is not yet locked. On a file system without flock the writes go on unlocked, under the names the age rule
of app/housekeeping.py covers.
"""

from __future__ import annotations

import fcntl
import os
import tempfile
from contextlib import contextmanager
from pathlib import Path

#: How the temporary file of a write in progress ends: its writer holds an flock on it until it is renamed.
LOCKED_TMP = ".lock.tmp"


def write_atomic(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` so that the file is either absent/old or complete, and durable on return.

    The bytes go to a temporary name in the same folder, locked (LOCKED_TMP), are fsynced, and renamed over the
    final name; then the folder is fsynced, so the rename survives a power cut too.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    f = os.fdopen(fd, "wb")
    try:
        if _lock(fd):  # else (a file system without flock) the temporary name is left to the age rule
            locked = tmp[: -len(".tmp")] + LOCKED_TMP
            os.rename(tmp, locked)
            tmp = locked
        f.write(data)
        f.flush()
        os.fsync(fd)
        os.replace(tmp, path)  # still locked: a sweeper that opened the old name finds it gone when it gets the lock
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    finally:
        f.close()
    dir_fd = os.open(path.parent, os.O_RDONLY)
    try:
        os.fsync(dir_fd)
    finally:
        os.close(dir_fd)


@contextmanager
def holding(lock: Path):
    """Hold an flock on the file ``lock`` (made, with its folder) while the block runs; the file is removed after.

    The lock is taken on a temporary name that is then renamed to ``lock``: whoever finds ``lock`` finds it held
    (or its holder dead)."""
    while True:  # a sweeper may take a folder caught before its lock (``unborn``) for a dead writer's: make it again
        lock.parent.mkdir(parents=True, exist_ok=True)
        try:
            fd, tmp = tempfile.mkstemp(dir=lock.parent, prefix=f"{lock.name}.", suffix=".tmp")
        except FileNotFoundError:
            continue
        try:
            if _lock(fd):  # else no lock file: the folder is left to the age rule
                os.rename(tmp, lock)
            break
        except FileNotFoundError:
            os.close(fd)
    try:
        yield
    finally:
        for name in (tmp, lock):  # the temporary name only when the rename did not happen
            try:
                os.unlink(name)
                break
            except FileNotFoundError:
                pass
        os.close(fd)


def unborn(folder: Path, lock_name: str) -> bool:
    """Whether ``folder`` holds nothing but unheld temporary names of its lock file (``lock_name``): what a writer
    killed while making the folder's lock (:func:`holding`, between its mkdir and its flock) leaves, with no lock to
    ask. A live writer caught in that instant makes the folder again if a sweeper removes it."""
    return all(p.name.startswith(f"{lock_name}.") and p.name.endswith(".tmp") and abandoned(p) is not False
               for p in folder.iterdir())


def _lock(fd: int) -> bool:
    """Take an exclusive flock on a file nobody else has opened yet; False where the file system has no flock."""
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)  # a sweeper may hold it for an instant (abandoned), never longer
    except OSError:  # ENOLCK, EOPNOTSUPP: an old network file system
        return False
    return True


def abandoned(lock: Path) -> bool | None:
    """Whether the process that locked ``lock`` is gone: True when the lock can be taken at once (it is released
    again before returning), False when a live process holds it, None when there is no such file."""
    try:
        fd = os.open(lock, os.O_RDONLY)
    except (FileNotFoundError, NotADirectoryError):
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:  # held (BlockingIOError), or a file system without flock: leave it
        return False
    finally:
        os.close(fd)
    return True
