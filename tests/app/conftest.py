"""Fixtures of the app tests: a real PostgreSQL server (tests/app/postgres.py), started once per session."""

import shutil
import tempfile
from pathlib import Path

import pytest
from postgres import postgres_server


@pytest.fixture(scope="session")
def postgres_url():
    """SQLAlchemy URL of a fresh PostgreSQL database on 127.0.0.1 (never skipped: CI installs the server). Its
    folder is under /tmp, not pytest's 0700 tree, so the unprivileged server user can enter it."""
    folder = Path(tempfile.mkdtemp(prefix="era-postgres-"))
    try:
        with postgres_server(folder) as url:
            yield url
    finally:
        shutil.rmtree(folder, ignore_errors=True)
