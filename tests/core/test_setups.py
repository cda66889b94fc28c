"""Multi-setup tests (issue 26): a beam's four modes recorded in four ambient setups that share two reference sensors,
each identified on its own through NExT and ERA, merged into one shape at all twelve points (era.merge_setups)."""

from dataclasses import replace
from functools import lru_cache

import numpy as np
import pytest

import era
from era.examples.synthetic import ambient_response
from era.setups.poser import combine, merge_with_evidence

FREQUENCY_HZ = np.array([2.0, 5.5, 9.0, 14.0])
DAMPING = np.array([0.015, 0.01, 0.012, 0.01])
#: a simply supported beam at twelve evenly spaced points: sin(j π x), no point on a node of modes 1-4
X = np.arange(1, 13) / 13
TRUE_SHAPES = np.sin(np.pi * np.outer(X, np.arange(1, 5)))
REFERENCES = [1, 4]  # the two sensors that stay put: each moves in every mode (0.46-0.99 of the largest)
ROVING = [[0, 2, 3], [5, 6, 7], [8, 9], [10, 11]]
LEVELS = [1.0, 2.5, 0.7, 1.8]  # the ambient excitation differs from setup to setup
DT = 0.025  # 40 Hz; 300 s per setup in 8 segments (σ from their scatter)


def setup_records(k: int, modes=(0, 1, 2, 3), test: int = 0):
    """Setup k's ambient record at its sensors (the references first, then its roving points), of ``modes``;
    ``test`` numbers independent repetitions of the whole test."""
    rows, modes = REFERENCES + ROVING[k], list(modes)
    y, _ = ambient_response(FREQUENCY_HZ[modes], DAMPING[modes], len(rows), 12_000, DT, snr_db=20,
                            seed=10 + k + 100 * test, shapes=TRUE_SHAPES[rows][:, modes])
    return LEVELS[k] * y


def analyse_setup(y, k: int | None = None) -> era.AnalysisResult:
    """NExT then ERA; the channels named by their point (P1..P12) when ``k`` is given, else y1, y2, ..."""
    names = None if k is None else [f"P{i + 1}" for i in REFERENCES + ROVING[k]]
    data = era.markov_from_ambient(np.array_split(y, 8), DT, n_lags=160, names=names)
    return era.analyse(data)


@lru_cache(maxsize=None)
def analyses(test: int = 0) -> tuple:
    return tuple(analyse_setup(setup_records(k, test=test), k) for k in range(4))


def points_truth(model) -> np.ndarray:
    """The true shapes at the merged model's points (references, then each setup's roving points)."""
    order = REFERENCES + [i for rov in ROVING for i in rov]
    assert len(model.points) == len(order) == 12
    return TRUE_SHAPES[order]


def test_each_setup_finds_the_four_modes():
    for a in analyses():
        assert a.model.n_modes == 4
        np.testing.assert_allclose(a.model.frequency_hz, FREQUENCY_HZ, rtol=0.01)


def test_merged_shapes_match_the_truth_at_all_twelve_points():
    result = merge_with_evidence(analyses(), [[0, 1]] * 4)
    model = result.model
    assert isinstance(model, era.ModalModel) and model.n_modes == 4
    assert model.points == ("P2", "P5", "P1", "P3", "P4", "P6", "P7", "P8", "P9", "P10", "P11", "P12")
    assert model.point_shapes.shape == (12, 4) and np.all(np.isfinite(model.point_shapes))
    np.testing.assert_allclose(np.max(np.abs(model.point_shapes), axis=0), 1.0)
    macs = np.diag(era.mac(model.point_shapes, points_truth(model)))
    print("merged MAC with the truth:", macs.round(5))
    assert np.all(macs >= 0.99)
    # the truth is real: the merged shapes are too (one phase for all setups), and their scale is the truth's
    assert np.all(model.mpc > 0.99)
    truth = points_truth(model)
    for j in range(4):
        best = truth[:, j] / truth[np.argmax(np.abs(model.point_shapes[:, j])), j]
        assert np.max(np.abs(model.point_shapes[:, j] - best)) < 0.05
    assert np.all(result.complete) and result.dropped == ()
    assert np.all(result.reference_mac > 0.99)
    np.testing.assert_array_equal(result.point_setup, [-1, -1, 0, 0, 0, 1, 1, 1, 2, 2, 3, 3])


def test_without_the_rescaling_the_shapes_do_not_match():
    """The control: the setups' parts as identified (each with its own scale and sign) are not the mode shape."""
    parts = [a.model.shapes[2:] for a in analyses()]
    raw = np.vstack([analyses()[0].model.shapes[:2]] + parts)
    macs = np.diag(era.mac(raw, points_truth(era.merge_setups(analyses(), [[0, 1]] * 4))))
    assert np.min(macs) < 0.9


