"""era.Frame in and out: the JSON/TOML model format and members from a test geometry's trace lines."""

import json

import numpy as np
import pytest

from era.errors import DataError
from era.examples.grid import CABLES_FT, joint_index, nasa_grid
from era.fem.statics import G_STANDARD
from era.core.geometry import Geometry
from era.structure import Frame, Section

TOML_PORTAL = """
format = "era.frame"
version = 1
members = [["A", "B", "col"], ["B", "C", "beam", [0, 0, 1]], ["C", "D", "col"]]
sensors = [["B", "x"], ["C", "-x"], ["C", [0, 0.6, 0.8]]]
gravity = [0, 0, -9.81]

[nodes]
A = [0, 0, 0]
B = [0, 0, 0.9]
C = [1.2, 0, 0.9]
D = [1.2, 0, 0]

[sections.col]
shape = "square_tube"
width = 0.03
wall = 0.002

[sections.beam]
area = 3.0e-4
iy = 9.0e-10
iz = 6.25e-8
j = 3.4e-9
e = 2.0e11
g = 7.7e10
density = 7850

[supports]
A = "fixed"
D = { kx = "fixed", ky = "fixed", kz = "fixed", rx = 2e3, ry = 2e3, rz = "fixed" }

[masses]
C = 0.25
"""


def test_a_hand_written_toml_model_loads_and_survives_a_json_round_trip(tmp_path):
    path = tmp_path / "portal.toml"
    path.write_text(TOML_PORTAL)
    frame = Frame.load(path)
    assert frame.sections["col"] == Section.square_tube(0.03, 0.002)
    assert frame.sections["beam"].ip == pytest.approx(9.0e-10 + 6.25e-8)
    assert frame.supports["D"]["rx"] == 2e3 and np.isinf(frame.supports["D"]["kx"])
    f, shapes = frame.modes(8)
    assert shapes.shape == (3, 8) and np.all(np.diff(f) >= 0) and f[0] > 0
    frame.save(tmp_path / "portal.json")
    text = (tmp_path / "portal.json").read_text()
    assert "Infinity" not in text
    d = json.loads(text)
    assert d["supports"] == {"A": "fixed", "D": {"kx": "fixed", "ky": "fixed", "kz": "fixed", "rx": 2e3,
                                                 "ry": 2e3, "rz": "fixed"}}
    again = Frame.load(tmp_path / "portal.json")
    assert again.to_dict() == frame.to_dict()
    f2, s2 = again.modes(8)
    np.testing.assert_array_equal(f2, f)
    np.testing.assert_array_equal(s2, shapes)
    assert Frame.from_dict(frame.to_dict()).to_dict() == d


def test_pinned_fixed_cable_and_default_orientation_round_trip():
    frame = Frame(nodes={1: (0, 0, 0), 2: (1, 0, 0), 3: (2, 0, 0)}, members=[(1, 2, "s"), (2, 3, "s")],
                  sections={"s": Section.circle(0.02)}, supports={1: {"cable": 0.4, "rx": "fixed"}, 3: {"cable": 0.4}},
                  masses={2: 1}, sensors=[(2, "z")], gravity=(0, 0, -9.81), elements_per_member=3)
    d = frame.to_dict()
    assert d["members"] == [["1", "2", "s"], ["2", "3", "s"]] and d["supports"]["3"] == {"cable": 0.4}
    assert d["masses"] == {"2": 1.0} and d["elements_per_member"] == 3
    back = Frame.from_dict(json.loads(json.dumps(d)))
    np.testing.assert_array_equal(back.modes(4)[0], frame.modes(4)[0])


