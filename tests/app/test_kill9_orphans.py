"""kill -9 leaves no orphan after the next start, and a live writer's work is never taken for one.

A write in progress holds an flock (app/store/files.py) that dies with its process: the sweep at start removes what
a killed server left half-written at once, while what another live process is writing stays, however old."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import threading
import time
from pathlib import Path

import httpx

from apiclient import REPO, live_server
from app import housekeeping
from app.store import WRITING, Store

#: At most this many kills to catch the server in the middle of writing a report.
MAX_KILLS = 6

# A process of its own that writes through the store and stops for good in the middle of one write (its fsync of
# the temporary file named by argv[3]), as a slow disk would: its lock is held until it is killed.
_WRITER = r"""
import os, sys, time
from pathlib import Path
import app.store.files as files
from app.store import Store
root, what, stall = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
fsync = os.fsync
def slow(fd):
    if os.path.basename(os.readlink(f"/proc/self/fd/{fd}")).startswith(stall):
        print("writing", flush=True)
        time.sleep(3600)
    fsync(fd)
files.os.fsync = slow
store = Store(root)
if what == "report":
    store.add_report("writing", "an-analysis", {"order": 4}, {"mode_0.viser": b"recorded"})
else:
    import era.examples.paper_cases
    store.add_dataset(era.examples.paper_cases.case_1(50), None, "d", {})
