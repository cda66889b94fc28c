"""era.Frame refuses a bad description with a DataError that says what to change."""

import numpy as np
import pytest

from era.errors import DataError, EraError
from era.structure import Frame, Section

SEC = Section.rectangle(width=0.05, depth=0.006)
NODES = {"1": (0.0, 0.0, 0.0), "2": (0.0, 0.0, 0.9), "3": (1.0, 0.0, 0.9), "4": (1.0, 0.0, 0.0)}
MEMBERS = [("1", "2", "s"), ("2", "3", "s"), ("3", "4", "s")]


def portal(**changes):
    kw = dict(nodes=NODES, members=MEMBERS, sections={"s": SEC}, supports={"1": "fixed", "4": "fixed"},
              sensors=[("2", "x")])
    return Frame(**{**kw, **changes})


@pytest.mark.parametrize("changes, words", [
    (dict(members=MEMBERS + [("3", "9", "s")]), ["member 3", "node 9", "not in nodes"]),
    (dict(nodes={**NODES, "5": (1.0, 0.0, 0.9)}, members=MEMBERS + [("3", "5", "s")]), ["member 3", "zero length"]),
    (dict(members=MEMBERS[:2] + [("3", "4", "beam")]), ["unknown section 'beam'", "known: ['s']"]),
    (dict(members=MEMBERS[:2] + [("3", "4", "s", (0, 0, 2))]), ["orientation", "parallel"]),
    (dict(nodes={**NODES, "7": (5.0, 0, 0)}), ["node 7", "on no member"]),
    (dict(nodes={**NODES, "2": (0.0, np.nan, 0.9)}), ["node 2", "finite coordinates"]),
    (dict(nodes={**NODES, "2": ("a", 0, 0.9)}), ["node 2", "finite coordinates"]),
    (dict(members=MEMBERS[:2] + [("3", "4", "s", "up")]), ["orientation 'up'"]),
    (dict(sensors=[("2", [1, "y", 0])]), ["sensor at node 2"]),
    (dict(sensors=[("8", "x")]), ["sensor at node 8", "not in nodes"]),
    (dict(sensors=[("2", "up")]), ["sensor at node 2", "direction 'up'"]),
    (dict(sensors=[("2", (0, 0, 0))]), ["sensor at node 2"]),
    (dict(supports={"1": "clamped"}), ["support at node 1", "'fixed', 'pinned'"]),
    (dict(supports={"1": {"kq": 3.0}}), ["support at node 1", "unknown key 'kq'"]),
    (dict(supports={"1": {"kz": -3.0}}), ["support at node 1", "kz"]),
    (dict(supports={"6": "fixed"}), ["support at node 6", "not in nodes"]),
    (dict(supports={"1": {"cable": 0.5}}), ["cable at node 1", "gravity along a global axis"]),
    (dict(masses={"2": -1.0}), ["mass at node 2"]),
    (dict(masses={"12": 1.0}), ["mass at node 12"]),
    (dict(gravity=(0, 0)), ["gravity"]),
    (dict(elements_per_member=0), ["elements_per_member"]),
    (dict(elements_per_member=(2, 2)), ["one such integer per member (3)"]),
    (dict(elements_per_member=(2, 2, 0)), ["elements_per_member"]),
])
def test_a_bad_description_is_refused_by_name(changes, words):
    with pytest.raises(DataError) as info:
        portal(**changes)
    for w in words:
        assert w in str(info.value)


def test_sections_refuse_non_positive_constants_and_unknown_materials():
    with pytest.raises(DataError, match="iy must be positive"):
        Section(area=1e-4, iy=0.0, iz=1e-8, j=1e-9, e=2e11, g=8e10, density=7850)
    with pytest.raises(DataError, match="unknown material 'cheese'"):
        Section.rectangle(0.05, 0.006, material="cheese")
    with pytest.raises(DataError, match="unknown shape"):
        Section.from_dict({"shape": "hexagon", "width": 0.1})
    assert issubclass(DataError, EraError)


