"""Campaigns in the app: the records of POST /api/campaigns (uploaded files, or a folder under ERA_CAMPAIGN_ROOT)
through era.campaign.run_campaign, on the Dask scheduler at ERA_DASK_SCHEDULER or, without one, on local processes
(ERA_CAMPAIGN_WORKERS).

A campaign takes minutes to hours, so it never holds a request or a heavy-job slot: each runs in a thread of its
own, one at a time per app process (ERA_CAMPAIGN_QUEUE more may wait). Its progress goes to the store's campaigns
row after every record, so any app process answers GET /api/campaigns/{id}; its result is written as
campaigns/{id}/campaign.json (what the page draws, schemas.CampaignResult) and table.csv (era's table) before the
row says done.
"""

from __future__ import annotations

import json
import logging
import math
import os
import secrets
import threading
import time
from pathlib import Path

import numpy as np
from fastapi import HTTPException

import era
from era.campaign import require_pandas, run_campaign, time_from_name

from . import payloads
from .config import Settings
from .errors import NotFound
from .loading import KINDS
from .store import Store, new_token, write_atomic

log = logging.getLogger("app.campaigns")
#: A running campaign whose row has not moved for this long lost the process that ran it, s.
STALE_S = 15 * 60
#: Subfolders of ERA_CAMPAIGN_ROOT listed for the page at most.
MAX_FOLDERS = 500


class _Stopped(Exception):
    """The app is shutting down: the running campaign stops after the records in progress."""


def engine(settings: Settings) -> str:
    """Where a campaign's records run, in words: the Dask scheduler's address or the local processes."""
    if settings.dask_scheduler:
        return f"Dask scheduler {settings.dask_scheduler}"
    return f"{local_workers(settings)} local process(es)"