def test_frequencies_and_damping_are_within_their_uncertainty():
    """Over four independent four-setup tests (16 modes) the merged σ says how far the truth is: frequencies
    within 2σ for ≥ 80 % of the modes, damping for ≥ 70 % (ERA's damping σ from eight segments is a little
    optimistic: 20 of 24 modes within 2σ over six such tests), none beyond 4σ; four setups tell more than one."""
    f_err, z_err = [], []
    for test in range(4):
        model = era.merge_setups(analyses(test), [[0, 1]] * 4)
        assert model.n_modes == 4 and "combined over 4 setups" in model.uncertainty_source
        f_err.append((model.frequency_hz - FREQUENCY_HZ) / model.frequency_std_hz)
        z_err.append((model.damping_ratio - DAMPING) / model.damping_std)
        single = np.array([a.model.frequency_std_hz for a in analyses(test)])
        assert np.all(model.frequency_std_hz < np.median(single, axis=0))
    f_err, z_err = np.abs(f_err), np.abs(z_err)
    print("merged frequency |error|/σ per test and mode:\n", f_err.round(2))
    print("merged damping |error|/σ per test and mode:\n", z_err.round(2))
    assert np.mean(f_err < 2) >= 0.8 and np.all(f_err < 4)
    assert np.mean(z_err < 2) >= 0.7 and np.all(z_err < 4)


def test_a_wrong_reference_choice_is_refused():
    """Setup 3's references named as its channels 0 and 2 (a roving sensor instead of the second reference)."""
    with pytest.raises(era.DataError, match=r"Setup 3's reference channels \[0, 2\] do not move like"):
        era.merge_setups(analyses(), [[0, 1], [0, 1], [0, 2], [0, 1]])


def test_a_wrong_reference_choice_forced_through_gives_a_wrong_shape():
    """Why the check matters: with the reference MAC test switched off (min_reference_mac=0), the modes pair by
    frequency alone and setup 3's part is scaled through a roving sensor: the merged shapes no longer match."""
    model = era.merge_setups(analyses(), [[0, 1], [0, 1], [0, 2], [0, 1]], min_reference_mac=0.0)
    assert model.n_modes == 4
    macs = np.diag(era.mac(model.point_shapes, points_truth(model)))
    print("MAC with setup 3's references wrong:", macs.round(3))
    assert np.min(macs) < 0.9


def test_references_in_the_wrong_order_are_refused():
    with pytest.raises(era.DataError, match="Setup 2's reference channels"):
        era.merge_setups(analyses(), [[0, 1], [1, 0], [0, 1], [0, 1]])


def test_a_mode_a_setup_missed_is_kept_with_nan_at_that_setups_points():
    """Setup 2's roving sensors and its records do not see mode 3 (its modal force is nil there): the merged mode 3
    has its frequency from the other three setups and NaN at setup 2's three points, not 0."""
    runs = list(analyses())
    runs[1] = analyse_setup(setup_records(1, modes=(0, 1, 3)))
    assert runs[1].model.n_modes == 3
    result = merge_with_evidence(runs, [[0, 1]] * 4)
    model = result.model
    assert model.n_modes == 4
    np.testing.assert_array_equal(result.complete, [True, True, False, True])
    missing = result.point_setup == 1
    assert np.all(np.isnan(model.point_shapes[missing, 2]))
    assert np.all(np.isfinite(model.point_shapes[~missing, 2]))
    seen = ~missing
    assert era.mac(model.point_shapes[seen, 2], points_truth(model)[seen, 2])[0, 0] > 0.99
    assert abs(model.frequency_hz[2] - 9.0) < 3 * model.frequency_std_hz[2]
    complete = model.select(np.flatnonzero(result.complete))  # what an export that needs every point takes
    assert complete.n_modes == 3 and np.all(np.isfinite(complete.point_shapes))


