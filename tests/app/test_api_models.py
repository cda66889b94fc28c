"""The structure model of a dataset (issue 9, in the app): drafted from an uploaded UFF geometry, described, saved,
uploaded as a file, refused with a sentence when wrong (the stored one kept), then used by simulation vs test,
which names the effect hidden in the simulated test at a node id, and frozen into a report.

The dataset: a simulated impact test of the portal frame (era.examples.frames.portal; 400 kg hidden at the
beam's mid node E, UFF node 3), written as UFF 15/82/58 with its geometry in mm (tests/frame_test_file.py).
"""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest
from frame_test_file import write_uff

import era
from apiclient import case1_npz, client, upload
from test_schemas import exact
from app import modeling, schemas
from era.examples.frames import portal

PLATE = {"shape": "rectangle", "width": 0.3, "depth": 0.05, "material": "steel"}   # the portal's 300 × 50 mm


@pytest.fixture(scope="module")
def portal_test(tmp_path_factory):
    """(client, dataset) of the uploaded portal test; the client stays open for the module."""
    folder = tmp_path_factory.mktemp("models")
    path = write_uff(folder / "portal.uff", portal(), dict(point_mass_at="E", point_mass_kg=200.0), inputs=(1, 4))
    with client(folder / "data", viewer=True) as c:
        ds = c.post("/api/datasets", files={"file": ("portal.uff", path.read_bytes(), "application/octet-stream")})
        assert ds.status_code == 200, ds.text
        yield c, ds.json()


def described(draft: dict) -> dict:
    """The model a person describes in the panel: the draft's members and sensors, one section per group, the
    two column bases (UFF nodes 1 and 5) fixed."""
    return {"nodes": draft["nodes"], "members": draft["members"],
            "sections": {g: dict(PLATE) for g in draft["groups"]}, "supports": {"1": "fixed", "5": "fixed"},
            "masses": {}, "sensors": draft["sensors"]}


def test_the_draft_reads_members_groups_and_sensors_from_the_geometry(portal_test):
    c, ds = portal_test
    d = exact(schemas.ModelDraft, c.get(f"/api/datasets/{ds['id']}/model/draft").json())
    assert len(d.nodes) == 7 and d.nodes["2"] == pytest.approx([0.0, 0.0, 3.0])     # mm in the file, m here
    assert {tuple(m[:2]) for m in d.members} == {("1", "6"), ("2", "6"), ("2", "3"), ("3", "4"), ("4", "7"),
                                                 ("5", "7")}
    assert set(d.groups) == {"col", "beam"}           # the file's named trace lines, one group each
    assert {tuple(m) for m in d.members if m[2] == "beam"} == {("2", "3", "beam"), ("3", "4", "beam")}
    assert d.sensors[:3] == [["6", "x"], ["2", "x"], ["3", "z"]] and len(d.sensors) == len(d.outputs) == 7
    assert c.get(f"/api/datasets/{ds['id']}/model").status_code == 404
    assert c.get(f"/api/datasets/{ds['id']}").json()["has_model"] is False  # the page does not ask (that 404)


def test_a_draft_needs_trace_lines_and_every_sensor_on_one():
    from app import modeling

    g = era.Geometry(node_ids=[1, 2, 3], coordinates=[[0, 0, 0], [1, 0, 0], [2, 0, 0]], edges=[[0, 1]],
                     channel_nodes=[1, 2], channel_directions=[[0, 0, 1], [0, 0, -1]], units="m")
    with pytest.raises(era.DataError, match="Output 2 \\(b\\) measures node 3, which is on no trace line"):
        modeling.draft(g, ("a", "b"))
    d = modeling.draft(era.Geometry(node_ids=g.node_ids, coordinates=g.coordinates, edges=[[0, 1], [1, 2]],
                                    channel_nodes=g.channel_nodes, channel_directions=g.channel_directions), ("a", "b"))
    assert d["sensors"] == [["2", "z"], ["3", "-z"]] and d["groups"] == ["along x"]
    with pytest.raises(era.DataError, match="no trace lines"):
        modeling.draft(era.Geometry(node_ids=g.node_ids, coordinates=g.coordinates, edges=np.zeros((0, 2)),
                                    channel_nodes=g.channel_nodes, channel_directions=g.channel_directions), ("a", "b"))


