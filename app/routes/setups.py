"""Multi-setup tests: upload the setups' files (POST), pick the references and merge (POST .../merge), read the
test back (GET), the merged modes as CSV and UFF 55, the merged shapes in the 3-D viewer; the page (/setups) and
its link (/s/{id}), which reopens the merged result."""

from __future__ import annotations

from fastapi import APIRouter, File, Form, HTTPException, Request, UploadFile
from fastapi.responses import FileResponse, HTMLResponse, Response

from .. import config, setups, setups_export, setups_offline
from ..errors import NotFound
from ..schemas.analyses import ViewerLink
from ..schemas.reports import ReportCreated
from ..schemas.setups import SetupsRequest, SetupsTest
from .datasets import read_parts
from .deps import cache, jobs, progress_key, store

router = APIRouter(tags=["setups"])


@router.post("/api/setups", response_model=SetupsTest,
             summary="Upload a multi-setup test: one file per setup, each read as a single upload is")
async def create(request: Request,
                 file: list[UploadFile] = File(description="one part per setup (at least two), in the test's order"),
                 kind: str = Form("auto", description="auto, ambient (NExT), decay, pulse, frf or io"),
                 dt: float | None = Form(None, gt=0, description="sampling interval, s, for files without a time "
                                                                 "column"),
                 name: str | None = Form(None, max_length=200, description="what to call the test")):
    """Every file is read as one setup, kept and analysed (era.analyse, era's defaults); the answer proposes the
    references from the data (era.reference_evidence), else from the names when they are not generic. Refusals (422) name the form control that fixes them in ``option``: file, kind or dt."""
    files = await read_parts(file)
    settings = cache(request).settings
    return await jobs(request).heavy(setups.create, store(request), settings, files, kind, dt, name,
                                     progress=progress_key(request), 
                                     message=f"Reading and analysing {len(files)} setups")


@router.get("/api/setups/{test_id}", response_model=SetupsTest, summary="A multi-setup test and its last merge")
async def read(request: Request, test_id: str):
    return await jobs(request).quick(setups.load, store(request), test_id)


@router.post("/api/setups/{test_id}/merge", response_model=SetupsTest,
             summary="Analyse every setup (era.analyse) and merge them through the references (era.merge_setups)")
async def merge(request: Request, test_id: str, body: SetupsRequest):
    """The test with its new merge. A refusal (422, ``option`` "references") says which setup's references do not
    match; ``option`` "points" when the points table is wrong; ``option`` "file" when a setup's records cannot be
    analysed or are no longer stored."""
    test = await jobs(request).quick(setups.load, store(request), test_id)
    settings = cache(request).settings
    merged = await jobs(request).heavy(setups.merge_test, store(request), settings, test, body.references, body.points,
                                       body.next_references, body.method,
                                       progress=progress_key(request),
                                       message=f"Analysing {len(test['setups'])} setups and merging them")
    return dict(test, merged=merged)


@router.post("/api/setups/{test_id}/nodes", response_model=SetupsTest,
             summary="Give the test's nodes as a UFF file (UFF 15 nodes, 82 trace lines) for a points table "
                     "point,node,direction")
async def nodes(request: Request, test_id: str,
                file: UploadFile = File(description="a UFF file with the nodes (and trace lines)")):
    """The test with its nodes; the next merge's points table may put its points on these nodes. A file without
    nodes is refused (422, ``option`` "points")."""
    (name, blob), = await read_parts([file])
    return await jobs(request).quick(setups.set_nodes, store(request), cache(request).settings, test_id, name, blob)


async def _merged(request: Request, test_id: str) -> dict:
    test = await jobs(request).quick(setups.load, store(request), test_id)
    if test["merged"] is None:
        raise NotFound("This test is not merged yet: pick its references and merge it first.")
    return test


@router.get("/api/setups/{test_id}/modes.csv", summary="The merged modes as CSV (unknown values empty)",
            response_class=Response,
            responses={200: {"content": {"text/csv": {}}, "description": "one row per merged mode"}})
async def modes_csv(request: Request, test_id: str):
    test = await _merged(request, test_id)
    return Response(setups_export.modes_csv(test["merged"]), media_type="text/csv; charset=utf-8",
                    headers={"Content-Disposition": f'attachment; filename="era-setups-{test_id[:8]}.csv"'})


@router.get("/api/setups/{test_id}/modes.uff", summary="The merged modes known at every point as UFF 55",
            response_class=Response, responses={200: {"content": {"application/octet-stream": {}},
                             "description": "UFF 15 nodes, 82 lines, one 55 set per complete mode; the header "
                                            "X-ERA-Left-Out says which modes are not in it"}})
async def modes_uff(request: Request, test_id: str):
    test = await _merged(request, test_id)
    blob = await jobs(request).quick(setups_export.modes_uff, test["merged"])
    headers = {"Content-Disposition": f'attachment; filename="era-setups-{test_id[:8]}.uff"'}
    said = setups_export.left_out(test["merged"])
    if said:
        headers["X-ERA-Left-Out"] = said.encode("ascii", "replace").decode("ascii")
    return Response(blob, media_type="application/octet-stream", headers=headers)


