"""Issue 26: an HDF5 file says where its channels are (attribute ``points`` on the data, one label per channel):
the shaker's point is where the chain was driven (mass 3, not measured), the accelerometers' where it was measured
(masses 1 and 2), and the model's shape is known at all three masses; the import step's points replace the file's."""

import io
import sys
from pathlib import Path

import h5py
import numpy as np

import era

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import chain, simulate  # noqa: E402

DT = 0.01


def shaker_h5(points) -> bytes:
    ad, bd, cd, dd, _, _ = chain(DT)
    rng = np.random.default_rng(7)
    u = rng.standard_normal((3000, 3)) * np.array([1.0, 0.0, 1.0])  # shakers on masses 1 and 3
    y = simulate(ad, bd, cd, dd, u)
    buf = io.BytesIO()
    with h5py.File(buf, "w") as f:
        f["test"] = np.column_stack([u[:, 0], u[:, 2], y[:, 0], y[:, 1]])
        f["test"].attrs["channels"] = ["f1", "f3", "a1", "a2"]
        f["test"].attrs["units"] = ["N", "N", "m/s^2", "m/s^2"]
        f["test"].attrs["points"] = points
        f.attrs["fs"] = 1 / DT
    return buf.getvalue()


def test_the_files_points_place_forces_and_responses():
    ds = era.load(shaker_h5(["1X", "3X", "1X", "2X"]), name="shakers.h5", kind="io")
    assert ds.data.inputs == ("f1", "f3") and ds.data.outputs == ("a1", "a2")
    assert ds.data.meta["input_points"] == ("1X", "3X") and ds.data.meta["output_points"] == ("1X", "2X")
    model = era.identify(ds.data, rows=40, cols=40).realize(order=6)
    assert model.points == ("1X", "2X", "3X")
    truth = np.linalg.eigh(1e4 * np.array([[2, -1, 0], [-1, 2, -1], [0, -1, 1.0]]))[1]
    order = np.argsort(model.frequency_hz)
    assert np.all(np.diag(era.mac(model.point_shapes[:, order], truth)) > 0.99)


def test_the_persons_points_replace_the_files_and_a_dropped_channel_takes_its_point_along():
    raw = shaker_h5(["1X", "3X", "1X", "2X"])
    ds = era.load(raw, name="shakers.h5", kind="io", points={2: "7Z", 3: "8Z"})
    assert ds.data.meta["output_points"] == ("7Z", "8Z") and ds.data.meta["input_points"] == ("", "")
    kept = era.load(raw, name="shakers.h5", kind="io", drop=[3])
    assert kept.data.meta["output_points"] == ("1X",) and kept.data.meta["input_points"] == ("1X", "3X")
    unknown = era.load(shaker_h5(["", "", "", ""]), name="shakers.h5", kind="io")
    assert "output_points" not in unknown.data.meta
