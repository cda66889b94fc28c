"""Every modelled card against a truth worked out by hand: CORD2R positions and CD directions, PBARL sections by
textbook formulas, MAT1's rule for a blank field, CONM2's offset and products of inertia (parallel axes), springs,
SPC/SPC1 with the case control's set, RBE2, bar offsets and orientation; the unmodelled cards in one sentence;
errors that name the file, line and card."""

from __future__ import annotations

import numpy as np
import pytest
from nastran_decks import deck_text

from era.errors import DataError
from era.models.nastran import read_bdf, read_deck
from era.models.nastran.sections import section_properties


def _model(tmp_path, cards, style="free", header="", name="d.bdf"):
    path = tmp_path / name
    path.write_text(deck_text(cards, style, header))
    return read_bdf(path)


def test_cord2r_positions_and_a_frame_defined_in_another(tmp_path):
    # frame 1: origin (1, 2, 3), z along basic x, x along basic y; frame 2 in frame 1, shifted 5 along its z
    cards = [("CORD2R", [1, 0, 1., 2., 3., 2., 2., 3., 1., 3., 3.]),
             ("CORD2R", [2, 1, 0., 0., 5., 0., 0., 6., 1., 0., 5.]),
             ("GRID", [1, 1, 1., 0., 0.]), ("GRID", [2, 2, 0., 1., 2.]), ("GRID", [3, 0, 0., 0., 0.]),
             ("CELAS2", [1, 1.0, 1, 1]), ("CELAS2", [2, 1.0, 2, 1]), ("CELAS2", [3, 1.0, 3, 1]),
             ("CONM2", [4, 1, 0, 1.]), ("CONM2", [5, 2, 0, 1.]), ("CONM2", [6, 3, 0, 1.])]
    m = _model(tmp_path, cards)
    # in frame 1, x = basic y, y = z × x = basic z, z = basic x
    assert m.coordinates["1"] == pytest.approx((1.0, 3.0, 3.0))
    assert m.coordinates["2"] == pytest.approx((1 + 7.0, 2.0, 3 + 1.0))


def test_a_displacement_frame_turns_the_grid_dofs(tmp_path):
    # a rod along basic x; grid 2's CD frame is turned 45° about z (x = (1, 1, 0)/√2, y = (-1, 1, 0)/√2): the
    # rod's axis is (1, -1)/√2 in it, so EA/L · n nᵀ acts on its x and y
    cards = [("CORD2R", [6, 0, 0., 0., 0., 0., 0., 1., 1., 1., 0.]),
             ("GRID", [1, None, 0., 0., 0., None, 123456]), ("GRID", [2, None, 2., 0., 0., 6]),
             ("CROD", [1, 1, 1, 2]), ("PROD", [1, 1, 3.]), ("MAT1", [1, 10., None, 0.3, 1.])]
    m = _model(tmp_path, cards)
    assert m.dofs == (("2", "x"), ("2", "y"))       # PROD has no J: AUTOSPC holds the twist
    assert m.stiffness.toarray() == pytest.approx(10 * 3 / 2 * np.array([[0.5, -0.5], [-0.5, 0.5]]))
    # consistent mass at the free end: ρAL/3 along the rod, the beam element's 156/420 ρAL across it
    turn = np.array([[1, 1], [-1, 1]]) / np.sqrt(2)         # rows: CD x, y in basic x, y
    basic = np.diag([6.0 / 3, 6.0 * 156 / 420])
    assert m.mass.toarray() == pytest.approx(turn @ basic @ turn.T)


@pytest.mark.parametrize("shape, dims, truth", [
    ("ROD", [0.5], (np.pi * 0.25, np.pi * 0.5 ** 4 / 4, np.pi * 0.5 ** 4 / 4, np.pi * 0.5 ** 4 / 2)),
    ("TUBE", [2., 1.], (3 * np.pi, 15 * np.pi / 4, 15 * np.pi / 4, 15 * np.pi / 2)),
    ("BAR", [2., 6.], (12., 2 * 216 / 12, 6 * 8 / 12, None)),
    # a symmetric I 10 high, flanges 6 × 1, web 0.5: I1 = (6·10³ − 5.5·8³)/12, I2 = 2·1·6³/12 + 8·0.5³/12
    ("I", [10., 6., 6., .5, 1., 1.], (16., (6000 - 5.5 * 512) / 12, (2 * 216 + 8 * .125) / 12, None)),
    # a box 4 wide, 6 high, walls 0.5: outer minus inner rectangle
    ("BOX", [4., 6., .5, .5], (24 - 15, (4 * 216 - 3 * 125) / 12, (6 * 64 - 5 * 27) / 12, None)),
    # a channel's strong axis as the I's (same web and flanges)
    ("CHAN", [3., 10., .5, 1.], (6 + 4., (3 * 1000 - 2.5 * 512) / 12, None, None)),
])
def test_pbarl_sections_match_textbook_formulas(shape, dims, truth):
    got = section_properties(shape, dims)
    for g, t in zip(got, truth):
        if t is not None:
            assert g == pytest.approx(t, rel=1e-12)