def test_bad_models_are_refused_with_a_sentence_and_the_saved_one_is_kept(portal_test):
    c, ds = portal_test
    url = f"/api/datasets/{ds['id']}/model"
    draft = c.get(f"{url}/draft").json()
    good = described(draft)
    r = c.put(url, json={"model": good})
    assert r.status_code == 200, r.text
    saved = exact(schemas.StructureModel, r.json())
    assert saved.n_nodes == 7 and saved.n_members == 6 and saved.n_sensors == 7 and saved.source == "geometry"
    assert saved.frequency_hz[0] == pytest.approx(portal().modes(1)[0][0], rel=1e-6)   # the same structure
    assert "rectangle 300 × 50 mm steel" in saved.text

    def refused(model, words):
        r = c.put(url, json={"model": model})
        assert r.status_code == 422 and words in r.json()["error"], r.text

    bad = copy.deepcopy(good)
    bad["members"].append(["3", "99", "col"])
    refused(bad, "goes to node 99, which is not in nodes")
    bad = copy.deepcopy(good)
    del bad["sections"]["col"]["material"]
    refused(bad, "Section 'col' has no material")
    bad = copy.deepcopy(good)
    bad["sensors"] = bad["sensors"][:6]
    refused(bad, "6 sensors but this dataset has 7 outputs")
    bad = copy.deepcopy(good)
    bad["sensors"][0], bad["sensors"][1] = bad["sensors"][1], bad["sensors"][0]
    refused(bad, "output 1 (Fx) measures node 6 along x")
    bad = copy.deepcopy(good)
    bad["supports"] = {"1": "pinned", "5": "pinned"}       # pins in 3-D: the frame spins about the line 1-5
    refused(bad, "is a mechanism")
    files = {"file": ("model.json", b"{not json", "application/json")}
    r = c.post(f"{url}/file", files=files)
    assert r.status_code == 422 and "model.json: not a readable model file" in r.json()["error"]
    assert c.get(url).json()["model"] == good            # nothing saved is lost


def test_a_model_file_in_json_or_toml_is_read_and_stored(portal_test):
    c, ds = portal_test
    url = f"/api/datasets/{ds['id']}/model"
    model = described(c.get(f"{url}/draft").json())
    r = c.post(f"{url}/file", files={"file": ("portal.json", json.dumps(model).encode(), "application/json")})
    assert r.status_code == 200 and r.json()["source"] == "file" and r.json()["name"] == "portal.json", r.text
    toml = ("sensors = " + json.dumps(model["sensors"]) + "\n"
            + "members = " + json.dumps(model["members"]) + "\n"
            + "[nodes]\n" + "".join(f'"{k}" = {json.dumps(v)}\n' for k, v in model["nodes"].items())
            + '[supports]\n"1" = "fixed"\n"5" = "pinned"\n'
            + "".join(f'[sections."{g}"]\nshape = "rectangle"\nwidth = 0.3\ndepth = 0.05\nmaterial = "steel"\n'
                      for g in model["sections"]))
    r = c.post(f"{url}/file", files={"file": ("portal.toml", toml.encode(), "text/plain")})
    assert r.status_code == 200, r.text
    assert c.get(url).json()["model"]["supports"] == {"1": "fixed", "5": "pinned"}


