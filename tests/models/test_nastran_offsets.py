"""ZOFFS on CQUAD4/CTRIA3 (a shell's mid-surface offset from its grids along its normal) read from decks: a
T-stiffened cantilever panel whose plate lies on top of the web's edge (ZOFFS = t/2, and the same plate as a PCOMP
with Z0 = 0) against CalculiX's shells with OFFSET (ccx run as a separate program); a flat plate offset as a whole
and clamped at its grids is the plate without offset (the offset is a rigid link from a held grid)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from nastran_decks import deck_text

from era.errors import DataError
from era.models.nastran import read_bdf

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fem"))
from calculix import frequencies, frequency_inp, run  # noqa: E402

E, NU, RHO = 7e10, 0.33, 2700.0
A, B, HW = 0.4, 0.3, 0.03          # plate a × b, web depth
NX, NY, NW = 16, 12, 3
TP, TW = 0.006, 0.004


def _model(tmp_path, cards, name):
    path = tmp_path / name
    path.write_text(deck_text(cards, "small"))
    return read_bdf(path)


def _panel(plate_offset: float, composite: bool = False) -> tuple[list, dict, list]:
    """The panel's cards (plate PSHELL 1 or PCOMP 1 with ZOFFS ``plate_offset``, web PSHELL 2 below the plate's
    middle line y = b/2, the x = 0 edge clamped), its nodes {grid: xyz} and shells [(property, grids)] for ccx."""
    cards, nodes, shells, gid = [], {}, [], {}

    def grid(key, xyz):
        gid[key] = len(gid) + 1
        nodes[str(gid[key])] = xyz
        cards.append(("GRID", [gid[key], None, *xyz, None, 123456 if xyz[0] == 0 else None]))

    for j in range(NY + 1):
        for i in range(NX + 1):
            grid(("p", i, j), (A * i / NX, B * j / NY, 0.0))
    for k in range(1, NW + 1):
        for i in range(NX + 1):
            grid(("w", i, k), (A * i / NX, B / 2, -HW * k / NW))
    web = lambda i, k: gid["p", i, NY // 2] if k == 0 else gid["w", i, k]     # noqa: E731
    for j in range(NY):
        for i in range(NX):
            c = [gid["p", i, j], gid["p", i + 1, j], gid["p", i + 1, j + 1], gid["p", i, j + 1]]
            cards.append(("CQUAD4", [len(shells) + 1, 1, *c, None, plate_offset]))
            shells.append(("plate", tuple(map(str, c))))
    for k in range(NW):
        for i in range(NX):
            c = [web(i, k), web(i + 1, k), web(i + 1, k + 1), web(i, k + 1)]
            cards.append(("CQUAD4", [len(shells) + 1, 2, *c]))
            shells.append(("web", tuple(map(str, c))))
    plate = ("PCOMP", [1, 0.0, None, None, None, None, None, None, 1, TP, 0.0]) if composite else \
        ("PSHELL", [1, 1, TP, 1])
    cards += [plate, ("PSHELL", [2, 1, TW, 1]), ("MAT1", [1, E, None, NU, RHO])]
    return cards, nodes, shells


def test_a_t_stiffened_panel_with_its_plate_offset_against_calculix(tmp_path):
    from era.fem.mesh import FEMesh, ShellProperty

    _, nodes, shells = _panel(TP / 2)
    props = {"plate": ShellProperty(TP, E, NU, RHO), "web": ShellProperty(TW, E, NU, RHO)}
    mesh = FEMesh(nodes, tuple(shells), (), props,
                  fixed=tuple((n, d) for n, x in nodes.items() if x[0] == 0 for d in ("x", "y", "z", "rx", "ry", "rz")))
    # ccx's OFFSET = −0.5: the grids on the plate's bottom surface, the plate above them (Nastran's ZOFFS = t/2)
    truth = frequencies(run(frequency_inp(mesh, 6, offsets={"plate": -0.5}), tmp_path / "ccx"))
    f = {}
    for key, offset, composite in (("zoffs", TP / 2, False), ("z0", 0.0, True), ("below", -TP / 2, False)):
        f[key] = _model(tmp_path, _panel(offset, composite)[0], f"{key}.bdf").modes(6)[0]
    assert f["zoffs"][:5] == pytest.approx(truth[:5], rel=0.01)
    assert f["zoffs"][5] == pytest.approx(truth[5], rel=0.025)        # 16 × 12 linear quads: its torsion-bending
    # PCOMP Z0 = 0 lays the plate the same way, through B = z̄ A instead of a rigid link (only the drilling
    # penalty and the drilling rotation's small inertia see the two differently)
    assert f["z0"] == pytest.approx(f["zoffs"], rel=1e-4)
    # the plate sunk into the web instead (ZOFFS = −t/2): the T is shallower, its first bending mode 20 % lower
    assert f["below"][0] < 0.85 * truth[0]


@pytest.mark.parametrize("kind", ["CQUAD4", "CTRIA3"])
def test_a_plate_offset_as_a_whole_and_clamped_at_its_grids_is_the_plate(tmp_path, kind):
    cards = []
    for j in range(5):
        for i in range(9):
            cards.append(("GRID", [1 + i + 9 * j, None, 0.05 * i, 0.05 * j, 0.0, None, 123456 if i == 0 else None]))
    elements = []
    for j in range(4):
        for i in range(8):
            c = [1 + i + 9 * j, 2 + i + 9 * j, 11 + i + 9 * j, 10 + i + 9 * j]
            elements += [c] if kind == "CQUAD4" else [[c[0], c[1], c[2]], [c[0], c[2], c[3]]]
    f = []
    for offset in (0.0, 0.02):
        shells = [(kind, [k + 1, 1, *c, None, offset]) for k, c in enumerate(elements)]
        m = _model(tmp_path, cards + shells + [("PSHELL", [1, 1, 0.004, 1]), ("MAT1", [1, E, None, NU, RHO])],
                   f"{kind}{offset}.bdf")
        f.append(m.modes(6)[0])
    assert f[1] == pytest.approx(f[0], rel=1e-9)


def test_corner_thicknesses_are_refused(tmp_path):
    cards = [("GRID", [k + 1, None, float(k % 2), float(k // 2), 0.]) for k in range(4)]
    cards += [("CQUAD4", [1, 1, 1, 2, 4, 3, None, None, None, None, 0.01, 0.01, 0.01, 0.01]),
              ("PSHELL", [1, 1, 0.01, 1]), ("MAT1", [1, E, None, NU, RHO])]
    with pytest.raises(DataError, match="CQUAD4 1: corner thicknesses"):
        _model(tmp_path, cards, "t.bdf")
