"""RBE3 and MPC/MPCADD read from decks, against truths derived by hand: a mass hung on an RBE3 over four grids on
springs (the rigid-body kinematics of the weighted least-squares fit give its six frequencies in closed form), a
lever written as an MPC (one DOF: k₁ + a²k₂ over m₁ + a²m₂), the case control's MPC set through an MPCADD, and a
cantilever plate cut in two and tied again by MPCs equal to the whole plate; a mass hung by an RBE3 on a plate
against CalculiX's distributing coupling (ccx run as a separate program)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from nastran_decks import deck_text

from era.errors import DataError
from era.models.nastran import read_bdf

K, MASS = 1.0e4, 2.0
IXX, IYY, IZZ = 0.3, 0.5, 0.7


def _model(tmp_path, cards, name="d.bdf", header=""):
    path = tmp_path / name
    path.write_text(deck_text(cards, "free", header))
    return read_bdf(path)


def _hung_mass(ref_xyz, weights=(1.0, 1.0)) -> list:
    """Grids 1-4 at (±1, ±1, 0) on springs K to ground in x, y, z; grid 9 at ``ref_xyz`` with a CONM2 (MASS,
    IXX, IYY, IZZ) following them through an RBE3 (REFC 123456, C 123; grids 1, 2 weighted weights[0], 3, 4
    weights[1])."""
    corners = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]
    cards = [("GRID", [k + 1, None, x, y, 0.0]) for k, (x, y) in enumerate(corners)]
    cards += [("CELAS2", [10 * g + c, K, g, c]) for g in range(1, 5) for c in (1, 2, 3)]
    cards += [("GRID", [9, None, *ref_xyz]), ("CONM2", [1, 9, 0, MASS, 0., 0., 0., None, IXX, 0., IYY, 0., 0., IZZ]),
              ("RBE3", [7, None, 9, 123456, weights[0], 123, 1, 2, weights[1], 123, 3, 4])]
    return cards


def test_an_rbe3_over_four_springs_at_their_centre(tmp_path):
    # the reference at the centroid: a translation of every corner moves it alike (k = 4K on m), a turn about z
    # moves each corner √2 θ across (k = 4·2K on Izz), a turn about x lifts the corners ±θ (k = 4K on Ixx)
    m = _model(tmp_path, _hung_mass((0.0, 0.0, 0.0)))
    assert m.unmodelled == ""
    f, _ = m.modes(6)
    w = np.sqrt([4 * K / MASS] * 3 + [4 * K / IXX, 4 * K / IYY, 8 * K / IZZ])
    assert f == pytest.approx(np.sort(w) / (2 * np.pi), rel=1e-9)
    assert m.total_mass() == pytest.approx(MASS, rel=1e-12)


def test_an_rbe3_reference_above_the_grids(tmp_path):
    """The reference 0.4 above the centroid: a turn β about y moves it β·0.4 along x, so the x translation and
    the y turn share the mass [[m, m h], [m h, m h² + Iyy]] over the springs' 4K and K Σx² = 4K (equal weights:
    the corners' motions that do not move the reference are then orthogonal to the rigid ones in K too)."""
    h = 0.4
    m = _model(tmp_path, _hung_mass((0.0, 0.0, h), weights=(2.0, 2.0)))
    f, _ = m.modes(6)
    pair = scipy.linalg.eigh(np.diag([4 * K, 4 * K]), np.array([[MASS, MASS * h], [MASS * h, MASS * h ** 2 + IYY]]),
                             eigvals_only=True)
    pair_x = scipy.linalg.eigh(np.diag([4 * K, 4 * K]), np.array([[MASS, -MASS * h],
                                                                   [-MASS * h, MASS * h ** 2 + IXX]]),
                               eigvals_only=True)
    w2 = np.concatenate([pair, pair_x, [4 * K / MASS, 8 * K / IZZ]])
    assert f == pytest.approx(np.sort(np.sqrt(w2)) / (2 * np.pi), rel=1e-9)


