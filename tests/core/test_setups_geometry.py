"""The points table of a multi-setup test (era.setups.geometry): parsed as typed, placed on the merged points by
their names, refused with the row that is wrong."""

import numpy as np
import pytest

import era
from era.setups.geometry import parse_points, point_aliases, points_geometry

TABLE = """point,x,y,z,direction
S1:ch1, 0, 0, 1, x
S1:ch2, 0, 0, 1, -y
S2:ch1, 0, 0, 2, 0 1 1
S1:ch3, 0, 0, 3, z
from,to
S1:ch1,S2:ch1
S2:ch1,S1:ch3
"""


def aliases():
    # two setups: channels ch1 (roving), ch2 (roving, setup 1 only), ch3 the reference (setup 2: ch2)
    outputs = [["ch1", "ch2", "ch3"], ["ch1", "ch2"]]
    points = ("ch3", "S1:ch1", "S1:ch2", "S2:ch1")
    return point_aliases(points, np.array([-1, 0, 0, 1]), np.array([2, 0, 1, 0]), outputs, [[2], [1]])


def test_a_typed_table_places_every_merged_point_on_its_node():
    g = points_geometry(parse_points(TABLE), aliases())
    assert g.node_ids.tolist() == [1, 2, 3]  # S1:ch1 and S1:ch2 share the point at z = 1
    np.testing.assert_allclose(g.coordinates[:, 2], [1, 2, 3])
    assert g.channel_nodes.tolist() == [2, 0, 0, 1]  # the reference (ch3) at z = 3
    np.testing.assert_allclose(g.channel_directions[1:3], [[1, 0, 0], [0, -1, 0]])
    np.testing.assert_allclose(g.channel_directions[3], [0, 2 ** -0.5, 2 ** -0.5])
    assert g.edges.tolist() == [[0, 1], [1, 2]]


def test_a_reference_may_be_named_as_any_setup_names_it():
    table = TABLE.replace("S1:ch3, 0, 0, 3, z", "S2:ch2, 0, 0, 3, z").replace("S2:ch1,S1:ch3", "S2:ch1,S2:ch2")
    assert points_geometry(parse_points(table), aliases()).channel_nodes.tolist() == [2, 0, 0, 1]


@pytest.mark.parametrize("table, words", [
    ("x,y,z\n1,2,3\n", "must start with the header point,x,y,z,direction"),
    ("point,x,y,z,direction\nP1,0,0,one,x\n", "Row 2 of the points table: x, y, z must be numbers"),
    ("point,x,y,z,direction\nP1,0,0,1,w\n", "the direction is an axis"),
    ("point,x,y,z,direction\nP1,0,0,1,x\nP1,0,0,2,x\n", "Point P1 is in the points table twice"),
    ("point,x,y,z,direction\nP1,0,0,1,x\nfrom,to\nP1,P9\n", "names point P9, which the points table does not have"),
])
def test_a_wrong_table_is_refused_with_its_row(table, words):
    with pytest.raises(era.DataError, match=words):
        parse_points(table)


def test_a_table_that_misses_a_point_or_names_a_stranger_is_refused():
    with pytest.raises(era.DataError, match="has no row for S2:ch1"):
        points_geometry(parse_points("point,x,y,z,direction\nS1:ch1,0,0,1,x\nS1:ch2,0,0,1,y\nch3,0,0,3,z\n"),
                        aliases())
    with pytest.raises(era.DataError, match="names S7:ch1, which is not a point of this test"):
        points_geometry(parse_points(TABLE.replace("S2:ch1", "S7:ch1")), aliases())


def nodes_uff(path, ids, xyz, traces=()):
    """A UFF file of nodes (15) and trace lines (82) written by pyuff, as another program would."""
    import pyuff

    xyz = np.asarray(xyz, float)
    sets = [pyuff.prepare_15(node_nums=list(ids), def_cs=[0] * len(ids), disp_cs=[0] * len(ids),
                             color=[1] * len(ids), x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2])]
    for t, seq in enumerate(traces):
        sets.append({"type": 82, "trace_num": t + 1, "n_nodes": len(seq), "color": 1, "id": f"line {t + 1}",
                     "nodes": np.asarray(seq, dtype=int)})
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    return path


def test_points_on_the_nodes_of_a_uff_file_take_its_coordinates_and_lines(tmp_path):
    """UFF 15 nodes 10..14 (10: the ground, no sensor) and one trace line up through them, written by pyuff; the
    table puts each point on a node: the geometry keeps every node and line of the file."""
    xyz = [[0, 0, 0], [0, 0, 1.5], [0.5, 0, 1.5], [0, 0, 2.5], [0, 0, 3.5]]
    path = nodes_uff(tmp_path / "nodes.uff", [10, 11, 12, 13, 14], xyz, [[10, 11, 13, 14], [11, 12]])
    nodes = era.load(path).geometry
    table = "point,node,direction\nS1:ch1,11,x\nS1:ch2,12,-y\nS2:ch1,13,0 1 1\nch3,14,z\nfrom,to\nS1:ch2,S2:ch1\n"
    parsed = parse_points(table, nodes=nodes)
    assert parsed.nodes == (11, 12, 13, 14)
    np.testing.assert_allclose(parsed.coordinates, np.array(xyz)[1:])
    g = points_geometry(parsed, aliases())
    assert g.node_ids.tolist() == [10, 11, 12, 13, 14]
    np.testing.assert_allclose(g.coordinates, xyz)
    assert g.channel_nodes.tolist() == [4, 1, 2, 3]  # the reference ch3 on node 14
    np.testing.assert_allclose(g.channel_directions[2], [0, -1, 0])
    assert sorted(map(tuple, g.edges.tolist())) == [(0, 1), (1, 2), (1, 3), (2, 3), (3, 4)]
    # a node the file does not have, and nodes without the file, are refused in words
    with pytest.raises(era.DataError, match="node 99 is not in the UFF file"):
        parse_points(table.replace(",14,", ",99,"), nodes=nodes)
    with pytest.raises(era.DataError, match="give the UFF file that defines them"):
        parse_points(table)
