"""GET /api/jobs/...: the progress of a long request."""

from __future__ import annotations

from pydantic import Field

from .common import Schema

class Progress(Schema):
    state: str = Field(description="queued, running, done or failed")
    message: str = Field(description="what the job does")
    seconds: float = Field(description="queued or running (or ran) for this long, s")
    queued_ahead: int = Field(description="jobs queued before this one (0 unless queued)")
    running_total: int = Field(description="jobs running on the server now")
