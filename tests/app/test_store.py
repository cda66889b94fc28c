"""The store keeps datasets in era's own NPZ format: what it writes era.load reads, what era.save_npz writes it
stores, the layout it wrote before still opens in both, and explanations go through it (old files-only ones too)."""

from __future__ import annotations

import io
import json
import sqlite3

import numpy as np

import era
from app.store import Store, write_atomic

JOINTS_FT = ((3.0, 2.0), (7.0, 5.0))


def grid_like() -> tuple[era.ResponseData, era.Geometry]:
    """3 sensors (mm) hit at 2 joints (N·s), with the joints recorded and a 4-node geometry in ft."""
    y = np.random.default_rng(3).standard_normal((64, 3, 2))
    data = era.ResponseData(y, 0.0125, outputs=("w(0,0) ft", "w(5,0) ft", "w(5,7) ft"), inputs=("hit a", "hit b"),
                            output_units=("mm",) * 3, input_units=("N·s",) * 2,
                            meta={"input_locations": JOINTS_FT})
    geometry = era.Geometry([1, 2, 3, 9], [[0, 0, 0], [5, 0, 0], [5, 7, 0], [0, 7, 0]], [[0, 1], [1, 2], [2, 3]],
                            [0, 1, 2], [[0, 0, 1]] * 3, units="ft")
    return data, geometry


def legacy_npz(data: era.ResponseData, geometry: era.Geometry | None, name: str) -> bytes:
    """A dataset file as the store wrote it before the formats merged (the old app.store.dataset_to_npz)."""
    def strings(values):
        return np.array([] if values is None else [str(v) for v in values], dtype=str)

    arrays = dict(markov=data.markov, dt=np.array(data.dt), name=np.array(name), outputs=strings(data.outputs),
                  inputs=strings(data.inputs), has_output_units=np.array(data.output_units is not None),
                  output_units=strings(data.output_units), has_input_units=np.array(data.input_units is not None),
                  input_units=strings(data.input_units), has_geometry=np.array(geometry is not None))
    where = (data.meta or {}).get("input_locations")
    if where is not None:
        arrays["input_locations"] = np.asarray(where, dtype=float)
    if geometry is not None:
        arrays.update(geo_node_ids=geometry.node_ids, geo_coordinates=geometry.coordinates, geo_edges=geometry.edges,
                      geo_channel_nodes=geometry.channel_nodes, geo_channel_directions=geometry.channel_directions,
                      geo_units=np.array(geometry.units))
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def assert_same(data, geometry, want_data, want_geometry):
    """Everything a stored dataset carries is equal: markov bitwise, dt, labels, units, input points, geometry."""
    assert data.markov.tobytes() == want_data.markov.tobytes() and data.markov.shape == want_data.markov.shape
    assert data.dt == want_data.dt
    for k in ("outputs", "inputs", "output_units", "input_units"):
        assert getattr(data, k) == getattr(want_data, k), k
    assert data.meta.get("input_locations") == want_data.meta.get("input_locations")
    if want_geometry is None:
        assert geometry is None
        return
    assert geometry.units == want_geometry.units
    for k in ("node_ids", "coordinates", "edges", "channel_nodes", "channel_directions"):
        np.testing.assert_array_equal(getattr(geometry, k), getattr(want_geometry, k), err_msg=k)


def test_a_stored_dataset_opens_in_era_load_with_geometry_units_input_points_and_name(tmp_path):
    data, geometry = grid_like()
    store = Store(tmp_path)
    dataset_id = store.add_dataset(data, geometry, "grid test.npz", {"n_outputs": 3})
    ds = era.load(store.dataset_path(dataset_id))
    assert ds.source["format"] == "npz" and ds.source["name"] == "grid test.npz"
    assert_same(ds.data, ds.geometry, data, geometry)
    assert ds.data.meta["input_locations"] == JOINTS_FT  # era.explain's residue term reads them from here
    loaded, geom, name = store.load_dataset(dataset_id)
    assert name == "grid test.npz"
    assert_same(loaded, geom, data, geometry)
    store.close()


def test_an_era_save_npz_file_goes_into_the_store_and_comes_back_equal(tmp_path):
    data, geometry = grid_like()
    era.save_npz(tmp_path / "export.npz", data, geometry, name="bridge run 4")
    ds = era.load(tmp_path / "export.npz")
    store = Store(tmp_path / "data")
    dataset_id = store.add_dataset(ds.data, ds.geometry, ds.source["name"], {})
    loaded, geom, name = store.load_dataset(dataset_id)
    assert name == "bridge run 4"
    assert_same(loaded, geom, data, geometry)
    assert store.load_dataset("no-such-id") is None
    store.close()


def test_labels_given_and_units_not_given_stay_so(tmp_path):
    data = era.ResponseData(np.arange(24.0).reshape(8, 3, 1), 0.5, outputs=("a", "b", "c"))
    store = Store(tmp_path)
    dataset_id = store.add_dataset(data, None, "plain", {})
    ds = era.load(store.dataset_path(dataset_id))
    for loaded, geometry in (store.load_dataset(dataset_id)[:2], (ds.data, ds.geometry)):
        assert loaded.output_units is None and loaded.input_units is None and geometry is None
        assert loaded.outputs == ("a", "b", "c") and loaded.inputs == ("u1",)
        assert "input_locations" not in loaded.meta
        assert_same(loaded, geometry, data, None)
    store.close()


