"""Several processes, one address: two app processes on one PostgreSQL database and one data folder serve one
browser session whose requests alternate between them — dataset, analysis, slider, diagram, viewer (a key
published by one process opens in the other and follows the mode chosen through either) and report."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import httpx
import numpy as np

from app.store import Store
from app.viewer import ModeViewer
from app.viewing import SharedStates
from era.examples.paper_cases import case_2
from ports import free_port

REPO = Path(__file__).resolve().parents[2]


def _serve(data_dir: Path, url: str) -> tuple[subprocess.Popen, str]:
    port = free_port()
    env = dict(os.environ, ERA_DATA_DIR=str(data_dir), ERA_DATABASE_URL=url, ERA_VIEWER="1")
    proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "app.main:app", "--host", "127.0.0.1", "--port",
                             str(port), "--log-level", "warning"], cwd=REPO, env=env, start_new_session=True)
    base = f"http://127.0.0.1:{port}"
    for _ in range(300):
        try:
            if httpx.get(base + "/api/health", timeout=1).status_code == 200:
                return proc, base
        except httpx.HTTPError:
            time.sleep(0.1)
    proc.kill()
    raise RuntimeError("an app process did not start")


def test_one_browser_session_alternating_between_two_processes(postgres_url, tmp_path):
    shared = tmp_path / "shared"
    (pa, a), (pb, b) = _serve(shared, postgres_url), _serve(shared, postgres_url)
    try:
        with httpx.Client(timeout=120) as c:
            ds = c.post(a + "/api/examples/case2").json()
            assert c.get(f"{b}/api/datasets/{ds['id']}").json()["n_outputs"] == 2
            an = c.post(b + "/api/analyses", json={"dataset_id": ds["id"], "rows": 45, "cols": 45}).json()
            step = c.get(f"{a}/api/analyses/{an['id']}/step", params={"order": 10})  # A never saw the SVD
            assert step.status_code == 200
            np.testing.assert_allclose(sorted(step.json()["modes"]["frequency_hz"])[-1], 5 / (2 * np.pi), rtol=1e-6)
            assert c.get(f"{b}/api/analyses/{an['id']}/stabilization").json()["orders"] == [2, 4, 6, 8, 10]
            pub = c.post(f"{a}/api/analyses/{an['id']}/viewer", json={"order": 10}).json()
            assert c.get(b + pub["url"]).status_code == 200          # B rebuilt the scene A published
            chosen = c.post(b + pub["mode_url"], json={"index": 2, "speed": 0})
            assert chosen.status_code == 200 and chosen.json()["index"] == 2
            made = c.post(a + "/api/reports", json={"analysis_id": an["id"], "order": 10, "modes": [0, 1]}).json()
            assert c.get(f"{b}/api/reports/{made['token']}").json()["kept"] == [0, 1]
            assert c.get(f"{b}/r/{made['token']}").status_code == 200
            assert c.get(f"{b}/api/health").json()["usage"]["rows"]["reports"] >= 1  # (the database is shared by the session)
    finally:
        for p in (pa, pb):
            p.terminate()
            p.wait(20)
    store = Store(shared, postgres_url)  # the state chosen through B is stored for every process to follow
    assert store.viewer_states([pub["key"]])[pub["key"]][0]["index"] == 2
    store.close()


def test_a_viewer_follows_the_mode_chosen_through_another_process(tmp_path):
    store = Store(tmp_path)
    scene = (None, np.array([1.0, 2.0, 3.0]), np.eye(3, dtype=complex), None)
    first, second = ModeViewer(), ModeViewer()
    for v in (first, second):
        v.states = SharedStates(store)
        v.resolver = lambda key: scene if store.viewer_key(key) else None
    key = first.publish(*scene)
    assert not second.ensure(key)                    # not in the store yet: unknown to the other process
    store.add_viewer_key(key, "some-analysis", {"kind": "modes", "order": 6})
    assert second.ensure(key) and second.registry.get(key).n_modes == 3
    first.set_mode(key, index=2, amplitude=0.3)
    second.follow_states([key], every_s=0.0)
    state = second.registry.get(key).state
    assert (state.index, state.amplitude) == (2, 0.3)
    store.close()


def test_worker_processes_end_with_the_app_process(tmp_path):
    """The SVD workers (app/compute.py) must not outlive a killed server: a restart would leak them."""
    import signal

    code = ("import os, sys, time\nfrom app import compute\n"
            "print(compute.run(os.getpid), flush=True)\ntime.sleep(60)\n")
    proc = subprocess.Popen([sys.executable, "-c", code], cwd=REPO, stdout=subprocess.PIPE, text=True)
    worker = int(proc.stdout.readline())
    assert worker != proc.pid and Path(f"/proc/{worker}").exists()
    proc.send_signal(signal.SIGKILL)
    proc.wait(10)
    for _ in range(50):
        try:
            if "zombie" in Path(f"/proc/{worker}/status").read_text().lower():
                break
        except FileNotFoundError:  # gone
            break
        time.sleep(0.1)
    else:
        raise AssertionError(f"worker {worker} outlived its killed parent")