"""


def _writer(root: Path, what: str, stall: str) -> subprocess.Popen:
    proc = subprocess.Popen([sys.executable, "-c", _WRITER, str(root), what, stall], cwd=REPO,
                            stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "writing"
    return proc


def _orphans(data: Path) -> list[str]:
    """Report folders with no indexed report, and temporary files, in a data folder (relative paths)."""
    with sqlite3.connect(data / "era.sqlite3") as db:
        tokens = {t for (t,) in db.execute("select token from reports")}
    folders = [p for p in (data / "reports").iterdir() if p.name not in tokens] if (data / "reports").is_dir() else []
    return sorted(str(p.relative_to(data)) for p in folders + list(data.rglob(".*.tmp")))


def test_a_live_writers_work_stays_and_a_killed_ones_goes_at_once(tmp_path):
    Store(tmp_path).close()
    reporting = _writer(tmp_path, "report", ".report.json.")   # stopped writing report.json, the recording written
    storing = _writer(tmp_path, "dataset", ".")                # stopped writing a dataset's file
    try:
        folder = tmp_path / "reports" / "writing"
        tmps = sorted(tmp_path.rglob(".*.lock.tmp"))
        assert [p.parent.name for p in tmps] == ["datasets", "writing"]
        old = tmp_path / "reports" / "old-layout"   # an older version's orphan, no lock: the age rule
        old.mkdir()
        (old / "mode_0.viser").write_bytes(b"v")
        sweeper = Store(tmp_path)                    # another process's sweep, long after: the live writes stay
        later = time.time() + 10 * housekeeping.ORPHAN_AFTER_S
        assert housekeeping.sweep(sweeper, 30, now=later)["orphans"] == 1
        assert not old.exists()
        assert (folder / "mode_0.viser").read_bytes() == b"recorded" and all(p.exists() for p in tmps)
        for proc in (reporting, storing):
            proc.kill()
            proc.wait(10)
        assert housekeeping.sweep(sweeper, 30)["orphans"] == 2  # right away, though all was written just now
        assert not folder.exists() and not any(p.exists() for p in tmps)
        assert _orphans(tmp_path) == []
    finally:
        for proc in (reporting, storing):
            proc.kill()
            proc.wait(10)


def test_kill_9_during_report_creation_leaves_no_orphan_after_the_next_start(tmp_path):
    data = tmp_path / "data"
    limits = dict(ERA_RATE_LIMIT="100000", ERA_RATE_LIMIT_HEAVY="100000", ERA_VIEWER="1")
    analysis_id, caught, kills = None, [], 0
    while not caught and kills < MAX_KILLS:
        with live_server(data, **limits) as (base, pid):
            if analysis_id is None:
                ds = httpx.post(base + "/api/examples/case1", timeout=60).json()
                analysis_id = httpx.post(base + "/api/analyses", json={"dataset_id": ds["id"], "rows": 90,
                                                                       "cols": 90}, timeout=60).json()["id"]
            stop = threading.Event()

            def create_reports():
                while not stop.is_set():
                    try:
                        httpx.post(base + "/api/reports", json={"analysis_id": analysis_id, "order": 10,
                                                                "modes": [0, 1, 2, 3, 4]}, timeout=30)
                    except httpx.HTTPError:
                        return

            clients = [threading.Thread(target=create_reports) for _ in range(3)]
            for t in clients:
                t.start()
            deadline = time.monotonic() + 30
            while not list((data / "reports").glob("*/" + WRITING)) and time.monotonic() < deadline:
                time.sleep(0.001)  # until a report is being written (its lock file is there), then at once:
            os.killpg(pid, signal.SIGKILL)
            kills += 1
            stop.set()
            for t in clients:
                t.join(30)
        caught = _orphans(data)
    assert caught, f"{kills} kills never caught the server writing a report"
    with live_server(data, **limits) as (base, pid):
        deadline = time.monotonic() + 5
        while _orphans(data) and time.monotonic() < deadline:  # the start-up sweep runs as the server answers
            time.sleep(0.05)
        assert _orphans(data) == [], f"{caught} left by the kill are still there after the next start"
        assert httpx.get(base + "/api/health", timeout=10).status_code == 200


def test_a_file_system_without_flock_still_takes_every_write(tmp_path, monkeypatch):
    """flock refused (ENOLCK, as an old NFS answers): writes go on unlocked, their leftovers under the age rule."""
    import errno

    import app.store.files as files

    def no_locks(fd, how):
        raise OSError(errno.ENOLCK, "No locks available")

    monkeypatch.setattr(files.fcntl, "flock", no_locks)
    store = Store(tmp_path)
    store.add_report("plain", "an-analysis", {"order": 4}, {"mode_0.viser": b"recorded"})
    assert store.report("plain") == {"order": 4} and not list(tmp_path.rglob(".*.tmp"))
    half = tmp_path / "reports" / "half"                 # what a kill left there: no lock to ask, so its age
    half.mkdir()
    (half / ".report.json.x1y2.tmp").write_bytes(b"{")
    assert housekeeping.sweep(store, 30)["orphans"] == 0
    assert housekeeping.sweep(store, 30, now=time.time() + 2 * housekeeping.ORPHAN_AFTER_S)["orphans"] == 1
    assert not half.exists()


def test_a_report_folder_killed_before_its_lock_goes_at_once_and_a_live_writer_makes_it_again(tmp_path, monkeypatch):
    """Killed between the folder's mkdir and its lock's rename (three writers at once made this the common catch):
    nothing but the lock's temporary name, no lock to ask; the next sweep removes it at once. A live writer whose
    folder a sweeper removed in that instant makes it again and writes its report whole."""
    import app.store.files as files

    store = Store(tmp_path)
    unborn = tmp_path / "reports" / "unborn"
    unborn.mkdir(parents=True)
    (unborn / f"{WRITING}.k1l2m3n4.tmp").write_bytes(b"")
    assert housekeeping.sweep(store, 30)["orphans"] == 1 and not unborn.exists()

    take, swept = files._lock, []

    def swept_first(fd):  # a sweeper removes the new folder just before this writer locks its first file
        if not swept:
            swept.append(housekeeping.sweep(Store(tmp_path), 30)["orphans"])
        return take(fd)

    monkeypatch.setattr(files, "_lock", swept_first)
    store.add_report("racing", "an-analysis", {"order": 4}, {"mode_0.viser": b"recorded"})
    assert swept == [1]
    assert store.report("racing") == {"order": 4} and store.report_file("racing", "mode_0.viser") is not None
    assert _orphans(tmp_path) == []
