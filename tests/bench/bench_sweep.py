"""The whole sweep for half an SVD (issue 14): identify + stabilization(2..120) against one dense gesdd of H(0),
measured in the same process, with 1 and 2 BLAS threads, and every stable pole against the dense path's; and the
whole default path, era.analyse (orders to 160, the σ its choice reads, the choice), against the same SVD with one
BLAS thread, beside era.analyse(..., pole_std="all") (every stable pole's σ, the path before).

Run: nice -n 5 python3 -m pytest tests/bench/bench_sweep.py -s
The sizes are those of the issue: H(0) 900 × 2392 (grid-like, p = 9, m = 8) and 1280 × 2000 (p = 32, m = 4).
Timings are interleaved (SVD, sweep, SVD, sweep, ...) and their medians compared, so a neighbour's load hits both.
"""

import os
import time

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

import era
from era.examples.synthetic import modal_response
from era.core.hankel import block_hankel
from era.core.svd import dense_svd

ORDERS = range(2, 121, 2)
CASES = {  # (p, m, N, rows, cols, dt, frequencies)
    "900x2392 p=9 m=8": (9, 8, 400, 100, 299, 1 / 32, np.linspace(0.3, 14, 20)),
    "1280x2000 p=32 m=4": (32, 4, 2000, 40, 500, 0.01, np.linspace(1, 45, 25)),
}
REPEAT = 5


@pytest.fixture(scope="module", params=list(CASES), ids=list(CASES))
def case(request):
    p, m, n, rows, cols, dt, f = CASES[request.param]
    data, _ = modal_response(f, 0.01, p, m, n, dt, snr_db=30, seed=0)
    return request.param, data, rows, cols


def _sweep(data, rows, cols, **kw):
    ident = era.identify(data, rows, cols, max_order=max(ORDERS))
    return ident, era.stabilization(ident, ORDERS, **kw)


def _timed(fn):
    """(wall-clock, CPU) seconds of one call: the CPU time of a one-thread run is what a neighbour's load on a
    shared machine disturbs least."""
    wall, cpu = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - wall, time.process_time() - cpu


def _ratios(data, rows, cols, threads):
    h0 = block_hankel(data.markov, np.arange(rows), np.arange(cols))
    with threadpool_limits(threads):
        _sweep(data, rows, cols)  # warm-up
        t_svd, t_sweep, t_sigma = [], [], []
        for _ in range(REPEAT):  # interleaved, so a neighbour's load hits both
            t_svd.append(_timed(lambda: dense_svd(h0)))
            t_sweep.append(_timed(lambda: _sweep(data, rows, cols)))
            t_sigma.append(_timed(lambda: _sweep(data, rows, cols, uncertainty=True)))
    wall = [np.median([t[0] for t in x]) for x in (t_svd, t_sweep, t_sigma)]
    cpu = [min(t[1] for t in x) for x in (t_svd, t_sweep)]
    return h0.shape, wall, cpu


#: the wall-clock ratio on the 2-core machine of the issue, shared with other jobs (the issue's target is 0.5 at
#: both thread counts): ratio ≤ LIMIT[case][threads] guards against regressions; the figures printed (and the
#: one-thread CPU-time ratio, which a neighbour's load disturbs least) are the measurement.
LIMIT = {"900x2392 p=9 m=8": {1: 0.55, 2: 0.55}, "1280x2000 p=32 m=4": {1: 0.4, 2: 0.4}}


def test_identify_and_stabilization_against_one_dense_svd_with_1_and_2_threads(case):
    """Measured (README, issue 14): see the section "Uncertainty of each mode, repeated modes, the sweep's cost".
    On 1280 × 2000 with two threads, wall-clock ms inside this loop against the gesdd's ~930: identify ≈ 125
    (the Gram matrix 8, its tridiagonal reduction 65, sterf 20.5 on one core while the other builds the
    reflectors' factors and H(0), stein 6.5, the reflectors 6.5, h^T v 10.5), the 60 eigensolutions ≈ 86, γ, μ
    and the contribution ≈ 30, tracking ≈ 5. With two threads the orders and the runs of modes go two at a time
    and identify's reduction takes both threads, OpenBLAS's idle workers being stopped after it
    (era.core.blas.rest_blas_workers). The ratio must not be worse with two threads than with one (5 % for noise)."""
    name, data, rows, cols = case
    assert era.identify(data, rows, cols, max_order=max(ORDERS)).svd_method == "truncated"
    ratio = {}
    for threads in (1, 2):
        shape, (svd, sweep, sigma), (svd_cpu, sweep_cpu) = _ratios(data, rows, cols, threads)
        cpu = f" | CPU time {sweep_cpu:.3f} s / {svd_cpu:.3f} s = {sweep_cpu / svd_cpu:.2f}×" if threads == 1 else ""
        print(f"\n[{name}, {threads} BLAS thread(s)] H(0) {shape[0]}×{shape[1]}: one dense gesdd {svd:.3f} s | "
              f"identify + stabilization(2..120) {sweep:.3f} s = {sweep / svd:.2f}× SVD (issue target 0.5){cpu} | "
              f"with the stable poles' σ {sigma:.3f} s = {sigma / svd:.2f}× SVD | load {os.getloadavg()[0]:.1f}")
        assert sweep / svd <= LIMIT[name][threads]
        ratio[threads] = sweep / svd
    assert ratio[2] <= 1.05 * ratio[1]


