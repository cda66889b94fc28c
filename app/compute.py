"""CPU-bound pure work (an SVD, a stabilization diagram, explain) in worker processes, not in the app's threads.

The app's threads share one GIL: a stabilization loop in a heavy thread would hold it against the slider's quick
threads. Worker processes have their own interpreter, run at low CPU priority (nice +10) with one BLAS thread,
so on a 2-core server the slider keeps its cores and its GIL while identifications run. The pool is one per Python
process, created on first use (spawned: safe next to threads) and shared by every app instance in it; functions
and arguments must be picklable (era's dataclasses are). ``run`` blocks: call it from a heavy-pool thread.
"""

from __future__ import annotations

import atexit
import multiprocessing
import os
import threading
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Callable, TypeVar

T = TypeVar("T")
#: CPU priority (nice) of the worker processes: behind the app process at 0.
WORKER_NICE = 10

_pool: ProcessPoolExecutor | None = None
_lock = threading.Lock()


def _init_worker() -> None:
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = "1"
    try:
        os.nice(WORKER_NICE)
    except OSError:
        pass


def _executor(workers: int) -> ProcessPoolExecutor:
    global _pool
    with _lock:
        if _pool is None:
            _pool = ProcessPoolExecutor(max_workers=max(1, workers), initializer=_init_worker,
                                        mp_context=multiprocessing.get_context("spawn"))
        return _pool


def _reset() -> None:
    global _pool
    with _lock:
        if _pool is not None:
            _pool.shutdown(wait=False, cancel_futures=True)
        _pool = None


def run(fn: Callable[..., T], *args, workers: int = 2, **kwargs) -> T:
    """``fn(*args, **kwargs)`` in a worker process; a pool broken by a killed worker is rebuilt once."""
    try:
        return _executor(workers).submit(fn, *args, **kwargs).result()
    except BrokenProcessPool:
        _reset()
        return _executor(workers).submit(fn, *args, **kwargs).result()


atexit.register(_reset)