def test_box_and_tube_torsion_by_bredt():
    # a thin square tube 10 × 10 (wall midlines), wall 0.1: J = 4 A² t / perimeter = 4·100²·0.1/40 = 100
    _, _, _, j = section_properties("BOX", [10.1, 10.1, .1, .1])
    assert j == pytest.approx(100.0, rel=1e-12)
    _, _, _, j = section_properties("TUBE", [1.0, 0.9])
    assert j == pytest.approx(np.pi * (1 - 0.9 ** 4) / 2)


@pytest.mark.parametrize("fields, e, g, nu", [([2., None, .25], 2., .8, .25), ([2., .8, None], 2., .8, .25),
                                               ([None, .8, .25], 2., .8, .25), ([2., None, None], 2., 0., 0.)])
def test_mat1_fills_one_blank_from_e_2_1_nu_g(tmp_path, fields, e, g, nu):
    (tmp_path / "m.bdf").write_text(deck_text([("MAT1", [1, *fields, 7.8])], "small"))
    m = read_deck(tmp_path / "m.bdf").materials[1]
    assert (m.e, m.g, m.nu, m.rho) == pytest.approx((e, g, nu, 7.8))


def test_conm2_offset_and_products_by_the_parallel_axis_rule(tmp_path):
    m, r = 2.0, np.array([0.5, -1.0, 2.0])
    inertia = [3., 0.1, 4., 0.2, 0.3, 5.]        # I11 I21 I22 I31 I32 I33
    cards = [("GRID", [1, None, 0., 0., 0.]), ("CONM2", [1, 1, 0, m, *r, None, *inertia])]
    cards += [("CELAS2", [10 + c, 1.0, 1, c]) for c in range(1, 7)]
    model = _model(tmp_path, cards, "large")
    mm = model.mass.toarray()
    j = np.array([[3., -0.1, -0.2], [-0.1, 4., -0.3], [-0.2, -0.3, 5.]])
    j_node = j + m * (r @ r * np.eye(3) - np.outer(r, r))          # about the grid: parallel axes
    assert mm[:3, :3] == pytest.approx(m * np.eye(3))
    assert mm[3:, 3:] == pytest.approx(j_node)
    # a unit rotation about x moves the mass by x̂ × r
    assert mm[:3, 3] == pytest.approx(m * np.cross([1, 0, 0], r))


def test_springs_celas1_with_pelas_and_celas2_between_grids(tmp_path):
    cards = [("GRID", [1, None, 0., 0., 0.]), ("GRID", [2, None, 1., 0., 0.]),
             ("CELAS1", [1, 7, 1, 3]), ("PELAS", [7, 100., None, None, 8, 5.]), ("CELAS1", [2, 8, 2, 3]),
             ("CELAS2", [3, 40., 1, 3, 2, 3]), ("CONM2", [4, 1, 0, 1.]), ("CONM2", [5, 2, 0, 1.])]
    m = _model(tmp_path, cards)
    assert m.dofs == (("1", "z"), ("2", "z"))
    assert m.stiffness.toarray() == pytest.approx(np.array([[140., -40.], [-40., 45.]]))
    assert "AUTOSPC: 10 DOFs" in " ".join(m.notes)


def _cantilever(n=4, length=2.0, spc_header="", extra=()):
    cards = [("GRID", [k + 1, None, length * k / n, 0., 0.]) for k in range(n + 1)]
    cards += [("CBAR", [k + 1, 1, k + 1, k + 2, 0., 1., 0.]) for k in range(n)]
    cards += [("PBAR", [1, 1, 0.01, 2e-6, 1e-6, 3e-6]), ("MAT1", [1, 2e11, None, 0.3, 7800.]),
              ("SPC1", [1, 123456, 1]), ("SPC1", [2, 3, n + 1])]
    return cards + list(extra)