def local_workers(settings: Settings) -> int:
    """ERA_CAMPAIGN_WORKERS, or half the cores (at least 1): the other half stays for the interactive pages."""
    return settings.campaign_workers or max(1, (os.cpu_count() or 2) // 2)


def options(kind: str, dt: float | None, max_order: int, settings: Settings) -> dict:
    """The analysis every record gets, checked: {kind, dt (s or None), orders [2, 4, … max_order]}."""
    require_pandas()  # the campaign's table: without the campaign extra, say how to install it before any work
    if kind not in KINDS:
        raise era.DataError(f"`kind` must be one of {', '.join(KINDS)}, got {kind!r}.")
    top = settings.max_stabilization_order
    if not 2 <= max_order <= top:
        raise era.OrderError(f"`max_order` is the highest order of each record's stabilization diagram, 2 to {top} "
                             f"on this server (ERA_MAX_ORDER); got {max_order}.")
    return {"kind": kind, "dt": dt, "orders": list(range(2, max_order + 1, 2))}


def folder_records(root: Path | None, folder: str) -> list[str]:
    """The record files (not hidden, by name) of ``folder``, a path relative to ERA_CAMPAIGN_ROOT ("" or "." for
    the root itself). Refuses (era.DataError) when no root is set, or the folder is outside it or holds no file."""
    if root is None:
        raise era.DataError("This server runs campaigns on uploaded files only: its administrator has not set "
                            "ERA_CAMPAIGN_ROOT (the server folder of monitoring records). Upload the files instead.")
    base = Path(root).resolve()
    target = (base / folder.strip().lstrip("/")).resolve()  # symlinks resolved: no way out of the root
    if target != base and base not in target.parents:
        raise era.DataError(f"{folder!r} is outside this server's campaign folder; give one of the folders "
                            "GET /api/campaigns/folders lists.")
    if not target.is_dir():
        raise era.DataError(f"No folder {folder!r} in this server's campaign folder; GET /api/campaigns/folders "
                            "lists them.")
    files = [str(p) for p in _record_files(base, target)]
    if not files:
        raise era.DataError(f"The folder {folder!r} holds no record files (links to files outside this server's "
                            "campaign folder are not read).")
    return files


def _record_files(base: Path, folder: Path) -> list[Path]:
    """The files of ``folder`` a campaign reads, by name: not hidden, and inside ``base`` (resolved) once links are
    followed, so a link to a file elsewhere on the server is never read."""
    return sorted(p for p in folder.iterdir() if p.is_file() and not p.name.startswith(".")
                  and base in p.resolve().parents)


def folders(root: Path | None) -> list[dict]:
    """[{name, n_files}] of ERA_CAMPAIGN_ROOT itself (".") and its subfolders that hold record files, by name; []
    when none is set."""
    if root is None or not Path(root).is_dir():
        return []
    base = Path(root).resolve()
    found = [base] + sorted((p for p in base.iterdir() if p.is_dir() and not p.name.startswith(".")),
                            key=lambda p: p.name)[:MAX_FOLDERS]
    out = []
    for p in found:
        n = len(_record_files(base, p))
        if n:
            out.append({"name": "." if p == base else p.name, "n_files": n})
    return out


def _cell(text: str) -> str:
    """A name safe for spreadsheets: a leading = + - @ would be read as a formula."""
    return "'" + text if text[:1] in ("=", "+", "-", "@") else text


def document(result, names: list[str], *, campaign_id: str, name: str, engine_text: str, analysis: dict,
             seconds: float) -> dict:
    """What the campaign page draws (schemas.CampaignResult) from an era.campaign.CampaignResult.

    names : the file name of each source (the table's ``record`` indexes it). The analysed records are in time
    order; each tracked mode's series has one value per analysed record (null where the record does not show it).
    """
    t = result.table
    records = t.drop_duplicates("record")[["record", "time"]]
    dated = len(t) and np.issubdtype(t["time"].dtype, np.datetime64)
    times = [str(np.datetime64(v, "s")) for v in records["time"]] if dated else [float(v) for v in records["time"]]
    series = []
    for m in result.modes:
        rows = t[t["mode"] == m.mode]  # the table's order: time, then record
        series.append({"mode": m.mode, "frequency_hz": payloads.floats(rows["frequency_hz"]),
                       "damping_ratio": payloads.floats(rows["damping_ratio"]),
                       "mac_to_reference": payloads.floats(rows["mac_to_reference"])})
    return {
        "id": campaign_id, "name": name, "engine": engine_text, "analysis": analysis,
        "seconds": round(seconds, 2), "n_records": len(names), "time_axis": "date" if dated else "record",
        "records": [{"record": int(r), "name": names[int(r)], "time": tm} for r, tm in zip(records["record"], times)],
        "modes": [{"mode": m.mode, "reference_frequency_hz": _num(m.reference_frequency_hz),
                   "reference_damping_ratio": _num(m.reference_damping_ratio), "origin": m.origin,
                   "first_record": m.first_record, "n_found": m.n_found,
                   "n_held": m.n_held, "identification_rate": m.identification_rate if m.n_held else None}
                  for m in result.modes],
        "series": series,
        "failed": [{"record": f.index, "name": names[f.index], "reason": f.reason} for f in result.failed],
    }


def _num(x) -> float | None:
    return float(x) if math.isfinite(x) else None


def standalone_html(status: dict) -> str:
    """campaign.html with plotly.js, the CSS, the page script and the finished campaign (schemas.Campaign with
    ``standalone``) inlined: the campaign's report as one file that opens with no server."""
    from .offline_page import offline_page, script, static_text
    from .reporting import script_json

    return offline_page("campaign.html", {
        '<script src="/static/js/campaign.js"></script>':
            f"<script>window.CAMPAIGN_DATA = {script_json(dict(status, standalone=True))};</script>"
            + script(static_text("js", "campaign.js")),
    })


class Campaigns:
    """The campaigns of one app process: start(), status(), table_path(); shutdown() stops the running one."""

    def __init__(self, store: Store, settings: Settings):
        self.store, self.settings = store, settings
        self._slot = threading.Lock()       # one campaign runs at a time
        self._count = threading.Lock()
        self._pending = 0                   # running + waiting here
        self._stop = threading.Event()

    def start(self, name: str, sources: list, names: list[str], analysis: dict) -> dict:
        """Queue a campaign over ``sources`` (paths or named BytesIO, one per record, ``names`` their file names);
        returns its row. 503 when ERA_CAMPAIGN_QUEUE campaigns already wait; era.DataError above the records limit."""
        limit = self.settings.max_campaign_records
        if len(sources) > limit:
            raise era.DataError(f"{len(sources)} records in one campaign; this server takes at most {limit} "
                                "(ERA_MAX_CAMPAIGN_RECORDS). Split the campaign by week or month.")
        with self._count:
            if self._pending >= 1 + self.settings.campaign_queue:
                raise HTTPException(503, f"{self._pending} campaigns are running or waiting on this server, its "
                                         "limit (ERA_CAMPAIGN_QUEUE). Start this one when one has finished.",
                                    headers={"Retry-After": "60"})
            self._pending += 1
        campaign_id = new_token()
        try:
            self.store.add_campaign(campaign_id, name, len(sources))
            threading.Thread(target=self._run, args=(campaign_id, name, sources, names, analysis), daemon=True,
                             name=f"era-campaign-{campaign_id[:6]}").start()
        except BaseException:
            with self._count:
                self._pending -= 1
            raise
        return self.store.campaign(campaign_id)

    def _run(self, campaign_id: str, name: str, sources: list, names: list[str], analysis: dict) -> None:
        set_row = lambda **v: self.store.set_campaign(campaign_id, **v)  # noqa: E731
        try:
            with self._slot:
                if self._stop.is_set():
                    raise _Stopped
                set_row(state="running")
                started = time.monotonic()

                def progress(done, total):
                    if self._stop.is_set():
                        raise _Stopped
                    set_row(done=done)

                stamps = [time_from_name(n) for n in names]
                # an uploaded record may inflate to ERA_MAX_UPLOAD_MB at most (a folder's are the server's own)
                uploaded = any(not isinstance(src, (str, Path)) for src in sources)
                result = run_campaign(sources, kind=analysis["kind"], dt=analysis["dt"], orders=analysis["orders"],
                                      load_options={"max_bytes": self.settings.max_upload_bytes} if uploaded else None,
                                      client=self.settings.dask_scheduler or None,
                                      workers=local_workers(self.settings), progress=progress,
                                      times=stamps if all(s is not None for s in stamps) else None)
                doc = document(result, names, campaign_id=campaign_id, name=name,
                               engine_text=engine(self.settings), analysis=analysis,
                               seconds=time.monotonic() - started)
                table = result.table.assign(name=[_cell(names[r]) for r in result.table["record"]])
                folder = self.store.campaign_dir(campaign_id)
                write_atomic(folder / "table.csv", table.to_csv(index=False).encode())
                write_atomic(folder / "campaign.json", json.dumps(doc, separators=(",", ":")).encode())
                set_row(state="done", done=len(names))
        except _Stopped:
            set_row(state="failed", message="The server stopped during the campaign; start the campaign again.")
        except era.EraError as exc:
            set_row(state="failed", message=str(exc))
        except Exception:
            ref = secrets.token_hex(4)
            log.exception("Campaign %s failed (reference %s)", campaign_id, ref)
            set_row(state="failed", message=f"Internal error (reference {ref}); it has been logged. Please report "
                                            "it with the reference.")
        finally:
            with self._count:
                self._pending -= 1

    def status(self, campaign_id: str) -> dict:
        """The campaign's state (schemas.Campaign), with its result once done. NotFound for an unknown id."""
        row = self.store.campaign(campaign_id)
        if row is None:
            raise NotFound("No campaign with this link: check that the whole link was copied.")
        out = {k: row[k] for k in ("id", "name", "state", "done", "total", "message")}
        out.update(url=f"/c/{campaign_id}", result=None, engine=engine(self.settings))
        if row["state"] in ("queued", "running") and time.time() - row["updated"] > STALE_S:
            out["message"] = (f"No progress for {int((time.time() - row['updated']) // 60)} min: the server process "
                              "that ran this campaign may have stopped. Start the campaign again if it does not move.")
        if row["state"] == "done":
            out["result"] = json.loads((self.store.campaign_dir(campaign_id) / "campaign.json").read_bytes())
            out["engine"] = out["result"]["engine"]
        return out

    def table_path(self, campaign_id: str) -> Path:
        row = self.store.campaign(campaign_id)
        if row is None or row["state"] != "done":
            raise NotFound("No finished campaign with this link: its table exists once every record is done.")
        return self.store.campaign_dir(campaign_id) / "table.csv"

    def shutdown(self) -> None:
        self._stop.set()
