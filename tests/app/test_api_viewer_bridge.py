"""The app's side of the viser viewer: publishing the modes of an order, selecting one, report recordings."""

from __future__ import annotations

from apiclient import analysis, client


def test_publish_select_and_record(tmp_path):
    with client(tmp_path, viewer=True) as c:
        assert c.app.state.viewer is not None
        _, a = analysis(c)
        v = c.post(f"/api/analyses/{a['id']}/viewer", json={"order": 10})
        assert v.status_code == 200, v.text
        v = v.json()
        assert v["n_modes"] == 5 and v["url"].startswith("/viser/") and len(v["key"]) >= 22
        r = c.post(v["mode_url"], json={"index": 3, "amplitude": 0.2, "speed": 0.5})
        assert r.status_code == 200 and r.json()["index"] == 3
        assert c.post(v["mode_url"], json={"index": 9}).status_code in (404, 422)  # no such mode
        assert c.get(v["url"]).status_code == 200  # viser's shipped client page

        token = c.post("/api/reports", json={"analysis_id": a["id"], "order": 10, "modes": [0, 4]}).json()["token"]
        rep = c.get(f"/api/reports/{token}").json()
        assert rep["recordings"] == {"0": "mode_0.viser", "4": "mode_4.viser"}
        assert set(rep["playback"]) == {"0", "4"} and "playbackPath=" in rep["playback"]["0"]
        rec = c.get(f"/api/reports/{token}/files/mode_4.viser")
        assert rec.status_code == 200 and len(rec.content) > 100


def test_viewer_routes_say_when_the_viewer_is_off(tmp_path):
    with client(tmp_path, viewer=False) as c:
        _, a = analysis(c)
        r = c.post(f"/api/analyses/{a['id']}/viewer", json={"order": 10})
        assert r.status_code == 503 and "viewer" in r.json()["error"]
        assert c.post(f"/api/analyses/{a['id']}/viewer", json={"order": 0}).status_code == 422
        assert c.post("/api/analyses/nope/viewer", json={"order": 2}).status_code == 404


def test_downloaded_report_carries_the_viser_player_once_and_each_recording(tmp_path):
    with client(tmp_path, viewer=True) as c:
        _, a = analysis(c)
        token = c.post("/api/reports", json={"analysis_id": a["id"], "order": 10, "modes": [0, 4]}).json()["token"]
        html = c.get(f"/api/reports/{token}/report.html").text
    assert html.count("window.VISER_PAGE = ") == 1
    assert '"offline_recordings":{"0":"' in html and '"4":"' in html
    assert '"viser_marker":"window.__VISER_EMBED_DATA__=\\"\\""' in html