def test_an_mpc_lever_and_the_case_control_s_set(tmp_path):
    # grid 2's x is twice grid 1's: 1·u2 − 2·u1 = 0, so one DOF with k1 + 4 k2 and m1 + 4 m2
    k1, k2, m1, m2 = 300.0, 50.0, 2.0, 0.5
    cards = [("GRID", [1, None, 0., 0., 0.]), ("GRID", [2, None, 1., 0., 0.]),
             ("CELAS2", [1, k1, 1, 1]), ("CELAS2", [2, k2, 2, 1]),
             ("CONM2", [3, 1, 0, m1]), ("CONM2", [4, 2, 0, m2]),
             ("SPC1", [1, 23456, 1, 2]),
             ("MPC", [5, 2, 1, 1.0, 1, 1, -2.0]), ("MPC", [6, 2, 1, 1.0, 1, 1, 3.0]),
             ("MPCADD", [8, 5])]
    lever = _model(tmp_path, cards, "a.bdf", "SOL 103\nCEND\nSPC = 1\nMPC = 8")
    assert lever.dofs == (("1", "x"),) and lever.unmodelled == ""
    assert lever.modes(1)[0] == pytest.approx([np.sqrt((k1 + 4 * k2) / (m1 + 4 * m2)) / (2 * np.pi)], rel=1e-12)
    other = _model(tmp_path, cards, "b.bdf", "SOL 103\nCEND\nSPC = 1\nMPC = 6")      # u2 = −3 u1
    assert other.modes(1)[0] == pytest.approx([np.sqrt((k1 + 9 * k2) / (m1 + 9 * m2)) / (2 * np.pi)], rel=1e-12)
    with pytest.raises(DataError, match="dependent DOF of two constraints"):
        _model(tmp_path, cards, "c.bdf", "SOL 103\nCEND\nSPC = 1")                  # both sets: grid 2 twice


def test_a_plate_cut_in_two_and_tied_by_mpcs_is_the_whole_plate(tmp_path):
    nx, ny, a, b = 8, 4, 0.4, 0.2
    def cards(cut: bool) -> list:
        out, gid = [], {}
        for j in range(ny + 1):
            for i in range(nx + 1):
                gid[i, j] = 1 + i + j * (nx + 1)
                out.append(("GRID", [gid[i, j], None, a * i / nx, b * j / ny, 0., None, 123456 if i == 0 else None]))
                if cut and i == nx // 2:
                    gid[i, j, "right"] = 1000 + j
                    out.append(("GRID", [1000 + j, None, a * i / nx, b * j / ny, 0.]))
                    out += [("MPC", [1, 1000 + j, c, 1.0, gid[i, j], c, -1.0]) for c in range(1, 7)]
        for j in range(ny):
            for i in range(nx):
                left = [gid[i, j], gid[i, j + 1]]
                right = [gid.get((i + 1, j, "right"), gid[i + 1, j]), gid.get((i + 1, j + 1, "right"),
                                                                               gid[i + 1, j + 1])]
                if cut and i == nx // 2:
                    left = [gid[i, j, "right"], gid[i, j + 1, "right"]]
                    right = [gid[i + 1, j], gid[i + 1, j + 1]]
                out.append(("CQUAD4", [1 + i + nx * j, 1, left[0], right[0], right[1], left[1]]))
        return out + [("PSHELL", [1, 1, 0.003, 1]), ("MAT1", [1, 7e10, None, 0.33, 2700.])]
    whole = _model(tmp_path, cards(False), "whole.bdf").modes(6)[0]
    tied = _model(tmp_path, cards(True), "tied.bdf")
    assert "1000" in tied.coordinates
    assert tied.modes(6)[0] == pytest.approx(whole, rel=1e-9)


def test_rbe3_errors_name_the_card(tmp_path):
    line = [("GRID", [k + 1, None, float(k), 0., 0.]) for k in range(3)] + [("GRID", [9, None, 1.5, 0., 0.])]
    line += [("CELAS2", [10 + k, K, k + 1, 3]) for k in range(3)] + [("CONM2", [1, 9, 0, 1.])]
    with pytest.raises(DataError, match=r"RBE3 7: its independent grids' components do not determine component 4"):
        _model(tmp_path, line + [("RBE3", [7, None, 9, 1234, 1.0, 123, 1, 2, 3])], "a.bdf")
    with pytest.raises(DataError, match="RBE3 7: the UM fields"):
        _model(tmp_path, line + [("RBE3", [7, None, 9, 123, 1.0, 123, 1, 2, 3, "UM", 1, 1])], "b.bdf")


