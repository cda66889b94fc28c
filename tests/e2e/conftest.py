"""Fixtures of the browser tests: one Chromium (Debian's, never downloaded) for the whole run, a clean browser for
each test (its tabs closed after it), and the screenshots folder ($APP_SHOTS when set, to look at them)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]



@pytest.fixture(scope="session")
def playwright():
    """Playwright's driver, started once (every browser of the run comes from it)."""
    if not Path(CHROMIUM).exists():
        pytest.fail(f"Debian's chromium is not installed at {CHROMIUM}: `apt-get install chromium` (.ci/run does)")
    from playwright import sync_api
    with sync_api.sync_playwright() as p:
        yield p


@pytest.fixture(scope="session")
def _chromium(playwright):
    b = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
    yield b
    b.close()


@pytest.fixture()
def browser(_chromium):
    """The run's Chromium; every page a test opens (each in a context of its own) is closed after the test."""
    yield _chromium
    for context in _chromium.contexts:
        context.close()


@pytest.fixture()
def shots(tmp_path) -> Path:
    out = Path(os.environ.get("APP_SHOTS", tmp_path / "shots"))
    out.mkdir(parents=True, exist_ok=True)
    return out


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """One app for a module's tests that each open their own page and upload their own files (a test that
    restarts the app or needs an empty store starts its own :class:`app_server.Server`)."""
    from app_server import Server
    folder = tmp_path_factory.mktemp("app")
    app = Server(folder / "data", folder / "server.log")
    yield app
    app.stop()
