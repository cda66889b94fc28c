"""Every order from one SVD; stability flags; suggested modes."""

import numpy as np
import pytest

import era
from era.examples.synthetic import modal_response


@pytest.fixture(scope="module")
def noisy():
    f = [3.1, 7.4, 7.6, 12.0, 25.0]
    data, truth = modal_response(f, [0.01, 0.02, 0.02, 0.005, 0.03], n_outputs=8, n_inputs=3, n_samples=1200,
                                 dt=0.01, snr_db=30, seed=1)
    return era.identify(data, rows=60, cols=150), truth


def test_each_order_equals_a_direct_realization_of_that_order(noisy):
    ident, _ = noisy
    stab = era.stabilization(ident, orders=[6, 10, 20])
    for n in (6, 10, 20):
        model = ident.realize(n)
        at = stab.order == n
        np.testing.assert_allclose(stab.frequency_hz[at], model.frequency_hz, rtol=1e-12)
        np.testing.assert_allclose(stab.emac[at], model.emac, rtol=1e-9)
        np.testing.assert_allclose(stab.mpc[at], model.mpc, rtol=1e-9)


def test_no_svd_is_recomputed(noisy, monkeypatch):
    ident, _ = noisy

    def forbidden(*args, **kwargs):
        raise AssertionError("stabilization must not call an SVD")

    monkeypatch.setattr(era.core.svd, "dense_svd", forbidden)
    monkeypatch.setattr(np.linalg, "svd", forbidden)
    era.stabilization(ident, orders=range(2, 41, 2))


def test_suggested_modes_are_the_true_modes_with_their_spread(noisy):
    ident, truth = noisy
    stab = era.stabilization(ident, orders=range(2, 81, 2))
    assert stab.orders.tolist() == list(range(2, 81, 2))
    found = np.array([m.frequency_hz for m in stab.modes if len(m.orders) >= 10])
    assert len(found) == len(truth.frequency_hz)
    np.testing.assert_allclose(found, truth.frequency_hz, rtol=2e-3)
    for m in stab.modes:
        if len(m.orders) >= 10:
            assert m.frequency_std_hz < 2e-3 * m.frequency_hz
            assert m.emac > 0.95 and m.mpc > 0.95
            assert abs(m.damping_ratio - truth.damping_ratio[np.argmin(abs(truth.frequency_hz - m.frequency_hz))]) < 0.003


def test_flags_are_consistent(noisy):
    ident, _ = noisy
    stab = era.stabilization(ident, orders=range(2, 61, 2), freq_tol=0.01, damping_tol=0.05, mac_min=0.98)
    assert not stab.stable_frequency[stab.order == 2].any()
    assert np.array_equal(stab.stable, stab.stable_frequency & stab.stable_damping & stab.stable_shape)
    assert stab.shapes.shape == (8, stab.order.size)
    strict = era.stabilization(ident, orders=range(2, 61, 2), freq_tol=1e-6)
    assert strict.stable_frequency.sum() < stab.stable_frequency.sum()


def test_orders_above_the_rank_are_skipped_and_bad_orders_refused():
    data, _ = modal_response([1.0, 2.0], 0.01, 2, 1, 200, 0.05, seed=0)  # rank 4, noise-free
    ident = era.identify(data, rows=30, cols=30)
    stab = era.stabilization(ident, orders=range(2, 21, 2))
    assert stab.orders.tolist() == [2, 4]
    with pytest.raises(era.EraError, match="positive integers"):
        era.stabilization(ident, orders=[0, 2])


def test_a_repeated_pair_is_suggested_as_two_modes_at_one_frequency():
    f = [3.1, 7.4, 7.6, 12.0, 18.5, 18.5, 25.0]
    data, _ = modal_response(f, [0.01, 0.02, 0.02, 0.005, 0.01, 0.01, 0.03], 8, 3, 1200, 0.01, snr_db=30, seed=1)
    stab = era.stabilization(era.identify(data, rows=60, cols=150), orders=range(2, 81, 2))
    persistent = [m for m in stab.modes if len(m.orders) >= 15]
    np.testing.assert_allclose([m.frequency_hz for m in persistent], f, rtol=1e-3)
    repeated = [m for m in persistent if abs(m.frequency_hz - 18.5) < 0.05]
    assert len(repeated) == 2
    assert set(repeated[0].orders) & set(repeated[1].orders)  # two poles at one order: two modes, not one track


def test_stable_poles_carry_the_standard_deviations_of_their_order_model(noisy):
    ident, _ = noisy
    stab = era.stabilization(ident, orders=[10, 20, 30], uncertainty=True)
    assert np.all(np.isnan(era.stabilization(ident, orders=[10, 20]).frequency_std_hz))
    assert np.all(np.isnan(stab.frequency_std_hz[~stab.stable]))
    assert np.all(np.isfinite(stab.frequency_std_hz[stab.stable])) and stab.stable.sum() >= 8
    for n in (20, 30):
        model = ident.model(n)
        at = (stab.order == n) & stab.stable
        np.testing.assert_allclose(stab.frequency_std_hz[at], model.frequency_std_hz[stab.mode_index[at]], rtol=1e-9)
        np.testing.assert_allclose(stab.damping_std[at], model.damping_std[stab.mode_index[at]], rtol=1e-9)
    serial = era.stabilization(ident, orders=[10, 20, 30], uncertainty=True, workers=1)
    np.testing.assert_array_equal(serial.frequency_std_hz, stab.frequency_std_hz)
    assert all(np.isfinite(m.data_frequency_std_hz) for m in stab.modes)


def test_gamma_without_the_histories_equals_gamma_from_them_with_any_column_shifts():
    """era.core.sweep.sweep_emac (inner products from Q^T arranged by shift and the conjugate powers) against
    indicators.emac on the histories themselves, with non-consecutive column shifts and orders of several
    widths in one batch (zero-padded rows)."""
    from era.core import indicators
    from era.core.sweep import sweep_emac

    rng = np.random.default_rng(7)
    m, shifts, k = 3, np.array([0, 1, 3, 4, 7, 11]), 9
    q, _ = np.linalg.qr(rng.standard_normal((len(shifts) * m, k)))  # orthonormal columns, as the SVD's
    root = np.sqrt(np.sort(rng.random(k) + 0.5)[::-1])
    left = [rng.standard_normal((2, n)) + 1j * rng.standard_normal((2, n)) for n in (4, 6, 9)]
    z = 0.97 * np.exp(1j * rng.uniform(0.1, 3.0, 6))
    by_shift = np.ascontiguousarray(q.T.reshape(k, len(shifts), m).transpose(0, 2, 1))
    got = sweep_emac(left, z, by_shift, root, indicators.powers(z, shifts))
    histories = np.concatenate([(x * root[:x.shape[1]]) @ q[:, :x.shape[1]].T for x in left])
    np.testing.assert_allclose(got, indicators.emac(histories, z, shifts, m), rtol=1e-12)
    assert np.all((got > 0) & (got < 1))