def test_spc_set_from_the_case_control_or_every_set(tmp_path):
    every = _model(tmp_path, _cantilever(), name="a.bdf")
    one = _model(tmp_path, _cantilever(), header="CEND\nSPC = 1", name="b.bdf")
    assert ("5", "z") not in every.dofs and ("5", "z") in one.dofs
    assert "every set is applied (1, 2)" in " ".join(every.notes)
    missing = _model(tmp_path, _cantilever(), header="CEND\nSPC = 9", name="c.bdf")
    assert "does not define" in " ".join(missing.notes)


def test_rbe2_joining_two_grids_gives_the_continuous_beam(tmp_path):
    whole = _model(tmp_path, _cantilever(), header="CEND\nSPC=1", name="w.bdf")
    cut = _cantilever()
    cut = [c for c in cut if not (c[0] == "CBAR" and c[1][0] == 3)]
    cut += [("GRID", [9, None, 1.0, 0., 0.]), ("CBAR", [3, 1, 9, 4, 0., 1., 0.]), ("RBE2", [20, 3, 123456, 9])]
    split = _model(tmp_path, cut, header="CEND\nSPC=1", name="s.bdf")
    assert np.allclose(split.modes(6)[0], whole.modes(6)[0], rtol=1e-10)


def test_orientation_by_g0_and_by_vector_agree_and_choose_the_bending_planes(tmp_path):
    by_vector = _model(tmp_path, _cantilever(), header="CEND\nSPC=1", name="v.bdf")
    g0 = [c if c[0] != "CBAR" else ("CBAR", [*c[1][:4], 99]) for c in _cantilever()]
    by_g0 = _model(tmp_path, g0 + [("GRID", [99, None, 0., 5., 0.])], header="CEND\nSPC=1", name="g.bdf")
    assert np.allclose(by_g0.modes(6)[0], by_vector.modes(6)[0], rtol=1e-10)
    # v along y: plane 1 is x-y, I1 = 2e-6 governs the y bending, I2 = 1e-6 the z bending: f_y/f_z = √2
    f, phi = by_vector.modes(2)
    assert f[1] / f[0] == pytest.approx(np.sqrt(2), rel=1e-9)
    assert abs(phi[by_vector.index("5", "z"), 0]) > 0 and phi[by_vector.index("5", "y"), 0] == pytest.approx(0)


def test_bar_offsets_are_rigid_links(tmp_path):
    # the same cantilever drawn 0.3 below its grids, offsets up to them: the same modes
    plain = _model(tmp_path, _cantilever(), header="CEND\nSPC=1", name="p.bdf")
    low = [c if c[0] != "GRID" else ("GRID", [c[1][0], None, c[1][2], 0., -0.3]) for c in _cantilever()]
    low = [c if c[0] != "CBAR" else ("CBAR", [*c[1], None, None, None, 0., 0., 0.3, 0., 0., 0.3]) for c in low]
    offset = _model(tmp_path, low, header="CEND\nSPC=1", name="o.bdf")
    assert np.allclose(offset.modes(6)[0], plain.modes(6)[0], rtol=1e-9)


def test_the_unmodelled_cards_in_one_sentence(tmp_path):
    cards = _cantilever() + [("EIGRL", [1, None, None, 10]), ("CQUAD8", [1, 2, 1, 2, 3, 4, 5]),
                             ("CQUAD8", [2, 2, 1, 2, 3, 4, 5]), ("FORCE", [1, 5, 0, 1., 0., 0., 1.])]
    m = _model(tmp_path, cards)
    sentence = m.notes[0]
    assert sentence.count(".") == 1 and sentence == m.unmodelled
    assert "4 cards" in sentence and "CQUAD8 (2)" in sentence and "EIGRL (1)" in sentence and "FORCE (1)" in sentence
    assert "left out of the model (CQUAD8, FORCE)" in sentence


