"""era.blas: BLAS thread limits, and OpenBLAS's idle workers stopped only where that is safe."""

import threading
import time

import numpy as np
import pytest
import scipy.linalg
from threadpoolctl import threadpool_limits

from era import blas


def _cpu_while_sleeping(seconds: float = 0.05) -> float:
    """Process CPU seconds spent while the calling thread sleeps (what idle BLAS workers burn)."""
    start = time.process_time()
    time.sleep(seconds)
    return time.process_time() - start


def test_rest_is_only_done_when_the_caller_is_the_only_python_thread():
    assert blas.workers_can_rest() == (threading.active_count() == 1)
    release = threading.Event()
    other = threading.Thread(target=release.wait)
    other.start()
    try:
        assert not blas.workers_can_rest()
        assert blas.rest_blas_workers() is False
    finally:
        release.set()
        other.join()


def test_stopped_workers_burn_no_cpu_and_blas_still_computes_right_after():
    if not blas.workers_can_rest():
        pytest.skip("another Python thread runs in this test process")
    a = np.random.default_rng(0).standard_normal((600, 600))
    expected = a @ a.T
    with threadpool_limits(2):
        for _ in range(3):
            a @ a.T  # a threaded call: OpenBLAS's workers spin for ~0.1 s after it
            assert blas.rest_blas_workers() is True
            assert _cpu_while_sleeping() < 0.02  # would be ~0.05 per spinning worker
            np.testing.assert_allclose(a @ a.T, expected, rtol=1e-12)  # the workers start again on demand
            w = scipy.linalg.eigvalsh(expected)
            np.testing.assert_allclose(w, np.linalg.eigvalsh(expected), rtol=0, atol=1e-10 * w[-1])


def test_limits_are_applied_and_restored_and_leave_no_spinning_workers():
    if not blas.workers_can_rest():
        pytest.skip("another Python thread runs in this test process")
    a = np.random.default_rng(1).standard_normal((500, 500))
    with threadpool_limits(2):
        before = blas.blas_threads()
        with blas.single_threaded_blas():
            assert blas.blas_threads() == 1
            a @ a
        assert blas.blas_threads() == before
        assert _cpu_while_sleeping() < 0.02  # restoring the count started workers; they were stopped again
        with blas.blas_threads_limited(2):
            a @ a
        assert blas.blas_threads() == before
