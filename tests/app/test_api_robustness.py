"""Limits and failure modes: rate limits, no stack traces, pages, the job pool, the store's durability."""

from __future__ import annotations

import asyncio
import re
import sqlite3
import time

import pytest
from fastapi import HTTPException

from apiclient import analysis, case1_npz, client, upload
from app.jobs import Jobs
from app.store import Store, write_atomic


def test_rate_limit_per_client_is_429_with_retry_after(tmp_path):
    with client(tmp_path, rate_limit_heavy_per_minute=2) as c:
        assert upload(c, case1_npz()).status_code == 200
        assert upload(c, case1_npz()).status_code == 200
        r = upload(c, case1_npz())
        assert r.status_code == 429 and int(r.headers["retry-after"]) >= 1
        assert "per minute" in r.json()["error"]
        assert c.get("/api/examples").status_code == 200  # reading is counted separately


def test_overall_rate_limit(tmp_path):
    with client(tmp_path, rate_limit_per_minute=3) as c:
        codes = [c.get("/api/examples").status_code for _ in range(4)]
        assert codes == [200, 200, 200, 429]
        assert c.get("/").status_code == 200  # pages are not API calls


def test_unexpected_errors_are_500_json_without_traceback(tmp_path, monkeypatch, caplog):
    from app import payloads

    def boom(*args, **kwargs):
        raise RuntimeError("secret internal detail /etc/passwd")

    monkeypatch.setattr(payloads, "modes_json", boom)
    with client(tmp_path, raise_errors=False) as c:
        _, a = analysis(c)
        r = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 10})
    assert r.status_code == 500
    body = r.json()
    assert set(body) == {"error"} and "reference" in body["error"]
    assert "secret" not in r.text and "Traceback" not in r.text
    ref = re.search(r"reference (\w+)", body["error"]).group(1)
    assert any(ref in rec.getMessage() for rec in caplog.records)  # logged with the same reference


def test_validation_errors_are_readable_json(tmp_path):
    with client(tmp_path) as c:
        r = c.post("/api/analyses", content=b"{not json", headers={"content-type": "application/json"})
        assert r.status_code == 422 and r.json()["error"].startswith("Invalid request")
        r = c.post("/api/analyses", json={"dataset_id": "x", "rows": "many", "cols": 3})
        assert r.status_code == 422 and "rows" in r.json()["error"]


def test_pages_and_vendored_plotly(tmp_path):
    with client(tmp_path) as c:
        index = c.get("/")
        assert index.status_code == 200 and 'id="order"' in index.text
        assert not re.search(r"src=\"https?://", index.text)  # no CDN: everything from this server
        js = c.get("/vendor/plotly.min.js")
        assert js.status_code == 200 and "javascript" in js.headers["content-type"] and len(js.content) > 1_000_000
        for path in ("/static/js/main.js", "/static/js/report.js", "/static/css/app.css", "/static/report.html"):
            assert c.get(path).status_code == 200, path
        docs = c.get("/docs")
        assert docs.status_code == 200 and "/api/analyses" in c.get("/openapi.json").text
        assert "cdn." not in docs.text  # Swagger UI from this server: /docs works offline
        assert c.get("/vendor/swagger/swagger-ui-bundle.js").status_code == 200


def test_heavy_pool_is_bounded_and_says_busy():
    async def scenario():
        jobs = Jobs(heavy_workers=1, heavy_queue=1)
        slow = [asyncio.create_task(jobs.heavy(time.sleep, 0.3)) for _ in range(2)]
        await asyncio.sleep(0.05)
        with pytest.raises(HTTPException) as err:
            await jobs.heavy(time.sleep, 0)
        await asyncio.gather(*slow)
        assert await jobs.heavy(lambda: 42) == 42  # capacity is back
        jobs.shutdown()
        return err.value

    err = asyncio.run(scenario())
    assert err.status_code == 503 and "busy" in err.detail


def test_store_uses_wal_and_atomic_files(tmp_path):
    store = Store(tmp_path)
    mode = sqlite3.connect(tmp_path / "era.sqlite3").execute("PRAGMA journal_mode").fetchone()[0]
    assert mode == "wal"
    target = tmp_path / "sub" / "f.bin"
    write_atomic(target, b"one")
    write_atomic(target, b"two")
    assert target.read_bytes() == b"two"
    assert [p.name for p in target.parent.iterdir()] == ["f.bin"]  # no temporary left behind
    store.close()


def test_progress_of_a_named_heavy_request(tmp_path):
    with client(tmp_path) as c:
        ds = upload(c, case1_npz()).json()
        key = "k" * 20
        r = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 90, "cols": 90},
                   headers={"X-Progress-Key": key})
        assert r.status_code == 200
        p = c.get(f"/api/jobs/{key}").json()
        assert p["state"] == "done" and "SVD of H(0) (90 × 90)" in p["message"] and p["seconds"] >= 0
        assert c.get("/api/jobs/unknownkey123").status_code == 404


def test_progress_says_queued_then_running():
    async def scenario():
        jobs = Jobs(heavy_workers=1, heavy_queue=2)
        first = asyncio.create_task(jobs.heavy(time.sleep, 0.4, progress="first-job", message="Sleeping"))
        await asyncio.sleep(0.05)
        second = asyncio.create_task(jobs.heavy(time.sleep, 0.1, progress="second-job", message="Next"))
        await asyncio.sleep(0.05)
        during = jobs.progress("first-job"), jobs.progress("second-job")
        await asyncio.gather(first, second)
        after = jobs.progress("second-job")
        jobs.shutdown()
        return during, after

    (first, second), after = asyncio.run(scenario())
    assert first["state"] == "running" and first["message"] == "Sleeping"
    assert second["state"] == "queued" and second["queued_ahead"] == 0 and second["running_total"] == 1
    assert after["state"] == "done"
