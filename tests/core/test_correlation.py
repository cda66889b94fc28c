"""Correlation of test and model modes: pairing by frequency AND shape, COMAC, SEREP expansion."""

import numpy as np
import pytest

import era
from era.core.correlation import comac, gap, pair_modes, real_shapes, serep


def _beam_modes(n_nodes=40, n_modes=8):
    """Pinned-pinned beam: shapes sin(jπx), frequencies ∝ j²."""
    x = np.linspace(0, 1, n_nodes)
    j = np.arange(1, n_modes + 1)
    return x, 1.7 * j**2, np.sin(np.pi * np.outer(x, j))


def test_pairing_follows_shapes_when_model_modes_swap_order():
    x, f, phi = _beam_modes()
    sensors = np.array([3, 9, 14, 20, 27, 33, 37])
    measured_f = np.array([1.0, 2.0, 3.0, 3.2, 5.0])
    measured_phi = phi[sensors, :5]
    # the model's modes 3 and 4 come in the other order: frequency order would pair them wrongly
    model_f = np.array([1.0, 2.0, 3.25, 3.0, 5.0, 7.0])
    p = pair_modes(measured_f, measured_phi, model_f, phi[sensors, :6])
    assert list(p.measured_index) == [0, 1, 2, 3, 4]
    assert list(p.model_index) == [0, 1, 2, 3, 4]
    assert p.unpaired_model == (5,)
    np.testing.assert_allclose(p.mac, 1.0, atol=1e-12)


def test_spurious_measured_mode_is_set_aside_not_forced():
    x, f, phi = _beam_modes()
    sensors = np.array([3, 9, 14, 20, 27, 33, 37])
    rng = np.random.default_rng(1)
    noise_shape = rng.standard_normal((sensors.size, 1))
    mf = np.r_[f[:3], 0.5 * (f[1] + f[2])]
    mphi = np.c_[phi[sensors, :3], noise_shape]
    p = pair_modes(mf, mphi, f[:3] * 1.03, phi[sensors, :3], min_mac=0.6)
    assert p.n_pairs == 3
    assert p.unpaired_measured == (3,)
    np.testing.assert_allclose(p.frequency_error_pct, 3.0, atol=1e-9)
    g = gap(p)
    assert g.max_abs_freq_error_pct == pytest.approx(3.0) and g.min_mac == pytest.approx(1.0)


def test_model_mode_at_zero_hz_still_pairs_by_shape():
    """A nominal without gravity has its swing mode at 0 Hz; it must pair with the measured swing."""
    x, f, phi = _beam_modes()
    sensors = np.array([3, 9, 14, 20, 27, 33, 37])
    rigid = np.ones((x.size, 1))
    mf, mphi = np.r_[0.36, f[:2]], np.c_[rigid[sensors], phi[sensors, :2]]
    p = pair_modes(mf, mphi, np.r_[0.0, f[:2]], mphi, max_freq_error=1.0)
    assert p.n_pairs == 3 and p.frequency_error_pct[0] == pytest.approx(-100.0)


def test_real_shapes_undo_complex_rotation_and_sign():
    rng = np.random.default_rng(0)
    phi = rng.standard_normal((6, 3))
    rotated = phi * np.exp(1j * np.array([0.3, 2.0, -1.1]))[None, :] * np.array([1.0, -2.0, 0.5])
    r = real_shapes(rotated)
    np.testing.assert_allclose(era.mac(r, phi).diagonal(), 1.0, atol=1e-12)
    for k in range(3):
        assert r[np.argmax(np.abs(r[:, k])), k] > 0


def test_comac_flags_the_sensor_that_disagrees():
    x, f, phi = _beam_modes()
    sensors = np.array([3, 9, 14, 20, 27, 33, 37])
    model = phi[sensors, :4]
    measured = model.copy()
    measured[4] = [0.3, -0.9, 0.1, 0.8]  # sensor 4 loose: its readings follow none of the modes
    c = comac(measured, model)
    assert np.argmin(c) == 4
    assert np.all(np.delete(c, 4) > c[4])


def test_serep_reproduces_a_shape_in_the_model_subspace_at_every_node():
    x, f, phi = _beam_modes()
    sensors = np.array([3, 9, 14, 20, 27, 33, 37])
    combo = phi[:, :4] @ np.array([1.0, -0.3, 0.2, 0.05])
    expanded = serep(combo[sensors], phi[sensors, :4], phi[:, :4])
    np.testing.assert_allclose(expanded, combo, atol=1e-10)
    with pytest.raises(era.DataError, match="at most as many modes"):
        serep(combo[sensors], phi[sensors, :8], phi[:, :8])


def test_subspace_mac_judges_a_nearly_repeated_pair_by_its_plane():
    """Two model modes 1 % apart: a measured shape mixing them is fine for the pair, not for either mode."""
    x, f, phi = _beam_modes()
    sensors = np.array([3, 9, 14, 20, 27, 33, 37])
    model_f = np.array([1.0, 5.0, 5.05])
    model_phi = phi[sensors, :3]
    mixed = model_phi[:, 1] * np.cos(0.6) + model_phi[:, 2] * np.sin(0.6)
    measured = np.c_[model_phi[:, 0], mixed]
    p = pair_modes([1.0, 5.02], measured, model_f, model_phi, min_mac=0.3)
    assert p.n_pairs == 2 and p.mac[1] < 0.9
    sub = era.subspace_mac(p, measured, model_phi, model_f, close=0.03)
    assert sub[0] == pytest.approx(p.mac[0]) and sub[1] == pytest.approx(1.0)
    assert gap(p, sub).min_mac == pytest.approx(1.0)
