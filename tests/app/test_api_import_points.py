"""Issue 26 in the import step: the "point" of each time channel. Two shakers drive a three-mass chain at masses 1
and 3 while accelerometers measure masses 1 and 2; the person types where each channel is (1X, 3X for the forces;
1X, 2X for the responses), and the model's shape is then known at all three masses: mass 3 was driven, not
measured, and its value comes from the input side through the driving point 1X (reciprocity, era.core.points)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import era

from apiclient import client

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import chain, simulate  # noqa: E402

DT = 0.01


def shaker_csv() -> bytes:
    ad, bd, cd, dd, _, _ = chain(DT)
    rng = np.random.default_rng(5)
    u = rng.standard_normal((3000, 3)) * np.array([1.0, 0.0, 1.0])  # shakers on masses 1 and 3
    y = simulate(ad, bd, cd, dd, u)
    table = np.column_stack([u[:, 0], u[:, 2], y[:, 0], y[:, 1]])
    head = "time [s],f1 [N],f3 [N],a1 [V],a2 [V]"
    rows = [f"{k * DT:.4f}," + ",".join(f"{v:.10e}" for v in r) for k, r in enumerate(table)]
    return ("\n".join([head] + rows) + "\n").encode()


def test_points_typed_in_the_import_step_give_the_shape_at_a_driven_point_not_measured(tmp_path):
    k = 1e4 * np.array([[2, -1, 0], [-1, 2, -1], [0, -1, 1.0]])
    truth = np.linalg.eigh(k)[1]  # unit masses, proportional damping: the real mode shapes, ascending
    with client(tmp_path) as c:
        up = c.post("/api/imports", files=[("file", ("shakers.csv", shaker_csv(), "text/csv"))]).json()
        assert [ch["force"] for ch in up["preview"]["channels"]] == [True, True, False, False]
        bad = c.post(f"/api/imports/{up['id']}/dataset", json={"kind": "io", "points": {"7": "4X"}})
        assert bad.status_code == 422 and bad.json()["option"] == "points"
        assert "the channels' points" in bad.json()["error"] and "`points`" not in bad.json()["error"]
        ds = c.post(f"/api/imports/{up['id']}/dataset",
                    json={"kind": "io", "points": {"0": "1X", "1": "3X", "2": "1X", "3": "2X"}})
        assert ds.status_code == 200, ds.text
        ds = ds.json()
        assert ds["source"]["options"]["points"] == {"0": "1X", "1": "3X", "2": "1X", "3": "2X"}
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 40, "cols": 40}).json()
        m = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 6, "fit": False}).json()
    assert m["points"] == ["1X", "2X", "3X"]
    shapes = (np.array(m["point_shapes_re"]) + 1j * np.array(m["point_shapes_im"])).T  # (points, modes)
    order = np.argsort(m["frequency_hz"])
    macs = np.diag(era.mac(shapes[:, order], truth))
    print("MAC at masses 1-3 (mass 3 driven, not measured):", macs.round(5))
    assert np.all(macs > 0.99)
