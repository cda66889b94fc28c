"""Modes in one click (issue 25): era.analyse chooses the structure's modes, each once, and says why every other
cluster of the diagram is not one."""

import glob

import numpy as np
import pytest

import era
from era.choice.choose import REASONS
from era.examples import paper_cases
from era.examples.synthetic import ambient_response, modal_response
from tests.shared_data import SHARED_DATASETS, require_shared


def _matched(found, truth, tol=0.01):
    """How many of ``truth`` (Hz) have a found frequency within ``tol`` (relative), one-to-one."""
    found, used = list(np.sort(found)), set()
    for t in truth:
        near = [k for k, f in enumerate(found) if k not in used and abs(f - t) <= tol * t]
        if near:
            used.add(min(near, key=lambda k: abs(found[k] - t)))
    return len(used)


def _consistent(a):
    """The contract of an AnalysisResult: the order is a diagram order, each chosen mode has its pole there,
    the model is exactly those modes, every cluster is chosen or rejected with a reason."""
    stab, ident = a.stabilization, a.identification
    assert a.order in stab.orders
    assert a.model.n_modes == len(a.choice.chosen) == a.indices.size
    full = ident.model(a.order)
    np.testing.assert_allclose(a.model.frequency_hz, full.frequency_hz[a.indices])
    assert np.all(np.diff(a.model.frequency_hz) >= 0)
    for c, k in zip(a.choice.chosen, a.indices):
        at = np.flatnonzero((stab.order == a.order) & (stab.mode_index == k))
        assert at.size == 1
    # nothing chosen is a real pole, a growing one, or beyond Nyquist
    assert np.all(a.model.is_pair) and np.all(a.model.damping_ratio > 0)
    assert np.all(a.model.frequency_hz < 0.5 / ident.dt)
    if stab.modes and a.choice.chosen and a.choice.chosen[0].diagram_index >= 0:
        assert len(a.choice.chosen) + len(a.rejected) == len(stab.modes)
    for c in a.rejected:
        assert c.code in REASONS and c.reason
    return a


def test_case_i_noise_free_gives_the_five_modes_with_gamma_and_mu_one():
    a = _consistent(era.analyse(paper_cases.case_1()))
    assert a.order == 10
    np.testing.assert_allclose(a.model.frequency_hz, np.arange(1, 6) / (2 * np.pi), rtol=1e-9)
    np.testing.assert_allclose(a.model.emac, 1.0, atol=1e-6)
    np.testing.assert_allclose(a.model.mpc, 1.0, atol=1e-6)


def test_case_ii_mimo_finds_both_copies_of_the_repeated_pair():
    a = _consistent(era.analyse(paper_cases.case_2()))
    np.testing.assert_allclose(a.model.frequency_hz, np.array([1, 1, 3, 4, 5]) / (2 * np.pi), rtol=1e-6)


@pytest.mark.parametrize("snr", [40, 10])
def test_mimo_impulse_test_every_mode_once_and_no_noise_pole(snr):
    f = [3, 7.5, 12, 18.5, 26, 33]
    data, _ = modal_response(f, [0.01, 0.015, 0.01, 0.02, 0.012, 0.015], 4, 2, 2000, 0.01, snr_db=snr, seed=0)
    a = _consistent(era.analyse(data))
    assert a.model.n_modes == len(f)  # a noise pole or a twin kept would add one
    assert _matched(a.model.frequency_hz, f) == len(f)
    assert np.all(a.model.frequency_std_hz > 0)  # the chosen modes come with the data's uncertainty


def test_one_sensor_long_free_decay_where_mu_says_nothing():
    f = [2.1, 9.3, 17.8, 31]
    data, _ = modal_response(f, [0.005, 0.008, 0.006, 0.01], 1, 1, 8000, 0.01, snr_db=30, seed=1)
    a = _consistent(era.analyse(data))
    np.testing.assert_allclose(a.stabilization.mpc, 1.0)  # one sensor: μ = 1 for every pole
    assert a.model.n_modes == 4 and _matched(a.model.frequency_hz, f) == 4
    codes = {c.code for c in a.rejected}
    assert "noise" in codes and "twin" in codes  # there were noise poles and split twins, and none was kept


