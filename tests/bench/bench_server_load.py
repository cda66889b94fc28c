"""A team server under load: N simulated browser sessions at once against one app process on this machine.

Run: python3 -m pytest tests/bench/bench_server_load.py -s            (20 sessions; 20 and 50 through a proxy)
 or: python3 tests/bench/bench_server_load.py 20 100                  (the sizes to run)
 or: python3 tests/bench/bench_server_load.py --proxy 20 50           (as a team behind the sign-in proxy)
Each session does what the page does: upload a 9 × 8 × 400 dataset (NPZ), identify it (the default Hankel size),
15 order-slider steps (GET /step), the stabilization diagram, and a report of the kept modes. A 503 or 429 is
retried after its Retry-After, as the page does, and counted. Printed: per route, requests, refusals, errors,
p50/p95/max latency; the slider's p95 while identifications run is the figure the issue asks for (< 150 ms).
Through the proxy (issue 29) the server trusts X-Forwarded-User, keeps its default rate limits, and every session
is its own engineer: limits count per user, so none may get a 429; 503 + Retry-After is the back-pressure.
Traffic goes to 127.0.0.1 only, and every loop is bounded in count and time.
"""

from __future__ import annotations

import io
import os
import statistics
import subprocess
import sys
import threading
import time
from collections import defaultdict
from pathlib import Path

import httpx

import era
from era.examples.synthetic import modal_response

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from ports import free_port  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
STEPS = 15
DEADLINE_S = 900  # the whole run stops by then whatever happens


def dataset_npz(seed: int) -> bytes:
    data, _ = modal_response([0.8, 1.9, 3.1, 4.4, 5.2, 6.7, 8.1, 9.6, 11.2, 12.9], 0.01, 9, 8, 400, 1 / 32,
                             snr_db=30, seed=seed)
    buf = io.BytesIO()
    era.save_npz(buf, data)
    return buf.getvalue()


class Log:
    """Latencies and outcomes per route, thread-safe."""

    def __init__(self):
        self.lock = threading.Lock()
        self.times = defaultdict(list)
        self.refused = defaultdict(int)
        self.limited = defaultdict(int)  # of the refusals, the 429s
        self.errors = defaultdict(list)

    def call(self, client: httpx.Client, route: str, method: str, url: str, **kw) -> httpx.Response | None:
        """One request, retried after Retry-After on 503/429 (at most 30 times); the time counts every wait."""
        t0 = time.perf_counter()
        for _ in range(30):
            r = client.request(method, url, **kw)
            if r.status_code in (429, 503):
                with self.lock:
                    self.refused[route] += 1
                    self.limited[route] += r.status_code == 429
                time.sleep(min(float(r.headers.get("retry-after", "1")), 5.0))
                continue
            break
        dt = time.perf_counter() - t0
        with self.lock:
            self.times[route].append(dt)
            if r.status_code != 200:
                self.errors[route].append(f"{r.status_code} {r.text[:120]}")
                return None
        return r


def session(base: str, log: Log, k: int, proxy: bool = False) -> None:
    user = {"X-Forwarded-User": f"engineer{k}"} if proxy else {}
    with httpx.Client(base_url=base, timeout=600, headers=user) as c:
        r = log.call(c, "upload", "POST", "/api/datasets", files={"file": (f"s{k}.npz", dataset_npz(k))})
        if r is None:
            return
        ds = r.json()
        body = {"dataset_id": ds["id"], **{x: ds["defaults"][x] for x in ("rows", "cols", "max_order")}}
        r = log.call(c, "identify", "POST", "/api/analyses", json=body)
        if r is None:
            return
        a = r.json()
        kept = []
        for n in range(20, 20 + 2 * STEPS, 2):
            r = log.call(c, "step", "GET", f"/api/analyses/{a['id']}/step",
                         params={"order": n, "min_emac": 0.9, "min_mpc": 0.9, "physical_only": True})
            if r is not None:
                kept = r.json()["reconstruction"]["kept"]
        log.call(c, "stabilization", "GET", f"/api/analyses/{a['id']}/stabilization")
        log.call(c, "report", "POST", "/api/reports",
                 json={"analysis_id": a["id"], "order": 20 + 2 * (STEPS - 1), "modes": kept})


def run(n_sessions: int, data_dir: Path, proxy: bool = False) -> Log:
    port = free_port()
    env = dict(os.environ, ERA_DATA_DIR=str(data_dir), ERA_RATE_LIMIT="100000/min", ERA_RATE_LIMIT_HEAVY="100000")
    if proxy:  # the defaults, counted per user
        env = dict(env, ERA_TRUST_USER_HEADER="X-Forwarded-User")
        env.pop("ERA_RATE_LIMIT"), env.pop("ERA_RATE_LIMIT_HEAVY")
    server = subprocess.Popen([sys.executable, "-m", "uvicorn", "app.main:app", "--host", "127.0.0.1", "--port",
                               str(port), "--log-level", "warning"], cwd=REPO, env=env)
    base = f"http://127.0.0.1:{port}"
    try:
        for _ in range(300):
            try:
                if httpx.get(base + "/api/health", timeout=2).status_code == 200:
                    break
            except httpx.HTTPError:
                time.sleep(0.1)
        log = Log()
        threads = [threading.Thread(target=session, args=(base, log, k, proxy), daemon=True)
                   for k in range(n_sessions)]
        t0 = time.perf_counter()
        for t in threads:
            t.start()
        for t in threads:
            t.join(max(1.0, DEADLINE_S - (time.perf_counter() - t0)))
        wall = time.perf_counter() - t0
    finally:
        server.terminate()
        server.wait(20)
    print(f"\n{n_sessions} sessions at once{' through the proxy, one user each' if proxy else ''}, one app process "
          f"on {os.cpu_count()} cores: {wall:.1f} s in all")
    print(f"  {'route':14s} {'requests':>8s} {'refused':>8s} {'429':>5s} {'errors':>6s} {'p50 ms':>8s} {'p95 ms':>8s} "
          f"{'max ms':>8s}")
    for route in ("upload", "identify", "step", "stabilization", "report"):
        ts = sorted(log.times[route])
        if not ts:
            continue
        p95 = ts[min(len(ts) - 1, int(0.95 * len(ts)))]
        print(f"  {route:14s} {len(ts):8d} {log.refused[route]:8d} {log.limited[route]:5d} {len(log.errors[route]):6d} "
              f"{1e3 * statistics.median(ts):8.0f} {1e3 * p95:8.0f} {1e3 * ts[-1]:8.0f}")
    for route, errs in log.errors.items():
        for e in errs[:3]:
            print(f"  error on {route}: {e}")
    return log


def test_twenty_sessions(tmp_path):
    log = run(20, tmp_path)
    assert not any(log.errors.values()), dict(log.errors)
    steps = sorted(log.times["step"])
    assert len(steps) == 20 * STEPS


def test_twenty_and_fifty_engineers_behind_the_proxy_are_never_rate_limited(tmp_path):
    for n in (20, 50):
        log = run(n, tmp_path / str(n), proxy=True)
        assert not any(log.errors.values()), dict(log.errors)
        assert not any(log.limited.values()), dict(log.limited)  # busy is 503 + Retry-After, never a 429
        assert len(log.times["report"]) == n


if __name__ == "__main__":
    import tempfile
    proxy = "--proxy" in sys.argv
    for n in [int(x) for x in sys.argv[1:] if x != "--proxy"] or [20]:
        with tempfile.TemporaryDirectory() as d:
            run(n, Path(d), proxy=proxy)
