"""Decompression bombs (issue 29): an NPZ whose markov.npy and an HDF5 file whose gzip-chunked dataset inflate to
1 GiB of zeros from about 1 MB on the wire are refused by both upload routes with 413 naming the limit, while the
server (a real uvicorn process on 127.0.0.1) grows by less than 300 MB and stores nothing large."""

from __future__ import annotations

import io
import threading
import time
import zipfile
from pathlib import Path

import httpx
import numpy as np
import psutil
import pytest

from apiclient import live_server

INFLATED = 1 << 30  # 1 GiB of zeros
CHUNK = 1 << 22


def npz_bomb() -> bytes:
    """era's NPZ format with a 1 GiB markov (N, 1, 1) of zeros, deflated to about 1 MB."""
    n = INFLATED // 8
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (n, 1, 1)})
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as zf:
        with zf.open("markov.npy", "w", force_zip64=True) as fh:
            fh.write(header.getvalue())
            zeros = bytes(CHUNK)
            for _ in range(INFLATED // CHUNK):
                fh.write(zeros)
        dt = io.BytesIO()
        np.save(dt, np.array(0.01))
        zf.writestr("dt.npy", dt.getvalue())
    return out.getvalue()


def hdf5_bomb() -> bytes:
    """An HDF5 file with one gzip-chunked 1 GiB dataset of zeros (every chunk written, so stored) and fs."""
    import h5py

    out = io.BytesIO()
    n, chunk = INFLATED // 8, CHUNK // 8
    with h5py.File(out, "w") as f:
        ds = f.create_dataset("acc", shape=(n,), dtype="f8", chunks=(chunk,), compression="gzip",
                              compression_opts=9)
        zeros = np.zeros(chunk)
        for k in range(0, n, chunk):
            ds[k:k + chunk] = zeros
        f.attrs["fs"] = 100.0
    return out.getvalue()


@pytest.fixture(scope="module")
def bombs():
    return {"bomb.npz": npz_bomb(), "bomb.h5": hdf5_bomb()}


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    data_dir = tmp_path_factory.mktemp("bombs")
    with live_server(data_dir) as (base, pid):
        yield base, pid, data_dir


def tree_rss(pid: int) -> int:
    """Resident bytes of the process and its children."""
    root = psutil.Process(pid)
    total = 0
    for p in [root, *root.children(recursive=True)]:
        try:
            total += p.memory_info().rss
        except psutil.NoSuchProcess:
            pass
    return total


def peak_during(pid: int, work) -> tuple[object, int]:
    """(work(), the peak RSS of the process tree while it ran, sampled every 10 ms)."""
    peak, done = [tree_rss(pid)], threading.Event()

    def watch():
        while not done.is_set():
            peak[0] = max(peak[0], tree_rss(pid))
            time.sleep(0.01)

    t = threading.Thread(target=watch)
    t.start()
    try:
        result = work()
    finally:
        done.set()
        t.join()
    return result, max(peak[0], tree_rss(pid))


def largest_file(folder: Path) -> int:
    return max((p.stat().st_size for p in folder.rglob("*") if p.is_file()), default=0)


def test_bombs_are_refused_on_both_routes_with_little_memory_and_nothing_large_stored(server, bombs):
    base, pid, data_dir = server
    with httpx.Client(timeout=120) as c:
        assert c.post(base + "/api/examples/case1").status_code == 200  # warm: imports, numpy, the store
        small = io.BytesIO()  # and h5py with the HDF5 library, imported on the first HDF5 file (~15-150 MB the
        import h5py           # first time, with modules compiled): the bombs' own cost is what is measured

        with h5py.File(small, "w") as f:
            f["acc"] = np.sin(np.arange(400) / 7.0)
            f.attrs["fs"] = 100.0
        assert c.post(base + "/api/imports", files={"file": ("small.h5", small.getvalue())}).status_code == 200
        before = tree_rss(pid)
        growth = {}
        for name, blob in bombs.items():
            assert len(blob) < 2 << 20, f"{name} is {len(blob)} bytes on the wire"
            for route in ("/api/imports", "/api/datasets"):
                r, peak = peak_during(pid, lambda: c.post(base + route, files={"file": (name, blob)}))
                growth[(name, route)] = peak - before
                assert r.status_code == 413, (name, route, r.status_code, r.text)
                body = r.json()
                assert set(body) == {"error"}
                assert "ERA_MAX_UPLOAD_MB" in body["error"] and "64 MB" in body["error"], body["error"]
                assert "uncompressed" in body["error"]
    print("memory growth (MB):", {k: round(v / 2**20, 1) for k, v in growth.items()})
    assert max(growth.values()) < 300 * 2**20, growth
    assert largest_file(data_dir) < 4 << 20  # the refused imports are not kept either
    assert len(list((data_dir / "imports").glob("*/*.bin"))) == 1  # the small file only: refused imports go


def test_the_dataset_cache_is_bounded_by_bytes_and_a_dataset_by_four_uploads():
    import era
    from app.cache import LRU, CachedDataset, dataset_bytes
    from app.loading import check_stored

    def ds(mb: int) -> CachedDataset:
        return CachedDataset("x", era.ResponseData(markov=np.ones((mb * 2**17, 1, 1)), dt=0.1), None, "x")

    cache = LRU(16, max_bytes=100 * 2**20, weigh=dataset_bytes)
    for k in range(5):
        cache.put(k, ds(30))
    assert cache.nbytes <= 100 * 2**20 and cache.get(0) is None and cache.get(4) is not None
    cache.put("big", ds(150))  # alone above the bound: kept (it is in use), the others go
    assert cache.get("big") is not None and cache.get(4) is None
    check_stored(ds(8).data, 2 * 2**20)
    with pytest.raises(era.TooLargeError, match="4 × the upload limit"):
        check_stored(ds(9).data, 2 * 2**20)


def test_a_bomb_among_a_campaigns_uploaded_records_fails_alone_naming_the_limit(tmp_path):
    from era.campaign.simulated import monitoring_truth, write_campaign
    from test_api_campaigns import finish

    folder = tmp_path / "site"
    paths = write_campaign(folder, monitoring_truth(3, hours_between=3.0, damage_from=9, duration_s=300.0), seed=5)
    blob = io.BytesIO()
    np.savez_compressed(blob, markov=np.zeros((2_000_000, 1, 1)), dt=np.array(0.05))  # 16 MB from 16 kB
    files = [("file", (Path(p).name, Path(p).read_bytes(), "text/csv")) for p in paths]
    files.append(("file", ("rec_2026-03-02T09-00.npz", blob.getvalue(), "application/octet-stream")))
    from apiclient import client

    with client(tmp_path / "data", max_upload_bytes=8 * 2**20) as c:
        done = finish(c, c.post("/api/campaigns", files=files, data={"kind": "ambient", "max_order": "40"}))
    assert done["state"] == "done", done
    failed = done["result"]["failed"]
    assert len(failed) == 1 and "rec_2026-03-02T09-00.npz" in failed[0]["name"]
    assert "8.0 MB" in failed[0]["reason"] and "uncompressed" in failed[0]["reason"]
    assert len(done["result"]["records"]) == 3


def test_identifications_are_kept_within_their_bytes(tmp_path):
    from apiclient import analysis, client
    from app.cache import identification_bytes

    with client(tmp_path, cache_identification_bytes=1) as c:  # room for the newest only
        _, first = analysis(c, rows=20, cols=20)
        _, second = analysis(c, rows=21, cols=21)
        cache = c.app.state.cache
        idents = cache._idents
        assert idents.get(second["id"]) is not None and idents.get(first["id"]) is None
        assert idents.nbytes == identification_bytes(idents.get(second["id"]))
        assert c.get(f"/api/analyses/{first['id']}/step", params={"order": 4}).status_code == 200  # recomputed
