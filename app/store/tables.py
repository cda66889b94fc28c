"""The store's index tables (SQLAlchemy Core): what exists, and where its files are. Times are Unix seconds.

The rows are the commit points: a row is inserted only after its files are complete on disk, so a row always
points at whole files. The schema changes only through a migration (app/store/migrations/versions).
"""

from __future__ import annotations

import sqlalchemy as sa

metadata = sa.MetaData()

datasets = sa.Table(
    "datasets", metadata,
    sa.Column("id", sa.String(64), primary_key=True),
    sa.Column("name", sa.Text, nullable=False),
    sa.Column("sha256", sa.String(64), nullable=False),
    sa.Column("created", sa.Float, nullable=False),
    sa.Column("summary", sa.Text, nullable=False),  # the JSON the API returns for the dataset
)

analyses = sa.Table(
    "analyses", metadata,
    sa.Column("id", sa.String(64), primary_key=True),
    sa.Column("dataset_id", sa.String(64), sa.ForeignKey("datasets.id"), nullable=False),
    sa.Column("params", sa.Text, nullable=False),  # JSON: rows, cols, row_shifts, col_shifts, max_order
    sa.Column("created", sa.Float, nullable=False),
)

reports = sa.Table(
    "reports", metadata,
    sa.Column("token", sa.String(64), primary_key=True),
    sa.Column("analysis_id", sa.String(64), nullable=False),
    sa.Column("created", sa.Float, nullable=False),
)

explanations = sa.Table(
    "explanations", metadata,
    sa.Column("analysis_id", sa.String(64), primary_key=True),
    sa.Column("created", sa.Float, nullable=False),
)

viewer_keys = sa.Table(
    "viewer_keys", metadata,
    sa.Column("key", sa.String(64), primary_key=True),
    sa.Column("analysis_id", sa.String(64), nullable=False, index=True),
    sa.Column("spec", sa.Text, nullable=False),      # JSON: {"kind": "modes", "order": n} or {"kind": "explain", ...}
    sa.Column("state", sa.Text, nullable=True),      # JSON view state (mode, amplitude, speed, interpolate) or null
    sa.Column("revision", sa.Integer, nullable=False, server_default="0"),  # bumped on every state change
    sa.Column("created", sa.Float, nullable=False),
)

campaigns = sa.Table(
    "campaigns", metadata,
    sa.Column("id", sa.String(64), primary_key=True),
    sa.Column("name", sa.Text, nullable=False),
    sa.Column("state", sa.String(16), nullable=False),   # queued, running, done or failed
    sa.Column("done", sa.Integer, nullable=False),        # records finished (analysed or failed)
    sa.Column("total", sa.Integer, nullable=False),       # records in the campaign
    sa.Column("message", sa.Text, nullable=True),         # why a campaign failed as a whole, or null
    sa.Column("created", sa.Float, nullable=False),
    sa.Column("updated", sa.Float, nullable=False),       # last progress: a stale "running" row lost its process
)
