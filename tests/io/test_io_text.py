"""Headerless text in: channels in rows or columns (from the shape, or as said), a time column found by its even
increase, and a sampling interval asked for by name when the file has none. The real Carini ambient record (3 rows
of 32768 samples at 25 Hz, MIT, read from ../shared) gives its PSD peaks."""

import sys
from pathlib import Path

import numpy as np
import pytest

import era
import uff_files as U

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import hammer_decay  # noqa: E402
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

CARINI = SHARED_DATASETS / "carini_ambient_3ch" / "yk.txt"
DT = 0.01


def decay(n=1500):
    return hammer_decay(n, 2, DT)


def savetxt(path, a, **kw):
    np.savetxt(path, a, **kw)
    return path


def test_the_carini_rows_file_needs_its_rate_and_gives_the_psd_peaks():
    require_shared(CARINI)
    with pytest.raises(era.DataError, match=r"^no sampling interval in yk.txt: give the sample rate \(dt=\.\.\.\)"):
        era.load(CARINI)
    ds = era.load(CARINI, dt=1 / 25, orientation="rows", kind="ambient", n_lags=500)
    assert ds.data.markov.shape == (500, 3, 3) and ds.data.dt == 0.04
    assert ds.data.outputs == ("ch1", "ch2", "ch3") and ds.data.output_units is None
    assert "3 channels in rows (as given) × 32768 samples" in ds.source["records"][0]
    model = era.identify(ds.data, rows=100, cols=60).realize(order=20)
    strong = model.select(min_contribution=0.2)
    for peak in (2.31, 4.96, 7.37):  # PSD peaks (dataset README)
        assert np.min(np.abs(strong.frequency_hz - peak)) < 0.01 * peak, (peak, strong.frequency_hz)
    auto = era.load(CARINI, dt=1 / 25, kind="ambient", n_lags=500)  # 3 × 32768: rows, from the shape
    assert "in rows (from the shape)" in auto.source["records"][0]
    np.testing.assert_array_equal(auto.data.markov, ds.data.markov)


@pytest.mark.parametrize("orientation", ["columns", "rows"])
def test_a_bare_matrix_either_way_round_gives_the_chain(tmp_path, orientation):
    y, f_modes = decay()
    path = savetxt(tmp_path / "y.txt", y if orientation == "columns" else y.T, fmt="%.12e")
    ds = era.load(path, dt=DT)
    assert ds.data.outputs == ("ch1", "ch2", "ch3") and ds.source["kind"] == "decay"
    assert f"3 channels in {orientation} (from the shape)" in ds.source["records"][0]
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)
    other = "rows" if orientation == "columns" else "columns"
    with pytest.raises(era.DataError, match="Record 1 has 3 samples"):  # said the wrong way round: 1500 channels
        era.load(path, dt=DT, orientation=other)


def test_a_time_column_or_row_is_found_and_must_be_even(tmp_path):
    y, f_modes = decay()
    t = np.arange(len(y)) * DT
    table = np.column_stack([t, y])
    ds = era.load(savetxt(tmp_path / "ty.dat", table, fmt="%.6f", delimiter=","))
    assert ds.data.dt == pytest.approx(DT) and "time in the first column" in ds.source["records"][0]
    ds = era.load(savetxt(tmp_path / "rows.txt", table.T, fmt="%.8g", delimiter="\t"))
    assert ds.data.dt == pytest.approx(DT) and "time in the first row" in ds.source["records"][0]
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)
    t[800:] += 0.004  # a late sample: not even
    with pytest.raises(era.DataError, match=r"uneven.txt, column 1 \(time\), line 801: the time step is 0.014 s"):
        era.load(savetxt(tmp_path / "uneven.txt", np.column_stack([t, y]), fmt="%.6f"))


def test_orientation_is_refused_where_it_means_nothing(tmp_path):
    y, _ = decay(200)
    with pytest.raises(era.DataError, match="`orientation` must be 'rows'"):
        era.load(savetxt(tmp_path / "y.txt", y), dt=DT, orientation="sideways")
    (tmp_path / "h.csv").write_text("a,b\n" + "".join(f"{k},{k * k}\n" for k in range(50)))
    with pytest.raises(era.DataError, match="h.csv: `orientation` is for text without a header"):
        era.load(tmp_path / "h.csv", dt=DT, orientation="rows")
    U.write(tmp_path / "one.uff", [U.record58(y[:, 0], 0.0, DT, (1, 3))])
    with pytest.raises(era.DataError, match=r"one.uff: `orientation` applies to CSV/TEXT/.* files, not to UFF"):
        era.load(tmp_path / "one.uff", orientation="rows")


def test_hostile_matrices_name_the_line(tmp_path):
    y, _ = decay(300)
    good = [" ".join(f"{v:.6e}" for v in row) for row in y]
    cases = {
        "ragged.txt": (good[:40] + [good[40].rsplit(" ", 1)[0]] + good[41:], r"ragged.txt, line 41: 2 values where "
                                                                           r"line 1 has 3"),
        "word.txt": (good[:60] + ["1.0 abc 2.0"] + good[61:], r"word.txt, line 61, value 2: 'abc' is not a number"),
        "nan.txt": (good[:70] + ["1.0 nan 2.0"] + good[71:], r"nan.txt, line 71, value 2: NaN or infinite"),
        "cut.txt": (good[:150] + [good[150][:15]], r"cut.txt, line 151: 2 values where line 1 has 3"),
    }
    for name, (lines, message) in cases.items():
        (tmp_path / name).write_text("\n".join(lines) + "\n")
        with pytest.raises(era.DataError, match=message):
            era.load(tmp_path / name, dt=DT)
