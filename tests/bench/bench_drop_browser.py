"""Drop → stabilization diagram in a real browser, for the two largest shared datasets (the speed a person feels
first; target 3 s).

A real server (`python3 -m uvicorn app.main:app`, its workers started with it) and Debian's Chromium (headless,
software rendering). Per dataset, twice on the same server ("fresh": the server's first upload; "warm": the same
files again): the files are given to the page's file input as a drop gives them, "Use these records" is pressed
as soon as the import step allows it, and the clock stops when the stabilization diagram is drawn and painted (its
plot holds the poles, then the next frame). Timed in the page (performance.now()), from the moment the files are
set: ``drop → preview`` (upload and reading, until the button is enabled) and ``use → diagram`` (the dataset, the
identification and the diagram's request, and plotly's drawing); their sum is "drop → diagram" without the
person's own pause. The page's requests are listed from its resource timings (start and end, ms after the drop)
so what the page waits on shows.

    nice -n 5 python3 -m pytest tests/bench/bench_drop_browser.py -s
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "e2e"))
from app_server import Server  # noqa: E402
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

pytestmark = pytest.mark.bench

CHROMIUM = "/usr/bin/chromium"  # Debian's, as tests/e2e/conftest.py starts it
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]

DATASETS = [
    ("USC cantilever (LVM free decay)", ["usc_cantilever_free_decay/timeseries_data.lvm"], {}),
    ("ModeLAB beam (9 SignalCalc FRFs)",
     [f"modelab_beam_frf/SignalCalc/ASCII0000{k}/Hxysv0000{k}.txt" for k in range(1, 10)], {}),
]
#: Target, s, from the drop to the diagram drawn (issue: 3 s).
TARGET = 3.0

#: The diagram is drawn: its plot holds the poles and the chosen modes' marks.
DRAWN = "document.getElementById('stab-plot').data?.length > 0 && " \
        "(document.getElementById('stab-plot').layout?.shapes || []).length > 0"
#: The end of the next frame (what the eye sees).
PAINTED = "new Promise((resolve) => requestAnimationFrame(() => setTimeout(() => resolve(performance.now()), 0)))"


def drop_to_diagram(page, paths: list[Path]) -> dict:
    """Seconds of drop → preview and use → diagram, timed in the page, and the page's requests (ms after the drop)."""
    page.evaluate("performance.clearResourceTimings(); Plotly.purge('stab-plot')")  # the last run's diagram
    page.evaluate("window.__t0 = performance.now()")
    page.set_input_files("#file", [str(p) for p in paths])
    page.wait_for_function("!document.getElementById('import').hidden && "
                           "!document.getElementById('import-use').disabled", timeout=300000, polling="raf")
    ready = page.evaluate("performance.now()")
    page.click("#import-use")
    clicked = page.evaluate("performance.now()")
    page.wait_for_function(DRAWN, timeout=300000, polling="raf")
    painted = page.evaluate(PAINTED)
    t0 = page.evaluate("window.__t0")
    requests = page.evaluate("""(t0) => performance.getEntriesByType('resource')
        .filter((e) => e.name.includes('/api/') && !e.name.includes('/api/jobs/'))
        .map((e) => [new URL(e.name).pathname.replace(/[0-9a-f]{16,}|[A-Za-z0-9_-]{20,}/g, '…'),
                     Math.round(e.startTime - t0), Math.round(e.responseEnd - t0), e.encodedBodySize])""", t0)
    return {"preview": (ready - t0) / 1000, "diagram": (painted - clicked) / 1000,
            "total": (ready - t0 + painted - clicked) / 1000, "requests": requests}


@pytest.mark.parametrize("name,files,options", DATASETS, ids=[d[0].split(" (")[0] for d in DATASETS])
def test_drop_to_diagram(name, files, options, tmp_path):
    from playwright import sync_api
    paths = [require_shared(SHARED_DATASETS / f) for f in files]
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        time.sleep(3.0)  # the workers start with the server; a person takes longer to find the file
        with sync_api.sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
            try:
                page = browser.new_page(viewport={"width": 1400, "height": 1000})
                errors = []
                page.on("pageerror", lambda e: errors.append(str(e)))
                page.goto(server.base + "/")
                page.wait_for_load_state("networkidle")
                runs = {}
                for run in ("fresh", "warm"):
                    runs[run] = drop_to_diagram(page, paths)
                assert not errors, errors
            finally:
                browser.close()
    finally:
        server.stop()
    for run, t in runs.items():
        print(f"\n{name} {run}: drop → diagram {t['total']:.2f} s (drop → preview {t['preview']:.2f} s, "
              f"use → diagram drawn {t['diagram']:.2f} s; target {TARGET} s)")
        for path, start, end, size in t["requests"]:
            print(f"    {start:6d} → {end:6d} ms  {path}  ({size / 1024:.0f} kB)")
