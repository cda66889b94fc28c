"""Shared test fixtures: where the measured datasets live (the shared/ folder beside the repository)."""

from pathlib import Path

import pytest
from shared_data import SHARED_DATASETS, require_shared


@pytest.fixture(scope="session")
def shared_datasets() -> Path:
    """The shared datasets folder (a test failure when it is absent: see tests/shared_data.py)."""
    return require_shared(SHARED_DATASETS)
