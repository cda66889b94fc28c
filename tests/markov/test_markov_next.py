"""NExT (James, Carne & Lauffer 1995): correlations of ambient response as free decays; simulated, then the real
3-channel ambient record of Carini (MIT)."""


import numpy as np
import pytest

import era
from chain_sim import chain, simulate
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

SHARED = SHARED_DATASETS
CARINI = SHARED / "carini_ambient_3ch" / "yk.txt"


def test_correlations_equal_the_direct_sums():
    y = np.random.default_rng(0).standard_normal((5000, 2))
    data = era.markov_from_ambient(y, 0.01, references=[1], n_lags=50, detrend=False)
    tau = 7
    direct = (y[tau + 1:, 0] @ y[:-(tau + 1), 1]) / (len(y) - tau - 1)  # markov[k] is lag k + 1
    assert data.markov[tau, 0, 0] == pytest.approx(direct, rel=1e-12)
    assert data.inputs == ("ref y2",)


def test_simulated_ambient_response_gives_the_known_modes():
    ad, bd, cd, dd, f_modes, zeta = chain(0.005)
    rng = np.random.default_rng(3)
    acc = simulate(ad, bd, cd, dd, rng.standard_normal((200000, 3)))  # white-noise forces on every mass
    acc += 0.1 * acc.std(axis=0) * rng.standard_normal(acc.shape)
    data = era.markov_from_ambient(acc, 0.005, references=["a3"], n_lags=400, names=["a1", "a2", "a3"],
                                   output_units=["m/s^2"] * 3)
    assert data.markov.shape == (400, 3, 1) and data.input_units == ("m/s^2",)
    model = era.identify(data, rows=100, cols=100).realize(order=6)
    order = np.argsort(model.frequency_hz)
    np.testing.assert_allclose(model.frequency_hz[order], f_modes, rtol=5e-3)
    np.testing.assert_allclose(model.damping_ratio[order], zeta, rtol=0.3)  # random error of ambient damping


def test_bad_ambient_input_is_refused_clearly():
    y = np.random.default_rng(0).standard_normal((100, 3))
    with pytest.raises(era.DataError, match="Too few samples for NExT"):
        era.markov_from_ambient(y, 0.01, n_lags=80)
    with pytest.raises(era.DataError, match="'z' is not among"):
        era.markov_from_ambient(y, 0.01, references="z", names=["x", "y", "w"])
    y[40, 2] = np.inf
    with pytest.raises(era.DataError, match="sample 40, channel 2"):
        era.markov_from_ambient(y, 0.01)


def test_carini_ambient_record_gives_the_psd_peaks():
    require_shared(CARINI)
    y = np.loadtxt(CARINI).T  # 3 × 32768 in the file, 25 Hz
    assert y.shape == (32768, 3)
    data = era.markov_from_ambient(y, 1 / 25, n_lags=500)
    model = era.identify(data, rows=100, cols=60).realize(order=20)
    strong = model.select(min_contribution=0.2)
    for peak in (2.31, 4.96, 7.37):  # PSD peaks (dataset README)
        assert np.min(np.abs(strong.frequency_hz - peak)) < 0.01 * peak, peak
