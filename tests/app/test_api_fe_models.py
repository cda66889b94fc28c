"""The engineer's own FE model in the app: a Nastran deck or a .zip of matrices uploaded in the Model panel, the
test's points matched to its nodes (a mapping table where they differ), its modes beside the test's, and
simulation vs test on it.

The structure and the test: tests/fe_test_files.py (a cantilever plate deck, 1.5 kg hidden on node 28).
"""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest
from fe_test_files import HIDDEN_KG, POINTS, A, T, deck, simulated

import era
from apiclient import client, npz_bytes, upload
from test_schemas import exact
from app import schemas


@pytest.fixture(scope="module")
def plate(tmp_path_factory):
    """(client, dataset, deck bytes, matrices zip bytes, model) of the uploaded plate test."""
    folder = tmp_path_factory.mktemp("fe")
    (folder / "plate.bdf").write_text(deck())
    model = era.load_model(folder / "plate.bdf")
    era.save_model(model, folder / "plate.zip")
    with client(folder / "data", viewer=True) as c:
        ds = upload(c, npz_bytes(simulated(model)), "plate.npz")
        assert ds.status_code == 200, ds.text
        yield c, ds.json(), deck().encode(), (folder / "plate.zip").read_bytes(), model


def send(c, ds, name, blob):
    return c.post(f"/api/datasets/{ds['id']}/model/file", files={"file": (name, blob, "application/octet-stream")})


def test_bad_model_files_are_refused_with_what_to_do_and_the_stored_model_is_kept(plate):
    c, ds, good, matrices, _ = plate
    url = f"/api/datasets/{ds['id']}/model"
    assert send(c, ds, "plate.bdf", good).status_code == 200
    before = c.get(url).json()

    def refused(name, blob, *words):
        r = send(c, ds, name, blob)
        assert r.status_code == 422, (r.status_code, r.text)
        text = r.json()["error"]
        assert all(w in text for w in words), text
        assert c.get(url).json() == before            # the model stored before is kept
        return text

    bad_card = good.replace(b"GRID,9,,", b"GRID,9,,1.2.3")
    assert bad_card != good
    refused("plate.bdf", bad_card, "plate.bdf", "GRID", "1.2.3")
    refused("plate.zip", b"this is not a zip", "plate.zip")
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z, zipfile.ZipFile(io.BytesIO(matrices)) as src:
        for n in src.namelist():
            if not n.endswith("M.mtx"):
                z.writestr(n, src.read(n))
    refused("plate.zip", buf.getvalue(), "M.mtx")
    refused("empty.nas", b"", "empty", ".bdf")
    refused("plate.dat", b"BEGIN BULK\ninclude '/etc/passwd'\nENDDATA\n", "INCLUDEs", "paste")   # no server file read
    files = sorted(p.name for p in (c.app.state.store.root / "models").iterdir())
    assert len(files) == 2, files                     # the JSON and the one deck kept, nothing left behind


def test_the_deck_and_its_matrices_give_the_same_modes_and_the_points_are_matched_by_label(plate):
    c, ds, deck_bytes, matrices, model = plate
    url = f"/api/datasets/{ds['id']}/model"
    r = send(c, ds, "plate.zip", matrices)
    assert r.status_code == 200, r.text
    z = exact(schemas.StructureModel, r.json())
    r = send(c, ds, "plate.bdf", deck_bytes)
    assert r.status_code == 200, r.text
    s = exact(schemas.StructureModel, r.json())
    assert s.source == "fe" and s.n_dofs == 30 * 6 and s.n_nodes == 30
    assert s.notes and "EIGRL" in s.notes[0]          # the cards not modelled, in one sentence
    # the first bending frequency against Leissa's cantilever plate (a/b = 1.5: λ = 3.47 for ν = 0.3), ± 3 %
    d = 2.1e11 * T**3 / (12 * (1 - 0.3**2))
    f1 = 3.47 / (2 * np.pi * A**2) * np.sqrt(d / (7850 * T))
    assert s.frequency_hz[0] == pytest.approx(f1, rel=0.03)
    assert np.allclose(z.frequency_hz, s.frequency_hz, rtol=1e-6)
    # every labelled form matched to its node along z; "TIP z" matches no node: said in one sentence
    got = {m.output: (m.node, m.direction) for m in s.mapping}
    assert got["4:z"] == ("4", "z") and got["7 +Z"] == ("7", "z") and got["21 z"] == ("21", "z")
    assert got["TIP z"] == (None, None)
    assert s.unmatched.startswith("1 output of 8 matches no free DOF") and "TIP z" in s.unmatched
    assert exact(schemas.StructureModel, c.get(url).json()).mapping == s.mapping
    assert c.get(f"/api/datasets/{ds['id']}").json()["has_model"] is True


