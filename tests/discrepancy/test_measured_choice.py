"""Explain's measured modes are era's one choice (era.choose_modes): the modes the app ticks and era.analyse returns,
each with its track's means and spread; a person's kept modes are used exactly as kept."""

import dataclasses

import numpy as np
import pytest

import era
from era.choice.analysis import diagram_orders
from era.discrepancy import identify_modes, measured_modes
from era.discrepancy.measured import input_weights
from era.examples.paper_cases import case_2
from era.examples.synthetic import modal_response


@pytest.fixture(scope="module")
def four_modes():
    return modal_response([2.0, 5.5, 5.9, 11.0], [0.01, 0.02, 0.015, 0.005], n_outputs=5, n_inputs=2,
                          n_samples=600, dt=0.02, snr_db=30, seed=3)


def test_the_measured_modes_are_the_tracks_of_the_modes_era_chooses(four_modes):
    data, truth = four_modes
    ident = era.identify(data, rows=40, cols=120)
    stab = era.stabilization(ident, diagram_orders(ident.max_order), uncertainty=True)
    choice = era.choose_modes(ident, stab)
    mm = measured_modes(ident)
    tracks = [stab.modes[c.diagram_index] for c in choice.chosen]
    assert mm.n_modes == choice.n_modes == 4
    np.testing.assert_allclose(mm.frequency_hz, [t.frequency_hz for t in tracks], rtol=1e-12)
    np.testing.assert_allclose(mm.frequency_hz, [2.0, 5.5, 5.9, 11.0], rtol=2e-3)
    np.testing.assert_array_equal(mm.n_orders, [len(t.orders) for t in tracks])
    np.testing.assert_allclose(mm.frequency_std_hz, [t.frequency_std_hz for t in tracks], rtol=1e-12)
    # each shape is its track's mean (unit norm), nearer the true shape than the one at the track's highest order
    mean_miss = 1 - np.diag(era.mac(mm.shapes, truth.shapes))
    top_miss = 1 - np.diag(era.mac(np.stack([t.shape for t in tracks], axis=1), truth.shapes))
    assert np.all(np.abs(np.linalg.norm(mm.shapes, axis=0) - 1) < 1e-12)
    assert np.all(mean_miss < 1e-3) and mean_miss.sum() < top_miss.sum()


def test_kept_modes_are_exactly_those_kept_at_their_order(four_modes):
    ident = era.identify(four_modes[0], rows=40, cols=120)
    model = ident.model(30)
    kept = [int(k) for k in era.kept_modes(model, min_emac=0.9, min_mpc=0.9)[:2]]
    mm = measured_modes(ident, kept=(30, kept))
    np.testing.assert_array_equal(mm.frequency_hz, model.frequency_hz[kept])


def test_identify_modes_is_era_analyse_on_the_balanced_inputs(four_modes):
    """The second input 300× stronger: balanced, era.analyse's choice is the same as on the records as made."""
    data = dataclasses.replace(four_modes[0], markov=four_modes[0].markov * np.array([1.0, 300.0]))
    w = input_weights(data.markov)
    found = era.analyse(dataclasses.replace(data, markov=data.markov * w[None, None, :]))
    mm = identify_modes(data)
    np.testing.assert_allclose(mm.frequency_hz, [found.stabilization.modes[c.diagram_index].frequency_hz
                                                 for c in found.choice.chosen], rtol=1e-12)
    np.testing.assert_allclose(mm.frequency_hz, [2.0, 5.5, 5.9, 11.0], rtol=2e-3)


def test_noise_free_case_ii_gives_the_exact_realizations_modes():
    """Case II at its exact rank: era chooses the modes of that realization (no diagram cluster needed)."""
    ident = era.identify(case_2(200, mimo=True), rows=45, cols=45)
    mm = measured_modes(ident)
    model = ident.model(ident.max_order)
    np.testing.assert_allclose(np.sort(mm.frequency_hz), np.sort(model.frequency_hz[model.damping_ratio > 0]),
                               rtol=1e-9)


def test_records_of_noise_alone_hold_no_mode_and_say_why():
    noise = era.ResponseData(np.random.default_rng(0).standard_normal((400, 3, 1)), 0.01)
    with pytest.raises(era.DataError, match="era chose no mode of the structure.*is left out"):
        identify_modes(noise)
