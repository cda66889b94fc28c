"""GET /api/health: the server's state and what its store holds."""

from __future__ import annotations

from pydantic import Field

from .common import Schema

class StoreUsage(Schema):
    rows: dict[str, int] = Field(description="rows per table: datasets, analyses, reports, explanations")
    bytes: dict[str, int] = Field(description="bytes per folder of the data folder (app.store.FOLDERS: datasets, "
                                                "reports, explanations, imports, models, campaigns, setups)")
    free_bytes: int = Field(description="free space on the data folder's disk, bytes")


class Health(Schema):
    status: str = Field(description="ok when the server answers")
    version: str = Field(description="era-modal version of this server (era.__version__)")
    store: str | None = Field(description="the index database: sqlite or postgresql (null: not signed in to a "
                                          "restricted server, as the next three)")
    schema_revision: str | None = Field(description="its migration revision (app/store/migrations)")
    usage: StoreUsage | None = Field(description="what the store holds")
    expire_days: float | None = Field(description="datasets and analyses in no report are deleted after this, days "
                                                  "(0: never)")
    access: str = Field(description="open, or restricted (a team token or a sign-in proxy)")