def test_the_model_mass_is_given_in_its_own_unit_and_in_kg_where_the_file_says_the_unit(plate):
    """The plate's mass (ρ t times the area that moves: the clamped edge's nodes hold none of it) in the model's
    own unit: a .zip with units.txt says kg; a deck says nothing, unless its PARAM WTMASS is 1/g (here in in/s²:
    an inch-pound deck whose masses are weights in lbf), which gives lbf·s²/in and the kg from it."""
    c, ds, deck_bytes, matrices, model = plate
    z = exact(schemas.StructureModel, send(c, ds, "plate.zip", matrices).json())
    assert z.mass_unit == "kg" and "units.txt" in z.mass_unit_note
    assert z.total_mass == z.total_mass_kg == pytest.approx(model.total_mass(), rel=1e-12)
    s = exact(schemas.StructureModel, send(c, ds, "plate.bdf", deck_bytes).json())
    assert s.mass_unit is None and "does not say its units" in s.mass_unit_note
    assert s.total_mass == pytest.approx(z.total_mass, rel=1e-9)
    inch = deck_bytes.replace(b"ENDDATA", b"PARAM,WTMASS,0.00259008\nENDDATA")
    w = exact(schemas.StructureModel, send(c, ds, "plate.bdf", inch).json())
    assert w.mass_unit == "lbf·s²/in" and "PARAM WTMASS 0.00259008 = 1/386.089" in w.mass_unit_note
    assert w.total_mass == pytest.approx(0.00259008 * s.total_mass, rel=1e-9)
    assert w.total_mass_kg == pytest.approx(w.total_mass * 4.4482216152605 / 0.0254, rel=1e-6)   # lbf·s²/in in kg


def test_explain_on_the_deck_names_the_hidden_mass_after_the_mapping_is_completed(plate):
    c, ds, deck_bytes, _, _ = plate
    url = f"/api/datasets/{ds['id']}/model"
    assert send(c, ds, "plate.bdf", deck_bytes).status_code == 200
    a = c.post("/api/analyses", json=dict(dataset_id=ds["id"], rows=60, cols=60)).json()
    r = c.post(f"/api/analyses/{a['id']}/explain", json={})
    assert r.status_code == 422 and "TIP z" in r.json()["error"], r.text     # unmatched: said, not guessed
    bad = c.put(f"{url}/mapping", json={"sensors": [[n, "z"] for _, n in POINTS[:-1]] + [["1", "z"]]})
    assert bad.status_code == 422 and "node 1" in bad.json()["error"]        # node 1 is clamped: no free DOF
    fixed = c.put(f"{url}/mapping", json={"sensors": [[n, "z"] for _, n in POINTS]})
    assert fixed.status_code == 200, fixed.text
    assert exact(schemas.StructureModel, fixed.json()).unmatched is None
    order = 20
    test = c.get(f"/api/analyses/{a['id']}/modes", params={"order": order}).json()
    keep = [k for k, (f, g) in enumerate(zip(test["frequency_hz"], test["emac"])) if f and 5 < f < 300 and g > 0.9]
    m = exact(schemas.ModelComparison, c.get(f"/api/analyses/{a['id']}/model/mac",
                                             params={"order": order, "modes": ",".join(map(str, keep))}).json())
    assert len(m.best) >= 3 and m.best[0].mac > 0.9 and 10 < m.best[0].frequency_error_pct < 40  # model higher
    r = c.post(f"/api/analyses/{a['id']}/explain", json={})
    assert r.status_code == 200, r.text
    s = exact(schemas.Explanation, r.json())
    assert s.fe_model and "Nastran deck plate.bdf" in s.model_text
    assert s.verdict == "explained" and s.effect.name == "point_mass", s.effect
    near = {"28", "27", "21", "35", "20", "34"}       # node 28 and its neighbours
    assert s.effect.location in near, (s.effect.location, s.effect.places)
    low, high = s.effect.interval["point_mass"]
    assert low <= HIDDEN_KG <= high and s.effect.parameters["point_mass"] == pytest.approx(HIDDEN_KG, rel=0.15)
    again = exact(schemas.Explanation, c.get(f"/api/analyses/{a['id']}/explain").json())
    assert again.effect.location == "28" and again.stale is None
    made = c.post("/api/reports", json={"analysis_id": a["id"], "order": order, "modes": keep[:2]})
    assert made.status_code == 200, made.text
    report = c.get(f"/api/reports/{made.json()['token']}").json()
    assert "Nastran deck plate.bdf" in report["structure_model"]["text"]
    assert report["explanation"]["effect"]["location"] == "28"
    # a changed mapping changes the model: the explanation is then stale, and says so
    moved = c.put(f"{url}/mapping", json={"sensors": [[n, "z"] for _, n in POINTS[:-1]] + [["34", "z"]]})
    assert moved.status_code == 200
    later = c.get(f"/api/analyses/{a['id']}/explain").json()
    assert later["stale"] and "earlier model" in later["stale"]
    # the 3-D viewer draws the shapes on the deck's mesh: its 35 nodes (the 5 clamped ones held still), the
    # shells' edges and the 24 quads as 48 triangles, two per quad along its diagonal
    assert len(s.mesh["nodes"]) == 35 and len(s.mesh["node_labels"]) == 90 == len(s.expanded_measured)
    assert ["2", "3"] in s.mesh["members"] and ["2", "9"] in s.mesh["members"] and ["1", "2"] in s.mesh["members"]
    assert len(s.mesh["faces"]) == 48 and ["1", "2", "9"] in s.mesh["faces"] and ["1", "9", "8"] in s.mesh["faces"]
    v = c.post(f"/api/analyses/{a['id']}/explain/viewer", json={"which": "model"})
    assert v.status_code == 200 and v.json()["n_modes"] == len(s.modes), v.text
    # the viewer gets the faces as a surface over all 35 nodes, and the clamped edge stays still in every mode
    drawn = c.app.state.viewer.registry.get(v.json()["key"])
    assert drawn.geometry.faces.shape == (48, 3) and drawn.geometry.n_nodes == 35
    clamped = [k for k, xyz in enumerate(drawn.geometry.coordinates) if xyz[0] == 0.0]
    assert len(clamped) == 5 and all(np.abs(v[clamped]).max() == 0 for v in drawn.spline_vectors)
    assert all(np.abs(v).max() > 0 for v in drawn.spline_vectors)
