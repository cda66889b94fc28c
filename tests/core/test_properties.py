"""Properties that must hold whatever the data: invariances, exact reconstruction, indicator ranges."""

import numpy as np
import pytest

import era
from era.core import indicators
from era.core.decomposition import decompose
from era.core.modal import build_model
from era.examples.paper_cases import case_2
from era.examples.synthetic import modal_response


@pytest.fixture(scope="module")
def noisy():
    data, truth = modal_response([2.0, 5.5, 5.9, 11.0], [0.01, 0.02, 0.015, 0.005], n_outputs=5, n_inputs=2,
                                 n_samples=600, dt=0.02, snr_db=30, seed=3)
    return data, truth


def test_a_similarity_transform_leaves_the_modal_parameters_unchanged(noisy):
    data, _ = noisy
    ident = era.identify(data, rows=40, cols=120)
    A, B, C, W = ident.balanced(16)
    ref = build_model(A, B, C, W, data.dt, ident.row_shifts, ident.col_shifts)
    rng = np.random.default_rng(0)
    T = rng.standard_normal((16, 16)) + 4 * np.eye(16)
    Ti = np.linalg.inv(T)
    other = build_model(T @ A @ Ti, T @ B, C @ Ti, T @ W, data.dt, ident.row_shifts, ident.col_shifts)
    for name in ("frequency_hz", "damping_ratio", "emac", "mpc", "contribution"):
        np.testing.assert_allclose(getattr(other, name), getattr(ref, name), rtol=1e-7, atol=1e-9, err_msg=name)
    np.testing.assert_allclose(era.mac(other.shapes, ref.shapes).diagonal(), 1.0, atol=1e-9)


def test_permuting_channels_leaves_the_modal_parameters_unchanged(noisy):
    data, _ = noisy
    out_perm, in_perm = np.array([3, 0, 4, 1, 2]), np.array([1, 0])
    permuted = era.ResponseData(data.markov[:, out_perm][:, :, in_perm], data.dt)
    a = era.identify(data, rows=40, cols=120).realize(16)
    b = era.identify(permuted, rows=40, cols=120).realize(16)
    for name in ("frequency_hz", "damping_ratio", "emac", "mpc"):
        np.testing.assert_allclose(getattr(b, name), getattr(a, name), rtol=1e-6, atol=1e-8, err_msg=name)
    np.testing.assert_allclose(b.shapes, a.shapes[out_perm], rtol=1e-6, atol=1e-8)


def test_reconstruction_of_noise_free_mimo_data_is_exact():
    data = case_2()
    model = era.identify(data, rows=45, cols=45).realize(10)
    np.testing.assert_allclose(model.reconstruct(data.n_samples), data.markov, atol=1e-10)
    assert np.all(model.fit_error(data) < 1e-10)


def test_select_keeps_modes_and_the_reduced_model_reproduces_their_response():
    data, _ = modal_response([1.0, 3.0], [0.02, 0.01], 3, 1, 300, 0.05, seed=1)
    model = era.identify(data, rows=20, cols=20).realize(4)
    only_second = model.select([1])
    assert only_second.n_modes == 1 and only_second.A.shape == (2, 2)
    np.testing.assert_allclose(only_second.frequency_hz, model.frequency_hz[1:])
    # the reduced model's state-space form gives the same response as its modal sum
    y = np.stack([only_second.C @ np.linalg.matrix_power(only_second.A, k) @ only_second.B for k in range(50)])
    np.testing.assert_allclose(y, only_second.reconstruct(50), atol=1e-10)
    both = model.select([0]).reconstruct(300) + only_second.reconstruct(300)
    np.testing.assert_allclose(both, data.markov, atol=1e-9)


