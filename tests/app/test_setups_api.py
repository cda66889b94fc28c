"""Multi-setup tests through the API (issue 26): a beam's four modes recorded in four ambient setups that share two
reference sensors, uploaded as four CSV files (one per setup), the references proposed by name, each setup analysed
and the four merged: the merged shape matches the truth at all twelve points; wrong references, a missing one and a
single file are refused in the page's words next to the control that fixes them."""

from __future__ import annotations

import csv
import io
import sys
from pathlib import Path

import numpy as np
import pyuff

import era

from apiclient import client

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from simulated_setups import (FREQUENCY_HZ, TOWER_HEIGHTS, TOWER_HZ, TOWER_REFERENCES, TOWER_ROVING,  # noqa: E402
                              setup_file, setup_npz, tower_file, tower_geometry_csv, tower_truth, truth_at)

def upload(c, files, **form):
    return c.post("/api/setups", files=[("file", (n, b, "text/csv")) for n, b in files],
                  data={"kind": "ambient", **form})


def shapes_of(merged) -> np.ndarray:
    re = np.array([[np.nan if v is None else v for v in row] for row in merged["shapes_re"]])
    im = np.array([[np.nan if v is None else v for v in row] for row in merged["shapes_im"]])
    return (re + 1j * im).T


def test_four_setups_merge_to_the_true_shape_at_every_point(tmp_path):
    with client(tmp_path) as c:
        r = upload(c, [setup_file(k) for k in range(4)], name="beam")
        assert r.status_code == 200, r.text
        test = r.json()
        assert test["name"] == "beam" and len(test["setups"]) == 4 and test["merged"] is None
        assert test["proposed_names"] == ["P2", "P5"] and test["proposed"] == [[0, 1]] * 4
        r = c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"]})
        assert r.status_code == 200, r.text
        merged = r.json()["merged"]
        assert merged["points"] == ["P2", "P5", "P1", "P3", "P4", "P6", "P7", "P8", "P9", "P10", "P11", "P12"]
        assert merged["point_setup"] == [0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 4, 4]
        assert merged["reference_names"] == ["P2", "P5"]
        freqs = [m["frequency_hz"] for m in merged["modes"]]
        np.testing.assert_allclose(freqs, FREQUENCY_HZ, rtol=0.01)
        assert all(m["complete"] and m["seen"] == "seen in 4 of 4 setups" for m in merged["modes"])
        shapes = shapes_of(merged)
        macs = np.diag(era.mac(shapes, truth_at(merged["points"])))
        print("merged MAC with the truth:", macs.round(5))
        assert np.all(macs >= 0.99)
        # the spurious poles of single setups are named with their reason
        assert all("seen in 1 of 4 setups" in d["reason"] or "twin" in d["reason"] or "also ha" in d["reason"]
                   for d in merged["dropped"])
        # a pole left out beside a mode other setups saw is never "seen in 1 of 4"
        for d in merged["dropped"]:
            if any(abs(d["frequency_hz"] - f) < 0.03 * f for f in FREQUENCY_HZ):
                assert "seen in 1 of" not in d["reason"], d

        # the picked references only as NExT references (era.load's references=): the same four modes
        r = c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"],
                                                            "next_references": "references"})
        assert r.status_code == 200, r.text
        only = r.json()["merged"]
        assert only["next_references"] == "references" and len(only["modes"]) == 4
        np.testing.assert_allclose([m["frequency_hz"] for m in only["modes"]], FREQUENCY_HZ, rtol=0.01)
        assert np.all(np.diag(era.mac(shapes_of(only), truth_at(only["points"]))) >= 0.99)
        merged = c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"]}).json()["merged"]
        # by default both ways, the better merge kept and said (era.merge_choosing_next)
        assert merged["next_asked"] == "auto" and merged["next_references"] in ("every", "references")
        assert merged["next_choice"].startswith("Kept ") and len(merged["next_complete"]) == 2
        assert max(merged["next_complete"]) == 4

        # the link reopens it: the same merge, read back
        again = c.get(f"/api/setups/{test['id']}").json()
        assert again["merged"]["points"] == merged["points"] and again["merged"]["shapes_re"] == merged["shapes_re"]
        page = c.get(f"/s/{test['id']}")
        assert page.status_code == 200 and "setups.js" in page.text
        assert c.get("/s/unknown-test").status_code == 404

        # CSV: one row per mode, each point's value
        rows = list(csv.reader(io.StringIO(c.get(f"/api/setups/{test['id']}/modes.csv").text)))
        assert rows[0][:10] == ["mode", "frequency_hz", "frequency_std_hz", "damping_ratio", "damping_std", "mpc",
                                "seen_in_setups", "n_setups", "complete", "unknown_at"]
        assert len(rows) == 5 and rows[1][6:9] == ["4", "4", "1"]
        # UFF 55: every mode, point k at node k + 1 (no geometry)
        r = c.get(f"/api/setups/{test['id']}/modes.uff")
        assert r.status_code == 200 and "x-era-left-out" not in r.headers
        path = tmp_path / "merged.uff"
        path.write_bytes(r.content)
        sets = [s for s in pyuff.UFF(str(path)).read_sets() if s["type"] == 55]
        assert len(sets) == 4
        for j, s in enumerate(sets):
            np.testing.assert_array_equal(s["node_nums"], np.arange(1, 13))
            np.testing.assert_allclose(s["r3"], shapes[:, j], atol=1e-5)


