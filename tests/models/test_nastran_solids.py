"""CHEXA, CPENTA and CTETRA (PSOLID, MAT1) read from decks: a block cantilever meshed in each against CalculiX's
C3D8I, C3D6 and C3D4 on the same mesh (ccx run as a separate program: modes, and a tip load's deflection), and the
block's rigid-body inertia, exact for every element's consistent mass."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse.linalg
from nastran_decks import deck_text

from era.errors import DataError
from era.models.nastran import read_bdf

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fem"))
from calculix import displacements, frequencies, run  # noqa: E402

E, NU, RHO = 2.1e11, 0.3, 7850.0
L, B, H = 0.2, 0.03, 0.04
NX, NY, NZ = 10, 2, 2


def _block(kind: str) -> tuple[dict, list]:
    """The cantilever's grids {id: xyz} and elements (grids per element) in hexahedra, wedges (each hexahedron
    cut along a diagonal of its x-y faces) or tetrahedra (six per hexahedron around its main diagonal)."""
    gid = {(i, j, k): 1 + i + (NX + 1) * (j + (NY + 1) * k)
           for k in range(NZ + 1) for j in range(NY + 1) for i in range(NX + 1)}
    grids = {g: (L * i / NX, B * j / NY, H * k / NZ) for (i, j, k), g in gid.items()}
    elements = []
    for k in range(NZ):
        for j in range(NY):
            for i in range(NX):
                c = [gid[i, j, k], gid[i + 1, j, k], gid[i + 1, j + 1, k], gid[i, j + 1, k],
                     gid[i, j, k + 1], gid[i + 1, j, k + 1], gid[i + 1, j + 1, k + 1], gid[i, j + 1, k + 1]]
                if kind == "CHEXA":
                    elements.append(c)
                elif kind == "CPENTA":
                    elements += [[c[0], c[1], c[2], c[4], c[5], c[6]], [c[0], c[2], c[3], c[4], c[6], c[7]]]
                else:
                    for a, b in ((1, 2), (2, 3), (3, 7), (7, 4), (4, 5), (5, 1)):
                        tet = [c[0], c[a], c[b], c[6]]
                        x = np.array([grids[g] for g in tet])
                        if np.linalg.det(x[1:] - x[0]) < 0:      # ccx wants G4 on the side G1-G2-G3 turns to
                            tet[1], tet[2] = tet[2], tet[1]
                        elements.append(tet)
    return grids, elements


def _deck(kind: str) -> list:
    grids, elements = _block(kind)
    cards = [("GRID", [g, None, *x, None, 123456 if x[0] == 0 else None]) for g, x in grids.items()]
    cards += [(kind, [e + 1, 1, *c]) for e, c in enumerate(elements)]
    return cards + [("PSOLID", [1, 1]), ("MAT1", [1, E, None, NU, RHO])]


def _ccx(kind: str, folder: Path, step: list, element: str | None = None) -> str:
    """ccx's .dat text of the block meshed in ``kind``, as ccx ``element`` (its linear counterpart by default),
    clamped at x = 0, with the ``step``'s cards."""
    grids, elements = _block(kind)
    ccx_type = element or {"CHEXA": "C3D8I", "CPENTA": "C3D6", "CTETRA": "C3D4"}[kind]
    lines = ["*NODE, NSET=NALL"] + [f"{g}, {x!r}, {y!r}, {z!r}" for g, (x, y, z) in grids.items()]
    lines += [f"*ELEMENT, TYPE={ccx_type}, ELSET=EALL"] + [f"{e + 1}, " + ", ".join(map(str, c))
                                                         for e, c in enumerate(elements)]
    lines += ["*NSET, NSET=FIX"] + [str(g) for g, x in grids.items() if x[0] == 0]
    lines += ["*NSET, NSET=TIP"] + [str(g) for g, x in grids.items() if x[0] == L]
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{E!r}, {NU!r}", "*DENSITY", f"{RHO!r}",
              "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL", "*BOUNDARY", "FIX, 1, 3", "*STEP", *step, "*END STEP"]
    return run("\n".join(lines) + "\n", folder)


def _read(tmp_path, kind):
    path = tmp_path / f"{kind}.bdf"
    path.write_text(deck_text(_deck(kind), "large"))
    return read_bdf(path)


