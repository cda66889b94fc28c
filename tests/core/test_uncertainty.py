"""Each mode's σ from the data (era.core.uncertainty): 95 % intervals hold the truth 95 % of the time."""

import numpy as np
import pytest

import era
from era.examples.synthetic import modal_response
from era.core.uncertainty import Z95, modal_std

F_HZ = np.array([2.0, 3.3])
ZETA = np.array([0.02, 0.03])


@pytest.fixture(scope="module")
def draws():
    """200 noise draws (10 % of the rms, white) on one small noise-free system: 3 outputs, 2 inputs, H(0) 60 × 80."""
    clean, _ = modal_response(F_HZ, ZETA, 3, 2, 300, 0.05, seed=1)
    y = clean.markov
    level = 0.1 * np.sqrt(np.mean(y**2))
    out = {k: [] for k in ("f", "z", "sf", "sz")}
    for seed in range(200):
        noisy = era.ResponseData(y + level * np.random.default_rng(1000 + seed).standard_normal(y.shape), clean.dt)
        model = era.identify(noisy, 20, 40).model(4)
        j = [int(np.argmin(abs(model.frequency_hz - f))) for f in F_HZ]
        out["f"].append(model.frequency_hz[j])
        out["z"].append(model.damping_ratio[j])
        out["sf"].append(model.frequency_std_hz[j])
        out["sz"].append(model.damping_std[j])
    return {k: np.array(v) for k, v in out.items()}


def _coverage(value, truth, std, scale=1.0):
    return np.mean(np.abs(value - truth) <= Z95 * scale * std, axis=0)


def test_95_percent_intervals_hold_the_true_frequency_and_damping_in_90_to_98_percent_of_200_draws(draws):
    for value, std, truth in ((draws["f"], draws["sf"], F_HZ), (draws["z"], draws["sz"], ZETA)):
        cover = _coverage(value, truth, std)
        assert np.all((cover >= 0.90) & (cover <= 0.98)), cover


def test_the_coverage_test_fails_when_the_standard_deviation_is_off_by_two(draws):
    for value, std, truth in ((draws["f"], draws["sf"], F_HZ), (draws["z"], draws["sz"], ZETA)):
        assert np.all(_coverage(value, truth, std, 2.0) > 0.98)  # σ twice too large: ~100 % coverage
        assert np.all(_coverage(value, truth, std, 0.5) < 0.90)  # σ half: ~68 %


def test_the_standard_deviation_is_the_scatter_over_draws(draws):
    """The mean σ over draws equals the draws' own standard deviation within 15 %."""
    for value, std in ((draws["f"], draws["sf"]), (draws["z"], draws["sz"])):
        ratio = std.mean(axis=0) / value.std(axis=0)
        np.testing.assert_allclose(ratio, 1.0, atol=0.15)


def test_intervals_and_select_carry_the_standard_deviations():
    data, _ = modal_response(F_HZ, ZETA, 3, 2, 300, 0.05, snr_db=25, seed=4)
    model = era.identify(data, 20, 40).model(8)
    assert model.frequency_std_hz.shape == model.damping_std.shape == (model.n_modes,)
    assert np.all(np.isfinite(model.frequency_std_hz)) and np.all(model.frequency_std_hz > 0)
    lo, hi = model.frequency_interval_hz()
    np.testing.assert_allclose(hi - lo, 2 * Z95 * model.frequency_std_hz, atol=1e-12)
    lo, hi = model.damping_interval()
    np.testing.assert_allclose((hi + lo) / 2, model.damping_ratio, atol=1e-15)
    kept = model.select([1, 2])
    np.testing.assert_array_equal(kept.frequency_std_hz, model.frequency_std_hz[[1, 2]])
    assert np.all(np.isnan(era.identify(data, 20, 40).model(8, uncertainty=False).frequency_std_hz))
    assert np.all(np.isnan(era.identify(data, 20, 40).realize(8, method="A2").damping_std))


def test_noise_free_data_give_round_off_standard_deviations():
    clean, _ = modal_response(F_HZ, ZETA, 3, 2, 300, 0.05, seed=1)
    model = era.identify(clean, 20, 40).model(4)
    assert np.all(model.frequency_std_hz < 1e-9 * F_HZ)


def test_records_scatter_gives_the_same_standard_deviation_as_repeated_experiments():
    """Mean of 12 records: σ from the records' scatter (Reynders et al. 2008) against the spread of 60 means."""
    clean, _ = modal_response(F_HZ, ZETA, 3, 2, 300, 0.05, seed=1)
    y = clean.markov
    level = 0.3 * np.sqrt(np.mean(y**2))
    f, sf = [], []
    for seed in range(60):
        records = y + level * np.random.default_rng(seed).standard_normal((12,) + y.shape)
        mean = era.ResponseData(records.mean(axis=0), clean.dt)
        model = era.identify(mean, 20, 40).model(4, records=records)
        j = [int(np.argmin(abs(model.frequency_hz - x))) for x in F_HZ]
        f.append(model.frequency_hz[j])
        sf.append(model.frequency_std_hz[j])
    f, sf = np.array(f), np.array(sf)
    np.testing.assert_allclose(sf.mean(axis=0) / f.std(axis=0), 1.0, atol=0.25)
    assert 0.85 <= _coverage(f, F_HZ, sf).min()


def test_modal_std_is_the_chain_rule_through_the_logarithm():
    """σ of f and ζ from a covariance of z, against finite differences of f(z) and ζ(z)."""
    dt, s = 0.01, -0.3 + 2j * np.pi * 5.0
    z = np.exp(s * dt)
    cov = np.array([[4e-8, 1e-8], [1e-8, 9e-8]])

    def f_zeta(zz):
        ss = np.log(zz) / dt
        return np.array([ss.imag / (2 * np.pi), -ss.real / abs(ss)])

    h = 1e-7
    jac = np.stack([(f_zeta(z + h) - f_zeta(z - h)) / (2 * h), (f_zeta(z + 1j * h) - f_zeta(z - 1j * h)) / (2 * h)],
                   axis=1)
    expected = np.sqrt(np.diag(jac @ cov @ jac.T))
    got = modal_std(np.array([z]), cov[None], dt)
    np.testing.assert_allclose([got[0][0], got[1][0]], expected, rtol=1e-5)


def test_shape_scatter_predicts_the_mean_mac_deficit_over_draws():
    """E[1 - MAC(estimate, truth)] of each shape (Identification.shape_scatter) against 100 noise draws: within 25 %."""
    clean, _ = modal_response(F_HZ, ZETA, 5, 2, 300, 0.05, seed=1)
    y = clean.markov
    level = 0.1 * np.sqrt(np.mean(y**2))
    truth = era.identify(clean, 20, 40).model(4)
    k = [int(np.argmin(abs(truth.frequency_hz - f))) for f in F_HZ]
    deficit, predicted = [], []
    for seed in range(100):
        noisy = era.ResponseData(y + level * np.random.default_rng(seed).standard_normal(y.shape), clean.dt)
        ident = era.identify(noisy, 20, 40)
        model = ident.model(4, uncertainty=False)
        j = [int(np.argmin(abs(model.frequency_hz - f))) for f in F_HZ]
        deficit.append([1 - era.mac(model.shapes[:, a], truth.shapes[:, b])[0, 0] for a, b in zip(j, k)])
        predicted.append(ident.shape_scatter(4, j))
    ratio = np.mean(predicted, axis=0) / np.mean(deficit, axis=0)
    np.testing.assert_allclose(ratio, 1.0, atol=0.25)
