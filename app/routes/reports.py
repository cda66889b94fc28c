"""Reports: freeze an analysis (POST), read it back (GET), download it as HTML, CSV or UFF 55."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import FileResponse, HTMLResponse, Response
from pydantic import BaseModel, Field

from .. import engine as eng
from .. import reporting
from ..engine import NotFound
from ..store import new_token
from .deps import engine, jobs, progress_key

router = APIRouter(prefix="/api/reports", tags=["reports"])
#: Mode-shape recordings for the report's viser playback, at most this many (kept modes first).
MAX_RECORDINGS = 12


class ReportRequest(BaseModel):
    analysis_id: str = Field(min_length=1, max_length=100)
    order: int = Field(ge=1)
    modes: list[int] = Field(description="indices of the kept modes at this order")


def _recording_name(k: int) -> str:
    return f"mode_{k}.viser"


@router.post("", summary="Freeze an analysis into a report; returns its token and link")
async def create(request: Request, body: ReportRequest):
    e = engine(request)
    e.analysis(body.analysis_id)  # 404 first
    viewer = request.app.state.viewer
    version = request.app.version

    def work():
        model = e.model(body.analysis_id, body.order)
        kept = eng.parse_modes(body.modes, model.n_modes)
        report = reporting.build(e, body.analysis_id, body.order, kept, version)
        files = {}
        geometry = e.dataset(e.analysis(body.analysis_id)[0])[1]
        if viewer is not None and hasattr(viewer, "record"):
            for k in kept.tolist()[:MAX_RECORDINGS]:
                files[_recording_name(k)] = viewer.record(geometry, model.frequency_hz, model.shapes, k)
        report["recordings"] = {str(k): name for k, name in
                                ((int(n.split("_")[1].split(".")[0]), n) for n in files)}
        token = new_token()
        e.store.add_report(token, body.analysis_id, report, files)  # on disk before the link is returned
        return token

    token = await jobs(request).heavy(work, progress=progress_key(request),
                                      message=f"Freezing the report and recording {min(len(body.modes), MAX_RECORDINGS)} mode shapes")
    return {"token": token, "url": f"/r/{token}"}


def _report(request: Request, token: str) -> dict:
    report = engine(request).store.report(token)
    if report is None:
        raise NotFound("No report with this link: check that the whole link was copied.")
    return report


@router.get("/{token}", summary="A frozen report as JSON")
async def read(request: Request, token: str):
    report = dict(_report(request, token), token=token, url=f"/r/{token}")
    viewer = request.app.state.viewer
    playback = {}
    if viewer is not None and hasattr(viewer, "playback_url"):
        for k, name in report.get("recordings", {}).items():
            playback[k] = viewer.playback_url(f"/api/reports/{token}/files/{name}")
    report["playback"] = playback
    return report


@router.get("/{token}/files/{name}", summary="A file of a report (mode-shape recordings)")
async def file(request: Request, token: str, name: str):
    path = engine(request).store.report_file(token, name)
    if path is None or name == "report.json":
        raise NotFound(f"No file {name!r} in this report.")
    return FileResponse(path, media_type="application/octet-stream")


@router.get("/{token}/report.html", summary="The report as one self-contained HTML file (opens offline)")
async def download_html(request: Request, token: str):
    report = _report(request, token)
    store = engine(request).store

    def build():
        recordings = {k: store.report_file(token, name).read_bytes()
                      for k, name in report.get("recordings", {}).items() if store.report_file(token, name)}
        page, encoded = reporting.offline_viser(request.app.state.viewer, recordings)
        return reporting.standalone_html(report, token, page, encoded)

    html = await jobs(request).quick(build)
    return HTMLResponse(html, headers={"Content-Disposition": f'attachment; filename="era-report-{token[:8]}.html"'})


@router.get("/{token}/modes.csv", summary="The modes of the report as CSV")
async def download_csv(request: Request, token: str):
    text = reporting.modes_csv(_report(request, token))
    return Response(text, media_type="text/csv; charset=utf-8",
                    headers={"Content-Disposition": f'attachment; filename="era-modes-{token[:8]}.csv"'})


@router.get("/{token}/modes.uff", summary="The kept modes as UFF 55, with the geometry as UFF 15/82")
async def download_uff(request: Request, token: str):
    blob = await jobs(request).quick(reporting.modes_uff, _report(request, token))
    return Response(blob, media_type="application/octet-stream",
                    headers={"Content-Disposition": f'attachment; filename="era-modes-{token[:8]}.uff"'})