def test_select_by_thresholds_drops_noise_modes(noisy):
    data, truth = noisy
    model = era.identify(data, rows=40, cols=120).realize(30)
    kept = model.select(min_emac=0.9, min_mpc=0.9)
    np.testing.assert_allclose(np.sort(kept.frequency_hz), truth.frequency_hz, rtol=2e-3)
    assert kept.fit_error(data).max() < 0.1  # 30 dB noise is ~3 % of the signal
    with pytest.raises(era.EraError, match="out of range"):
        model.select([model.n_modes])
    with pytest.raises(era.EraError, match="fraction"):
        model.select(min_emac=1.5)


def test_real_unstable_and_zero_poles_give_finite_values_without_warnings():
    dt = 0.1
    z = np.array([0.5, 1.2, 0.0, -0.7, np.exp((0.01 + 2j) * dt)])
    A = np.diag(z[:4].real)
    A = np.block([[A, np.zeros((4, 2))], [np.zeros((2, 4)), np.array([[z[4].real, -z[4].imag], [z[4].imag, z[4].real]])]])
    B, C = np.ones((6, 1)), np.ones((1, 6))
    W = np.hstack([np.linalg.matrix_power(A, k) @ B for k in range(5)])
    with np.errstate(all="raise"):
        model = build_model(A, B, C, W, dt, np.arange(5), np.arange(5))
    for name in ("frequency_hz", "damping_ratio", "emac", "mpc", "contribution"):
        assert np.all(np.isfinite(getattr(model, name))), name
    f, zeta = model.frequency_hz, model.damping_ratio
    assert model.n_modes == 5
    real_positive = np.isclose(model.z, 0.5) | np.isclose(model.z, 1.2) | (np.abs(model.z) == 0)
    assert np.all(f[real_positive] == 0)
    assert np.isclose(zeta[np.isclose(model.z, 1.2)][0], -1.0)  # growing real pole
    assert np.isclose(f[np.isclose(model.z, -0.7)][0], 1 / (2 * dt))  # negative real z: Nyquist
    assert np.isclose(zeta[np.isclose(model.z, z[4])][0], -0.01 / abs(0.01 + 2j))  # unstable pair


def test_indicators_follow_their_definitions_and_are_fractions_before_any_clipping(noisy):
    """γ (eqs. 42-45) and μ (eqs. 46-54) recomputed naively, mode by mode, agree with the library; the naive
    values, which nothing clips, lie in [0, 1] (γ by Cauchy-Schwarz) and [1/2, 1] (μ, a share of the scatter)."""
    data, _ = noisy
    ident = era.identify(data, rows=40, cols=120)
    A, B, C, W = ident.balanced(60)
    dec = decompose(A, B, C, W)
    m, ts = data.n_inputs, ident.col_shifts
    gamma, mu = [], []
    for j in range(dec.z.size):
        q = dec.histories[j].reshape(ts.size, m)
        ideal = np.array([dec.z[j] ** t * q[0] for t in ts])  # eq. 43: q̄ = [b*, z^{t_1} b*, ...]
        gamma.append(abs(np.vdot(ideal, q)) / (np.linalg.norm(ideal) * np.linalg.norm(q)))
        c = dec.shapes[:, j] - dec.shapes[:, j].mean()
        scatter = np.cov(np.vstack([c.real, c.imag]), bias=True)
        lam = np.linalg.eigvalsh(scatter)
        mu.append(lam[1] / lam.sum())
    gamma, mu = np.array(gamma), np.array(mu)
    assert np.all((gamma >= 0) & (gamma <= 1 + 1e-12)) and np.all((mu >= 0.5 - 1e-12) & (mu <= 1 + 1e-12))
    np.testing.assert_allclose(indicators.emac(dec.histories, dec.z, ts, m), gamma, atol=1e-10)
    np.testing.assert_allclose(indicators.mpc(dec.shapes), mu, atol=1e-10)
    assert gamma.min() < 0.9 and mu.min() < 0.9  # noise modes at order 60: the test sees real spread
    model = ident.model(60)
    assert np.all(model.contribution >= 0)


