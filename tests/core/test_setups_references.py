"""A tower in four ambient setups (tests/simulated_setups.py): channels named ch1..ch8, the two references the last
channels of every setup and near a node of the third mode. The references are found from the modes, the merge
is complete and matches the exact shear-cantilever shapes; a symmetric beam with references at mirror points gets
no proposal (the data cannot tell them apart)."""

from functools import lru_cache

import numpy as np

import era
from era.examples.synthetic import ambient_response
from era.setups.poser import merge_with_evidence
from tests.simulated_setups import DT, TOWER_HZ, TOWER_REFERENCES, TOWER_ROVING, tower_records, tower_truth

TRUE_REFERENCES = [[4, 5], [6, 7], [6, 7], [6, 7]]  # ch5, ch6 in setup 1; ch7, ch8 in setups 2-4


@lru_cache(maxsize=None)
def tower(n_samples: int = 24_000, seed: int = 0) -> tuple:
    """The four setups through NExT (every channel a correlation reference, era's default) and era.analyse."""
    out = []
    for k in range(4):
        y = tower_records(k, n_samples, seed=seed)
        data = era.markov_from_ambient(y, DT, names=[f"ch{i + 1}" for i in range(y.shape[1])])
        out.append(era.analyse(data))
    return tuple(out)


def merged_truth():
    return tower_truth(TOWER_REFERENCES + [i for rov in TOWER_ROVING for i in rov])


def test_the_references_are_found_from_the_modes_not_the_names():
    evidence = era.reference_evidence(tower())
    assert era.propose_references(tower()) == TRUE_REFERENCES == evidence.references
    np.testing.assert_allclose(evidence.shared_hz, TOWER_HZ, rtol=0.01)  # all five modes shared
    best = evidence.candidates[0]
    assert best.channels == tuple(tuple(r) for r in TRUE_REFERENCES)
    assert best.mac.shape == (4, 5) and best.score > 0.99
    assert all(c.score < 0.99 for c in evidence.candidates[1:])  # no roving pair passes
    print("proposal:", evidence.reason, "| best", round(best.score, 5), "next", round(evidence.candidates[1].score, 4))


def test_the_merge_through_the_proposed_references_is_complete_and_exact():
    result = merge_with_evidence(tower(), era.propose_references(tower()))
    model = result.model
    assert model.n_modes == 5 and np.all(result.complete)
    np.testing.assert_allclose(model.frequency_hz, TOWER_HZ, rtol=0.01)
    macs = np.diag(era.mac(model.point_shapes, merged_truth()))
    print("tower merged MAC with the exact shapes:", macs.round(5))
    assert np.all(macs >= 0.99)
    # the third mode's references are near its nodes: its scales are the least certain
    assert np.nanmean(result.scale_std[2]) > 3 * np.nanmean(np.delete(result.scale_std, 2, axis=0))


def test_references_near_a_node_pair_by_frequency_and_say_so():
    """The third mode's references sit near its nodes, so their components are small and noisy: here, in setups 1
    and 3, one of them has the wrong sign (a ratio noise can give). Its reference MAC fails there; each is the only
    mode of its setup within the window, so it is paired by frequency, said, and the merge stays complete."""
    from dataclasses import replace

    runs = list(tower(12_000, 1))
    third = [int(np.argmin(np.abs(a.model.frequency_hz - TOWER_HZ[2]))) for a in runs]
    models = []
    for k, a in enumerate(runs):
        shapes = a.model.shapes.copy()
        if k in (0, 2):
            shapes[TRUE_REFERENCES[k][1], third[k]] *= -1
        models.append(replace(a.model, shapes=shapes, points=(), point_shapes=None))
    result = merge_with_evidence(models, TRUE_REFERENCES)
    assert result.model.n_modes == 5 and np.all(result.complete)
    m = int(np.argmin(np.abs(result.model.frequency_hz - TOWER_HZ[2])))
    assert result.by_frequency[m].sum() >= 1 and result.by_frequency.sum() == result.by_frequency[m].sum()
    assert np.nanmax(result.scale_std[m]) > 3 * np.nanmax(np.delete(result.scale_std, m, axis=0))
    assert not any("seen in 1 of" in d.reason for d in result.dropped)
    macs = np.diag(era.mac(result.model.point_shapes, merged_truth()))
    print("flipped references: paired by frequency in setups", np.flatnonzero(result.by_frequency[m]) + 1,
          "scale σ", result.scale_std[m].round(3), "MAC", macs.round(4))
    assert np.all(np.delete(macs, m) >= 0.99)
    # the same test unflipped: complete too, every mode MAC ≥ 0.95 (0.978 for the third at 300 s)
    plain = merge_with_evidence(runs, TRUE_REFERENCES)
    assert np.all(plain.complete) and np.all(np.diag(era.mac(plain.model.point_shapes, merged_truth())) >= 0.95)


