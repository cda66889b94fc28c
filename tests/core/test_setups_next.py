"""NExT's references chosen per test from the merges (era.merge_ambient_setups, era.choose_next): a beam whose
roving channels are much noisier than its two reference sensors (as a scanning laser vibrometer's beside reference
accelerometers) keeps a merge that finds every mode complete, the merge with more complete modes when the other
loses one; the shapes match the exact simply supported beam's sin(jπx)."""

from functools import lru_cache

import numpy as np
import pytest

import era
from era.examples.synthetic import ambient_response
from tests.simulated_setups import DAMPING, DT, FREQUENCY_HZ, LEVELS, REFERENCES, ROVING, TRUE_SHAPES, truth_at

#: The roving channels' noise: 10 dB above their structural response (SNR -10 dB); the references' 20 dB below.
ROVING_SNR_DB, REFERENCE_SNR_DB = -10.0, 20.0


def noisy_records(k: int, n_samples: int = 8000) -> np.ndarray:
    """Setup k of the beam (the references P2, P5 first, then its roving points), 200 s at 40 Hz; white sensor
    noise 10 dB above the signal on the roving channels, 20 dB below it on the references."""
    rows = REFERENCES + ROVING[k]
    y, _ = ambient_response(FREQUENCY_HZ, DAMPING, len(rows), n_samples, DT, seed=10 + k, shapes=TRUE_SHAPES[rows])
    snr = np.r_[[REFERENCE_SNR_DB] * 2, [ROVING_SNR_DB] * (len(rows) - 2)]
    rms = np.sqrt(np.mean(y**2, axis=0))
    noise = np.random.default_rng(500 + k).standard_normal(y.shape) * rms * 10 ** (-snr / 20)
    return LEVELS[k] * (y + noise)


@lru_cache(maxsize=None)
def noisy_choice() -> era.NextChoice:
    records = [noisy_records(k) for k in range(4)]
    names = [[f"P{i + 1}" for i in REFERENCES + ROVING[k]] for k in range(4)]
    return era.merge_ambient_setups(records, DT, [[0, 1]] * 4, names=names)


def test_noisy_roving_channels_keep_a_merge_with_every_mode_complete():
    """Every channel as NExT reference once lost a mode here (the roving channels' noise drowned it below the
    choice's strength rule), so the references-only merge was kept; since a mode that lasts over most of the
    diagram, coherent over three sensors or more, is chosen (era.choice.evidence), both merges find all four modes
    complete in every setup and the rule keeps the one with the more consistent shapes. Whichever it keeps, its
    modes are the beam's."""
    choice = noisy_choice()
    print(choice.reason)
    every, only = choice.complete
    assert only == 4 and every == 4
    assert choice.result is choice.merges[0 if choice.used == "every" else 1]
    model = choice.result.model
    assert np.all(choice.result.complete) and model.n_modes == 4
    np.testing.assert_allclose(model.frequency_hz, FREQUENCY_HZ, rtol=0.01)
    macs = np.diag(era.mac(model.point_shapes, truth_at(model.points)))
    print(f"noisy roving channels, {choice.used}: MAC with sin(jπx)", macs.round(4))
    assert np.all(macs[:3] >= 0.95) and macs[3] >= 0.85  # the roving channels' noise, 10 dB above the signal
    assert "4 complete" in choice.reason


def test_the_merge_with_more_complete_modes_is_kept():
    """Every channel as NExT reference with one mode not complete in some setup (as it was here before weak
    modes that last over the diagram were chosen): the references-only merge is kept for its one more mode."""
    from dataclasses import replace

    every, only = noisy_choice().merges
    members, recovered = every.members.copy(), every.recovered.copy()
    members[-1, 0], recovered[-1, 0] = -1, False  # the last mode: not found in setup 1
    lost = replace(every, members=members, recovered=recovered)
    kept = era.choose_next(lost, only)
    assert kept.used == "references" and kept.result is only and tuple(kept.complete) == (3, 4)
    assert "more modes complete" in kept.reason


def test_the_rule_keeps_the_merge_that_was_not_refused_and_counts_split_twins_once():
    only = noisy_choice().merges[1]
    refused = era.DataError("Setup 1 has no modes")
    kept = era.choose_next(refused, only)
    assert kept.used == "references" and kept.complete[0] == -1 and "refused (Setup 1 has no modes)" in kept.reason
    assert era.choose_next(only, refused).used == "every"
    with pytest.raises(era.DataError, match="no modes"):
        era.choose_next(refused, era.DataError("other"))
    # the same merge both ways: a tie, kept by the default (every channel)
    assert era.choose_next(only, only).used == "every" and "era's default kept" in era.choose_next(only, only).reason
    # a mode within the pairing window of another counts once
    from dataclasses import replace

    f = only.model.frequency_hz.copy()
    f[1] = f[0] * 1.01
    twin = replace(only, model=replace(only.model, z=np.exp((-0.01 + 2j * np.pi * f) * only.model.dt)))
    assert era.setups.next_references.count_complete_modes(twin) == 3
