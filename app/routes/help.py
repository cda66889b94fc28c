"""The docs site at /help/: the MkDocs build of docs/ (``mkdocs build``), served by the app with no internet.

The folder is ``ERA_DOCS_DIR`` when set, else ``site/`` beside the source tree (where ``mkdocs build`` writes it).
When it was not built, /help/ says how to build it; the page's help links then land there.
"""

from __future__ import annotations

import mimetypes
import os
from pathlib import Path

from fastapi import APIRouter
from fastapi.responses import FileResponse, HTMLResponse, RedirectResponse

router = APIRouter(include_in_schema=False)

SOURCE_TREE = Path(__file__).resolve().parents[2]


def site_dir() -> Path:
    """Where the built site is looked for, on every request (a build made while the app runs is served at once)."""
    return Path(os.environ.get("ERA_DOCS_DIR") or SOURCE_TREE / "site")


def _not_built(site: Path) -> HTMLResponse:
    return HTMLResponse(
        "<!doctype html><meta charset=utf-8><title>Help not built</title>"
        "<h1>The help pages are not built</h1>"
        "<p>This server serves the docs site from <code>" + _escape(str(site)) + "</code>, which holds no site yet. "
        "Build it once from the project's folder:</p>"
        "<pre>python3 -m pip install -e '.[docs]'\nmkdocs build --strict</pre>"
        "<p>or build it elsewhere (<code>mkdocs build -d FOLDER</code>) and start the app with "
        "<code>ERA_DOCS_DIR=FOLDER</code>. The same pages are the Markdown files in <code>docs/</code>.</p>"
        "<p><a href=\"/\">Back to the analysis</a></p>", status_code=404)


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


@router.get("/help")
async def help_root():
    return RedirectResponse("/help/", status_code=307)


@router.get("/help/{path:path}")
async def help_page(path: str = ""):
    site = site_dir().resolve()
    if not (site / "index.html").is_file():
        return _not_built(site)
    target = (site / path).resolve()
    if not target.is_relative_to(site):
        return _missing(path)
    if target.is_dir():
        if path and not path.endswith("/"):  # relative links inside a page need the trailing slash
            return RedirectResponse(f"/help/{path}/", status_code=307)
        target = target / "index.html"
    if not target.is_file():
        return _missing(path)
    media_type = mimetypes.guess_type(target.name)[0] or "application/octet-stream"
    return FileResponse(target, media_type=media_type)


def _missing(path: str) -> HTMLResponse:
    return HTMLResponse("<!doctype html><meta charset=utf-8><title>No such help page</title>"
                        f"<h1>No such help page</h1><p>/help/{_escape(path)} is not a page of the docs site.</p>"
                        "<p><a href=\"/help/\">The help's first page</a></p>", status_code=404)
