"""LabVIEW LVM in: the real USC cantilever file (CC BY-SA, read from ../shared, never copied) reaches its published
frequencies; files written here in each LVM layout (X columns none/one/multi, segments, comma separators) read the
chain's modes; malformed ones are refused naming the line."""

import sys
from pathlib import Path

import numpy as np
import pytest

import era

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import hammer_decay  # noqa: E402
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

USC = SHARED_DATASETS / "usc_cantilever_free_decay" / \
    "timeseries_data.lvm"
DT = 0.01


def decays(n=1500, hits=(2,)):
    """Acceleration of the chain after a hammer pulse on each mass of ``hits``: list of (N, 3), and the modes."""
    runs = [hammer_decay(n, hit, DT) for hit in hits]
    return [y for y, _ in runs], runs[0][1]


def lvm_text(segments, *, x_columns="One", sep="\t", decimal=".", names=("a1", "a2", "a3"), unit="m/s^2",
             delta_x=DT, starts=None, header_per_segment=True):
    """An LVM file as LabVIEW writes it: file header, then per segment a header, the names line and the data."""
    dec = (lambda v: v.replace(".", ",")) if decimal == "," else (lambda v: v)
    lines = ["LabVIEW Measurement" + sep, f"Writer_Version{sep}2", f"Reader_Version{sep}2",
             f"Separator{sep}{'Tab' if sep == chr(9) else 'Comma'}", f"Decimal_Separator{sep}{decimal}",
             f"Multi_Headings{sep}Yes", f"X_Columns{sep}{x_columns}", f"Time_Pref{sep}Relative",
             f"Operator{sep}test", "***End_of_Header***" + sep, ""]
    c = len(names)
    for s, y in enumerate(segments):
        t0 = starts[s] if starts else 0.0
        gap = [""] if x_columns == "Multi" else []
        per = lambda v: sep.join(sum(([dec(v)] + gap for _ in range(c)), [])[:None if not gap else -1])  # noqa: E731
        if header_per_segment or s == 0:
            lines += [f"Channels{sep}{c}", f"Samples{sep}{per(str(len(y)))}", f"Y_Unit_Label{sep}{per(unit)}",
                      f"X_Dimension{sep}{per('Time')}", f"X0{sep}{per(f'{t0:.16E}')}",
                      f"Delta_X{sep}{per(f'{delta_x:.6f}')}", "***End_of_Header***" + sep * 2]
            if x_columns == "Multi":
                head = sep.join(f"X_Value{sep}{nm}" for nm in names)
            else:
                head = sep.join(["X_Value"] + list(names))
            lines.append(head + sep + "Comment")
        t = t0 + DT * np.arange(len(y))
        for ti, row in zip(t, y):
            vals = [dec(f"{v:.9e}") for v in row]
            tx = dec(f"{ti:.6f}")
            if x_columns == "One":
                cells = [tx] + vals
            elif x_columns == "Multi":
                cells = sum(([tx, v] for v in vals), [])
            else:
                cells = [""] + vals
            lines.append(sep.join(cells))
        lines.append("")
    return "\r\n".join(lines) + "\r\n"


def test_the_usc_cantilever_lvm_reaches_the_published_frequencies():
    require_shared(USC)
    ds = era.load(USC, n_samples=14000)  # the decay from just after the impact, 8.5 s
    assert ds.source["format"] == "lvm" and ds.source["kind"] == "decay"
    assert ds.data.outputs == ("Acceleration",) and ds.data.output_units == ("g",)
    # Δt from the X_Value column (49.599395 s after 81919 steps: 51.2 kHz / 31), not the header's rounded 0.000605
    assert ds.data.dt == pytest.approx(49.599395 / 81919, rel=1e-7)
    assert "1 record of 81920 samples × 1 channel," in ds.source["records"][0]
    ident = era.identify(ds.data, rows=200, cols=3500)
    stab = era.stabilization(ident, orders=range(2, 61, 2))
    persistent = [m for m in stab.modes if len(m.orders) >= 10 and m.emac > 0.98]
    for published, tol in ((6.62, 0.003), (41.4, 0.003), (117.5, 0.006)):  # upstream README: read off an FFT
        best = min(persistent, key=lambda m: abs(m.frequency_hz - published))
        assert abs(best.frequency_hz - published) / published < tol, (published, best.frequency_hz)
        assert 0 < best.damping_ratio < 0.01


@pytest.mark.parametrize("x_columns", ["One", "Multi", "No"])
def test_each_x_column_layout_reads_the_chain(tmp_path, x_columns):
    (y,), f_modes = decays()
    (tmp_path / "decay.lvm").write_text(lvm_text([y], x_columns=x_columns))
    ds = era.load(tmp_path / "decay.lvm")
    assert ds.source["kind"] == "decay" and ds.data.outputs == ("a1", "a2", "a3")
    assert ds.data.output_units == ("m/s^2",) * 3 and ds.data.dt == pytest.approx(DT, rel=1e-9)
    expected = "X_Value column" if x_columns != "No" else "Delta_X"
    assert expected in ds.source["records"][0]
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)


