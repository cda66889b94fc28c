"""Housekeeping: datasets and analyses that no report uses are deleted ``ERA_EXPIRE_DAYS`` after they were made;
reports (and what they froze) are kept; what a killed process left half-written (a report folder never indexed,
temporary files) goes at the next sweep, the one at start included: a write in progress holds an flock that dies with
its process (app/store/files.py), so another live process's writes are never taken for orphans. What carries no
lock (written by an older version) goes ORPHAN_AFTER_S after its last change. Runs at start and every hour, in a
thread; several app processes may run it at once (deleting is idempotent)."""

from __future__ import annotations

import asyncio
import logging
import time

from .store import Store
from .store.staging import IMPORT_TTL_S

log = logging.getLogger("app.housekeeping")
#: Seconds between sweeps.
EVERY_S = 3600.0
#: A half-written report folder or temporary file with no lock (an older version's) this old (s since its last
#: change) is a killed process's: no write of the app takes this long, so a write in progress is never removed.
ORPHAN_AFTER_S = 600.0


def sweep(store: Store, expire_days: float, now: float | None = None) -> dict:
    """Delete what expired by ``now`` (Unix s); returns the counts. ``expire_days`` ≤ 0 keeps every dataset and
    analysis; uploads never turned into a dataset (the import step's) go a day after they came, and what killed
    processes left half-written (``orphans``) at once when its writer's lock is free, ORPHAN_AFTER_S after its last
    change when it has none, always."""
    now = time.time() if now is None else now
    imports = store.staging.expire(before=now - IMPORT_TTL_S)
    orphans = store.sweep_orphans(before=now - ORPHAN_AFTER_S)
    if expire_days <= 0:
        return {"analyses": 0, "datasets": 0, "imports": imports, "orphans": orphans}
    return dict(store.expire(before=now - 86400.0 * expire_days), imports=imports, orphans=orphans)


async def sweep_forever(store: Store, expire_days: float) -> None:
    while True:
        try:
            gone = await asyncio.to_thread(sweep, store, expire_days)
            if any(gone.values()):
                log.info("housekeeping: %s expired (older than %g days, in no report)", gone, expire_days)
        except Exception:  # a failed sweep must not stop the server; the next one tries again
            log.exception("housekeeping failed")
        await asyncio.sleep(EVERY_S)
