"""era.explain on the paper's dwell test (air jet at (10, 0) ft tuned to each of the first 8 modes, then free
decays): the eight decays differ ~500× in size (response ∝ 1/ω²), each with noise at 3 % of its own RMS.
identify_modes must weigh each decay alike (era.discrepancy.measured.input_weights) or the higher modes sink
under the largest decay's noise: unweighted ERA kept 3-5 modes and left these cases "ambiguous"."""

import numpy as np
import pytest

from era.discrepancy import explain
from era.discrepancy.measured import identify_modes, input_weights
from era.examples.grid import nasa_grid
from era.examples.grid_simulation import simulate_grid_test


@pytest.mark.parametrize("effect, seed", [("torsion_stiffness", 0), ("joint_flexibility", 1)])
def test_a_dwell_test_yields_the_dwelled_modes_and_names_the_hidden_effect(effect, seed):
    data, truth = simulate_grid_test(effect, seed=seed, excitation="dwell")
    r = explain(data, nasa_grid(**truth["nominal_params"]))
    assert len(r.fit_modes) >= 9                     # the 8 dwelled modes and at least one more
    f_true = truth["frequency_hz"]
    found = r.measured.frequency_hz[r.fit_modes]
    for f in f_true[:8]:                             # every dwelled mode, within 0.2 % of the truth
        assert np.min(np.abs(found - f)) < 0.002 * f
    assert r.verdict == "explained" and r.effect.name == effect
    assert r.after.max_abs_freq_error_pct < 0.7 and r.after.min_mac > 0.95


def test_weighting_each_decay_is_what_recovers_the_small_decays_modes():
    data, truth = simulate_grid_test("torsion_stiffness", seed=0, excitation="dwell")
    w = input_weights(data.markov)
    assert w.max() / w.min() > 100                   # the decays really are of very different size
    plain = identify_modes(data, balance_inputs=False)
    weighted = identify_modes(data)
    assert plain.n_modes <= 6 and weighted.n_modes >= 9
    assert np.all(weighted.frequency_hz[:6] > 0.0)
    assert np.min(np.abs(weighted.frequency_hz - truth["frequency_hz"][5])) < 0.002 * truth["frequency_hz"][5]


def test_input_weights_leave_all_zero_records_alone():
    y = np.zeros((50, 3, 2))
    y[:, :, 0] = 2.0
    assert input_weights(y) == pytest.approx([0.5, 1.0])


def test_weighting_leaves_the_modal_constants_of_pulse_responses_unchanged():
    """The weights scale B's columns; modal constants (1/kg, from the residues) are divided by them again."""
    data, truth = simulate_grid_test("point_mass", seed=0)
    assert input_weights(data.markov).max() / input_weights(data.markov).min() > 1.5
    plain, weighted = identify_modes(data, balance_inputs=False), identify_modes(data)
    for k, f in enumerate(plain.frequency_hz[:6]):
        j = int(np.argmin(np.abs(weighted.frequency_hz - f)))
        a, b = plain.modal_constants[:, :, k], weighted.modal_constants[:, :, j]
        assert np.linalg.norm(b - a) < 0.03 * np.linalg.norm(a)
