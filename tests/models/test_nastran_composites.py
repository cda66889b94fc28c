"""PCOMP laminates (MAT8 and MAT1 plies, LAM blank and SYM, Z0) read from decks: a simply supported cross-ply
plate against the Navier solution of classical lamination theory, cantilevers of an antisymmetric angle-ply and of
a cross-ply laid on one side of its grids against CalculiX's composite shells (ccx run as a separate program), and
a one-ply PCOMP of a MAT1 equal to the PSHELL."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from nastran_decks import deck_text, plate_cards

from era.errors import DataError
from era.models.nastran import read_bdf

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fem"))
from calculix import frequencies, frequency_inp, run  # noqa: E402

# a graphite-epoxy ply (Reddy, Mechanics of Laminated Composite Plates and Shells, table 1.3-1, material 1)
E1, E2, NU12, G12, G13, G23, RHO = 138e9, 8.96e9, 0.3, 7.1e9, 7.1e9, 3.45e9, 1600.0
MAT8 = ("MAT8", [8, E1, E2, NU12, G12, G13, G23, RHO])


def _model(tmp_path, cards, name="d.bdf", style="free"):
    path = tmp_path / name
    path.write_text(deck_text(cards, style))
    return read_bdf(path)


def _pcomp(pid, plies, z0=None, lam=None, nsm=None):
    fields = [pid, z0, nsm, None, None, None, None, lam]
    for mid, t, theta in plies:
        fields += [mid, t, theta, None]
    return ("PCOMP", fields)


def _with_property(cards, prop):
    return [c for c in cards if c[0] not in ("PSHELL", "MAT1")] + prop


def test_a_simply_supported_cross_ply_against_navier(tmp_path):
    """[0/90]s (LAM = SYM, four plies of t/4): D16 = D26 = 0 and B = 0, so the Navier series is exact in
    Kirchhoff's theory: ω² = π⁴ (D11 (m/a)⁴ + 2 (D12 + 2 D66) (m/a)² (n/b)² + D22 (n/b)⁴) / (ρ h) (Reddy, eq.
    5.3.14; Whitney, Structural Analysis of Laminated Anisotropic Plates, 1987)."""
    a, b, h = 0.6, 0.4, 0.003
    cards = _with_property(plate_cards(36, 24, a, b, h, 1.0, 0.3, 1.0),
                           [_pcomp(1, [(8, h / 4, 0.0), (8, h / 4, 90.0)], lam="SYM"), MAT8])
    m = _model(tmp_path, cards)
    assert set(m.parts) == {"PCOMP 1"} and m.unmodelled == ""
    same_mass = _model(tmp_path, plate_cards(36, 24, a, b, h, 1.0, 0.3, RHO), "shell.bdf")
    assert abs(m.mass - same_mass.mass).max() <= 1e-12 * abs(m.mass).max()     # one density through h
    d = 1 - NU12 ** 2 * E2 / E1
    q11, q22, q12, q66 = E1 / d, E2 / d, NU12 * E2 / d, G12
    # the outer 0° plies hold 7/8 of h³/12, the inner 90° plies 1/8
    d11, d22 = h ** 3 / 12 * (7 / 8 * q11 + q22 / 8), h ** 3 / 12 * (q11 / 8 + 7 / 8 * q22)
    d12, d66 = h ** 3 / 12 * q12, h ** 3 / 12 * q66
    truth = sorted(np.pi ** 2 * np.sqrt((d11 * (i / a) ** 4 + 2 * (d12 + 2 * d66) * (i / a) ** 2 * (j / b) ** 2
                                         + d22 * (j / b) ** 4) / (RHO * h)) / (2 * np.pi)
                   for i in range(1, 6) for j in range(1, 6))[:4]
    f, _ = m.modes(4)
    assert f == pytest.approx(truth, rel=0.01)


def _cantilever_cards(nx, ny, a, b, prop) -> tuple[list, dict, tuple]:
    """A plate a × b of nx × ny CQUAD4 (property 1) clamped at x = 0, and its grids and quads for ccx."""
    cards, nodes, gid = [], {}, {}
    for j in range(ny + 1):
        for i in range(nx + 1):
            gid[i, j] = 1 + i + j * (nx + 1)
            nodes[str(gid[i, j])] = (a * i / nx, b * j / ny, 0.0)
            cards.append(("GRID", [gid[i, j], None, a * i / nx, b * j / ny, 0.0, None,
                                   123456 if i == 0 else None]))
    quads = []
    for j in range(ny):
        for i in range(nx):
            c = [gid[i, j], gid[i + 1, j], gid[i + 1, j + 1], gid[i, j + 1]]
            cards.append(("CQUAD4", [len(quads) + 1, 1, *c]))
            quads.append(("lam", tuple(map(str, c))))
    return cards + prop, nodes, tuple(quads)


@pytest.mark.parametrize("angles, z0, offset", [((30.0, -30.0), None, None), ((0.0, 90.0), 0.0, -0.5)])
def test_laminated_cantilevers_against_calculix(tmp_path, angles, z0, offset):
    """An antisymmetric angle-ply [30/−30] (B16, B26, D16, D26 ≠ 0), and an unsymmetric cross-ply [0/90] laid
    above its grids (PCOMP Z0 = 0: B = z A, the mass's first moment), both against ccx's S8R composite sections
    (expanded into layered 20-node solids; the second with OFFSET = −0.5, the grids on its bottom surface)."""
    from era.fem.mesh import FEMesh, ShellProperty

    t = 0.001
    a, b = 0.3, 0.15
    cards, nodes, quads = _cantilever_cards(16, 8, a, b, [_pcomp(1, [(8, t, ang) for ang in angles], z0), MAT8])
    m = _model(tmp_path, cards, style="large")
    f, _ = m.modes(6)
    mesh = FEMesh(nodes, quads, (), {"lam": ShellProperty(2 * t, 1.0, 0.3, 1.0)},
                  fixed=tuple((n, d) for n, x in nodes.items() if x[0] == 0 for d in ("x", "y", "z", "rx", "ry", "rz")))
    layers = {"lam": [(t, E1, E2, NU12, G12, G13, G23, RHO, ang) for ang in angles]}
    truth = frequencies(run(frequency_inp(mesh, 6, layers=layers, offsets={"lam": offset} if offset else None),
                            tmp_path / "ccx"))
    assert f[:4] == pytest.approx(truth[:4], rel=0.015)
    assert f[4:] == pytest.approx(truth[4:], rel=0.03)      # 16 × 8 linear quads against ccx's quadratic ones


def test_one_mat1_ply_is_the_pshell(tmp_path):
    """A PCOMP of one MAT1 ply (and LAM = SYM of two half plies, NSM alike) gives the PSHELL's matrices."""
    a, b, t = 0.6, 0.4, 0.004
    shell = _model(tmp_path, plate_cards(6, 4, a, b, t, 7e10, 0.3, 2700.0), "shell.bdf")
    for k, prop in enumerate(([_pcomp(1, [(1, t, 0.0)])], [_pcomp(1, [(1, t / 2, 0.0)], lam="SYM")])):
        cards = _with_property(plate_cards(6, 4, a, b, t, 7e10, 0.3, 2700.0), prop + [("MAT1", [1, 7e10, None,
                                                                                                  0.3, 2700.0])])
        m = _model(tmp_path, cards, f"comp{k}.bdf")
        assert m.dofs == shell.dofs
        assert abs(m.stiffness - shell.stiffness).max() <= 1e-12 * abs(shell.stiffness).max()
        assert abs(m.mass - shell.mass).max() <= 1e-12 * abs(shell.mass).max()


def test_composite_errors_name_the_card(tmp_path):
    plate = plate_cards(2, 2, 1.0, 1.0, 0.01, 7e10, 0.3, 2700.0)
    with pytest.raises(DataError, match=r"PCOMP 1: LAM 'MEM' is not read"):
        _model(tmp_path, _with_property(plate, [_pcomp(1, [(8, .01, 0.)], lam="MEM"), MAT8]), "a.bdf")
    with pytest.raises(DataError, match=r"PCOMP 1: material \(MAT1 or MAT8\) 9 is not in the deck"):
        _model(tmp_path, _with_property(plate, [_pcomp(1, [(9, .01, 0.)]), MAT8]), "b.bdf")
    turned = [("CQUAD4", c[1][:6] + [30.0]) if c[0] == "CQUAD4" else c for c in plate]
    with pytest.raises(DataError, match=r"CQUAD4 1: a material angle THETA"):
        _model(tmp_path, _with_property(turned, [_pcomp(1, [(8, .01, 0.)]), MAT8]), "c.bdf")
