"""σ from several records of one test (ResponseData.records): used by itself from MIN_RECORDS records, named in the
model, filled by era.markov from repeated records, and equal to the spread of repeated experiments."""

import numpy as np
import pytest

import era
from era.examples.synthetic import modal_response
from era.markov import markov_from_ambient, markov_from_io
from era.core.uncertainty import MIN_RECORDS, Z95

F_HZ = np.array([2.0, 3.3])
ZETA = np.array([0.02, 0.03])


def _coloured(rng, shape, rho=0.8):
    """AR(1) noise along the samples (axis 1), unit variance: errors correlated in time, as NExT's or OKID's."""
    e = rng.standard_normal(shape)
    for k in range(1, shape[1]):
        e[:, k] = rho * e[:, k - 1] + np.sqrt(1 - rho**2) * e[:, k]
    return e


@pytest.fixture(scope="module")
def experiments():
    """40 experiments of 8 records each (coloured noise, 30 % of the rms per record), identified from the mean with
    the records carried by the data."""
    clean, _ = modal_response(F_HZ, ZETA, 4, 2, 300, 0.05, seed=1)
    y = clean.markov
    truth = era.identify(clean, 20, 40).model(4)
    level = 0.3 * np.sqrt(np.mean(y**2))
    out = {k: [] for k in ("f", "z", "sf", "sz", "mac", "scatter", "source")}
    for seed in range(40):
        records = y + level * _coloured(np.random.default_rng(seed), (8,) + y.shape)
        data = era.ResponseData(records.mean(axis=0), clean.dt, records=records)
        ident = era.identify(data, 20, 40)
        model = ident.model(4)
        j = [int(np.argmin(abs(model.frequency_hz - f))) for f in F_HZ]
        k = [int(np.argmin(abs(truth.frequency_hz - f))) for f in F_HZ]
        out["f"].append(model.frequency_hz[j])
        out["z"].append(model.damping_ratio[j])
        out["sf"].append(model.frequency_std_hz[j])
        out["sz"].append(model.damping_std[j])
        out["mac"].append([1 - era.mac(model.shapes[:, a], truth.shapes[:, b])[0, 0] for a, b in zip(j, k)])
        out["scatter"].append(ident.shape_scatter(4, j))
        out["source"].append(model.uncertainty_source)
    return {k: (v if k == "source" else np.array(v)) for k, v in out.items()}


def test_the_model_names_the_records_it_took_sigma_from(experiments):
    assert set(experiments["source"]) == {"σ from 8 records"}


def test_sigma_from_the_records_is_the_spread_of_repeated_experiments(experiments):
    """Mean σ against the 40 experiments' own standard deviation (within 30 %: 40 draws), and 95 % intervals that
    hold the true frequency and damping in most experiments (≥ 85 %), under noise correlated in time."""
    for value, std, truth in ((experiments["f"], experiments["sf"], F_HZ),
                              (experiments["z"], experiments["sz"], ZETA)):
        np.testing.assert_allclose(std.mean(axis=0) / value.std(axis=0), 1.0, atol=0.3)
        assert np.all(np.mean(np.abs(value - truth) <= Z95 * std, axis=0) >= 0.85)
        assert np.all(np.mean(np.abs(value - truth) <= Z95 * std / 3, axis=0) < 0.85)  # a 3× too large σ fails


def test_the_shape_scatter_from_the_records_is_the_mean_mac_deficit(experiments):
    ratio = experiments["scatter"].mean(axis=0) / experiments["mac"].mean(axis=0)
    np.testing.assert_allclose(ratio, 1.0, atol=0.35)


def test_fewer_records_than_min_records_leave_sigma_to_the_residuals():
    clean, _ = modal_response(F_HZ, ZETA, 3, 2, 300, 0.05, seed=1)
    rng = np.random.default_rng(3)
    records = clean.markov + 0.2 * np.sqrt(np.mean(clean.markov**2)) * rng.standard_normal((MIN_RECORDS - 1,)
                                                                                          + clean.markov.shape)
    mean = records.mean(axis=0)
    few = era.identify(era.ResponseData(mean, clean.dt, records=records), 20, 40).model(4)
    alone = era.identify(era.ResponseData(mean, clean.dt), 20, 40).model(4)
    assert few.uncertainty_source == alone.uncertainty_source == "σ from one record's residuals"
    np.testing.assert_array_equal(few.frequency_std_hz, alone.frequency_std_hz)
    assert era.identify(era.ResponseData(mean, clean.dt), 20, 40).model(4, uncertainty=False).uncertainty_source == ""