@pytest.mark.parametrize("card, match", [
    (("GRID", [7, None, "1.2.3", 0., 0.]), r"d\.bdf, line 2, GRID 7: X1 '1\.2\.3' is not a number"),
    (("CBAR", [50, 4, 1, 2, 0., 1., 0.]), r"CBAR 50: property .* 4 is not in the deck"),
    (("CQUAD4", [60, 1, 1, 2, 3, 77]), r"CQUAD4 60: property \(PSHELL or PCOMP\) 1 is not in the deck"),
    (("PBARL", [9, 1, None, "ZED", None, None, None, None, 1.]), r"PBARL 9: the section TYPE 'ZED'"),
    (("GRID", [1, None, 0., 0., 0.]), r"id 1 is used twice"),
])
def test_bad_cards_name_the_file_line_and_card(tmp_path, card, match):
    with pytest.raises(DataError, match=match):
        _model(tmp_path, [card] + _cantilever(), style="small")


def test_pbarl_bar_bends_with_i1_in_the_plane_of_v(tmp_path):
    # BAR DIM1 = 0.01 (along element z), DIM2 = 0.03 (along y): I1 = DIM1·DIM2³/12 for deflection along v = y,
    # I2 = DIM2·DIM1³/12 along z; a cantilever's first bending is 1.8751²/(2π L²) √(EI/ρA) (Euler-Bernoulli)
    n, length, e, rho = 20, 1.0, 2e11, 7800.0
    cards = [("GRID", [k + 1, None, length * k / n, 0., 0.]) for k in range(n + 1)]
    cards += [("CBAR", [k + 1, 1, k + 1, k + 2, 0., 1., 0.]) for k in range(n)]
    cards += [("PBARL", [1, 1, None, "BAR", None, None, None, None, 0.01, 0.03]), ("MAT1", [1, e, None, 0.3, rho]),
              ("SPC1", [1, 123456, 1])]
    m = _model(tmp_path, cards, "small")
    f, phi = m.modes(2)
    area = 0.01 * 0.03
    for k, (inertia, d) in enumerate(((0.03 * 0.01 ** 3 / 12, "z"), (0.01 * 0.03 ** 3 / 12, "y"))):
        assert f[k] == pytest.approx(1.875104 ** 2 / (2 * np.pi * length ** 2) * np.sqrt(e * inertia / (rho * area)),
                                     rel=1e-4)
        other = "y" if d == "z" else "z"
        assert abs(phi[m.index(n + 1, d), k]) > 1e6 * abs(phi[m.index(n + 1, other), k])


def test_pynastran_free_field_channel_deck():
    # pyNastran's models/bars/pbarl_chan.bdf (BSD): CHAN 10 wide, 30 high, web 2, flanges 6, in free field with
    # a comma continuation; its area by pyNastran's documented formula 2·DIM1·DIM4 + (DIM2 − 2·DIM4)·DIM3
    from pathlib import Path
    deck = read_deck(Path(__file__).resolve().parents[1] / "data" / "nastran" / "pynastran" / "pbarl_chan.bdf")
    s = deck.line_sections[100]
    assert s.area == pytest.approx(2 * 10 * 6 + (30 - 12) * 2)
    assert s.i1 == pytest.approx((10 * 30 ** 3 - 8 * 18 ** 3) / 12)
    assert deck.materials[1000].g == pytest.approx(3e7 / 2.6)
    assert sorted(deck.lines) == [10, 11] and deck.skipped == {}


def test_grdset_gives_the_grids_blank_frames_and_constraints(tmp_path):
    cards = [("GRDSET", [None, 7, None, None, None, 7, 456]),
             ("CORD2R", [7, 0, 0., 0., 0., 0., 0., 1., 0., 1., 0.]),      # x = basic y, y = basic -x
             ("GRID", [1, 0, 0., 0., 0., 0, 123456]), ("GRID", [2, None, 1., 0., 0.]),
             ("CROD", [1, 1, 1, 2]), ("PROD", [1, 1, 1.]), ("MAT1", [1, 10., None, 0.3, 1.])]
    m = _model(tmp_path, cards)
    assert m.coordinates["2"] == pytest.approx((0., 1., 0.))    # CP 7 from the GRDSET
    assert m.dofs == (("2", "x"),)                                  # the rod runs along grid 2's CD x; PS 456
    assert m.stiffness.toarray()[0, 0] == pytest.approx(10.0)
    assert m.unmodelled == ""


