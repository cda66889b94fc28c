"""The store on both databases it supports: SQLite by default and a real PostgreSQL server; Alembic migrations
bring an existing data folder up to date in place; two stores on one database (two app processes) see each
other's rows; concurrent writers lose nothing."""

from __future__ import annotations

import sqlite3
import threading

import numpy as np
import pytest
import sqlalchemy as sa
from fastapi.testclient import TestClient

from app.config import Settings
from app.main import create_app
from app.store import Store
from app.store.database import connect, migrate
from era.examples.paper_cases import case_2

NEWEST = "0004"


@pytest.fixture(params=["sqlite", "postgresql"])
def url(request):
    return None if request.param == "sqlite" else request.getfixturevalue("postgres_url")


def _rows(store: Store, table: str) -> int:
    with store._engine.connect() as conn:
        return conn.execute(sa.text(f"SELECT count(*) FROM {table}")).scalar_one()


def test_every_kind_of_record_round_trips(url, tmp_path):
    store = Store(tmp_path / "files", url)
    assert store.revision == NEWEST and store.backend == ("sqlite" if url is None else "postgresql")
    data = case_2(120)
    dataset_id = store.add_dataset(data, None, "case 2", {"n_samples": 120})
    got, geometry, name = store.load_dataset(dataset_id)
    assert name == "case 2" and geometry is None and np.array_equal(got.markov, data.markov)
    assert store.dataset_summary(dataset_id)["n_samples"] == 120 and store.dataset_summary("nope") is None
    analysis_id = store.add_analysis(dataset_id, {"rows": 45, "cols": 45})
    assert store.analysis(analysis_id) == (dataset_id, {"rows": 45, "cols": 45})
    store.add_report("tok-1", analysis_id, {"order": 10}, {"mode_0.viser": b"\x00\x01"})
    assert store.report("tok-1") == {"order": 10} and store.report_file("tok-1", "mode_0.viser").read_bytes() == b"\x00\x01"
    responses = {k: np.full((5, 2, 2), i, float) for i, k in enumerate(("measured", "nominal", "updated"))}
    for verdict in ("explained", "unexplained"):  # a second run replaces the first
        store.add_explanation(analysis_id, {"verdict": verdict}, responses, 0.05)
    assert store.explanation(analysis_id) == {"verdict": "unexplained"} and _rows(store, "explanations") == 1
    arrays, dt = store.explanation_responses(analysis_id)
    assert dt == 0.05 and arrays["updated"][0, 0, 0] == 2.0
    store.close()


def test_two_processes_on_one_database_see_each_others_rows(postgres_url, tmp_path):
    """Two stores on one PostgreSQL database and one shared folder, as two app processes behind one address."""
    shared = tmp_path / "shared"
    a, b = Store(shared, postgres_url), Store(shared, postgres_url)
    dataset_id = a.add_dataset(case_2(100), None, "from a", {})
    analysis_id = b.add_analysis(dataset_id, {"rows": 40, "cols": 40})
    assert b.load_dataset(dataset_id)[2] == "from a" and a.analysis(analysis_id)[0] == dataset_id
    a.add_report("tok-ab", analysis_id, {"from": "a"}, {})
    assert b.report("tok-ab") == {"from": "a"}
    a.close()
    b.close()


def test_concurrent_writers_lose_nothing(url, tmp_path):
    store = Store(tmp_path / "files", url)
    dataset_id = store.add_dataset(case_2(60), None, "x", {})
    made, errors = [], []

    def write(k):
        try:
            for i in range(10):
                made.append(store.add_analysis(dataset_id, {"rows": k, "cols": i}))
        except Exception as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=write, args=(k,)) for k in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == [] and len(set(made)) == 60
    assert all(store.analysis(a) is not None for a in made)
    store.close()


def test_a_data_folder_from_before_migrations_upgrades_in_place(tmp_path):
    """The SQLite file sessions 1-7 wrote (raw SQL, no alembic_version): recognised, upgraded, rows kept."""
    folder = tmp_path / "old"
    folder.mkdir()
    db = sqlite3.connect(folder / "era.sqlite3")
    db.executescript("""
        CREATE TABLE datasets (id TEXT PRIMARY KEY, name TEXT NOT NULL, sha256 TEXT NOT NULL, created REAL NOT NULL,
                               summary TEXT NOT NULL);
        CREATE TABLE analyses (id TEXT PRIMARY KEY, dataset_id TEXT NOT NULL REFERENCES datasets(id),
                               params TEXT NOT NULL, created REAL NOT NULL);
        CREATE TABLE reports (token TEXT PRIMARY KEY, analysis_id TEXT NOT NULL, created REAL NOT NULL);
        INSERT INTO datasets VALUES ('d1', 'old', 'abc', 1.0, '{"n_samples": 7}');
        INSERT INTO analyses VALUES ('a1', 'd1', '{"rows": 3}', 2.0);
        INSERT INTO reports VALUES ('t1', 'a1', 3.0);
    """)
    db.commit()
    db.close()
    (folder / "reports" / "t1").mkdir(parents=True)
    (folder / "reports" / "t1" / "report.json").write_text('{"order": 4}')
    store = Store(folder)
    assert store.revision == NEWEST
    assert store.dataset_summary("d1") == {"n_samples": 7} and store.analysis("a1") == ("d1", {"rows": 3})
    assert store.report("t1") == {"order": 4} and store.explanation("a1") is None
    store.close()
    assert migrate(connect(f"sqlite:///{folder / 'era.sqlite3'}")) == NEWEST  # idempotent


def test_the_app_runs_on_postgresql(postgres_url, tmp_path):
    settings = Settings(data_dir=tmp_path / "files", database_url=postgres_url, viewer=False)
    with TestClient(create_app(settings)) as c:
        health = c.get("/api/health").json()
        assert health["store"] == "postgresql" and health["schema_revision"] == NEWEST
        ds = c.post("/api/examples/case2").json()
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 45, "cols": 45}).json()
        made = c.post("/api/reports", json={"analysis_id": a["id"], "order": 10, "modes": [0, 1]}).json()
    with TestClient(create_app(settings)) as c:  # a restart: everything is read back from PostgreSQL
        assert c.get(f"/api/reports/{made['token']}").json()["kept"] == [0, 1]
        modes = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 10}).json()
        np.testing.assert_allclose(sorted(modes["frequency_hz"])[-1], 5 / (2 * np.pi), rtol=1e-6)
