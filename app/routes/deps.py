"""Shared access to the app-wide objects set up in the lifespan."""

from fastapi import Request

from ..engine import Engine
from ..jobs import Jobs


def engine(request: Request) -> Engine:
    return request.app.state.engine


def jobs(request: Request) -> Jobs:
    return request.app.state.jobs
