"""How many BLAS threads the core uses where it matters (threadpoolctl, a dependency; process-wide limits)."""

from __future__ import annotations

import ctypes
import threading
from contextlib import contextmanager
from functools import lru_cache

import numpy as np  # noqa: F401  (loaded first, so the controller sees its BLAS)
from threadpoolctl import ThreadpoolController


@lru_cache(maxsize=1)
def _controller() -> ThreadpoolController:
    """The process's thread pools, found once (threadpoolctl's functions search the loaded libraries on every
    call: 0.2-2 ms each, several times per sweep)."""
    return ThreadpoolController()


def blas_threads() -> int:
    """Threads the loaded BLAS may use now (so an enclosing ``threadpool_limits`` applies). The sweep runs that
    many orders at a time: each order's eigensolution is too small for a threaded BLAS, so threads across
    orders are what makes the sweep scale like the SVD does."""
    counts = [int(lib.get("num_threads") or 1) for lib in _controller().info() if lib.get("user_api") == "blas"]
    return max(counts, default=1)


def single_threaded_blas():
    """A context with one BLAS thread (process-wide while it lasts): for work that a threaded BLAS slows down,
    such as small eigensolutions and batched products run side by side in the sweep's own threads
    (era.core.sweep.in_parallel)."""
    return blas_threads_limited(1)


@contextmanager
def blas_threads_limited(threads: int):
    """A context with at most ``threads`` BLAS threads (process-wide while it lasts).

    Where it is safe (:func:`workers_can_rest`), OpenBLAS's idle workers are stopped after the limit is set and
    after it is lifted (:func:`rest_blas_workers`): OpenBLAS starts a stopped pool again whenever its thread
    count is set, and a fresh worker spins for 0.1 s, so without that every limit would leave spinning workers
    behind in each OpenBLAS loaded (numpy's and scipy's). A threaded call starts the workers it needs."""
    try:
        with _controller().limit(limits=max(1, int(threads)), user_api="blas"):
            rest_blas_workers()
            yield
    finally:  # also when the body raised: no spinning workers left behind
        rest_blas_workers()


@lru_cache(maxsize=1)
def _openblas_shutdowns() -> tuple:
    """``blas_thread_shutdown_`` of each loaded OpenBLAS with its own pthreads pool (numpy and scipy each bring
    one), found once; an OpenMP build's threads are OpenMP's, and are left alone."""
    found = []
    for lib in _controller().lib_controllers:
        if getattr(lib, "internal_api", "") != "openblas" or getattr(lib, "threading_layer", "") != "pthreads":
            continue
        try:
            fn = ctypes.CDLL(lib.filepath).blas_thread_shutdown_
        except (OSError, AttributeError):
            continue
        fn.argtypes, fn.restype = [], ctypes.c_int
        found.append(fn)
    return tuple(found)


def workers_can_rest() -> bool:
    """Whether :func:`rest_blas_workers` may stop OpenBLAS's workers now: only when the calling thread is the
    process's only Python thread. OpenBLAS's shutdown is not safe against a threaded call running in another
    thread at the same time, which a lone thread rules out (in the app's worker processes, with their watch
    thread, and under Dask's threads it is never done)."""
    return threading.active_count() == 1


def rest_blas_workers() -> bool:
    """Stop OpenBLAS's worker threads now, when :func:`workers_can_rest`; returns whether they were stopped.
    The next threaded call starts them again. Stopping a pool takes 0.03-0.14 ms, but 1-4 ms while the other
    core is busy with a spinning worker (6-11 ms in all per sweep of tests/bench/bench_sweep.py with 2
    threads); a tridiagonal reduction of order 900 with 2 threads took 29.4 ms on fresh workers and 29.3 ms
    on spinning ones.

    After a threaded call they spin for about 0.1 s (OpenBLAS's THREAD_TIMEOUT, fixed when the library loads)
    and take a core from the Python threads that follow: on the 2-core machine measured, the 60 eigensolutions
    of tests/bench/bench_sweep.py in 2 threads took 85 ms when no threaded call preceded them, 117-130 ms right
    after one."""
    if not workers_can_rest():
        return False
    for shutdown in _openblas_shutdowns():
        shutdown()
    return True
