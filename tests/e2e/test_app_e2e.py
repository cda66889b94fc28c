"""The whole web app in a real browser: upload, order slider, pole click, keep/reject, report link, restart,
the same table from the link (and from the offline HTML download).

Runs `uvicorn app.main:app` in a subprocess on a free 127.0.0.1 port with a temporary ERA_DATA_DIR and drives
Debian's Chromium (never downloaded). Screenshots go to $APP_SHOTS if set (to look at them), else to tmp_path.
"""

from __future__ import annotations

import json
import os
import urllib.request

import pytest

import era
import era.examples.paper_cases
from app_server import Server, open_page, table_rows

pytestmark = pytest.mark.e2e

EVIL = "<img src=x onerror=window.__xss=1>"


def pole_position(page, order: int):
    """Page coordinates of a pole of the given order that is stable in frequency, damping and shape, and not drawn
    on top of another (the two poles of a repeated pair share one place: a click there picks either)."""
    return page.evaluate("""(order) => {
        const div = document.getElementById('stab-plot'), fl = div._fullLayout;
        const t = div.data.find(tr => tr.name.startsWith('stable f'));
        const at = t.y.flatMap((y, k) => (y === order ? [k] : []));
        const k = at.find(k => !at.some(j => j !== k && Math.abs(t.x[j] - t.x[k]) < 1e-3 * t.x[k]));
        if (k === undefined) return null;
        const box = div.getBoundingClientRect();
        return { x: box.left + fl.xaxis._offset + fl.xaxis.l2p(t.x[k]), y: box.top + fl.yaxis._offset + fl.yaxis.l2p(t.y[k]),
                 order: t.customdata[k][0], index: t.customdata[k][1], frequency: t.x[k] };
    }""", order)


