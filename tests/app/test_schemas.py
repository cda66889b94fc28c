"""The JSON contract (app/schemas/): every answer validates against the model its route declares, carries
exactly its fields (nothing the builders add is silently dropped), and /openapi.json shows the models."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from pydantic import TypeAdapter

import era
import era.examples.paper_cases
from apiclient import client
from app import choosing, payloads, reporting, schemas
from app.cache import Analysis
from app.config import Settings
from era.core.stabilization import COHERENT_MIN


def _fields(x):
    """The dict keys of a JSON value at every depth (lists of plain values collapse to [])."""
    if isinstance(x, dict):
        return {k: _fields(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_fields(v) for v in x if isinstance(v, (dict, list))]
    return None


def exact(kind, value):
    """Validate ``value`` against ``kind`` (a schema or a type such as list[schemas.Example]) and check that it
    has no field the schema lacks (those would be dropped from the answer, or sent unvalidated by /step)."""
    adapter = TypeAdapter(kind)
    parsed = adapter.validate_python(value)
    assert _fields(adapter.dump_python(parsed, mode="json", exclude_unset=True)) == _fields(value)
    return parsed


def ok(response, kind):
    assert response.status_code == 200, response.text
    return exact(kind, response.json())


def _flow(c, example: str, thresholds: dict):
    """An example through every analysis route; returns the (dataset, analysis, stabilization) answers."""
    ok(c.get("/api/examples"), list[schemas.Example])
    key = "schema-flow-" + example
    ds = ok(c.post(f"/api/examples/{example}", headers={"X-Progress-Key": key}), schemas.Dataset)
    ok(c.get(f"/api/jobs/{key}"), schemas.Progress)
    assert ok(c.get(f"/api/datasets/{ds.id}"), schemas.Dataset) == ds
    rec = ok(c.get(f"/api/datasets/{ds.id}/records", params={"input": ds.n_inputs - 1}), schemas.Records)
    assert len(rec.series) == ds.n_outputs and rec.input == ds.inputs[-1]
    ok(c.get(f"/api/datasets/{ds.id}/spectrum"), schemas.Spectrum)
    body = {"dataset_id": ds.id, "rows": ds.defaults.rows, "cols": ds.defaults.cols,
            "max_order": ds.defaults.max_order}
    a = ok(c.post("/api/analyses", json=body), schemas.Analysis)
    assert ok(c.get(f"/api/analyses/{a.id}"), schemas.Analysis) == a
    base = f"/api/analyses/{a.id}"
    order = a.suggested_order
    m = ok(c.get(f"{base}/modes", params={"order": order}), schemas.Modes)
    assert len(m.fit_percent) == ds.n_outputs and len(m.fit_percent[0]) == ds.n_inputs
    assert ok(c.get(f"{base}/modes", params={"order": order, "fit": False}), schemas.Modes).fit_percent is None
    last = {"order": order, "output": ds.n_outputs - 1, "input": ds.n_inputs - 1, **thresholds}
    step = ok(c.get(f"{base}/step", params=last), schemas.Step)
    rec = ok(c.get(f"{base}/reconstruction", params=last), schemas.Reconstruction)
    assert step.reconstruction == rec and step.modes.n_modes == m.n_modes
    ok(c.get(f"{base}/reconstruction", params={"order": order, "modes": "0"}), schemas.Reconstruction)
    stab = ok(c.get(f"{base}/stabilization"), schemas.Stabilization)
    assert stab.coherent_min == COHERENT_MIN
    assert all(mo.coherent == (mo.emac * mo.mpc >= stab.coherent_min) for mo in stab.modes)
    kept = rec.kept or [0]
    made = ok(c.post("/api/reports", json={"analysis_id": a.id, "order": order, "modes": kept}),
              schemas.ReportCreated)
    report = ok(c.get(f"/api/reports/{made.token}"), schemas.Report)
    assert report.kept == kept and report.stabilization.modes == stab.modes and report.url == made.url
    html = c.get(f"/api/reports/{made.token}/report.html").text
    offline = json.loads(re.search(r"window\.REPORT_DATA = (\{.*?\});</script>", html).group(1))
    exact(schemas.OfflineReport, offline)
    return ds, a, stab


def test_case_1_answers_match_their_schemas(tmp_path):
    with client(tmp_path) as c:
        ds, a, _ = _flow(c, "case1", {"min_emac": 0.9, "min_mpc": 0.9})
    assert ds.defaults.rows == 90 and a.suggested_order == 10


def test_grid_answers_match_their_schemas(tmp_path):
    thresholds = {"min_emac": 0.9, "min_mpc": 0.9, "min_contribution": 0.01, "physical_only": True}
    with client(tmp_path) as c:
        ds, _, stab = _flow(c, "grid", thresholds)
    assert ds.geometry is not None and ds.source.example == "grid"
    assert any(mo.coherent for mo in stab.modes) and not all(mo.coherent for mo in stab.modes)


def test_viewer_links_and_report_playback_match_their_schemas(tmp_path):
    with client(tmp_path, viewer=True) as c:
        ds = ok(c.post("/api/examples/case1"), schemas.Dataset)
        a = ok(c.post("/api/analyses", json={"dataset_id": ds.id, "rows": 90, "cols": 90}), schemas.Analysis)
        link = ok(c.post(f"/api/analyses/{a.id}/viewer", json={"order": 10}), schemas.ViewerLink)
        assert link.n_modes == 5
        token = ok(c.post("/api/reports", json={"analysis_id": a.id, "order": 10, "modes": [1, 3]}),
                   schemas.ReportCreated).token
        report = ok(c.get(f"/api/reports/{token}"), schemas.Report)
    assert set(report.playback) == set(report.recordings) == {"1", "3"}


def test_simulation_vs_test_answers_match_their_schemas(tmp_path):
    with client(tmp_path) as c:
        ds = ok(c.post("/api/examples/grid"), schemas.Dataset)
        body = {"dataset_id": ds.id, "rows": ds.defaults.rows, "cols": ds.defaults.cols}
        a = ok(c.post("/api/analyses", json=body), schemas.Analysis)
        ran = ok(c.post(f"/api/analyses/{a.id}/explain", json={"output": 2}), schemas.Explanation)
        assert ran.overlay.output_index == 2 and ran.overlays is None
        again = ok(c.get(f"/api/analyses/{a.id}/explain"), schemas.Explanation)
        assert again.verdict == ran.verdict and again.modes == ran.modes
        only = ok(c.get(f"/api/analyses/{a.id}/explain", params={"overlay_only": True, "input": 0}),
                  schemas.ExplanationOverlay)
        assert only.overlay.input_index == 0
        token = c.post("/api/reports", json={"analysis_id": a.id, "order": 40, "modes": [0, 1]}).json()["token"]
        report = ok(c.get(f"/api/reports/{token}"), schemas.Report)
    assert report.explanation.verdict == ran.verdict
    assert len(report.explanation.overlays) == ds.n_outputs * ds.n_inputs


def test_the_builders_send_exactly_the_schema_fields_for_a_mimo_dataset():
    data = era.examples.paper_cases.case_2(200, mimo=True)
    settings = Settings()
    ident = era.identify(data, 45, 45)
    model = ident.model(10)
    summary = payloads.dataset_summary(data, None, "case 2", settings, {"format": "npz", "conversions": []})
    exact(schemas.Dataset, dict(summary, id="x", sha256="0" * 64))
    exact(schemas.Records, payloads.records_json(data, 1, 4000))
    exact(schemas.Spectrum, payloads.spectrum_json(data, 4000))
    diagram = choosing.diagram(ident, None, settings)
    exact(schemas.Analysis, payloads.analysis_json("a", "d", {"rows": 45, "cols": 45}, ident, diagram))
    exact(schemas.Modes, payloads.modes_json(model, data))
    rec = exact(schemas.Reconstruction, payloads.reconstruction_json(model, data, np.array([0, 2]), 1, 1, 4000))
    assert rec.kept == [0, 2] and (rec.output, rec.input) == (data.outputs[1], data.inputs[1])
    exact(schemas.Stabilization, payloads.stabilization_json(diagram, data, 4000))
    a = Analysis("a", "d", {"rows": 45, "cols": 45}, data, None, "case 2")
    report = reporting.build(a, ident, model, np.array([1, 3]), diagram, dataset=dict(summary, id="d", sha256="0"),
                             explanation=None, recordings={}, version="0", plot_points=4000)
    exact(schemas.ReportDocument, report)
    assert len(report["reconstruction"]["pairs"]) == 4 and report["kept"] == [1, 3]


def test_nan_and_inf_are_sent_as_null():
    assert payloads.floats([1.0, np.nan, np.inf]) == [1.0, None, None]
    assert payloads.floats([[np.nan], [2.0]]) == [[None], [2.0]]
    exact(schemas.Spectrum, {"frequency_hz": [0.0, None], "values": [[None, 1.0]]})


def test_openapi_declares_a_schema_for_every_api_answer(tmp_path):
    with client(tmp_path) as c:
        spec = c.get("/openapi.json").json()
    seen = 0
    for path, operations in spec["paths"].items():
        if not path.startswith("/api/"):
            continue
        for method, op in operations.items():
            content = op["responses"].get("200", op["responses"].get("202"))["content"]  # 202: a campaign starts
            if "application/json" in content:
                assert "#/components/schemas/" in json.dumps(content["application/json"]["schema"]), (method, path)
                seen += 1
            else:  # a download: declared with its own media type, not as JSON
                assert set(content) & {"text/html", "text/csv", "application/octet-stream"}, (method, path)
            assert "/Error" in json.dumps(op["responses"]["422"]), (method, path)  # {"error": …}, not FastAPI's
    assert seen >= 18
    components = spec["components"]["schemas"]
    assert "Hz" in components["Modes"]["properties"]["frequency_hz"]["description"]
    assert components["Step"]["properties"]["modes"]["$ref"].endswith("/Modes")


def test_refusals_match_the_error_schema(tmp_path):
    with client(tmp_path) as c:
        answers = [c.get("/api/analyses/nope"), c.get("/api/datasets/nope/records"), c.post("/api/examples/nope"),
                   c.post("/api/analyses", json={"dataset_id": "x", "rows": "many", "cols": 3})]
    assert [r.status_code for r in answers] == [404, 404, 404, 422]
    for r in answers:
        exact(schemas.Error, r.json())


@pytest.mark.parametrize("kind, missing", [(schemas.Modes, "emac"), (schemas.Stabilization, "spectrum")])
def test_an_answer_without_a_field_does_not_validate(kind, missing):
    fields = {name: None for name in kind.model_fields}
    del fields[missing]
    with pytest.raises(Exception, match=missing):
        kind.model_validate(fields)