def test_setups_with_a_geometry_merge_onto_it(tmp_path):
    """Each setup's NPZ places its channels on the beam's nodes: the merged points are on their nodes (the
    references P2, P5 on nodes 2 and 5), and the UFF 55 export writes each point's value at its node."""
    with client(tmp_path) as c:
        test = upload(c, [setup_npz(k) for k in range(4)], kind="auto").json()
        assert all(s["has_geometry"] and not s["ambient"] for s in test["setups"])
        merged = c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"]}).json()["merged"]
        g = merged["geometry"]
        assert g["node_ids"] == list(range(1, 13))
        node_of = [g["node_ids"][n] for n in g["channel_nodes"]]
        assert node_of == [int(q[1:]) for q in merged["points"]]
        shapes = shapes_of(merged)
        assert np.all(np.diag(era.mac(shapes, truth_at(merged["points"]))) >= 0.99)
        path = tmp_path / "merged.uff"
        path.write_bytes(c.get(f"/api/setups/{test['id']}/modes.uff").content)
        modes = era.read_modes_uff(path)
        np.testing.assert_array_equal(modes.node_ids, np.arange(1, 13))
        at_nodes = np.empty((12, 4), complex)
        at_nodes[np.array(node_of) - 1] = shapes
        np.testing.assert_allclose(modes.shapes[:, 2, :], at_nodes, atol=1e-5)
        # the server runs without the viewer here: said, not a 500
        r = c.post(f"/api/setups/{test['id']}/viewer")
        assert r.status_code == 503 and "not available" in r.json()["error"]


