"""A page of static/ as one self-contained HTML file that opens with no server: its plotly.js (from the installed
plotly package, no CDN), its CSS and its scripts written into it, and the document it shows as a global. The
downloaded reports (an analysis's, a campaign's, a multi-setup test's) are made here.
"""

from __future__ import annotations

import base64
from pathlib import Path

from . import config

#: The tags of static/'s pages that a download replaces by what they load.
PLOTLY_TAG = '<script src="/vendor/plotly.min.js"></script>'
CSS_TAG = '<link rel="stylesheet" href="/static/css/app.css">'


def static_text(*parts: str) -> str:
    """A file of static/ (e.g. "js", "report.js") as text."""
    return config.STATIC_DIR.joinpath(*parts).read_text(encoding="utf-8")


def plotly_js() -> str:
    """plotly.js as the installed plotly package ships it (what /vendor/plotly.min.js serves)."""
    import plotly
    return (Path(plotly.__file__).parent / "package_data" / "plotly.min.js").read_text(encoding="utf-8")


def script(body: str, module: bool = False) -> str:
    """A <script> element holding ``body`` (a "</script" inside cannot end it early)."""
    tag = '<script type="module">' if module else "<script>"
    return tag + body.replace("</script", "<\\/script") + "</script>"


def module_inlined(name: str) -> str:
    """static/js/``name`` as an ES module with its imports of sibling modules ("./x.js") inlined as data: URLs, so
    it runs from a file with no server. The imported modules must not import others themselves."""
    body = static_text("js", name)
    for line in [ln for ln in body.splitlines() if ln.startswith("import ") and ' from "./' in ln]:
        dep = line.split(' from "./', 1)[1].split('"', 1)[0]
        inner = static_text("js", dep)
        if any(ln.startswith("import ") for ln in inner.splitlines()):
            raise RuntimeError(f"static/js/{dep} imports another module: the download cannot inline it")
        url = "data:text/javascript;base64," + base64.b64encode(inner.encode("utf-8")).decode("ascii")
        body = body.replace(line, line.replace(f'"./{dep}"', f'"{url}"'))
    return body


def offline_page(page: str, swaps: dict[str, str]) -> str:
    """static/``page`` with plotly.js and the CSS inlined and each tag of ``swaps`` replaced by its text (the page's
    scripts and data). RuntimeError when the page lost a tag (the download would load it from a server)."""
    html = static_text(page)
    swaps = {PLOTLY_TAG: script(plotly_js()), CSS_TAG: "<style>" + static_text("css", "app.css") + "</style>",
             **swaps}
    for old, new in swaps.items():
        if old not in html:
            raise RuntimeError(f"static/{page} lost the line {old!r} that the download inlines")
        html = html.replace(old, new)
    return html
