"""The import step's choices in the library: the start sample (pre-trigger), channels left out, which channels are
forces, NExT references named as read; and the preview that shows a file before anything is converted, even one
without a sampling interval (the real Carini rows file, MIT, read from ../shared)."""

import pickle
import sys
from pathlib import Path

import numpy as np
import pytest

import era
from era.io.preview import preview, thin

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import chain, hammer_decay, simulate  # noqa: E402
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

CARINI = SHARED_DATASETS / "carini_ambient_3ch" / "yk.txt"
DT = 0.01


def csv(y: np.ndarray, names, units, dt=DT) -> bytes:
    head = "time [s]," + ",".join(f"{n} [{u}]" for n, u in zip(names, units))
    rows = [f"{k * dt:.4f}," + ",".join(f"{v:.10e}" for v in r) for k, r in enumerate(y)]
    return ("\n".join([head] + rows) + "\n").encode()


def test_start_sample_cuts_the_pretrigger_and_keeps_time():
    y, f_modes = hammer_decay(1500, 2, DT)  # the hit is at sample 20
    raw = csv(y, ["a1", "a2", "a3"], ["g"] * 3)
    ds = era.load(raw, name="hit.csv", kind="decay", start_sample=21)
    assert ds.data.n_samples <= 1500 - 21  # the samples before the cut are gone for every builder
    assert "the first 21 samples of every record skipped (the records start at 0.21 s)" in ds.source["records"]
    model = era.identify(ds.data, rows=40, cols=40).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-3)
    with pytest.raises(era.DataError, match="fewer than 8 samples"):  # a cut that leaves too little is refused, not run
        era.load(raw, name="hit.csv", kind="decay", start_sample=1495)


def test_drop_removes_channels_with_their_units_and_names():
    y, _ = hammer_decay(600, 2, DT)
    ds = era.load(csv(y, ["a1", "broken", "a3"], ["g", "V", "g"]), name="x.csv", kind="decay", drop=["broken"])
    assert ds.data.outputs == ("a1", "a3") and ds.data.output_units == ("g", "g")
    assert ds.source["channels_read"] == ["a1", "broken", "a3"]
    assert "channels dropped: broken" in ds.source["records"]
    same = era.load(csv(y, ["a1", "broken", "a3"], ["g", "V", "g"]), name="x.csv", kind="decay", drop=[1])
    np.testing.assert_array_equal(same.data.markov, ds.data.markov)
    with pytest.raises(era.DataError, match="no channel 'nope'") as err:
        era.load(csv(y, ["a1", "a2", "a3"], ["g"] * 3), name="x.csv", drop=["nope"])
    assert err.value.option == "drop"
    with pytest.raises(era.DataError, match="leaves no channel") as err:
        era.load(csv(y, ["a1", "a2", "a3"], ["g"] * 3), name="x.csv", drop=[0, 1, 2])
    assert err.value.option == "drop"


def test_forces_say_which_channel_is_the_hammer_when_the_file_does_not():
    ad, bd, cd, dd, f_modes, _ = chain(DT)
    rng = np.random.default_rng(3)
    u = rng.standard_normal((3000, 3)) * np.array([0.0, 0.0, 1.0])  # a shaker on mass 3
    y = simulate(ad, bd, cd, dd, u)
    table = np.column_stack([u[:, 2], y])  # channel 0 is the force, in volts: nothing in the file says so
    raw = csv(table, ["ch0", "ch1", "ch2", "ch3"], ["V", "V", "V", "V"])
    with pytest.raises(era.DataError, match="forces=") as err:
        era.load(raw, name="shaker.csv", kind="io")
    assert err.value.option == "forces"
    ds = era.load(raw, name="shaker.csv", kind="io", forces=[0])
    assert ds.data.inputs == ("ch0",) and ds.data.outputs == ("ch1", "ch2", "ch3")
    assert "force channels: ch0" in ds.source["records"]
    model = era.identify(ds.data, rows=40, cols=40).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=2e-3)


def test_next_references_are_named_as_read_even_when_channels_are_dropped():
    rng = np.random.default_rng(0)
    y = rng.standard_normal((4000, 4))
    raw = csv(y, ["a", "b", "c", "d"], ["g"] * 4)
    ds = era.load(raw, name="amb.csv", kind="ambient", drop=[0], references=[2])
    assert ds.data.outputs == ("b", "c", "d") and ds.data.inputs == ("ref c",)
    with pytest.raises(era.DataError, match="'a' is dropped") as err:
        era.load(raw, name="amb.csv", kind="ambient", drop=[0], references=[0])
    assert err.value.option == "references"


def test_errors_keep_the_option_that_fixes_them_across_processes():
    err = era.DataError("no sampling interval in x.txt", option="dt")
    back = pickle.loads(pickle.dumps(err))
    assert type(back) is era.DataError and str(back) == str(err) and back.option == "dt"
    assert era.EraError("plain").option is None