def test_points_on_the_nodes_of_a_uff_file_and_a_report_of_the_merge(tmp_path):
    """The beam's nodes as another program writes them (pyuff: UFF 15 nodes 100-113, the supports 100 and 113
    without sensors, one UFF 82 trace line through them): given to the test, a points table point,node,direction
    puts every merged point on its node, the drawing keeps every node and the line, and UFF 55 writes each point's
    value at its node. A report freezes that merge: its link reopens it (modes and geometry) after a later merge."""
    ids = np.arange(100, 114)
    x = np.arange(14) / 13 * 1.3
    sets = [pyuff.prepare_15(node_nums=[int(i) for i in ids], def_cs=[0] * 14, disp_cs=[0] * 14, color=[1] * 14,
                             x=x, y=np.zeros(14), z=np.zeros(14)),
            {"type": 82, "trace_num": 1, "n_nodes": 14, "color": 1, "id": "beam", "nodes": ids}]
    pyuff.UFF(str(tmp_path / "beam.uff")).write_sets(sets, mode="overwrite")
    table = "point,node,direction\n" + "".join(f"P{i},{99 + i},z\n" for i in range(1, 13))
    with client(tmp_path) as c:
        test = upload(c, [setup_npz(k) for k in range(4)], kind="auto").json()
        r = c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"], "points": table})
        assert r.status_code == 422 and r.json()["option"] == "points" and "UFF file" in r.json()["error"]
        r = c.post(f"/api/setups/{test['id']}/nodes", files={"file": ("notes.csv", b"a,b\n1,2\n", "text/csv")})
        assert r.status_code == 422 and r.json()["option"] == "points"
        r = c.post(f"/api/setups/{test['id']}/nodes",
                   files={"file": ("beam.uff", (tmp_path / "beam.uff").read_bytes(), "application/octet-stream")})
        assert r.status_code == 200, r.text
        assert r.json()["nodes"] == {"file": "beam.uff", "n_nodes": 14, "n_lines": 1, "node_ids": ids.tolist()}
        assert c.get(f"/api/setups/{test['id']}").json()["nodes"]["n_nodes"] == 14
        merged = c.post(f"/api/setups/{test['id']}/merge",
                        json={"references": test["proposed"], "points": table}).json()["merged"]
        g = merged["geometry"]
        assert g["node_ids"] == ids.tolist() and len(g["edges"]) == 13
        np.testing.assert_allclose(np.array(g["coordinates"])[:, 0], x, atol=1e-9)
        node_of = [g["node_ids"][n] for n in g["channel_nodes"]]
        assert node_of == [99 + int(q[1:]) for q in merged["points"]]
        path = tmp_path / "merged.uff"
        path.write_bytes(c.get(f"/api/setups/{test['id']}/modes.uff").content)
        modes = era.read_modes_uff(path)
        row = {int(n): i for i, n in enumerate(modes.node_ids)}
        np.testing.assert_allclose(modes.shapes[[row[n] for n in node_of], 2, :], shapes_of(merged), atol=1e-5)

        # a report freezes this merge: its link reopens the merged modes on these nodes after a later merge
        csv_now = c.get(f"/api/setups/{test['id']}/modes.csv").text
        r = c.post(f"/api/setups/{test['id']}/report")
        assert r.status_code == 200 and r.json()["url"] == f"/s/{test['id']}/r/{r.json()['token']}"
        token = r.json()["token"]
        c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"]})  # the files' geometry
        assert c.get(f"/api/setups/{test['id']}").json()["merged"]["geometry"]["node_ids"] == list(range(1, 13))
        frozen = c.get(f"/api/setups/{test['id']}/reports/{token}").json()
        assert frozen["report"]["token"] == token and frozen["merged"] == merged
        assert frozen["merged"]["geometry"]["node_ids"] == ids.tolist()
        assert c.get(f"/api/setups/{test['id']}/reports/{token}/modes.csv").text == csv_now
        assert c.get(f"/s/{test['id']}/r/{token}").status_code == 200
        assert c.get(f"/s/{test['id']}/r/nosuchreport").status_code == 404
        assert c.get(f"/api/setups/{test['id']}/reports/nosuchreport").status_code == 404


def test_a_mode_one_setup_missed_is_kept_seen_in_3_of_4_and_left_out_of_uff(tmp_path):
    files = [setup_file(0), setup_file(1, modes=(0, 1, 3)), setup_file(2), setup_file(3)]
    with client(tmp_path) as c:
        test = upload(c, files).json()
        merged = c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"]}).json()["merged"]
        third = merged["modes"][2]
        assert abs(third["frequency_hz"] - 9.0) < 0.1
        assert third["seen"] == "seen in 3 of 4 setups" and not third["complete"] and third["missing_setups"] == [2]
        assert "setup 2 (P6, P7, P8)" in third["note"]
        assert all(merged["shapes_re"][2][q] is None for q in (5, 6, 7))
        r = c.get(f"/api/setups/{test['id']}/modes.uff")
        assert r.headers["x-era-left-out"].startswith("Left out (not known at every point): mode 3 (")
        assert "Hz, not measured in setup 2)" in r.headers["x-era-left-out"]
        path = tmp_path / "merged.uff"
        path.write_bytes(r.content)
        assert [int(s["mode_n"]) for s in pyuff.UFF(str(path)).read_sets() if s["type"] == 55] == [1, 2, 4]
        rows = list(csv.reader(io.StringIO(c.get(f"/api/setups/{test['id']}/modes.csv").text)))
        assert rows[3][8:10] == ["0", "P6 P7 P8"] and rows[3][10 + 2 * 5] == ""


