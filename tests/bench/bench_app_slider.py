"""Speed of the order slider on the grid example, through the HTTP API (the browser's two requests per step).

Run: python3 -m pytest tests/bench/bench_app_slider.py -s
One slider step = GET /modes?order=n&fit=false and GET /reconstruction?order=n&thresholds (the page sends both
at once; here one after the other).
Reference: the analysis' own SVD (POST /api/analyses, H(0) 792 × 798), in the same process: a step must
cost a small fraction of it (the SVD is never recomputed). On the 2-core reference machine (lightly loaded) a
step is 20-35 ms over orders 20-60 and the SVD 0.16-0.7 s; we assert a median step ≤ 0.5 × the SVD and print
both in ms. The browser adds drawing (table, diagram shapes, reconstruction curve): the e2e test prints it.
"""

import statistics
import time

import pytest
from fastapi.testclient import TestClient

pytest.importorskip("era.simulate")

from app.config import Settings  # noqa: E402
from app.main import create_app  # noqa: E402


def test_slider_step_is_a_fraction_of_the_svd(tmp_path):
    with TestClient(create_app(Settings(data_dir=tmp_path, viewer=False))) as c:
        ds = c.post("/api/examples/grid").json()
        body = {"dataset_id": ds["id"], **{k: ds["defaults"][k] for k in ("rows", "cols", "max_order")}}
        svd = []
        for _ in range(3):
            t = time.perf_counter()
            a = c.post("/api/analyses", json=body).json()
            svd.append(time.perf_counter() - t)
        steps = []
        for n in range(20, 61):
            t = time.perf_counter()
            assert c.get(f"/api/analyses/{a['id']}/modes", params={"order": n, "fit": False}).status_code == 200
            r = c.get(f"/api/analyses/{a['id']}/reconstruction",
                      params={"order": n, "min_emac": 0.9, "min_mpc": 0.9, "min_contribution": 0.01, "physical_only": True})
            assert r.status_code == 200
            steps.append(time.perf_counter() - t)
    step, ref = statistics.median(steps), statistics.median(svd)
    print(f"\nslider step on the grid (orders 20-60): median {1e3 * step:.1f} ms, "
          f"p90 {1e3 * sorted(steps)[int(0.9 * len(steps))]:.1f} ms; SVD (POST /api/analyses) {1e3 * ref:.0f} ms; "
          f"ratio {step / ref:.3f}")
    assert step <= 0.5 * ref
