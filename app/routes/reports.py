"""Reports: freeze an analysis (POST), read it back (GET), download it as HTML, CSV or UFF 55."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import FileResponse, HTMLResponse, Response

import era

from .. import explaining, reporting, schemas, viewing
from ..choosing import Diagram
from ..errors import NotFound
from ..schemas import ReportRequest
from ..store import new_token
from .analyses import diagrammed, identified
from .deps import cache, find_analysis, jobs, progress_key, store

router = APIRouter(prefix="/api/reports", tags=["reports"])
#: Mode-shape recordings for the report's viser playback, at most this many (kept modes first).
MAX_RECORDINGS = 12


def _kept(body: ReportRequest, diagram: Diagram) -> tuple[int, list[int]]:
    """(order, kept modes) of a report: as asked, with era's choice for what is not (era.EraError when modes are
    left out where the choice names none: at another order, or when it chose no mode)."""
    order = diagram.order if body.order is None else body.order
    if body.modes is not None:
        return order, body.modes
    if order != diagram.order or not diagram.chosen_indices:
        why = (f"modes at order {diagram.order} only" if diagram.chosen_indices else "no mode of this analysis")
        raise era.EraError(f"Name the modes kept at order {order} (`modes`): the automatic choice keeps {why}.")
    return order, diagram.chosen_indices


def _recording_name(k: int) -> str:
    return f"mode_{k}.viser"


@router.post("", summary="Freeze an analysis into a report (by default at the chosen order with the chosen modes); "
             "returns its token and link",
             response_model=schemas.ReportCreated)
async def create(request: Request, body: ReportRequest):
    a = await find_analysis(request, body.analysis_id)
    c, viewer, version = cache(request), request.app.state.viewer, request.app.version
    ident = await identified(request, a)
    diagram = await diagrammed(request, a)
    order, modes = _kept(body, diagram)

    def work():
        model = c.model(a, order)
        kept = era.kept_modes(model, modes)
        recorded = kept.tolist()[:MAX_RECORDINGS] if viewer is not None else []
        geometry, frequency_hz, shapes, _ = viewing.modes_scene(a, model)  # at every point measured or struck
        files = {_recording_name(k): viewer.record(geometry, frequency_hz, shapes, k) for k in recorded}
        recordings = {str(k): _recording_name(k) for k in recorded}
        structure = c.store.model(a.dataset_id)
        explanation = explaining.for_report(c.store.explanation(a.id), c.store.explanation_responses(a.id), structure)
        report = reporting.build(a, ident, model, kept, diagram, dataset=c.summary(a.dataset_id),
                                 explanation=explanation, recordings=recordings, version=version,
                                 plot_points=c.settings.max_plot_points, structure=structure)
        token = new_token()
        c.store.add_report(token, a.id, report, files)  # on disk before the link is returned
        return token

    token = await jobs(request).heavy(work, progress=progress_key(request),
                                      message=f"Freezing the report and recording {min(len(modes), MAX_RECORDINGS)} mode shapes")
    return {"token": token, "url": f"/r/{token}"}


def _report(request: Request, token: str) -> dict:
    report = store(request).report(token)
    if report is None:
        raise NotFound("No report with this link: check that the whole link was copied.")
    return report


@router.get("/{token}", summary="A frozen report as JSON", response_model=schemas.Report)
async def read(request: Request, token: str):
    report = dict(_report(request, token), token=token, url=f"/r/{token}")
    viewer = request.app.state.viewer
    playback = {}
    if viewer is not None:
        for k, name in report.get("recordings", {}).items():
            playback[k] = viewer.playback_url(f"/api/reports/{token}/files/{name}")
    report["playback"] = playback
    return report


@router.get("/{token}/files/{name}", summary="A file of a report (mode-shape recordings)", response_class=FileResponse,
            responses={200: {"content": {"application/octet-stream": {}}, "description": "the file's bytes"}})
async def file(request: Request, token: str, name: str):
    path = store(request).report_file(token, name)
    if path is None or name == "report.json":
        raise NotFound(f"No file {name!r} in this report.")
    return FileResponse(path, media_type="application/octet-stream")


@router.get("/{token}/report.html", summary="The report as one self-contained HTML file (opens offline)",
            response_class=HTMLResponse)
async def download_html(request: Request, token: str):
    report = _report(request, token)
    files = store(request)

    def build():
        recordings = {k: files.report_file(token, name).read_bytes()
                      for k, name in report.get("recordings", {}).items() if files.report_file(token, name)}
        page, encoded = reporting.offline_viser(request.app.state.viewer, recordings)
        return reporting.standalone_html(report, token, page, encoded)

    html = await jobs(request).quick(build)
    return HTMLResponse(html, headers={"Content-Disposition": f'attachment; filename="era-report-{token[:8]}.html"'})


@router.get("/{token}/modes.csv", summary="The modes of the report as CSV", response_class=Response,
            responses={200: {"content": {"text/csv": {}}, "description": "one row per mode"}})
async def download_csv(request: Request, token: str):
    text = reporting.modes_csv(_report(request, token))
    return Response(text, media_type="text/csv; charset=utf-8",
                    headers={"Content-Disposition": f'attachment; filename="era-modes-{token[:8]}.csv"'})


@router.get("/{token}/modes.uff", summary="The kept modes as UFF 55, with the geometry as UFF 15/82",
            response_class=Response,
            responses={200: {"content": {"application/octet-stream": {}}, "description": "a UFF file"}})
async def download_uff(request: Request, token: str):
    blob = await jobs(request).quick(reporting.modes_uff, _report(request, token))
    return Response(blob, media_type="application/octet-stream",
                    headers={"Content-Disposition": f'attachment; filename="era-modes-{token[:8]}.uff"'})