def test_every_stable_pole_equals_the_dense_paths_to_1e_8(case):
    name, data, rows, cols = case
    fast, stab_fast = _sweep(data, rows, cols)
    dense = era.identify(data, rows, cols, svd_method="dense")
    stab_dense = era.stabilization(dense, ORDERS)
    np.testing.assert_allclose(fast.singular_values[:120], dense.singular_values[:120], rtol=1e-10)
    assert np.array_equal(stab_fast.stable, stab_dense.stable)
    worst = 0.0
    for n in ORDERS:
        at = stab_dense.order == n
        stable = stab_dense.stable[at]
        if not stable.any():
            continue
        s_fast, s_dense = fast.model(n, uncertainty=False).eigenvalues, dense.model(n, uncertainty=False).eigenvalues
        rel = np.abs(s_fast[stable] - s_dense[stable]) / np.abs(s_dense[stable])
        worst = max(worst, float(rel.max()))
    print(f"\n[{name}] {int(stab_dense.stable.sum())} stable poles over orders 2..120: largest relative difference "
          f"truncated vs dense {worst:.1e}")
    assert worst <= 1e-8


def _analyse_ratios(data, rows, cols, repeat=REPEAT):
    """Medians of wall-clock and minima of CPU seconds, one BLAS thread, interleaved: one dense gesdd of H(0),
    era.analyse with the σ its choice reads, and with every stable pole's σ."""
    h0 = block_hankel(data.markov, np.arange(rows), np.arange(cols))
    runs = {"svd": lambda: dense_svd(h0), "analyse": lambda: era.analyse(data, rows=rows, cols=cols),
            "all": lambda: era.analyse(data, rows=rows, cols=cols, pole_std="all")}
    times = {k: [] for k in runs}
    with threadpool_limits(1):
        runs["analyse"]()  # warm-up
        for _ in range(repeat):
            for k, fn in runs.items():
                times[k].append(_timed(fn))
    wall = {k: float(np.median([t[0] for t in v])) for k, v in times.items()}
    cpu = {k: min(t[1] for t in v) for k, v in times.items()}
    return h0.shape, wall, cpu


#: era.analyse over one dense SVD with one BLAS thread, wall-clock: at most what it was with every stable pole's σ
#: on a quiet machine (2.53 and 1.65), a guard against regressions that holds at a load of 8-9 on 2 cores; the
#: issue's target is 0.5, what was reached is in docs/performance.md#analyse.
ANALYSE_LIMIT = {"900x2392 p=9 m=8": 2.5, "1280x2000 p=32 m=4": 1.65}


def test_the_default_analysis_against_one_dense_svd_with_one_blas_thread(case):
    """era.analyse(data, rows, cols) as a user calls it (max_order 200, the diagram to 160, the σ its choice
    reads, the choice, the chosen model) against one gesdd of the same H(0); "before": every stable pole's σ.
    The choice is the same with both (tests/core/test_choice_std.py)."""
    name, data, rows, cols = case
    shape, wall, cpu = _analyse_ratios(data, rows, cols)
    print(f"\n[{name}, 1 BLAS thread] H(0) {shape[0]}×{shape[1]}: one dense gesdd {wall['svd']:.3f} s | "
          f"era.analyse {wall['analyse']:.3f} s = {wall['analyse'] / wall['svd']:.2f}× SVD (CPU "
          f"{cpu['analyse'] / cpu['svd']:.2f}×; issue target 0.5) | with every stable pole's σ {wall['all']:.3f} s = "
          f"{wall['all'] / wall['svd']:.2f}× (CPU {cpu['all'] / cpu['svd']:.2f}×) | load {os.getloadavg()[0]:.1f}")
    assert wall["analyse"] < wall["all"]
    assert wall["analyse"] / wall["svd"] <= ANALYSE_LIMIT[name]
