"""A server on a network: a shared team token or a sign-in proxy's header keeps strangers out while report links
stay readable; what no report uses expires; /api/health shows what the store holds; nothing listens beyond the
configured host."""

from __future__ import annotations

import socket
import time

import numpy as np

from apiclient import client

from app import housekeeping
from app.store import Store
from era.examples.paper_cases import case_1, case_2


def _report(c, headers=None):
    ds = c.post("/api/examples/case1", headers=headers).json()
    a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 90, "cols": 90}, headers=headers).json()
    made = c.post("/api/reports", json={"analysis_id": a["id"], "order": 10, "modes": [0, 1]}, headers=headers)
    return ds, a, made.json()


def test_a_team_token_keeps_strangers_out_and_report_links_open(tmp_path):
    with client(tmp_path, access_token="s3cret-team") as c:
        refused = c.post("/api/examples/case1")
        assert refused.status_code == 401 and "access token" in refused.json()["error"]
        page = c.get("/", follow_redirects=False)
        assert page.status_code == 401 and "Team access token" in page.text  # the sign-in form, not a stack trace
        assert c.post("/api/examples/case1", headers={"Authorization": "Bearer wrong"}).status_code == 401
        _, a, made = _report(c, headers={"Authorization": "Bearer s3cret-team"})
        # a browser signs in once; the cookie carries the token afterwards
        signed = c.post("/login", data={"token": "s3cret-team", "next": "/"}, follow_redirects=False)
        assert signed.status_code == 303 and "era_token" in signed.headers["set-cookie"]
        assert "HttpOnly" in signed.headers["set-cookie"]
        assert c.get(f"/api/analyses/{a['id']}").status_code == 200
        assert c.post("/login", data={"token": "nope"}).status_code == 401
    with client(tmp_path, access_token="s3cret-team") as stranger:  # a fresh client: no cookie
        for path in (f"/r/{made['token']}", f"/api/reports/{made['token']}", f"/api/reports/{made['token']}/modes.csv",
                     "/static/js/report.js", "/api/health"):
            assert stranger.get(path).status_code == 200, path
        assert stranger.get(f"/api/analyses/{a['id']}").status_code == 401
        assert stranger.get("/api/health").json()["access"] == "restricted"


def test_a_sign_in_proxys_header_is_required(tmp_path):
    with client(tmp_path, trust_user_header="X-Forwarded-User") as c:
        r = c.post("/api/examples/case1")
        assert r.status_code == 401 and "X-Forwarded-User" in r.json()["error"]
        assert c.post("/api/examples/case1", headers={"X-Forwarded-User": "ana"}).status_code == 200


def test_what_no_report_uses_expires_and_reports_are_kept(tmp_path):
    store = Store(tmp_path)
    keep_ds = store.add_dataset(case_1(200), None, "kept", {})
    keep_a = store.add_analysis(keep_ds, {"rows": 90})
    store.add_report("tok", keep_a, {"order": 10}, {})
    old_ds = store.add_dataset(case_2(120), None, "old", {})
    old_a = store.add_analysis(old_ds, {"rows": 45})
    store.add_explanation(old_a, {"verdict": "x"}, {k: np.zeros((3, 1, 1)) for k in ("measured", "nominal", "updated")},
                          0.1)
    store.staging.add("upload1", [("a.txt", b"1 2 3")])                           # an import never finished
    assert housekeeping.sweep(store, 30) == {"analyses": 0, "datasets": 0, "imports": 0,  # nothing is old yet
                                             "orphans": 0}
    assert housekeeping.sweep(store, 0, now=time.time() + 1e9) == {"analyses": 0, "datasets": 0,  # 0: never, but
                                                                   "imports": 1,  # a staged upload goes after a day
                                                                   "orphans": 0}
    assert store.staging.files("upload1") is None
    gone = housekeeping.sweep(store, 30, now=time.time() + 31 * 86400)
    assert gone == {"analyses": 1, "datasets": 1, "imports": 0, "orphans": 0}
    assert store.analysis(old_a) is None and store.load_dataset(old_ds) is None and store.explanation(old_a) is None
    assert not store.dataset_path(old_ds).exists() and not (tmp_path / "explanations" / f"{old_a}.npz").exists()
    assert store.report("tok") == {"order": 10} and store.analysis(keep_a) is not None  # reports keep theirs
    use = store.usage()
    assert use["rows"] == {"datasets": 1, "analyses": 1, "reports": 1, "explanations": 0}
    assert use["bytes"]["datasets"] == store.dataset_path(keep_ds).stat().st_size and use["free_bytes"] > 0


def test_health_shows_the_store_and_the_viewer_listens_on_loopback_only(tmp_path):
    with client(tmp_path, viewer=True) as c:
        _report(c)
        h = c.get("/api/health").json()
        assert h["access"] == "open" and h["usage"]["rows"]["reports"] == 1 and h["usage"]["bytes"]["datasets"] > 0
        viewer = c.app.state.viewer
        for host in _addresses():  # the internal viser server answers on 127.0.0.1, not on the machine's addresses
            with socket.socket() as s:
                s.settimeout(0.5)
                assert s.connect_ex((host, viewer.port)) != 0, host
        with socket.create_connection(("127.0.0.1", viewer.port), timeout=2):
            pass


def _addresses() -> list[str]:
    """This machine's non-loopback IPv4 addresses (none in a bare sandbox: then the loopback check is all)."""
    try:
        infos = socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET)
    except socket.gaierror:
        return []
    return sorted({i[4][0] for i in infos if not i[4][0].startswith("127.")})