def test_preview_of_the_carini_rows_file_without_a_sample_rate():
    require_shared(CARINI)
    pv = preview(CARINI)
    assert pv.step is None and pv.problem_option == "dt" and "give the sample rate" in pv.problem
    assert [c.name for c in pv.channels] == ["ch1", "ch2", "ch3"] and pv.n_samples == [32768]
    assert pv.traces.shape[0] == 3 and pv.x[0] == 0 and pv.x[-1] <= 32767  # against the sample number
    pv = preview(CARINI, dt=0.04, orientation="rows", start_sample=250, drop=[2])
    assert pv.problem is None and pv.step == pytest.approx(0.04) and pv.start == pytest.approx(10.0)
    assert [c.dropped for c in pv.channels] == [False, False, True] and pv.n_samples == [32768 - 250]
    assert pv.kind == "ambient"
    assert pv.traces.shape == (3, len(pv.x)) and len(pv.x) <= 2000  # every channel drawn, thinned
    with pytest.raises(era.DataError) as err:
        preview(CARINI, dt=0.04, orientation="columns")  # 32768 channels of 3 samples: refused, naming the fix
    assert "samples" in str(err.value)


def test_thin_keeps_every_peak():
    y = np.zeros((100_000, 2))
    y[54_321, 1] = 7.0
    idx = thin(y, 1000)
    assert len(idx) <= 1000 and 54_321 in idx and np.all(np.diff(idx) > 0)
    np.testing.assert_array_equal(thin(y[:500], 1000), np.arange(500))


def test_choices_that_do_not_fit_the_records_are_refused_by_option():
    y, _ = hammer_decay(100, 2, DT)
    raw = csv(y, ["a1", "a2", "a3"], ["g"] * 3)
    with pytest.raises(era.DataError, match="start_sample") as err:
        era.load(raw, name="x.csv", start_sample=95)
    assert err.value.option == "start_sample"
    with pytest.raises(era.DataError, match="channel 7 does not exist") as err:
        era.load(raw, name="x.csv", forces=[7])
    assert err.value.option == "forces"


LADISK = SHARED_DATASETS / "ladisk_pyfrf_impact"


def test_five_npy_hammer_records_with_a_time_row_become_one_input_output_dataset():
    """The real ladisk impacts (MIT, read from ../shared): five .npy files of rows [time, force N, acc m/s²]. The
    time row is found (25.6 kHz), the files match by position, and saying which channel is the force gives OKID's
    Markov parameters exactly as the direct call does (tests/markov/test_markov_okid.py checks their modes)."""
    paths = [require_shared(LADISK / f"measurements_{k}.npy") for k in range(1, 6)]
    pv = preview(paths)
    assert pv.problem is None and 1 / pv.step == pytest.approx(25600, rel=1e-9) and pv.n_records == 5
    # the layout says it: of the two channels after the time row, the first is a short pulse (the hammer)
    assert [c.force for c in pv.channels] == [True, False] and pv.kind == "io"
    assert "'measurements_1:2' proposed as the force" in pv.described[0]
    ds = era.load(paths, kind="io", forces=[0], n_observer=40, n_markov=400)
    recs = [np.load(p) for p in paths]
    direct = era.markov_from_io([r[1][:, None] for r in recs], [r[2][:, None] for r in recs], pv.step,
                                n_observer=40, n_markov=400)
    np.testing.assert_allclose(ds.data.markov, direct.markov, rtol=1e-9, atol=1e-12 * np.abs(direct.markov).max())
    assert "Δt = 0.0000390625 s (25600 Hz) from the first channel, a time axis" in ds.source["records"][0]


def test_complex_numbers_in_text_are_named_as_frfs_without_a_frequency_axis():
    """pyuff's README sample FRFs (MIT, ../shared): one complex number per line, no frequency axis."""
    path = require_shared(SHARED_DATASETS / "pyuff_samples" /
                          "meas_point_1.txt")
    with pytest.raises(era.DataError, match="complex numbers .*FRFs without a frequency axis.*UFF 58"):
        era.load(path)


def test_points_place_the_force_and_response_channels_of_time_records():
    """A shaker on mass 3 of the chain, the responses at masses 1-3: the person says where each channel is; the
    force's point is where the structure was driven (input_points), the responses' where it was measured
    (output_points), and the model's shape is at those points (a driving point at 3X)."""
    ad, bd, cd, dd, f_modes, _ = chain(DT)
    rng = np.random.default_rng(3)
    u = rng.standard_normal((3000, 3)) * np.array([0.0, 0.0, 1.0])
    y = simulate(ad, bd, cd, dd, u)
    raw = csv(np.column_stack([u[:, 2], y]), ["ch0", "ch1", "ch2", "ch3"], ["N", "V", "V", "V"])
    ds = era.load(raw, name="shaker.csv", kind="io", forces=[0], points={"0": "3X", 1: "1X", "ch2": "2X", 3: "3X"})
    assert ds.data.meta["input_points"] == ("3X",) and ds.data.meta["output_points"] == ("1X", "2X", "3X")
    assert "points: ch0 at 3X, ch1 at 1X, ch2 at 2X, ch3 at 3X" in ds.source["records"]
    model = era.identify(ds.data, rows=40, cols=40).realize(order=6)
    assert model.points == ("1X", "2X", "3X")
    # the driving point ties the input side to the outputs': the point shapes are the outputs' shapes
    assert np.all(np.diag(era.mac(model.point_shapes, model.shapes)) > 0.999)
    # a dropped channel takes its point with it; ambient records place their outputs only
    amb = era.load(raw, name="amb.csv", kind="ambient", drop=[0], points={1: "1X", 3: "3X"})
    assert amb.data.meta["output_points"] == ("1X", "", "3X") and "input_points" not in amb.data.meta
    with pytest.raises(era.DataError, match="no channel 'ch9'") as err:
        era.load(raw, name="x.csv", kind="io", forces=[0], points={"ch9": "1X"})
    assert err.value.option == "points"
