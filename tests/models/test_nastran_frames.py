"""Cylindrical and spherical frames (CORD2C, CORD2S, CORD1R/C/S) as a grid's position frame CP and displacement
frame CD: a free ring of CBARs given in a cylindrical frame against the thin ring's closed-form frequencies and
inextensional shapes, a clamped cylinder given in a tilted CORD2C equal to the same cylinder in basic, positions
and directions worked out by hand."""

from __future__ import annotations

import numpy as np
import pytest
from nastran_decks import deck_text

from era.errors import DataError
from era.models.nastran import read_bdf

E, NU, RHO = 2.1e11, 0.3, 7850.0


def _model(tmp_path, cards, name="d.bdf", style="free"):
    path = tmp_path / name
    path.write_text(deck_text(cards, style))
    return read_bdf(path)


def _ring_cards(n: int, radius: float, b: float, h: float, cd: int | None) -> list:
    """A free circle of n CBARs, grids in CORD2C 5 (axis basic z) at (R, θ, 0), displacement frame ``cd``; the
    section b (radial) × h (axial), orientation v along the axis."""
    cards = [("CORD2C", [5, 0, 0., 0., 0., 0., 0., 1., 1., 0., 0.])]
    cards += [("GRID", [k + 1, 5, radius, 360.0 * k / n, 0.0, cd]) for k in range(n)]
    v = (0.0, 0.0, 1.0)
    cards += [("CBAR", [k + 1, 1, k + 1, (k + 1) % n + 1, *v]) for k in range(n)]
    # v along the axis: element y is axial, element z radial; I1 (about z) bends the ring out of its plane
    i_out, i_in = b * h ** 3 / 12, h * b ** 3 / 12
    beta = 1 / 3 - 0.21 * (b / h) * (1 - (b / h) ** 4 / 12)
    cards += [("PBAR", [1, 1, b * h, i_out, i_in, beta * h * b ** 3]), ("MAT1", [1, E, None, NU, RHO])]
    return cards


def test_a_free_ring_in_a_cylindrical_frame_against_the_thin_ring(tmp_path):
    radius, b, h = 1.0, 0.02, 0.03
    m = _model(tmp_path, _ring_cards(72, radius, b, h, None))
    assert m.unmodelled == ""
    assert m.coordinates["19"] == pytest.approx((0.0, 1.0, 0.0), abs=1e-15)       # θ = 90°
    f, _ = m.modes(10)
    area, i_in, i_out = b * h, h * b ** 3 / 12, b * h ** 3 / 12
    beta = 1 / 3 - 0.21 * (b / h) * (1 - (b / h) ** 4 / 12)
    gj = E / (2 * (1 + NU)) * beta * h * b ** 3
    # a thin ring's bending modes with n waves: in its plane ω² = EI n²(n² − 1)² / (ρA R⁴ (n² + 1)); out of it
    # ω² = EI n²(n² − 1)² / (ρA R⁴ (n² + EI/GJ)) (Blevins, Formulas for natural frequency and mode shape, 9-3)
    def ring(n, ei, rest):
        return np.sqrt(ei * n ** 2 * (n ** 2 - 1) ** 2 / (RHO * area * radius ** 4 * rest)) / (2 * np.pi)

    truth = sorted([ring(2, E * i_in, 5.0)] * 2 + [ring(2, E * i_out, 4 + E * i_out / gj)] * 2)
    assert np.all(f[:6] < 1e-4 * f[6])
    assert f[6:10] == pytest.approx(truth, rel=2e-3)


