"""Real files as they are: a delimiter ending every row (a phone app's CSV), times saved with 7 significant digits
judged against their own digits, and a jittered clock resampled only when asked, with what was done said."""

import sys
from pathlib import Path

import numpy as np
import pytest

import era
import era.io.preview

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from chain_sim import hammer_decay  # noqa: E402
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

PHONE = Path(__file__).resolve().parents[1] / "data" / "cessipy_smartphone_slab.csv"
USC = SHARED_DATASETS / "usc_cantilever_free_decay" / "timeseries_data.lvm"
DT = 0.01


def csv_bytes(t, y, fmt="{:.7g}", end=""):
    lines = ["time_s,a1,a2,a3" + end] + [",".join([fmt.format(ti)] + [f"{v:.10e}" for v in row]) + end
                                         for ti, row in zip(t, y)]
    return ("\n".join(lines) + "\n").encode()


def test_a_delimiter_ending_every_row_is_not_a_channel():
    y, f_modes = hammer_decay(600, 2, DT)
    t = np.arange(len(y)) * DT
    for end in (",", ";"):
        raw = csv_bytes(t, y, end=end) if end == "," else csv_bytes(t, y, end=end).replace(b",", b";")
        ds = era.load(raw, name="trailing.csv")
        assert ds.data.outputs == ("a1", "a2", "a3") and ds.data.dt == pytest.approx(DT)
        assert "a delimiter ending every line" in ds.source["records"][0]
    headerless = "\n".join(f"{ti:.2f},{a:.8e},{b:.8e}," for ti, (a, b, _) in zip(t, y)).encode()
    assert era.load(headerless, name="bare.csv").data.markov.shape[1] == 2


def test_the_phone_csv_is_read_and_its_jittered_clock_resampled_only_when_asked():
    with pytest.raises(era.DataError, match=r"cessipy_smartphone_slab.csv, line 3: the time step is 0.00235208 s "
                                            r"where the typical step is 0.0023525 s.*No sample is missing or "
                                            r"repeated.*steady rate of 425.077 Hz") as refused:
        era.load(PHONE)
    assert refused.value.option == "resample"
    ds = era.load(PHONE, resample=True)
    assert ds.data.outputs == ("X-Axis", "Y- Axis", "Z-Axis") and ds.data.output_units == ("m/s2",) * 3
    assert 1 / ds.data.dt == pytest.approx(425.077, abs=1e-3)
    said = ds.source["conversions"][0]
    assert said.startswith("cessipy_smartphone_slab.csv: resampled onto an even grid at the mean rate 425.077 Hz")
    assert "linear interpolation" in said and "25291 → 25290 samples" in said


def test_a_record_with_one_sample_missing_is_refused_naming_the_line():
    y, _ = hammer_decay(600, 2, DT)
    t = np.arange(len(y)) * DT
    rng = np.random.default_rng(1)
    jittered = t + rng.uniform(-2e-4, 2e-4, len(t))
    keep = np.r_[0:250, 251:len(t)]  # the sample of line 252 is missing
    for name, times in (("even.csv", t), ("jittered.csv", jittered)):
        for resample in (False, True):
            with pytest.raises(era.DataError, match=rf"{name}, line 252: the time step is 0.0\d+ s where the typical "
                                                    r"step is 0.01\d* s .*: 1 sample is missing"):
                era.load(csv_bytes(times[keep], y[keep], fmt="{:.6f}"), name=name, resample=resample)
    repeated = np.r_[0:250, 249:len(t)]
    with pytest.raises(era.DataError, match=r"line 252: the time goes from 2.49 to 2.49 s \(a repeat"):
        era.load(csv_bytes(t[repeated], y[repeated], fmt="{:.6f}"), name="repeat.csv", resample=True)