@pytest.mark.parametrize("shape, dims, area", [
    # areas by pyNastran's documented MSC formulas (pyNastran/bdf/cards/properties/bars.py docstring)
    ("T", [6., 8., 1., .5], 6 * 1 + (8 - 1) * .5),
    ("H", [4., 2., 6., .5], 2 * (0.5 * 2) * 6 + 4 * .5),
    ("CROSS", [4., .5, 6., .5], .5 * 6 + 2 * (0.5 * 4) * .5),
    ("I", [10., 6., 4., .5, 1., .8], 4 * .8 + 6 * 1 + (10 - 1.8) * .5),
])
def test_pbarl_areas_follow_msc(shape, dims, area):
    assert section_properties(shape, dims)[0] == pytest.approx(area)


def test_open_sections_inertia_by_numerical_integration():
    # a T (flange 6 × 1 on top of a web 0.5 × 7) and an L (legs 5 × 1 and 1 × 7) sampled on a fine grid: ∫y² dA
    # and ∫z² dA about the centroid
    def integrate(inside, box, n=1500):
        z, y = np.meshgrid(np.linspace(box[0], box[1], n), np.linspace(box[2], box[3], n))
        w = inside(z, y) * ((box[1] - box[0]) / (n - 1)) * ((box[3] - box[2]) / (n - 1))
        a = w.sum()
        yc, zc = (w * y).sum() / a, (w * z).sum() / a
        return a, (w * (y - yc) ** 2).sum(), (w * (z - zc) ** 2).sum()

    def tee(z, y):
        return ((abs(z) <= 3) & (y >= 7) & (y <= 8)) | ((abs(z) <= 0.25) & (y >= 0) & (y < 7))

    def ell(z, y):
        return ((z >= 0) & (z <= 5) & (y >= 0) & (y <= 1)) | ((z >= 0) & (z <= 1) & (y > 1) & (y <= 8))

    for shape, dims, inside, box in (("T", [6., 8., 1., .5], tee, (-3, 3, 0, 8)),
                                     ("L", [5., 8., 1., 1.], ell, (0, 5, 0, 8))):
        a, i1, i2, _ = section_properties(shape, dims)
        na, ni1, ni2 = integrate(inside, box)
        assert (a, i1, i2) == pytest.approx((na, ni1, ni2), rel=0.01)


def test_cbush_to_ground_and_between_coincident_grids_in_its_frame(tmp_path):
    # frame 4 turned 90° about z (its x = basic y): K1 = 100 acts along basic y, K2 = 7 along basic -x
    cards = [("CORD2R", [4, 0, 0., 0., 0., 0., 0., 1., 0., 1., 0.]),
             ("GRID", [1, None, 0., 0., 0.]), ("GRID", [2, None, 0., 0., 0.]),
             ("CBUSH", [1, 9, 1, None, None, None, None, 4]), ("PBUSH", [9, "K", 100., 7., 0., 0., 0., 0.]),
             ("CBUSH", [2, 8, 1, 2, None, None, None, 0]), ("PBUSH", [8, "K", 0., 0., 30., 0., 0., 0.]),
             ("CONM2", [3, 1, 0, 1.]), ("CONM2", [4, 2, 0, 1.])]
    m = _model(tmp_path, cards)
    assert m.dofs == (("1", "x"), ("1", "y"), ("1", "z"), ("2", "z"))
    assert m.stiffness.toarray() == pytest.approx(np.array([[7., 0, 0, 0], [0, 100., 0, 0], [0, 0, 30., -30.],
                                                            [0, 0, -30., 30.]]))
    assert m.unmodelled == ""
    with pytest.raises(DataError, match="zero-length bush"):
        _model(tmp_path, cards[:-1] + [("GRID", [5, None, 1., 0., 0.]), ("CBUSH", [6, 8, 1, 5, None, None, None, 0])],
               name="e.bdf")


def test_a_ply_by_ply_composite_is_refused_by_name(tmp_path):
    cards = [("GRID", [k, None, float(k % 2), float(k // 2), 0.]) for k in range(4)]
    cards += [("CQUAD4", [1, 5, 0, 1, 3, 2]), ("PCOMPG", [5, None, None, None, None, None, None, None, 1, 1,
                                                          .001, 0.])]
    with pytest.raises(DataError, match=r"CQUAD4 1: its property 5 is no PSHELL or PCOMP of the deck; PCOMPG"):
        _model(tmp_path, cards)
