"""The order slider end to end in a real browser, on the grid example: slider input -> poles, table and
reconstruction drawn and painted.

Run: python3 -m pytest tests/bench/bench_slider_browser.py -s
Starts the app as the tests do (apiclient.live_server: uvicorn on a free port, a temporary data folder), opens
the page in Debian's Chromium (software rendering), loads the grid example and presses the arrow key on the focused
slider ~20 times, one step after the other, each to an order not shown before (so the server realizes it: no
cache help).

Per step, timed in the page from the input event's timeStamp (so the wait for the page's main thread counts):
- ``drawn``: until the DOM shows that order in all three panels: the table (its note), the stabilization diagram
  (its current-order marks) and a new reconstructed curve drawn after those two (MutationObservers, no polling;
  not the page's own record, so any way of drawing is timed the same way);
- ``painted``: to the end of the next frame after that (requestAnimationFrame, then a task): what the eye sees.
After each step (outside the timing) the bench checks that the panels show that order: the table note, the order
marks of the diagram, and the drawn reconstruction against the server's own answer for that order.
The page's own split (window.eraTiming: fetch, drawing calls, the frame plotly draws the curve in) is printed too.

Reference in the same run: the server-only time of a step (the requests the page sends for one order, over HTTP
from Python, on a second analysis of the same data so no order is cached). Also a fast drag: 15 inputs 5 ms
apart, then the time until the last order's panels are painted (stale requests must not queue up).

Measured on the 2-core machine (load ~3 from other jobs), three runs each, orders 31-50, input -> painted:
before (two requests per step, plotly relayouts, newPlot-style redraws): median 109-114 ms, p90 132-160 ms,
server-only 17-26 ms (GET /modes + GET /reconstruction), fast drag 94-253 ms; after: median 43-49 ms, p90 51-57 ms,
server-only 9-12 ms (GET /step), fast drag 44-80 ms.
"""

from __future__ import annotations

import json
import statistics
import sys
import time
import urllib.error
import urllib.parse
import urllib.request
from pathlib import Path

import pytest

CHROMIUM = "/usr/bin/chromium"
if not Path(CHROMIUM).exists():
    pytest.skip("Debian's chromium is not installed", allow_module_level=True)
sync_api = pytest.importorskip("playwright.sync_api")

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tests" / "app"))
from apiclient import live_server  # noqa: E402  (the tests' one way to start the app on a free port)

ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]
STEPS = 20
THRESHOLDS = {"min_emac": 0.9, "min_mpc": 0.9, "min_contribution": 0.01, "physical_only": "true"}

# Installed once per page: the timeStamp of each slider input, and __watch(order): window.__pending, a promise of
# the time at which the three panels show that order (``drawn``) and of the end of the next frame (``painted``).
# A curve counts only if drawn once the table and the diagram show the order (the page draws the curve first, or
# in the next frame), so an earlier order's curve from a drag does not. Armed before the key press.
HOOK = """() => {
  window.__inputs = [];
  document.getElementById('order').addEventListener('input', (e) => window.__inputs.push(e.timeStamp), true);
  const $ = (id) => document.getElementById(id);
  window.__watch = (order) => { window.__pending = new Promise((resolve) => {
    let curve = false;
    const table = () => $('table-note').textContent.endsWith(`at order ${order}`);
    const poles = () => $('stab-marks')?.dataset.order === String(order);
    const watchers = [];
    const check = () => {
      if (!(curve && table() && poles())) return;
      watchers.forEach((w) => w.disconnect());
      const drawn = performance.now();
      requestAnimationFrame(() => setTimeout(() => resolve({ drawn, painted: performance.now() }), 0));
    };
    const observe = (id, onChange) => {
      const w = new MutationObserver(() => { onChange(); check(); });
      w.observe($(id), { subtree: true, childList: true, attributes: true, characterData: true });
      watchers.push(w);
    };
    observe('recon-plot', () => { if (table() && poles()) curve = true; });
    observe('table-note', () => {});
    observe('stab-plot', () => {});
  }); };
}"""


def get(base: str, path: str, params: dict | None = None, method: str = "GET", body: dict | None = None):
    q = "" if not params else "?" + urllib.parse.urlencode(params)
    req = urllib.request.Request(base + path + q, method=method,
                                 data=None if body is None else json.dumps(body).encode(),
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=60) as r:
        return json.loads(r.read())


def summary(values) -> str:
    v = sorted(values)
    return f"median {statistics.median(v):.1f} ms, p90 {v[int(0.9 * (len(v) - 1) + 0.5)]:.1f} ms, max {v[-1]:.1f} ms"


@pytest.fixture()
def server(tmp_path):
    with live_server(tmp_path / "data") as (base, _pid):
        yield base