def test_upload_to_report_survives_a_restart(tmp_path, browser, shots):
    data_dir = tmp_path / "data"
    upload = tmp_path / "case2 <i>italic.npz"
    case2 = era.examples.paper_cases.case_2(200, mimo=True)
    era.save_npz(str(upload), era.ResponseData(case2.markov, case2.dt, outputs=(EVIL, "sensor 2"),
                                               inputs=("IC <b>1</b>", "IC 2")))
    server = Server(data_dir, tmp_path / "server1.log")
    try:
        page, errors = open_page(server, browser)

        # 1. upload through the drop zone's file input, see what was read, use it; the defaults identify at once
        page.set_input_files("#file", str(upload))
        page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr")
        assert page.text_content("#import-channels tbody tr td:nth-child(2)") == EVIL  # a name, shown as text
        page.click("#import-use")
        page.wait_for_selector("#summary:not([hidden])")
        page.wait_for_selector("#modes-table tbody tr")
        summary = page.text_content("#summary")
        assert EVIL in summary and "case2 <i>italic.npz" in summary  # names shown as text
        assert page.locator("#summary img, #summary i").count() == 0
        assert page.evaluate("window.__xss") is None
        page.wait_for_selector("#recon-plot .ytitle")
        assert "IC <b>1</b>" in page.text_content("#recon-plot .ytitle")  # plotly shows it as typed, not bold
        assert page.locator("#recon-plot .ytitle b, #recon-plot .ytitle [style*=bold]").count() == 0
        assert page.input_value("#rows") == "90" and page.input_value("#max-order") == "180"
        assert page.text_content("#order-value") == "10"
        assert len(table_rows(page, "#modes-table")) == 5
        page.wait_for_function("document.getElementById('stab-plot').data?.length > 3")
        # the server's rules, shown: coherence, and era's choice (noise-free Case II is of exact rank 10: its five
        # modes at order 10, the order and the ticks the page opens with)
        page.wait_for_function("document.getElementById('stab-status').textContent.includes('coherent')")
        assert "coherent, mean γ·μ ≥ 0.9" in page.text_content("#stab-status")
        assert "era chose 5 modes of the structure, read at order 10" in page.text_content("#stab-status")
        assert "Ticked: the 5 modes era chose at order 10" in page.text_content("#table-rule")
        assert all(r["kept"] for r in table_rows(page, "#modes-table"))
        page.screenshot(path=str(shots / "app-1-uploaded.png"), full_page=True)

        # 2. move the order slider (keyboard on the range input): table and reconstruction follow
        page.focus("#order")
        page.keyboard.press("ArrowLeft")
        page.keyboard.press("ArrowLeft")
        page.wait_for_function("document.getElementById('order-value').textContent === '8' && "
                               "document.querySelectorAll('#modes-table tbody tr').length === 4")
        page.wait_for_function("window.eraTiming.parts.some(p => p.order === 8)")
        # single steps, each to its end: every one shows its own order's table; timed by the page (window.eraTiming)
        for key, order, modes in (("ArrowRight", 9, 5), ("ArrowRight", 10, 5), ("ArrowLeft", 9, 5), ("ArrowLeft", 8, 4)):
            page.keyboard.press(key)
            page.wait_for_function(f"window.eraTiming.parts.at(-1).order === {order} && "
                                   f"document.getElementById('table-note').textContent.endsWith('at order {order}')")
            assert len(table_rows(page, "#modes-table")) == modes and f"of {modes} modes" in page.text_content("#table-note")
        steps = page.evaluate("window.eraTiming.order.slice(-4)")
        print("slider updates (ms, slider -> table + poles + reconstruction drawn):",
              [round(x) for x in page.evaluate("window.eraTiming.order")])
        # generous: CI is a loaded 2-core machine (tests/bench/bench_slider_browser.py measures the real figures)
        assert sorted(steps)[1] < 500, steps
        assert "4 kept modes" in page.text_content("#recon-fit") or "kept modes" in page.text_content("#recon-fit")

        # 3. click a pole of order 10 in the stabilization diagram: order 10 and that mode are selected everywhere
        page.locator("#stab-plot").scroll_into_view_if_needed()
        pole = pole_position(page, 10)
        assert pole is not None, "no stable pole at order 10"
        page.mouse.move(pole["x"], pole["y"])
        page.mouse.click(pole["x"], pole["y"])
        page.wait_for_function("document.getElementById('order-value').textContent === '10'")
        selected = page.locator("#modes-table tbody tr.selected")
        selected.wait_for()
        assert int(selected.get_attribute("data-mode")) == pole["index"]
        assert f"{pole['frequency']:.4f}" in selected.text_content()
        assert f"{pole['frequency']:.4f}" in page.text_content("#shape-title")
        assert page.input_value("#order") == "10"

        # 4. keep/reject: reject the selected mode; the reconstruction is redrawn with one mode fewer
        fit_before = page.text_content("#recon-fit")
        box = selected.locator("input[type=checkbox]")
        assert box.is_checked()
        box.uncheck()
        assert "rejected" in selected.get_attribute("class")
        page.wait_for_function(f"document.getElementById('recon-fit').textContent !== {json.dumps(fit_before)}")
        assert "4 kept modes" in page.text_content("#recon-fit")
        # the shape scatter (1 − MAC) column fills once the slider rests on an order (GET /modes?scatter=true)
        page.wait_for_function("[...document.querySelectorAll('#modes-table td[data-key=shape_scatter]')]"
                               ".every(td => td.textContent !== '–')", timeout=30000)
        app_rows = table_rows(page, "#modes-table")
        assert sum(r["kept"] for r in app_rows) == 4
        assert all(r["cells"]["shape_scatter"] == "0.0000" for r in app_rows)  # noise-free Case II
        page.screenshot(path=str(shots / "app-2-pole-selected-mode-rejected.png"), full_page=True)

        # 5. create the report link
        page.click("#create-report")
        page.wait_for_selector("#report-link-box:not([hidden])")
        link = page.get_attribute("#report-link", "href")
        assert link.startswith("/r/") and len(link) >= 3 + 22
        address = page.evaluate("location.hash")  # #analysis=ID&order=10: a reload reopens the analysis
        assert address.startswith("#analysis=") and address.endswith("&order=10")
        assert not errors, errors
    finally:
        server.stop()

    # 6. restart the server (new process, new port, same data folder) and open the link
    server = Server(data_dir, tmp_path / "server2.log")
    try:
        page = browser.new_page(viewport={"width": 1400, "height": 1000})
        page.goto(server.base + link)
        page.wait_for_selector("body[data-ready='1']", timeout=30000)
        report_rows = table_rows(page, "#report-table")
        assert [r["cells"] for r in report_rows] == [r["cells"] for r in sorted(app_rows, key=lambda r: r["mode"])]
        assert [r["kept"] for r in report_rows] == [r["kept"] for r in sorted(app_rows, key=lambda r: r["mode"])]
        assert EVIL in page.text_content("#report-pair") or EVIL in page.text_content("body")
        assert page.locator("main img").count() == 0
        page.screenshot(path=str(shots / "report-after-restart.png"), full_page=True)

        # the analysis itself reopens from its address after the restart (the SVD is recomputed from the stored data)
        page = browser.new_page(viewport={"width": 1400, "height": 1000})
        page.goto(server.base + "/" + address)
        page.wait_for_function("document.querySelectorAll('#modes-table tbody tr').length === 5", timeout=30000)
        assert page.text_content("#order-value") == "10" and page.input_value("#rows") == "90"
        # the shape scatter (1 − MAC) column fills once the slider rests on an order (GET /modes?scatter=true)
        page.wait_for_function("[...document.querySelectorAll('#modes-table td[data-key=shape_scatter]')]"
                               ".every(td => td.textContent !== '–')", timeout=30000)
        reopened = table_rows(page, "#modes-table")
        assert sorted((r["mode"], tuple(r["cells"].items())) for r in reopened) == \
            sorted((r["mode"], tuple(r["cells"].items())) for r in app_rows)

        # 7. the offline download shows the same table with no server at all
        token = link.rsplit("/", 1)[1]
        html = urllib.request.urlopen(f"{server.base}/api/reports/{token}/report.html", timeout=30).read()
        offline = tmp_path / "report.html"
        offline.write_bytes(html)
    finally:
        server.stop()
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    fetched = []
    page.on("request", lambda req: fetched.append(req.url) if req.url.startswith(("http:", "https:", "ws:")) else None)
    page.goto(offline.as_uri())
    page.wait_for_selector("body[data-ready='1']", timeout=30000)
    assert [r["cells"] for r in table_rows(page, "#report-table")] == [r["cells"] for r in report_rows]
    if os.environ.get("ERA_VIEWER", "1") != "0":  # the kept mode plays in viser's own client, inlined
        frame = page.locator("#report-viewer iframe")
        assert frame.count() == 1 and len(frame.get_attribute("srcdoc") or "") > 100_000
        page.wait_for_timeout(2000)
    assert fetched == [], fetched  # nothing from any server
    page.screenshot(path=str(shots / "report-offline.png"), full_page=True)