@pytest.mark.parametrize("text, suffix, words", [
    ("{not json", ".json", ["bad.json", "not a readable model"]),
    ("nodes = [", ".toml", ["bad.toml", "not a readable model"]),
    ('{"format": "other"}', ".json", ["bad.json", "not an era.frame model"]),
    ('{"nodes": {}, "members": [], "sections": {}, "colour": 1}', ".json", ["unknown key 'colour'"]),
    ('{"nodes": {"1": [0, 0, 0]}}', ".json", ["lacks ['members', 'sections']"]),
    ('{"nodes": {"1": [0,0,0], "2": [1,0,0]}, "members": [["1", "2", "s"]], '
     '"sections": {"s": {"shape": "rectangle", "width": 0.1}}}', ".json", ["Section", "depth"]),
])
def test_a_bad_model_file_is_refused_by_name(tmp_path, text, suffix, words):
    path = tmp_path / f"bad{suffix}"
    path.write_text(text)
    with pytest.raises(DataError) as info:
        Frame.load(path)
    for w in words:
        assert w in str(info.value)


def test_the_grid_from_its_test_geometry_is_nasa_grid():
    """nasa_grid().geometry(): 88 joints (ids 1..88, metres), 157 trace lines, nine channels along +z."""
    geometry = nasa_grid().geometry()
    bar = Section.rectangle(width=2 * 0.0254, depth=0.25 * 0.0254, material="aluminium")
    left, right = (str(joint_index(c) + 1) for c in CABLES_FT)
    frame = Frame.from_geometry(geometry, section=bar, supports={left: {"cable": 0.51, "kx": "fixed"},
                                                                 right: {"cable": 0.51}},
                                gravity=(0, -G_STANDARD, 0))
    assert len(frame.nodes) == 88 and len(frame.members) == 157
    assert frame.sensors[0] == ("1", "z") and len(frame.sensors) == 9
    f, shapes = frame.modes(10)
    f0, s0 = nasa_grid().modes(10)
    np.testing.assert_allclose(f, f0, rtol=1e-5)
    np.testing.assert_allclose(np.abs(shapes), np.abs(s0), atol=1e-4 * np.abs(s0).max())


def test_from_geometry_converts_units_skips_loose_nodes_and_keeps_skew_channels():
    geometry = Geometry(node_ids=[10, 20, 30, 99], coordinates=[[0, 0, 0], [0, 0, 500], [400, 0, 500], [9, 9, 9]],
                        edges=[[0, 1], [1, 2], [2, 1]], channel_nodes=[2, 1],
                        channel_directions=[[0.6, 0.8, 0], [-1, 0, 0]], units="mm")
    frame = Frame.from_geometry(geometry, section=Section.circle(0.01), supports={"10": "fixed"})
    assert frame.nodes == {"10": (0.0, 0.0, 0.0), "20": (0.0, 0.0, 0.5), "30": (0.4, 0.0, 0.5)}
    assert frame.members == (("10", "20", "section", None), ("20", "30", "section", None))
    assert frame.sensors == (("30", (0.6, 0.8, 0.0)), ("20", "-x"))
    f, u = frame.node_modes(4)
    _, shapes = frame.modes(4)
    np.testing.assert_allclose(shapes[0], u[2].T @ [0.6, 0.8, 0])
    np.testing.assert_allclose(shapes[1], -u[1, 0])
    with pytest.raises(DataError, match="unknown length unit 'furlong'"):
        Frame.from_geometry(Geometry([1, 2], [[0, 0, 0], [1, 0, 0]], [[0, 1]], [], np.zeros((0, 3)), units="furlong"),
                            section=Section.circle(0.01))
    with pytest.raises(DataError, match="channel 1 measures node 99, which is on no trace line"):
        Frame.from_geometry(Geometry([10, 20, 99], [[0, 0, 0], [1, 0, 0], [5, 5, 5]], [[0, 1]], [2], [[1, 0, 0]]),
                            section=Section.circle(0.01))
    with pytest.raises(DataError, match="channel 2 has no node"):
        Frame.from_geometry(Geometry([10, 20], [[0, 0, 0], [1, 0, 0]], [[0, 1]], [1, -1], [[1, 0, 0], [0, 0, 0]]),
                            section=Section.circle(0.01))
