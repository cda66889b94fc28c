"""Modes in one click (issue 25), in a real browser on the real files: what a person sees right after "Use these
records", without touching anything. The table ticks era's choice of modes (era.choose_modes) at the order the
slider starts at, which is always one of the stabilization diagram's orders.

- the USC cantilever's LabVIEW free decay: exactly three modes below 130 Hz ticked, 6.62 / 41.4 / ~117 Hz, each once,
  and a report made at once holds the ticked modes;
- Carini's ambient rows file at 25 Hz: the slider starts at an order inside the diagram, and "Back to the automatic
  choice" returns there from another order;
- the ModeLAB beam's nine SignalCalc FRFs (band 65-1000 Hz, setup.csv's fMin and fMax, given in the import step):
  111.99 / 306.86 / 596.37 / 974.14 Hz ticked, one each.

Same server and browser setup as the other browser tests (app_server.py, conftest.py) (Debian's Chromium, never downloaded). Screenshots go to
$APP_SHOTS when set.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

from app_server import open_page, table_rows

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

pytestmark = pytest.mark.e2e

USC = SHARED_DATASETS / "usc_cantilever_free_decay" / "timeseries_data.lvm"
CARINI = SHARED_DATASETS / "carini_ambient_3ch" / "yk.txt"
MODELAB = SHARED_DATASETS / "modelab_beam_frf" / "SignalCalc"
#: The published frequencies (Hz) of each dataset (their README files).
USC_HZ = (6.62, 41.4, 117.0)
MODELAB_HZ = (111.99, 306.86, 596.37, 974.14)


#: The page is open: the table's rule is written, the diagram's status line names its orders, and the table's note
#: names the order the slider shows (all read in one go: a line read later could belong to a later step).
OPEN = """() => {
    const text = (id) => document.getElementById(id).textContent;
    const orders = text('stab-status').match(/orders \\((\\d+)–(\\d+)\\)/), order = text('order-value');
    return text('table-rule').length > 0 && orders !== null && text('table-note').endsWith(`at order ${order}`);
}"""


def opened(page) -> dict:
    """After "Use these records": wait until the slider's first order is drawn and the diagram is there, then read
    what the page shows: the order, the diagram's orders (from its status line), the ticked rows' frequencies, the
    sentence above the table."""
    page.wait_for_selector("#summary:not([hidden])")
    try:
        page.wait_for_function(OPEN, timeout=240000)
    except Exception as e:  # say what the page shows instead (an error in the plot's place, a progress line)
        seen = {s: page.text_content(s) for s in ("#stab-status", "#stab-plot", "#table-rule", "#table-note",
                                                  "#order-value")}
        raise AssertionError(f"the diagram and the table did not open: the page shows {seen}") from e
    status, order = page.text_content("#stab-status"), int(page.text_content("#order-value"))
    first, last = map(int, re.search(r"orders \((\d+)–(\d+)\)", status).groups())
    rows = table_rows(page, "#modes-table")
    ticked = sorted(float(r["cells"]["frequency_hz"].split()[0]) for r in rows if r["kept"])
    return {"order": order, "diagram": (first, last), "ticked_hz": ticked, "rule": page.text_content("#table-rule"),
            "status": status, "n_modes": len(rows)}


def one_each(ticked: list[float], targets, rtol: float) -> dict:
    """For each target frequency, the ticked frequencies within rtol of it."""
    return {f: [x for x in ticked if abs(x - f) <= rtol * f] for f in targets}


def mark_position(page, trace: str) -> dict:
    """Page coordinates of the mark of a verdict trace (the row above the diagram) farthest from any other mark."""
    return page.evaluate("""(name) => {
        const div = document.getElementById('stab-plot'), fl = div._fullLayout;
        const marks = div.data.filter(t => t.yaxis === 'y3'), t = marks.find(tr => tr.name === name);
        const all = marks.flatMap(tr => tr.x);
        const gap = (x) => Math.min(...all.filter(v => v !== x).map(v => Math.abs(v - x)));
        const x = t.x.reduce((best, v) => (gap(v) > gap(best) ? v : best), t.x[0]);
        const box = div.getBoundingClientRect();
        return { x: box.left + fl.xaxis._offset + fl.xaxis.l2p(x), y: box.top + fl.yaxis3._offset + fl.yaxis3.l2p(t.y[0]),
                 frequency: x };
    }""", trace)


def in_diagram(shown: dict) -> bool:
    first, last = shown["diagram"]
    return first <= shown["order"] <= last and (shown["order"] - first) % 2 == 0


def test_the_usc_cantilever_opens_with_its_three_modes_ticked_each_once(tmp_path, browser, shots, server):
    lvm = require_shared(USC)
    page, errors = open_page(server, browser, 1100)
    # requests the page sends for what it knows is not there (a model, an explanation); a progress poll of a
    # request answered from memory before it became a job is not one (progress is best effort)
    missing = []
    page.on("response", lambda r: missing.append(r.url)
            if r.status == 404 and "/api/" in r.url and "/api/jobs/" not in r.url else None)
    page.set_input_files("#file", str(lvm))
    page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr")
    page.click("#import-use")
    shown = opened(page)
    print("USC cantilever, as opened:", shown)
    page.locator("#panel-table").screenshot(path=str(shots / "choice-usc-table.png"))
    page.screenshot(path=str(shots / "choice-usc.png"), full_page=True)
    below = [f for f in shown["ticked_hz"] if f < 130.0]
    found = one_each(below, USC_HZ, 0.012)
    assert len(below) == 3 and all(len(v) == 1 for v in found.values()), (shown, found)
    assert in_diagram(shown) and shown["rule"].startswith("Ticked: the "), shown
    # the diagram marks the chosen modes (green, numbered) above its poles, the others grey with a reason
    marks = page.evaluate("""() => Object.fromEntries(document.getElementById('stab-plot').data
        .filter(t => t.yaxis === 'y3').map(t => [t.name, t.x.length]))""")
    assert marks["chosen modes"] == len(shown["ticked_hz"]) and marks["other candidates (hover: why not)"] > 0
    # hovering over a grey mark says why it was left out; over a green one, which mode it is
    page.locator("#stab-plot").scroll_into_view_if_needed()
    for name, words in (("other candidates (hover: why not)", "not chosen: "), ("chosen modes", "chosen automatically: mode")):
        where = mark_position(page, name)
        page.mouse.move(where["x"], where["y"])
        page.wait_for_function(f"[...document.querySelectorAll('#stab-plot .hovertext')]"
                               f".some(n => n.textContent.includes({words!r}))", timeout=10000)
        print(f"hover over {where['frequency']:.4g} Hz:", page.text_content("#stab-plot .hovertext"))
    page.locator("#panel-stab").screenshot(path=str(shots / "choice-usc-diagram-hover.png"))
    # a report made without touching anything holds exactly the chosen modes, and says so
    page.click("#create-report")
    page.wait_for_selector("#report-link-box:not([hidden])", timeout=120000)
    report = browser.new_page(viewport={"width": 1400, "height": 1000})
    report.goto(server.base + page.get_attribute("#report-link", "href"))
    report.wait_for_selector("body[data-ready='1']", timeout=60000)
    kept = sorted(float(r["cells"]["frequency_hz"].split()[0]) for r in table_rows(report, "#report-table")
                  if r["kept"])
    assert kept == shown["ticked_hz"], (kept, shown["ticked_hz"])
    assert "the modes era chose automatically" in report.text_content("#report-meta")
    # not the grid: no grid-only control, and Run says what to do instead of asking the server
    assert page.locator("#field-explain-gravity").is_hidden()
    page.click("#explain-run")
    page.wait_for_selector("#explain-error:not([hidden])")
    assert "no model of this structure yet" in page.text_content("#explain-error")
    assert "grid" not in page.text_content("#explain-error")
    assert not errors, errors
    assert not missing, missing


def test_carinis_ambient_records_open_at_an_order_inside_the_diagram(tmp_path, browser, shots, server):
    yk = require_shared(CARINI)
    page, errors = open_page(server, browser, 1100)
    page.set_input_files("#file", str(yk))
    page.wait_for_selector("#import-error-dt:not([hidden])")
    page.fill("#import-rate", "25")  # Δt = 0.04 s
    page.select_option("#import-orientation", "rows")
    page.wait_for_function("!document.getElementById('import-use').disabled")
    page.click("#import-use")
    shown = opened(page)
    print("Carini yk.txt at 25 Hz, as opened:", shown)
    page.screenshot(path=str(shots / "choice-carini.png"), full_page=True)
    assert in_diagram(shown), shown
    # the current order's line is drawn inside the diagram, not on an axis stretched above it
    assert page.get_attribute("#stab-marks", "data-order") == str(shown["order"])
    # one step away the thresholds tick, and one click brings the automatic choice back
    page.focus("#order")
    page.keyboard.press("ArrowRight")
    page.wait_for_function(f"document.getElementById('table-note').textContent.endsWith('at order {shown['order'] + 1}')")
    assert page.text_content("#table-rule").startswith("Ticked by the thresholds") and page.is_visible("#use-choice")
    page.click("#use-choice")
    page.wait_for_function(f"document.getElementById('table-note').textContent.endsWith('at order {shown['order']}')")
    assert opened(page)["ticked_hz"] == shown["ticked_hz"] and page.is_hidden("#use-choice")
    assert not errors, errors


def test_the_modelab_beams_nine_frfs_open_with_its_four_modes_ticked_one_each(tmp_path, browser, shots, server):
    folder = require_shared(MODELAB)
    files = [str(folder / f"ASCII0000{k}" / f"Hxysv0000{k}.txt") for k in range(1, 10)]
    page, errors = open_page(server, browser, 1100)
    page.set_input_files("#file", files)
    page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr", timeout=120000)
    assert page.is_visible("#field-band")  # FRFs: the band they are valid in (setup.csv: fMin 65, fMax 1000)
    page.fill("#import-band-low", "65")
    page.fill("#import-band-high", "1000")
    page.click("#import-use")
    shown = opened(page)
    print("ModeLAB beam, nine SignalCalc FRFs, band 65-1000 Hz, as opened:", shown)
    page.screenshot(path=str(shots / "choice-modelab.png"), full_page=True)
    assert "band 65–1000 Hz" in page.text_content("#summary")
    assert in_diagram(shown), shown
    found = one_each(shown["ticked_hz"], MODELAB_HZ, 0.003)
    assert len(shown["ticked_hz"]) == 4 and all(len(v) == 1 for v in found.values()), (shown, found)
    assert not errors, errors
