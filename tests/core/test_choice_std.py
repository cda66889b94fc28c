"""era.analyse computes the data's σ of only the diagram's poles its choice reads (era.stabilization(...,
uncertainty="choice")), a fraction of the work of every stable pole's: the choice, the chosen modes and their σ
are the same as with every stable pole's σ (``pole_std="all"``), on records of every kind: FRFs cut to a band,
the paper's noise-free Case II (exact rank), an ambient record (σ from its segments) and an impulse test.
tests/bench/bench_sweep.py measures the time on the issue's sizes."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import numpy as np
import pytest

import era
from era.examples import paper_cases
from era.examples.synthetic import ambient_response, modal_response

choice_module = importlib.import_module("era.choice.choose")
stabilization_module = importlib.import_module("era.core.stabilization")  # era.stabilization is the function

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_choice_blas import chain_frf_data  # noqa: E402


def _verdicts(a) -> list:
    """Every cluster's verdict and the chosen modes, as comparable tuples."""
    return [(c.diagram_index, c.code, c.reason, c.mode, c.frequency_hz) for c in a.choice.candidates()]


def _cluster_std(a) -> np.ndarray:
    """(clusters, 2) the σ of frequency and damping each cluster's verdict read (its last pole's)."""
    return np.array([(c.frequency_std_hz, c.damping_std) for c in a.choice.candidates()]).reshape(-1, 2)


def _same_analysis(full, fast) -> None:
    assert fast.order == full.order
    assert np.array_equal(fast.indices, full.indices)
    assert _verdicts(fast) == _verdicts(full)
    # the same numbers, computed with fewer poles of their order beside them: equal to round-off
    np.testing.assert_allclose(_cluster_std(fast), _cluster_std(full), rtol=1e-12)
    for name in ("frequency_hz", "damping_ratio", "frequency_std_hz", "damping_std"):  # the chosen modes, bit for bit
        assert np.array_equal(getattr(fast.model, name), getattr(full.model, name)), name
    s_full, s_fast = full.stabilization, fast.stabilization
    assert np.array_equal(s_fast.frequency_hz, s_full.frequency_hz)
    computed = np.isfinite(s_fast.frequency_std_hz)
    assert computed.sum() < np.isfinite(s_full.frequency_std_hz).sum() or not s_full.modes
    np.testing.assert_allclose(s_fast.frequency_std_hz[computed], s_full.frequency_std_hz[computed], rtol=1e-12)
    np.testing.assert_allclose(s_fast.damping_std[computed], s_full.damping_std[computed], rtol=1e-12)
    for m in s_fast.modes:  # what the choice reads of each cluster: its last pole's σ
        assert np.isfinite(m.data_frequency_std_hz) and np.isfinite(m.data_damping_std)


def test_chain_frfs_cut_to_a_band_the_same_choice_and_the_chains_frequencies():
    data, f_modes = chain_frf_data()
    full = era.analyse(data, band_hz=(2.0, 40.0), pole_std="all")
    fast = era.analyse(data, band_hz=(2.0, 40.0))
    _same_analysis(full, fast)
    np.testing.assert_allclose(fast.model.frequency_hz, f_modes, rtol=1e-3)  # the chain's own eigenvalues


def test_paper_case_2_exact_rank_the_same_modes_with_their_sigma():
    data = paper_cases.case_2()
    full, fast = era.analyse(data, pole_std="all"), era.analyse(data)
    _same_analysis(full, fast)
    # the paper's system: ω = 1, 1, 3, 4, 5 rad/s
    np.testing.assert_allclose(np.sort(fast.model.frequency_hz), np.array([1, 1, 3, 4, 5]) / (2 * np.pi), rtol=1e-6)


def test_an_ambient_record_sigma_from_its_segments_the_same_choice():
    y, _ = ambient_response([1.2, 3.1, 4.7], [0.01, 0.015, 0.02], 4, 15000, 0.02, snr_db=20, seed=2)
    data = era.markov_from_ambient(y, 0.02, n_lags=150)
    full, fast = era.analyse(data, pole_std="all"), era.analyse(data)
    assert fast.identification.records_used() is not None  # the segments' scatter, not the residual blocks
    _same_analysis(full, fast)


def test_clusters_that_reach_the_uncertainty_threshold_get_every_pole_and_the_same_verdict(monkeypatch):
    """With the threshold lowered to the clusters' own σ level, about half of them are "uncertain": then every
    pole of theirs is computed and the verdicts are those of the full path."""
    data, _ = modal_response([3, 7.5, 12, 18.5], [0.01, 0.015, 0.01, 0.02], 4, 2, 600, 0.01, 15, 3)
    size = dict(rows=30, cols=60, max_order=60)
    full = era.analyse(data, pole_std="all", **size)
    level = [np.median(full.stabilization.frequency_std_hz[list(m.pole_indices)]) / m.frequency_hz
             for m in full.stabilization.modes if m.frequency_hz > 0]
    fraction = float(np.median(level))
    for module in (stabilization_module, choice_module):
        monkeypatch.setattr(module, "UNCERTAIN_FRACTION", fraction)
    full, fast = era.analyse(data, pole_std="all", **size), era.analyse(data, **size)
    codes = [c.code for c in full.choice.candidates()]
    assert "uncertain" in codes and codes.count("uncertain") < len(codes)
    _same_analysis(full, fast)
    stab = fast.stabilization
    for m in stab.modes:
        poles = list(m.pole_indices)
        known = stab.frequency_std_hz[poles]
        if not np.all(np.isfinite(known)):  # only part computed: more than half of them, all below the threshold
            done = known[np.isfinite(known)]
            assert done.size >= len(poles) // 2 + 1 and np.all(done < fraction * m.frequency_hz)


def test_bad_uncertainty_and_pole_std_values_say_what_is_allowed():
    data, _ = modal_response([3, 7.5], 0.01, 2, 1, 400, 0.01, 30, 0)
    ident = era.identify(data, 20, 20)
    with pytest.raises(era.EraError, match="choice"):
        era.stabilization(ident, range(2, 11, 2), uncertainty="some")
    with pytest.raises(era.EraError, match="all"):
        era.analyse(data, pole_std="every")
