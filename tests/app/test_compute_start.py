"""The worker processes start with the server and import era before the first upload, so the first analysis does
not pay for them (a spawned worker starts with nothing: numpy, scipy and era take a second or more to import)."""

import time
from pathlib import Path

from apiclient import live_server


def spawned_workers(pid: int) -> list[int]:
    """The children of ``pid`` that are multiprocessing's spawned workers."""
    out = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        for child in (task / "children").read_text().split():
            try:
                cmd = Path(f"/proc/{child}/cmdline").read_bytes().replace(b"\0", b" ")
            except OSError:
                continue
            if b"spawn_main" in cmd:
                out.append(int(child))
    return out


def imported_era(pid: int) -> bool:
    """True when process ``pid`` has era's modules loaded (one of its compiled files mapped or its source open is
    not visible; numpy's OpenBLAS mapped is: era imports numpy and scipy's LAPACK)."""
    maps = Path(f"/proc/{pid}/maps").read_text()
    return "openblas" in maps and "_flapack" in maps


def test_the_workers_start_with_the_server_and_import_era_before_any_request(tmp_path):
    with live_server(tmp_path, ERA_HEAVY_WORKERS="2") as (_, pid):
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            workers = spawned_workers(pid)
            if len(workers) == 2 and all(imported_era(w) for w in workers):
                break
            time.sleep(0.2)
        assert len(workers) == 2, workers
        assert all(imported_era(w) for w in workers)
