"""How many BLAS threads the core uses where it matters (threadpoolctl, a dependency; process-wide limits)."""

from __future__ import annotations

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
    """A context with one BLAS thread (process-wide while it lasts).

    For work that a threaded BLAS slows down: small eigensolutions and batched products run side by side in the
    sweep's own threads (era.sweep.in_parallel), and the truncated SVD and projection that come just before
    them. OpenBLAS's worker threads keep spinning for about 0.1 s after a threaded call, so a threaded call
    just before the sweep's threads takes a core from them: on the 2-core machine measured, the 60
    eigensolutions of tests/bench/bench_sweep.py in 2 threads took 85 ms when no threaded call preceded them,
    117-130 ms right after one (100 ms after 50 ms, 91 ms after 0.1 s). The truncated SVD's steps gain less
    from 2 threads than that (its tridiagonal reduction 41 → 26 ms, idle).
    """
    return blas_threads_limited(1)


def blas_threads_limited(threads: int):
    """A context with at most ``threads`` BLAS threads (process-wide while it lasts)."""
    return _controller().limit(limits=max(1, int(threads)), user_api="blas")