def server_step(base: str, analysis_id: str, order: int) -> None:
    """The request of one slider step as the page sends it: GET /step (the modes and the reconstruction).
    (Before /step existed the page sent GET /modes and GET /reconstruction at once: run this bench on such a
    checkout and it times those two, one after the other.)"""
    p, params = f"/api/analyses/{analysis_id}", {"order": order, **THRESHOLDS, "output": 0, "input": 0}
    try:
        get(base, f"{p}/step", params)
    except urllib.error.HTTPError as err:
        if err.code != 404:
            raise
        get(base, f"{p}/modes", {"order": order, "fit": "false"})
        get(base, f"{p}/reconstruction", params)


def test_slider_in_the_browser(server):
    base = server
    with sync_api.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 1400, "height": 1000})
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(base + "/")
        page.click("button[data-example=grid]")
        page.wait_for_function("window.eraTiming && window.eraTiming.parts.length > 0", timeout=60000)
        page.wait_for_function("document.getElementById('stab-plot').data?.length > 3", timeout=60000)
        page.wait_for_timeout(500)
        page.evaluate(HOOK)
        analysis_id = page.evaluate("location.hash").split("analysis=")[1].split("&")[0]
        start = int(page.text_content("#order-value"))
        page.focus("#order")
        drawn, painted, orders = [], [], []
        for i in range(STEPS):
            order = start + i + 1
            page.evaluate("(order) => window.__watch(order)", order)
            page.keyboard.press("ArrowRight")
            t = page.evaluate("async () => { const r = await window.__pending; const t0 = window.__inputs.at(-1);"
                              " return [r.drawn - t0, r.painted - t0]; }")
            drawn.append(t[0])
            painted.append(t[1])
            orders.append(order)
            page.wait_for_function(f"window.eraTiming.parts.at(-1).order === {order}")
            check_panels(page, base, analysis_id, order)
        parts = page.evaluate(f"window.eraTiming.parts.slice(-{STEPS})")

        # a fast drag: 15 inputs 5 ms apart (each a new order), then time to the last order painted
        drag = []
        for rep in range(3):
            first = start + STEPS + 1 + 15 * rep
            page.evaluate("(order) => window.__watch(order)", first + 14)
            t = page.evaluate("""async (first) => {
                const s = document.getElementById('order');
                for (let k = 0; k < 15; k++) {
                  s.value = first + k; s.dispatchEvent(new Event('input', { bubbles: true }));
                  await new Promise((r) => setTimeout(r, 5));
                }
                const t0 = window.__inputs.at(-1);
                return (await window.__pending).painted - t0;
            }""", first)
            drag.append(t)
            page.wait_for_function(f"window.eraTiming.parts.at(-1).order === {first + 14}")
            check_panels(page, base, analysis_id, first + 14)
        assert not errors, errors
        browser.close()

    # server-only reference, same run: a second analysis of the same data (nothing cached), the same orders
    a = get(base, f"/api/analyses/{analysis_id}")
    body = {k: a[k] for k in ("dataset_id", "rows", "cols")} | {"max_order": a["requested_max_order"]}
    other = get(base, "/api/analyses", method="POST", body=body)["id"]
    server_ms = []
    for order in orders:
        t0 = time.perf_counter()
        server_step(base, other, order)
        server_ms.append(1e3 * (time.perf_counter() - t0))
    print(f"\nslider on the grid, orders {orders[0]}-{orders[-1]}, {STEPS} steps in headless Chromium:"
          f"\n  input -> drawn:   {summary(drawn)}"
          f"\n  input -> painted: {summary(painted)}"
          f"\n  server only (the page's request for one order over HTTP): {summary(server_ms)}"
          f"\n  ratio painted / server (medians): {statistics.median(painted) / statistics.median(server_ms):.2f}"
          f"\n  the page's own record (window.eraTiming, median ms): "
          + ", ".join(f"{k} {statistics.median(p[k] for p in parts):.1f}" for k in parts[0] if k != "order") +
          f"\n  fast drag, 15 inputs 5 ms apart, last input -> last order painted: "
          f"{', '.join(f'{x:.0f}' for x in drag)} ms")
    assert statistics.median(painted) < 100  # the requirement (measured: 43-49 ms, 2 cores at load ~3)


def check_panels(page, base: str, analysis_id: str, order: int) -> None:
    """The table, the diagram's order line and the reconstruction all show ``order`` (the server's answer)."""
    note = page.text_content("#table-note")
    assert note.endswith(f"at order {order}"), note
    marks = page.evaluate("(() => { const m = document.getElementById('stab-marks');"
                          " return [Number(m.dataset.order), m.querySelectorAll('circle').length]; })()")
    n_modes = int(note.split(" of ")[1].split()[0])
    assert marks == [order, n_modes], (marks, order, n_modes)  # the order line, a ring on each of its poles
    curve = page.evaluate("document.getElementById('recon-plot').data[1].y")
    truth = get(base, f"/api/analyses/{analysis_id}/reconstruction",
                {"order": order, **THRESHOLDS, "output": 0, "input": 0})
    step = max(1, round(len(truth["reconstructed"]) / len(curve)))
    assert curve == truth["reconstructed"][::step][: len(curve)], f"order {order}: reconstruction is not this order's"
