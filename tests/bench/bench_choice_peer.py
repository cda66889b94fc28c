"""Our automatic choice of modes (era.analyse) against pyOMA2's automated clustering, on the same ambient records.

Run: python3 -m pip install -e '.[bench]' && python3 -m pytest tests/bench/bench_choice_peer.py -s

The records (era.examples.synthetic.ambient_response): 6 outputs, 25 minutes at 80 Hz (10 × the highest mode),
five well-separated modes at 1-2 % damping with SNR 20 dB and 10 dB (three seeds each), and a close pair 1 % apart
with orthogonal shapes (two seeds). Both methods get the raw records y (N, p) and nothing else:

* ours: ``era.markov_from_ambient(y, dt)`` (NExT, every channel a reference) then ``era.analyse(data)`` with its
  defaults; the modes reported are ``result.model.frequency_hz``.
* pyOMA2 (PyPI ``pyOMA-2`` >= 1.2, where the covariance-driven SSI is ``SSI(method="cov")``: the ``SSIcov`` class
  and ``AutoSSI`` were folded into it, so clustering applies to it directly):
  ``SingleSetup(y, fs)``, ``SSI(name, method="cov", br=50, ordmax=100, step=2)``,
  ``ssi.add_clustering(Clustering(name, steps=(Step1(), Step2(), Step3())))``, ``setup.add_algorithms(ssi)``,
  ``setup.run_by_name(name)``, ``ssi.run_clustering(name)``; the modes reported are
  ``ssi.result.clustering_results[name].Fn``. br, ordmax and step are those of pyOMA2's own clustering example
  (Example5), not tuned to these records; Step1/2/3 at their defaults are its hierarchical clustering (average
  linkage on the eigenvalue and MAC distances, then merge_similar, damp_IQR, fn_IQR, 1xorder, min_size_pctg, MTT).

Score: a reported mode is a true positive when it matches a not-yet-matched true mode within 2 % in frequency
(one-to-one, nearest pairs first); precision = TP / reported, recall = TP / true, per record and over all records
together. Times are one wall-clock run per record and method (BLAS pinned to one thread by conftest.py): ours
NExT + analyse, pyOMA2 SSI (its correlations included) + clustering. Asserted: both ran on every record, and ours
reaches precision and recall ≥ 0.95 over all records. pyOMA2 comes with the bench extra.
"""

import os
import time

import numpy as np
import pytest

import era
from era.examples.synthetic import ambient_response

# pyOMA2 logs every step at INFO and draws tqdm bars; both must be set before it (and tqdm) is imported
os.environ.setdefault("PYOMA_LOG_LEVEL", "WARNING")
os.environ.setdefault("TQDM_DISABLE", "1")

N_OUTPUTS = 6
DT = 1 / 80  # 80 Hz: 10 × the highest mode
N_SAMPLES = int(25 * 60 / DT)  # 25 minutes
FREQUENCY_HZ = np.array([1.0, 2.6, 4.1, 5.9, 7.8])
DAMPING = np.array([0.01, 0.015, 0.02, 0.012, 0.018])
PAIR_HZ = np.array([1.0, 2.6, 4.1, 4.141, 5.9, 7.8])  # 4.1 and 4.141 Hz: 1 % apart
PAIR_DAMPING = np.array([0.01, 0.015, 0.01, 0.01, 0.012, 0.018])
MATCH = 0.02  # a reported mode within 2 % of a true one finds it
TARGET = 0.95  # ours: precision and recall over all records
PEER = {"br": 50, "ordmax": 100, "step": 2}  # pyOMA2's Example5


def _pair_shapes():
    """(p, 6) shapes with the close pair's two columns orthogonal (MAC 0) and of the others' size."""
    phi = np.random.default_rng(7).standard_normal((N_OUTPUTS, PAIR_HZ.size))
    q, _ = np.linalg.qr(phi[:, [2, 3]])
    phi[:, [2, 3]] = q * np.sqrt(N_OUTPUTS)
    return phi