def test_simulation_vs_test_names_the_hidden_mass_at_a_node_and_the_report_keeps_the_model(portal_test):
    c, ds = portal_test
    url = f"/api/datasets/{ds['id']}/model"
    model = described(c.get(f"{url}/draft").json())
    assert c.put(url, json={"model": model}).status_code == 200
    assert c.get(f"/api/datasets/{ds['id']}").json()["has_model"] is True
    a = c.post("/api/analyses", json=dict(dataset_id=ds["id"], rows=100, cols=100)).json()
    # before explaining: the model's modes beside the test's; the sway mode 12 % high (the hidden mass), the
    # others close, each test mode with a clear partner
    order = 12
    test = c.get(f"/api/analyses/{a['id']}/modes", params={"order": order}).json()
    keep = [k for k, (f, g, mu) in enumerate(zip(test["frequency_hz"], test["emac"], test["mpc"]))
            if f and 0 < f < 40 and g > 0.9 and mu > 0.9]
    m = exact(schemas.ModelComparison, c.get(f"/api/analyses/{a['id']}/model/mac",
                                             params={"order": order, "modes": ",".join(map(str, keep))}).json())
    assert len(m.test_hz) == 3 and len(m.mac) == 3 and len(m.mac[0]) == len(m.model_hz) >= 10
    assert all(b.mac > 0.9 for b in m.best) and 10 < m.best[0].frequency_error_pct < 16
    assert all(abs(b.frequency_error_pct) < 3 for b in m.best[1:])
    bad = c.get(f"/api/analyses/{a['id']}/model/mac", params={"order": order, "modes": "a,b"})
    assert bad.status_code == 422 and "comma-separated" in bad.json()["error"]
    r = c.post(f"/api/analyses/{a['id']}/explain", json={})
    assert r.status_code == 200, r.text
    s = exact(schemas.Explanation, r.json())
    assert s.verdict == "explained" and s.effect.name == "point_mass"
    assert s.effect.parameters["point_mass_kg"] == pytest.approx(200.0, rel=0.15)
    assert s.effect.location in {"2", "3", "4"}        # the beam's nodes: B, E, C (three modes cannot tell them)
    assert s.grid_shape is None and s.frame["members"][0] == ["1", "6"] and "7 nodes, 6 members" in s.model_text
    assert len(s.expanded_measured) == len(s.frame["node_labels"]) == 21
    # the measured shapes expanded to every node follow the model's (the out-of-plane modes, which the in-plane
    # sensors do not see, stay out of the SEREP basis)
    assert np.all(np.diag(era.mac(np.array(s.expanded_measured), np.array(s.expanded_model))) > 0.95)
    v = c.post(f"/api/analyses/{a['id']}/explain/viewer", json={"which": "model"})
    assert v.status_code == 200 and v.json()["n_modes"] == len(s.modes), v.text

    made = c.post("/api/reports", json={"analysis_id": a["id"], "order": 20, "modes": [0, 1]})
    assert made.status_code == 200, made.text
    report = exact(schemas.Report, c.get(f"/api/reports/{made.json()['token']}").json())
    assert report.structure_model.model == model and report.explanation.effect.location == s.effect.location
    assert s.stale is None and s.model_used.source == "geometry" and "7 nodes, 6 members" in s.model_used.text
    assert s.model_used.fingerprint == c.get(url).json()["fingerprint"] == modeling.fingerprint(model)
    # the stored model changes afterwards: the stored result is shown stale, with the model it was made with; the
    # report keeps the model and the (then current) result it froze
    changed = dict(model, masses={"3": 5.0})
    saved = c.put(url, json={"model": changed}).json()
    assert saved["fingerprint"] != s.model_used.fingerprint
    again = c.get(f"/api/reports/{made.json()['token']}").json()
    assert again["structure_model"]["model"] == model and again["explanation"]["stale"] is None
    now = exact(schemas.Explanation, c.get(f"/api/analyses/{a['id']}/explain").json())
    assert "made with an earlier model" in now.stale and "masses 3 5 kg" in now.stale
    assert now.model_used == s.model_used and now.effect.location == s.effect.location   # kept as it was
    # a report frozen now keeps the new model, and the result marked stale beside the model it was made with
    later = c.post("/api/reports", json={"analysis_id": a["id"], "order": 20, "modes": [0, 1]}).json()
    frozen = exact(schemas.Report, c.get(f"/api/reports/{later['token']}").json())
    assert frozen.structure_model.model == changed and frozen.explanation.stale == now.stale
    assert frozen.explanation.model_used.fingerprint == modeling.fingerprint(model)
    # the same model again (tables in another order): current again
    same = dict(reversed(list(model.items())))
    assert c.put(url, json={"model": same}).status_code == 200
    assert c.get(f"/api/analyses/{a['id']}/explain").json()["stale"] is None


def test_a_result_stored_before_its_model_was_recorded_is_judged_by_its_description():
    from app import modeling

    model = {"nodes": {"1": [0, 0, 0], "2": [1, 0, 0]}, "members": [["1", "2", "s"]],
             "sections": {"s": PLATE}, "supports": {"1": "fixed"}, "sensors": [["2", "z"]]}
    stored = {"model": model, "source": "geometry"}
    old = {"model_text": modeling.describe(model)}            # a frame result from before model_used
    assert modeling.stale(old, stored) is None
    assert "has changed since" in modeling.stale(old, {"model": dict(model, masses={"2": 1.0}), "source": "file"})
    grid = {"model_text": None}                               # a grid result; the dataset then got a model
    assert modeling.stale(grid, None) is None
    assert "NASA grid's built-in model" in modeling.stale(grid, stored)
    assert modeling.stale({"model_used": modeling.used(None)}, None) is None
    assert modeling.stale({"model_used": modeling.used(stored)}, stored) is None