def test_a_weak_cluster_a_setup_left_out_is_recovered_when_the_other_setups_confirm_the_mode():
    """Setup 2's choice left mode 3 out as a noise pole (simulated: the chosen cluster moved to the rejected ones):
    the other three setups confirm a mode at 9 Hz with the same reference components, so setup 2's part of the
    shape is taken from that cluster; the frequency and damping come from the three setups that chose it."""
    runs = list(analyses())
    a = runs[1]
    weak = replace(a.choice.chosen[2], code="noise", reason="noise pole (simulated)", mode=None)
    choice = replace(a.choice, indices=a.choice.indices[[0, 1, 3]], chosen=a.choice.chosen[:2] + a.choice.chosen[3:],
                     rejected=a.choice.rejected + (weak,))
    runs[1] = replace(a, choice=choice, model=a.model.select([0, 1, 3]))
    result = merge_with_evidence(runs, [[0, 1]] * 4)
    assert result.members[2, 1] == -1 and result.recovered[2, 1] and np.all(result.complete)
    assert result.recovered_from[2, 1] == len(a.choice.rejected)
    macs = np.diag(era.mac(result.model.point_shapes, points_truth(result.model)))
    assert np.all(macs >= 0.99)
    three = [runs[k].model.frequency_hz[2] for k in (0, 2, 3)]
    assert min(three) <= result.model.frequency_hz[2] <= max(three)
    # without recovery, setup 2's points are NaN for that mode
    plain = merge_with_evidence(runs, [[0, 1]] * 4, recover=False)
    assert not plain.complete[2] and np.all(np.isnan(plain.model.point_shapes[plain.point_setup == 1, 2]))


def test_a_mode_seen_in_one_setup_only_is_dropped_with_its_reason():
    runs = list(analyses())
    lonely = runs[0].model
    runs = [runs[0]] + [a.model.select([0, 1, 3]) for a in runs[1:]]
    result = merge_with_evidence(runs, [[0, 1]] * 4)
    assert result.model.n_modes == 3
    assert [(d.setup, d.index) for d in result.dropped] == [(0, 2)]
    assert "seen in 1 of 4 setups" in result.dropped[0].reason
    assert result.dropped[0].frequency_hz == pytest.approx(lonely.frequency_hz[2])
    # with min_setups=1 it is kept, known at setup 1's points only
    kept = merge_with_evidence(runs, [[0, 1]] * 4, min_setups=1)
    assert kept.model.n_modes == 4 and np.count_nonzero(np.isfinite(kept.model.point_shapes[:, 2])) == 5


def test_a_split_twin_in_one_setup_is_dropped_as_such():
    """Setup 1 reports mode 3 twice (9.01 and 9.03 Hz, one shape): one pole joins the other setups' mode 3, the
    other is dropped and the reason names it a split twin."""
    runs = list(analyses())
    model = runs[0].model
    idx = np.array([0, 1, 2, 2, 3])
    z = model.z[idx].copy()
    z[3] *= np.exp(2j * np.pi * 0.02 * model.dt)
    per_mode = {name: getattr(model, name)[idx] for name in
                ("amplitudes", "emac", "mpc", "contribution", "is_pair", "frequency_std_hz", "damping_std")}
    runs[0] = replace(model, z=z, shapes=model.shapes[:, idx], point_shapes=model.shapes[:, idx], **per_mode)
    result = merge_with_evidence(runs, [[0, 1]] * 4)
    assert result.model.n_modes == 4 and np.all(result.complete)
    assert len(result.dropped) == 1 and result.dropped[0].setup == 0 and result.dropped[0].index in (2, 3)
    assert "split twin" in result.dropped[0].reason
    assert np.all(np.diag(era.mac(result.model.point_shapes, points_truth(result.model))) >= 0.99)


def test_a_mode_at_a_node_of_the_references_cannot_be_scaled():
    """References at the nodes of a mode leave its parts without a common scale: left out, and the reason says so."""
    runs = list(analyses())
    model = runs[0].model
    flat = model.shapes.copy()
    flat[[0, 1], 1] *= 1e-3  # mode 2 barely moves at the references in setup 1
    runs[0] = _with_shapes(model, flat)
    result = merge_with_evidence(runs, [[0, 1]] * 4)
    assert any(d.setup == 0 and d.index == 1 and "near a node" in d.reason for d in result.dropped)
    # mode 2 is still merged from the other three setups
    assert result.model.n_modes == 4 and not result.complete[1]


def _with_shapes(model, shapes):
    return replace(model, shapes=shapes, point_shapes=shapes)


def test_generic_channel_names_are_told_apart_by_their_setup():
    runs = [analyse_setup(setup_records(0)), analyse_setup(setup_records(1))]
    model = era.merge_setups(runs, [[0, 1]] * 2)
    assert model.points == ("y1", "y2", "S1:y3", "S1:y4", "S1:y5", "S2:y3", "S2:y4", "S2:y5")


def test_one_setup_merges_to_itself():
    a = analyses()[0]
    model = era.merge_setups([a], [[0, 1]])
    assert model.points == a.model.outputs
    np.testing.assert_allclose(model.frequency_hz, a.model.frequency_hz)
    assert np.all(np.diag(era.mac(model.point_shapes, a.model.shapes)) > 1 - 1e-12)


