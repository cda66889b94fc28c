"""Trace lines keep their names (UFF 82 trace line number and description) in era.Geometry, through era's own
.npz format and the app's store, and the Model panel's draft groups members by them (issue 9).

Files: LMS Test.Lab's geometry from pyuff's data (tests/data: trace lines 'Massif', 'Stator', 'Dalle') and UFF
files written here with pyuff (named, unnamed and pyuff's "NONE" placeholder)."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pyuff
import pytest

import era
from app import modeling
from era.io.npz import npz_bytes, read_npz

DATA = Path(__file__).resolve().parents[1] / "data"


def test_testlab_trace_lines_keep_their_numbers_and_names():
    g = era.load(DATA / "testlab_geometry_15_82.uff").geometry
    assert g.line_ids.tolist() == [1, 2, 3] and g.line_names == ("Massif", "Stator", "Dalle")
    # Massif 2-5-6-3-4-1-2-3 (7 segments), Stator 16 segments between pen-ups, Dalle 34-33-36-35-32-31-34, 33-32
    assert np.bincount(g.edge_lines).tolist() == [7, 16, 7]
    names = g.edge_names()
    seg = {tuple(sorted(g.node_ids[e].tolist())): n for e, n in zip(g.edges, names)}
    assert seg[(2, 5)] == "Massif" and seg[(7, 19)] == "Stator" and seg[(32, 33)] == "Dalle"


def test_the_draft_groups_members_by_named_trace_line():
    g = era.load(DATA / "testlab_geometry_15_82.uff").geometry
    used = sorted({int(i) for e in g.edges for i in e})
    # a channel on node 2 (Massif) along z, so the draft has a sensor
    g = era.Geometry(g.node_ids, g.coordinates, g.edges, [used[0]], [[0, 0, 1]], units=g.units,
                     edge_lines=g.edge_lines, line_ids=g.line_ids, line_names=g.line_names)
    d = modeling.draft(g, ("a",))
    assert d["groups"] == ["Dalle", "Massif", "Stator"]
    count = {name: sum(m[2] == name for m in d["members"]) for name in d["groups"]}
    assert count == {"Massif": 7, "Stator": 16, "Dalle": 7} and len(d["members"]) == 30


def _uff(path: Path, traces) -> Path:
    """Four nodes of a portal in m (1 and 4 on the ground, 2-3 the beam), the trace lines given as (number,
    description, node sequence), and one channel at node 2 along x."""
    sets = [pyuff.prepare_15(node_nums=[1, 2, 3, 4], def_cs=[0] * 4, disp_cs=[0] * 4, color=[1] * 4,
                             x=[0.0, 0.0, 2.0, 2.0], y=[0.0] * 4, z=[0.0, 1.5, 1.5, 0.0])]
    for num, name, seq in traces:
        sets.append({"type": 82, "trace_num": num, "n_nodes": len(seq), "color": 1, "id": name,
                     "nodes": np.array(seq, dtype=int)})
    t = np.arange(64) * 0.01
    sets.append({"type": 58, "binary": 0, "func_type": 1, "rsp_node": 2, "rsp_dir": 1, "ref_node": 2, "ref_dir": 1,
                 "load_case_id": 0, "rsp_ent_name": "2x", "id1": "pulse 2x/2x", "data": np.exp(-t) * np.sin(40 * t),
                 "x": t, "abscissa_spacing": 1, "abscissa_spec_data_type": 17, "abscissa_axis_units_lab": "s",
                 "ordinate_spec_data_type": 8, "ordinate_axis_units_lab": "m", "orddenom_spec_data_type": 13,
                 "orddenom_axis_units_lab": "N s"})
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


def test_named_lines_group_and_unnamed_ones_fall_back_to_direction(tmp_path):
    path = _uff(tmp_path / "portal.uff", [(1, "columns", [1, 2, 0, 3, 4]), (7, "NONE", [2, 3]), (8, "beam", [3, 2])])
    ds = era.load(path)
    g = ds.geometry
    assert g.line_ids.tolist() == [1, 7, 8] and g.line_names == ("columns", "NONE", "beam")
    assert g.edge_names() == ["columns", "columns", "", "beam"]          # pyuff's placeholder is no name
    d = modeling.draft(g, ds.data.outputs)          # 2-3 drawn twice: one member, in the first line drawing it
    assert d["members"] == [["1", "2", "columns"], ["2", "3", "along x"], ["3", "4", "columns"]]
    assert d["groups"] == ["along x", "columns"]


def test_the_names_survive_eras_npz_and_the_apps_store(tmp_path):
    from app.store import Store

    ds = era.load(_uff(tmp_path / "portal.uff", [(3, "left column", [1, 2]), (4, "beam", [2, 3]),
                                                   (5, "right column", [3, 4])]))
    _, g, _, _ = read_npz(npz_bytes(ds.data, ds.geometry), "portal.npz")
    assert g.line_ids.tolist() == [3, 4, 5] and g.edge_names() == ["left column", "beam", "right column"]
    store = Store(tmp_path / "data")
    _, stored, _ = store.load_dataset(store.add_dataset(ds.data, ds.geometry, "portal", {}))
    assert stored.line_names == ("left column", "beam", "right column") and stored.edge_lines.tolist() == [0, 1, 2]
    # an archive from before the names: every segment unknown, the draft groups by direction
    buf = io.BytesIO()
    np.savez(buf, markov=ds.data.markov, dt=ds.data.dt, node_ids=g.node_ids, coordinates=g.coordinates,
             edges=g.edges, channel_nodes=g.channel_nodes, channel_directions=g.channel_directions)
    _, old, _, _ = read_npz(buf.getvalue(), "old.npz")
    assert old.edge_names() == ["", "", ""] and old.line_ids.size == 0
    assert modeling.draft(old, ds.data.outputs)["groups"] == ["along x", "vertical"]
    # and era's UFF writer writes each trace line under its own number and name
    model = era.identify(ds.data, rows=20, cols=20).model(2)
    out = io.BytesIO()
    era.save_modes_uff(out, model, g)
    (tmp_path / "modes.uff").write_bytes(out.getvalue())
    back = era.load(tmp_path / "modes.uff").geometry
    assert back.line_ids.tolist() == [3, 4, 5] and back.edge_names() == ["left column", "beam", "right column"]
    buf = io.BytesIO()
    np.savez(buf, markov=ds.data.markov, dt=ds.data.dt, node_ids=g.node_ids, coordinates=g.coordinates,
             edges=g.edges, channel_nodes=g.channel_nodes, channel_directions=g.channel_directions,
             line_ids=g.line_ids)
    with pytest.raises(era.DataError, match="without \\['edge_lines', 'line_names'\\]"):
        read_npz(buf.getvalue(), "half.npz")


def test_inconsistent_trace_lines_are_refused():
    base = dict(node_ids=[1, 2], coordinates=[[0, 0, 0], [1, 0, 0]], edges=[[0, 1]], channel_nodes=[0],
                channel_directions=[[0, 0, 1]])
    with pytest.raises(era.DataError, match="2 trace line ids but 1 trace line names"):
        era.Geometry(**base, line_ids=[1, 2], line_names=["a"])
    with pytest.raises(era.DataError, match="refers to a trace line that does not exist"):
        era.Geometry(**base, edge_lines=[1], line_ids=[1], line_names=["a"])
    with pytest.raises(era.DataError, match="1 trace line segments but 2 trace line indices"):
        era.Geometry(**base, edge_lines=[0, 0], line_ids=[1], line_names=["a"])
