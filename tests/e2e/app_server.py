"""The app as the browser tests run it: `python3 -m uvicorn app.main:app` in a subprocess on a free 127.0.0.1 port
with its own ERA_DATA_DIR, and the helpers that read what its page shows. The fixtures (a Chromium browser,
the screenshots folder) are in conftest.py beside this file."""

from __future__ import annotations

import os
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

from ports import free_port

REPO = Path(__file__).resolve().parents[2]


class Server:
    """`python3 -m uvicorn app.main:app` on a free port; stop() ends it (and only it) and prints its log's last
    lines, which pytest shows when the test fails."""

    def __init__(self, data_dir: Path, log: Path):
        self.port = free_port()
        self.base = f"http://127.0.0.1:{self.port}"
        env = dict(os.environ, ERA_DATA_DIR=str(data_dir), ERA_VIEWER=os.environ.get("ERA_VIEWER", "1"))
        self._log, self._log_path = open(log, "ab"), log
        self.proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "app.main:app", "--host", "127.0.0.1",
                                      "--port", str(self.port)], cwd=REPO, env=env, stdout=self._log,
                                     stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 120  # a loaded 2-core machine imports era, scipy and viser slowly
        while True:
            try:
                with urllib.request.urlopen(self.base + "/api/examples", timeout=2) as r:
                    if r.status == 200:
                        return
            except OSError:
                pass
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.stop()
                raise RuntimeError(f"the app did not start; see {log}")
            time.sleep(0.2)

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(5)
        self._log.close()
        print("server log, last lines:", *self._log_path.read_text(errors="replace").splitlines()[-30:], sep="\n")


def open_page(server, browser, height: int = 1000):
    """The app's page in a new tab, and the list its JavaScript errors are collected in."""
    page = browser.new_page(viewport={"width": 1400, "height": height})
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(server.base + "/")
    return page, errors


def table_rows(page, selector: str) -> list[dict]:
    """Each body row of a modes table: its mode number, whether it is kept, and the text of every column."""
    return page.eval_on_selector_all(f"{selector} tbody tr", """rows => rows.map(tr => ({
        mode: Number(tr.dataset.mode), kept: !tr.classList.contains('rejected'),
        cells: Object.fromEntries([...tr.querySelectorAll('td[data-key]')].map(td => [td.dataset.key, td.textContent]))
    }))""")
