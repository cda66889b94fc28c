"""Issue 27 in the app: the NASA grid example described from its test geometry with the model step's default
section (solid rectangle 50 × 6 mm, steel) and no supports (free-free, as the grid hangs on soft cords) is saved,
compared and explained: Run explain answers 200 with a verdict (was a 500, "Internal error"), or a 422 with a
sentence; the free frame's rigid-body modes are neither shown as its lowest frequencies nor paired."""

from __future__ import annotations

import pytest

from apiclient import client
from test_schemas import exact
from app import schemas

DEFAULT = {"shape": "rectangle", "width": 0.05, "depth": 0.006, "material": "steel"}


@pytest.fixture(scope="module")
def grid_model(tmp_path_factory):
    """(client, analysis, saved model answer) of the grid example with a free-free model from its geometry."""
    with client(tmp_path_factory.mktemp("free")) as c:
        ds = c.post("/api/examples/grid").json()
        url = f"/api/datasets/{ds['id']}/model"
        draft = c.get(f"{url}/draft").json()
        model = {"nodes": draft["nodes"], "members": draft["members"],
                 "sections": {g: dict(DEFAULT) for g in draft["groups"]}, "supports": {}, "masses": {},
                 "sensors": draft["sensors"]}
        saved = c.put(url, json={"model": model})
        assert saved.status_code == 200, saved.text
        a = c.post("/api/analyses", json=dict(dataset_id=ds["id"], rows=ds["defaults"]["rows"],
                                               cols=ds["defaults"]["cols"])).json()
        yield c, a, saved.json()


def test_the_saved_free_frame_shows_its_elastic_frequencies(grid_model):
    _, _, saved = grid_model
    assert "free-free" in saved["text"] and min(saved["frequency_hz"]) > 1.0


def test_run_explain_on_the_free_free_grid_frame_answers_with_a_verdict(grid_model):
    c, a, _ = grid_model
    r = c.post(f"/api/analyses/{a['id']}/explain", json={})
    assert r.status_code in (200, 422), r.text
    if r.status_code == 422:                   # a refusal is a sentence, never an internal error
        assert len(r.json()["error"]) > 20
        return
    s = exact(schemas.Explanation, r.json())
    assert s.verdict in {"explained", "no_significant_discrepancy", "ambiguous", "unexplained"} and s.message
    assert all(m.nominal_hz is None or m.nominal_hz > 1.0 for m in s.modes)      # no rigid-body partner
    assert min(s.model_hz_before) > 1.0
