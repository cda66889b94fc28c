"""era.examples.frame_simulation.truth_model keeps the nominal's non-structural mass (a deck's kg/m) when it gives
each member its own scattered section."""

import dataclasses

import numpy as np

from era.discrepancy.frame_model import FrameModel
from era.examples.frame_simulation import truth_model
from era.examples.frames import portal


def test_truth_model_keeps_non_structural_mass_per_length():
    nominal = portal()
    beam = nominal.members[-1][2]
    frame = dataclasses.replace(nominal, added_mass_per_length={beam: 40.0})
    assert frame.total_mass_kg > nominal.total_mass_kg + 1.0
    model, _ = truth_model(frame, {}, scatter=0.0, rng=0, refine=1)
    np.testing.assert_allclose(model.total_mass_kg, frame.total_mass_kg, rtol=1e-12)
    f_truth, _ = model.modes(3)
    f_nominal, _ = FrameModel.of(frame, reduced=False).modes(3)
    f_bare, _ = FrameModel.of(nominal, reduced=False).modes(3)
    np.testing.assert_allclose(f_truth, f_nominal, rtol=1e-6)
    assert np.all(f_truth < f_bare * 0.999)      # the deck's mass lowers every mode
