"""CSV in (delimiters, decimal comma, units, several records) and era's own NPZ format both ways (the store's
old layout: tests/app/test_store.py)."""

import io
import sys
from pathlib import Path

import numpy as np
import pytest

import era

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import chain, hammer_decay, simulate  # noqa: E402

DT = 0.01


def free_decays(n=1500, hit_mass=2):
    """Acceleration of the chain after a hammer pulse on one mass, with 20 pre-trigger samples: (N, 3)."""
    return hammer_decay(n, hit_mass, DT)


def csv_text(t, y, header, delim=",", decimal="."):
    lines = [header]
    for ti, row in zip(t, y):
        cells = [f"{ti:.6f}"] + [f"{v:.12e}" for v in row]
        lines.append(delim.join(c.replace(".", decimal) for c in cells))
    return "\n".join(lines) + "\n"


def test_comma_csv_of_a_free_decay_with_units_in_the_header(tmp_path):
    y, f_modes = free_decays()
    t = np.arange(len(y)) * DT
    path = tmp_path / "decay.csv"
    path.write_text(csv_text(t, y, "time [s],a1 [m/s^2],a2 [m/s^2],a3 [m/s^2]"))
    ds = era.load(path)
    assert ds.source["format"] == "csv" and ds.source["kind"] == "decay"
    assert ds.data.outputs == ("a1", "a2", "a3") and ds.data.output_units == ("m/s^2",) * 3
    assert ds.data.dt == pytest.approx(DT)
    assert ds.data.meta["start_samples"] == [int(np.argmax(np.abs(y).max(axis=1))) + 1]
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)


def test_semicolon_decimal_comma_cp1252_units_row_and_a_test_column(tmp_path):
    y1, f_modes = free_decays(hit_mass=2)
    y2, _ = free_decays(hit_mass=0)
    t = np.arange(len(y1)) * DT
    lines = ["Zeit;Test;b1;b2;b3", "s;;m/s²;m/s²;m/s²"]
    for name, y in (("hit3", y1), ("hit1", y2)):
        for ti, row in zip(t, y):
            lines.append(";".join([f"{ti:.6f}".replace(".", ","), name] + [f"{v:.12e}".replace(".", ",") for v in row]))
    path = tmp_path / "tests.txt"
    path.write_bytes(("\r\n".join(lines) + "\r\n").encode("cp1252"))
    ds = era.load(path)
    assert "decimal comma" in ds.source["records"][0] and "2 records" in ds.source["records"][0]
    assert ds.data.markov.shape[2] == 2 and ds.data.output_units == ("m/s²",) * 3
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)


def test_several_files_are_several_records_and_a_force_column_means_okid(tmp_path):
    ad, bd, cd, dd, f_modes, _ = chain(DT)
    rng = np.random.default_rng(5)
    paths = []
    for k in range(2):
        force = rng.standard_normal((2000, 1))
        acc = simulate(ad, bd[:, 2:], cd, dd[:, 2:], force)
        t = np.arange(2000) * DT
        paths.append(tmp_path / f"run{k}.csv")
        paths[-1].write_text(csv_text(t, np.hstack([force, acc]), "t\thammer (N)\ta1 (g)\ta2 (g)\ta3 (g)", delim="\t"))
    ds = era.load(paths, n_observer=10)
    assert ds.source["kind"] == "io" and ds.data.inputs == ("hammer",) and ds.data.input_units == ("N",)
    assert len(ds.source["records"]) == 2
    model = era.identify(ds.data, rows=20, cols=20).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-6)


def test_csv_without_time_column_needs_dt():
    raw = b"s1 s2\n" + b"".join(f"{np.sin(k / 3):.6f} {np.cos(k / 5):.6f}\n".encode() for k in range(400))
    with pytest.raises(era.DataError, match="no time column.*dt"):
        era.load(raw, name="x.dat")
    ds = era.load(raw, name="x.dat", dt=0.5, kind="ambient", n_lags=50)
    assert ds.data.dt == 0.5 and ds.data.outputs == ("s1", "s2")


