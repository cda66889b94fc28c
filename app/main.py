"""The FastAPI application: ``app.main:app`` (``uvicorn app.main:app``, or ``python3 -m app``).

create_app() wires settings, the store, the cache service (app/cache.py), the job pools, the viser viewer
(unless ERA_VIEWER=0), the middleware (app/middleware.py: upload size, access, per-user rates) and the error
handlers that keep stack traces out of responses (app/errors.py). The JSON of every answer is declared in
app/schemas/ (see /docs).
"""

from __future__ import annotations

import asyncio
import logging
from contextlib import asynccontextmanager

from fastapi import FastAPI
from fastapi.openapi.docs import get_swagger_ui_html
from fastapi.staticfiles import StaticFiles
from swagger_ui_bundle import swagger_ui_path

import era

from . import compute, config, errors, housekeeping, middleware, schemas, viewing
from .access import Access
from .cache import Cache
from .campaigns import Campaigns
from .jobs import Jobs
from .routes import analyses, campaigns, datasets, examples, explain, health, imports, models, pages, reports
from .routes import jobs as job_routes
from .routes import help as help_routes  # the docs site at /help/
from .routes import setups as setups_routes  # multi-setup tests
from .store import Store
from .viewer import ModeViewer

log = logging.getLogger("app")


def create_app(settings: config.Settings | None = None) -> FastAPI:
    settings = settings or config.from_env()
    viewer = ModeViewer() if settings.viewer else None  # ERA_VIEWER=0: viewer routes answer 503

    @asynccontextmanager
    async def lifespan(app: FastAPI):
        store = Store(settings.data_dir, settings.database_url)
        app.state.store = store
        app.state.cache = Cache(store, settings)
        app.state.jobs = Jobs(settings.heavy_workers, settings.heavy_queue)
        app.state.campaigns = Campaigns(store, settings)
        compute.start(settings.heavy_workers)  # the workers import era now, not on the first upload
        if viewer is not None:  # a key published by another process is rebuilt here from the store
            viewer.resolver = viewing.resolver(app.state.cache)
            viewer.states = viewing.SharedStates(store)
            viewer.start()
        log.info("ERA app: files in %s, index in %s (revision %s), viewer %s", settings.data_dir.resolve(),
                 store.backend, store.revision, "on" if viewer else "off")
        sweeper = asyncio.create_task(housekeeping.sweep_forever(store, settings.expire_days))
        try:
            yield
        finally:
            sweeper.cancel()
            if viewer is not None:
                viewer.stop()
            app.state.jobs.shutdown()
            app.state.campaigns.shutdown()
            store.close()

    answers = {400: "a body that cannot be parsed (not UTF-8, a broken multipart form)",
               401: "signed-in users only (ERA_ACCESS_TOKEN, ERA_TRUST_USER_HEADER)", 404: "unknown id",
               413: "the upload, or what its files inflate to, is above ERA_MAX_UPLOAD_MB",
               422: "invalid request or data, with what to change", 429: "rate limit, with Retry-After",
               500: "internal error, with a logged reference", 503: "busy or off, with Retry-After when busy"}
    app = FastAPI(title="ERA modal analysis", version=era.__version__, lifespan=lifespan, docs_url=None, redoc_url=None,
                  responses={code: {"model": schemas.Error, "description": text} for code, text in answers.items()},
                  description="Eigensystem Realization Algorithm (Juang & Pappa 1985): upload pulse responses, "
                              "identify modes, judge them with γ and μ, share a report.")
    app.state.settings = settings
    app.state.viewer = viewer
    access = app.state.access = Access(settings.access_token, settings.trust_user_header)

    errors.install(app, settings.max_upload_bytes)
    for module in (datasets, imports, models, examples, analyses, explain, reports, campaigns, job_routes, health,
                   pages, help_routes, setups_routes):
        app.include_router(module.router)
    if viewer is not None:
        app.include_router(viewer.router)
    app.mount("/static", StaticFiles(directory=config.STATIC_DIR), name="static")
    _api_docs(app)
    _errors_are_json(app)
    middleware.install(app, settings, access)
    return app


def _errors_are_json(app: FastAPI) -> None:
    """Declare every error answer as what it is, JSON ``{"error"}``, also on routes whose success is HTML, CSV or a
    file (FastAPI would declare their errors in the success's media type)."""
    make = app.openapi

    def openapi() -> dict:
        if app.openapi_schema is None:
            for ops in make()["paths"].values():
                for op in ops.values():
                    for status, answer in op.get("responses", {}).items():
                        content = answer.get("content")
                        if status[:1] in "45" and content and "application/json" not in content:
                            answer["content"] = {"application/json": next(iter(content.values()))}
        return app.openapi_schema

    app.openapi = openapi


def _api_docs(app: FastAPI) -> None:
    """/docs (Swagger UI) served from the swagger-ui-bundle package (a dependency): the page works with no
    internet. It shows the JSON contract of app/schemas/."""
    app.mount("/vendor/swagger", StaticFiles(directory=swagger_ui_path), name="swagger")

    @app.get("/docs", include_in_schema=False)
    async def docs():
        return get_swagger_ui_html(openapi_url=app.openapi_url, title=f"{app.title}: API",
                                   swagger_js_url="/vendor/swagger/swagger-ui-bundle.js",
                                   swagger_css_url="/vendor/swagger/swagger-ui.css",
                                   swagger_favicon_url="data:,")


app = create_app()