def test_a_resampled_record_has_the_modes_of_the_original():
    """The chain's free decay, stamped by a clock that jitters ±0.3 ms and wanders 0.01 % in rate: resampled, the
    analysis finds the modes of the evenly sampled original."""
    y, f_modes = hammer_decay(3000, 2, DT)
    n = len(y)
    t = np.arange(n) * DT
    rng = np.random.default_rng(7)
    clock = t * (1 + 1e-4 * np.sin(np.arange(n) / n * 2 * np.pi)) + rng.uniform(-3e-4, 3e-4, n)
    clock -= clock[0]
    values = np.column_stack([np.interp(clock, t, y[:, c]) for c in range(3)])  # what the jittered sensor saw
    original = era.analyse(era.load(csv_bytes(t, y, fmt="{:.6f}"), name="even.csv", kind="decay").data)
    with pytest.raises(era.DataError, match="Resample onto an even grid"):
        era.load(csv_bytes(clock, values, fmt="{:.6f}"), name="phone.csv", kind="decay")
    ds = era.load(csv_bytes(clock, values, fmt="{:.6f}"), name="phone.csv", kind="decay", resample=True)
    assert ds.data.dt == pytest.approx(DT, rel=1e-4)
    resampled = era.analyse(ds.data)
    f0, f1 = np.sort(original.model.frequency_hz), np.sort(resampled.model.frequency_hz)
    assert len(f0) == len(f1) == len(f_modes)
    np.testing.assert_allclose(f1, f0, rtol=2e-3)
    np.testing.assert_allclose(np.sort(resampled.model.damping_ratio), np.sort(original.model.damping_ratio),
                               atol=2e-3)
    assert ds.source["conversions"][0].startswith("phone.csv: resampled onto an even grid")


def test_the_usc_cantilever_saved_with_7_significant_digits_is_even():
    """Times kept in single precision and printed to 7 significant digits stray ~5 µs from an even step: within
    their printed digit of the least-squares line, so the record is even (no resampling)."""
    rec = era.io.read(require_shared(USC)).records
    y = rec.values[0][:, 0]
    t = (rec.step * np.arange(len(y))).astype(np.float32).astype(float)
    raw = ("time_s,tip_acc_g\n" + "\n".join(f"{a:.7g},{b:.7g}" for a, b in zip(t, y)) + "\n").encode()
    ds = era.load(raw, name="usc.csv", kind="decay")
    assert ds.data.dt == pytest.approx(rec.step, rel=1e-6) and not any("resampled" in c
                                                                        for c in ds.source["conversions"])
    missing = raw.decode().splitlines()
    del missing[40000]
    with pytest.raises(era.DataError, match=r"usc.csv, line 40001: .*1 sample is missing"):
        era.load("\n".join(missing).encode(), name="usc.csv")


LADISK = SHARED_DATASETS / "ladisk_pyfrf_impact"


def test_a_hammer_test_says_which_channel_is_the_force(tmp_path):
    """Time, force, response: named (unit N or lbf, a name 'hammer'), or laid out as the ladisk files are (the
    short pulse among ringing channels), the force is proposed and the records read as input and output."""
    hit = np.load(require_shared(LADISK / "measurements_1.npy"))  # (3, 25600): time, force N, acc m/s²
    np.savetxt(tmp_path / "hit.txt", hit.T, fmt="%.9g")  # headerless columns
    for path in (LADISK / "measurements_1.npy", tmp_path / "hit.txt"):
        rec = era.io.read(path).records
        assert rec.force.tolist() == [True, False], path
        assert "proposed as the force (a short pulse" in rec.described[0]
        assert era.io.preview.preview(path).kind == "io"
    for header, force in (("t,Hammer,acc", [True, False]), ("t,F (lbf),acc", [True, False]),
                          ("t,a1,a2", [True, False])):  # names that say nothing: the values do
        raw = (header + "\n" + "\n".join(",".join(f"{v:.9g}" for v in row) for row in hit.T[:2000]) + "\n").encode()
        assert era.io.read(raw, name="named.csv").records.force.tolist() == force, header


def test_units_written_as_a_name_suffix_are_read_and_a_force_in_n_is_proposed():
    y, _ = hammer_decay(300, 2, DT)
    t = np.arange(len(y)) * DT
    raw = csv_bytes(t, y).replace(b"time_s,a1,a2,a3", b"time_s,tip_acc_g,force_N,acc_x")
    rec = era.io.read(raw, name="suffix.csv").records
    assert rec.outputs == ("tip_acc_g", "force_N", "acc_x") and rec.output_units == ("g", "N", "")
    assert rec.force.tolist() == [False, True, False]
