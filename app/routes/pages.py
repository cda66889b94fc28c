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


@router.get("/r/{token}")
async def report_page(request: Request, token: str):
    if store(request).report(token) is None:
        return HTMLResponse("<!doctype html><meta charset=utf-8><title>Report not found</title>"
                            "<h1>Report not found</h1><p>No report has this link. Check that the whole link was "
                            "copied.</p><p><a href=\"/\">Start a new analysis</a></p>", status_code=404)
    return FileResponse(config.STATIC_DIR / "report.html", media_type="text/html")


@router.get("/campaigns")
async def campaigns_page():
    return FileResponse(config.STATIC_DIR / "campaign.html", media_type="text/html")


@router.get("/c/{campaign_id}")
async def campaign_page(request: Request, campaign_id: str):
    if store(request).campaign(campaign_id) is None:
        return HTMLResponse("<!doctype html><meta charset=utf-8><title>Campaign not found</title>"
                            "<h1>Campaign not found</h1><p>No campaign has this link. Check that the whole link was "
                            "copied.</p><p><a href=\"/campaigns\">Start a campaign</a></p>", status_code=404)
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