def test_wrong_references_are_refused_next_to_the_picker(tmp_path):
    with client(tmp_path) as c:
        test = upload(c, [setup_file(k) for k in range(4)]).json()
        url = f"/api/setups/{test['id']}/merge"
        # setup 3's second reference is a roving sensor (P9 instead of P5)
        r = c.post(url, json={"references": [[0, 1], [0, 1], [0, 2], [0, 1]]})
        assert r.status_code == 422 and r.json()["option"] == "references"
        assert "Setup 3's reference channels [0, 2] do not move like those of the setups before it" in r.json()["error"]
        assert "Check setup 3's references in the picker" in r.json()["error"]
        assert "references[" not in r.json()["error"]
        for refs, words in [([[0, 1], [0], [0, 1], [0, 1]], "Setup 2 (setup2.csv) has 1 reference channels picked "
                                                              "where setup 1 has 2"),
                            ([[0, 1], [0, 1], [0, 9], [0, 1]], "Setup 3 (setup3.csv) has 4 channels; a picked "
                                                               "reference is not one of them"),
                            ([[0, 1]] * 3, "References are given for 3 setups, but the test has 4"),
                            ([[]] * 4, "No reference channel is picked"),
                            ([[0, 0]] * 4, "channel P2 is picked as two references")]:
            r = c.post(url, json={"references": refs})
            assert r.status_code == 422 and words in r.json()["error"], (refs, r.text)
            assert r.json()["option"] == "references"
        assert c.get(f"/api/setups/{test['id']}").json()["merged"] is None
        assert c.get(f"/api/setups/{test['id']}/modes.csv").status_code == 404


def test_a_reference_missing_in_one_setup_is_named_and_one_reference_is_refused(tmp_path):
    """Setup 2's file calls its second reference Q5: only P2 is in every setup by name, and P5 is named as missing
    in setup 2; the data propose P2 and P5 (Q5 in setup 2) all the same; a merge through one reference is refused (it could not tell a wrong pick); with
    Q5 picked by hand as setup 2's second reference, the merge goes through."""
    name, blob = setup_file(1)
    renamed = blob.replace(b"P5,", b"Q5,", 1)
    with client(tmp_path) as c:
        test = upload(c, [setup_file(0), (name, renamed), setup_file(2)]).json()
        assert test["unmatched"] == [{"name": "P5", "missing_in": [2]}]
        # the data find both references, Q5 in setup 2 too (the names alone would propose P2 only)
        assert test["proposed_from"] == "data" and test["proposed"] == [[0, 1]] * 3
        assert test["proposed_names"] == ["P2", "P5"]
        r = c.post(f"/api/setups/{test['id']}/merge", json={"references": [[0], [0], [0]]})
        assert r.status_code == 422 and r.json()["option"] == "references"
        assert r.json()["error"].startswith("One reference channel is picked") and "at least two" in r.json()["error"]
        r = c.post(f"/api/setups/{test['id']}/merge", json={"references": [[0, 1]] * 3})
        assert r.status_code == 200, r.text
        assert r.json()["merged"]["reference_names"] == ["P2", "P5"]


def test_references_in_another_column_order_are_proposed(tmp_path):
    with client(tmp_path) as c:
        test = upload(c, [setup_file(0), setup_file(1, references_last=True)]).json()
        assert test["proposed"] == [[0, 1], [3, 4]] and test["proposed_names"] == ["P2", "P5"]


