"""Helpers for the API tests: an app on a temporary data folder, and small datasets as upload files."""

from __future__ import annotations

import io
import os
import socket
import subprocess
import sys
import time
import urllib.request
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

import numpy as np
from fastapi.testclient import TestClient

import era
import era.examples.paper_cases
from app.config import Settings
from app.main import create_app


@contextmanager
def client(data_dir: Path, raise_errors: bool = True, **overrides):
    """A TestClient with the lifespan running (store, pools); the viser viewer off unless asked for."""
    settings = replace(Settings(data_dir=Path(data_dir), viewer=False), **overrides)
    with TestClient(create_app(settings), raise_server_exceptions=raise_errors) as c:
        yield c


REPO = Path(__file__).resolve().parents[2]


@contextmanager
def live_server(data_dir: Path, log=subprocess.DEVNULL, **env):
    """``uvicorn app.main:app`` in a process of its own on a free port of 127.0.0.1 (ERA_DATA_DIR = ``data_dir``, the
    viewer off, SQLite; ``env`` adds variables), once it answers; yields (base URL, pid) and ends it after."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    base = f"http://127.0.0.1:{port}"
    variables = {k: v for k, v in os.environ.items() if k != "ERA_DATABASE_URL"}
    variables.update({"ERA_DATA_DIR": str(data_dir), "ERA_VIEWER": "0", **env})  # env may turn the viewer on
    proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "app.main:app", "--host", "127.0.0.1", "--port",
                             str(port), "--log-level", "warning"], cwd=REPO, env=variables, stdout=log,
                            stderr=subprocess.STDOUT, start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        while True:
            try:
                with urllib.request.urlopen(base + "/api/examples", timeout=2):
                    break
            except OSError:
                if proc.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError("the app did not start") from None
                time.sleep(0.1)
        yield base, proc.pid
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()


def npz_bytes(data: era.ResponseData, geometry: era.Geometry | None = None) -> bytes:
    buf = io.BytesIO()
    era.save_npz(buf, data, geometry)
    return buf.getvalue()


def case1_npz() -> bytes:
    return npz_bytes(era.examples.paper_cases.case_1(200))


def upload(c: TestClient, blob: bytes, name: str = "case1.npz"):
    return c.post("/api/datasets", files={"file": (name, blob, "application/octet-stream")})


def analysis(c: TestClient, rows: int = 90, cols: int = 90, **extra) -> tuple[dict, dict]:
    """Upload Case I and identify it; returns (dataset, analysis)."""
    ds = upload(c, case1_npz()).json()
    r = c.post("/api/analyses", json=dict(dataset_id=ds["id"], rows=rows, cols=cols, **extra))
    assert r.status_code == 200, r.text
    return ds, r.json()


def case1_frequencies_hz() -> np.ndarray:
    return np.arange(1, 6) / (2 * np.pi)  # eq. 58: Im s_j = j rad/s
