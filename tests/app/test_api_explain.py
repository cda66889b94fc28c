"""Simulation vs test in the app (issue 5 item 4): POST/GET /api/analyses/{id}/explain, stored with the analysis and
frozen into a report; the grid's nine sensors required; bad nominal parameters and unknown ids refused clearly.

One explain run (a few seconds) is shared by the module: the grid example, identified once.
"""

from __future__ import annotations

import numpy as np
import pytest

import era
from apiclient import analysis, client
from app import explaining

VERDICTS = {"explained", "no_significant_discrepancy", "ambiguous", "unexplained"}


@pytest.fixture(scope="module")
def grid_run(tmp_path_factory):
    """(client, analysis, POST answer) for the built-in grid example; the client stays open for the module."""
    with client(tmp_path_factory.mktemp("explain"), viewer=True) as c:
        ds = c.post("/api/examples/grid")
        assert ds.status_code == 200, ds.text
        ds = ds.json()
        a = c.post("/api/analyses", json=dict(dataset_id=ds["id"], rows=ds["defaults"]["rows"],
                                               cols=ds["defaults"]["cols"]))
        assert a.status_code == 200, a.text
        a = a.json()
        before = c.get(f"/api/analyses/{a['id']}/explain")
        assert before.status_code == 404 and "has not run" in before.json()["error"]
        assert a["has_explanation"] is False  # so the page does not ask (that 404 above)
        assert c.get(f"/api/analyses/{a['id']}").json()["has_explanation"] is False
        r = c.post(f"/api/analyses/{a['id']}/explain", json={"output": 2, "input": 1})
        assert r.status_code == 200, r.text
        assert c.get(f"/api/analyses/{a['id']}").json()["has_explanation"] is True
        yield c, a, r.json()


def test_grid_example_gets_a_verdict_and_the_update_closes_the_gap(grid_run):
    _, _, s = grid_run
    assert s["verdict"] in VERDICTS
    if s["verdict"] == "explained":  # a name comes with its parameters, their uncertainty and a sentence
        e = s["effect"]
        assert e["name"] in {r["name"] for r in s["ranking"]} and e["probability"] >= 0.9
        assert set(e["uncertainty"]) <= set(e["parameters"]) and e["description"]
        assert s["after"]["max_abs_freq_error_pct"] < s["before"]["max_abs_freq_error_pct"]
        assert s["after"]["min_mac"] >= s["before"]["min_mac"]
    else:  # an honest non-name carries no effect
        assert s["effect"] is None and s["message"]
    probabilities = [r["probability"] for r in s["ranking"]]
    assert abs(sum(probabilities) - 1) < 1e-6 and probabilities == sorted(probabilities, reverse=True)
    k = len(s["modes"])
    assert k >= 5 and len(s["mac_before"]) == k == len(s["mac_after"]) == len(s["measured_hz"])
    assert len(s["mac_before"][0]) == len(s["model_hz_before"])
    assert len(s["expanded_measured"]) == len(s["node_xy_ft"]) == 88 and len(s["expanded_measured"][0]) == k
    # the overlay asked for: output 2, input 1, measured record as stored, and the updated model fits it better
    o = s["overlay"]
    assert (o["output_index"], o["input_index"]) == (2, 1)
    assert len(o["time_s"]) == len(o["measured"]) == len(o["nominal"]) == len(o["updated"]) > 100
    fit = s["overlay_fit_percent"]
    assert fit["updated"][2][1] > fit["nominal"][2][1]


