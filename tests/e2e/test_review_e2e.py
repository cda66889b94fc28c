"""What a person sees on the USC cantilever (issue 28's screenshot review), in a real browser:

- the 3-D viewer shows the whole structure: viser's control panel starts minimized, so nothing but the canvas is
  under the viewer's centre or the points around it (the software-WebGL notice that only a GPU-less headless
  browser gets is left out of the count);
- the model step's file input shows its button and "No file chosen" whole (it was clipped to "Choose File N");
- the import step's plot of the records fits its card (drawn while the step was still hidden, it was 700 px wide);
- the import step says what was read in one sentence, with real plurals (it said it twice, the second time in
  "1 channel(s), 1 record(s)"), and the dataset's conversion names its start sample (was "sample(s) [1826]");
- the modes table shows "—" where a number would mislead: frequency and damping of a real pole (no oscillation),
  μ and 1 − MAC with one sensor (1 and 0 by construction), each with its reason on hover; the close pair's ± is
  marked as the group's (one σ by design, era.core.decomposition.repeated_clusters);
- the model step says in words, not only on hover, why "Describe it from the test geometry" is disabled;
- the shape bar chart's legend is above its plot area (its white box covered the top of the bars).

Same server and browser setup as the other browser tests (app_server.py, conftest.py) (Debian's Chromium, never downloaded). Screenshots go to
$APP_SHOTS when set.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

from app_server import Server, open_page

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

pytestmark = pytest.mark.e2e

USC = SHARED_DATASETS / "usc_cantilever_free_decay" / "timeseries_data.lvm"

#: In the viewer's page: what is under nine points of its canvas (15, 50 and 85 % of its width and height).
UNDER_THE_CANVAS = """() => {
  const canvas = [...document.querySelectorAll('canvas')].sort((a, b) => b.width * b.height - a.width * a.height)[0];
  const r = canvas.getBoundingClientRect(), hits = [];
  for (const fx of [0.15, 0.5, 0.85]) for (const fy of [0.15, 0.5, 0.85]) {
    const e = document.elementFromPoint(r.left + fx * r.width, r.top + fy * r.height);
    const notice = e.closest('[class*="Notification"]') !== null;
    hits.push({ at: [fx, fy], canvas: e === canvas, notice, what: `${e.tagName}.${String(e.className).slice(0, 60)}` });
  }
  const labels = [...document.querySelectorAll('*')].filter(e => e.children.length === 0 &&
                   ['Mode', 'Amplitude', 'Speed'].includes(e.textContent.trim()) && e.getClientRects().length > 0);
  return { size: [r.width, r.height], hits, open_controls: labels.length };
}"""


#: Each row of the modes table: {column key: [text, title]} and its type.
TABLE_CELLS = """() => [...document.querySelectorAll('#modes-table tbody tr')].map(tr => {
  const row = {};
  for (const td of tr.querySelectorAll('td[data-key]')) row[td.dataset.key] = [td.textContent, td.title || ''];
  row.type = row.is_pair[0];
  return row;
})"""

#: The shape bar chart: the bottom of its legend's box and the top of its plot area (px).
LEGEND_AND_PLOT = """() => {
  const box = document.getElementById('shape-plot');
  return { legend_bottom: box.querySelector('.legend').getBoundingClientRect().bottom,
           plot_top: box.querySelector('.nsewdrag').getBoundingClientRect().top };
}"""


def test_the_viewer_shows_the_whole_structure_and_the_model_file_input_is_whole(tmp_path, browser, shots):
    lvm = require_shared(USC)
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page, errors = open_page(server, browser, 1100)
        page.set_input_files("#file", str(lvm))
        page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr")
        page.wait_for_selector("#import-plot .main-svg")
        plot = page.evaluate("() => { const box = document.getElementById('import-plot'); "
                             "return { drawn: box.querySelector('.main-svg').getBoundingClientRect().width, "
                             "box: box.clientWidth }; }")
        assert 0 < plot["drawn"] <= plot["box"], plot  # drawn while hidden it took Plotly's 700 px, past the card
        page.locator("#panel-data").screenshot(path=str(shots / "review-import.png"))
        assert page.text_content("#import-files") == "timeseries_data.lvm · 1.60 MB"  # was "1 file(s): ..."
        assert page.text_content("#import-read") == (
            "timeseries_data.lvm: LabVIEW LVM, 1 record of 81920 samples × 1 channel, Δt = 0.000605469 s "
            "(1651.61 Hz, from the X_Value column); read as “free decays” unless you say otherwise.")
        assert not re.search(r"[A-Za-z]\(s\)", page.text_content("#panel-data"))
        page.click("#import-use")
        page.wait_for_selector("#modes-table tbody tr:not(.rejected)", timeout=240000)
        summary = page.text_content("#panel-data")
        assert re.search(r"free decay from sample \d+ \(t = ", summary) and "[" not in summary, summary
        cells = page.evaluate(TABLE_CELLS)
        real = [c for c in cells if c["type"] == "real"]
        assert real and all(c["frequency_hz"] == ["—", "a real pole: no oscillation"]
                            and c["damping_ratio"] == ["—", "a real pole: no oscillation"] for c in real), real
        assert all(c["mpc"] == ["—", "one sensor"] and c["shape_scatter"] == ["—", "one sensor"] for c in cells)
        pair = [c for c in cells if c["frequency_hz"][0].startswith(("116.8", "117.2"))]
        assert len(pair) == 2 and all(c["frequency_hz"][0].endswith("(group)") for c in pair), pair
        assert all("the ± of the group of modes" in c["frequency_hz"][1] for c in pair), pair
        assert "one ± for the group" in page.text_content("#table-note")
        why = page.locator("#model-from-geometry-why")
        assert page.is_disabled("#model-from-geometry") and why.is_visible()
        assert why.text_content() == "This dataset has no trace lines: upload a model file instead."
        file_input = page.evaluate("() => { const e = document.getElementById('model-file'); "
                                   "return { scroll: e.scrollWidth, client: e.clientWidth }; }")
        assert 0 < file_input["scroll"] <= file_input["client"], file_input  # was 189 > 108: "Choose File N"
        page.locator("#panel-model").screenshot(path=str(shots / "review-model-file.png"))
        page.click("#modes-table tbody tr:not(.rejected) >> nth=0")
        page.wait_for_selector("#shape-plot .legend")
        legend = page.evaluate(LEGEND_AND_PLOT)
        assert legend["legend_bottom"] <= legend["plot_top"] + 1, legend  # it covered the bars' tops (1 read 0.97)
        page.wait_for_selector("#viewer-box iframe", timeout=60000)
        page.frame_locator("#viewer-box iframe").locator("text=Connected").wait_for(timeout=60000)
        page.wait_for_timeout(1500)  # the scene and the panel's placement arrive after the connection
        frame = next(f for f in page.frames if "/viser/" in f.url)
        seen = frame.evaluate(UNDER_THE_CANVAS)
        page.locator("#panel-shapes").screenshot(path=str(shots / "review-viewer.png"))
        assert seen["size"][0] > 400 and seen["size"][1] > 300, seen
        covered = [h for h in seen["hits"] if not h["canvas"] and not h["notice"]]
        assert covered == [], seen  # the panel floating open covered the right half (x 54-100 %, y 25-74 %)
        assert seen["open_controls"] == 0, seen  # minimized: its + opens the controls
        assert errors == []
    finally:
        server.stop()
