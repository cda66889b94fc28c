"""Work off the event loop: a small bounded pool for heavy jobs, a separate one for quick ones, and progress.

Heavy jobs (parsing a large upload, the SVD, the stabilization diagram, a report) run at most ``heavy_workers``
at a time and at most ``heavy_queue`` more may wait; beyond that the request fails fast with 503 and a
Retry-After instead of piling up. Quick jobs (realizing one order for the slider, a reconstruction, a small upload)
have their own threads and are never refused. Heavy threads run at a lower CPU priority (nice +10, per thread on
Linux), so on a loaded server the kernel gives the slider's threads the cores first.

Progress: a request may name itself with a random key (header ``X-Progress-Key``); while it waits or runs,
``GET /api/jobs/{key}`` says whether it is queued (and behind how many), what it is doing, and for how long.
"""

from __future__ import annotations

import asyncio
import os
import functools
import itertools
import re
import threading
import time
from collections import OrderedDict
from concurrent.futures import ThreadPoolExecutor
from typing import Callable, TypeVar

from fastapi import HTTPException

T = TypeVar("T")
_KEY = re.compile(r"^[A-Za-z0-9_-]{8,64}$")
_FINISHED_KEPT = 256  # finished jobs remembered for late polls


#: CPU priority of the heavy threads (Linux nice value, per thread): behind the quick threads at 0.
HEAVY_NICE = 10


def _lower_priority() -> None:
    """Run this (heavy) thread at nice HEAVY_NICE; best effort where threads have no priority of their own."""
    try:
        os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), HEAVY_NICE)
    except (AttributeError, OSError):
        pass


class Jobs:
    def __init__(self, heavy_workers: int, heavy_queue: int, quick_workers: int = 4):
        self._heavy = ThreadPoolExecutor(max_workers=heavy_workers, thread_name_prefix="era-heavy",
                                         initializer=_lower_priority)
        self._quick = ThreadPoolExecutor(max_workers=quick_workers, thread_name_prefix="era-quick")
        self._capacity = heavy_workers + heavy_queue
        self._workers = heavy_workers
        self._pending = 0
        self._lock = threading.Lock()
        self._order = itertools.count()
        self._jobs: OrderedDict[str, dict] = OrderedDict()

    async def heavy(self, fn: Callable[..., T], *args, progress: str | None = None, message: str = "Working",
                    **kwargs) -> T:
        """Run ``fn`` on the heavy pool; 503 when the pool and its queue are full.

        progress : the client's key for GET /api/jobs/{key} (ignored unless 8-64 URL-safe characters)
        message : what the job does, shown while it runs
        """
        key = progress if progress and _KEY.match(progress) else None
        with self._lock:
            if self._pending >= self._capacity:
                wait = max(2, min(60, self._pending // max(1, self._workers)))
                raise HTTPException(503, f"The server is busy: {self._pending} computations are running or queued, "
                                         f"its limit (ERA_HEAVY_QUEUE). The page retries by itself in {wait} s.",
                                    headers={"Retry-After": str(wait)})
            self._pending += 1
            job = {"state": "queued", "message": message, "seq": next(self._order), "queued_at": time.monotonic(),
                   "started_at": None, "finished_at": None}
            if key:
                self._jobs[key] = job
                self._jobs.move_to_end(key)

        def run():
            job["state"], job["started_at"] = "running", time.monotonic()
            return fn(*args, **kwargs)

        try:
            loop = asyncio.get_running_loop()
            result = await loop.run_in_executor(self._heavy, run)
            job["state"] = "done"
            return result
        except BaseException:
            job["state"] = "failed"
            raise
        finally:
            job["finished_at"] = time.monotonic()
            with self._lock:
                self._pending -= 1
                finished = [k for k, j in self._jobs.items() if j["finished_at"] is not None]
                for k in finished[:-_FINISHED_KEPT]:
                    del self._jobs[k]

    def progress(self, key: str) -> dict | None:
        """{state, message, seconds, ahead} of a job named by its key, or None."""
        with self._lock:
            job = self._jobs.get(key)
            if job is None:
                return None
            now = time.monotonic()
            ahead = sum(1 for j in self._jobs.values() if j["state"] == "queued" and j["seq"] < job["seq"])
            since = job["started_at"] or job["queued_at"]
            end = job["finished_at"] or now
            return {"state": job["state"], "message": job["message"], "seconds": round(end - since, 2),
                    "queued_ahead": ahead if job["state"] == "queued" else 0,
                    "running_total": sum(1 for j in self._jobs.values() if j["state"] == "running")}

    async def quick(self, fn: Callable[..., T], *args, **kwargs) -> T:
        loop = asyncio.get_running_loop()
        return await loop.run_in_executor(self._quick, functools.partial(fn, *args, **kwargs))

    def shutdown(self) -> None:
        self._heavy.shutdown(wait=False, cancel_futures=True)
        self._quick.shutdown(wait=False, cancel_futures=True)