def test_a_dataset_in_the_old_store_layout_opens_in_the_store_and_in_era_load(tmp_path):
    data, geometry = grid_like()
    plain = era.ResponseData(data.markov[:, :, :1], data.dt)  # no units, no geometry, no input points
    store = Store(tmp_path)
    for d, g, name in ((data, geometry, "old grid.npz"), (plain, None, "old plain")):
        dataset_id = store.add_dataset(d, g, name, {})
        write_atomic(store.dataset_path(dataset_id), legacy_npz(d, g, name))  # as an old data folder holds it
        loaded, geom, stored_name = store.load_dataset(dataset_id)
        assert stored_name == name
        assert_same(loaded, geom, d, g)
        ds = era.load(store.dataset_path(dataset_id))
        assert ds.source["name"] == name
        assert_same(ds.data, ds.geometry, d, g)
    assert ds.data.output_units is None and ds.geometry is None
    store.close()


def test_an_explanation_round_trips_and_survives_a_restart(tmp_path):
    store = Store(tmp_path)
    analysis_id = store.add_analysis("some-dataset", {"rows": 40})
    assert store.explanation(analysis_id) is None and store.explanation_responses(analysis_id) is None
    rng = np.random.default_rng(1)
    responses = {k: rng.standard_normal((50, 9, 2)) for k in ("measured", "nominal", "updated")}
    summary = {"verdict": "explained", "effect": "point_mass", "mac_before": [[0.9, 0.1]]}
    store.add_explanation(analysis_id, summary, responses, 0.02)
    assert store.explanation(analysis_id) == summary
    got, dt = store.explanation_responses(analysis_id)
    assert dt == 0.02 and set(got) == set(responses)
    for k in responses:
        assert got[k].tobytes() == responses[k].tobytes() and got[k].shape == (50, 9, 2)
    store.add_explanation(analysis_id, dict(summary, verdict="ambiguous"), responses, 0.02)  # run again: replaced
    store.close()
    again = Store(tmp_path)
    assert again.explanation(analysis_id)["verdict"] == "ambiguous"
    assert again.explanation("../era.sqlite3") is None and again.explanation_responses("nope") is None
    again.close()


def test_explanation_files_written_before_the_index_are_found_and_old_databases_gain_the_table(tmp_path):
    old = sqlite3.connect(tmp_path / "era.sqlite3")  # a database of the schema before explanations were indexed
    old.executescript("""
        CREATE TABLE datasets (id TEXT PRIMARY KEY, name TEXT NOT NULL, sha256 TEXT NOT NULL, created REAL NOT NULL,
                               summary TEXT NOT NULL);
        CREATE TABLE analyses (id TEXT PRIMARY KEY, dataset_id TEXT NOT NULL REFERENCES datasets(id),
                               params TEXT NOT NULL, created REAL NOT NULL);
        CREATE TABLE reports (token TEXT PRIMARY KEY, analysis_id TEXT NOT NULL, created REAL NOT NULL);""")
    old.close()
    responses = {k: np.full((30, 9, 1), v) for k, v in (("measured", 1.0), ("nominal", 2.0), ("updated", 3.0))}
    buf = io.BytesIO()  # exactly as the old app/explaining.save wrote them, beside the store
    np.savez(buf, dt=np.array(0.05), **responses)
    (tmp_path / "explanations").mkdir()
    (tmp_path / "explanations" / "oldAnalysis_1.npz").write_bytes(buf.getvalue())
    (tmp_path / "explanations" / "oldAnalysis_1.json").write_text(json.dumps({"verdict": "unexplained"}))
    store = Store(tmp_path)
    assert store.explanation("oldAnalysis_1") == {"verdict": "unexplained"}
    got, dt = store.explanation_responses("oldAnalysis_1")
    assert dt == 0.05 and [float(got[k][0, 0, 0]) for k in ("measured", "nominal", "updated")] == [1.0, 2.0, 3.0]
    store.add_explanation("new_one", {"verdict": "explained"}, responses, 0.05)
    rows = sqlite3.connect(tmp_path / "era.sqlite3").execute("SELECT analysis_id FROM explanations").fetchall()
    assert rows == [("new_one",)]
    store.close()


def test_the_multi_setup_folder_is_swept_of_leftover_temporary_files_and_counted_in_the_usage(tmp_path):
    """app/setups.py writes under setups/{id}/ with write_atomic: a write killed midway leaves its temporary file
    there, which the sweep must remove like any other folder's; the disk usage counts the folder."""
    store = Store(tmp_path)
    test = tmp_path / "setups" / "t1"
    write_atomic(test / "test.json", b'{"id": "t1"}')
    leftover = test / ".setup1.bin.abc123.tmp"  # an unlocked temporary file, last changed long ago
    leftover.write_bytes(b"half a file")
    assert store.usage()["bytes"]["setups"] == len(b'{"id": "t1"}') + len(b"half a file")
    assert store.sweep_orphans(before=leftover.stat().st_mtime + 1) == 1
    assert not leftover.exists() and (test / "test.json").read_bytes() == b'{"id": "t1"}'
    assert store.usage()["bytes"]["setups"] == len(b'{"id": "t1"}')
