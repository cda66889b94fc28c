"""era.core.blas: BLAS thread limits, and OpenBLAS's idle workers stopped only where that is safe.

The checks that need the caller to be the process's only Python thread run in a fresh interpreter (the test
process may hold other threads: servers, clusters)."""

import subprocess
import sys
import textwrap
import threading

from era.core import blas

_CPU_WHILE_SLEEPING = """
import time

def cpu_while_sleeping(seconds=0.05):  # process CPU seconds spent while this thread sleeps: idle workers' spin
    start = time.process_time()
    time.sleep(seconds)
    return time.process_time() - start
"""


def _run_alone(body: str) -> str:
    """Run ``body`` in a fresh interpreter; its stdout (it fails the test with its traceback if it raises)."""
    out = subprocess.run([sys.executable, "-c", _CPU_WHILE_SLEEPING + textwrap.dedent(body)], capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_rest_is_only_done_when_the_caller_is_the_only_python_thread():
    release = threading.Event()
    other = threading.Thread(target=release.wait)
    other.start()
    try:
        assert not blas.workers_can_rest()
        assert blas.rest_blas_workers() is False
    finally:
        release.set()
        other.join()
    assert _run_alone("""
        import threading
        from era.core import blas
        assert blas.workers_can_rest() and blas.rest_blas_workers()
        t = threading.Thread(target=threading.Event().wait, args=(0.5,))
        t.start()
        assert not blas.workers_can_rest() and not blas.rest_blas_workers()
        t.join()
        print("ok")
    """).strip() == "ok"


def test_stopped_workers_burn_no_cpu_and_blas_still_computes_right_after():
    _run_alone("""
        import numpy as np, scipy.linalg
        from threadpoolctl import threadpool_limits
        from era.core import blas
        a = np.random.default_rng(0).standard_normal((600, 600))
        expected = a @ a.T
        with threadpool_limits(2):
            for _ in range(3):
                a @ a.T  # a threaded call: OpenBLAS's workers spin for ~0.1 s after it
                assert blas.rest_blas_workers() is True
                spent = cpu_while_sleeping()
                assert spent < 0.02, spent  # ~0.05 per spinning worker
                np.testing.assert_allclose(a @ a.T, expected, rtol=1e-12)  # the workers start again on demand
                w = scipy.linalg.eigvalsh(expected)
                np.testing.assert_allclose(w, np.linalg.eigvalsh(expected), rtol=0, atol=1e-10 * w[-1])
    """)


def test_limits_are_applied_and_restored_and_leave_no_spinning_workers():
    _run_alone("""
        import numpy as np
        from threadpoolctl import threadpool_limits
        from era.core import blas
        a = np.random.default_rng(1).standard_normal((500, 500))
        with threadpool_limits(2):
            before = blas.blas_threads()
            with blas.single_threaded_blas():
                assert blas.blas_threads() == 1
                a @ a
            assert blas.blas_threads() == before
            spent = cpu_while_sleeping()  # restoring the count started workers; they were stopped again
            assert spent < 0.02, spent
            with blas.blas_threads_limited(2):
                a @ a
            assert blas.blas_threads() == before
    """)


def test_a_sweep_alone_in_its_process_equals_one_beside_another_thread():
    """The threaded reduction and the stopped workers (alone) against the one-thread reduction (beside a
    thread): the same singular values and stable poles to round-off."""
    out = _run_alone("""
        import threading
        import numpy as np
        from threadpoolctl import threadpool_limits
        import era
        from era.examples.synthetic import modal_response
        data, _ = modal_response(np.linspace(0.3, 14, 20), 0.01, 9, 8, 400, 1 / 32, snr_db=30, seed=0)

        def sweep():
            ident = era.identify(data, 100, 299, max_order=60)
            return ident.singular_values[:60], era.stabilization(ident, range(2, 61, 2))

        with threadpool_limits(2):
            d_alone, s_alone = sweep()
            release = threading.Event()
            other = threading.Thread(target=release.wait)
            other.start()
            d_beside, s_beside = sweep()
            release.set()
            other.join()
        np.testing.assert_allclose(d_alone, d_beside, rtol=1e-12)
        assert np.array_equal(s_alone.stable, s_beside.stable) and s_alone.stable.sum() > 100
        np.testing.assert_allclose(s_alone.frequency_hz[s_alone.stable], s_beside.frequency_hz[s_beside.stable],
                                   rtol=1e-9)
        print(int(s_alone.stable.sum()))
    """)
    assert int(out) > 100