CASES = {  # name: (frequencies Hz, damping ratios, SNR dB, seeds, shapes or None for random ones per seed)
    "5 modes, 20 dB": (FREQUENCY_HZ, DAMPING, 20, (0, 1, 2), None),
    "5 modes, 10 dB": (FREQUENCY_HZ, DAMPING, 10, (0, 1, 2), None),
    "close pair 1 %, 20 dB": (PAIR_HZ, PAIR_DAMPING, 20, (0, 1), _pair_shapes()),
}


def score(reported_hz, true_hz, tolerance=MATCH):
    """(TP, reported, true, spurious Hz, missed Hz): one-to-one matches within ``tolerance`` relative frequency,
    the nearest pairs first."""
    reported_hz, true_hz = np.sort(np.asarray(reported_hz, float)), np.asarray(true_hz, float)
    err = np.abs(reported_hz[:, None] / true_hz[None, :] - 1)
    used_r, used_t = set(), set()
    for i, j in sorted(zip(*np.nonzero(err <= tolerance)), key=lambda ij: err[ij]):
        if i not in used_r and j not in used_t:
            used_r.add(i)
            used_t.add(j)
    spurious = [f for i, f in enumerate(reported_hz) if i not in used_r]
    missed = [f for j, f in enumerate(true_hz) if j not in used_t]
    return len(used_r), reported_hz.size, true_hz.size, spurious, missed


def ours(y):
    """Reported frequencies (Hz), the seconds of NExT and of analyse, and the rejected clusters as (Hz, code)."""
    t0 = time.perf_counter()
    data = era.markov_from_ambient(y, DT)
    t1 = time.perf_counter()
    result = era.analyse(data)
    t2 = time.perf_counter()
    rejected = [(c.frequency_hz, c.code) for c in result.rejected]
    return np.asarray(result.model.frequency_hz), (t1 - t0, t2 - t1), rejected


def why_missed(missed_hz, rejected):
    """Each missed true mode with the code of the nearest rejected cluster within the match tolerance."""
    out = []
    for f in missed_hz:
        near = [(abs(fr / f - 1), code) for fr, code in rejected if abs(fr / f - 1) <= MATCH]
        out.append(f"{f:.3f} ({min(near)[1] if near else 'no cluster'})")
    return "[" + ", ".join(out) + "]"


def _load_peer():
    """pyOMA2's classes and version (the bench extra: python3 -m pip install -e '.[bench]')."""
    from importlib.metadata import version

    from pyoma2.algorithms import SSI
    from pyoma2.algorithms.data.run_params import Clustering, Step1, Step2, Step3
    from pyoma2.setup.single import SingleSetup
    return SingleSetup, SSI, Clustering, (Step1, Step2, Step3), version("pyOMA-2")


def peer(y, classes):
    """pyOMA2's covariance SSI and its default hierarchical clustering: reported frequencies (Hz) and the seconds
    of the SSI run and of the clustering."""
    SingleSetup, SSI, Clustering, steps, _ = classes
    t0 = time.perf_counter()
    setup = SingleSetup(y, fs=1 / DT)
    ssi = SSI(name="ssicov", method="cov", **PEER)
    ssi.add_clustering(Clustering(name="hierarc", steps=tuple(step() for step in steps)))
    setup.add_algorithms(ssi)
    setup.run_by_name("ssicov")
    t1 = time.perf_counter()
    ssi.run_clustering("hierarc")
    t2 = time.perf_counter()
    return np.asarray(ssi.result.clustering_results["hierarc"].Fn, float), (t1 - t0, t2 - t1)


@pytest.fixture(scope="module")
def runs():
    """Every record through both methods: a list of rows and pyOMA2's version."""
    classes = _load_peer()
    rows = []
    for name, (f, zeta, snr, seeds, shapes) in CASES.items():
        for seed in seeds:
            y, truth = ambient_response(f, zeta, N_OUTPUTS, N_SAMPLES, DT, snr_db=snr, seed=seed, shapes=shapes)
            row = {"case": name, "seed": seed, "true": truth.frequency_hz}
            row["ours"], row["ours_s"], row["ours_rejected"] = ours(y)
            try:
                row["peer"], row["peer_s"] = peer(y, classes)
            except Exception as e:  # noqa: BLE001 - shown in the table; the test then says the peer failed
                row["peer_error"] = f"{type(e).__name__}: {e}"
            rows.append(row)
    return rows, classes[-1]


