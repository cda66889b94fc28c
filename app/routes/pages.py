"""HTML pages and the vendored plotly.js (served from the installed plotly package: no CDN)."""

from __future__ import annotations

from pathlib import Path

import plotly
from fastapi import APIRouter, Form, Request
from fastapi.responses import FileResponse, HTMLResponse, RedirectResponse

from .. import config
from ..access import login_page
from .deps import store

router = APIRouter(include_in_schema=False)
PLOTLY_JS = Path(plotly.__file__).parent / "package_data" / "plotly.min.js"


@router.get("/")
async def index():
    return FileResponse(config.STATIC_DIR / "index.html", media_type="text/html")


def _not_found(what: str, back: str, back_text: str) -> HTMLResponse:
    """The 404 page of a shared link (report, campaign) that leads nowhere."""
    return HTMLResponse(f"<!doctype html><meta charset=utf-8><title>{what.title()} not found</title>"
                        f"<h1>{what.title()} not found</h1><p>No {what} has this link. Check that the whole link was "
                        f"copied.</p><p><a href=\"{back}\">{back_text}</a></p>", status_code=404)


@router.get("/r/{token}")
async def report_page(request: Request, token: str):
    if store(request).report(token) is None:
        return _not_found("report", "/", "Start a new analysis")
    return FileResponse(config.STATIC_DIR / "report.html", media_type="text/html")


@router.get("/campaigns")
async def campaigns_page():
    return FileResponse(config.STATIC_DIR / "campaign.html", media_type="text/html")


@router.get("/c/{campaign_id}")
async def campaign_page(request: Request, campaign_id: str):
    if store(request).campaign(campaign_id) is None:
        return _not_found("campaign", "/campaigns", "Start a campaign")
    return FileResponse(config.STATIC_DIR / "campaign.html", media_type="text/html")


@router.get("/vendor/plotly.min.js")
async def plotly_js():
    return FileResponse(PLOTLY_JS, media_type="application/javascript",
                        headers={"Cache-Control": "public, max-age=86400"})


@router.get("/login")
async def login_form(request: Request, next: str = "/"):
    if request.app.state.access.token is None:
        return RedirectResponse("/", status_code=303)
    return login_page("This server is for its team: give the access token the administrator shared.", 200, next)


@router.post("/login")
async def login(request: Request, token: str = Form(""), next: str = Form("/")):
    return request.app.state.access.login(token, next)
