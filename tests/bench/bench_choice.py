"""Modes in one click (issue 25): how often era.analyse's automatic choice is right, and what the choice costs.

Run: python3 -m pytest tests/bench/bench_choice.py -s

1. Precision and recall of ``era.analyse(data).model`` against known modes: the real records in ../shared/datasets
   with published frequencies (USC cantilever below 130 Hz, ModeLAB 65-1000 Hz, Carini's three peaks) and
   synthetic systems (MIMO impulse tests at 40/20/15/10 dB, one sensor with a long free decay, close pairs with
   different shapes, ambient records through NExT, heavy damping, noise-free data, the paper's Cases I and II).
   A reported mode is right when it is within 2 % of a true mode not matched yet (one-to-one, nearest first); a
   split twin, a noise pole, a 0 Hz pole or a negative damping counts as false. The table is printed; precision and
   recall over all records must reach 0.95. (tests/bench/bench_choice_peer.py compares with pyOMA2 on ambient
   records that were not used to design the rule.)
2. The cost: era.analyse against identify + stabilization(uncertainty=True) on the sweep benchmark's sizes
   (tests/bench/bench_sweep.py), same Hankel size and orders, interleaved medians: at most 1.2.
"""

import glob
import time

import numpy as np
import pytest

import era
from era.examples import paper_cases
from era.examples.synthetic import ambient_response, modal_response
from tests.bench.timing import median_time
from tests.shared_data import SHARED_DATASETS, require_shared

TARGET = 0.95


def _synthetic():
    f6, z6 = [3, 7.5, 12, 18.5, 26, 33], [0.01, 0.015, 0.01, 0.02, 0.012, 0.015]
    for snr in (40, 20, 10):
        for seed in (0, 1):
            yield f"MIMO 4×2, 6 modes, {snr} dB, seed {seed}", modal_response(f6, z6, 4, 2, 2000, 0.01, snr, seed)
    f8 = [4, 9, 13.5, 21, 30, 44, 58, 77]
    z8 = [0.005, 0.01, 0.03, 0.015, 0.02, 0.01, 0.025, 0.012]
    for seed in (3, 4):
        yield f"MIMO 6×3, 8 modes, 15 dB, seed {seed}", modal_response(f8, z8, 6, 3, 3000, 0.005, 15, seed)
    for seed in (0, 1):
        yield (f"one sensor, free decay 80 s, seed {seed}",
               modal_response([2.1, 9.3, 17.8, 31], [0.005, 0.008, 0.006, 0.01], 1, 1, 8000, 0.01, 30, seed))
    shapes = np.linalg.qr(np.random.default_rng(5).standard_normal((6, 3)))[0]
    for seed in (0, 1):
        yield (f"close pair 1 % (6×2), seed {seed}",
               modal_response([10, 10.1, 25], 0.01, 6, 2, 3000, 0.01, 30, seed, shapes=shapes))
    shapes8 = np.linalg.qr(np.random.default_rng(9).standard_normal((8, 3)))[0]
    yield ("close pair 0.5 % (8×1)",
           modal_response([15, 15.075, 40], [0.005, 0.005, 0.01], 8, 1, 4000, 0.005, 25, 2, shapes=shapes8))
    for snr, seed in ((20, 0), (20, 1), (10, 0), (10, 1)):
        y, truth = ambient_response([1.2, 3.1, 4.7, 6.6, 8.9], [0.01, 0.015, 0.01, 0.02, 0.015], 6, 60000, 0.02,
                                    snr_db=snr, seed=seed)
        yield f"ambient 6 ch, 20 min, {snr} dB, seed {seed}", (era.markov_from_ambient(y, 0.02, n_lags=500), truth)
    for seed in (3, 4):
        y, truth = ambient_response([0.8, 2.2, 2.25, 3.9, 5.5, 7.1], [0.02, 0.01, 0.01, 0.015, 0.01, 0.02], 4,
                                    90000, 0.02, snr_db=15, seed=seed)
        yield f"ambient 4 ch, close pair 2 %, seed {seed}", (era.markov_from_ambient(y, 0.02, n_lags=600), truth)
    yield "heavy damping 3-8 %", modal_response([3, 8, 17], [0.05, 0.08, 0.03], 3, 1, 1500, 0.01, 30, 1)
    yield "noise-free MIMO", modal_response([2, 6, 11, 16], 0.01, 4, 2, 3000, 0.01, None, 3)


