"""Campaigns: one row per campaign with its state and progress, so any app process can answer for it;
the result is a file (campaigns/{id}/campaign.json and table.csv) written before the row says done.

Revision ID: 0004
Revises: 0003
"""

import sqlalchemy as sa
from alembic import op

revision = "0004"
down_revision = "0003"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table("campaigns",
                    sa.Column("id", sa.String(64), primary_key=True),
                    sa.Column("name", sa.Text, nullable=False),
                    sa.Column("state", sa.String(16), nullable=False),
                    sa.Column("done", sa.Integer, nullable=False),
                    sa.Column("total", sa.Integer, nullable=False),
                    sa.Column("message", sa.Text, nullable=True),
                    sa.Column("created", sa.Float, nullable=False),
                    sa.Column("updated", sa.Float, nullable=False))


def downgrade() -> None:
    op.drop_table("campaigns")
