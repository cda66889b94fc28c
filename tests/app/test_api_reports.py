"""Reports: creation, reading back (also after a restart), downloads (HTML, CSV, UFF 55), bad input."""

from __future__ import annotations

import csv
import io
import re

import numpy as np
import pytest

import era
from apiclient import analysis, case1_frequencies_hz, client


def _report(c, a, order=10, modes=(0, 2, 4)):
    r = c.post("/api/reports", json={"analysis_id": a["id"], "order": order, "modes": list(modes)})
    assert r.status_code == 200, r.text
    return r.json()


def test_report_freezes_the_analysis_and_survives_a_restart(tmp_path):
    with client(tmp_path) as c:
        ds, a = analysis(c)
        made = _report(c, a)
        assert made["url"] == f"/r/{made['token']}" and len(made["token"]) >= 22  # ≥ 128 random bits
        first = c.get(f"/api/reports/{made['token']}").json()
    # the file and the row are on disk before the link was returned; a new process reads them
    assert (tmp_path / "reports" / made["token"] / "report.json").is_file()
    with client(tmp_path) as c:
        again = c.get(f"/api/reports/{made['token']}").json()
        page = c.get(made["url"])
    assert page.status_code == 200 and "report.js" in page.text
    assert again["modes"] == first["modes"] and again["kept"] == [0, 2, 4] and again["order"] == 10
    np.testing.assert_allclose(again["modes"]["frequency_hz"], case1_frequencies_hz(), rtol=1e-8)
    assert again["dataset"]["sha256"] == ds["sha256"]
    assert again["analysis"]["rows"] == 90 and again["software"]["era-modal"]
    assert len(again["reconstruction"]["pairs"]) == 1
    fit = again["kept_fit_percent"][0][0]
    assert 0 < fit < 99  # three of five modes kept


def test_tokens_are_unique(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        tokens = {_report(c, a)["token"] for _ in range(3)}
    assert len(tokens) == 3


@pytest.mark.parametrize("body, status", [
    ({"order": 10, "modes": [9]}, 422),
    ({"order": 99, "modes": [0]}, 422),
    ({"order": 8}, 422),  # modes left out: the choice's, at its order (10) only
    ({"order": 10, "modes": ["x"]}, 422),
])
def test_bad_report_requests(tmp_path, body, status):
    with client(tmp_path) as c:
        _, a = analysis(c)
        r = c.post("/api/reports", json={"analysis_id": a["id"], **body})
    assert r.status_code == status and r.json()["error"]


def test_unknown_report_and_analysis_are_404(tmp_path):
    with client(tmp_path) as c:
        assert c.post("/api/reports", json={"analysis_id": "nope", "order": 2, "modes": []}).status_code == 404
        for path in ("/api/reports/nope", "/api/reports/nope/report.html", "/api/reports/nope/modes.csv",
                     "/api/reports/nope/modes.uff", "/api/reports/nope/files/mode_0.viser"):
            assert c.get(path).status_code == 404, path
        page = c.get("/r/nope")
        assert page.status_code == 404 and "Report not found" in page.text


def test_report_files_cannot_escape_the_report_folder(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        token = _report(c, a)["token"]
        for name in ("report.json", ".hidden", "%2e%2e%2fera.sqlite3", "..%2freport.json"):
            assert c.get(f"/api/reports/{token}/files/{name}").status_code == 404, name


def test_html_download_is_self_contained(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        token = _report(c, a)["token"]
        r = c.get(f"/api/reports/{token}/report.html")
    assert r.status_code == 200 and "attachment" in r.headers["content-disposition"]
    html = r.text
    assert not re.search(r"<script[^>]+src=", html) and 'rel="stylesheet"' not in html  # nothing fetched
    assert "window.REPORT_DATA" in html and "Plotly" in html and len(html) > 3_000_000  # plotly.js inlined
    assert '"standalone":true' in html


def test_csv_download_lists_every_mode_with_the_kept_flag(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        token = _report(c, a)["token"]
        r = c.get(f"/api/reports/{token}/modes.csv")
    rows = list(csv.DictReader(io.StringIO(r.text)))
    assert len(rows) == 5 and [int(x["kept"]) for x in rows] == [1, 0, 1, 0, 1]
    np.testing.assert_allclose([float(x["frequency_hz"]) for x in rows], case1_frequencies_hz(), rtol=1e-8)
    assert "sensor 1 re" in rows[0]
    # noise-free Case I: the standard deviations from the data are round-off
    assert all(0 <= float(x["frequency_std_hz"]) < 1e-8 and 0 <= float(x["damping_std"]) < 1e-8 for x in rows)


def test_uff_download_holds_the_kept_modes(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        token = _report(c, a)["token"]
        r = c.get(f"/api/reports/{token}/modes.uff")
        assert r.status_code == 200
        path = tmp_path / "modes.uff"
        path.write_bytes(r.content)
        modes = era.read_modes_uff(str(path))
        assert r.content.decode("latin-1").count("std f ") == 3  # each mode's standard deviations, ID line 3
        freqs = np.sort(np.asarray(modes.frequency_hz))
        np.testing.assert_allclose(freqs, case1_frequencies_hz()[[0, 2, 4]], rtol=1e-4)
        empty = _report(c, a, modes=())["token"]
        r = c.get(f"/api/reports/{empty}/modes.uff")
        assert r.status_code == 422 and "no modes" in r.json()["error"]