@pytest.mark.parametrize("supports, words", [
    ({"1": "pinned", "4": "pinned"}, ["rotation about x is free", "rigid body", "1 zero-stiffness"]),
    ({"1": {"kx": "fixed", "ky": "fixed", "kz": "fixed", "rx": "fixed", "ry": "fixed"}},
     ["rotation about z is free", "add a support or a member", "rigid body"]),
    ({"1": {"kx": "fixed", "kz": "fixed", "rx": "fixed", "ry": "fixed", "rz": "fixed"}},
     ["translation along y is free"]),
])
def test_a_mechanism_names_the_free_dof(supports, words):
    """Two pins in 3-D leave the portal free to rock about the line through them (rotation about x)."""
    with pytest.raises(DataError) as info:
        portal(supports=supports).modes(5)
    assert "mechanism" in str(info.value)
    for w in words:
        assert w in str(info.value)


def test_two_unconnected_pieces_of_a_free_structure_are_a_mechanism_beyond_the_six_rigid_modes():
    nodes = {"a": (0, 0, 0), "b": (1, 0, 0), "c": (0, 1, 0), "d": (1, 1, 0)}
    free = Frame(nodes=nodes, members=[("a", "b", "s"), ("c", "d", "s")], sections={"s": SEC})
    with pytest.raises(DataError, match="is free: add a support or a member; 4 zero-stiffness motion"):
        free.modes(10)
    one_piece = Frame(nodes=nodes, members=[("a", "b", "s"), ("b", "d", "s"), ("d", "c", "s")], sections={"s": SEC})
    assert np.all(one_piece.modes(10)[0][:6] < 1e-2) and one_piece.modes(10)[0][6] > 1.0


def test_gravity_on_a_free_structure_and_a_pushing_cable_are_refused():
    with pytest.raises(DataError, match="do not carry the self-weight"):
        portal(supports={}, gravity=(0, 0, -9.81)).modes(3)
    # a beam pinned at b with a long overhang b-c: the cable at a would have to pull it down
    beam = Frame(nodes={"a": (0, 0, 0), "b": (1, 0, 0), "c": (3, 0, 0)}, members=[("a", "b", "s"), ("b", "c", "s")],
                 sections={"s": SEC}, supports={"a": {"cable": 0.5, "rx": "fixed"}, "b": "pinned"},
                 gravity=(0, 0, -9.81))
    with pytest.raises(DataError, match="cable at node a would push"):
        beam.modes(3)


def test_self_weight_beyond_the_buckling_load_is_refused():
    """Greenhill: a clamped column buckles under its own weight when q L³ = 7.837 EI."""
    s = Section.circle(diameter=0.004, material="steel")
    L_cr = (7.837 * s.e * s.iy / (s.mass_per_length * 9.81)) ** (1 / 3)

    def column(L, gravity=(0, 0, -9.81)):
        return Frame(nodes={"base": (0, 0, 0), "top": (0, 0, L)}, members=[("base", "top", "s")], sections={"s": s},
                     supports={"base": "fixed"}, gravity=gravity)
    loaded, unloaded = column(0.97 * L_cr).modes(1)[0][0], column(0.97 * L_cr, None).modes(1)[0][0]
    assert 0 < loaded < 0.3 * unloaded                        # near buckling the first frequency drops
    with pytest.raises(DataError, match="buckles under its self-weight"):
        column(1.03 * L_cr).modes(2)


def test_bad_mode_counts_are_refused():
    with pytest.raises(DataError, match="positive integer"):
        portal().modes(0)
    with pytest.raises(DataError, match="free DOFs"):
        portal(elements_per_member=1).modes(30)


def test_buckling_is_caught_on_the_sparse_path_too():
    """A clamped column meshed finely (over 200 DOFs, the Lanczos path) under 1.5× its Greenhill load."""
    s = Section.circle(diameter=0.004, material="steel")
    L = 1.5 ** (1 / 3) * (7.837 * s.e * s.iy / (s.mass_per_length * 9.81)) ** (1 / 3)
    column = Frame(nodes={"base": (0, 0, 0), "top": (0, 0, L)}, members=[("base", "top", "s")], sections={"s": s},
                   supports={"base": "fixed"}, gravity=(0, 0, -9.81), elements_per_member=60)
    with pytest.raises(DataError, match="buckles under its self-weight"):
        column.modes(3)
