"""Work off the event loop: a small bounded pool for heavy jobs, a separate one for quick ones.

Heavy jobs (parsing an upload, the SVD, the stabilization diagram) run at most ``heavy_workers`` at a time
and at most ``heavy_queue`` more may wait; beyond that the request fails fast with 503 instead of piling up.
Quick jobs (realizing one order for the slider, a reconstruction) have their own threads, so a running SVD
never makes the slider wait.
"""

from __future__ import annotations

import asyncio
import functools
import threading
from concurrent.futures import ThreadPoolExecutor
from typing import Callable, TypeVar

from fastapi import HTTPException

T = TypeVar("T")


class Jobs:
    def __init__(self, heavy_workers: int, heavy_queue: int, quick_workers: int = 4):
        self._heavy = ThreadPoolExecutor(max_workers=heavy_workers, thread_name_prefix="era-heavy")
        self._quick = ThreadPoolExecutor(max_workers=quick_workers, thread_name_prefix="era-quick")
        self._capacity = heavy_workers + heavy_queue
        self._pending = 0
        self._lock = threading.Lock()

    async def heavy(self, fn: Callable[..., T], *args, **kwargs) -> T:
        """Run ``fn`` on the heavy pool; 503 when the pool and its queue are full."""
        with self._lock:
            if self._pending >= self._capacity:
                raise HTTPException(503, f"The server is busy with {self._pending} computations; "
                                         "try again in a few seconds.")
            self._pending += 1
        try:
            loop = asyncio.get_running_loop()
            return await loop.run_in_executor(self._heavy, functools.partial(fn, *args, **kwargs))
        finally:
            with self._lock:
                self._pending -= 1

    async def quick(self, fn: Callable[..., T], *args, **kwargs) -> T:
        loop = asyncio.get_running_loop()
        return await loop.run_in_executor(self._quick, functools.partial(fn, *args, **kwargs))

    def shutdown(self) -> None:
        self._heavy.shutdown(wait=False, cancel_futures=True)
        self._quick.shutdown(wait=False, cancel_futures=True)
