"""Schemathesis on the app's own OpenAPI (issue 29): bounded generated examples for every operation, sent to a real
server on 127.0.0.1 (uvicorn in a subprocess, a temporary data folder). The contract: never a 5xx, and only the
statuses each operation declares. tests/app/test_api_openapi_fuzz.py adds hand-made hostile values on real ids."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

schemathesis = pytest.importorskip("schemathesis")
from hypothesis import HealthCheck, settings  # noqa: E402
from schemathesis.specs.openapi.checks import status_code_conformance  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = 10  # per operation: 38 operations in about 15 s


@pytest.fixture(scope="module")
def api_schema(tmp_path_factory):
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    base = f"http://127.0.0.1:{port}"
    folder = tmp_path_factory.mktemp("schemathesis")
    env = dict(os.environ, ERA_DATA_DIR=str(folder / "data"), ERA_VIEWER="0", ERA_RATE_LIMIT="100000/min")
    with open(folder / "server.log", "wb") as log:
        proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "app.main:app", "--host", "127.0.0.1", "--port",
                                 str(port)], cwd=REPO, env=env, stdout=log, stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + 60
        while True:
            try:
                with urllib.request.urlopen(base + "/api/examples", timeout=2):
                    break
            except OSError:
                if proc.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError(f"the app did not start; see {folder / 'server.log'}") from None
                time.sleep(0.2)
        yield schemathesis.openapi.from_url(base + "/openapi.json")
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()


schema = schemathesis.pytest.from_fixture("api_schema")


@schema.parametrize()
@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
def test_every_operation_answers_a_documented_status_and_never_a_5xx(case):
    case.call_and_validate(checks=[schemathesis.checks.not_a_server_error, status_code_conformance])