def test_a_mass_hung_by_an_rbe3_on_a_plate_s_tip_against_calculix(tmp_path):
    """A 5 kg CONM2 at the middle of a cantilever plate's free edge, carried by an RBE3 (REFC 123) over the edge's
    nine grids, against CalculiX's distributing coupling (DCOUP3D, equal weights) with a MASS element: the mass
    lowers the first mode to the same fraction of the bare plate's (ccx run as a separate program). The reference
    is at the grids' centroid, where ccx's weighted mean of their translations and RBE3's least-squares rigid fit
    coincide; off the centroid they differ (tried with unequal weights: ccx's mass moved in the plate's torsion,
    8 % lower, where the rigid fit keeps it still, as Nastran's RBE3 moment-distribution does)."""
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fem"))
    from calculix import frequencies, frequency_inp, node_ids, run

    from era.fem.mesh import FEMesh, ShellProperty

    nx, ny, a, b, t = 12, 8, 0.3, 0.2, 0.003
    e, nu, rho = 7e10, 0.33, 2700.0
    cards, nodes, shells, gid = [], {}, [], {}
    for j in range(ny + 1):
        for i in range(nx + 1):
            gid[i, j] = 1 + i + j * (nx + 1)
            nodes[str(gid[i, j])] = (a * i / nx, b * j / ny, 0.0)
            cards.append(("GRID", [gid[i, j], None, a * i / nx, b * j / ny, 0.0, None, 123456 if i == 0 else None]))
    for j in range(ny):
        for i in range(nx):
            c = [gid[i, j], gid[i + 1, j], gid[i + 1, j + 1], gid[i, j + 1]]
            cards.append(("CQUAD4", [len(shells) + 1, 1, *c]))
            shells.append(("plate", tuple(map(str, c))))
    tip = [gid[nx, j] for j in range(ny + 1)]
    nodes["999"] = (a, b / 2, 0.0)
    plate = [("PSHELL", [1, 1, t, 1]), ("MAT1", [1, e, None, nu, rho])]
    clamp = tuple((n, d) for n, x in nodes.items() if x[0] == 0 for d in ("x", "y", "z", "rx", "ry", "rz"))
    f, truth = {}, {}
    for mass in (0.0, 5.0):
        hung = [("GRID", [999, None, a, b / 2, 0.0]), ("CONM2", [1, 999, 0, mass]),
                ("RBE3", [5, None, 999, 123, 1.0, 123, *tip])] if mass else []
        f[mass] = _model(tmp_path, cards + hung + plate, f"plate{mass}.bdf").modes(4)[0]
        mesh = FEMesh(nodes if mass else {n: x for n, x in nodes.items() if n != "999"}, tuple(shells), (),
                      {"plate": ShellProperty(t, e, nu, rho)}, masses=(("999", mass, (0, 0, 0)),) if mass else (),
                      fixed=clamp)
        inp = frequency_inp(mesh, 4)
        if mass:
            ids = node_ids(mesh)
            coupling = ["*ELEMENT, TYPE=DCOUP3D, ELSET=COUP", f"90001, {ids['999']}",
                        "*DISTRIBUTING COUPLING, ELSET=COUP"] + [f"{ids[str(g)]}, 1." for g in tip]
            inp = inp.replace("*STEP", "\n".join(coupling) + "\n*STEP", 1)
        truth[mass] = frequencies(run(inp, tmp_path / f"ccx{mass}"))
    # 12 × 8 linear quads against ccx's quadratic S8R: the bare plate's first mode 1 % apart, the rest within 1 %
    assert f[5.0] == pytest.approx(truth[5.0], rel=0.012)
    assert f[5.0][0] / f[0.0][0] == pytest.approx(truth[5.0][0] / truth[0.0][0], rel=5e-3)
