"""The truncated SVD (Gram matrix + one Rayleigh-Ritz step) that the sweep takes when max_order is far below
min(H(0) shape): the same singular values, poles and indicators as the dense path."""

import numpy as np

import era
from era.examples.paper_cases import case_1
from era.examples.synthetic import modal_response
from era.svd import dense_svd, truncated_svd


def test_auto_takes_the_truncated_svd_only_when_the_order_is_far_below_the_shape():
    data, _ = modal_response(np.linspace(2, 40, 12), 0.01, 6, 4, 900, 0.01, snr_db=40, seed=2)
    assert era.identify(data, rows=50, cols=100, max_order=40).svd_method == "truncated"  # 40 ≤ 300 / 4
    assert era.identify(data, rows=50, cols=100, max_order=200).svd_method == "dense"
    assert era.identify(data, rows=50, cols=100).svd_method == "dense"


def test_truncated_sweep_equals_the_dense_one_pole_by_pole():
    data, _ = modal_response(np.linspace(2, 40, 12), 0.01, 6, 4, 900, 0.01, snr_db=30, seed=2)
    fast = era.identify(data, rows=50, cols=100, max_order=60)
    dense = era.identify(data, rows=50, cols=100, svd_method="dense")
    np.testing.assert_allclose(fast.singular_values[:60], dense.singular_values[:60], rtol=1e-11)
    orders = range(2, 61, 2)
    a, b = era.stabilization(fast, orders), era.stabilization(dense, orders)
    assert np.array_equal(a.order, b.order) and np.array_equal(a.stable, b.stable)
    np.testing.assert_allclose(a.frequency_hz, b.frequency_hz, rtol=1e-8)
    np.testing.assert_allclose(a.damping_ratio[a.stable], b.damping_ratio[b.stable], rtol=1e-7)
    np.testing.assert_allclose(a.emac[a.stable], b.emac[b.stable], atol=1e-8)
    np.testing.assert_allclose(a.mpc[a.stable], b.mpc[b.stable], atol=1e-8)


def test_truncated_singular_values_keep_the_round_off_of_the_dense_ones():
    """Noise-free Case I: past the rank, the values stay at round-off (not ε·d_1²/d_i as a Gram matrix alone
    would give), so the δ test (eqs. 38-39) finds order 10 on this path too."""
    ident = era.identify(case_1(), rows=90, cols=90, max_order=20)
    assert ident.svd_method == "truncated"
    d = ident.singular_values
    assert ident.order(tol=1e-12) == 10 and d[10] / d[0] < 1e-13
    np.testing.assert_allclose(ident.realize(10).frequency_hz, np.arange(1, 6) / (2 * np.pi), rtol=1e-8)


def test_truncated_triplets_are_orthonormal_and_wide_matrices_work():
    rng = np.random.default_rng(0)
    h = (rng.standard_normal((120, 30)) * np.logspace(0, -4, 30)) @ rng.standard_normal((30, 200))
    for m in (h, h.T):  # values down to 2e-3 d_1: the direct Gram route (orthogonality to ε d_1²/d_k²)
        p, d, q = truncated_svd(m, 20)
        np.testing.assert_allclose(p.T @ p, np.eye(20), atol=1e-10)
        np.testing.assert_allclose(q.T @ q, np.eye(20), atol=1e-10)
        exact = dense_svd(m)[1]
        np.testing.assert_allclose(d[:20], exact[:20], rtol=1e-10)
        np.testing.assert_allclose(m @ q, p * d[:20], atol=1e-10 * d[0])
        # the values past the rank, from the Gram matrix (the plot and the order suggestion): to ε d_1²/d_i²
        # relative above its round-off, at its round-off (√ε d_1, not ε d_1) where H(0) has none (rank 30)
        assert d.size == 120 and np.all(np.diff(d) <= 0)
        np.testing.assert_allclose(d[20:30], exact[20:30], rtol=1e-6)
        assert np.all(d[30:] < 1e-6 * d[0])
