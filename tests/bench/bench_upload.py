"""Upload → chosen modes over HTTP, for every shared dataset the app reads (the speed a person feels first).

A real server (`python3 -m uvicorn app.main:app`, its worker pool started with it) on this machine; per dataset the
import's three requests as the page sends them (stage the files, make the dataset with the import's options,
identify with the defaults) and the stabilization answer that carries the chosen modes. Each dataset is sent twice:
"fresh" is the first upload the server ever sees (one new server per dataset: its workers started, nothing
computed yet), "warm" the same files again on that server. The figures are ratios to one dense SVD of the
dataset's own H(0) in this process (1 BLAS thread), and seconds for the targets (1.5 s warm, 2.5 s fresh).

    python3 -m pytest tests/bench/bench_upload.py -s
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import httpx
import numpy as np
import pytest
from threadpoolctl import threadpool_limits

import era

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "e2e"))
from app_server import Server  # noqa: E402
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

pytestmark = pytest.mark.bench

#: (name, files, the import's options as the page sends them when the person has said what the file does not)
DATASETS = [
    ("USC cantilever (LVM free decay)", ["usc_cantilever_free_decay/timeseries_data.lvm"], {}),
    ("Carini (ambient rows, 25 Hz)", ["carini_ambient_3ch/yk.txt"],
     {"dt": 0.04, "orientation": "rows", "kind": "ambient"}),
    ("ModeLAB beam (9 SignalCalc FRFs)",
     [f"modelab_beam_frf/SignalCalc/ASCII0000{k}/Hxysv0000{k}.txt" for k in range(1, 10)],
     {"band_hz": [65.0, 1000.0]}),
    ("LADISK hammer (5 .npy)", [f"ladisk_pyfrf_impact/measurements_{k}.npy" for k in range(1, 6)], {}),
    ("MPSTD (UFF 58)", ["pyuff_samples/MPSTD_Set001_2024_10_08.uff"], {}),
]


def upload_to_modes(base: str, paths: list[Path], options: dict) -> tuple[float, dict]:
    """Seconds from the first byte sent to the chosen modes' answer, and that answer."""
    files = [("file", (p.name, p.read_bytes())) for p in paths]
    with httpx.Client(base_url=base, timeout=300) as c:
        t0 = time.perf_counter()
        staged = c.post("/api/imports", files=files)
        assert staged.status_code == 200, staged.text
        ds = c.post(f"/api/imports/{staged.json()['id']}/dataset", json=options)
        assert ds.status_code == 200, ds.text
        ds = ds.json()
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": ds["defaults"]["rows"],
                                          "cols": ds["defaults"]["cols"]})
        assert a.status_code == 200, a.text
        stab = c.get(f"/api/analyses/{a.json()['id']}/stabilization")
        assert stab.status_code == 200, stab.text
        return time.perf_counter() - t0, stab.json() | {"hankel_shape": a.json()["hankel_shape"]}


def one_svd_seconds(shape) -> float:
    """One dense SVD of a random matrix of H(0)'s shape, 1 BLAS thread (the best of 3)."""
    h = np.random.default_rng(0).standard_normal(tuple(shape))
    best = np.inf
    with threadpool_limits(1):
        for _ in range(3):
            t = time.perf_counter()
            np.linalg.svd(h, full_matrices=False)
            best = min(best, time.perf_counter() - t)
    return best


@pytest.mark.parametrize("name,files,options", DATASETS, ids=[d[0].split(" (")[0] for d in DATASETS])
def test_upload_to_chosen_modes(name, files, options, tmp_path):
    paths = [require_shared(SHARED_DATASETS / f) for f in files]
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        time.sleep(3.0)  # the workers import era (started with the server); a person takes longer to drop a file
        fresh, stab = upload_to_modes(server.base, paths, options)
        warm, again = upload_to_modes(server.base, paths, options)
    finally:
        server.stop()
    svd = one_svd_seconds(stab["hankel_shape"])
    chosen = [round(c["frequency_hz"], 2) for c in stab["candidates"] if c["code"] == "chosen"]
    print(f"\n{name}: H(0) {stab['hankel_shape'][0]} × {stab['hankel_shape'][1]}, {len(chosen)} chosen "
          f"{chosen}; upload → chosen modes fresh {fresh:.2f} s ({fresh / svd:.1f} × one SVD), warm {warm:.2f} s "
          f"({warm / svd:.1f} ×); one SVD {svd:.3f} s; era {era.__version__}")
    assert [c["code"] for c in again["candidates"]] == [c["code"] for c in stab["candidates"]]  # the same choice
