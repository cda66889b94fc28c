"""Issue 26 in a real browser: the ModeLAB roving-hammer beam uploaded as its nine SignalCalc files with its
setup.csv shows each mode's shape at the nine hit points (1X … 9X along the beam), not one bar for its one
accelerometer; the first bending mode has both ends against the middle. Same server and browser as the other
browser tests (app_server.py, conftest.py); screenshots to $APP_SHOTS when set."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from app_server import Server, open_page, table_rows
from test_choice_e2e import MODELAB_HZ, opened

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

pytestmark = pytest.mark.e2e

MODELAB = SHARED_DATASETS / "modelab_beam_frf" / "SignalCalc"


def test_the_modelab_beam_with_its_setup_shows_the_shape_at_nine_points(tmp_path, browser, shots):
    folder = require_shared(MODELAB)
    files = [str(folder / f"ASCII0000{k}" / f"Hxysv0000{k}.txt") for k in range(1, 10)] + [str(folder / "setup.csv")]
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page, errors = open_page(server, browser, 1100)
        page.set_input_files("#file", files)
        page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr", timeout=120000)
        # setup.csv proposes the band (fMin 65 Hz, fMax 1000 Hz)
        assert (page.input_value("#import-band-low"), page.input_value("#import-band-high")) == ("65", "1000")
        page.click("#import-use")
        shown = opened(page)
        first = min(shown["ticked_hz"])
        assert abs(first - MODELAB_HZ[0]) < 0.003 * MODELAB_HZ[0], shown
        row = next(r for r in table_rows(page, "#modes-table") if r["kept"])  # the table is sorted by frequency
        page.click(f"#modes-table tbody tr[data-mode='{row['mode']}'] td[data-key=frequency_hz]")
        page.wait_for_function("document.getElementById('shape-title').textContent.includes('111.9')")
        bars = page.evaluate("""() => { const d = document.getElementById('shape-plot').data;
                                        return { x: d[0].x, re: d[0].y, im: d[1].y }; }""")
        assert bars["x"] == [f"{k}X" for k in range(1, 10)], bars
        # the first bending mode (largest component real 1): both ends move against the middle
        assert max(abs(v) for v in bars["im"]) < 0.1 and bars["re"][0] * bars["re"][-1] > 0 > bars["re"][0] * bars["re"][4]
        page.wait_for_selector("#viewer-box iframe", state="attached", timeout=60000)
        page.screenshot(path=str(shots / "points-modelab.png"), full_page=True)
        assert not errors, errors
    finally:
        server.stop()
