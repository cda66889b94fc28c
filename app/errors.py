"""The app's errors: its own (NotFound, an unknown id: 404; everything else the person can fix is an era.EraError:
422), the one JSON shape every refusal takes, ``{"error", "option"?}``, and the handlers that keep stack traces out
of responses (:func:`install`)."""

from __future__ import annotations

import logging
import secrets

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException

import era

log = logging.getLogger("app")


class NotFound(LookupError):
    """An unknown dataset, analysis, report, example or progress key (404); the message says what to do."""


def error_response(status: int, message: str, headers: dict | None = None, option: str | None = None) -> JSONResponse:
    """The answer of every refusal and failure: ``{"error": message}``, with ``option`` (the form control that fixes
    it) when there is one."""
    body = {"error": message} if option is None else {"error": message, "option": option}
    return JSONResponse(body, status_code=status, headers=headers)


def install(app: FastAPI, max_upload_bytes: int) -> None:
    """Answer every error of ``app`` with :func:`error_response`: era.EraError 422, era.TooLargeError 413 (files
    that inflate past ``max_upload_bytes``, bytes), NotFound 404, starlette's HTTP errors with their status, an
    invalid request 422 naming the fields, and anything else 500 with a logged reference."""

    @app.exception_handler(era.EraError)
    async def era_error(request: Request, exc: era.EraError):
        return error_response(422, str(exc), option=getattr(exc, "option", None))

    @app.exception_handler(era.TooLargeError)
    async def too_large(request: Request, exc: era.TooLargeError):  # files that inflate past ERA_MAX_UPLOAD_MB
        return error_response(413, f"{exc} This server's limit is {max_upload_bytes / 2**20:.0f} MB "
                                   "(ERA_MAX_UPLOAD_MB), for the upload and for what it inflates to.")

    @app.exception_handler(NotFound)
    async def not_found(request: Request, exc: NotFound):
        return error_response(404, str(exc))

    @app.exception_handler(HTTPException)  # starlette's: also a malformed body's 400 and an unknown route's 404
    async def http_error(request: Request, exc: HTTPException):
        said = str(exc.detail)
        if exc.status_code == 404 and said == "Not Found":
            said = f"No such address: {request.method} {request.url.path}. The API is listed at /docs."
        return error_response(exc.status_code, said, getattr(exc, "headers", None))

    @app.exception_handler(RequestValidationError)
    async def invalid_request(request: Request, exc: RequestValidationError):
        parts = []
        for e in exc.errors():
            where = ".".join(str(x) for x in e.get("loc", ()) if x not in ("body", "query", "path"))
            parts.append(f"{where or 'request'}: {e.get('msg', 'invalid')}")
        return error_response(422, "Invalid request: " + "; ".join(parts) + ".")

    @app.exception_handler(Exception)
    async def unexpected(request: Request, exc: Exception):
        ref = secrets.token_hex(4)
        log.exception("Unhandled error %s on %s %s", ref, request.method, request.url.path)
        return error_response(500, f"Internal error (reference {ref}); it has been logged. Please report it with "
                                   "the reference.")
