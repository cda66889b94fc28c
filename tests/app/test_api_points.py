"""Issue 26 through the API: the ModeLAB roving-hammer beam uploaded as its nine SignalCalc files and setup.csv
answers each mode's shape at the nine hit points (``points``, ``point_shapes_re/_im``), and the viewer draws them
on the line of points the setup gives; the UFF 55 export writes them at those nodes."""

from __future__ import annotations

import csv
import io

import numpy as np
import pyuff

from apiclient import client
from app import viewing
from shared_data import SHARED_DATASETS, require_shared

MODELAB = SHARED_DATASETS / "modelab_beam_frf" / "SignalCalc"


def test_the_modelab_beam_with_its_setup_answers_the_shape_at_nine_points(tmp_path):
    folder = require_shared(MODELAB)
    paths = [folder / f"ASCII0000{k}" / f"Hxysv0000{k}.txt" for k in range(1, 10)] + [folder / "setup.csv"]
    parts = [("file", (p.name, p.read_bytes(), "application/octet-stream")) for p in paths]
    with client(tmp_path, viewer=True) as c:
        recorded = []  # what the report's mode-shape recordings are drawn on
        record = c.app.state.viewer.record
        c.app.state.viewer.record = lambda g, f, psi, k: recorded.append((g, psi)) or record(g, f, psi, k)
        r = c.post("/api/datasets", files=parts, data={"band_hz": "65,1000"})
        assert r.status_code == 200, r.text
        ds = r.json()
        assert ds["n_inputs"] == 9 and ds["n_outputs"] == 1
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": ds["defaults"]["rows"],
                                          "cols": ds["defaults"]["cols"]}).json()
        stab = c.get(f"/api/analyses/{a['id']}/stabilization").json()
        order, chosen = stab["chosen_order"], stab["chosen_indices"]
        modes = c.get(f"/api/analyses/{a['id']}/modes", params={"order": order, "fit": "false"}).json()
        assert modes["points"] == [f"{k}X" for k in range(1, 10)] and modes["outputs"] == ["resp 0-Z"]
        shapes = np.array(modes["point_shapes_re"]) + 1j * np.array(modes["point_shapes_im"])
        assert shapes.shape == (modes["n_modes"], 9)
        first = shapes[chosen[0]]  # the first bending mode: both ends against the middle
        real = (first * np.exp(-1j * np.angle(first[np.argmax(abs(first))]))).real
        assert np.sign(real[0]) == np.sign(real[-1]) != np.sign(real[4])
        cache = c.app.state.cache  # the viewer's scene: nine points on the line of nodes, along x
        analysis = cache.analysis(a["id"])
        geometry, _, drawn, _ = viewing.modes_scene(analysis, cache.model(analysis, order))
        assert geometry.channel_nodes.tolist() == list(range(9)) and drawn.shape[0] == 9
        np.testing.assert_allclose(geometry.channel_directions, [[1, 0, 0]] * 9)
        # the report's UFF 55 holds the kept modes at the nine nodes, moving along x; its CSV the nine points
        token = c.post("/api/reports", json={"analysis_id": a["id"], "order": order, "modes": chosen}).json()["token"]
        report = c.get(f"/api/reports/{token}").json()
        assert report["geometry"]["channel_nodes"] == list(range(9))  # the report's animation: the nine points
        assert len(recorded) == 4 and all(g.channel_nodes.tolist() == list(range(9)) and psi.shape[0] == 9
                                          for g, psi in recorded)
        blob = c.get(f"/api/reports/{token}/modes.uff").content
        rows = list(csv.DictReader(io.StringIO(c.get(f"/api/reports/{token}/modes.csv").text)))
    path = tmp_path / "modes.uff"
    path.write_bytes(blob)
    sets = [d for d in pyuff.UFF(str(path)).read_sets() if d["type"] == 55]
    assert len(sets) == 4 and all(list(d["node_nums"]) == list(range(1, 10)) for d in sets)
    for d, k in zip(sets, chosen):
        np.testing.assert_allclose(d["r1"], shapes[k], atol=1e-6)
        assert np.allclose(d["r2"], 0) and np.allclose(d["r3"], 0)
    assert all(f"point {k}X re" in rows[0] for k in range(1, 10)) and "resp 0-Z re" in rows[0]


def test_without_a_geometry_the_viewer_draws_the_points_in_a_row():
    import era
    from app.cache import Analysis
    y = np.zeros((200, 1, 3))
    t = np.arange(200) * 0.01
    for k, phi in enumerate([0.3, 0.8, 1.0]):  # one sensor at point 3, hits at points 1, 2, 3: one mode
        y[:, 0, k] = phi * np.exp(-0.5 * t) * np.sin(2 * np.pi * 5 * t)
    data = era.ResponseData(markov=y, dt=0.01, meta={"output_points": ("3Z",), "input_points": ("1Z", "2Z", "3Z")})
    model = era.identify(data, rows=40, cols=40).model(2)
    geometry, _, drawn, _ = viewing.modes_scene(Analysis("a", "d", {}, data, None, "row"), model)
    assert geometry is None and model.points == ("1Z", "2Z", "3Z")
    np.testing.assert_allclose(drawn[:, 0].real, [0.3, 0.8, 1.0], atol=1e-6)
