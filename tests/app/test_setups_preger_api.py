"""A multi-setup test through the API, merged by PreGER, reported offline, and analysed once per setup and pick.

The beam of tests/simulated_setups.py (four ambient setups, references P2 and P5): PreGER through the page equals
the library's steps on the same files (era.load with the references, era.merge_correlations, era.analyse) and
finds the beam's four modes (MAC ≥ 0.97 with the exact sin(jπx), its one factor per setup holding only roughly as
the setups' levels differ); records that are not ambient are refused next to the picker. The frozen report
downloads as one HTML file with plotly.js, the page's script and the merge inside. A wrong pick in one setup,
then the right one: only that setup is analysed again."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import era

from apiclient import client

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from simulated_setups import FREQUENCY_HZ, setup_file, truth_at  # noqa: E402


def upload(c, files, kind="ambient"):
    return c.post("/api/setups", files=[("file", (n, b, "text/csv")) for n, b in files], data={"kind": kind})


def shapes_of(merged) -> np.ndarray:
    re = np.array([[np.nan if v is None else v for v in row] for row in merged["shapes_re"]])
    im = np.array([[np.nan if v is None else v for v in row] for row in merged["shapes_im"]])
    return (re + 1j * im).T


def test_preger_on_the_page_equals_the_librarys_steps_and_its_report_opens_offline(tmp_path):
    files = [setup_file(k) for k in range(4)]
    with client(tmp_path) as c:
        test = upload(c, files).json()
        refs = test["proposed"]
        assert refs == [[0, 1]] * 4
        r = c.post(f"/api/setups/{test['id']}/merge", json={"references": refs, "method": "preger"})
        assert r.status_code == 200, r.text
        merged = r.json()["merged"]
        assert merged["method"] == "preger" and merged["next_choice"].startswith("PreGER: ")
        assert merged["preger_scales"][0] == 1 and len(merged["preger_residual"]) == 4
        assert all(m["complete"] and m["seen"] == "identified once from all 4 setups (PreGER)"
                   for m in merged["modes"])
        assert merged["points"] == ["P2", "P5", "P1", "P3", "P4", "P6", "P7", "P8", "P9", "P10", "P11", "P12"]
        # frozen, then downloaded as one file
        report = c.post(f"/api/setups/{test['id']}/report").json()
        html = c.get(f"/api/setups/{test['id']}/reports/{report['token']}/report.html")
        assert html.status_code == 200 and "attachment" in html.headers["content-disposition"]
        assert "<script src=" not in html.text and "window.SETUPS_DATA = " in html.text
        assert "Plotly" in html.text and '"method":"preger"' in html.text and "data:text/javascript;base64," in html.text
        assert c.get(f"/api/setups/{test['id']}/reports/nope/report.html").status_code == 404
        # the page's path with the method asked of a decay test: refused next to the picker
        other = upload(c, files[:2], kind="decay").json()
        r = c.post(f"/api/setups/{other['id']}/merge", json={"references": [[0, 1]] * 2, "method": "preger"})
        assert r.status_code == 422 and r.json()["option"] == "references"
        assert "PreGER merges NExT correlation functions of ambient records" in r.json()["error"]
    data = []
    for (name, blob), r in zip(files, refs):
        (tmp_path / name).write_bytes(blob)
        data.append(era.load(tmp_path / name, kind="ambient", references=r).data)
    library = era.analyse(era.merge_correlations(data, refs).data).model
    np.testing.assert_allclose([m["frequency_hz"] for m in merged["modes"]], library.frequency_hz, rtol=1e-9)
    np.testing.assert_allclose(np.abs(era.mac(shapes_of(merged), library.shapes).diagonal()), 1, atol=1e-9)
    macs = era.mac(shapes_of(merged), truth_at(merged["points"]))
    freqs = np.array([m["frequency_hz"] for m in merged["modes"]])
    for j, f in enumerate(FREQUENCY_HZ):  # each of the beam's modes: the nearest merged mode
        k = int(np.argmin(np.abs(freqs - f)))
        assert abs(freqs[k] - f) <= 0.01 * f and macs[k, j] >= 0.97, (f, freqs[k], macs[k, j])


def test_a_new_pick_analyses_again_only_the_setups_whose_references_changed(tmp_path, monkeypatch):
    calls = []
    analyse = era.analyse

    def counted(data, **options):
        calls.append(data.markov.shape)
        return analyse(data, **options)

    monkeypatch.setattr(era, "analyse", counted)
    with client(tmp_path) as c:
        test = upload(c, [setup_file(k) for k in range(4)]).json()
        assert len(calls) == 4  # the upload: each setup, every channel as NExT reference
        wrong = [[0, 1], [0, 1], [0, 2], [0, 1]]
        r = c.post(f"/api/setups/{test['id']}/merge", json={"references": wrong})
        assert r.status_code == 422 and len(calls) == 8  # the references' way, each setup
        r = c.post(f"/api/setups/{test['id']}/merge", json={"references": test["proposed"]})
        assert r.status_code == 200 and len(calls) == 9  # setup 3 alone again
        assert calls[-1][2] == 2
