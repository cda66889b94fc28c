"""The references of an ambient multi-setup test proposed through the analyses its merge uses.

A beam whose roving channels are 10 dB noisier than their signal (a laser vibrometer beside two reference
accelerometers), channels named ch1…ch5, the references first in setup 1 and last in the others (swapped in setup
3): NExT with every channel as reference leaves one mode shared by the four setups, too few to tell anything; the
pair whose correlations look alike in every setup, analysed through NExT with it only (as the merge's references
way), has its ratios kept in every mode: proposed, right in every setup. Where no pair stays in place no proposal is
made. The reference-only correlations are the columns of the every-channel ones, checked against the direct sum
Σ y_i(t+τ) y_j(t) / (N - τ)."""

from functools import lru_cache

import numpy as np

import era
from era.setups.ambient_references import correlation_candidates
from tests.core.test_setups_next import noisy_records
from tests.simulated_setups import DT

#: Per setup, where its two reference sensors (P2, P5) are among its channels.
TRUE_REFERENCES = [[0, 1], [3, 4], [3, 2], [2, 3]]


def arranged(k: int) -> np.ndarray:
    """Setup k's records (tests/core/test_setups_next.py: the references P2, P5 first, then the roving points) with
    the references moved where TRUE_REFERENCES says."""
    y = noisy_records(k)
    if k == 0:
        return y
    refs = y[:, [1, 0]] if k == 2 else y[:, :2]
    return np.column_stack([y[:, 2:], refs])


@lru_cache(maxsize=None)
def correlations(k: int) -> era.ResponseData:
    y = arranged(k)
    return era.markov_from_ambient(y, DT, names=[f"ch{i + 1}" for i in range(y.shape[1])])


@lru_cache(maxsize=None)
def every_channel(k: int) -> era.AnalysisResult:
    return era.analyse(correlations(k))


def test_reference_only_correlations_are_nexts_with_those_references():
    y = arranged(1)
    every = correlations(1)
    only = era.references_only(every, [3, 4])
    again = era.markov_from_ambient(y, DT, references=[3, 4], names=[f"ch{i + 1}" for i in range(5)])
    np.testing.assert_array_equal(only.markov, again.markov)
    np.testing.assert_array_equal(only.records, again.records)
    assert only.inputs == again.inputs == ("ref ch4", "ref ch5") and only.meta["references"] == [3, 4]
    np.testing.assert_array_equal(only.meta["zero_lag"], again.meta["zero_lag"])
    assert only.meta["conversions"] == again.meta["conversions"]
    # the truth: the direct unbiased sum, means removed
    z = y - y.mean(axis=0)
    n = len(z)
    for tau in (1, 7, 40):
        direct = z[tau:].T @ z[:n - tau, [3, 4]] / (n - tau)
        np.testing.assert_allclose(only.markov[tau - 1], direct, rtol=1e-9, atol=1e-12)


def test_noisy_roving_channels_propose_the_references_through_next_with_them():
    setups = [correlations(k) for k in range(4)]
    mapping, likeness = correlation_candidates(setups, 1)[0]
    assert [list(m) for m in mapping] == TRUE_REFERENCES and likeness > 0.95
    found = era.propose_ambient_references(setups, [every_channel(k) for k in range(4)])
    print(found.tried)
    # every channel as NExT reference tells nothing: too few modes found in every setup to tell the references
    assert "found in every setup" in found.tried[0][1] and "3 or more are needed" in found.tried[0][1]
    assert found.way == "references" and found.references == TRUE_REFERENCES == found.candidate
    assert found.evidence.shared_hz.size >= 3 and found.evidence.candidates[0].score >= 0.99
    assert found.evidence.reason.startswith("through NExT with channels 1 and 2 of setup 1")
    assert era.propose_references([a.model for a in found.analyses]) == TRUE_REFERENCES  # the contract, on them


def test_no_pair_in_place_no_proposal():
    # setup 2's reference sensors replaced by two more roving points (its P2, P5 records of another beam test:
    # setup 3's roving channels): no two channels keep their place in every setup
    setups = [correlations(k) for k in range(4)]
    y = arranged(1)
    y[:, 3:] = arranged(2)[:, :2]
    setups[1] = era.markov_from_ambient(y, DT, names=[f"ch{i + 1}" for i in range(5)])
    every = [every_channel(k) if k != 1 else era.analyse(setups[1]) for k in range(4)]
    found = era.propose_ambient_references(setups, every, n_candidates=1)
    assert found.references is None and len(found.tried) == 2