def cases():
    """(name, ResponseData, true frequencies (Hz), band graded (Hz) or None)."""
    for name, (data, truth) in _synthetic():
        yield name, data, list(truth.frequency_hz), None
    yield "paper Case I", paper_cases.case_1(), list(np.arange(1, 6) / (2 * np.pi)), None
    yield "paper Case II", paper_cases.case_2(), list(np.array([1, 1, 3, 4, 5]) / (2 * np.pi)), None
    usc = require_shared(SHARED_DATASETS / "usc_cantilever_free_decay" / "timeseries_data.lvm")
    yield "USC cantilever (< 130 Hz)", era.load(usc).data, [6.62, 41.4, 117.5], (0.0, 130.0)
    files = sorted(glob.glob(str(require_shared(SHARED_DATASETS / "modelab_beam_frf" / "SignalCalc") / "*" /
                                 "Hxysv*.txt")))
    yield ("ModeLAB beam FRFs", era.load(files, band_hz=(65.0, 1000.0)).data, [111.99, 306.86, 596.37, 974.14],
           (65.0, 1000.0))
    carini = require_shared(SHARED_DATASETS / "carini_ambient_3ch" / "yk.txt")
    yield "Carini ambient 3 ch", era.load(carini, dt=1 / 25).data, [2.31, 4.96, 7.37], None


def score(found, truth, tol=0.02):
    """(true positives, reported, true, spurious, missed): one-to-one, nearest pairs first."""
    pairs = sorted((abs(f - t) / t, i, j) for i, f in enumerate(found) for j, t in enumerate(truth)
                   if abs(f - t) <= tol * t)
    used_f, used_t = set(), set()
    for _, i, j in pairs:
        if i not in used_f and j not in used_t:
            used_f.add(i)
            used_t.add(j)
    return (len(used_f), len(found), len(truth), [f for i, f in enumerate(found) if i not in used_f],
            [t for j, t in enumerate(truth) if j not in used_t])


def test_precision_and_recall_of_the_automatic_choice():
    total = np.zeros(3, int)
    print(f"\n{'record':42s} {'order':>5s} {'precision':>10s} {'recall':>8s} {'time s':>7s}  spurious / missed")
    for name, data, truth, band in cases():
        t = time.perf_counter()
        a = era.analyse(data)
        elapsed = time.perf_counter() - t
        f = a.model.frequency_hz
        if band is not None:
            f = f[(f >= band[0]) & (f <= band[1])]
        tp, n_found, n_true, spurious, missed = score(list(f), truth)
        total += (tp, n_found, n_true)
        print(f"{name:42s} {a.order:5d} {tp:>4d}/{n_found:<5d} {tp:>3d}/{n_true:<4d} {elapsed:7.2f}  "
              f"{np.round(spurious, 3).tolist()} / {np.round(missed, 3).tolist()}")
    precision, recall = total[0] / max(total[1], 1), total[0] / max(total[2], 1)
    print(f"{'all records':42s} {'':5s} {precision:10.3f} {recall:8.3f}   ({total[0]} right of {total[1]} reported, "
          f"{total[2]} true)")
    assert precision >= TARGET and recall >= TARGET


SIZES = {  # as tests/bench/bench_sweep.py: (p, m, N, rows, cols, dt, frequencies)
    "900x2392 p=9 m=8": (9, 8, 400, 100, 299, 1 / 32, np.linspace(0.3, 14, 20)),
    "1280x2000 p=32 m=4": (32, 4, 2000, 40, 500, 0.01, np.linspace(1, 45, 25)),
}
ORDERS = range(2, 121, 2)


@pytest.mark.parametrize("size", list(SIZES))
def test_analyse_costs_at_most_1_2_identify_and_stabilization(size):
    p, m, n, rows, cols, dt, f = SIZES[size]
    data, _ = modal_response(f, 0.01, p, m, n, dt, snr_db=30, seed=0)

    def parts():
        ident = era.identify(data, rows, cols, max_order=max(ORDERS))
        era.stabilization(ident, ORDERS, uncertainty=True)

    def whole():
        return era.analyse(data, rows=rows, cols=cols, max_order=max(ORDERS), orders=ORDERS)

    whole()
    t_parts, t_whole = [], []
    for _ in range(5):  # interleaved, so a neighbour's load hits both
        t_parts.append(median_time(parts, repeat=1))
        t_whole.append(median_time(whole, repeat=1))
    ratio = np.median(t_whole) / np.median(t_parts)
    a = whole()
    print(f"\n{size}: analyse {np.median(t_whole):.3f} s, identify + stabilization(uncertainty) "
          f"{np.median(t_parts):.3f} s, ratio {ratio:.3f}; {a.model.n_modes} modes chosen of {len(f)} at order "
          f"{a.order}")
    assert score(list(a.model.frequency_hz), list(f))[0] == len(f)
    assert ratio <= 1.2
