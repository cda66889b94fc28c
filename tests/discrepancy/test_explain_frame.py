"""explain() on era.Frame models: the frame effect library, chosen blind on simulated tests of a cantilever and a
portal whose truth differs from the model (2 % member scatter, twice the mesh, 0.1 % frequency noise, 1 % shape
noise, 2 % sensor gains). The full matrix (four structures, every effect, several seeds) is
tests/bench/bench_explain_frame.py."""

import numpy as np
import pytest

import era
from era.discrepancy.effects_frame import frame_effects
from era.discrepancy.frame_model import FrameModel
from era.examples.frame_simulation import simulate_frame_test
from era.examples.frames import cantilever, portal, truss, two_storey

#: The truths here are era's own finite elements (the members' stiffness scattered 2 %): the nominal's model form is
#: the truth's, so no model-form allowance beyond the members' scatter (ErrorLevels.model_form; a real structure:
#: docs/explain-accuracy.md#model-form).
EXACT_FORM = era.discrepancy.ErrorLevels(model_form=0.0, model_form_shape=0.0)
from era.structure import Frame, Section


def _portal(**kw):
    sec = Section.rectangle(0.05, 0.1)
    return Frame(nodes={"A": (0, 0, 0), "B": (0, 0, 3), "C": (4, 0, 3), "D": (4, 0, 0)},
                 members=[("A", "B", "s"), ("B", "C", "s"), ("C", "D", "s")], sections={"s": sec},
                 supports={"A": "fixed", "D": "fixed"}, sensors=[("B", "x")], **kw)


def test_a_stiff_joint_spring_is_a_rigid_joint_and_a_soft_one_releases_the_beam():
    rigid = _portal().modes(5)[0]
    np.testing.assert_allclose(_portal(joint_springs={"B": 1e12, "C": 1e12}).modes(5)[0], rigid, rtol=1e-6)
    soft = _portal(joint_springs={"B": 1e2, "C": 1e2}).modes(5)[0]
    assert soft[0] == pytest.approx(rigid[0], rel=1e-4)       # out-of-plane sway: the spring acts in the plane
    # in-plane sway with pinned beam ends: two fixed-base cantilever columns carrying the beam, 3EI/h³ each
    assert soft[2] < 0.8 * rigid[2]


def test_added_mass_per_length_weighs_and_adds_to_the_total():
    frame = _portal(added_mass_per_length={"s": 5.0})
    assert frame.total_mass_kg == pytest.approx(_portal().total_mass_kg + 5.0 * 10.0)
    assert Frame.from_dict(frame.to_dict()).added_mass_per_length == {"s": 5.0}


def test_the_frame_library_offers_each_effect_where_it_can_be():
    lib = {s.name: s for s in frame_effects(FrameModel.of(two_storey()))}
    assert set(lib) == {"none", "support_flexibility", "joint_flexibility", "point_mass", "member_stiffness",
                        "distributed_mass"}
    assert set(lib["support_flexibility"].locations) == {"10", "20", "30", "40"}
    assert set(lib["joint_flexibility"].locations) == {"11", "21", "31", "41", "12", "22", "32", "42"}
    assert ("11", "12") in lib["member_stiffness"].locations
    truss_lib = {s.name: s for s in frame_effects(FrameModel.of(truss()))}
    assert truss_lib["support_flexibility"].params[0].name == "support_vertical_stiffness"
    gravity = {s.name for s in frame_effects(FrameModel.of(portal(gravity=(0, 0, -9.81)), gravity=False))}
    assert "gravity_stiffening" in gravity


@pytest.mark.parametrize("effect, params, where", [
    ("support_flexibility", dict(support_at="0", support_rotation_stiffness=300.0), "0"),
    ("point_mass", dict(point_mass_at="3", point_mass_kg=0.15), "3"),
])
def test_a_cantilever_names_the_hidden_effect_and_where(effect, params, where):
    measured, truth = simulate_frame_test(cantilever(), effect, params, seed=1)
    r = era.explain(measured, cantilever(), errors=EXACT_FORM)
    assert r.verdict == "explained" and r.effect.name == effect and r.effect.location == where
    name = next(k for k in params if not k.endswith("_at"))
    value, sd = r.effect.parameters[name], r.effect.uncertainty[name]
    assert abs(value - params[name]) < max(3 * sd, 0.05 * params[name])
    assert r.after.max_abs_freq_error_pct < 0.5 and r.before.max_abs_freq_error_pct > 5


def test_a_portal_with_a_semi_rigid_beam_to_column_joint_names_it_at_its_node():
    measured, _ = simulate_frame_test(portal(), "joint_flexibility", dict(joint_at="C", joint_stiffness=3e5), seed=1)
    r = era.explain(measured, portal(), errors=EXACT_FORM)
    assert r.verdict == "explained" and r.effect.name == "joint_flexibility" and r.effect.location == "C"
    assert r.effect.parameters["joint_stiffness"] == pytest.approx(3e5, rel=0.05)
    assert "at node C" in r.effect.description


def test_a_portal_as_drawn_raises_no_alarm():
    measured, _ = simulate_frame_test(portal(), seed=1)
    r = era.explain(measured, portal(), errors=EXACT_FORM)
    assert r.verdict == "no_significant_discrepancy" and r.effect is None


def test_a_softer_column_is_named_on_its_member():
    measured, _ = simulate_frame_test(portal(), "member_stiffness", dict(member_at=("C", "G"), member_factor=0.6),
                                      seed=1)
    r = era.explain(measured, portal(), errors=EXACT_FORM)
    assert r.verdict == "explained" and r.effect.location == ("C", "G")
    assert r.effect.parameters["member_factor"] == pytest.approx(0.6, abs=0.03)


def test_two_effects_at_once_are_both_named_at_their_places():
    """A flexible base and an added mass: the first alone leaves 3.8 %, the search names the second on top."""
    measured, _ = simulate_frame_test(portal(), "two", dict(point_mass_at="E", point_mass_kg=30.0, support_at="A",
                                                              support_rotation_stiffness=3e5), seed=1)
    r = era.explain(measured, portal(), errors=EXACT_FORM)
    assert r.verdict == "explained"
    assert [(e.name, e.location) for e in r.effects] == [("support_flexibility", "A"), ("point_mass", "E")]
    assert r.effects[1].parameters["point_mass_kg"] == pytest.approx(30.0, rel=0.1)
    assert r.effects[0].parameters["support_rotation_stiffness"] == pytest.approx(3e5, rel=0.15)
    assert r.effects[0].gap_after.max_abs_freq_error_pct > 1.0 > 0.5 > r.after.max_abs_freq_error_pct
