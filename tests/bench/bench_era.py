"""ERA speed as ratios against references run in the same process.

Run: python3 -m pip install -e '.[bench]' && python3 -m pytest tests/bench/bench_era.py -s
References: one dense SVD of H(0) (LAPACK gesdd), and python-control's eigensys_realization on the same data.
"""

import tracemalloc

import numpy as np
import pytest

import era
from era.core.hankel import block_hankel
from era.core.svd import dense_svd
from era.examples.synthetic import modal_response
from timing import median_time

ORDERS = range(2, 121, 2)
CASES = {  # (p, m, N, rows, cols, dt, frequencies)
    "grid-like p=9 m=8 N=400": (9, 8, 400, 100, 299, 1 / 32, np.linspace(0.3, 14, 20)),
    "p=32 m=4 N=2000": (32, 4, 2000, 40, 500, 0.01, np.linspace(1, 45, 25)),
}


@pytest.fixture(scope="module", params=list(CASES), ids=list(CASES))
def case(request):
    p, m, n, rows, cols, dt, f = CASES[request.param]
    data, _ = modal_response(f, 0.01, p, m, n, dt, snr_db=30, seed=0)
    h0 = block_hankel(data.markov, np.arange(rows), np.arange(cols))
    t_svd = median_time(lambda: dense_svd(h0))
    return request.param, data, rows, cols, h0.shape, t_svd


def test_stabilization_costs_at_most_one_and_a_half_svds(case):
    name, data, rows, cols, shape, t_svd = case
    ident = era.identify(data, rows, cols)
    t_ident = median_time(lambda: era.identify(data, rows, cols), repeat=2)
    t_stab = median_time(lambda: era.stabilization(ident, ORDERS))
    print(f"\n[{name}] H(0) {shape[0]}×{shape[1]}: one SVD {t_svd:.3f} s | identify {t_ident:.3f} s "
          f"({t_ident / t_svd:.2f}× SVD) | stabilization of {len(ORDERS)} orders {t_stab:.3f} s "
          f"({t_stab / t_svd:.2f}× SVD)")
    assert t_stab <= 1.5 * t_svd


def test_peak_memory_next_to_the_size_of_h0(case):
    name, data, rows, cols, shape, _ = case
    h0_mb = shape[0] * shape[1] * 8 / 1e6
    tracemalloc.start()
    ident = era.identify(data, rows, cols)
    era.stabilization(ident, ORDERS)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print(f"\n[{name}] H(0) {h0_mb:.1f} MB, peak traced memory of identify + stabilization {peak / 1e6:.1f} MB "
          f"({peak / 1e6 / h0_mb:.1f}× H(0))")
    assert peak / 1e6 < 8 * h0_mb


def test_against_python_control(case):
    control = pytest.importorskip("control")
    name, data, rows, cols, shape, _ = case
    # python-control wants (outputs, inputs, samples) with Y(0) = D in front
    yy = np.concatenate([np.zeros((1,) + data.markov.shape[1:]), data.markov]).transpose(1, 2, 0)

    def peer(order):
        sys, _ = control.eigensys_realization(yy, order, m=rows, n=cols)
        return np.linalg.eigvals(sys.A)

    def ours_one(order):
        return era.identify(data, rows, cols).realize(order).eigenvalues

    t_peer_one = median_time(lambda: peer(40), repeat=5)
    t_ours_one = median_time(lambda: ours_one(40), repeat=5)
    t_ours_sweep = median_time(lambda: era.stabilization(era.identify(data, rows, cols), ORDERS), repeat=2)
    # python-control recomputes the SVD for every order, so its sweep is len(ORDERS) calls of about equal cost
    t_peer_sweep = t_peer_one * len(ORDERS)
    print(f"\n[{name}] one order: ours {t_ours_one:.3f} s, python-control {t_peer_one:.3f} s "
          f"(ours {t_peer_one / t_ours_one:.1f}× faster) | sweep of {len(ORDERS)} orders: ours {t_ours_sweep:.3f} s, "
          f"python-control ≈ {t_peer_sweep:.1f} s (ours {t_peer_sweep / t_ours_sweep:.0f}× faster)")
    # the same eigenvalues at order 40
    z = np.exp(ours_one(40) * data.dt)
    np.testing.assert_allclose(np.sort_complex(np.concatenate([z, z[z.imag > 0].conj()])),
                               np.sort_complex(peer(40)), atol=1e-8)
    assert t_ours_one <= t_peer_one
    assert t_peer_sweep >= 20 * t_ours_sweep
