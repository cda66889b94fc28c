"""The simulation-vs-test panel in a real browser: open the grid example, run the panel, read the verdict and the
gap table, then find the same verdict in the report created afterwards.

Same server and browser setup as the other browser tests (app_server.py, conftest.py) (Debian's Chromium, never downloaded).
"""

from __future__ import annotations

import pytest

from app_server import Server, open_page

pytestmark = pytest.mark.e2e


def test_grid_example_panel_names_its_verdict_and_the_report_keeps_it(tmp_path, browser, shots):
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page, errors = open_page(server, browser)
        page.click("#examples button[data-example='grid']")
        page.wait_for_selector("#modes-table tbody tr", timeout=60000)
        page.wait_for_function("!document.getElementById('explain-run').disabled")
        assert page.locator("#field-explain-gravity").is_visible()  # the grid's nominal model: its gravity box
        page.click("#explain-run")
        page.wait_for_selector("#explain-verdict", timeout=120000)

        verdict = page.get_attribute("#explain-verdict", "data-verdict")
        head = page.text_content("#explain-verdict > div")
        assert verdict in {"explained", "no_significant_discrepancy", "ambiguous", "unexplained"}
        words = {"explained": "Explained", "no_significant_discrepancy": "No significant discrepancy",
                 "ambiguous": "Ambiguous", "unexplained": "Unexplained"}[verdict]
        assert head.startswith(words) and "Gap before" in page.text_content("#explain-verdict")
        # what is certain, in the panel's words: the allowance for model-form error the evidence used (none for the
        # grid's own model) and, for a named effect, its place (or "one of these"), size, what the data cannot tell
        assert "Model-form allowance" in page.text_content("#explain-verdict")
        if verdict == "explained":
            named = page.text_content("#explain-effect")
            assert "Place" in named or "Size (95 % interval)" in named, named
            assert "The data cannot tell" in named and "Gap before → after" in named, named
        gap = page.eval_on_selector_all("#explain-gap tbody tr",
                                        "rows => rows.map(r => [...r.cells].map(c => c.textContent))")
        assert [r[0] for r in gap] == ["before (nominal model)", "after (updated model)"]
        assert all(float(v) >= 0 for r in gap for v in r[1:5])
        assert page.locator("#explain-modes tbody tr").count() >= 5
        basis = page.text_content("#explain-basis")  # what was compared: this analysis's H(0) and orders
        assert "This analysis's H(0)" in basis and "era chose at order" in basis  # the table's default ticks
        for plot in ("#explain-mac-before", "#explain-mac-after", "#explain-overlay", "#explain-shape-measured"):
            page.wait_for_selector(f"{plot} .main-svg")
        page.wait_for_timeout(1500)
        page.locator("#panel-explain").screenshot(path=str(shots / "explain-panel.png"))

        # the modes kept in the table at the current order: the panel says it compared exactly those
        kept = page.locator("#modes-table tbody input[type=checkbox]:checked").count()
        order = page.input_value("#order")
        page.select_option("#explain-which", "kept")
        page.click("#explain-run")
        page.wait_for_function(f"(document.getElementById('explain-basis') || {{}}).textContent"
                               f"?.includes('kept at order {order}')", timeout=120000)
        assert f"the {kept} {'mode' if kept == 1 else 'modes'} kept at order {order}" in page.text_content("#explain-basis")
        head = page.text_content("#explain-verdict > div")

        # a report created now freezes the result; its page draws the same verdict read-only
        page.click("#create-report")
        page.wait_for_selector("#report-link-box:not([hidden])", timeout=60000)
        page.goto(server.base + page.get_attribute("#report-link", "href"))
        page.wait_for_selector("body[data-ready='1']", timeout=60000)
        assert page.is_visible("#report-explain-card")
        assert page.text_content("#report-explain-verdict > div") == head
        assert page.locator("#report-explain-gap tbody tr").count() == 2
        page.locator("#report-explain-card").screenshot(path=str(shots / "explain-report.png"))
        assert errors == [], errors
    finally:
        server.stop()
