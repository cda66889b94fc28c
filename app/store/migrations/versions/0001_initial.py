"""The index as the store first wrote it (sessions 1-7, raw SQLite): datasets, analyses, reports.

Revision ID: 0001
Revises:
"""

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table("datasets",
                    sa.Column("id", sa.String(64), primary_key=True),
                    sa.Column("name", sa.Text, nullable=False),
                    sa.Column("sha256", sa.String(64), nullable=False),
                    sa.Column("created", sa.Float, nullable=False),
                    sa.Column("summary", sa.Text, nullable=False))
    op.create_table("analyses",
                    sa.Column("id", sa.String(64), primary_key=True),
                    sa.Column("dataset_id", sa.String(64), sa.ForeignKey("datasets.id"), nullable=False),
                    sa.Column("params", sa.Text, nullable=False),
                    sa.Column("created", sa.Float, nullable=False))
    op.create_table("reports",
                    sa.Column("token", sa.String(64), primary_key=True),
                    sa.Column("analysis_id", sa.String(64), nullable=False),
                    sa.Column("created", sa.Float, nullable=False))


def downgrade() -> None:
    for name in ("reports", "analyses", "datasets"):
        op.drop_table(name)
