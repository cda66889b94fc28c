"""γ and μ: definitions, invariances and degenerate cases."""

import numpy as np

from era.core.indicators import emac, mac, mpc


def _printed_eq_52_54(c):
    """μ exactly as printed in eqs. 48-54."""
    c = c - c.mean()
    crr, cii, cri = c.real @ c.real, c.imag @ c.imag, c.real @ c.imag
    e = (cii - crr) / (2 * cri)
    theta = np.arctan(e + np.sign(e) * np.sqrt(1 + e * e))
    return (crr + cri * (2 * (e * e + 1) * np.sin(theta) ** 2 - 1) / e) / (crr + cii)


def test_mpc_is_one_for_any_real_shape_times_any_complex_number():
    rng = np.random.default_rng(0)
    real = rng.standard_normal((7, 1))
    for angle in np.linspace(0, 2 * np.pi, 37):
        for gain in (1e-6, 1.0, 3e4):
            assert abs(mpc(real * gain * np.exp(1j * angle))[0] - 1.0) < 1e-12


def test_the_printed_formula_depends_on_the_shape_phase_and_ours_does_not():
    rng = np.random.default_rng(1)
    shape = rng.standard_normal(6) + 0.4j * rng.standard_normal(6)
    angles = np.linspace(0.05, 3.1, 25)
    printed = np.array([_printed_eq_52_54(shape * np.exp(1j * a)) for a in angles])
    ours = np.array([mpc((shape * np.exp(1j * a))[:, None])[0] for a in angles])
    assert printed.max() - printed.min() > 0.5  # the printed branch jumps between major and minor axis
    np.testing.assert_allclose(ours, ours[0], rtol=1e-12)
    np.testing.assert_allclose(ours[0], printed.max(), rtol=1e-10)  # and agrees with its major-axis branch


def test_mpc_of_an_evenly_spread_shape_is_one_half():
    circle = np.exp(1j * np.linspace(0, 2 * np.pi, 8, endpoint=False))
    assert np.isclose(mpc(circle[:, None])[0], 0.5)


def test_mpc_degenerate_cases():
    assert mpc(np.array([[0.3 - 2j]]))[0] == 1.0  # a single sensor
    assert mpc(np.full((4, 1), 2 + 1j))[0] == 1.0  # all sensors as one
    assert mpc(np.zeros((4, 1), dtype=complex))[0] == 0.0  # unobserved mode
    assert mpc(np.array([[1.0], [-1.0], [2.0]]))[0] == 1.0  # c_ri = 0, c_ii = 0


def test_emac_is_one_for_an_exact_history_and_low_for_a_wrong_eigenvalue():
    z = np.array([np.exp(-0.01 + 0.7j)])
    shifts = np.arange(30)
    b = np.array([1.0 - 0.5j, 0.3 + 2j])
    history = (z[:, None, None] ** shifts[None, :, None] * b).reshape(1, -1)
    assert np.isclose(emac(history, z, shifts, 2)[0], 1.0)
    assert emac(history, z * np.exp(0.3j), shifts, 2)[0] < 0.3
    assert emac(np.zeros((1, 60)), z, shifts, 2)[0] == 0.0


def test_mac_matrix():
    a = np.array([[1.0, 0], [0, 1], [1, 0]])
    m = mac(a, a * (2 - 1j))
    np.testing.assert_allclose(m, np.eye(2), atol=1e-15)
    assert mac(np.zeros(3), a).tolist() == [[0.0, 0.0]]


def test_consecutive_powers_by_blocks_equal_pythons_complex_power():
    """z^0 .. z^(N-1) for N past the block size: inside the unit circle (by blocks), on it, outside it (the
    running product) and zero, each against Python's own complex power."""
    from era.core.indicators import POWER_BLOCK, powers
    z = np.array([0.999 * np.exp(0.3j), 0.95 * np.exp(2.9j), -0.5, 1.0, np.exp(1.1j), 1.002 * np.exp(0.7j), 0.0])
    n = 3 * POWER_BLOCK + 17
    got = powers(z, np.arange(n))
    truth = np.array([[complex(zj) ** k if k else 1.0 for k in range(n)] for zj in z])
    np.testing.assert_allclose(got, truth, rtol=1e-13, atol=1e-300)
