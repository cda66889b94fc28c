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
    """A context with one BLAS thread (process-wide while it lasts), for work that a threaded BLAS slows down:
    small eigensolutions run side by side in threads, and the memory-bound steps of the truncated SVD (the
    Gram matrix's thin first block row and its tridiagonal reduction, 25-40 % slower with 2 threads on the
    2-core machines measured: tests/bench/bench_sweep.py)."""
    return _controller().limit(limits=1, user_api="blas")
