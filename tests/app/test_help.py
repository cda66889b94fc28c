"""The docs site at /help/: built with `mkdocs build --strict` into a temporary folder and served by the app
(app/routes/help.py), every help link of the page landing on a page and an anchor that exist."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from apiclient import client

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    out = tmp_path_factory.mktemp("site")
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d", str(out)], cwd=REPO,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-4000:]
    return out


def test_help_serves_the_built_site_offline(site, tmp_path, monkeypatch):
    monkeypatch.setenv("ERA_DOCS_DIR", str(site))
    with client(tmp_path) as c:
        first = c.get("/help/")
        assert first.status_code == 200 and "text/html" in first.headers["content-type"]
        assert "ERA modal analysis" in first.text
        assert c.get("/help", follow_redirects=False).headers["location"] == "/help/"
        assert c.get("/help/choosing-modes", follow_redirects=False).headers["location"] == "/help/choosing-modes/"
        page = c.get("/help/choosing-modes/")
        assert page.status_code == 200 and "persistence" in page.text
        assert c.get("/help/img/app.png").headers["content-type"] == "image/png"
        api = c.get("/help/reference/choice/")
        assert api.status_code == 200 and "choose_modes" in api.text   # mkdocstrings rendered the docstrings
        # nothing the site needs comes from outside: no stylesheet, script or font from another host
        assert not re.search(r'(src|href)="https?://(?!127\.0\.0\.1)[^"]*\.(js|css|woff2?)', first.text)
        assert c.get("/help/no-such-page/").status_code == 404
        assert c.get("/help/%2e%2e/%2e%2e/pyproject.toml").status_code == 404


def test_every_help_link_of_the_page_opens_its_page_and_anchor(site):
    index = (REPO / "static" / "index.html").read_text(encoding="utf-8")
    links = re.findall(r'href="/help/([^"]*)"', index)
    assert len(links) >= 10
    for link in links:
        path, _, anchor = link.partition("#")
        html = (site / path / "index.html").read_text(encoding="utf-8")
        if anchor:
            assert f'id="{anchor}"' in html, link


def test_help_says_how_to_build_it_when_it_was_not_built(tmp_path, monkeypatch):
    monkeypatch.setenv("ERA_DOCS_DIR", str(tmp_path / "nothing-here"))
    with client(tmp_path) as c:
        r = c.get("/help/")
        assert r.status_code == 404 and "mkdocs build --strict" in r.text and "ERA_DOCS_DIR" in r.text
