"""What every answer shares: the null-for-NaN float lists, the request integer bound, the base model, the error."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field

Floats = list[float | None]
Matrix = list[list[float | None]]
#: The largest integer a request may carry (2³¹ − 1, far above any sample, channel, shift or order count): larger
#: ones are refused (422) before numpy, which would overflow or wrap them, sees them.
MAX_INT = 2**31 - 1
#: An index, count or shift in a request: 0 ≤ n ≤ MAX_INT.
Index = Annotated[int, Field(ge=0, le=MAX_INT)]


class Schema(BaseModel):
    """Answers of this server: unknown fields are dropped (a stored report may hold more than it shows)."""

    model_config = ConfigDict(extra="ignore")


class Error(Schema):
    """Every refusal and failure (400, 401, 404, 413, 422, 429, 500, 503): no stack trace, a sentence to act on."""

    error: str = Field(description="what is wrong and what to do about it")
    option: str | None = Field(None, description="the option that fixes it (e.g. dt, orientation, forces), when one "
                                                 "does: a form shows the message next to that control")