def test_close_pair_one_percent_apart_with_different_shapes_is_two_modes():
    shapes = np.linalg.qr(np.random.default_rng(5).standard_normal((6, 3)))[0]
    f = [10, 10.1, 25]
    data, _ = modal_response(f, 0.01, 6, 2, 3000, 0.01, snr_db=30, seed=0, shapes=shapes)
    a = _consistent(era.analyse(data))
    assert a.model.n_modes == 3 and _matched(a.model.frequency_hz, f, tol=0.002) == 3


def test_ambient_record_through_next():
    f = [1.2, 3.1, 4.7, 6.6, 8.9]
    y, _ = ambient_response(f, [0.01, 0.015, 0.01, 0.02, 0.015], 6, 60000, 0.02, snr_db=20, seed=0)
    a = _consistent(era.analyse(era.markov_from_ambient(y, 0.02, n_lags=500)))
    assert a.model.n_modes == 5 and _matched(a.model.frequency_hz, f, tol=0.02) == 5


def test_an_undamped_mains_line_is_named_a_harmonic_not_a_mode():
    data, _ = modal_response([7.0, 23.0, 41.0], [0.01, 0.01, 0.02], 1, 1, 6000, 1 / 500, snr_db=40, seed=2)
    t = np.arange(data.n_samples) * data.dt
    hum = 0.05 * np.abs(data.markov).max() * np.sin(2 * np.pi * 120.0 * t + 0.3)
    a = _consistent(era.analyse(era.ResponseData(data.markov + hum[:, None, None], data.dt)))
    assert a.model.n_modes == 3 and _matched(a.model.frequency_hz, [7, 23, 41]) == 3
    line = [c for c in a.rejected if abs(c.frequency_hz - 120) < 0.5]
    assert line and all(c.code == "harmonic" for c in line), [(c.frequency_hz, c.reason) for c in line]


def test_overrides_are_used():
    data, _ = modal_response([3, 12], 0.01, 2, 1, 1000, 0.01, snr_db=40, seed=0)
    a = era.analyse(data, rows=60, cols=80, orders=range(2, 41, 2), band_hz=(5.0, 50.0))
    assert (a.identification.rows, a.identification.cols) == (60, 80)
    assert a.stabilization.orders.tolist() == list(range(2, 41, 2))
    assert a.band_hz == (5.0, 50.0)
    np.testing.assert_allclose(a.model.frequency_hz, [12.0], rtol=1e-3)  # 3 Hz lies outside the band
    assert any(c.code == "band" and abs(c.frequency_hz - 3) < 0.1 for c in a.rejected)


def test_analyse_refuses_what_is_not_response_data():
    with pytest.raises(era.EraError, match="ResponseData"):
        era.analyse(np.zeros((100, 1, 1)))


# ---- real records with published frequencies (../shared/datasets) ----------------------------------------------
def test_usc_cantilever_three_modes_below_130_hz_each_once():
    ds = era.load(require_shared(SHARED_DATASETS / "usc_cantilever_free_decay" / "timeseries_data.lvm"))
    a = _consistent(era.analyse(ds.data))
    low = a.model.frequency_hz[a.model.frequency_hz < 130]
    np.testing.assert_allclose(low, [6.62, 41.4, 117.5], rtol=0.01)  # published; a twin or a sideband adds one
    near = [c for c in a.rejected if 100 < c.frequency_hz < 130]
    assert any(c.code == "twin" and c.mode == 2 for c in near)  # the 116.75 Hz track is mode 3's split twin
    assert all(c.code != "chosen" for c in near)


def test_modelab_roving_hammer_four_modes_and_the_band_edges_refused():
    files = sorted(glob.glob(str(require_shared(SHARED_DATASETS / "modelab_beam_frf" / "SignalCalc") /
                                 "*" / "Hxysv*.txt")))
    a = _consistent(era.analyse(era.load(files, band_hz=(65.0, 1000.0)).data))
    np.testing.assert_allclose(a.model.frequency_hz, [111.99, 306.86, 596.37, 974.14], rtol=1e-3)
    assert any(c.code == "band" and c.frequency_hz > 990 for c in a.rejected)


def test_carini_ambient_three_peaks_at_an_order_inside_the_diagram():
    ds = era.load(require_shared(SHARED_DATASETS / "carini_ambient_3ch" / "yk.txt"), dt=1 / 25)
    a = _consistent(era.analyse(ds.data))
    assert a.stabilization.orders[0] <= a.order <= a.stabilization.orders[-1]
    np.testing.assert_allclose(a.model.frequency_hz, [2.31, 4.96, 7.37], rtol=0.01)
