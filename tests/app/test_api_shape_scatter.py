"""The shape's scatter from the data (expected 1 - MAC, era Identification.shape_scatter) in the modes payload
when asked for, in the report's modes and in its CSV, beside the ± σ of frequency and damping."""

from __future__ import annotations

import csv
import io

import numpy as np

from app import limits, payloads, reporting
from app.config import Settings
from app.examples import catalogue

from apiclient import client


def test_modes_carry_the_shape_scatter_when_asked_and_the_csv_has_its_column(tmp_path):
    data, _ = catalogue()["grid"].build()
    with client(tmp_path) as c:
        ds = c.post("/api/examples/grid").json()
        params = {"rows": ds["defaults"]["rows"], "cols": ds["defaults"]["cols"]}
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], **params}).json()
        plain = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 20, "fit": False}).json()
        assert plain["shape_scatter"] is None  # the slider's payload does not pay for it
        step = c.get(f"/api/analyses/{a['id']}/step", params={"order": 20}).json()
        assert step["modes"]["shape_scatter"] is None
        m = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 20, "fit": False, "scatter": True}).json()
    ident = limits.identify_within_limits(data, params, Settings())
    expected = ident.shape_scatter(20)
    scatter = np.array(m["shape_scatter"], dtype=float)
    assert scatter.shape == (m["n_modes"],) and np.all((scatter >= 0) & (scatter < 1))
    np.testing.assert_allclose(scatter, expected, rtol=1e-6, atol=1e-12)
    # well-determined modes (strong, coherent) have a small scatter, and some noise mode a larger one
    strong = (np.array(m["emac_mpc"]) > 0.99) & (np.array(m["contribution_relative"]) > 0.05)
    assert strong.any() and scatter[strong].max() < 0.01 and scatter.max() > 10 * scatter[strong].max()

    model = ident.model(20)
    doc = {"modes": payloads.modes_json(model, data, False, expected), "kept": [0, 1]}
    rows = list(csv.DictReader(io.StringIO(reporting.modes_csv(doc))))
    assert len(rows) == model.n_modes
    np.testing.assert_allclose([float(r["shape_scatter"]) for r in rows], expected)
    old = {"modes": payloads.modes_json(model, data, False), "kept": []}  # a report frozen before the scatter
    assert all(r["shape_scatter"] == "" for r in csv.DictReader(io.StringIO(reporting.modes_csv(old))))
