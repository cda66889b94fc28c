"""Explanations (era.explain on an analysis) indexed like the rest: a row once their files are complete.

Revision ID: 0002
Revises: 0001
"""

import sqlalchemy as sa
from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    # a development build created this table without a migration: keep it if it is there
    if "explanations" not in sa.inspect(op.get_bind()).get_table_names():
        op.create_table("explanations",
                        sa.Column("analysis_id", sa.String(64), primary_key=True),
                        sa.Column("created", sa.Float, nullable=False))


def downgrade() -> None:
    op.drop_table("explanations")
