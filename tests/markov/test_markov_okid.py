"""OKID (Juang, Phan, Horta & Longman 1993): a simulated noisy shaker test, and real hammer records (ladisk)."""


import numpy as np
import pytest

import era
from chain_sim import chain, simulate
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

SHARED = SHARED_DATASETS
LADISK = SHARED / "ladisk_pyfrf_impact"


def test_noise_free_records_give_the_exact_markov_parameters():
    ad, bd, cd, dd, _, _ = chain(0.005)
    u = np.random.default_rng(0).standard_normal((3000, 2))
    y = simulate(ad, bd[:, :2], cd, dd[:, :2], u)
    data = era.markov_from_io(u, y, 0.005, n_observer=6, n_markov=50)
    exact = np.stack([cd @ np.linalg.matrix_power(ad, k) @ bd[:, :2] for k in range(50)])  # Y_1..Y_50 = C A^k B
    np.testing.assert_allclose(data.markov, exact, atol=1e-9 * np.abs(exact).max())
    np.testing.assert_allclose(data.meta["direct_term"], dd[:, :2], atol=1e-9)
    assert data.meta["fit_residual"] < 1e-9


def test_noisy_shaker_test_recovers_the_known_modes():
    ad, bd, cd, dd, f_modes, zeta = chain(0.005)
    rng = np.random.default_rng(1)
    force = rng.standard_normal((20000, 1))  # random shaker force on mass 3
    acc = simulate(ad, bd[:, 2:], cd, dd[:, 2:], force)
    acc_meas = acc + 0.05 * acc.std(axis=0) * rng.standard_normal(acc.shape)  # 5 % sensor noise
    force_meas = force + 0.02 * rng.standard_normal(force.shape)
    data = era.markov_from_io(force_meas, acc_meas, 0.005, n_observer=20, n_markov=200,
                              output_names=["a1", "a2", "a3"], input_names=["shaker"],
                              output_units=["m/s^2"] * 3, input_units=["N"])
    assert data.markov.shape == (200, 3, 1) and data.inputs == ("shaker",) and data.input_units == ("N",)
    model = era.identify(data, rows=40, cols=40).realize(order=6)
    order = np.argsort(model.frequency_hz)
    np.testing.assert_allclose(model.frequency_hz[order], f_modes, rtol=2e-3)
    np.testing.assert_allclose(model.damping_ratio[order], zeta, rtol=0.1)


def test_several_records_are_fitted_together_and_bad_records_refused():
    ad, bd, cd, dd, f_modes, _ = chain(0.005)
    rng = np.random.default_rng(2)
    us = [rng.standard_normal((1500, 1)) for _ in range(3)]
    ys = [simulate(ad, bd[:, :1], cd, dd[:, :1], u) for u in us]
    data = era.markov_from_io(us, ys, 0.005, n_observer=8)
    model = era.identify(data, rows=20, cols=20).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-6)
    with pytest.raises(era.DataError, match="Record 1: 1500 input samples but 1499"):
        era.markov_from_io(us, [ys[0], ys[1][:-1], ys[2]], 0.005)
    with pytest.raises(era.DataError, match="Too few samples for OKID"):
        era.markov_from_io(us[0][:100], ys[0][:100], 0.005, n_observer=40)
    with pytest.raises(era.DataError, match="all zero"):
        era.markov_from_io(np.zeros((1500, 1)), ys[0], 0.005)


@pytest.fixture(scope="module")
def hammer():
    require_shared(LADISK)
    recs = [np.load(LADISK / f"measurements_{k}.npy") for k in range(1, 6)]  # (3, 25600): t, force N, acc m/s²
    return recs


def test_real_hammer_records_give_the_strong_h1_peaks(hammer):
    dt = float(hammer[0][0, 1] - hammer[0][0, 0])
    assert 1 / dt == pytest.approx(25600, rel=1e-6)
    data = era.markov_from_io([r[1][:, None] for r in hammer], [r[2][:, None] for r in hammer], dt,
                              n_observer=40, n_markov=2000, input_units=["N"], output_units=["m/s^2"])
    assert data.meta["fit_residual"] < 0.05  # the ARX fit explains > 95 % of the response
    model = era.identify(data, rows=400, cols=400).realize(order=40)
    strong = model.select(min_contribution=0.01)
    # H1 peaks of this test (dataset README): ~900, 2640, 3669/3690, 4128/4164, 4392 Hz
    for peak in (900.0, 2640.0, 3669.0, 4128.0, 4392.0):
        assert np.min(np.abs(strong.frequency_hz - peak)) < 0.01 * peak, peak