def test_segments_that_start_again_are_records_and_continued_ones_are_joined(tmp_path):
    (y1, y2), f_modes = decays(hits=(2, 0))
    (tmp_path / "two_hits.lvm").write_text(lvm_text([y1, y2], sep=",", decimal="."))
    ds = era.load(tmp_path / "two_hits.lvm")
    assert ds.data.markov.shape[2] == 2 and "2 segments as 2 records" in ds.source["records"][0]
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)
    # one acquisition written in two calls, the second header without its own names line
    text = lvm_text([y1[:700], y1[700:]], starts=[0.0, 700 * DT], header_per_segment=False)
    ds = era.load(text.encode(), name="chunks.lvm")
    assert "2 segments as 1 record of 1500 samples" in ds.source["records"][0]
    assert ds.data.markov.shape[2] == 1


def test_decimal_comma_and_no_time_at_all_needs_dt(tmp_path):
    (y,), f_modes = decays()
    text = lvm_text([y], decimal=",", x_columns="No")
    ds = era.load(text.encode(), name="komma.lvm")
    assert ds.data.dt == pytest.approx(DT)
    bare = "\r\n".join(ln for ln in text.split("\r\n") if not ln.startswith(("Delta_X", "X0")))
    with pytest.raises(era.DataError, match=r"no sampling interval in bare.lvm: give the sample rate \(dt=\.\.\.\)"):
        era.load(bare.encode(), name="bare.lvm")
    ds = era.load(bare.encode(), name="bare.lvm", dt=DT)
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)


def test_content_sniffing_finds_an_lvm_without_its_extension():
    (y,), _ = decays(n=300)
    ds = era.load(lvm_text([y]).encode("utf-8-sig"), name="upload.txt")
    assert ds.source["format"] == "lvm"


def _lines(text):
    return text.split("\r\n")


def test_hostile_lvm_files_are_refused_naming_the_place(tmp_path):
    (y,), _ = decays(n=400)
    good = _lines(lvm_text([y]))
    data0 = next(k for k, ln in enumerate(good) if ln.startswith("X_Value")) + 1  # index of the first data line
    cases = {
        "cut.lvm": (good[:data0 + 200] + [good[data0 + 200][:12]], r"cut.lvm, line \d+: no value in column 3"),
        "cut_line.lvm": (good[:data0 + 123], r"cut_line.lvm, segment 1 .*promises 400 samples per write but the "
                                             r"segment holds 123 lines: the file is cut short"),
        "no_end.lvm": (good[:6], r"no_end.lvm: the LVM file header has no \*\*\*End_of_Header\*\*\* line"),
        "liar.lvm": ([ln.replace("Samples\t400", "Samples\t999999999999") for ln in good],
                     r"liar.lvm, segment 1 .*promises 999999999999 samples"),
        "delta.lvm": ([ln.replace("0.010000", "0.020000") if ln.startswith("Delta_X") else ln for ln in good],
                      r"delta.lvm, segment 1 .*X_Value column steps 0.01 s but the header's Delta_X is 0.02 s"),
        "word.lvm": ([ln.replace("0.010000", "fast") if ln.startswith("Delta_X") else ln for ln in good],
                     r"word.lvm, segment 1 .*Delta_X is 'fast', not a number"),
        "gap.lvm": (good[:data0 + 100] + good[data0 + 101:],
                    rf"gap.lvm, segment 1 .*X_Value column, line {data0 + 101}: the time step is 0.02 s where the "
                    r"typical step is 0.01"),
        "nan.lvm": (good[:data0 + 50] + ["0.500000\tNaN\t1\t1"] + good[data0 + 51:], r"NaN or infinite value.*line "),
        "spectrum.lvm": ([ln.replace("X_Dimension\tTime", "X_Dimension\tFrequency") for ln in good],
                         r"X_Dimension is 'Frequency'; ERA reads time records"),
    }
    for name, (lines, message) in cases.items():
        (tmp_path / name).write_text("\r\n".join(lines))
        with pytest.raises(era.DataError, match=message):
            era.load(tmp_path / name)
    garbage = b"LabVIEW Measurement\t\r\n" + np.random.default_rng(0).integers(0, 256, 4000, np.uint8).tobytes()
    with pytest.raises(era.DataError, match="junk.lvm"):
        era.load(garbage, name="junk.lvm")
    (y2,), _ = decays(n=400, hits=(1,))
    other = lvm_text([y, y2]).replace("X_Value\ta1\ta2\ta3\tComment", "X_Value\tb1\tb2\tb3\tComment", 1)
    with pytest.raises(era.DataError, match=r"segment 2 .*channels \['a1', 'a2', 'a3'\] differ"):
        era.load(other.encode(), name="other.lvm")