def test_the_result_is_stored_and_read_back_and_goes_into_a_report(grid_run):
    c, a, s = grid_run
    again = c.get(f"/api/analyses/{a['id']}/explain").json()
    for key in ("verdict", "effect", "ranking", "before", "after", "modes", "mac_after"):
        assert again[key] == s[key]
    assert (again["overlay"]["output_index"], again["overlay"]["input_index"]) == (0, 0)
    only = c.get(f"/api/analyses/{a['id']}/explain", params={"output": 2, "input": 1, "overlay_only": True}).json()
    assert set(only) == {"overlay"} and only["overlay"]["measured"] == s["overlay"]["measured"]
    bad = c.get(f"/api/analyses/{a['id']}/explain", params={"output": 9})
    assert bad.status_code == 422 and "output 0..8" in bad.json()["error"]

    made = c.post("/api/reports", json={"analysis_id": a["id"], "order": 20, "modes": [0, 1, 2]})
    assert made.status_code == 200, made.text
    report = c.get(f"/api/reports/{made.json()['token']}").json()
    x = report["explanation"]
    assert x["verdict"] == s["verdict"] and x["before"] == s["before"] and x["after"] == s["after"]
    assert len(x["overlays"]) == 9 * len(s["inputs"])  # every output for every input, stored in the report
    html = c.get(f"/api/reports/{made.json()['token']}/report.html").text
    assert "EraExplainView" in html and "/static/js/explain_view.js" not in html  # inlined: opens offline


def test_measured_and_model_shapes_go_to_the_viewer_on_every_joint(grid_run):
    c, a, s = grid_run
    for which in ("measured", "model"):
        v = c.post(f"/api/analyses/{a['id']}/explain/viewer", json={"which": which})
        assert v.status_code == 200, v.text
        v = v.json()
        assert v["n_modes"] == len(s["modes"]) and v["url"].startswith("/viser/")
        r = c.post(v["mode_url"], json={"index": len(s["modes"]) - 1})
        assert r.status_code == 200
    assert c.post(f"/api/analyses/{a['id']}/explain/viewer", json={"which": "truth"}).status_code == 422


