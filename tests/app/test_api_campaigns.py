"""Campaigns through the API: records uploaded (or a server folder) → every mode tracked, bad files listed as failed,
the Dask scheduler at ERA_DASK_SCHEDULER used when set, clear refusals.

The records are era.campaign.simulated's monitored structure (five modes, six sensors), 5 min at 20 Hz each and
every 3 h, so each takes about a second; orders up to 80 (the form's default: era.choose_modes weighs a mode
against the noise poles of the diagram's top order, and a diagram that stops at 40 leaves the weaker modes below
them). era's own accuracy on such campaigns is proven in tests/campaign; here the app must carry its results
faithfully.
"""

from __future__ import annotations

import json
import os
import re
import time
from pathlib import Path

import distributed
import numpy as np
import pytest

from apiclient import client
from app import schemas
from era.campaign import run_campaign
from era.campaign.simulated import monitoring_truth, write_campaign
from test_schemas import exact

CORRUPT = "rec_2026-03-02T12-00.csv"
EMPTY = "rec_2026-03-02T15-00.csv"
FORM = {"kind": "ambient", "max_order": "80"}


@pytest.fixture(scope="module")
def records(tmp_path_factory) -> Path:
    """Three good records, one cut off mid-line and one empty, all named with their date and hour."""
    folder = tmp_path_factory.mktemp("campaign") / "site-a"
    truth = monitoring_truth(3, hours_between=3.0, damage_from=2, duration_s=300.0)
    paths = write_campaign(folder, truth, seed=5)
    whole = Path(paths[0]).read_bytes()
    (folder / CORRUPT).write_bytes(whole[: len(whole) // 2])
    (folder / EMPTY).write_bytes(b"")
    return folder


def parts(folder: Path) -> list:
    return [("file", (p.name, p.read_bytes(), "text/csv")) for p in sorted(folder.iterdir())]


def finish(c, answer, timeout_s: float = 120.0) -> dict:
    """Poll GET /api/campaigns/{id} until the campaign is done or failed; its last answer, checked on its schema."""
    assert answer.status_code == 202, answer.text
    url = f"/api/campaigns/{answer.json()['id']}"
    deadline = time.monotonic() + timeout_s
    while True:
        body = c.get(url).json()
        if body["state"] in ("done", "failed") or time.monotonic() > deadline:
            exact(schemas.Campaign, body)
            return body
        time.sleep(0.2)


@pytest.fixture(scope="module")
def on_processes(records, tmp_path_factory):
    with client(tmp_path_factory.mktemp("data"), campaign_workers=2) as c:
        t0 = time.monotonic()
        body = finish(c, c.post("/api/campaigns", files=parts(records), data=dict(FORM, name="site A")))
        seconds = time.monotonic() - t0
        csv = c.get(f"/api/campaigns/{body['id']}/table.csv")
        page = c.get(body["url"])
        html = c.get(f"/api/campaigns/{body['id']}/campaign.html")
    return body, csv, page, html, seconds


def test_uploaded_records_are_tracked_and_bad_files_listed_as_failed(records, on_processes):
    body, csv, page, html, seconds = on_processes
    assert body["state"] == "done" and body["done"] == body["total"] == 5 and body["message"] is None
    r = body["result"]
    assert r["name"] == "site A" and r["engine"] == "2 local process(es)" and r["n_records"] == 5
    assert r["time_axis"] == "date"  # every file name holds its date
    assert [x["time"] for x in r["records"]] == ["2026-03-02T00:00:00", "2026-03-02T03:00:00", "2026-03-02T06:00:00"]
    assert {f["name"]: f["reason"] for f in r["failed"]}.keys() == {CORRUPT, EMPTY}
    assert all(f["reason"].startswith(f["name"]) for f in r["failed"])  # the loader names the file and the problem
    # what era.campaign gives on the same files, in this process: the app carries it unchanged
    mine = run_campaign(sorted(records.iterdir()), kind="ambient", orders=range(2, 81, 2), workers=0)
    assert [m["reference_frequency_hz"] for m in r["modes"]] == [m.reference_frequency_hz for m in mine.modes]
    assert [(m["n_held"], m["identification_rate"]) for m in r["modes"]] == \
        [(m.n_held, m.identification_rate) for m in mine.modes]  # each mode's rate, as era.campaign gives it
    assert all(m["n_held"] == 3 for m in r["modes"] if m["origin"] == "reference")  # the three analysed records
    for s in r["series"]:
        rows = mine.table[mine.table["mode"] == s["mode"]]
        assert np.allclose(np.array(s["frequency_hz"], dtype=float), rows["frequency_hz"], equal_nan=True)
        assert np.allclose(np.array(s["damping_ratio"], dtype=float), rows["damping_ratio"], equal_nan=True)
    truth = monitoring_truth(3, hours_between=3.0, damage_from=2, duration_s=300.0).frequency_hz[0]
    first = np.array([s["frequency_hz"][0] for s in r["series"]], dtype=float)
    close = [np.nanmin(np.abs(first - f) / f) < 0.01 for f in truth]
    assert sum(close) >= 4, first  # 5-min records at order 40 may miss a mode in one record, never invent one
    assert all(len(s["frequency_hz"]) == len(s["mac_to_reference"]) == 3 for s in r["series"])
    assert all(s["mac_to_reference"][0] == pytest.approx(1.0) for s in r["series"])  # the reference is record 0
    lines = csv.text.splitlines()
    assert csv.status_code == 200 and csv.headers["content-type"].startswith("text/csv")
    assert lines[0].startswith("record,name,time,mode,found,frequency_hz,damping_ratio,mac_to_reference")
    assert len(lines) == 1 + 3 * len(r["modes"]) and "rec_2026-03-02T03-00.csv" in lines[1 + len(r["modes"])]
    assert page.status_code == 200 and "campaign.js" in page.text
    inlined = re.search(r"window\.CAMPAIGN_DATA = (\{.*?\});</script>", html.text).group(1)
    assert json.loads(inlined)["result"] == r and 'src="/' not in html.text  # offline: nothing to fetch
    assert html.headers["content-disposition"].startswith("attachment")
    assert seconds < 60


def test_the_app_runs_the_records_on_the_dask_scheduler_it_is_given(records, on_processes, tmp_path):
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=40) as cluster:
        address = cluster.scheduler_address
        with client(tmp_path, dask_scheduler=address) as c:
            assert c.get("/api/campaigns/folders").json()["engine"] == f"Dask scheduler {address}"
            body = finish(c, c.post("/api/campaigns", files=parts(records), data=FORM))
        keys = {str(t[0]) for t in cluster.scheduler.transition_log}
    ran = {k for k in keys if k.startswith("era-campaign-")}
    assert len(ran) == 5 and body["state"] == "done"  # every record a task on that cluster, none here
    r, local = body["result"], on_processes[0]["result"]
    assert r["engine"] == f"Dask scheduler {address}"
    assert [f["name"] for f in r["failed"]] == [f["name"] for f in local["failed"]]
    assert r["series"] == local["series"] and r["modes"] == local["modes"]  # the same table either way


def test_a_folder_under_the_campaign_root_runs_like_an_upload(records, tmp_path):
    secret = tmp_path / "secret.csv"
    secret.write_text("time,a\n0,1\n")
    linked = records.parent / "linked"
    linked.mkdir(exist_ok=True)
    if not (linked / "rec.csv").is_symlink():
        (linked / "rec.csv").symlink_to(secret)  # a link out of the campaign folder: never read
    with client(tmp_path / "data", campaign_root=records.parent, campaign_workers=1) as c:
        listed = c.get("/api/campaigns/folders").json()
        exact(schemas.CampaignFolders, listed)
        assert listed["enabled"] and listed["folders"] == [{"name": "site-a", "n_files": 5}]
        body = finish(c, c.post("/api/campaigns", data=dict(FORM, folder="site-a")))
        outside = c.post("/api/campaigns", data=dict(FORM, folder="../"))
        missing = c.post("/api/campaigns", data=dict(FORM, folder="site-b"))
        link = c.post("/api/campaigns", data=dict(FORM, folder="linked"))
    assert body["state"] == "done" and body["name"] == "folder site-a"
    assert len(body["result"]["records"]) == 3 and {f["name"] for f in body["result"]["failed"]} == {CORRUPT, EMPTY}
    assert outside.status_code == 422 and "outside this server's campaign folder" in outside.json()["error"]
    assert missing.status_code == 422 and "No folder 'site-b'" in missing.json()["error"]
    assert link.status_code == 422 and "links to files outside" in link.json()["error"]


def test_refusals_say_what_is_wrong(records, tmp_path):
    one = [("file", ("a.csv", b"time,a\n0,1\n", "text/csv"))]
    with client(tmp_path, max_campaign_records=2, campaign_queue=0, campaign_workers=1) as c:
        cases = {
            "nothing": c.post("/api/campaigns", data=FORM),
            "both": c.post("/api/campaigns", files=one, data=dict(FORM, folder="x")),
            "no root": c.post("/api/campaigns", data=dict(FORM, folder="site-a")),
            "kind": c.post("/api/campaigns", files=one, data=dict(FORM, kind="modal")),
            "order": c.post("/api/campaigns", files=one, data=dict(FORM, max_order="1000")),
            "dt": c.post("/api/campaigns", files=one, data=dict(FORM, dt="-1")),
            "too many": c.post("/api/campaigns", files=parts(records), data=FORM),
        }
        unknown = [c.get("/api/campaigns/nope"), c.get("/api/campaigns/nope/table.csv")]
        page = c.get("/c/nope")
        first = c.post("/api/campaigns", files=one * 2, data=FORM)
        busy = c.post("/api/campaigns", files=one, data=FORM)  # ERA_CAMPAIGN_QUEUE=0: one campaign at a time
        finish(c, first)
    words = {"nothing": "No records", "both": "not both", "no root": "ERA_CAMPAIGN_ROOT", "kind": "`kind` must be",
             "order": "ERA_MAX_ORDER", "dt": "dt", "too many": "ERA_MAX_CAMPAIGN_RECORDS"}
    for case, r in cases.items():
        assert r.status_code == 422 and words[case] in r.json()["error"], (case, r.text)
    assert [r.status_code for r in unknown] == [404, 404] and "link" in unknown[0].json()["error"]
    assert page.status_code == 404 and "Campaign not found" in page.text
    assert busy.status_code == 503 and "ERA_CAMPAIGN_QUEUE" in busy.json()["error"]


def test_a_campaign_link_is_readable_without_the_team_token_but_starting_one_needs_it(tmp_path):
    one = [("file", ("rec_2026-03-02T00-00.csv", b"time,a\n0,1\n", "text/csv"))]
    with client(tmp_path, access_token="s3cret-team", campaign_workers=1) as team:
        made = team.post("/api/campaigns", files=one, data=FORM, headers={"Authorization": "Bearer s3cret-team"})
        body = finish(team, made)
        stranger_start = team.post("/api/campaigns", files=one, data=FORM)
        stranger_read = [team.get(body["url"]), team.get(f"/api/campaigns/{body['id']}"),
                         team.get(f"/api/campaigns/{body['id']}/table.csv")]
        folders = team.get("/api/campaigns/folders")
    assert body["state"] == "done" and [f["name"] for f in body["result"]["failed"]] == ["rec_2026-03-02T00-00.csv"]
    assert stranger_start.status_code == 401
    assert [r.status_code for r in stranger_read] == [200, 200, 200]
    assert folders.status_code == 401  # what the server holds is for the team only
    assert os.path.basename(body["url"]) == body["id"]


def test_a_campaign_running_when_the_server_stops_says_so_instead_of_running_forever(records, tmp_path):
    with client(tmp_path, campaign_workers=1) as c:
        started = c.post("/api/campaigns", files=parts(records), data=FORM).json()
    # the app stopped: the campaign ends after the record in progress, and says why to whoever opens its link
    deadline = time.monotonic() + 60
    with client(tmp_path) as c:
        while True:
            body = c.get(f"/api/campaigns/{started['id']}").json()
            if body["state"] not in ("queued", "running") or time.monotonic() > deadline:
                break
            time.sleep(0.2)
    assert body["state"] == "failed" and body["done"] < body["total"] and body["result"] is None
    assert body["message"] == "The server stopped during the campaign; start the campaign again."
