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
