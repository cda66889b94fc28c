"""CPU-bound pure work (an SVD, a stabilization diagram, explain) in worker processes, not in the app's threads.

The app's threads share one GIL: a stabilization loop in a heavy thread would hold it against the slider's quick
threads. Worker processes have their own interpreter, run at low CPU priority (nice +10) with one BLAS thread,
so on a 2-core server the slider keeps its cores and its GIL while identifications run. The pool is one per Python
process, started with the server (:func:`start`: its workers import era while the server answers, so the first
upload does not wait for them) or else on first use (spawned: safe next to threads), by one thread that lives as
long as the process, and shared by every app instance in it; functions and arguments must be picklable (era's
dataclasses are). ``run`` blocks: call it from a heavy-pool thread.
"""

from __future__ import annotations

import atexit
import multiprocessing
import os
import signal
import threading
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Callable, TypeVar

T = TypeVar("T")
#: CPU priority (nice) of the worker processes: behind the app process at 0.
WORKER_NICE = 10

_pool: ProcessPoolExecutor | None = None
_lock = threading.Lock()


def _init_worker(parent: int) -> None:
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = "1"
    try:
        os.nice(WORKER_NICE)
    except OSError:
        pass
    _die_with(parent)


def _die_with(parent: int) -> None:
    """End this worker when the app process ends, however it ends (kill -9 included): the kernel's parent-death
    signal on Linux, and a watch on the parent's pid everywhere (a spawned worker would otherwise live on)."""
    try:
        import ctypes
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent:  # the parent died before the signal was armed
        os._exit(0)

    def watch():
        while True:
            time.sleep(1.0)
            if os.getppid() != parent:
                os._exit(0)

    threading.Thread(target=watch, name="parent-watch", daemon=True).start()


#: The thread that starts the worker processes, alive as long as this process: a worker ends with the thread that
#: started it (the parent-death signal is the thread's), so workers started by an app's lifespan or a request's
#: thread would end with it, and the next app in the process (tests run hundreds) would start new ones.
_starter = ThreadPoolExecutor(max_workers=1, thread_name_prefix="era-worker-starter")


def _new_pool(workers: int) -> ProcessPoolExecutor:
    """A pool of ``workers`` processes, each started now (by the first submits: spawned pools start one process per
    submit until full) and importing era."""
    pool = ProcessPoolExecutor(max_workers=workers, initializer=_init_worker, initargs=(os.getpid(),),
                               mp_context=multiprocessing.get_context("spawn"))
    for _ in range(workers):
        pool.submit(_ready)
    return pool


def _executor(workers: int) -> ProcessPoolExecutor:
    global _pool
    with _lock:
        if _pool is None:
            _pool = _starter.submit(_new_pool, max(1, workers)).result()
        return _pool


def _ready() -> int:
    """Import in a worker what every analysis needs (a spawned worker starts with nothing): era, scipy's LAPACK;
    then one small analysis, so that the first upload does not pay for what a first call loads (scipy's FFT,
    the LAPACK routines era finds by ctypes, the thread pools' controller)."""
    import scipy.linalg  # noqa: F401

    import era
    from era.examples.synthetic import modal_response

    data, _ = modal_response([1.0, 2.5], 0.02, 2, 1, 80, 0.05, snr_db=40, seed=0)
    era.analyse(data, workers=2)
    return os.getpid()


def start(workers: int = 2) -> None:
    """Start the pool's ``workers`` processes now (they import era at once), without waiting for them; a pool
    already running is kept, a broken one (a worker was killed) replaced."""
    with _lock:
        broken = _pool is not None and getattr(_pool, "_broken", False)
    if broken:
        _reset()
    _executor(workers)


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