def test_a_model_is_replaced_whole_and_goes_with_its_dataset_when_that_expires(tmp_path):
    import time

    import era.examples.paper_cases
    from app.store import Store

    store = Store(tmp_path)
    ds = store.add_dataset(era.examples.paper_cases.case_1(200), None, "case1", {})
    assert store.model(ds) is None
    for mass in (1.0, 2.0):
        store.set_model(ds, {"model": {"masses": {"1": mass}}, "source": "file", "name": "m.json", "saved": 0.0})
    assert store.model(ds)["model"]["masses"] == {"1": 2.0}
    assert store.usage()["bytes"]["models"] > 0
    store.expire(time.time() + 1)
    assert store.model(ds) is None and not (tmp_path / "models" / f"{ds}.json").exists()


def test_edits_in_the_panel_springs_members_orientation_are_checked_by_era_frame_and_placed(portal_test):
    """What the panel's editing sends: spring supports (N/m, N·m/rad), a member added between two nodes or removed,
    a member's orientation vector. Each refusal is era.Frame's own sentence with the control that fixes it
    (``option``: the member's index, the node, the section); the stored model stays as it was."""
    c, ds = portal_test
    url = f"/api/datasets/{ds['id']}/model"
    good = described(c.get(f"{url}/draft").json())
    base = c.put(url, json={"model": good}).json()
    f0 = base["frequency_hz"][0]

    def saved(model):
        r = c.put(url, json={"model": model})
        assert r.status_code == 200, r.text
        return r.json()

    def refused(model, words, option):
        r = c.put(url, json={"model": model})
        assert r.status_code == 422 and words in r.json()["error"] and r.json().get("option") == option, r.text
        assert c.get(url).json()["model"] == kept            # nothing saved is lost

    # very stiff springs on every DOF behave as the fixed bases; a soft rotational spring lowers the sway mode
    stiff = {k: 1e13 for k in ("kx", "ky", "kz")} | {k: 1e12 for k in ("rx", "ry", "rz")}
    springs = saved(dict(good, supports={"1": stiff, "5": stiff}))
    assert springs["frequency_hz"][0] == pytest.approx(f0, rel=2e-3) and "1 springs" in springs["text"]
    soft = saved(dict(good, supports={"1": dict(stiff, ry=2e5), "5": dict(stiff, ry=2e5)}))
    assert soft["frequency_hz"][0] < 0.9 * f0
    # a diagonal brace between two nodes stiffens the sway; removing it again gives the portal back
    braced = saved(dict(good, members=good["members"] + [["1", "7", "col"]]))
    assert braced["n_members"] == 7 and braced["frequency_hz"][0] > 1.5 * f0
    # turning the columns' 300 × 50 plates by 90° about their axis (local z along y) changes the sway stiffness
    turned = [m + [[0.0, 1.0, 0.0]] if m[2] == "col" else m for m in good["members"]]
    assert abs(saved(dict(good, members=turned))["frequency_hz"][0] / f0 - 1) > 0.05
    kept = saved(good)["model"]

    k_col = next(k for k, m in enumerate(good["members"]) if m[2] == "col")
    refused(dict(good, supports={"1": dict(stiff, ry=-5.0), "5": "fixed"}),
            "support at node 1: ry must be a stiffness ≥ 0", "node:1")
    refused(dict(good, supports={"1": {}, "5": "fixed"}), "support at node 1 must be 'fixed', 'pinned' or a table",
            "node:1")
    refused(dict(good, supports={"1": {"kq": 1.0}, "5": "fixed"}), "unknown key 'kq'", "node:1")
    refused(dict(good, members=good["members"] + [["3", "3", "beam"]]), "has zero length",
            f"member:{len(good['members'])}")
    vertical = [m + [[0.0, 0.0, 1.0]] if k == k_col else m for k, m in enumerate(good["members"])]
    refused(dict(good, members=vertical), "must be a 3-vector not parallel to the member", f"member:{k_col}")
    refused(dict(good, members=[m for m in good["members"] if "3" not in m[:2]]), "node 3 is on no member", "node:3")
    refused(dict(good, masses={"3": -2.0}), "mass at node 3 must be a number of kg", "node:3")
    r = c.put(url, json={"model": dict(good, supports={"1": "pinned", "5": "pinned"})})   # spins about 1-5
    named = r.json()["error"].split("node ", 1)[1].split(" ", 1)[0]
    assert r.status_code == 422 and "is a mechanism" in r.json()["error"] and r.json()["option"] == f"node:{named}"
    no_wall = dict(good, sections=dict(good["sections"], col={"shape": "tube", "diameter": 0.05, "wall": 0.06,
                                                              "material": "steel"}))
    refused(no_wall, "Section", "section:col")


