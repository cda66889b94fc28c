"""Settings and limits of the web app, each overridable by an environment variable (ERA_*).

Every limit here is what the API enforces and what the README's limits table documents; a request over a
limit gets a 413, 422 or 429 whose message names the limit and what would fit.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field, replace
from pathlib import Path

from era.choice import DIAGRAM_MAX_ORDER


def _static_dir() -> Path:
    """The browser UI: ``app/static`` inside an installed wheel, else ``static/`` beside ``app/`` in a checkout."""
    here = Path(__file__).resolve().parent
    installed = here / "static"
    return installed if (installed / "index.html").is_file() else here.parent / "static"


#: index.html, report.html, js/ and css/ (served at / and /static, and inlined into downloaded reports).
STATIC_DIR = _static_dir()


def _env(name: str, default, cast):
    raw = os.environ.get(name)
    if raw is None or raw.strip() == "":
        return default
    try:
        return cast(raw)
    except ValueError:
        raise SystemExit(f"Environment variable {name}={raw!r} is not a valid {cast.__name__}.") from None


def rate(raw: str) -> int:
    """Requests per minute from a rate as the README writes it: ``1200``, ``1200/min``, ``20/s``, ``72000/h``."""
    count, _, per = raw.strip().partition("/")
    seconds = {"": 60, "s": 1, "sec": 1, "second": 1, "m": 60, "min": 60, "minute": 60, "h": 3600, "hour": 3600}
    unit = per.strip().lower()
    if unit not in seconds or not count.strip().isdigit():
        raise ValueError(raw)
    return max(1, round(int(count) * 60 / seconds[unit]))


@dataclass(frozen=True)
class Settings:
    """Limits and places. Build from the environment with :func:`from_env`, or directly in tests."""

    #: Folder of the SQLite database (era.sqlite3) and stored files (datasets/, reports/).
    data_dir: Path = field(default_factory=lambda: Path("data"))
    #: The index database (SQLAlchemy URL, e.g. postgresql+psycopg://era:pw@host/era); None: SQLite in data_dir.
    database_url: str | None = None
    #: Largest upload accepted by POST /api/datasets, bytes (413 above).
    max_upload_bytes: int = 64 * 1024 * 1024
    #: Largest H(0), in elements (rows·p × cols·m); H(1) is as large. 8 bytes each: 2.5e7 is 200 MB per matrix.
    max_hankel_elements: int = 25_000_000
    #: Largest model order (state dimension) kept from the SVD.
    max_order: int = 400
    #: Largest order shown in the stabilization diagram (every 2nd order from 2): a cap on era's own
    #: (era.choice.analysis.DIAGRAM_MAX_ORDER); the diagram goes up to the lower of the two (app/choosing.py).
    max_stabilization_order: int = DIAGRAM_MAX_ORDER
    #: Samples per curve sent to the browser for plots (records are decimated above it; fits use all).
    max_plot_points: int = 4000
    #: Heavy jobs (file parsing, SVD, stabilization) running at once; more wait in a queue.
    heavy_workers: int = 2
    #: Threads one analysis's stabilization diagram uses in its worker process (its orders realized and their σ
    #: computed that many at a time, each with one BLAS thread): one person's upload is answered on every core.
    analysis_threads: int = field(default_factory=lambda: max(1, min(2, os.cpu_count() or 1)))
    #: Heavy jobs waiting at most; beyond it a request gets 503 with Retry-After (the page retries by itself).
    heavy_queue: int = 64
    #: Uploads up to this size are read on the quick threads (never queued behind SVDs), bytes.
    small_upload_bytes: int = 4 * 1024 * 1024
    #: Identifications kept in memory (LRU; a 800 × 800 H(0) keeps ~3 MB of singular vectors); an evicted one is
    #: recomputed from the stored dataset.
    cache_identifications: int = 64
    #: Realized models (analysis, order) kept in memory for the order slider.
    cache_models: int = 128
    #: Identifications kept in memory, bytes in all (besides their count above); an evicted one is recomputed.
    cache_identification_bytes: int = 1024 * 1024 * 1024
    #: Loaded datasets kept in memory, bytes in all (besides at most 16 of them): a few large uploads cannot fill
    #: the memory; an evicted dataset is read from the store again.
    cache_dataset_bytes: int = 512 * 1024 * 1024
    #: Per client (IP address) and minute: requests to /api/ in all, and those that start heavy work.
    rate_limit_per_minute: int = 1200
    rate_limit_heavy_per_minute: int = 60
    #: A shared team token: without it only report links, static files and /api/health answer (app/access.py).
    access_token: str | None = None
    #: A header a reverse proxy sets to the authenticated user (e.g. X-Forwarded-User); requests without it: 401.
    trust_user_header: str | None = None
    #: Datasets and analyses that no report uses are deleted this many days after they were made (0: never).
    expire_days: float = 30.0
    #: Start the viser mode-shape viewer (app/viewer/); ERA_VIEWER=0 turns it off.
    viewer: bool = True
    #: Viewer websockets one user (the proxy's user, else one address) holds open at once; more are refused.
    viewer_connections: int = 16
    #: Campaigns (app/campaigns.py): the Dask scheduler their records run on (tcp://host:8786); None: local processes.
    dask_scheduler: str | None = None
    #: Local processes one campaign uses when there is no scheduler (0: half the cores, at least 1).
    campaign_workers: int = 0
    #: A server folder whose subfolders may be run as campaigns (POST /api/campaigns with folder=); None: uploads only.
    campaign_root: Path | None = None
    #: Records (files) in one campaign at most.
    max_campaign_records: int = 2000
    #: Campaigns waiting behind the running one (one runs at a time per app process); beyond it, 503.
    campaign_queue: int = 4

    @property
    def db_path(self) -> Path:
        return self.data_dir / "era.sqlite3"


def from_env() -> Settings:
    """Settings from ERA_DATA_DIR, ERA_DATABASE_URL, ERA_MAX_UPLOAD_MB, ERA_MAX_HANKEL_ELEMENTS, ERA_MAX_ORDER, ERA_RATE_LIMIT,
    ERA_RATE_LIMIT_HEAVY, ERA_HEAVY_WORKERS, ERA_HEAVY_QUEUE, ERA_ANALYSIS_THREADS, ERA_ACCESS_TOKEN,
    ERA_TRUST_USER_HEADER, ERA_EXPIRE_DAYS, ERA_VIEWER (0 turns the viser viewer off), ERA_VIEWER_CONNECTIONS and the
    campaigns' ERA_DASK_SCHEDULER, ERA_CAMPAIGN_WORKERS, ERA_CAMPAIGN_ROOT, ERA_MAX_CAMPAIGN_RECORDS and
    ERA_CAMPAIGN_QUEUE."""
    base = Settings()
    return replace(
        base,
        data_dir=Path(_env("ERA_DATA_DIR", str(base.data_dir), str)),
        database_url=_env("ERA_DATABASE_URL", None, str),
        max_upload_bytes=int(_env("ERA_MAX_UPLOAD_MB", base.max_upload_bytes / 2**20, float) * 2**20),
        max_hankel_elements=_env("ERA_MAX_HANKEL_ELEMENTS", base.max_hankel_elements, int),
        max_order=_env("ERA_MAX_ORDER", base.max_order, int),
        rate_limit_per_minute=_env("ERA_RATE_LIMIT", base.rate_limit_per_minute, rate),
        rate_limit_heavy_per_minute=_env("ERA_RATE_LIMIT_HEAVY", base.rate_limit_heavy_per_minute, rate),
        heavy_workers=_env("ERA_HEAVY_WORKERS", base.heavy_workers, int),
        heavy_queue=_env("ERA_HEAVY_QUEUE", base.heavy_queue, int),
        analysis_threads=max(1, _env("ERA_ANALYSIS_THREADS", base.analysis_threads, int)),
        access_token=_env("ERA_ACCESS_TOKEN", None, str),
        trust_user_header=_env("ERA_TRUST_USER_HEADER", None, str),
        expire_days=_env("ERA_EXPIRE_DAYS", base.expire_days, float),
        viewer=_env("ERA_VIEWER", 1, int) != 0,
        viewer_connections=_env("ERA_VIEWER_CONNECTIONS", base.viewer_connections, int),
        dask_scheduler=_env("ERA_DASK_SCHEDULER", None, str),
        campaign_workers=_env("ERA_CAMPAIGN_WORKERS", base.campaign_workers, int),
        campaign_root=_env("ERA_CAMPAIGN_ROOT", None, Path),
        max_campaign_records=_env("ERA_MAX_CAMPAIGN_RECORDS", base.max_campaign_records, int),
        campaign_queue=_env("ERA_CAMPAIGN_QUEUE", base.campaign_queue, int),
    )
