"""A multi-setup test merged by PreGER in a real browser, and its report downloaded and opened with no server.

The beam of tests/simulated_setups.py (four ambient setups, references P2 and P5, the twelve points typed as a
points table): the engineer picks "PreGER" beside the merge; the page says PreGER ran, its modes table says each
mode was identified once from all four setups, and the shapes as drawn match the beam's exact sin(jπx) shapes
(MAC ≥ 0.97: PreGER's one factor per setup holds only roughly here, as the setups' excitation levels differ) at
every point, on the points' geometry. Back to PoSER, the page says PoSER. The frozen report's HTML download opens
from a file with every network request refused: the same modes table and shape on the geometry, plotly.js inside
it. Same server and browser as the other browser tests (app_server.py, conftest.py)."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest

import era
from app_server import table_rows

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from simulated_setups import FREQUENCY_HZ, X, setup_file, truth_at  # noqa: E402

pytestmark = pytest.mark.e2e

#: The beam's points as an engineer types them: along x (m), each sensor vertical; the lines between neighbours.
POINTS_TABLE = ("point,x,y,z,direction\n" + "".join(f"P{i + 1},{x:.4f},0,0,z\n" for i, x in enumerate(X))
                + "from,to\n" + "".join(f"P{i},P{i + 1}\n" for i in range(1, 12)))


def drawn_macs(page) -> list[float]:
    """For each of the beam's four modes, the MAC of the nearest merged mode's shape as drawn with the truth."""
    rows = table_rows(page, "#setups-modes")
    freqs = np.array([float(r["cells"]["frequency_hz"]) for r in rows])
    macs = []
    for j, f in enumerate(FREQUENCY_HZ):
        k = int(np.argmin(np.abs(freqs - f)))
        assert abs(freqs[k] - f) <= 0.01 * f
        page.click(f"#setups-modes tbody tr[data-mode='{k}'] td[data-key=frequency_hz]")
        page.wait_for_function(f"document.getElementById('setups-shape-title').textContent.startsWith('mode {k + 1}:')")
        bars = page.evaluate("""() => { const d = document.getElementById('setups-shape-plot').data;
                                        return { x: d[0].x, re: d[0].y, im: d[1].y }; }""")
        shape = np.array(bars["re"], dtype=float) + 1j * np.array(bars["im"], dtype=float)
        assert len(bars["x"]) == 12 and np.all(np.isfinite(shape))
        macs.append(era.mac(shape, truth_at(bars["x"])[:, j])[0, 0])
    return macs


def on_geometry(page) -> bool:
    """The drawing is the beam in 3-D: the lines at rest and moved, and its twelve points."""
    return page.evaluate("""() => { const d = document.getElementById('setups-drawing').data;
        return d.length === 3 && d.every(t => t.type === 'scatter3d') && d[2].x.length === 12; }""")


def test_preger_chosen_on_the_page_and_the_report_opened_offline(tmp_path, browser, server, shots):
    files = []
    for k in range(4):
        name, blob = setup_file(k)
        (tmp_path / name).write_bytes(blob)
        files.append(str(tmp_path / name))
    page = browser.new_page(viewport={"width": 1400, "height": 1100})
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(server.base + "/setups")
    page.set_input_files("#setups-files", files)
    page.click("#setups-upload")
    page.wait_for_selector("#setups-refs:not([hidden]) #setups-ref-table tbody tr", timeout=120000)
    page.evaluate("document.getElementById('setups-points-box').open = true")
    page.fill("#setups-points", POINTS_TABLE)

    page.select_option("#setups-method", "preger")
    assert page.is_hidden("#setups-next-field")  # PreGER correlates with the picked references: no NExT choice
    page.click("#setups-merge")
    page.wait_for_selector("#setups-result:not([hidden]) #setups-modes tbody tr", timeout=120000)
    assert page.text_content("#setups-merge-status").startswith("Merged by PreGER:")
    assert "Merged by PreGER" in page.text_content("#setups-method-note")
    assert "Scales 1, " in page.text_content("#setups-next-note")
    rows = table_rows(page, "#setups-modes")
    assert rows and all(r["cells"]["seen"] == "identified once from all 4 setups (PreGER)" for r in rows)
    assert "Every mode is known at every point" in page.text_content("#setups-uff-note")
    macs = drawn_macs(page)
    print("PreGER as drawn, MAC with the exact shapes:", np.round(macs, 4))
    assert min(macs) >= 0.97
    assert on_geometry(page)
    page.screenshot(path=str(shots / "setups-preger.png"), full_page=True)

    page.select_option("#setups-method", "poser")
    assert page.is_visible("#setups-next-field")
    page.click("#setups-merge")
    page.wait_for_function("document.getElementById('setups-merge-status').textContent.startsWith('Merged by PoSER')",
                           timeout=120000)
    assert "Merged by PoSER" in page.text_content("#setups-method-note")
    poser_rows = table_rows(page, "#setups-modes")
    assert [r["cells"]["seen"] for r in poser_rows] == ["seen in 4 of 4 setups"] * 4

    # the report, frozen, then downloaded as one file and opened with no server
    page.click("#setups-freeze")
    page.wait_for_selector("#setups-report-share:not([hidden])")
    report = browser.new_page(viewport={"width": 1400, "height": 1100})
    report.on("pageerror", lambda e: errors.append(str(e)))
    report.goto(page.get_attribute("#setups-report-link", "href"))
    report.wait_for_selector("#setups-result:not([hidden]) #setups-html:not([hidden])", timeout=60000)
    with report.expect_download() as got:
        report.click("#setups-html")
    path = tmp_path / "report.html"
    got.value.save_as(path)
    html = path.read_text(encoding="utf-8")
    assert "<script src=" not in html and "<link rel=\"stylesheet\"" not in html  # plotly.js and the CSS inside

    context = browser.new_context(viewport={"width": 1400, "height": 1100})
    requested = []
    context.route(re.compile(r"^(https?|wss?)://"), lambda route: (requested.append(route.request.url), route.abort()))
    offline = context.new_page()
    offline.on("pageerror", lambda e: errors.append(str(e)))
    offline.goto(path.as_uri())
    offline.wait_for_selector("#setups-result:not([hidden]) #setups-modes tbody tr", timeout=30000)
    assert offline.is_hidden("#setups-new") and offline.is_hidden("#setups-refs")
    assert "report" in offline.text_content("#setups-title")
    assert table_rows(offline, "#setups-modes") == poser_rows
    assert min(drawn_macs(offline)) >= 0.99  # PoSER's shapes, as frozen
    assert on_geometry(offline)
    assert offline.get_attribute("#setups-csv", "href").startswith("data:text/csv;base64,")
    assert "needs the app" in offline.text_content("#setups-viewer")
    offline.screenshot(path=str(shots / "setups-report-offline.png"), full_page=True)
    assert not requested, requested  # nothing from a server
    assert not errors, errors
