"""The FastAPI application: ``app.main:app`` (``uvicorn app.main:app``, or ``python3 -m app``).

create_app() wires settings, the store, the cache service (app/cache.py), the job pools, the viser viewer
(unless ERA_VIEWER=0), the limits (upload size, per-client rates) and the error handlers that keep stack traces
out of responses. The JSON of every answer is declared in app/schemas/ (see /docs).
"""

from __future__ import annotations

import asyncio
import logging
import secrets
import time
from collections import deque
from contextlib import asynccontextmanager

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.openapi.docs import get_swagger_ui_html
from fastapi.responses import JSONResponse
from fastapi.staticfiles import StaticFiles
from starlette.exceptions import HTTPException
from swagger_ui_bundle import swagger_ui_path

import era

from . import config, housekeeping, schemas, viewing
from .access import Access, SocketGuard
from .cache import Cache
from .campaigns import Campaigns
from .errors import NotFound
from .jobs import Jobs
from .routes import analyses, campaigns, datasets, examples, explain, health, imports, models, pages, reports
from .routes import jobs as job_routes
from .routes import help as help_routes  # the docs site at /help/
from .store import Store
from .viewer import ModeViewer

log = logging.getLogger("app")


def _error(status: int, message: str, headers: dict | None = None, option: str | None = None) -> JSONResponse:
    body = {"error": message} if option is None else {"error": message, "option": option}
    return JSONResponse(body, status_code=status, headers=headers)


class UploadLimit:
    """Pure ASGI middleware: a request body above ``limit`` bytes gets 413 before it is parsed.

    Checks Content-Length first; a body without one (chunked) is counted as it arrives.
    """

    def __init__(self, app, limit: int):
        self.app, self.limit = app, limit

    def _message(self) -> str:
        return (f"The upload is larger than this server's limit of {self.limit / 2**20:.0f} MB (ERA_MAX_UPLOAD_MB). "
                "Send fewer channels or samples, or raise the limit.")

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http" or scope["method"] not in ("POST", "PUT"):
            return await self.app(scope, receive, send)
        for name, value in scope.get("headers", []):
            if name == b"content-length" and value.isdigit() and int(value) > self.limit:
                return await _error(413, self._message())(scope, receive, send)
        seen = 0
        answered = False  # we sent the 413 ourselves: drop whatever the app sends after it

        async def counting_receive():
            nonlocal seen, answered
            if answered:
                return {"type": "http.disconnect"}
            message = await receive()
            if message["type"] == "http.request":
                seen += len(message.get("body", b""))
                if seen > self.limit:
                    answered = True
                    await _error(413, self._message())(scope, receive, send)
                    return {"type": "http.disconnect"}  # the app stops reading: the client went away
            return message

        async def guarded_send(message):
            if not answered:
                await send(message)

        try:
            await self.app(scope, counting_receive, guarded_send)
        except Exception:
            if not answered:
                raise