def test_the_ring_s_dofs_in_its_cylindrical_frame_are_radial_tangential_axial(tmp_path):
    """With CD = the cylindrical frame, "x" is radial, "y" tangential: the in-plane n = 2 pair is inextensional,
    u_θ = −u_r'/n... so its tangential amplitude is half its radial; the out-of-plane pair moves along "z" only.
    The matrices are the basic model's turned grid by grid (Aᵀ K A), the mass the same."""
    radius, b, h = 1.0, 0.02, 0.03
    basic = _model(tmp_path, _ring_cards(48, radius, b, h, None), "basic.bdf")
    turned = _model(tmp_path, _ring_cards(48, radius, b, h, 5), "turned.bdf")
    assert turned.dofs == basic.dofs and set(turned.dof_axes) == {str(k + 1) for k in range(48)}
    a = np.zeros((turned.n_dofs, turned.n_dofs))
    for i, (node, d) in enumerate(turned.dofs):
        for j, (node2, d2) in enumerate(turned.dofs):
            if node == node2 and (d in ("x", "y", "z")) == (d2 in ("x", "y", "z")):
                a[j, i] = turned.dof_axes[node]["xyz".index(d2[-1]), "xyz".index(d[-1])]
    assert turned.stiffness.toarray() == pytest.approx(a.T @ basic.stiffness.toarray() @ a, abs=1e-6 * abs(
        basic.stiffness).max())
    assert turned.total_mass() == pytest.approx(basic.total_mass(), rel=1e-12)
    assert turned.total_mass() == pytest.approx(RHO * b * h * 2 * np.pi * radius, rel=1e-3)
    f_basic, _ = basic.modes(10)
    f, phi = turned.modes(10)
    assert np.all(f[:6] < 1e-4 * f[6]) and f[6:] == pytest.approx(f_basic[6:], rel=1e-9)
    in_plane, out_of_plane = phi[:, 6:8], phi[:, 8:10]          # b < h: the ring is softer in its plane
    for pair, moving in ((in_plane, ("x", "y")), (out_of_plane, ("z",))):
        for d in ("x", "y", "z"):
            amp = np.abs(pair[turned.rows(d)]).max()
            assert (amp > 1e-3 * np.abs(pair).max()) == (d in moving)
    ur, ut = (np.abs(in_plane[turned.rows(d)]).max(axis=0) for d in ("x", "y"))
    assert ut / ur == pytest.approx([0.5, 0.5], rel=1e-2)      # the ring stretches a little (0.4 %)


def _cylinder_cards(frame: list | None, origin, axes, nt=16, nz=4, radius=0.3, length=0.6, cd=None) -> list:
    """A cylinder of CQUAD4 clamped at z = 0: grids in the CORD2C ``frame`` (R, θ, z) when given, else in basic
    through ``origin`` + ``axes`` @ (R cos θ, R sin θ, z)."""
    cards = [("CORD2C", frame)] if frame else []
    gid = {}
    for j in range(nz + 1):
        for i in range(nt):
            gid[i, j] = 1 + i + nt * j
            t, z = 360.0 * i / nt, length * j / nz
            if frame:
                xyz, cp = [radius, t, z], frame[0]
            else:
                xyz = list(map(float, origin + axes @ [radius * np.cos(np.radians(t)), radius * np.sin(np.radians(t)), z]))
                cp = 0
            cards.append(("GRID", [gid[i, j], cp, *xyz, cd, 123456 if j == 0 else None]))
    cards += [("CQUAD4", [k + 1, 1, gid[i, j], gid[(i + 1) % nt, j], gid[(i + 1) % nt, j + 1], gid[i, j + 1]])
              for k, (i, j) in enumerate((i, j) for j in range(nz) for i in range(nt))]
    return cards + [("PSHELL", [1, 1, 0.003, 1]), ("MAT1", [1, E, None, NU, RHO])]


def test_a_cylinder_in_a_tilted_cord2c_equals_the_same_cylinder_in_basic(tmp_path):
    # CORD2C 9: origin (1, 2, 3), axis along (1, 1, 1)/√3, x axis in the plane of (1, 0, 0)
    origin, b = np.array([1.0, 2.0, 3.0]), np.array([2.0, 3.0, 4.0])
    z = (b - origin) / np.linalg.norm(b - origin)
    c = origin + np.array([1.0, 0.0, 0.0])
    y = np.cross(z, c - origin)
    y /= np.linalg.norm(y)
    axes = np.column_stack([np.cross(y, z), y, z])
    frame = [9, 0, *origin, *b, *c]
    basic = _model(tmp_path, _cylinder_cards(None, origin, axes), "basic.bdf")
    cyl = _model(tmp_path, _cylinder_cards(frame, origin, axes), "cyl.bdf", "large")
    for node, xyz in basic.coordinates.items():
        assert cyl.coordinates[node] == pytest.approx(xyz, abs=1e-9)      # the large field's 10 digits
    f_basic = basic.modes(8)[0]
    assert cyl.modes(8)[0] == pytest.approx(f_basic, rel=1e-9)
    # every grid's DOFs along its own radial, tangential and axial directions: the same frequencies
    turned = _model(tmp_path, _cylinder_cards(frame, origin, axes, cd=9), "turned.bdf", "large")
    assert turned.modes(8)[0] == pytest.approx(f_basic, rel=1e-9)
    assert turned.dof_axes["18"][:, 2] == pytest.approx(z)           # "z" of every grid is the axis
    radial = np.asarray(turned.coordinates["18"]) - origin
    radial -= (radial @ z) * z
    assert turned.dof_axes["18"][:, 0] == pytest.approx(radial / np.linalg.norm(radial))