def test_each_refusal_of_era_frame_names_its_control():
    from app import modeling

    model = {"members": [["1", "2", "s"], ["2", "3", "s"]], "sections": {"s": PLATE, "t": {"area": -1}}}
    cases = {"Frame: member 1 (2-3) has zero length: its nodes coincide.": "member:1",
             "Frame: support at node A 1: ry must be a stiffness ≥ 0 or 'fixed'": "node:A 1",
             "Frame: support at node 7 must be 'fixed', 'pinned' or a table": "node:7",
             "Frame: support at node 9, which is not in nodes.": "node:9",
             "Frame: mass at node 3 must be a number of kg ≥ 0, got -2.": "node:3",
             "Frame: joint spring at node 4 must be a number of N·m/rad > 0, got 0.": "node:4",
             "Frame: node 6 is on no member: add a member or remove the node (1 such node).": "node:6",
             "Frame is a mechanism: node B rotation about z is free: add a support or a member": "node:B",
             "Frame: sensor at node 2: direction 'q' is not one of": "sensors",
             "Frame: gravity must be None or a non-zero (gx, gy, gz) in m/s², got 0.": "gravity",
             "Section: area must be positive and finite, got -1.": "section:t",
             "Frame: no members.": None}
    for message, option in cases.items():
        assert modeling.control(message, model) == option, message


def test_the_model_in_the_3d_view_hands_its_picks_to_the_panel(portal_test, tmp_path):
    """POST .../model/viewer publishes the description being edited (its nodes clickable in viser); the page polls
    the picks, turns the view to a node and recolours nodes. (The click itself, in viser's client, is in
    tests/e2e/test_model_e2e.py.)"""
    c, ds = portal_test
    draft = c.get(f"/api/datasets/{ds['id']}/model/draft").json()
    body = {"nodes": draft["nodes"], "members": [m[:2] for m in draft["members"]], "marks": {"1": "fixed"}}
    link = exact(schemas.ModelViewLink, c.post(f"/api/datasets/{ds['id']}/model/viewer", json=body).json())
    assert c.get(link.url).status_code == 200                        # viser's page for the iframe
    assert c.get(link.picks_url).json() == {"picks": [], "last": 0}
    viewer = c.app.state.viewer
    for node in ("3", "5", "3"):                                     # what a click on a sphere records
        viewer._live.pickable.add_pick(link.key, node)
    assert c.get(link.picks_url, params={"after": 1}).json() == {
        "picks": [{"seq": 2, "node": "5"}, {"seq": 3, "node": "3"}], "last": 3}
    assert c.post(link.look_url, json={"node": "3"}).json() == {"views": 0}       # no browser open here
    assert c.post(link.look_url, json={"node": "99"}).status_code == 404
    assert c.post(link.marks_url, json={"marks": {"5": "springs", "3": "mass"}}).status_code == 200
    bad = c.post(link.marks_url, json={"marks": {"5": "glued"}})
    assert bad.status_code == 422 and "Unknown node mark 'glued'" in bad.json()["error"]
    assert c.get("/viser/nokey/picks").status_code == 404
    for wrong, words in (({"nodes": {}}, "needs the model's nodes"),
                         ({"nodes": {"1": [0, 0, 0]}, "members": [["1", "2"]]}, "does not join two of its nodes"),
                         ({"nodes": {"1": [0, 0]}}, "three finite coordinates")):
        r = c.post(f"/api/datasets/{ds['id']}/model/viewer", json=wrong)
        assert r.status_code == 422 and words in r.json()["error"], r.text
    with client(tmp_path / "off") as off:                             # a server without the viewer says so
        other = upload(off, case1_npz()).json()
        r = off.post(f"/api/datasets/{other['id']}/model/viewer", json=body)
        assert r.status_code == 503 and "pick nodes in the drawing" in r.json()["error"]