@pytest.mark.parametrize("references, message", [
    ([[0, 1]] * 3, "4 setups but 3 reference lists"),
    ([[0, 1], [0, 1], [0, 5], [0, 1]], r"Setup 3's reference indices \[0, 5\] are out of range: it has 4 channels"),
    ([[0, 1], [0], [0, 1], [0, 1]], "Setup 2 has 1 reference channels where setup 1 has 2"),
    ([[0, 0], [0, 1], [0, 1], [0, 1]], "names a reference channel twice"),
    ([[0, 1], [], [0, 1], [0, 1]], "Setup 2 names no reference channel"),
])
def test_mismatched_references_are_refused(references, message):
    with pytest.raises(era.DataError, match=message):
        era.merge_setups(analyses(), references)


def test_a_setup_with_no_modes_is_refused():
    runs = list(analyses())
    runs[2] = runs[2].model.select([])
    with pytest.raises(era.DataError, match="Setup 3 has no modes"):
        era.merge_setups(runs, [[0, 1]] * 4)


def test_combine_weights_by_inverse_variance_and_widens_for_scatter():
    mean, sd = combine([1.0, 2.0], [0.1, 0.2])
    assert mean == pytest.approx((1 / 0.01 + 2 / 0.04) / (1 / 0.01 + 1 / 0.04))
    assert sd > 1 / np.sqrt(1 / 0.01 + 1 / 0.04)  # 1 and 2 are 4.5 σ apart: the scatter widens σ
    assert combine([1.0, 1.0], [0.1, 0.1]) == pytest.approx((1.0, 0.1 / np.sqrt(2)))
    mean, sd = combine([1.0, 2.0], [0.1, np.nan])
    assert mean == 1.5 and np.isnan(sd)


def test_a_uff55_export_of_merged_point_shapes_reads_back_at_the_right_nodes(tmp_path):
    """Setup 2 misses mode 3, so mode 3 is NaN at its points: the UFF 55 export writes modes 1, 2 and 4 (their
    numbers kept), says mode 3 (index 2) was left out, and pyuff reads each point's value at node k + 1."""
    import pyuff

    runs = list(analyses())
    runs[1] = analyse_setup(setup_records(1, modes=(0, 1, 3)), 1)
    model = merge_with_evidence(runs, [[0, 1]] * 4).model
    path = tmp_path / "merged.uff"
    assert era.save_modes_uff(path, model) == (2,)
    sets = pyuff.UFF(str(path)).read_sets()
    nodes = [s for s in sets if s["type"] == 15][0]
    np.testing.assert_array_equal(nodes["node_nums"], np.arange(1, 13))
    modes = [s for s in sets if s["type"] == 55]
    assert [int(s["mode_n"]) for s in modes] == [1, 2, 4]
    for s, k in zip(modes, (0, 1, 3)):
        np.testing.assert_array_equal(s["node_nums"], np.arange(1, 13))
        np.testing.assert_allclose(s["r3"], model.point_shapes[:, k], atol=1e-5)
    back = era.read_modes_uff(path)
    np.testing.assert_allclose(back.frequency_hz, model.natural_frequency_hz[[0, 1, 3]], rtol=1e-5)
    assert np.all(np.diag(era.mac(back.shapes[:, 2, :], points_truth(model)[:, [0, 1, 3]])) >= 0.99)


def test_no_complete_mode_is_refused_in_words(tmp_path):
    runs = list(analyses())
    model = merge_with_evidence(runs, [[0, 1]] * 4).model
    gappy = replace(model, shapes=np.where(np.arange(12)[:, None] == 11, np.nan, model.shapes),
                    point_shapes=np.where(np.arange(12)[:, None] == 11, np.nan, model.shapes))
    with pytest.raises(era.DataError, match="None of the 4 modes is known at every point"):
        era.save_modes_uff(tmp_path / "none.uff", gappy)


def test_merged_points_are_placed_on_each_setups_geometry():
    """Each setup's file places its own channels on the beam's nodes (node i + 1 is point Pi+1, moving in z): the
    merged geometry puts every point, references included, on its node."""
    nodes = np.arange(1, 13)
    xyz = np.column_stack([X, np.zeros(12), np.zeros(12)])
    edges = np.column_stack([np.arange(11), np.arange(1, 12)])
    geos = [era.Geometry(nodes, xyz, edges, np.array(REFERENCES + ROVING[k]),
                         np.tile([0.0, 0, 1], (2 + len(ROVING[k]), 1))) for k in range(4)]
    geos[2] = None  # a setup without geometry: its points are not placed
    result = merge_with_evidence(analyses(), [[0, 1]] * 4)
    g = era.setups.poser.merged_geometry(geos, result)
    order = REFERENCES + [i for rov in ROVING for i in rov]
    expect = np.where(result.point_setup == 2, -1, order)
    np.testing.assert_array_equal(g.channel_nodes, expect)
    assert era.setups.poser.merged_geometry([None] * 4, result) is None