def test_the_page_and_the_library_give_one_answer_on_generic_names(tmp_path):
    """The tower of tests/simulated_setups.py as the files of issue 36: no time column (40 Hz typed), channels
    ch1..ch8, the references the last two channels. The names would propose ch1..ch6 (wrong); the data propose
    ch5, ch6 / ch7, ch8; the page's merge equals the library's on the same files: each read by era.load both ways
    (every channel as NExT reference; the references only), era.analyse, era.merge_choosing_next (300 s records:
    both ways find the five modes complete, every channel's shapes the more consistent)."""
    files = [tower_file(k, 12_000, seed=1) for k in range(4)]
    with client(tmp_path) as c:
        test = upload(c, files, dt="0.025").json()
        assert test["proposed_from"] == "data", test["data_proposal"]
        assert test["proposed"] == [[4, 5], [6, 7], [6, 7], [6, 7]]
        assert len(test["shared_hz"]) == 5 and test["candidates"][0]["channels"][1] == ["ch7", "ch8"]
        assert test["candidates"][0]["score"] > 0.99 > test["candidates"][1]["score"]
        merged = c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"]}).json()["merged"]
        assert merged["geometry"] is None
        # the points table places every merged point on the tower: the same modes, now on its nodes
        table = tower_geometry_csv()
        placed = c.post(f"/api/setups/{test['id']}/merge",
                        json={"references": test["proposed"], "points": table}).json()["merged"]
        assert placed["modes"] == merged["modes"] and placed["points_table"] == table
        g = placed["geometry"]
        assert len(g["node_ids"]) == 24 and len(g["edges"]) == 23 and min(g["channel_nodes"]) >= 0
        height = np.array(g["coordinates"])[g["channel_nodes"], 2] / 60
        heights = TOWER_HEIGHTS[TOWER_REFERENCES + [i for rov in TOWER_ROVING for i in rov]]
        np.testing.assert_allclose(height, heights, atol=1e-4)
        assert all(d == [1.0, 0.0, 0.0] for d in g["channel_directions"])
        # UFF 55 at those nodes: read back with pyuff, each node's x value is the merged shape at its point
        path = tmp_path / "tower.uff"
        path.write_bytes(c.get(f"/api/setups/{test['id']}/modes.uff").content)
        sets = [s for s in pyuff.UFF(str(path)).read_sets() if s["type"] == 55]
        assert len(sets) == 5
        node_of = np.array(g["node_ids"])[g["channel_nodes"]]
        for j, s in enumerate(sets):
            at = dict(zip(np.asarray(s["node_nums"], int), s["r1"]))
            np.testing.assert_allclose([at[n] for n in node_of], shapes_of(placed)[:, j], atol=1e-5)
        # a table that misses points, or names one the test does not have, is refused next to it
        short = "\n".join(table.splitlines()[:5])
        r = c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"], "points": short})
        assert r.status_code == 422 and r.json()["option"] == "points"
        assert "has no row for" in r.json()["error"]
        r = c.post(f"/api/setups/{test['id']}/merge",
                   json={"references": test["proposed"], "points": table.replace("S2:ch1", "S9:ch1")})
        assert r.status_code == 422 and "S9:ch1" in r.json()["error"]
    every, only = [], []
    for (name, blob), refs in zip(files, test["proposed"]):
        (tmp_path / name).write_bytes(blob)
        every.append(era.analyse(era.load(tmp_path / name, dt=0.025, kind="ambient").data))
        only.append(era.analyse(era.load(tmp_path / name, dt=0.025, kind="ambient", references=refs).data))
    choice = era.merge_choosing_next(every, only, test["proposed"])
    library = choice.result.model
    assert merged["next_references"] == choice.used == "every" and merged["next_complete"] == [5, 5]
    assert merged["next_choice"] == choice.reason
    np.testing.assert_allclose([m["frequency_hz"] for m in merged["modes"]], library.frequency_hz, rtol=1e-9)
    np.testing.assert_allclose(shapes_of(merged), library.point_shapes, atol=1e-6)
    assert merged["points"] == list(library.points)
    assert len(merged["modes"]) == 5 and all(m["complete"] for m in merged["modes"])
    np.testing.assert_allclose(library.frequency_hz, TOWER_HZ, rtol=0.01)
    order = TOWER_REFERENCES + [i for rov in TOWER_ROVING for i in rov]
    macs = np.diag(era.mac(library.point_shapes, tower_truth(order)))
    print("tower through the page: MAC with the exact shapes", macs.round(5))
    assert np.all(macs >= 0.99)


def test_one_file_and_unreadable_files_are_refused_next_to_the_file_control(tmp_path):
    with client(tmp_path) as c:
        r = upload(c, [setup_file(0)])
        assert r.status_code == 422 and r.json()["option"] == "file"
        assert "a multi-setup test needs 2 files or more" in r.json()["error"]
        r = upload(c, [setup_file(0), ("notes.csv", b"this is not, a record\nat, all\n")])
        assert r.status_code == 422 and r.json()["error"].startswith("Setup 2 (notes.csv): ")
        assert r.json()["option"] in ("file", "dt", "kind")
        r = c.post("/api/setups", files=[("file", setup_file(0)), ("file", setup_file(1))], data={"kind": "modal"})
        assert r.status_code == 422 and r.json()["option"] == "kind"
        assert c.get("/api/setups/no-such-test").status_code == 404


def test_names_propose_only_when_the_data_cannot_and_the_names_are_not_generic():
    from app.setups import proposal

    none = era.ReferenceProposal(None, np.zeros(0), np.zeros((2, 0), int), (), "too few shared modes")
    generic = [["ch1", "ch2", "ch3", "ch4"], ["ch1", "ch2", "ch3", "ch4", "ch5", "ch6"]]
    said = proposal(generic, none)
    assert said["proposed_from"] == "" and said["proposed"] == [[], []] and said["data_proposal"] == "too few shared modes"
    named = [["P2", "P5", "P1"], ["P7", "P5", "P2"]]
    said = proposal(named, none)
    assert said["proposed_from"] == "names" and said["proposed"] == [[0, 1], [2, 1]]
    assert said["proposed_names"] == ["P2", "P5"]