@pytest.mark.parametrize("kind", ["CHEXA", "CPENTA", "CTETRA"])
def test_the_block_s_rigid_body_inertia_is_exact(tmp_path, kind):
    """A linear field is in every element's shapes and the consistent mass integrates its square exactly: the
    block read without its clamp moves its whole mass with a translation, and a rigid turn about the x axis
    through its corner gives ρ∫(y² + z²)dV = m (B² + H²)/3."""
    cards = [c if c[0] != "GRID" else ("GRID", c[1][:5]) for c in _deck(kind)]
    path = tmp_path / "free.bdf"
    path.write_text(deck_text(cards, "free"))
    m = read_bdf(path)
    assert m.total_mass() == pytest.approx(RHO * L * B * H, rel=1e-12)
    turn = np.array([-m.coordinates[n][2] if d == "y" else m.coordinates[n][1] if d == "z" else 0.0
                     for n, d in m.dofs])
    assert turn @ (m.mass @ turn) == pytest.approx(RHO * L * B * H * (B ** 2 + H ** 2) / 3, rel=1e-12)


def test_hexahedra_against_calculix_c3d8i(tmp_path):
    m = _read(tmp_path, "CHEXA")
    assert set(m.parts) == {"PSOLID 1"} and m.unmodelled == ""
    assert {d for _, d in m.dofs} == {"x", "y", "z"}              # AUTOSPC holds the solids' grids' rotations
    f, _ = m.modes(6)
    truth = frequencies(_ccx("CHEXA", tmp_path / "ccx", ["*FREQUENCY", "6"]))
    # the two bending modes as ccx's C3D8I; torsion and the higher modes within 1.5 % (ccx's incompatible modes
    # are not quite Wilson's nine)
    assert f[:2] == pytest.approx(truth[:2], rel=1e-3)
    assert f == pytest.approx(truth, rel=0.015)


def test_tetrahedra_bend_as_calculix_c3d4_under_a_tip_load(tmp_path):
    """Constant-strain tetrahedra are one element everywhere: the tip's deflection under 1 kN along z, spread on
    the tip's grids, is ccx's C3D4's to its printed digits."""
    m = _read(tmp_path, "CTETRA")
    tip = [str(g) for g, x in _block("CTETRA")[0].items() if x[0] == L]
    load = np.zeros(m.n_dofs)
    load[[m.index(n, "z") for n in tip]] = 1000.0 / len(tip)
    u = scipy.sparse.linalg.spsolve(m.stiffness.tocsc(), load)
    dat = _ccx("CTETRA", tmp_path / "ccx", ["*STATIC", "*CLOAD"] + [f"{n}, 3, {1000.0 / len(tip)!r}" for n in tip]
               + ["*NODE PRINT, NSET=TIP", "U"])
    truth = displacements(dat, [(int(n), "z") for n in tip])[:, 0]
    assert u[[m.index(n, "z") for n in tip]] == pytest.approx(truth, rel=1e-5)


@pytest.mark.parametrize("kind, element, tol", [("CPENTA", "C3D6", 0.035), ("CTETRA", "C3D4", 0.04)])
def test_wedges_and_tetrahedra_against_calculix(tmp_path, kind, element, tol):
    """Their modes near ccx's on the same mesh: its C3D6 bends 3 % softer (its own integration of the wedge); its
    C3D4 has the same stiffness (the tip load above) but not the exact consistent mass used here (whose rigid-body
    inertia is exact, above): ccx's torsion comes 4 % higher."""
    f, _ = _read(tmp_path, kind).modes(6)
    truth = frequencies(_ccx(kind, tmp_path / "ccx", ["*FREQUENCY", "6"], element))
    assert f == pytest.approx(truth, rel=tol)


def test_solid_errors_name_the_card(tmp_path):
    cards = _deck("CTETRA")
    with pytest.raises(DataError, match=r"CTETRA 1: mid-side grids"):
        path = tmp_path / "mid.bdf"
        path.write_text(deck_text([c if (c[0], c[1][0]) != ("CTETRA", 1) else ("CTETRA", c[1] + [5, 6])
                                   for c in cards], "free"))
        read_bdf(path)
    with pytest.raises(DataError, match=r"CTETRA 1: PSOLID 1 is not in the deck"):
        path = tmp_path / "nop.bdf"
        path.write_text(deck_text([c for c in cards if c[0] != "PSOLID"], "free"))
        read_bdf(path)


def test_a_psolid_part_stiffer_and_lighter_is_patched_as_a_new_mat1(tmp_path):
    from era.models.nastran import deck_patch_for, write_patched_deck

    nominal = _read(tmp_path, "CTETRA")
    params = {"part_at": "part:PSOLID 1", "part_factor": 1.25, "part_mass_at": "part:PSOLID 1",
              "part_mass_factor": 0.8}
    patch = deck_patch_for(nominal.deck, params)
    got = read_bdf(write_patched_deck(nominal.deck, patch, tmp_path / "patched"))
    assert abs(got.stiffness - 1.25 * nominal.stiffness).max() <= 1e-9 * abs(nominal.stiffness).max()
    assert abs(got.mass - 0.8 * nominal.mass).max() <= 1e-9 * abs(nominal.mass).max()
