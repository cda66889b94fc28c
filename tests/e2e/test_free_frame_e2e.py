"""Issue 27 in a real browser: the NASA grid example, "Describe it from the test geometry", the model step's default
section (solid rectangle 50 × 6 mm) in steel, no supports (free-free: the grid hangs on soft cords). Save shows the
free frame's elastic frequencies (not six zeros), and Run simulation vs test ends in a verdict in words — it used
to answer "Internal error" (HTTP 500).

Same server and browser setup as the other browser tests (app_server.py, conftest.py) (Debian's Chromium, never downloaded).
"""

from __future__ import annotations

import pytest

from app_server import Server, open_page

pytestmark = pytest.mark.e2e


def test_the_free_free_grid_from_its_test_geometry_is_explained_in_words(tmp_path, browser, shots):
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page, errors = open_page(server, browser)
        page.click("#examples button[data-example='grid']")
        page.wait_for_selector("#modes-table tbody tr", timeout=60000)
        page.wait_for_function("!document.getElementById('model-from-geometry').disabled")
        page.click("#model-from-geometry")
        page.wait_for_selector("#model-sections tbody tr")
        assert page.locator("#model-nodes tbody tr").count() == 88
        for g in page.eval_on_selector_all("#model-sections tbody tr", "rows => rows.map(r => r.dataset.group)"):
            row = page.locator(f"#model-sections tr[data-group='{g}']")
            assert row.locator("input[data-size=width]").input_value() == "50"       # the default section
            assert row.locator("input[data-size=depth]").input_value() == "6"
            row.locator("select.material").select_option("steel")
        page.click("#model-save")
        page.wait_for_selector("#model-summary:not([hidden])", timeout=60000)
        assert page.is_hidden("#model-error")
        summary = page.text_content("#model-summary")
        assert "88 nodes" in summary and "none (free-free)" in summary
        assert " 0 Hz" not in summary and "0, 0, 0" not in summary, summary     # the rigid-body modes left out

        page.wait_for_function("!document.getElementById('explain-run').disabled")
        page.click("#explain-run")
        page.wait_for_selector("#explain-verdict, #explain-error:not([hidden])", timeout=240000)
        assert page.is_hidden("#explain-error"), page.text_content("#explain-error")
        verdict = page.get_attribute("#explain-verdict", "data-verdict")
        assert verdict in {"explained", "no_significant_discrepancy", "ambiguous", "unexplained"}
        assert "Gap before" in page.text_content("#explain-verdict")
        assert "88 nodes" in page.text_content("#explain-model")
        page.locator("#panel-explain").screenshot(path=str(shots / "free-frame-explain.png"))
        assert errors == [], errors
    finally:
        server.stop()