def _cells(row, key):
    if key not in row:
        return "  (" + row.get(f"{key}_error", "not run")[:60] + ")", None
    tp, n_rep, n_true, spurious, missed = s = score(row[key], row["true"])
    p, r = tp / n_rep if n_rep else 0.0, tp / n_true
    return f"{p:11.2f}{r:8.2f}{sum(row[f'{key}_s']):8.2f}", s


def _hz(values):
    return "[" + ", ".join(f"{v:.3f}" for v in values) + "]"


def _report(rows, peer_version):
    label = f"pyOMA2 {peer_version}"
    lines = [f"\n{'':<29} | {'ours (NExT + era.analyse)':<27} | {label} (SSI cov + clustering)",
             f"{'case':<24}{'seed':>5} | {'precision':>11}{'recall':>8}{'time s':>8} | "
             f"{'precision':>11}{'recall':>8}{'time s':>8}"]
    totals = {"ours": np.zeros(4), "peer": np.zeros(4)}  # TP, reported, true, seconds
    details = []
    for row in rows:
        cells = {}
        for key in ("ours", "peer"):
            cells[key], s = _cells(row, key)
            if s is not None:
                totals[key] += (s[0], s[1], s[2], sum(row[f"{key}_s"]))
        lines.append(f"{row['case']:<24}{row['seed']:>5} | {cells['ours']} | {cells['peer']}")
        for key, who in (("ours", "ours"), ("peer", "pyOMA2")):
            if key in row:
                _, _, _, spurious, missed = score(row[key], row["true"])
                a, b = row[f"{key}_s"]
                parts = ("NExT", "analyse") if key == "ours" else ("SSI", "clustering")
                missed = why_missed(missed, row["ours_rejected"]) if key == "ours" else _hz(missed)
                details.append(f"  {row['case']}, seed {row['seed']}, {who}: spurious {_hz(spurious)}, missed "
                               f"{missed}; {parts[0]} {a:.2f} s + {parts[1]} {b:.2f} s")
    for key in ("ours", "peer"):
        tp, n_rep, n_true, sec = totals[key]
        totals[key] = (tp / n_rep if n_rep else 0.0, tp / n_true if n_true else 0.0, int(tp), int(n_rep),
                       int(n_true), sec)
    o, p = totals["ours"], totals["peer"]
    lines.append(f"{'all records':<29} | {o[0]:11.2f}{o[1]:8.2f}{o[5]:8.2f} | "
                 + (f"{p[0]:11.2f}{p[1]:8.2f}{p[5]:8.2f}" if p[4] else "  (not run)"))
    lines.append(f"  (TP / reported / true: ours {o[2]}/{o[3]}/{o[4]}, pyOMA2 {p[2]}/{p[3]}/{p[4]}; a mode within "
                 f"{MATCH:.0%} of a true one, one-to-one)")
    print("\n".join(lines + details))
    return totals


def test_both_methods_ran_on_every_record_and_the_table_is_printed(runs):
    rows, peer_version = runs
    _report(rows, peer_version)
    assert all(len(row["ours"]) > 0 for row in rows)
    failed = [f"{row['case']} seed {row['seed']}: {row['peer_error']}" for row in rows if "peer_error" in row]
    assert not failed, f"pyOMA2 failed on {failed}"


def test_ours_finds_every_mode_and_nothing_else_over_all_records(runs):
    """Precision and recall ≥ 0.95 over all records together. Measured (issue 25): ours 1.00 / 1.00 (42 of 42, no
    spurious mode), pyOMA2 1.4.3 0.85 / 0.98 (41 true and 7 spurious of 48 reported), ours 12 s against 89 s."""
    rows = runs[0]
    tp = sum(score(row["ours"], row["true"])[0] for row in rows)
    n_rep = sum(len(row["ours"]) for row in rows)
    n_true = sum(len(row["true"]) for row in rows)
    precision, recall = tp / n_rep, tp / n_true
    assert precision >= TARGET and recall >= TARGET, (f"precision {precision:.2f} ({tp}/{n_rep}), recall "
                                                      f"{recall:.2f} ({tp}/{n_true}) over {len(rows)} records")
