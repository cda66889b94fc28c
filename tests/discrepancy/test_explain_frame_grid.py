"""The NASA grid described through era.Frame (era.examples.frames.nasa_grid_frame) gives the same explain results
as nasa_grid() on simulated grid tests, candidate for candidate (the effects both libraries share: a point mass at
a joint, spread mass), with the same measured modes (frequencies and shapes; the frame model is given no input
points, so neither uses the modal constants)."""

import dataclasses

import numpy as np
import pytest

import era
from era.discrepancy import frame_effects, grid_effects, identify_modes
from era.discrepancy.frame_model import FrameModel
from era.examples.frames import nasa_grid_frame
from era.examples.grid import nasa_grid
from era.examples.grid_simulation import simulate_grid_test

SHARED = ("none", "point_mass", "distributed_mass")


def _both(effect):
    data, _ = simulate_grid_test(effect, seed=3)
    m = identify_modes(data)
    m = dataclasses.replace(m, modal_constants=None, modal_constant_std=None, input_locations=None)
    grid = nasa_grid()
    frame = FrameModel.of(nasa_grid_frame())
    by_grid = era.explain(m, grid, effects=tuple(s for s in grid_effects(grid) if s.name in SHARED))
    by_frame = era.explain(m, frame, effects=tuple(s for s in frame_effects(frame) if s.name in SHARED),
                           errors=era.discrepancy.ErrorLevels(model_form=0.0, model_form_shape=0.0))  # as the grid
    return by_grid, by_frame


def test_a_point_mass_on_the_grid_is_named_at_the_same_joint_with_the_same_mass_by_both_models():
    g, f = _both({"name": "point_mass", "point_mass_kg": 1.5, "point_mass_at": (7.0, 2.0)})
    assert g.verdict == f.verdict == "explained" and g.effect.name == f.effect.name == "point_mass"
    assert g.effect.location == (7.0, 2.0) and f.effect.location == "7,2"
    assert f.effect.parameters["point_mass_kg"] == pytest.approx(g.effect.parameters["point_mass_kg"], rel=0.01)
    assert f.after.max_abs_freq_error_pct == pytest.approx(g.after.max_abs_freq_error_pct, abs=0.02)


def test_no_effect_on_the_grid_is_no_discrepancy_for_both_models():
    g, f = _both(None)
    assert g.verdict == f.verdict == "no_significant_discrepancy"
    np.testing.assert_allclose(f.before.max_abs_freq_error_pct, g.before.max_abs_freq_error_pct, atol=0.01)
