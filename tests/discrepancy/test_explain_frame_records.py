"""explain() on an era.Frame from records, not modal arrays: the portal's truth (2 % member scatter, twice the
mesh, the hidden effect) rings after unit impulses at two sensors (1 % damping, 2 % sensor gains, 1 % noise);
ERA identifies the modes (era.identify through explain's identify_modes) and explain names what was hidden."""

import numpy as np
import pytest

import era
from era.discrepancy.weights import node_rows
from era.discrepancy.measured import input_point
from era.examples.frame_simulation import simulate_frame_records
from era.examples.frames import portal

#: The truths here are era's own finite elements (the members' stiffness scattered 2 %): the nominal's model form is
#: the truth's, so no model-form allowance beyond the members' scatter (ErrorLevels.model_form; a real structure:
#: docs/explain-accuracy.md#model-form).
EXACT_FORM = era.discrepancy.ErrorLevels(model_form=0.0, model_form_shape=0.0)


@pytest.mark.parametrize("seed", [0, 1])
def test_a_semi_rigid_knee_is_named_from_the_portals_impulse_responses(seed):
    data, truth = simulate_frame_records(portal(), "joint_flexibility", dict(joint_at="C", joint_stiffness=3e5),
                                         seed=seed, inputs=(0, 2))
    r = era.explain(data, portal(), errors=EXACT_FORM)
    f_truth = truth.model.modes(12)[0]
    # ERA found the truth's modes the sensors see, to the noise
    assert r.measured.n_modes >= 6
    assert np.all(np.min(np.abs(r.measured.frequency_hz[:, None] / f_truth[None, :] - 1), axis=1) < 2e-3)
    assert r.verdict == "explained" and (r.effect.name, r.effect.location) == ("joint_flexibility", "C")
    low, high = r.effect.interval["joint_stiffness"]
    assert low < 3e5 < high and high / low < 1.5
    assert r.before.max_abs_freq_error_pct > 10 and r.after.max_abs_freq_error_pct < 0.5


def test_input_points_keep_frame_node_ids_as_names_and_grid_joints_as_numbers():
    assert input_point(("E", "x")) == ("E", "x")
    assert input_point(("12", " z")) == ("12", "z")          # a numeric node id stays a name
    assert input_point((3, np.float32(2.5))) == (3.0, 2.5)   # a grid joint (x_ft, y_ft)
    for bad in ((None, "x"), (3.0, float("nan")), (True, 2.0)):
        with pytest.raises(era.DataError, match=r"input_locations.*node id, direction"):
            input_point(bad, 1)


def test_known_impulses_at_frame_nodes_give_modal_constants_and_the_knee():
    """Impulses at F (x) and E (z) with their points in meta: ERA's modal constants are the truth's φ(sensor)
    φ(input) in 1/kg (to its sensor gains and member scatter), explain fits them and still names the knee."""
    data, truth = simulate_frame_records(portal(), "joint_flexibility", dict(joint_at="C", joint_stiffness=3e5),
                                         seed=0, inputs=(0, 2), known_inputs=True)
    assert data.meta["input_locations"] == (("F", "x"), ("E", "z"))
    r = era.explain(data, portal(), errors=EXACT_FORM)
    m = r.measured
    assert m.input_locations == (("F", "x"), ("E", "z")) and m.modal_constants.shape[:2] == (7, 2)
    rows = node_rows(r.nominal_model, m)
    assert rows is not None and rows[1] == [3 * 5 + 0, 3 * 2 + 2]       # F is the 6th node, E the 3rd
    f, w = truth.model.node_modes(14)
    for k in range(m.n_modes):
        j = int(np.argmin(np.abs(f - m.frequency_hz[k])))
        P = np.outer(w[rows[0], j], w[rows[1], j])
        Q = m.modal_constants[:, :, k]
        assert abs(np.sum(Q * P) / np.sum(P * P) - 1) < 0.06, (k, m.frequency_hz[k])
    assert r.verdict == "explained" and (r.effect.name, r.effect.location) == ("joint_flexibility", "C")
    low, high = r.effect.interval["joint_stiffness"]
    assert low < 3e5 < high and high / low < 1.5
    assert r.after.max_abs_freq_error_pct < 0.5


def test_the_portal_as_drawn_gets_no_effect_beyond_its_members_scatter():
    """Nothing hidden: no effect is named but, at most, the one member the truth's 2 % scatter put furthest off,
    at about its factor. Records give shapes far more precise than the modal arrays' 1 % noise, so the members'
    scatter must widen the shapes' error levels too (member_shape_sensitivity), not only the frequencies': seed
    2's truth has member E-C 4.9 % soft and C-G 3.6 % stiff, and with frequencies alone widened explain named
    member F-B 4.6 % soft (posterior 0.99), a confident wrong place."""
    members = [(i, j) for i, j, *_ in portal().members]
    for seed in (1, 2, 3):
        data, truth = simulate_frame_records(portal(), seed=seed, inputs=(1, 4))
        r = era.explain(data, portal(), errors=EXACT_FORM)
        assert r.before.max_abs_freq_error_pct < 1.0
        assert r.verdict != "explained" or len(r.effects) == 1, seed
        for e in r.effects:
            assert e.name == "member_stiffness", (seed, e.name)
            k = members.index(tuple(e.location))
            assert abs(e.parameters["member_factor"] - truth.scatter[k]) < 0.02, (seed, e.location)
            assert abs(truth.scatter[k] - 1) == np.max(np.abs(truth.scatter - 1)), (seed, e.location)


@pytest.mark.parametrize("seed", [0, 1, pytest.param(2, marks=pytest.mark.xfail(strict=True, reason=(
    "known gap: the members' scatter is one draw for every mode, but only the modal constants' sizes carry it "
    "correlated; frequencies and shapes take it mode by mode, which over-counts a one-member pattern: seed 2 "
    "(E-C 4.9 % soft, C-G 3.6 % stiff) is named member F-B 4.4 % soft, 94 %"))), 3])
def test_the_portal_as_drawn_with_known_impulses_gets_no_effect(seed):
    """Nothing hidden, impulses of known size at B (x) and C (z): the modal constants fix the absolute mass, and
    the members' scatter widens their sizes too (member_scale_sensitivity): no effect is named."""
    data, truth = simulate_frame_records(portal(), seed=seed, inputs=(1, 4), known_inputs=True)
    r = era.explain(data, portal(), errors=EXACT_FORM)
    assert r.measured.modal_constants is not None and node_rows(r.nominal_model, r.measured) is not None
    assert r.verdict != "explained", [(e.name, e.location) for e in r.effects]
