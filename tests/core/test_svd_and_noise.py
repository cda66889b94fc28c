"""The randomized SVD path for large H(0), and identification of known systems from noisy data."""

import numpy as np
import pytest

import era
from era.core.svd import dense_svd, randomized_svd
from era.examples.synthetic import modal_response


def test_randomized_svd_agrees_with_the_dense_one_on_a_size_where_both_run():
    data, _ = modal_response(np.linspace(2, 40, 12), 0.01, 6, 4, 900, 0.01, snr_db=40, seed=2)
    dense = era.identify(data, rows=100, cols=200, svd_method="dense")
    fast = era.identify(data, rows=100, cols=200, svd_method="randomized", max_order=60)
    assert fast.svd_method == "randomized" and fast.singular_values.size == 60
    np.testing.assert_allclose(fast.singular_values[:24], dense.singular_values[:24], rtol=1e-10)
    a, b = dense.realize(24), fast.realize(24)
    np.testing.assert_allclose(b.frequency_hz, a.frequency_hz, rtol=1e-9)
    np.testing.assert_allclose(b.damping_ratio, a.damping_ratio, rtol=1e-6, atol=1e-10)
    np.testing.assert_allclose(b.emac, a.emac, atol=1e-8)
    with pytest.raises(era.OrderError, match="larger max_order"):
        fast.realize(61)


def test_randomized_triplets_are_orthonormal():
    rng = np.random.default_rng(0)
    h = (rng.standard_normal((300, 30)) * np.logspace(0, -4, 30)) @ rng.standard_normal((30, 200))
    p, d, q = randomized_svd(h, 20)
    np.testing.assert_allclose(p.T @ p, np.eye(20), atol=1e-12)
    np.testing.assert_allclose(q.T @ q, np.eye(20), atol=1e-12)
    np.testing.assert_allclose(d, dense_svd(h)[1][:20], rtol=1e-10)


def test_auto_switches_to_randomized_above_the_work_limit(monkeypatch):
    monkeypatch.setattr(era.core.svd, "DENSE_SVD_WORK_LIMIT", 1e3)
    data, _ = modal_response([1.0], 0.01, 1, 1, 100, 0.05, seed=0)
    assert era.identify(data, rows=20, cols=20, max_order=10).svd_method == "randomized"


@pytest.mark.parametrize("snr_db, seed", [(20, 0), (30, 1), (40, 2)])
def test_close_modes_at_realistic_noise_are_found_and_noise_modes_told_apart(snr_db, seed):
    f = np.array([4.0, 9.5, 9.8, 15.0, 21.0])  # 9.5 / 9.8 Hz: 3 % apart
    zeta = np.array([0.002, 0.01, 0.012, 0.03, 0.005])
    data, truth = modal_response(f, zeta, n_outputs=6, n_inputs=2, n_samples=2000, dt=0.01, snr_db=snr_db, seed=seed)
    model = era.identify(data, rows=50, cols=400).realize(40)
    system = model.select(min_emac=0.8, min_mpc=0.8, min_contribution=0.05)
    assert system.n_modes == 5, (snr_db, system.frequency_hz)
    np.testing.assert_allclose(system.frequency_hz, f, rtol=2e-3)
    np.testing.assert_allclose(system.damping_ratio, zeta, atol=0.004 if snr_db == 20 else 0.002)
    noise = np.setdiff1d(np.arange(model.n_modes), [np.argmin(abs(model.frequency_hz - x)) for x in f])
    assert np.median(model.emac[noise] * model.mpc[noise]) < 0.7
    assert np.min(era.mac(system.shapes, truth.shapes).diagonal()) > 0.99


def test_repeated_modes_need_several_inputs():
    shapes = np.random.default_rng(5).standard_normal((6, 3))
    f, zeta = [3.0, 3.0, 6.0], [0.01, 0.01, 0.01]
    mimo, _ = modal_response(f, zeta, 6, 2, 800, 0.02, seed=5, shapes=shapes)
    siso, _ = modal_response(f, zeta, 6, 1, 800, 0.02, seed=5, shapes=shapes)
    assert era.identify(mimo, rows=30, cols=60).order() == 6
    assert era.identify(siso, rows=30, cols=60).order() == 4
