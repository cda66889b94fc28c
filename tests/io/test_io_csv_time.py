"""CSV time columns by name in the spellings and units acquisition software writes, channel units from the header,
and the rule that a record is evenly sampled or refused, however its times are printed."""

import sys
from pathlib import Path

import numpy as np
import pytest

import era

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import hammer_decay  # noqa: E402

DT = 0.01


def decay(n=1500):
    return hammer_decay(n, 2, DT)


def csv_bytes(header, t, y, fmt="{:.6f}", time_at=0):
    lines = [header]
    for ti, row in zip(t, y):
        cells = [f"{v:.10e}" for v in row]
        cells.insert(time_at, fmt.format(float(ti)))
        lines.append(",".join(cells))
    return ("\n".join(lines) + "\n").encode()


@pytest.mark.parametrize("time_name, scale", [("time", 1), ("t", 1), ("time_s", 1), ("Time (s)", 1), ("t [s]", 1),
                                              ("Zeit", 1), ("TIME", 1), ("time_ms", 1e3), ("Time (ms)", 1e3),
                                              ("t [ms]", 1e3), ("Zeit [µs]", 1e6)])
def test_time_columns_in_common_spellings_and_units(time_name, scale):
    y, f_modes = decay()
    t = np.arange(len(y)) * DT * scale
    raw = csv_bytes(f"{time_name},acc 1 (g),acc 2 [m/s^2],acc3", t, y, fmt="{:.4f}")
    ds = era.load(raw, name="run.csv")
    assert ds.data.dt == pytest.approx(DT, rel=1e-9)
    assert ds.data.outputs == ("acc 1", "acc 2", "acc3") and ds.data.output_units == ("g", "m/s^2", "")
    assert repr(time_name.split(" ")[0].split("_")[0]) in ds.source["records"][0] or "time column" in \
        ds.source["records"][0]
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)


def test_the_time_column_need_not_be_first():
    y, _ = decay(400)
    t = np.arange(len(y)) * DT
    ds = era.load(csv_bytes("a1,Time (s),a2,a3", t, y, time_at=1), name="middle.csv")
    assert ds.data.outputs == ("a1", "a2", "a3") and ds.data.dt == pytest.approx(DT)


def test_times_printed_short_are_still_checked_for_evenness():
    """The issue's silent error: a first time printed as '0' made the whole column look coarse, and an uneven
    column was analysed at its mean step."""
    y, _ = decay(600)
    t = np.arange(len(y)) * DT
    t[300:] += 0.003  # one late sample, then the clock keeps the delay
    raw = csv_bytes("time,a1,a2,a3", t, y, fmt="{:g}")  # 0, 0.01, ..., 3.003: as short as %g prints them
    with pytest.raises(era.DataError, match=r"late.csv, line 302: the time step is 0.013 s where the typical step is "
                                            r"0.01 s"):
        era.load(raw, name="late.csv")
    jitter = np.arange(len(y)) / 25600
    jitter[100] += 5e-6  # 5 µs off, printed to 1 µs
    with pytest.raises(era.DataError, match=r"jitter.csv, line 10[12]: the time step is"):
        era.load(csv_bytes("t,a1,a2,a3", jitter, y), name="jitter.csv")
    repeat = np.arange(len(y)) * DT
    repeat[200] = repeat[199]
    with pytest.raises(era.DataError, match=r"repeat.csv, line 202: the time goes from 1.99 to 1.99 s \(a repeat"):
        era.load(csv_bytes("t,a1,a2,a3", repeat, y, fmt="{:g}"), name="repeat.csv")
    rate = np.cumsum(np.r_[0, np.full(len(y) - 1, DT)])
    rate[300:] = rate[300] + (np.arange(len(y) - 300)) * DT * 1.0002  # the rate changes by 0.02 %
    with pytest.raises(era.DataError, match=r"rate.csv, line \d+: the samples drift .* the sampling rate changes"):
        era.load(csv_bytes("t,a1,a2,a3", rate, y, fmt="{:.5f}"), name="rate.csv")  # steps within a digit


def test_even_times_in_any_printing_are_accepted():
    y, _ = decay(600)
    k = np.arange(len(y))
    for fmt, t in (("{:g}", k * DT), ("{!r}", k * DT), ("{!r}", np.cumsum(np.full(len(y), DT)) - DT),
                   ("{:.6f}", k / 25600), ("{:.3e}", k * 1e-4), ("{:.7g}", 1000.0 + k * DT)):
        ds = era.load(csv_bytes("t,a1,a2,a3", t, y, fmt=fmt), name="even.csv")
        assert ds.data.dt == pytest.approx(t[1] - t[0], rel=1e-5), fmt


def test_a_time_column_in_an_unknown_unit_is_refused():
    y, _ = decay(100)
    with pytest.raises(era.DataError, match=r"hours.csv: the time column 'Time' is in 'h'"):
        era.load(csv_bytes("Time (h),a1,a2,a3", np.arange(100) / 3600, y, fmt="{:.9f}"), name="hours.csv")
