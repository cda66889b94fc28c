"""era.merge_setups on a real multi-setup ambient test: pyOMA's steel frame, 15 setups (issue 26).

Run: python3 tests/bench/bench_setups_ldv.py /path/to/pyOMA/tests/files [every | both | propose] [defaults]

A script, not a pytest benchmark: the records are GPL-3.0 and cannot be in this repository, so nothing here could
run them on its own. It exits non-zero when a figure below is not met.

The data (not copied here: GPL-3.0, 44 MB): https://github.com/pyOMA-dev/pyOMA ``tests/files/measurement_<n>/``,
n = 1..15, described in its ``doc/example_data.rst``: a 1 m five-floor steel frame (Bauhaus-Universität Weimar)
under fan excitation; each setup points a 3-D scanning laser vibrometer (3 velocity channels, columns 0-2) at one
node and records 240 s at 256 Hz together with two reference accelerometers at node 24 (x, y: columns 3, 4; the z
accelerometer, column 5, is left out as pyOMA's setup_info.txt says). Per setup: decimated ×3 ×3 (28.4 Hz, as
pyOMA's scripts), NExT with the two references (4 segments, 600 lags = 21 s: the modes' damping is ~0.15 %, so the
correlations need many cycles), era.analyse with its defaults; then era.merge_setups(analyses, [[3, 4]] * 15).

With "propose": the references proposed as the page proposes them (era.propose_ambient_references on the
every-channel correlations: their modes first, else the likeliest pairs' NExT analyses), asserted right or none.

With "both": the setups through NExT both ways and era.merge_choosing_next keeps one (asserted: the references
only, 10 modes complete where every channel gives 5, none complete).

Compared with pyOMA's own PoGER result on the same records (its notebook scripts/multi_setup_analysis_poger.ipynb,
stored output, band to 11.4 Hz): 1.229, 1.436, 2.100, 4.017, 4.769, 6.683, 7.616, 9.664 Hz, damping 0.13-0.23 %.
Asserted: each of those within 0.3 % by a merged mode with a shape at every point of the 15 setups; the references
agree (MAC ≥ 0.95 with the merged reference components in every setup).
"""

import sys
import time
from pathlib import Path

import numpy as np
from scipy.signal import decimate

import era
from era.setups.poser import merge_with_evidence

POGER_HZ = np.array([1.229, 1.436, 2.100, 4.017, 4.769, 6.683, 7.616, 9.664])
POGER_DAMPING = np.array([0.232, 0.147, 0.130, 0.162, 0.161, 0.190, 0.165, 0.174]) / 100
DT = 9 / 256
#: "defaults" on the command line: NExT with its own segments and lags instead of 4 segments and 600 lags.
DEFAULTS = "defaults" in sys.argv[2:]


def setup(root: Path, n: int, every_channel: bool = False) -> era.AnalysisResult:
    folder = root / f"measurement_{n}"
    y = np.load(folder / f"measurement_{n}.npy")[:, :5]
    y = decimate(decimate(y, 3, axis=0), 3, axis=0)
    rows = (folder / "channel_dofs.txt").read_text().splitlines()[1:6]
    names = [f"n{r.split()[1]}_{r.split()[4]}" if i < 3 else r.split()[4] for i, r in enumerate(rows)]
    # every_channel: every channel a correlation reference (era's default, what era.load and the app do), the
    # segments and lags as with the two references
    if DEFAULTS:  # era.markov_from_ambient's own segments and lags (what era.load does)
        data = era.markov_from_ambient(y, DT, references=None if every_channel else [3, 4], names=names)
    else:
        data = era.markov_from_ambient(np.array_split(y, 4), DT, references=None if every_channel else [3, 4],
                                       n_lags=600, names=names)
    return era.analyse(data)


