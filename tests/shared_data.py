"""The measured datasets in ../shared/datasets (beside the repository; CI clones the repository there). Tests that
read them fail, not skip, when the folder is missing: a skip would hide a CI that never ran them."""

from __future__ import annotations

from pathlib import Path

import pytest

SHARED_DATASETS = (Path(__file__).resolve().parents[1] / ".." / "shared" / "datasets").resolve()


def require_shared(path: Path) -> Path:
    """``path`` (a file or folder under ../shared/datasets), or a test failure that says what is missing."""
    if not Path(path).exists():
        pytest.fail(f"{path} is missing: the tests read the measured datasets from ../shared/datasets beside the "
                    "repository (CI puts it there); run them from such a checkout.", pytrace=False)
    return Path(path)
