"""Campaigns: start one on uploaded files or a server folder (POST), follow it and read its result (GET), download
its table as CSV and its report as one HTML file."""

from __future__ import annotations

import os

from fastapi import APIRouter, File, Form, Request, UploadFile
from fastapi.responses import FileResponse, HTMLResponse

import era

from .. import campaigns, loading, schemas
from ..campaigns import Campaigns
from ..errors import NotFound

router = APIRouter(prefix="/api/campaigns", tags=["campaigns"])


def service(request: Request) -> Campaigns:
    return request.app.state.campaigns


@router.post("", status_code=202, response_model=schemas.Campaign,
             summary="Start a campaign: the same analysis over many records, each mode tracked through them")
async def start(request: Request,
                file: list[UploadFile] = File(default=[], description="one part per record (one record per file)"),
                folder: str | None = Form(None, description="instead of files: a folder under the server's "
                                                            "ERA_CAMPAIGN_ROOT (see GET /api/campaigns/folders)"),
                name: str | None = Form(None, max_length=200, description="what to call the campaign"),
                kind: str = Form("auto", description="auto, ambient (NExT), decay, pulse, frf or io"),
                dt: float | None = Form(None, gt=0, description="sampling interval, s, for files without a time "
                                                                "column"),
                max_order: int = Form(80, ge=1, le=schemas.MAX_INT,
                                      description="highest order of each record's stabilization diagram")):
    """Multipart parts ``file`` (one per record; times are read from names such as rec_2026-03-02T05-00.csv, else
    the records are in the order sent) or a form field ``folder``. Answers 202 at once; GET /api/campaigns/{id}
    follows it. A file that cannot be analysed is listed in the result's ``failed``; it never stops the campaign."""
    s = service(request)
    analysis = campaigns.options(kind, dt, max_order, s.settings)
    if file and folder:
        raise era.DataError("Give the records either as files or as a server folder, not both.")
    if folder is not None:
        paths = campaigns.folder_records(s.settings.campaign_root, folder)
        names = [os.path.basename(p) for p in paths]
        row = s.start(name or f"folder {folder}", paths, names, analysis)
    else:
        if not file:
            raise era.DataError("No records: send one file part `file` per record, or a `folder` of the server.")
        files = []
        for part in file:
            files.append(((part.filename or "record").rsplit("/", 1)[-1].rsplit("\\", 1)[-1][:200], await part.read()))
        names = [n for n, _ in files]
        label = names[0] if len(names) == 1 else f"{names[0]} + {len(names) - 1} more"
        row = s.start(name or label, loading.named_sources(files), names, analysis)
    return s.status(row["id"])


@router.get("/folders", response_model=schemas.CampaignFolders,
            summary="The server folders a campaign may run on (ERA_CAMPAIGN_ROOT), where campaigns run, the limits")
async def folders(request: Request):
    s = service(request)
    root = s.settings.campaign_root
    return {"enabled": root is not None, "folders": campaigns.folders(root), "engine": campaigns.engine(s.settings),
            "max_records": s.settings.max_campaign_records}


@router.get("/{campaign_id}", response_model=schemas.Campaign,
            summary="A campaign's state and progress, and its result once done")
async def status(request: Request, campaign_id: str):
    return service(request).status(campaign_id)


@router.get("/{campaign_id}/table.csv", response_class=FileResponse, summary="The campaign's table as CSV",
            responses={200: {"content": {"text/csv": {}}, "description": "one row per record and tracked mode"}})
async def table(request: Request, campaign_id: str):
    return FileResponse(service(request).table_path(campaign_id), media_type="text/csv; charset=utf-8",
                        filename=f"era-campaign-{campaign_id[:8]}.csv")


@router.get("/{campaign_id}/campaign.html", response_class=HTMLResponse,
            summary="The campaign's report as one self-contained HTML file (opens offline)")
async def download_html(request: Request, campaign_id: str):
    status = service(request).status(campaign_id)
    if status["state"] != "done":
        raise NotFound("No finished campaign with this link: its report exists once every record is done.")
    html = await request.app.state.jobs.quick(campaigns.standalone_html, status)
    return HTMLResponse(html, headers={"Content-Disposition":
                                       f'attachment; filename="era-campaign-{campaign_id[:8]}.html"'})
