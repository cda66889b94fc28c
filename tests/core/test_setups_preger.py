"""Merging before identifying (era.setups.preger, PreGER): the beam's four setups as exact correlation functions
(the closed form of NExT's correlations for modes driven by independent white noise), each setup at its own
excitation level. Stacked on one scale and identified once, every mode is known at every point and matches the
exact shape sin(jπx); when the modes' excitation changes shape from setup to setup, one factor per setup no longer
holds and the reference residual says so."""

import numpy as np
import pytest

import era
from era.setups.preger import merge_correlations
from tests.simulated_setups import DAMPING, DT, FREQUENCY_HZ, LEVELS, REFERENCES, ROVING, TRUE_SHAPES, truth_at

N_LAGS = 200


def exact_correlations(k: int, modal_power=None) -> era.ResponseData:
    """Setup k's correlations with its two references, exact: R(τ) = Σ_j 2 q_j Re(z_j^τ) φ_j φ_ref,j^T, q_j the
    variance of mode j's coordinate under unit complex white noise (2 / (1 - |z_j|²)), times the setup's level²."""
    rows = REFERENCES + ROVING[k]
    wd = 2 * np.pi * FREQUENCY_HZ
    s = -DAMPING * wd / np.sqrt(1 - DAMPING**2) + 1j * wd
    z = np.exp(s * DT)
    q = 2 / (1 - np.abs(z) ** 2) * (1.0 if modal_power is None else np.asarray(modal_power))
    tau = np.arange(1, N_LAGS + 1)[:, None]
    decay = 2 * q * (z[None, :] ** tau).real  # (lags, modes)
    phi = TRUE_SHAPES[rows]
    markov = LEVELS[k] ** 2 * np.einsum("tj,ij,lj->til", decay, phi, phi[:2])
    return era.ResponseData(markov, DT, outputs=[f"P{i + 1}" for i in rows], inputs=["P2", "P5"])


def test_exact_correlations_at_four_levels_merge_to_the_exact_shapes_at_every_point():
    merged = merge_correlations([exact_correlations(k) for k in range(4)], [[0, 1]] * 4)
    np.testing.assert_allclose(merged.scales, LEVELS[0] ** 2 / np.array(LEVELS) ** 2, rtol=1e-12)
    assert np.all(merged.reference_residual < 1e-12)
    assert merged.data.outputs == ("P2", "P5", "P1", "P3", "P4", "P6", "P7", "P8", "P9", "P10", "P11", "P12")
    model = era.analyse(merged.data).model
    np.testing.assert_allclose(model.frequency_hz, FREQUENCY_HZ, rtol=1e-6)
    np.testing.assert_allclose(model.damping_ratio, DAMPING, rtol=1e-4)
    macs = np.diag(era.mac(model.shapes, truth_at(merged.data.outputs)))
    assert np.all(macs > 1 - 1e-9)


def test_one_factor_per_setup_fails_when_the_modes_excitation_changes_between_setups():
    """Setup 3's second mode excited four times as strongly (its spectrum changed shape): PreGER's one factor per
    setup cannot absorb it; the residual flags it and that mode's merged shape is off, where PoSER (era.merge_setups,
    one factor per mode) is exact on the same correlations."""
    setups = [exact_correlations(k, [1, 4, 1, 1] if k == 2 else None) for k in range(4)]
    merged = merge_correlations(setups, [[0, 1]] * 4)
    assert merged.reference_residual[2] > 0.1
    preger = era.analyse(merged.data).model
    poser = era.merge_setups([era.analyse(d) for d in setups], [[0, 1]] * 4)
    assert poser.n_modes == 4
    exact = np.diag(era.mac(poser.point_shapes, truth_at(poser.points)))
    assert np.all(exact > 1 - 1e-9)
    j = int(np.argmin(np.abs(preger.frequency_hz - FREQUENCY_HZ[1])))
    assert era.mac(preger.shapes[:, j], truth_at(merged.data.outputs)[:, 1])[0, 0] < 0.99


def test_setups_that_do_not_match_are_refused():
    setups = [exact_correlations(k) for k in range(2)]
    with pytest.raises(era.DataError, match="reference lists"):
        merge_correlations(setups, [[0, 1]])
    with pytest.raises(era.DataError, match="names 1"):
        merge_correlations(setups, [[0, 1], [0]])
