"""Speed of the order slider on the grid example, through the HTTP API.

Run: python3 -m pytest tests/bench/bench_app_slider.py -s
One slider step = GET /step?order=n&thresholds, the one request the page sends (the modes and the reconstruction);
also timed: the two requests it replaced, GET /modes?order=n&fit=false and GET /reconstruction?order=n&thresholds,
one after the other, on a second analysis (so neither finds its orders cached).
Reference: the analysis' own SVD (POST /api/analyses, H(0) 792 × 798), in the same process: a step must
cost a small fraction of it (the SVD is never recomputed). On the 2-core reference machine (lightly loaded) a
step is 20-35 ms over orders 20-60 and the SVD 0.16-0.7 s; we assert a median step ≤ 0.5 × the SVD and print
both in ms. The browser adds drawing (table, diagram shapes, reconstruction curve):
tests/bench/bench_slider_browser.py measures it end to end.
"""

import statistics
import time

from fastapi.testclient import TestClient

from app.config import Settings
from app.main import create_app


def test_slider_step_is_a_fraction_of_the_svd(tmp_path):
    with TestClient(create_app(Settings(data_dir=tmp_path, viewer=False))) as c:
        ds = c.post("/api/examples/grid").json()
        body = {"dataset_id": ds["id"], **{k: ds["defaults"][k] for k in ("rows", "cols", "max_order")}}
        svd = []
        for _ in range(3):
            t = time.perf_counter()
            a = c.post("/api/analyses", json=body).json()
            svd.append(time.perf_counter() - t)
        b = c.post("/api/analyses", json=body).json()
        thresholds = {"min_emac": 0.9, "min_mpc": 0.9, "min_contribution": 0.01, "physical_only": True}
        steps, pairs = [], []
        for n in range(20, 61):
            t = time.perf_counter()
            assert c.get(f"/api/analyses/{a['id']}/step", params={"order": n, **thresholds}).status_code == 200
            steps.append(time.perf_counter() - t)
            t = time.perf_counter()
            assert c.get(f"/api/analyses/{b['id']}/modes", params={"order": n, "fit": False}).status_code == 200
            r = c.get(f"/api/analyses/{b['id']}/reconstruction", params={"order": n, **thresholds})
            assert r.status_code == 200
            pairs.append(time.perf_counter() - t)
    step, pair, ref = statistics.median(steps), statistics.median(pairs), statistics.median(svd)
    print(f"\nslider step on the grid (orders 20-60), GET /step: median {1e3 * step:.1f} ms, "
          f"p90 {1e3 * sorted(steps)[int(0.9 * len(steps))]:.1f} ms; GET /modes + GET /reconstruction: median "
          f"{1e3 * pair:.1f} ms; SVD (POST /api/analyses) {1e3 * ref:.0f} ms; ratio step / SVD {step / ref:.3f}")
    assert step <= 0.5 * ref
