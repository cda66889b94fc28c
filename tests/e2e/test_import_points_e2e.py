"""Issue 26's "point" column in the import step, in a real browser: two shakers on masses 1 and 3 of a three-mass
chain, accelerometers on masses 1 and 2 (tests/app/test_api_import_points.py); the person types each channel's
point and the shape plot shows the three masses (mass 3 driven, not measured). Same server and browser as the other
browser tests (app_server.py, conftest.py)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from app_server import Server, open_page, table_rows

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "app"))
from test_api_import_points import shaker_csv  # noqa: E402

pytestmark = pytest.mark.e2e


def test_points_typed_for_the_channels_put_the_shape_at_every_mass(tmp_path, browser):
    path = tmp_path / "shakers.csv"
    path.write_bytes(shaker_csv())
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page, errors = open_page(server, browser, 1100)
        page.set_input_files("#file", [str(path)])
        page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr")
        assert page.eval_on_selector_all("#import-channels thead th", "t => t.map(x => x.textContent)")[-1] == "point"
        for channel, point in enumerate(["1X", "3X", "1X", "2X"]):
            page.fill(f"#import-channels input.point[data-channel='{channel}']", point)
            page.dispatch_event(f"#import-channels input.point[data-channel='{channel}']", "change")
        page.click("#import-use")
        page.wait_for_selector("#summary:not([hidden])")
        page.wait_for_selector("#modes-table tbody tr", timeout=120000)
        row = next(r for r in table_rows(page, "#modes-table") if r["kept"])
        page.click(f"#modes-table tbody tr[data-mode='{row['mode']}'] td[data-key=frequency_hz]")
        page.wait_for_function("document.getElementById('shape-plot').data?.length === 2")
        x = page.evaluate("() => document.getElementById('shape-plot').data[0].x")
        assert x == ["1X", "2X", "3X"]
        assert not errors, errors
    finally:
        server.stop()