def test_references_at_mirror_points_of_a_symmetric_beam_get_no_proposal():
    """A simply supported beam (sin jπx, exact) with the references at x = 3/13 and 10/13: φ_j(1 - x) = ±φ_j(x),
    so the pair and its swap keep the same ratios in every mode; a proposal would be a guess."""
    x = np.arange(1, 13) / 13
    shapes = np.sin(np.pi * np.outer(x, np.arange(1, 5)))
    refs, roving = [2, 9], [[0, 1, 3], [4, 5, 6], [7, 8], [10, 11]]
    runs = []
    for k in range(4):
        rows = roving[k] + refs
        y, _ = ambient_response([2.0, 5.5, 9.0, 14.0], 0.01, len(rows), 8000, DT, snr_db=20, seed=k,
                                shapes=shapes[rows])
        runs.append(era.analyse(era.markov_from_ambient(y, DT)))
    evidence = era.reference_evidence(runs)
    assert evidence.references is None and era.propose_references(runs) is None
    assert "cannot tell" in evidence.reason
    # the true pair is there, and passes; it is its swapped twin that makes it ambiguous
    best = evidence.candidates[0]
    assert best.score > 0.99 and best.runner_up > 0.99


def test_too_few_shared_modes_get_no_proposal():
    runs = tower(12_000, 1)
    few = [a.model.select([0, 1]) for a in runs]
    evidence = era.reference_evidence(few)
    assert evidence.references is None and "3 or more" in evidence.reason


def with_third_reference(runs, height_per_setup, position_per_setup):
    """The setups' models with one more channel: a sensor at the given height (h, 0-1) of each setup, its shape
    the exact one on each setup's own scale (per mode, the least-squares factor of the true references)."""
    from dataclasses import replace

    from tests.simulated_setups import TOWER_HEIGHTS, TOWER_SHAPES

    out = []
    for k, (a, h) in enumerate(zip(runs, height_per_setup)):
        m = a.model
        phi = m.shapes
        f = m.frequency_hz
        order = [int(np.argmin(np.abs(TOWER_HZ - x))) for x in f]
        truth_refs = TOWER_SHAPES[TOWER_REFERENCES][:, order]  # (2, modes)
        measured = phi[TRUE_REFERENCES[k]]
        scale = np.sum(np.conj(truth_refs) * measured, axis=0) / np.sum(np.abs(truth_refs) ** 2, axis=0)
        row = scale * np.sin((2 * np.array(order) + 1) * np.pi / 2 * h)
        at = position_per_setup[k]
        shapes = np.insert(phi, at, row, axis=0)
        outputs = list(m.outputs)
        outputs.insert(at, "extra")
        assert 0.2 < h < 1 and h not in TOWER_HEIGHTS
        out.append(replace(m, shapes=shapes, outputs=tuple(outputs), points=(), point_shapes=None))
    return out


def test_a_third_reference_is_found_in_its_place_in_every_setup():
    models = with_third_reference(tower(12_000, 1), [0.615] * 4, [1, 8, 0, 3])
    # setup 1: ch1 the new one, so the true references move to ch6, ch7; setup 3: the new one first
    expected = [[1, 5, 6], [8, 6, 7], [0, 7, 8], [3, 7, 8]]
    assert era.propose_references(models) == expected


def test_a_sensor_that_moved_in_one_setup_is_not_proposed():
    models = with_third_reference(tower(12_000, 1), [0.615, 0.615, 0.93, 0.615], [1, 8, 0, 3])
    assert era.propose_references(models) == [[5, 6], [6, 7], [7, 8], [7, 8]]


def test_the_tower_keeps_every_channel_as_nexts_reference_its_near_node_mode_the_closer():
    """The tower at 300 s merged both ways (era.merge_choosing_next): five modes complete each way and shapes as
    consistent (mean MPC 0.999 both; the references-only way once read setup 4 without its 4.5 Hz mode, recovered
    in the merge, and had the lower MPC), so the rule keeps every channel as NExT reference; that merge's third
    mode (the references near its nodes) is indeed the closer to the exact shape."""
    only = []
    for k in range(4):
        y = tower_records(k, 12_000, seed=1)
        only.append(era.analyse(era.markov_from_ambient(y, DT, TRUE_REFERENCES[k])))
    choice = era.merge_choosing_next(tower(12_000, 1), only, TRUE_REFERENCES)
    print(choice.reason)
    assert choice.used == "every" and list(choice.complete) == [5, 5]
    assert "as consistent" in choice.reason  # within era.setups.next_references.MPC_TIE: era's default kept
    assert np.all(choice.result.complete) and choice.result.model.n_modes == 5
    every, refs = (np.diag(era.mac(m.model.point_shapes, merged_truth())) for m in choice.merges)
    print("MAC with the exact shapes, every channel", every.round(4), "references only", refs.round(4))
    assert np.all(every >= 0.99) and every[2] > refs[2]
