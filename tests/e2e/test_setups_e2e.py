"""Issue 26 in a real browser: a multi-setup ambient test uploaded as four CSV files (one per setup) on /setups;
the picker proposes P2 and P5 (the channels named alike in every setup); a wrong pick is refused next to the
picker; the merge shows four modes, each seen in 4 of 4 setups, with the shape at all twelve points (MAC ≥ 0.99
with the truth); the test's link reopens the same result in a new tab. Same server and browser as the other
browser tests (app_server.py, conftest.py); screenshots to $APP_SHOTS when set."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import era
from app_server import Server, table_rows

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from simulated_setups import (FREQUENCY_HZ, TOWER_HZ, setup_file, setup_npz, tower_file,  # noqa: E402
                              tower_geometry_csv, truth_at)

pytestmark = pytest.mark.e2e

POINTS = ["P2", "P5", "P1", "P3", "P4", "P6", "P7", "P8", "P9", "P10", "P11", "P12"]


def shown_shape(page) -> tuple[list, np.ndarray]:
    bars = page.evaluate("""() => { const d = document.getElementById('setups-shape-plot').data;
                                    return { x: d[0].x, re: d[0].y, im: d[1].y }; }""")
    return bars["x"], np.array(bars["re"], dtype=float) + 1j * np.array(bars["im"], dtype=float)


def test_four_setups_uploaded_picked_merged_and_reopened(tmp_path, browser, shots):
    files = []
    for k in range(4):
        name, blob = setup_file(k)
        (tmp_path / name).write_bytes(blob)
        files.append(str(tmp_path / name))
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page = browser.new_page(viewport={"width": 1400, "height": 1100})
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(server.base + "/")
        page.click("#setups-entry")  # the main page's way to a multi-setup test
        page.wait_for_url("**/setups")

        # one file is refused next to the file control
        page.set_input_files("#setups-files", files[:1])
        page.click("#setups-upload")
        page.wait_for_selector("#setups-file-error:not([hidden])")
        assert "needs 2 files or more" in page.text_content("#setups-file-error")

        page.set_input_files("#setups-files", files)
        page.fill("#setups-name", "beam <b>")
        page.click("#setups-upload")
        page.wait_for_selector("#setups-refs:not([hidden]) #setups-ref-table tbody tr", timeout=60000)
        assert page.is_hidden("#setups-file-error")
        assert "/s/" in page.url
        assert "P2, P5" in page.text_content("#setups-proposal")
        picks = page.eval_on_selector_all("#setups-ref-table select", "s => s.map(x => x.selectedOptions[0].text)")
        assert picks == ["P2"] * 4 + ["P5"] * 4

        # a wrong pick: setup 3's second reference is its roving P9
        page.select_option("#setups-ref-table select[data-setup='2'][data-row='1']", label="P9")
        page.click("#setups-merge")
        page.wait_for_selector("#setups-references-error:not([hidden])", timeout=120000)
        said = page.text_content("#setups-references-error")
        assert "Setup 3's reference channels [0, 2] do not move like" in said and "in the picker" in said
        assert page.is_hidden("#setups-result")

        page.select_option("#setups-ref-table select[data-setup='2'][data-row='1']", label="P5")
        page.click("#setups-merge")
        page.wait_for_selector("#setups-result:not([hidden]) #setups-modes tbody tr", timeout=120000)
        assert page.is_hidden("#setups-references-error")
        rows = table_rows(page, "#setups-modes")
        assert len(rows) == 4 and all(r["cells"]["seen"] == "seen in 4 of 4 setups" for r in rows)
        freqs = [float(r["cells"]["frequency_hz"]) for r in rows]
        np.testing.assert_allclose(freqs, FREQUENCY_HZ, rtol=0.01)
        assert "Every mode is known at every point" in page.text_content("#setups-uff-note")

        macs = []
        for j in range(4):
            page.click(f"#setups-modes tbody tr[data-mode='{j}'] td[data-key=frequency_hz]")
            page.wait_for_function("document.getElementById('setups-shape-title').textContent"
                                   f".startsWith('mode {j + 1}:')")
            x, shape = shown_shape(page)
            assert x == POINTS and np.all(np.isfinite(shape))
            macs.append(era.mac(shape, truth_at(x)[:, j])[0, 0])
        print("merged MAC with the truth, as drawn:", np.round(macs, 5))
        assert min(macs) >= 0.99
        # no geometry: the points drawn in a row in the order of their names, the shape through them (mode 4)
        drawn = page.evaluate("() => { const d = document.getElementById('setups-drawing').data[1]; "
                              "return { x: d.x, y: d.y }; }")
        assert drawn["x"] == [f"P{i}" for i in range(1, 13)]
        assert era.mac(np.array(drawn["y"], dtype=float), truth_at(drawn["x"])[:, 3])[0, 0] >= 0.99
        page.wait_for_selector("#setups-viewer iframe, #setups-viewer .note", state="attached", timeout=60000)
        page.screenshot(path=str(shots / "setups-merged.png"), full_page=True)
        assert page.evaluate("window.__xss") is None and "beam <b>" in page.text_content("#setups-title")

        # the link reopens the merged result
        link = page.get_attribute("#setups-link", "href")
        again = browser.new_page(viewport={"width": 1400, "height": 1100})
        again.on("pageerror", lambda e: errors.append(str(e)))
        again.goto(link)
        again.wait_for_selector("#setups-result:not([hidden]) #setups-modes tbody tr", timeout=30000)
        assert [r["cells"]["frequency_hz"] for r in table_rows(again, "#setups-modes")] == \
            [r["cells"]["frequency_hz"] for r in rows]
        x, shape = shown_shape(again)
        assert x == POINTS and era.mac(shape, truth_at(x)[:, 0])[0, 0] >= 0.99
        picks = again.eval_on_selector_all("#setups-ref-table select", "s => s.map(x => x.selectedOptions[0].text)")
        assert picks == ["P2"] * 4 + ["P5"] * 4
        assert not errors, errors
    finally:
        server.stop()


def test_setups_with_a_geometry_draw_the_merged_shape_on_it(tmp_path, browser):
    """Each setup's NPZ places its channels on the beam's nodes: the drawing is the beam in 3-D with all twelve
    nodes moved by the merged shape, and the viewer shows it."""
    files = []
    for k in range(4):
        name, blob = setup_npz(k)
        (tmp_path / name).write_bytes(blob)
        files.append(str(tmp_path / name))
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page = browser.new_page(viewport={"width": 1400, "height": 1100})
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(server.base + "/setups")
        page.select_option("#setups-kind", "auto")
        page.set_input_files("#setups-files", files)
        page.click("#setups-upload")
        page.wait_for_selector("#setups-refs:not([hidden]) #setups-ref-table tbody tr", timeout=60000)
        page.click("#setups-merge")
        page.wait_for_selector("#setups-result:not([hidden]) #setups-modes tbody tr", timeout=120000)
        page.click("#setups-modes tbody tr[data-mode='1'] td[data-key=frequency_hz]")
        page.wait_for_function("document.getElementById('setups-shape-title').textContent.startsWith('mode 2:')")
        drawn = page.evaluate("""() => { const d = document.getElementById('setups-drawing').data;
                                         return { types: d.map(t => t.type), x: d[2].x, z: d[2].z }; }""")
        assert drawn["types"] == ["scatter3d"] * 3
        x, z = np.array(drawn["x"]), np.array(drawn["z"])
        assert x.size == 12 and np.all(np.diff(x) > 0)  # nodes 1-12 along the beam
        # the second bending shape: the two halves move against each other, as sin(2 π x)
        assert era.mac(z, truth_at([f"P{i}" for i in range(1, 13)])[:, 1])[0, 0] >= 0.99
        page.wait_for_selector("#setups-viewer iframe", state="attached", timeout=60000)
        assert not errors, errors
    finally:
        server.stop()


def test_a_tower_with_generic_names_and_a_points_file_is_drawn_on_its_geometry(tmp_path, browser, shots):
    """The files of issue 36 (no time column, channels ch1..ch8, the references the last two): the page proposes
    ch5, ch6 / ch7, ch8 from the data with its evidence; with the points file (point,x,y,z,direction and the lines
    up the tower) the merged modes are drawn on the tower in 3-D, each its exact shear-cantilever shape, and the
    viewer shows them; a report of the merge reopens them on the tower."""
    files = []
    for k in range(4):
        name, blob = tower_file(k, 12_000, seed=1)
        (tmp_path / name).write_bytes(blob)
        files.append(str(tmp_path / name))
    (tmp_path / "points.csv").write_text(tower_geometry_csv())
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page = browser.new_page(viewport={"width": 1400, "height": 1100})
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(server.base + "/setups")
        page.set_input_files("#setups-files", files)
        page.fill("#setups-rate", "40")
        page.click("#setups-upload")
        page.wait_for_selector("#setups-refs:not([hidden]) #setups-ref-table tbody tr", timeout=180000)
        assert page.text_content("#setups-proposal").startswith("Proposed from the data: ch5, ch6 in setup 1; ch7, ch8")
        picks = page.eval_on_selector_all("#setups-ref-table select", "s => s.map(x => x.selectedOptions[0].text)")
        assert picks == ["ch5", "ch7", "ch7", "ch7", "ch6", "ch8", "ch8", "ch8"]
        evidence = table_rows(page, "#setups-evidence")
        assert len(evidence) >= 2 and len(page.eval_on_selector_all("#setups-evidence thead th", "t => t")) == 3 + 5
        page.click("#setups-points-box summary")
        page.set_input_files("#setups-points-file", str(tmp_path / "points.csv"))
        page.wait_for_function("document.getElementById('setups-points').value.startsWith('point,x,y,z')")
        page.click("#setups-merge")
        page.wait_for_selector("#setups-result:not([hidden]) #setups-modes tbody tr", timeout=180000)
        rows = table_rows(page, "#setups-modes")
        np.testing.assert_allclose([float(r["cells"]["frequency_hz"]) for r in rows], TOWER_HZ, rtol=0.01)
        assert all(r["cells"]["seen"] == "seen in 4 of 4 setups" for r in rows)
        # NExT's references chosen from the data (both ways merged), the choice said
        assert page.text_content("#setups-next-note").startswith("NExT references: Kept every channel as NExT reference")
        assert page.input_value("#setups-next") == "auto"
        assert "on the 24 nodes given" in page.text_content("#setups-drawing-note")
        macs = []
        for j in range(5):
            page.click(f"#setups-modes tbody tr[data-mode='{j}'] td[data-key=frequency_hz]")
            page.wait_for_function("document.getElementById('setups-shape-title').textContent"
                                   f".startsWith('mode {j + 1}:')")
            drawn = page.evaluate("""() => { const d = document.getElementById('setups-drawing').data;
                                             return { types: d.map(t => t.type), x: d[2].x, z: d[2].z }; }""")
            assert drawn["types"] == ["scatter3d"] * 3 and len(drawn["z"]) == 24
            sway, height = np.array(drawn["x"], float), np.array(drawn["z"], float) / 60
            macs.append(era.mac(sway, np.sin((2 * j + 1) * np.pi / 2 * height))[0, 0])
        print("tower as drawn on its points, MAC with the exact shapes:", np.round(macs, 5))
        assert min(macs) >= 0.99
        page.wait_for_selector("#setups-viewer iframe", state="attached", timeout=60000)
        page.screenshot(path=str(shots / "setups-tower.png"), full_page=True)
        # a report of the merge: its link reopens the merged modes on the tower, read-only
        page.click("#setups-freeze")
        page.wait_for_selector("#setups-report-share:not([hidden]) a[href*='/r/']")
        report = page.get_attribute("#setups-report-link", "href")
        page.goto(report)
        page.wait_for_selector("#setups-result:not([hidden]) #setups-modes tbody tr", timeout=60000)
        assert page.is_hidden("#setups-new") and page.is_hidden("#setups-refs")
        assert page.text_content("#setups-report-note").startswith("Read-only report, frozen ")
        assert len(table_rows(page, "#setups-modes")) == 5
        assert "on the 24 nodes given" in page.text_content("#setups-drawing-note")
        drawn = page.evaluate("() => document.getElementById('setups-drawing').data.map(t => t.type)")
        assert drawn == ["scatter3d"] * 3
        assert not errors, errors
    finally:
        server.stop()