class RateLimit:
    """Sliding one-minute windows per user (app.access.Access.user: the proxy's user, a signed-in browser, else
    the client address): all requests it limits, and the heavy ones (POST)."""

    def __init__(self, per_minute: int, heavy_per_minute: int):
        self.limits = {"all": per_minute, "heavy": heavy_per_minute}
        self._hits: dict[tuple[str, str], deque] = {}

    def check(self, client: str, heavy: bool) -> int | None:
        """Seconds to wait, or None when the request may go ahead (and is counted)."""
        now = time.monotonic()
        kinds = ("all", "heavy") if heavy else ("all",)
        for kind in kinds:
            q = self._hits.setdefault((client, kind), deque())
            while q and now - q[0] > 60.0:
                q.popleft()
            if len(q) >= self.limits[kind]:
                return max(1, int(60.0 - (now - q[0])) + 1)
        for kind in kinds:
            self._hits[(client, kind)].append(now)
        if len(self._hits) > 10_000:  # forget idle clients
            for key in [k for k, q in self._hits.items() if not q or now - q[-1] > 60.0]:
                del self._hits[key]
        return None


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

    errors = {400: "a body that cannot be parsed (not UTF-8, a broken multipart form)",
              401: "signed-in users only (ERA_ACCESS_TOKEN, ERA_TRUST_USER_HEADER)", 404: "unknown id",
              413: "the upload, or what its files inflate to, is above ERA_MAX_UPLOAD_MB",
              422: "invalid request or data, with what to change", 429: "rate limit, with Retry-After",
              500: "internal error, with a logged reference", 503: "busy or off, with Retry-After when busy"}
    app = FastAPI(title="ERA modal analysis", version=era.__version__, lifespan=lifespan, docs_url=None, redoc_url=None,
                  responses={code: {"model": schemas.Error, "description": text} for code, text in errors.items()},
                  description="Eigensystem Realization Algorithm (Juang & Pappa 1985): upload pulse responses, "
                              "identify modes, judge them with γ and μ, share a report.")
    app.state.settings = settings
    app.state.viewer = viewer
    limiter = RateLimit(settings.rate_limit_per_minute, settings.rate_limit_heavy_per_minute)
    access = app.state.access = Access(settings.access_token, settings.trust_user_header)

    @app.middleware("http")
    async def rate_limit(request: Request, call_next):
        path = request.url.path
        refused = access.check(request)
        # the API, and the links and sign-in a stranger could guess tokens at; refusals count for their address
        if path.startswith(("/api/", "/r/", "/c/")) or path == "/login" or refused is not None:
            who = access.user(request)
            # uploads, identifications, examples, reports and sign-ins start heavy work (or guess a token);
            # publishing to the viewer does not
            heavy = request.method == "POST" and not path.endswith("/viewer")
            wait = limiter.check(who, heavy=heavy)
            if wait is not None:
                return _error(429, f"Too many requests from {who}: the limit is "
                                   f"{settings.rate_limit_per_minute} per minute "
                                   f"({settings.rate_limit_heavy_per_minute} for uploads and computations). "
                                   f"Try again in {wait} s.", {"Retry-After": str(wait)})
        if refused is not None:
            return refused
        return await call_next(request)

    @app.exception_handler(era.EraError)
    async def era_error(request: Request, exc: era.EraError):
        return _error(422, str(exc), option=getattr(exc, "option", None))

    @app.exception_handler(era.TooLargeError)
    async def too_large(request: Request, exc: era.TooLargeError):  # files that inflate past ERA_MAX_UPLOAD_MB
        return _error(413, f"{exc} This server's limit is {settings.max_upload_bytes / 2**20:.0f} MB "
                           "(ERA_MAX_UPLOAD_MB), for the upload and for what it inflates to.")

    @app.exception_handler(NotFound)
    async def not_found(request: Request, exc: NotFound):
        return _error(404, str(exc))

    @app.exception_handler(HTTPException)  # starlette's: also a malformed body's 400 and an unknown route's 404
    async def http_error(request: Request, exc: HTTPException):
        said = str(exc.detail)
        if exc.status_code == 404 and said == "Not Found":
            said = f"No such address: {request.method} {request.url.path}. The API is listed at /docs."
        return _error(exc.status_code, said, getattr(exc, "headers", None))

    @app.exception_handler(RequestValidationError)
    async def invalid_request(request: Request, exc: RequestValidationError):
        parts = []
        for e in exc.errors():
            where = ".".join(str(x) for x in e.get("loc", ()) if x not in ("body", "query", "path"))
            parts.append(f"{where or 'request'}: {e.get('msg', 'invalid')}")
        return _error(422, "Invalid request: " + "; ".join(parts) + ".")

    @app.exception_handler(Exception)
    async def unexpected(request: Request, exc: Exception):
        ref = secrets.token_hex(4)
        log.exception("Unhandled error %s on %s %s", ref, request.method, request.url.path)
        return _error(500, f"Internal error (reference {ref}); it has been logged. Please report it with the "
                           "reference.")

    for module in (datasets, imports, models, examples, analyses, explain, reports, campaigns, job_routes, health,
                   pages, help_routes):
        app.include_router(module.router)
    if viewer is not None:
        app.include_router(viewer.router)
    app.mount("/static", StaticFiles(directory=config.STATIC_DIR), name="static")
    _api_docs(app)
    _errors_are_json(app)
    app.add_middleware(SocketGuard, access=access, per_user=settings.viewer_connections)
    # Outermost: refuse oversized bodies before anything reads them.
    app.add_middleware(UploadLimit, limit=settings.max_upload_bytes)
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
