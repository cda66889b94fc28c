"""The index database: SQLite in the data folder by default, any SQLAlchemy URL (PostgreSQL) when configured, and
its schema brought up to date by Alembic migrations when the store opens.

``ERA_DATABASE_URL`` / ``--database-url`` chooses it, e.g. ``postgresql+psycopg://era:secret@db.lab/era``; the
files stay under ``ERA_DATA_DIR`` (which may be a shared folder when several app processes serve one address).
"""

from __future__ import annotations

from pathlib import Path

import sqlalchemy as sa
from alembic import command
from alembic.config import Config

MIGRATIONS = Path(__file__).resolve().parent / "migrations"
#: The revision a database created by the store before migrations existed (session 1-7 SQLite files) is at.
FIRST_REVISION = "0001"


def default_url(data_dir: Path) -> str:
    """SQLite in the data folder: ``sqlite:///{data_dir}/era.sqlite3``."""
    return f"sqlite:///{(Path(data_dir) / 'era.sqlite3').resolve()}"


def connect(url: str) -> sa.Engine:
    """An engine for ``url``. SQLite gets WAL (readers never wait for a writer), synchronous=FULL (a committed
    row survives a power cut) and a 30 s busy timeout (several threads or processes may write)."""
    if url.startswith("sqlite"):
        engine = sa.create_engine(url, connect_args={"check_same_thread": False, "timeout": 30})

        @sa.event.listens_for(engine, "connect")
        def _pragmas(dbapi_connection, _record):
            cur = dbapi_connection.cursor()
            cur.execute("PRAGMA journal_mode=WAL")
            cur.execute("PRAGMA synchronous=FULL")
            cur.close()

        return engine
    return sa.create_engine(url, pool_pre_ping=True, pool_size=8, max_overflow=8)


def migrate(engine: sa.Engine) -> str:
    """Upgrade the schema to the newest revision, in place; returns it. A database the store made before
    migrations existed (tables, no alembic_version) is first recognised as revision 0001. On PostgreSQL an
    advisory lock keeps two processes that start together from migrating at once."""
    cfg = Config()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    with engine.begin() as conn:
        if conn.dialect.name == "postgresql":
            conn.execute(sa.text("SELECT pg_advisory_xact_lock(7365201)"))
        cfg.attributes["connection"] = conn
        tables = set(sa.inspect(conn).get_table_names())
        if "datasets" in tables and "alembic_version" not in tables:
            command.stamp(cfg, FIRST_REVISION)
        command.upgrade(cfg, "head")
        return conn.execute(sa.text("SELECT version_num FROM alembic_version")).scalar_one()