def correlations(root: Path, n: int) -> era.ResponseData:
    """Setup n's every-channel NExT correlations, named ch1…ch5 (the names say nothing), segments and lags as
    :func:`setup` makes them."""
    folder = root / f"measurement_{n}"
    y = decimate(decimate(np.load(folder / f"measurement_{n}.npy")[:, :5], 3, axis=0), 3, axis=0)
    names = [f"ch{i + 1}" for i in range(5)]
    if DEFAULTS:
        return era.markov_from_ambient(y, DT, names=names)
    return era.markov_from_ambient(np.array_split(y, 4), DT, n_lags=600, names=names)


def propose(root: Path) -> None:
    t0 = time.perf_counter()
    found = era.propose_ambient_references([correlations(root, n) for n in range(1, 16)])
    for way, said in found.tried:
        print(f"{way}: {said}")
    print(f"proposed: {found.references} (way: {found.way}) in {time.perf_counter() - t0:.0f} s")
    assert found.references in (None, [[3, 4]] * 15), found.references  # right, or none: never wrong


def main(root: Path, every_channel: bool = False, both: bool = False) -> None:
    t0 = time.perf_counter()
    runs = [setup(root, n, every_channel) for n in range(1, 16)]
    t1 = time.perf_counter()
    evidence = era.reference_evidence(runs)
    print(f"proposed references: {evidence.references} ({evidence.reason}; {evidence.shared_hz.size} shared modes)")
    if both:  # era's rule: both ways, the merge with more modes complete kept (what the page does by default)
        every = [setup(root, n, True) for n in range(1, 16)]
        t1 = time.perf_counter()
        choice = era.merge_choosing_next(every, runs, [[3, 4]] * 15)
        print(choice.reason)
        assert choice.used == "references", choice.reason
        result = choice.result
    else:
        result = merge_with_evidence(runs, [[3, 4]] * 15)
    t2 = time.perf_counter()
    model = result.model
    print(f"\n15 setups analysed in {t1 - t0:.1f} s, merged in {1000 * (t2 - t1):.0f} ms; {len(model.points)} points")
    print("  f (Hz)    σ (Hz)    ζ (%)   setups chose / recovered   min ref MAC   complete")
    for j in range(model.n_modes):
        print(f"{model.frequency_hz[j]:8.3f} {model.frequency_std_hz[j]:9.4f} {100 * model.damping_ratio[j]:8.3f}"
              f" {int(np.sum(result.members[j] >= 0)):10d} / {int(result.recovered[j].sum())}"
              f" {np.nanmin(result.reference_mac[j]):17.3f} {bool(result.complete[j])!s:>10}")
    for d in result.dropped:
        print(f"dropped: setup {d.setup + 1}, {d.frequency_hz:.3f} Hz: {d.reason}")
    assert len(model.points) == 2 + 15 * 3
    for f, zeta in zip(POGER_HZ, POGER_DAMPING):
        j = int(np.argmin(np.abs(model.frequency_hz - f)))
        assert abs(model.frequency_hz[j] - f) <= 0.003 * f, (f, model.frequency_hz[j])
        assert result.complete[j] and np.all(np.isfinite(model.point_shapes[:, j]))
        assert np.nanmin(result.reference_mac[j]) >= 0.95
        print(f"pyOMA PoGER {f:.3f} Hz ζ {100 * zeta:.3f} %  ->  ours {model.frequency_hz[j]:.3f} Hz "
              f"ζ {100 * model.damping_ratio[j]:.3f} %, μ {model.mpc[j]:.3f}")


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3, 4, 5) or not (Path(sys.argv[1]) / "measurement_1").is_dir():
        sys.exit("usage: python3 tests/bench/bench_setups_ldv.py PYOMA_TESTS_FILES [every] (the folder holding "
                 "measurement_1 … measurement_15 of pyOMA-dev/pyOMA's tests/files; 'every': NExT with every "
                 "channel as a correlation reference, instead of the two references; 'both': both ways and "
                 "era.merge_choosing_next's choice, as the page does; 'propose': the references proposed as the page "
                 "does; 'defaults': NExT's own segments and lags)")
    if "propose" in sys.argv[2:]:
        propose(Path(sys.argv[1]))
    else:
        main(Path(sys.argv[1]), "every" in sys.argv[2:], "both" in sys.argv[2:])
