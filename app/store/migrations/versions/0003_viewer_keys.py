"""Viewer keys: what each published viewer key shows and its view state, so any app process can rebuild the scene
of a key another process published, and follow the mode chosen through either.

Revision ID: 0003
Revises: 0002
"""

import sqlalchemy as sa
from alembic import op

revision = "0003"
down_revision = "0002"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table("viewer_keys",
                    sa.Column("key", sa.String(64), primary_key=True),
                    sa.Column("analysis_id", sa.String(64), nullable=False, index=True),
                    sa.Column("spec", sa.Text, nullable=False),
                    sa.Column("state", sa.Text, nullable=True),
                    sa.Column("revision", sa.Integer, nullable=False, server_default="0"),
                    sa.Column("created", sa.Float, nullable=False))


def downgrade() -> None:
    op.drop_table("viewer_keys")