def test_spherical_and_cord1_frames_by_hand(tmp_path):
    cards = [("CORD2S", [3, 0, 0., 0., 1., 0., 0., 2., 1., 0., 1.]),           # basic axes, origin (0, 0, 1)
             ("GRID", [1, 3, 2.0, 90.0, 90.0, 3]),      # R 2, θ 90° from the z axis, φ 90°: basic (0, 2, 1)
             ("GRID", [2, 3, 1.0, 60.0, 0.0]),          # basic (sin 60°, 0, 1 + cos 60°)
             ("GRID", [3, None, 5., 0., 0.]),
             ("CORD1C", [4, 3, 1, 2]),                  # origin grid 3, z towards grid 1, x-z plane through 2
             ("CORD1R", [6, 3, 1, 2, 7, 3, 2, 1]),      # two frames on one card
             ("GRID", [4, 4, 1.0, 90.0, 0.0, 7]),
             ("CONM2", [1, 1, 0, 1.]), ("CONM2", [2, 2, 0, 1.]), ("CONM2", [3, 3, 0, 1.]),
             ("CONM2", [4, 4, 0, 1.])]
    cards += [("CELAS2", [10 * g + c, 1e3, g, c]) for g in (1, 2, 3, 4) for c in (1, 2, 3)]
    m = _model(tmp_path, cards)
    assert m.unmodelled == ""
    assert m.coordinates["1"] == pytest.approx((0.0, 2.0, 1.0), abs=1e-15)
    assert m.coordinates["2"] == pytest.approx((np.sin(np.pi / 3), 0.0, 1.5))
    # grid 1 on the equator at φ = 90°: radial = basic y, meridian θ = basic -z, azimuth φ = basic -x
    assert m.dof_axes["1"] == pytest.approx(np.array([[0, 0, -1], [1, 0, 0], [0, -1, 0]]), abs=1e-15)
    # CORD1C 4: z from grid 3 (5, 0, 0) towards grid 1, x towards grid 2's side; grid 4 at R 1, θ 90° is one
    # unit along the frame's y = z × x
    zc = np.array([-5.0, 2.0, 1.0]) / np.sqrt(30)
    xc = np.array([np.sin(np.pi / 3) - 5, 0.0, 1.5])
    xc -= (xc @ zc) * zc
    xc /= np.linalg.norm(xc)
    assert m.coordinates["4"] == pytest.approx(np.array([5.0, 0, 0]) + np.cross(zc, xc))
    # CORD1R 7 (the card's second frame): z from grid 3 towards grid 2, x-z plane through grid 1
    z7 = np.array([np.sin(np.pi / 3) - 5, 0.0, 1.5])
    z7 /= np.linalg.norm(z7)
    assert m.dof_axes["4"][:, 2] == pytest.approx(z7)
    assert m.total_mass() == pytest.approx(4.0)


def test_frame_errors_name_the_card(tmp_path):
    grids = [("GRID", [1, 2, 1., 0., 0.]), ("CONM2", [1, 1, 0, 1.])]
    with pytest.raises(DataError, match=r"GRID 1: frame 2 is not a coordinate frame"):
        _model(tmp_path, grids, "a.bdf")
    circle = [("CORD1R", [2, 1, 3, 4]), ("GRID", [3, None, 0., 1., 0.]), ("GRID", [4, None, 1., 0., 0.])]
    with pytest.raises(DataError, match="in a circle"):
        _model(tmp_path, grids + circle, "b.bdf")
    cyl_mass = [("CORD2C", [2, 0, 0., 0., 0., 0., 0., 1., 1., 0., 0.]), ("GRID", [1, None, 1., 0., 0.]),
                ("CONM2", [1, 1, 2, 1., 0.1])]
    with pytest.raises(DataError, match=r"CONM2 1: its frame CID 2 is cylindrical"):
        _model(tmp_path, cyl_mass, "c.bdf")