def test_records_must_match_the_pulse_responses():
    y = np.zeros((50, 2, 1))
    y[0] = 1.0
    with pytest.raises(era.EraError, match="records"):
        era.ResponseData(y, 0.1, records=np.zeros((3, 40, 2, 1)))
    with pytest.raises(era.EraError, match="at least"):
        era.ResponseData(y, 0.1, records=y[None])
    with pytest.raises(era.EraError, match="finite"):
        era.ResponseData(y, 0.1, records=np.full((2, 50, 2, 1), np.nan))


def test_ambient_records_of_one_length_keep_each_records_correlations():
    rng = np.random.default_rng(0)
    ys = [rng.standard_normal((4000, 3)) for _ in range(6)]
    data = markov_from_ambient(ys, 0.01, n_lags=100)
    assert data.n_records == 6 and data.records.shape == (6,) + data.markov.shape
    np.testing.assert_allclose(data.records.mean(axis=0), data.markov, atol=1e-12)  # equal lengths: the pool
    uneven = markov_from_ambient([ys[0], ys[1][:2000]], 0.01, n_lags=100)
    assert uneven.records is None  # not comparable: their variances differ two-fold


def test_repeated_hits_by_okid_keep_each_hits_markov_parameters():
    sim, _ = modal_response(F_HZ, ZETA, 2, 1, 60, 0.05, seed=2)
    rng = np.random.default_rng(1)
    us, ys = [], []
    for _ in range(5):
        u = rng.standard_normal((800, 1))
        y = np.stack([np.convolve(u[:, 0], sim.markov[:, i, 0])[:800] for i in range(2)], axis=1)
        y[1:] = y[:-1].copy()
        y[0] = 0.0  # Y(1) reaches y one sample later
        us.append(u)
        ys.append(y + 0.01 * rng.standard_normal(y.shape))
    data = markov_from_io(us, ys, 0.05, n_observer=10, n_markov=50)
    assert data.n_records == 5
    np.testing.assert_allclose(data.records.mean(axis=0), data.markov, atol=0.05 * np.abs(data.markov).max())
    model = era.identify(data, 15, 30).model(4)
    assert model.uncertainty_source == "σ from 5 records"
    assert np.all(np.isfinite(model.frequency_std_hz)) and np.all(model.frequency_std_hz > 0)


def test_many_records_are_kept_as_group_means_whose_scatter_gives_the_same_sigma():
    """40 records kept as 20 batch means (era.markov.common.kept_records): σ within the estimate's own scatter."""
    from era.markov.common import MAX_KEPT_RECORDS, MAX_KEPT_VALUES, kept_records

    clean, _ = modal_response(F_HZ, ZETA, 3, 2, 300, 0.05, seed=1)
    y = clean.markov
    rng = np.random.default_rng(5)
    records = y + 0.3 * np.sqrt(np.mean(y**2)) * rng.standard_normal((40,) + y.shape)
    kept = kept_records(records)
    assert kept.shape == (MAX_KEPT_RECORDS,) + y.shape
    np.testing.assert_allclose(kept.mean(axis=0), records.mean(axis=0), atol=1e-12)  # equal groups: same mean
    mean = era.ResponseData(records.mean(axis=0), clean.dt)
    every = era.identify(mean, 20, 40).model(4, records=records)
    grouped = era.identify(era.ResponseData(records.mean(axis=0), clean.dt, records=kept), 20, 40).model(4)
    assert grouped.uncertainty_source == f"σ from {MAX_KEPT_RECORDS} records"
    np.testing.assert_allclose(grouped.frequency_std_hz / every.frequency_std_hz, 1.0, atol=0.45)
    big = records[:6, :, :1, :1].repeat(MAX_KEPT_VALUES // y[:, :1, :1].size // 4 + 1, axis=1)
    assert kept_records(big) is None  # 4 groups at most in MAX_KEPT_VALUES: fewer than MIN_RECORDS