@router.post("/api/setups/{test_id}/viewer", response_model=ViewerLink,
             summary="Publish the merged shapes to the viser viewer (on the geometry, else the points in a row)")
async def viewer(request: Request, test_id: str):
    test = await _merged(request, test_id)  # an unknown test is a 404 first, on every server
    return await _published(request, test)


# ---- reports: the last merge frozen, its link reopens it ------------------------------------------------------------
@router.post("/api/setups/{test_id}/report", response_model=ReportCreated,
             summary="Freeze the last merge into a report; its link (/s/{id}/r/{token}) reopens the merged modes "
                     "on their geometry")
async def freeze(request: Request, test_id: str):
    return await jobs(request).quick(setups.freeze, store(request), test_id)


@router.get("/api/setups/{test_id}/reports/{token}", response_model=SetupsTest,
            summary="A frozen report of a multi-setup test: the test and its merge as they were")
async def read_report(request: Request, test_id: str, token: str):
    return await jobs(request).quick(setups.report, store(request), test_id, token)


@router.get("/api/setups/{test_id}/reports/{token}/modes.csv", summary="A report's merged modes as CSV",
            response_class=Response, responses={200: {"content": {"text/csv": {}}}})
async def report_csv(request: Request, test_id: str, token: str):
    frozen = await jobs(request).quick(setups.report, store(request), test_id, token)
    return Response(setups_export.modes_csv(frozen["merged"]), media_type="text/csv; charset=utf-8",
                    headers={"Content-Disposition": f'attachment; filename="era-setups-{token[:8]}.csv"'})


@router.get("/api/setups/{test_id}/reports/{token}/modes.uff", summary="A report's complete merged modes as UFF 55",
            response_class=Response, responses={200: {"content": {"application/octet-stream": {}}}})
async def report_uff(request: Request, test_id: str, token: str):
    frozen = await jobs(request).quick(setups.report, store(request), test_id, token)
    blob = await jobs(request).quick(setups_export.modes_uff, frozen["merged"])
    return Response(blob, media_type="application/octet-stream",
                    headers={"Content-Disposition": f'attachment; filename="era-setups-{token[:8]}.uff"'})


@router.get("/api/setups/{test_id}/reports/{token}/report.html", response_class=HTMLResponse,
            summary="A report as one self-contained HTML file (opens offline): the merged modes, shapes and geometry")
async def report_html(request: Request, test_id: str, token: str):
    frozen = await jobs(request).quick(setups.report, store(request), test_id, token)
    html = await jobs(request).quick(setups_offline.standalone_html, frozen)
    return HTMLResponse(html, headers={"Content-Disposition": f'attachment; filename="era-setups-{token[:8]}.html"'})


@router.post("/api/setups/{test_id}/reports/{token}/viewer", response_model=ViewerLink,
             summary="Publish a report's merged shapes to the viser viewer")
async def report_viewer(request: Request, test_id: str, token: str):
    return await _published(request, await jobs(request).quick(setups.report, store(request), test_id, token))


async def _published(request: Request, test: dict) -> dict:
    v = request.app.state.viewer
    if v is None:
        raise HTTPException(503, "The mode-shape viewer is not available on this server.")
    scene = setups_export.viewer_scene(test["merged"])
    key = await jobs(request).quick(v.publish, *scene)
    return {"key": key, "url": v.iframe_url(key), "mode_url": f"/viser/{key}/mode", "n_modes": len(scene[1])}


# ---- the page -----------------------------------------------------------------------------------------------------
@router.get("/setups", include_in_schema=False)
async def page():
    return FileResponse(config.STATIC_DIR / "setups.html", media_type="text/html")


@router.get("/s/{test_id}/r/{token}", include_in_schema=False)
async def report_page(request: Request, test_id: str, token: str):
    try:
        await jobs(request).quick(setups.report, store(request), test_id, token)
    except NotFound:
        return HTMLResponse("<!doctype html><meta charset=utf-8><title>Report not found</title><h1>Report not found"
                            "</h1><p>No report of a multi-setup test has this link. Check that the whole link was "
                            "copied.</p><p><a href=\"/setups\">Start a multi-setup test</a></p>", status_code=404)
    return FileResponse(config.STATIC_DIR / "setups.html", media_type="text/html")


@router.get("/s/{test_id}", include_in_schema=False)
async def test_page(request: Request, test_id: str):
    try:
        await jobs(request).quick(setups.load, store(request), test_id)
    except NotFound:
        return HTMLResponse("<!doctype html><meta charset=utf-8><title>Test not found</title><h1>Test not found</h1>"
                            "<p>No multi-setup test has this link. Check that the whole link was copied.</p>"
                            "<p><a href=\"/setups\">Start a multi-setup test</a></p>", status_code=404)
    return FileResponse(config.STATIC_DIR / "setups.html", media_type="text/html")