def test_a_report_without_the_panel_has_no_explanation(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        made = c.post("/api/reports", json={"analysis_id": a["id"], "order": 10, "modes": [0, 2]}).json()
        assert c.get(f"/api/reports/{made['token']}").json()["explanation"] is None


def test_bad_nominal_parameters_get_422_with_the_reason(grid_run):
    c, a, _ = grid_run
    url = f"/api/analyses/{a['id']}/explain"
    cases = [({"gravty": False}, "Unknown nominal-model parameter"),
             ({"torsion_factor": "stiff"}, "must be a number"),
             ({"point_mass_kg": 1.0}, "point_mass_at"),
             ({"cable_length_m": -1}, "positive")]
    for nominal, words in cases:
        r = c.post(url, json={"nominal": nominal})
        assert r.status_code == 422 and words in r.json()["error"], (nominal, r.text)


def test_a_dataset_without_the_grid_sensors_gets_a_clear_422(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)  # the paper's Case I: one output, no geometry
        r = c.post(f"/api/analyses/{a['id']}/explain", json={})
        assert r.status_code == 422
        assert "needs the NASA grid's nine sensors in order" in r.json()["error"]


def test_unknown_analysis_is_404(tmp_path):
    with client(tmp_path) as c:
        for r in (c.post("/api/analyses/no-such-id/explain", json={}), c.get("/api/analyses/no-such-id/explain"),
                  c.post("/api/analyses/no-such-id/explain/viewer", json={"which": "measured"})):
            assert r.status_code == 404 and "No analysis" in r.json()["error"]


def test_the_built_in_example_names_its_hidden_point_mass_at_the_right_joint(grid_run):
    """The example hides a point mass (app/examples.py); the stored dataset keeps the input locations, so explain
    also weighs ERA's mass-normalised residues, and the panel names the effect, the joint and the mass."""
    from era.examples.grid_simulation import simulate_grid_test

    _, _, s = grid_run
    _, truth = simulate_grid_test(effect="point_mass", seed=7)
    hidden = truth["effect"]
    assert s["verdict"] == "explained" and s["effect"]["name"] == "point_mass"
    assert tuple(s["effect"]["location"]) == tuple(hidden["location"])
    true_kg = hidden["parameters"]["point_mass_kg"]
    assert abs(s["effect"]["parameters"]["point_mass_kg"] - true_kg) / true_kg < 0.15
    assert s["after"]["max_abs_freq_error_pct"] < 0.5 and s["after"]["min_mac"] > 0.95


def test_explain_runs_on_the_analysis_and_says_so(grid_run):
    """The default run uses this analysis's H(0) and the modes era chose from its diagram (the ones the page
    ticks: the analysis's chosen_indices at its suggested_order), tracked over the diagram's orders, and says so."""
    c, a, s = grid_run
    b = s["basis"]
    assert (b["hankel_rows"], b["hankel_cols"]) == (a["rows"], a["cols"]) and b["hankel_shape"] == a["hankel_shape"]
    assert (b["modes"], b["order"], b["kept"]) == ("stable", a["suggested_order"], a["chosen_indices"])
    assert b["orders"] == c.get(f"/api/analyses/{a['id']}/stabilization").json()["orders"]
    assert f"{a['hankel_shape'][0]} × {a['hankel_shape'][1]}" in b["text"]
    n = len(a['chosen_indices'])
    assert f"the {n} {'mode' if n == 1 else 'modes'} era chose at order {a['suggested_order']}" in b["text"]
    # the measured modes compared are the chosen ones, at the choice's order (unpaired ones set aside)
    modes = c.get(f"/api/analyses/{a['id']}/modes", params={"order": a["suggested_order"], "fit": False}).json()
    assert sorted(s["measured_hz"] + s["unpaired_measured_hz"]) == pytest.approx(
        sorted(modes["frequency_hz"][k] for k in a["chosen_indices"]), rel=1e-9)


def test_explain_compares_exactly_the_modes_kept_at_the_chosen_order(grid_run):
    c, a, _ = grid_run
    order = 40
    modes = c.get(f"/api/analyses/{a['id']}/modes", params={"order": order, "fit": False}).json()
    kept = [k for k in range(modes["n_modes"]) if modes["emac"][k] >= 0.9 and modes["mpc"][k] >= 0.9
            and modes["is_pair"][k] and 0 < modes["damping_ratio"][k] < 0.1][:7]  # the seven lowest physical modes
    r = c.post(f"/api/analyses/{a['id']}/explain", json={"modes": "kept", "order": order, "kept": kept,
                                                         "orders": [32, 36, 44]})
    assert r.status_code == 200, r.text
    s = r.json()
    b = s["basis"]
    assert (b["modes"], b["order"], b["kept"], b["orders"]) == ("kept", order, kept, [32, 36, 40, 44])
    assert f"{len(kept)} {'mode' if len(kept) == 1 else 'modes'} kept at order {order}" in b["text"]
    # the measured modes compared are the kept ones, at the chosen order's frequencies (unpaired ones set aside)
    chosen = sorted(s["measured_hz"] + s["unpaired_measured_hz"])
    # (explain runs in a worker process: the same arithmetic, last-bit differences from its own BLAS)
    assert chosen == pytest.approx(sorted(modes["frequency_hz"][k] for k in kept), rel=1e-9)
    assert c.get(f"/api/analyses/{a['id']}/explain").json()["basis"] == b  # stored as run
    missing = c.post(f"/api/analyses/{a['id']}/explain", json={"modes": "kept", "order": order})
    assert missing.status_code == 422 and "needs `order` and `kept`" in missing.json()["error"]
    outside = c.post(f"/api/analyses/{a['id']}/explain", json={"orders": [20, 100000]})
    assert outside.status_code == 422 and "outside this analysis" in outside.json()["error"]
    bad = c.post(f"/api/analyses/{a['id']}/explain", json={"modes": "kept", "order": order, "kept": [999]})
    assert bad.status_code == 422 and "out of range" in bad.json()["error"]


def test_with_no_mode_chosen_the_default_run_asks_for_ticked_modes():
    """era.choose_modes chose nothing (records of noise, say): the default run says so and what to do (422)."""
    empty = era.ModeChoice(order=2, indices=np.zeros(0, dtype=int), chosen=(), rejected=())
    with pytest.raises(era.DataError, match="era chose no mode.*tick the modes to compare"):
        explaining.chosen_modes(empty)
