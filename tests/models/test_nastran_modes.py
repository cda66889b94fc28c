"""Decks solved against truths from elsewhere: a cantilever with a tip mass (pyNastran's beam_modes deck, BSD)
against Euler-Bernoulli's frequency equation and against MSC Nastran's own f06 of that deck; a simply supported
plate of CQUAD4 and of CTRIA3 against Kirchhoff's formula; one deck of every card written in small, large and free
field gives one model."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from nastran_decks import (cantilever_tip_mass, deck_text, every_card, plate_cards, plate_frequencies,
                           stiffened_panel)

from era import load_model
from era.models.nastran import read_bdf

DATA = Path(__file__).resolve().parents[1] / "data" / "nastran" / "pynastran"
#: MSC Nastran 2005's eigenvalue table for beam_modes.dat (pyNastran's models/beam_modes/beam_modes.f06, BSD):
#: the bending pairs, the torsion and the axial mode, Hz
NASTRAN_F06 = {"bending 1": 456.6603, "bending 2": 2674.587, "torsion": 3554.923, "axial": 4507.487}


def test_pynastran_beam_deck_against_euler_bernoulli_and_nastran():
    m = load_model(DATA / "beam_modes.dat")          # INCLUDE 'cbar_cbeam.blk', SPC = 1 from the case control
    assert m.unmodelled == ("Not modelled: 8 cards of the deck, EIGRL (1), PARAM (6), USET (1); solution and "
                            "output requests (EIGRL, PARAM, USET) do not change the modes.")
    assert set(m.parts) == {"PBARL 1", "PBEAML 3"} and "12" not in m.nodes      # grid 12 touches nothing
    # steel rod r = 1 in, L = 10 in, E = 3e7 psi, ρ = 7.4851e-4 lbf·s²/in⁴, tip CONM2 2.59e-3 with I = 2.59e-3
    e, rho, area, inertia = 3e7, 7.4851e-4, np.pi, np.pi / 4
    truth = cantilever_tip_mass(e * inertia, rho * area, 10.0, 2.59e-3, 2.59e-3, 2, 4000.0)
    f, _ = m.modes(10)
    # the moving mass: Nastran's GPWG 2.610514e-2 less the clamped root's share of the first element's consistent
    # mass, (156 + 2·54)/420 of it
    assert m.total_mass() == pytest.approx(rho * area * (10 - 264 / 420) + 2.59e-3, rel=1e-12)
    assert f[[0, 1]] == pytest.approx([truth[0]] * 2, rel=2e-4)                     # 10 elements, consistent mass
    bending_2 = f[np.argmin(abs(f - truth[1]))]
    assert bending_2 == pytest.approx(truth[1], rel=1e-3)
    # Nastran's CBAR of a PBARL has shear flexibility (K = 0.9): its bending is lower than Euler-Bernoulli's by
    # 1.7 % (mode 1) and 10 % (mode 2, L/r = 5 per half wave); the axial mode has no such term
    assert f[0] == pytest.approx(NASTRAN_F06["bending 1"], rel=0.02)
    axial = f[np.argmin(abs(f - NASTRAN_F06["axial"]))]
    assert axial == pytest.approx(NASTRAN_F06["axial"], rel=3e-3)


@pytest.mark.parametrize("triangles", [False, True])
def test_simply_supported_plate_against_kirchhoff(tmp_path, triangles):
    a, b, t, e, nu, rho = 0.6, 0.4, 0.004, 7e10, 0.3, 2700.0
    path = tmp_path / "plate.bdf"
    path.write_text(deck_text(plate_cards(36, 24, a, b, t, e, nu, rho, triangles), "small"))
    m = read_bdf(path)
    assert set(m.parts) == {"PSHELL 1"}
    f, _ = m.modes(4)
    truth = plate_frequencies(a, b, t, e, nu, rho, 4)
    assert f == pytest.approx(truth, rel=0.015 if triangles else 0.01)


def test_small_large_and_free_field_give_one_model(tmp_path):
    models = []
    for style in ("small", "large", "free"):
        path = tmp_path / f"{style}.bdf"
        path.write_text(deck_text(every_card(), style, header="SOL 103\nCEND\nSPC = 1"))
        models.append(read_bdf(path))
    first = models[0]
    assert first.unmodelled == "" and set(first.parts) == {"PSHELL 1", "PBARL 2", "PBEAM 4", "PROD 5"}
    assert first.coordinates["100"] == pytest.approx((0., 0., 1.))            # CORD2R 3 lifts the plate
    for other in models[1:]:
        assert other.dofs == first.dofs
        assert abs(other.stiffness - first.stiffness).max() <= 1e-6 * abs(first.stiffness).max()
        assert abs(other.mass - first.mass).max() <= 1e-6 * abs(first.mass).max()
    f, _ = first.modes(6)
    assert np.all(f > 0) and np.all(np.isfinite(f))


def test_a_stiffened_panel_deck_against_calculix(tmp_path):
    """A plate with two shell-web stiffeners (CQUAD4 of two PSHELLs, clamped by SPC1) read from a large-field
    deck, against CalculiX (ccx run as a separate program; its S8R shells expanded into 20-node solids) on the
    same structure described to it directly."""
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fem"))
    from calculix import frequencies, frequency_inp, run

    from era.fem.mesh import FEMesh, ShellProperty

    cards, s = stiffened_panel(16, 12)
    path = tmp_path / "panel.bdf"
    path.write_text(deck_text(cards, "large"))
    model = read_bdf(path)
    assert set(model.parts) == {"PSHELL 1", "PSHELL 2"}
    f = model.modes(6)[0]
    mesh = FEMesh(s["nodes"], tuple(s["shells"]), (), {"plate": ShellProperty(*s["plate"]),
                                                       "web": ShellProperty(*s["web"])},
                  fixed=tuple((n, d) for n in s["clamped"] for d in ("x", "y", "z", "rx", "ry", "rz")))
    truth = frequencies(run(frequency_inp(mesh, 6), tmp_path / "ccx"))
    np.testing.assert_allclose(f, truth, rtol=0.015)


def test_pshell_12i_over_t3_scales_the_bending_stiffness(tmp_path):
    # a simply supported plate whose PSHELL says 12I/T³ = 2: D doubled, Kirchhoff's frequencies √2 higher than
    # the same mesh's with 12I/T³ = 1 (the transverse shear, not scaled, and the rotary inertia take 0.1 % off)
    a, b, t, e, nu, rho = 0.6, 0.4, 0.004, 7e10, 0.3, 2700.0
    f = []
    for ratio in (1.0, 2.0):
        cards = [c if c[0] != "PSHELL" else ("PSHELL", [1, 1, t, 1, ratio])
                 for c in plate_cards(24, 16, a, b, t, e, nu, rho)]
        path = tmp_path / f"plate{ratio}.bdf"
        path.write_text(deck_text(cards, "free"))
        f.append(read_bdf(path).modes(3)[0])
    assert f[1] / f[0] == pytest.approx(np.full(3, np.sqrt(2)), rel=2e-3)
    assert f[1] == pytest.approx(np.sqrt(2) * plate_frequencies(a, b, t, e, nu, rho, 3), rel=0.02)


def test_a_femap_deck_of_a_free_plate_against_calculix(tmp_path):
    """pyNastran's models/plate_py/plate_py.dat (BSD), written by Femap for NX Nastran: a free 2 × 1 in steel plate,
    1/8 in, 200 CQUAD4; cylindrical and spherical frames (read, unused) and a thermal material it never uses. Its rigid-body mass
    is ρ t A, six rigid modes come first, and the elastic ones match CalculiX's S8R on the same mesh."""
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fem"))
    from calculix import frequencies, frequency_inp, run

    from era.fem.mesh import FEMesh
    from era.models.nastran.mesh import deck_mesh

    m = read_bdf(DATA / "plate_py.dat")
    assert m.unmodelled == ("Not modelled: 8 cards of the deck, EIGRL (1), MAT4 (1), PARAM (6); it is left out "
                            "of the model (MAT4) and solution and output requests (EIGRL, PARAM) do not change the "
                            "modes.")
    assert m.total_mass() == pytest.approx(7.3315e-4 * 0.125 * 2.0 * 1.0, rel=1e-12)
    f, _ = m.modes(10)
    assert np.all(f[:6] < 1e-4 * f[6])
    dm = deck_mesh(m.deck)
    mesh = FEMesh(dm.mesh.nodes, dm.mesh.shells, (), dm.mesh.shell_properties)
    truth = frequencies(run(frequency_inp(mesh, 10), tmp_path / "ccx"))
    np.testing.assert_allclose(f[6:], truth[6:], rtol=0.015)
