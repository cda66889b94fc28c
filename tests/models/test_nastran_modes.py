"""Decks solved against truths from elsewhere: a cantilever with a tip mass (pyNastran's beam_modes deck, BSD)
against Euler-Bernoulli's frequency equation and against MSC Nastran's own f06 of that deck; a simply supported
plate of CQUAD4 and of CTRIA3 against Kirchhoff's formula; one deck of every card written in small, large and free
field gives one model."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from nastran_decks import cantilever_tip_mass, deck_text, plate_cards, plate_frequencies

from era.models import load_model
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


def every_card() -> list:
    """A small structure with every modelled card: a plate of CQUAD4 and CTRIA3 in a CORD2R frame, a CBAR
    stiffener (PBARL I, offset below the plate), a CBEAM (PBEAM) and a CROD (PROD) leg, a CONM2 with offset and
    inertia, springs (CELAS1/PELAS, CELAS2), an RBE2 spider, SPC and SPC1 of the case control's set 1."""
    cards = [("CORD2R", [3, 0, 0., 0., 1., 0., 0., 2., 1., 0., 1.])]          # shifted up 1, axes as basic
    gid = {}
    for j in range(3):
        for i in range(4):
            gid[i, j] = 100 + 10 * j + i
            cards.append(("GRID", [gid[i, j], 3, 0.25 * i, 0.25 * j, 0.]))
    eid = 1
    for j in range(2):
        for i in range(3):
            c = [gid[i, j], gid[i + 1, j], gid[i + 1, j + 1], gid[i, j + 1]]
            if (i + j) % 2:
                cards += [("CTRIA3", [eid, 1, c[0], c[1], c[2]]), ("CTRIA3", [eid + 1, 1, c[0], c[2], c[3]])]
                eid += 2
            else:
                cards.append(("CQUAD4", [eid, 1, *c]))
                eid += 1
    cards += [("PSHELL", [1, 1, 0.005, 1]), ("MAT1", [1, 7e10, None, 0.33, 2700.]),
              ("MAT1", [2, 2.1e11, 8.1e10, None, 7850.])]
    for i in range(3):
        cards.append(("CBAR", [30 + i, 2, gid[i, 1], gid[i + 1, 1], 0., 0., 1., None, None, None,
                               0., 0., -0.02, 0., 0., -0.02]))
    cards.append(("PBARL", [2, 2, None, "I", None, None, None, None, .03, .02, .02, .002, .003, .003]))
    cards += [("GRID", [1, None, 0., 0., 0.]), ("GRID", [2, None, 0.75, 0., 0.]),
              ("CBEAM", [40, 4, 1, gid[0, 0], 1., 0., 0.]), ("PBEAM", [4, 2, 1e-4, 1e-9, 2e-9, 0., 3e-9]),
              ("CROD", [41, 5, 2, gid[3, 0]]), ("PROD", [5, 2, 5e-5, 1e-9])]
    cards += [("CONM2", [50, gid[3, 2], 0, 0.4, 0.01, 0.02, 0.05, None, 1e-4, 0., 2e-4, 0., 0., 3e-4]),
              ("CELAS1", [51, 6, gid[0, 2], 3]), ("PELAS", [6, 2e4]), ("CELAS2", [52, 5e3, gid[3, 1], 3]),
              ("GRID", [3, None, 0.375, 0.25, 1.2]), ("RBE2", [60, 3, 123456, gid[1, 1], gid[2, 1], gid[1, 2]]),
              ("CONM2", [61, 3, 0, 0.2]),
              ("SPC", [1, 1, 123456, 0., 2, 123, 0.]), ("SPC1", [1, 6, 100, "THRU", 103]),
              ("SPC1", [2, 3, 110])]
    return cards


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
