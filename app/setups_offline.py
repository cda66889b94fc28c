"""A multi-setup test's report (app.setups.freeze) as one self-contained HTML file: static/setups.html with
plotly.js, the CSS, the page's module and the frozen document inlined (app.offline_page, as an analysis's report),
the merged modes' CSV and UFF 55 inside it as downloads; it opens offline and shows the merged modes table, the
shapes and their geometry as the report's link does."""

from __future__ import annotations

import base64

import era

from . import setups_export
from .offline_page import module_inlined, offline_page, script
from .reporting import script_json

#: The page's module tag that the download replaces by the document and the module itself.
MODULE_TAG = '<script type="module" src="/static/js/setups.js"></script>'


def standalone_html(frozen: dict) -> str:
    """The report ``frozen`` (schemas.SetupsTest with ``report``) as one HTML file that opens with no server."""
    merged = frozen["merged"]
    files = {"csv": base64.b64encode(setups_export.modes_csv(merged).encode("utf-8")).decode("ascii")}
    try:
        files["uff"] = base64.b64encode(setups_export.modes_uff(merged)).decode("ascii")
    except era.EraError:  # no mode known at every point: the CSV alone
        pass
    data = script_json(dict(frozen, standalone=True, offline_files=files))
    return offline_page("setups.html", {MODULE_TAG: f"<script>window.SETUPS_DATA = {data};</script>"
                                                    + script(module_inlined("setups.js"), module=True)})
