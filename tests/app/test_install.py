"""The app installs anywhere: the wheel built from this tree carries the page (app/static) and every package,
`era-app --help` prints its options, and the installed server, started from another folder, serves the page,
its scripts, the API and its version."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
import urllib.request
import zipfile
from pathlib import Path

import pytest

import era
from ports import free_port

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(out),
                    str(ROOT)], check=True, capture_output=True, timeout=300)
    return next(out.glob("era_modal-*.whl"))


def test_the_wheel_carries_the_page_and_every_package(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for page in ("index.html", "report.html", "js/main.js", "js/explain_view.js", "css/app.css"):
        assert f"app/static/{page}" in names
    shipped = {n.rsplit("/", 1)[0] for n in names if n.endswith("/__init__.py")}
    in_tree = {str(p.parent.relative_to(ROOT)) for top in ("era", "app") for p in (ROOT / top).rglob("__init__.py")
               if "__pycache__" not in p.parts}
    assert in_tree <= shipped, f"packages missing from pyproject's list: {sorted(in_tree - shipped)}"
    assert wheel.name.startswith(f"era_modal-{era.__version__}-")


def test_the_installed_server_runs_from_any_folder(wheel, tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True, timeout=120)
    py = venv / "bin" / "python"
    subprocess.run([str(py), "-m", "pip", "install", "-q", "--no-deps", "--force-reinstall", str(wheel)], check=True,
                   capture_output=True, timeout=300)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "ERA_DATA_DIR")}
    # the installed copy, not this checkout (the editable install points here)
    where = subprocess.run([str(py), "-c", "import app, era; print(app.__file__); print(era.__file__)"], cwd=elsewhere,
                           env=env, capture_output=True, text=True, check=True).stdout.split()
    assert all(str(venv) in w for w in where), where
    helped = subprocess.run([str(venv / "bin" / "era-app"), "--help"], cwd=elsewhere, env=env, capture_output=True,
                            text=True, timeout=60)
    assert helped.returncode == 0 and "--data-dir" in helped.stdout and "--port" in helped.stdout
    port = free_port()
    server = subprocess.Popen([str(venv / "bin" / "era-app"), "--port", str(port), "--data-dir", "store"],
                              cwd=elsewhere, env=dict(env, ERA_VIEWER="0"), stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT)
    try:
        base = f"http://127.0.0.1:{port}"
        for _ in range(300):
            try:
                page = urllib.request.urlopen(base + "/", timeout=2).read().decode()
                break
            except OSError:
                if server.poll() is not None:
                    pytest.fail(server.stdout.read().decode())
                time.sleep(0.1)
        else:
            pytest.fail("the installed server did not answer within 30 s")
        assert '<footer class="note" id="footer">' in page
        assert b"import" in urllib.request.urlopen(base + "/static/js/main.js", timeout=5).read()
        health = json.load(urllib.request.urlopen(base + "/api/health", timeout=5))
        assert (health["status"], health["version"], health["store"]) == ("ok", era.__version__, "sqlite")
        made = urllib.request.urlopen(urllib.request.Request(base + "/api/examples/case1", method="POST"), timeout=60)
        assert json.load(made)["n_samples"] == 200
        assert (elsewhere / "store" / "era.sqlite3").is_file()
    finally:
        server.terminate()
        server.wait(timeout=20)


def test_import_era_does_not_import_the_web_stack():
    code = "import sys, era; print(sorted({m.split('.')[0] for m in sys.modules} & {'fastapi', 'starlette', 'uvicorn', 'viser', 'plotly', 'app'}))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip() == "[]"
