"""The engineer's own FE model in a real browser: upload a simulated test of a cantilever plate (1.5 kg hidden on
node 28, tests/fe_test_files.py), upload the plate's Nastran deck in the Model panel, read the sentence naming the
output that matches no model node, give it its node in the mapping table, run simulation vs test and read the
point mass named at node 28.

Same server and browser setup as the other browser tests (app_server.py, conftest.py) (Debian's Chromium, never downloaded).
"""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image
from fe_test_files import deck, simulated

import era
from app_server import Server, open_page

pytestmark = pytest.mark.e2e


def test_a_deck_uploaded_in_the_model_panel_is_matched_mapped_and_explains_the_mass(tmp_path, browser):
    (tmp_path / "plate.bdf").write_text(deck())
    era.save_npz(str(tmp_path / "plate test.npz"), simulated(era.load_model(tmp_path / "plate.bdf")))
    server = Server(tmp_path / "data", tmp_path / "server.log")
    try:
        page, errors = open_page(server, browser)
        page.set_input_files("#file", str(tmp_path / "plate test.npz"))
        page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr", timeout=60000)
        page.click("#import-use")
        page.wait_for_selector("#modes-table tbody tr", timeout=120000)

        page.set_input_files("#model-file", str(tmp_path / "plate.bdf"))
        page.wait_for_selector("#model-mapping:not([hidden])", timeout=60000)
        assert "Nastran deck plate.bdf" in page.text_content("#model-summary")
        assert "EIGRL" in page.text_content("#model-summary")           # the card not modelled, said
        assert "in the model's own mass unit" in page.text_content("#model-summary")   # a deck says no unit
        unmatched = page.text_content("#model-unmatched")
        assert unmatched.startswith("1 output of 8 matches no free DOF") and "TIP z" in unmatched
        assert page.input_value("#model-map-node-0") == "4" and page.input_value("#model-map-dir-0") == "z"
        page.fill("#model-map-node-7", "1")                                # a clamped node: refused, said
        page.select_option("#model-map-dir-7", "z")
        page.click("#model-mapping-save")
        page.wait_for_selector("#model-mapping-error:not([hidden])", timeout=30000)
        assert "node 1" in page.text_content("#model-mapping-error")
        page.fill("#model-map-node-7", "35")
        page.click("#model-mapping-save")
        page.wait_for_function("document.getElementById('model-unmatched').textContent.startsWith('Every output')",
                               timeout=30000)

        page.click("#explain-run")
        page.wait_for_selector("#explain-verdict", timeout=180000)
        assert page.get_attribute("#explain-verdict", "data-verdict") == "explained"
        assert page.text_content("#explain-verdict > div").startswith("Explained: point mass")
        verdict = page.text_content("#explain-verdict")
        assert "node 28" in verdict, verdict
        assert "Nastran deck plate.bdf" in page.text_content("#explain-model")
        assert "over the FE model's mesh" in page.text_content("#explain-fe-shapes")
        page.wait_for_selector("#explain-viewers iframe", timeout=60000)
        # the plate's shells are drawn as a surface (pale blue-grey, shaded): a large area of unsaturated bluish
        # pixels, where trace lines alone leave the white background with thin coloured and grey lines
        frame = page.frame_locator("#explain-viewers iframe >> nth=0")
        frame.get_by_text("Connected").wait_for(timeout=60000)
        iframe = page.locator("#explain-viewers iframe >> nth=0")
        iframe.scroll_into_view_if_needed()
        page.wait_for_timeout(3000)
        box = iframe.bounding_box()
        png = page.screenshot(path=str(tmp_path / "surface.png"), clip=box)
        img = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
        surface = (img[..., 2] - img[..., 0] > 15) & (img.max(axis=-1) - img.min(axis=-1) < 60)
        assert surface.sum() > 0.03 * surface.size, (surface.sum(), surface.size)   # 7 % measured, lines alone 1 %
        assert not errors, errors
    finally:
        server.stop()
