"""explain is honest about model-form error (issue 27): a calibrated allowance enters the evidence, places the data
cannot tell apart are given as a set with the probability of each, the size with its interval, and a mode the
structure has twice where the model has it once is physics outside the library (nothing named)."""

import numpy as np
import pytest
from opensees_truth import make_case

import era
from era.discrepancy import ErrorLevels, modes_from_arrays
from era.discrepancy.effects import EffectSpec
from era.discrepancy.explanation import PLACE_COVERAGE
from era.discrepancy.frame_model import MODEL_FORM, FrameModel
from era.discrepancy.ranking import credible_places
from era.examples.frames import portal
from era.examples.grid import nasa_grid


def test_the_allowance_is_the_models_own_unless_given():
    frame, grid = FrameModel.of(portal()), nasa_grid()
    assert ErrorLevels().for_model(frame).model_form == MODEL_FORM[0] == 0.013
    assert ErrorLevels().for_model(frame).model_form_shape == MODEL_FORM[1]
    assert ErrorLevels().for_model(grid).model_form == 0.0      # its floors were calibrated on its own truths
    assert ErrorLevels(model_form=0.0).for_model(frame).model_form == 0.0
    m = modes_from_arrays([2.0, 5.0], np.eye(3)[:, :2])
    w = ErrorLevels(freq_floor=0.0, shape_floor=0.0, model_form=0.01, model_form_shape=0.02).weights(m)
    assert w.sigma_f == pytest.approx([0.02, 0.05]) and w.sigma_s == pytest.approx([0.02, 0.02])


def test_the_credible_set_holds_ninety_per_cent_of_the_places_most_probable_first():
    locs = ((("A", "B"), -1.0, 0.55), (("B", "C"), -1.5, 0.30), (("C", "D"), -2.0, 0.12), (("D", "E"), -9.0, 0.03))
    assert credible_places(locs, PLACE_COVERAGE) == ((("A", "B"), 0.55), (("B", "C"), 0.30), (("C", "D"), 0.12))
    assert credible_places(((("A", "B"), -1.0, 0.95), (("B", "C"), -4.0, 0.05))) == ((("A", "B"), 0.95),)


def test_a_point_mass_on_the_opensees_portal_is_named_with_its_place_size_interval_and_what_is_unsure():
    case = make_case("portal", "point_mass", 2)
    r = era.explain(case.data, case.frame)
    assert r.verdict == "explained" and r.effect.name == "point_mass"
    e = r.effect
    assert e.places[0][0] == e.location == case.truth["effects"][0][1]
    assert sum(q for _, q in e.places) >= PLACE_COVERAGE or len(e.places) == len(r.candidate("point_mass").locations)
    low, high = e.size_interval
    assert e.size_parameter == "point_mass_kg" and low < e.parameters["point_mass_kg"] < high
    d = e.as_dict()
    assert d["places"][0][0] == e.location and d["size_interval"] == [low, high] and isinstance(d["cannot_tell"], list)
    assert r.as_dict()["model_form"] == {"frequency": MODEL_FORM[0], "shape": MODEL_FORM[1]}
    assert "95 %" in e.description


def test_a_tuned_mass_is_not_named_a_point_mass_its_own_mode_has_no_partner():
    """A mass on a spring at joint (4, 6) of the grid adds a mode the model has once and the structure twice (a
    split pair): a point mass next to it fits the other modes, but the mode left alone has the shape of a model
    mode another measured mode pairs with: outside the library, no name (it was named a point mass at (5, 6))."""
    case = make_case("grid", "tuned_mass (outside)", 2)
    r = era.explain(case.data, case.frame)
    assert r.verdict == "unexplained" and not r.effects
    assert "no partner in the model, though the model has its shape" in r.message


def test_places_the_data_cannot_tell_apart_are_said_as_one_of_these():
    spec = EffectSpec("member_stiffness", location_keyword="member_at", summary="a member is less stiff than drawn")
    text = era.discrepancy.effects.describe(spec, {}, ("A", "B"), 0.97,
                                            places=((("A", "B"), 0.55), (("B", "C"), 0.30), (("C", "D"), 0.15)))
    assert "on one of these members: member A-B 55 %, member B-C 30 %, member C-D 15 %" in text
