"""The small ones of issue 29: the rates as the README writes them start the server; /api/health tells a stranger
on a token server only that it is up; housekeeping removes what a process killed mid-write left."""

from __future__ import annotations

import os
import time

import pytest

from apiclient import client
from app import housekeeping
from app.config import from_env, rate
from app.store import Store, write_atomic
from era.examples.paper_cases import case_1


def test_rates_as_the_readme_writes_them(monkeypatch):
    assert [rate(x) for x in ("1200", "100000/min", "20/s", "72000/h", " 60 / minute ")] == \
        [1200, 100000, 1200, 1200, 60]
    monkeypatch.setenv("ERA_RATE_LIMIT", "100000/min")
    monkeypatch.setenv("ERA_RATE_LIMIT_HEAVY", "600/min")
    settings = from_env()
    assert (settings.rate_limit_per_minute, settings.rate_limit_heavy_per_minute) == (100000, 600)
    monkeypatch.setenv("ERA_RATE_LIMIT", "lots")
    with pytest.raises(SystemExit, match="ERA_RATE_LIMIT='lots' is not a valid rate"):
        from_env()


def test_health_shows_the_store_only_to_those_signed_in(tmp_path):
    with client(tmp_path, access_token="s3cret-team") as c:
        stranger = c.get("/api/health").json()
        assert stranger["status"] == "ok" and stranger["access"] == "restricted" and stranger["version"]
        assert stranger["usage"] is None and stranger["store"] is None and stranger["expire_days"] is None
        member = c.get("/api/health", headers={"Authorization": "Bearer s3cret-team"}).json()
        assert member["usage"]["rows"]["datasets"] == 0 and member["store"] == "sqlite"
    with client(tmp_path) as c:  # an open server: everyone is a member
        assert c.get("/api/health").json()["usage"]["free_bytes"] > 0


def test_housekeeping_removes_a_report_folder_a_kill_left_half_written(tmp_path):
    store = Store(tmp_path)
    ds = store.add_dataset(case_1(200), None, "d", {})
    store.add_report("kept", store.add_analysis(ds, {"rows": 90}), {"order": 10}, {"mode_0.viser": b"v"})
    killed = store.report_dir("killed")                 # kill -9 while writing: a recording, no report.json, no row
    write_atomic(killed / "mode_0.viser", b"v")
    (killed / ".report.json.x1y2.tmp").write_bytes(b"{half")
    stray = tmp_path / "datasets" / ".abc.npz.q.tmp"    # a dataset write cut short
    stray.write_bytes(b"PK")
    writing = store.report_dir("writing")               # another process writing right now
    write_atomic(writing / "mode_0.viser", b"v")
    old = time.time() - 2 * housekeeping.ORPHAN_AFTER_S
    for p in (killed / "mode_0.viser", killed / ".report.json.x1y2.tmp", killed, stray):
        os.utime(p, (old, old))
    assert housekeeping.sweep(store, 30)["orphans"] == 2
    assert not killed.exists() and not stray.exists()
    assert writing.exists() and store.report("kept") == {"order": 10}
    assert store.report_file("kept", "mode_0.viser") is not None


def test_fifty_proxy_users_each_have_their_own_limits(tmp_path):
    """Behind the sign-in proxy every request has the proxy's address: limits count per user, so 50 engineers doing
    upload → analysis → slider → report all get through where one address's heavy limit (here 5) would stop them."""
    with client(tmp_path, trust_user_header="X-Forwarded-User", rate_limit_heavy_per_minute=5) as c:
        codes = set()
        for k in range(50):
            who = {"X-Forwarded-User": f"engineer{k}"}
            ds = c.post("/api/examples/case1", headers=who)
            a = c.post("/api/analyses", json={"dataset_id": ds.json()["id"], "rows": 20, "cols": 20}, headers=who)
            step = c.get(f"/api/analyses/{a.json()['id']}/step", params={"order": 4}, headers=who)
            report = c.post("/api/reports", json={"analysis_id": a.json()["id"], "order": 4, "modes": [0]},
                            headers=who)
            codes |= {ds.status_code, a.status_code, step.status_code, report.status_code}
        assert codes == {200}
        busy = {"X-Forwarded-User": "engineer0"}   # one user past the limit is told when to come back
        for _ in range(3):
            r = c.post("/api/examples/case1", headers=busy)
        assert r.status_code == 429 and int(r.headers["retry-after"]) >= 1 and "engineer0" in r.json()["error"]


def test_signed_in_browsers_count_apart_and_guessing_tokens_is_limited(tmp_path):
    with client(tmp_path, access_token="s3cret-team", rate_limit_heavy_per_minute=3) as c:
        browsers = []
        for _ in range(2):
            signed = c.post("/login", data={"token": "s3cret-team", "next": "/"}, follow_redirects=False)
            browsers.append({"Cookie": f"era_token=s3cret-team; era_session={signed.cookies['era_session']}"})
            c.cookies.clear()
        for who in browsers:  # the same address, two sessions: 2 heavy requests each stay under 3
            assert [c.post("/api/examples/case1", headers=who).status_code for _ in range(2)] == [200, 200]
        guesses = [c.post("/login", data={"token": f"guess{k}"}).status_code for k in range(5)]
        assert guesses[0] == 401 and guesses[-1] == 429  # sign-ins are heavy requests of the address
    with client(tmp_path, access_token="s3cret-team", rate_limit_per_minute=10) as c:
        guesses = [c.get(f"/r/guess{k:04d}").status_code for k in range(12)]
        assert guesses[:10] == [404] * 10 and guesses[10:] == [429, 429]  # report links cannot be enumerated