def test_npz_round_trip_with_labels_and_geometry(tmp_path):
    data = era.ResponseData(np.random.default_rng(0).standard_normal((50, 2, 1)), 0.02, outputs=["a", "b"],
                            inputs=["hammer"], output_units=["m/s^2", "m/s^2"], input_units=["N"])
    geom = era.Geometry([4, 7], [[0, 0, 0], [1, 0, 0]], [[0, 1]], [0, 1], [[0, 0, 1], [0, 0, -1]], units="mm")
    buf = io.BytesIO()
    era.save_npz(buf, data, geom)
    ds = era.load(buf.getvalue(), name="export.npz")
    assert ds.source["format"] == "npz"
    np.testing.assert_array_equal(ds.data.markov, data.markov)
    assert ds.data.outputs == ("a", "b") and ds.data.input_units == ("N",) and ds.data.dt == 0.02
    assert ds.geometry.units == "mm" and ds.geometry.node_ids.tolist() == [4, 7]
    np.testing.assert_array_equal(ds.geometry.channel_directions, geom.channel_directions)
    era.save_npz(tmp_path / "a.npz", data)
    assert era.load(tmp_path / "a.npz").geometry is None


def test_npz_keeps_the_name_and_the_input_points_and_units_not_given_stay_none(tmp_path):
    data = era.ResponseData(np.random.default_rng(1).standard_normal((40, 3, 2)), 0.05,
                            meta={"input_locations": ((3, 2), (7, 5))})  # hammer hits at grid joints (x_ft, y_ft)
    era.save_npz(tmp_path / "hits.npz", data, name="hammer test 3")
    ds = era.load(tmp_path / "hits.npz")
    assert ds.source["name"] == "hammer test 3"
    assert ds.data.meta["input_locations"] == ((3.0, 2.0), (7.0, 5.0))
    assert ds.data.output_units is None and ds.data.input_units is None and ds.data.outputs == ("y1", "y2", "y3")
    assert ds.data.markov.tobytes() == data.markov.tobytes()
    era.save_npz(tmp_path / "unnamed.npz", data)
    assert era.load(tmp_path / "unnamed.npz").source["name"] is None
    one_point = era.ResponseData(data.markov, 0.05, meta={"input_locations": [(3.0, 2.0)]})
    with pytest.raises(era.DataError, match=r"input_locations.*shape \(1, 2\); give one point per input"):
        era.save_npz(io.BytesIO(), one_point)
    buf = io.BytesIO()
    np.savez(buf, markov=data.markov, dt=np.array(0.05), input_locations=np.zeros((3, 2)))
    with pytest.raises(era.DataError, match=r"odd.npz: `input_locations` is float64 of shape \(3, 2\); expected"):
        era.load(buf.getvalue(), name="odd.npz")


def test_npz_keeps_a_frames_input_points_as_node_names(tmp_path):
    """An era.Frame's impulse points are (node id, direction): node ids such as "E" or "12" stay names."""
    data = era.ResponseData(np.zeros((40, 2, 2)), 0.01, meta={"input_locations": (("E", "x"), ("12", "z"))})
    era.save_npz(tmp_path / "portal.npz", data)
    assert era.load(tmp_path / "portal.npz").data.meta["input_locations"] == (("E", "x"), ("12", "z"))


def test_times_printed_with_few_decimals_are_even_but_a_dropped_sample_is_not():
    t = np.arange(2000) / 25600  # 39.0625 µs, printed as 0.000039, 0.000078, 0.000117, ...
    y = np.sin(2 * np.pi * 1000 * t) * np.exp(-30 * t)
    text = "time,a\n" + "".join(f"{a:.6f},{b:.6f}\n" for a, b in zip(t, y))
    ds = era.load(text.encode(), name="logger.csv", kind="decay")
    assert ds.data.dt == pytest.approx(1 / 25600, rel=1e-5)
    assert era.identify(ds.data, 20, 20).realize(order=2).frequency_hz[0] == pytest.approx(1000, rel=1e-5)
    lines = text.splitlines()
    del lines[701]  # sample 700 lost
    with pytest.raises(era.DataError, match="logger.csv, line 702: the time step is 7.8e-05 s where the typical"):
        era.load("\n".join(lines).encode(), name="logger.csv", kind="decay")
