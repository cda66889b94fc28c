"""Shared access to the app-wide objects set up in the lifespan."""

from fastapi import Request

from ..engine import Engine
from ..jobs import Jobs


def engine(request: Request) -> Engine:
    return request.app.state.engine


def jobs(request: Request) -> Jobs:
    return request.app.state.jobs


def progress_key(request: Request) -> str | None:
    """The client's name for this request's progress (GET /api/jobs/{key}), from the X-Progress-Key header."""
    return request.headers.get("x-progress-key")
