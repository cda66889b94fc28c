"""Nothing lost: a report whose link was returned survives `kill -9` of the server at any moment, on SQLite and on
PostgreSQL. The server is killed repeatedly while a client keeps creating reports; after each restart every link
returned so far must open, with the report it was given for."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import httpx
import pytest
from ports import free_port

REPO = Path(__file__).resolve().parents[2]
KILLS = 4


class Server:
    def __init__(self, data_dir: Path, database_url: str | None):
        self.data_dir, self.database_url = data_dir, database_url
        self.port = free_port()
        self.base = f"http://127.0.0.1:{self.port}"
        self.proc = None

    def start(self) -> None:
        env = dict(os.environ, ERA_DATA_DIR=str(self.data_dir), ERA_VIEWER="0", ERA_RATE_LIMIT="100000",
                   ERA_RATE_LIMIT_HEAVY="100000")
        if self.database_url:
            env["ERA_DATABASE_URL"] = self.database_url
        self.proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "app.main:app", "--host", "127.0.0.1",
                                      "--port", str(self.port), "--log-level", "warning"], cwd=REPO, env=env,
                                     start_new_session=True)  # its worker processes die with it (killpg)
        for _ in range(300):
            try:
                if httpx.get(self.base + "/api/health", timeout=1).status_code == 200:
                    return
            except httpx.HTTPError:
                time.sleep(0.1)
        raise RuntimeError("the server did not start")

    def kill9(self) -> None:
        os.killpg(self.proc.pid, signal.SIGKILL)
        self.proc.wait(10)


@pytest.mark.parametrize("backend", ["sqlite", "postgresql"])
def test_returned_report_links_survive_kill_9(backend, tmp_path, request):
    url = request.getfixturevalue("postgres_url") if backend == "postgresql" else None
    server = Server(tmp_path / "data", url)
    server.start()
    ds = httpx.post(server.base + "/api/examples/case1", timeout=60).json()
    a = httpx.post(server.base + "/api/analyses", json={"dataset_id": ds["id"], "rows": 90, "cols": 90},
                   timeout=60).json()
    returned: dict[str, list[int]] = {}   # token -> the modes it was created with
    stop = threading.Event()

    def create_reports():
        k = 0
        while not stop.is_set() and k < 500:
            modes = [k % 5, (k + 2) % 5]
            k += 1
            try:
                r = httpx.post(server.base + "/api/reports", json={"analysis_id": a["id"], "order": 10,
                                                                   "modes": modes}, timeout=30)
            except httpx.HTTPError:  # the server died mid-request: no link was returned, nothing is owed
                time.sleep(0.05)
                continue
            if r.status_code == 200:
                returned[r.json()["token"]] = sorted(set(modes))

    for kill in range(KILLS):
        writer = threading.Thread(target=create_reports)
        stop.clear()
        writer.start()
        # reports are being made (on a loaded machine the first takes a while), then a different moment of a
        # report's life each time
        made, deadline = len(returned), time.monotonic() + 60
        while len(returned) == made and time.monotonic() < deadline:
            time.sleep(0.02)
        time.sleep(0.05 + 0.13 * kill)
        server.kill9()
        stop.set()
        writer.join(30)
        server.start()
        for token, modes in returned.items():
            r = httpx.get(f"{server.base}/api/reports/{token}", timeout=30)
            assert r.status_code == 200, (kill, token, r.text)
            assert r.json()["kept"] == modes
    assert len(returned) >= KILLS  # reports were being made when the server died
    server.kill9()
