"""A campaign in a real browser: from the main page's link, upload a few monitoring records (one of them cut off),
watch the campaign run, read the tracking plots and the failed record, open the report link, download the table
and the report as one HTML file that opens with no server.

Same server and browser setup as the other browser tests (app_server.py, conftest.py) (Debian's Chromium, never downloaded); the records are
era.campaign.simulated's monitored structure (five modes, six sensors), short enough for seconds per record.
"""

from __future__ import annotations

import urllib.request

import pytest

from era.campaign.simulated import monitoring_truth, write_campaign
from app_server import Server, open_page

pytestmark = pytest.mark.e2e
CORRUPT = "rec_2026-03-02T12-00.csv"


def test_upload_records_as_a_campaign_see_the_tracking_and_open_its_report_link(tmp_path, browser, shots,
                                                                                 monkeypatch):
    paths = write_campaign(tmp_path / "records", monitoring_truth(4, hours_between=3.0, damage_from=2,
                                                                  duration_s=300.0), seed=3)
    whole = open(paths[0], "rb").read()
    corrupt = tmp_path / "records" / CORRUPT  # a transfer that stopped half-way through a line
    corrupt.write_bytes(whole[: len(whole) // 2])
    monkeypatch.setenv("ERA_VIEWER", "0")
    monkeypatch.setenv("ERA_CAMPAIGN_WORKERS", "2")
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page, errors = open_page(server, browser, 1100)
        page.click("#campaigns-link")
        page.wait_for_selector("#campaign-new:not([hidden])")
        assert "local process" in page.text_content("#campaign-engine")
        page.set_input_files("#campaign-files", [str(p) for p in paths] + [str(corrupt)])
        page.fill("#campaign-name", "bridge <b>March</b>")
        page.select_option("#campaign-kind", "ambient")
        page.fill("#campaign-order", "80")  # the form's default: the choice weighs modes against the top order's noise poles
        page.click("#campaign-start")
        page.wait_for_url("**/c/*")
        page.wait_for_selector("body[data-ready='1']", timeout=120000)

        # the plots: one trace per tracked mode, a value where the record shows it
        n_modes = page.locator("#campaign-modes tbody tr").count()
        assert 4 <= n_modes <= 6
        # each tracked mode's identification rate, as the table's "found in" counts say
        rows = page.evaluate("[...document.querySelectorAll('#campaign-modes tbody tr')].map(tr => "
                             "[...tr.cells].map(td => td.textContent))")
        assert page.text_content("#campaign-modes thead th:last-child") == "identification rate"
        for row in rows:
            found, held = (int(w) for w in row[5].split()[0:3:2])  # "4 of 4 records"
            assert row[6] == f"{100 * found / held:.1f} %", row
        for plot in ("#campaign-freq", "#campaign-damp", "#campaign-mac"):
            traces = page.evaluate(f"document.querySelector('{plot}').data.map(t => t.y.filter(v => v !== null)"
                                   ".length)")
            assert len(traces) == n_modes and sum(traces) >= 3 * n_modes, (plot, traces)
            assert page.locator(f"{plot} .main-svg .scatterlayer .trace").count() == n_modes
        x = page.evaluate("document.getElementById('campaign-freq').data[0].x")
        assert x[0].startswith("2026-03-02T00:00") and len(x) == 5 - 1  # dated from the names; the corrupt one out
        f = page.evaluate("document.getElementById('campaign-freq').data.map(t => Math.max(...t.y.filter(v => v)))")
        assert 1.2 < min(f) < 1.3 and 6.0 < max(f) < 6.4  # the simulated structure's first and last modes
        mac = page.evaluate("document.getElementById('campaign-mac').data.flatMap(t => t.y.filter(v => v !== null))")
        assert min(mac) > 0.8 and max(mac) <= 1.0 + 1e-9

        # relative to each mode's reference: the simulated damage (mode 2.44 Hz, -3 % from the third record, -4.3 %
        # with the temperature by the fourth) stands out of the others' temperature drift (at most -1.4 % here)
        page.select_option("#campaign-freq-scale", "change")
        page.wait_for_function("document.getElementById('campaign-freq')._fullLayout.yaxis.title.text"
                               ".startsWith('change')")
        rel = page.evaluate("""document.getElementById('campaign-freq').data.map(t => [t.name,
                               Math.min(...t.y.filter(v => v !== null)), Math.max(...t.y.filter(v => v !== null))])""")
        damaged = [lo for name, lo, hi in rel if "(2.4" in name]
        assert len(damaged) == 1 and damaged[0] < -3.0, rel
        assert all(-2.5 < lo <= 0.0 <= hi < 2.5 for name, lo, hi in rel if "(2.4" not in name), rel

        # the failed record, by name and with the loader's reason; the others finished
        failed = page.locator("#campaign-failed li")
        assert failed.count() == 1
        assert failed.first.text_content().startswith(f"{CORRUPT}: ") and "line" in failed.first.text_content()
        assert "4 analysed, 1 failed" in page.text_content("#campaign-meta")
        assert page.text_content("#campaign-title") == "ERA campaign: bridge <b>March</b>"  # text, never HTML
        page.locator("main").screenshot(path=str(shots / "campaign.png"))

        # the report link opens the same campaign in a new page; the table downloads as CSV
        with page.context.expect_page() as popup:
            page.click("#campaign-link")
        report = popup.value
        report.wait_for_selector("body[data-ready='1']", timeout=60000)
        assert report.url == page.url and report.locator("#campaign-modes tbody tr").count() == n_modes
        assert report.locator("#campaign-freq .main-svg .scatterlayer .trace").count() == n_modes
        csv = urllib.request.urlopen(server.base + page.get_attribute("#campaign-csv", "href")).read().decode()
        assert csv.splitlines()[0].startswith("record,name,time,mode,found,frequency_hz")
        assert len(csv.splitlines()) == 1 + 4 * n_modes

        # the offline report: one HTML file that draws the same plots with no server behind it
        html = urllib.request.urlopen(server.base + page.get_attribute("#campaign-html", "href")).read()
        (tmp_path / "campaign.html").write_bytes(html)
        server.stop()
        offline = browser.new_page()
        offline.on("pageerror", lambda e: errors.append(str(e)))
        offline.goto((tmp_path / "campaign.html").as_uri())
        offline.wait_for_selector("body[data-ready='1']", timeout=60000)
        assert offline.locator("#campaign-freq .main-svg .scatterlayer .trace").count() == n_modes
        assert offline.locator("#campaign-failed li").first.text_content().startswith(CORRUPT)
        assert offline.is_hidden("#campaign-share")
        assert errors == [], errors
    finally:
        server.stop()
