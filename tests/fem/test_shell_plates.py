"""Plate frequencies of era.fem's flat shells against closed-form and tabulated truths, quads and triangles.

Simply supported: Navier's exact Kirchhoff solution. Cantilever and free square plates: A. W. Leissa, *The free
vibration of rectangular plates*, J. Sound Vib. 31 (1973) 257-293 (Ritz, 36 beam-function terms, ν = 0.3), the
values also tabulated after M. V. Barton (J. Appl. Mech. 18, 1951) in code_aster's benchmark SDLS01. Leissa's
Ritz values are upper bounds: a converged mesh lies up to ~0.6 % (cantilever) and ~0.9 % (free) below them.
The thickness (5 mm on 1 m, a/t = 200) makes shear deformation and rotary inertia negligible (< 0.01 %).
"""

import numpy as np
import pytest

from era.fem import FEMesh, assemble, sparse_modes

from era.fem import ShellProperty

from plates import STEEL, cantilever, grid, leissa_hz, mindlin_hz, navier_hz, simply_supported

CANTILEVER = [3.492, 8.525, 21.43, 27.33, 31.11, 54.44]     # λ = ω a² √(ρt/D), clamped on one side
FREE = [13.49, 19.79, 24.43, 35.02, 35.02, 61.53]           # free on all sides, after the six rigid-body modes


def modes(mesh, n):
    m = assemble(mesh)
    return sparse_modes(m.stiffness, m.mass, n)[0]


@pytest.mark.parametrize("triangles", [False, True])
def test_simply_supported_plate_converges_to_navier(triangles):
    a, b = 1.0, 0.7
    exact = navier_hz(a, b, STEEL, 6)
    errors = [np.abs(modes(simply_supported(n, n, a, b, triangles=triangles), 6) / exact - 1) for n in (8, 16, 32)]
    assert np.all(errors[1] < errors[0]) and np.all(errors[2] < errors[1])
    # second-order convergence: halving the element size cuts the error about four-fold
    assert np.all(errors[2] < errors[1] / 3) and np.all(errors[1] < errors[0] / 2.5)
    assert errors[2].max() < (0.0085 if not triangles else 0.015)


@pytest.mark.parametrize("triangles, n", [(False, 32), (True, 48)])
def test_simply_supported_plate_within_one_percent_on_a_fine_mesh(triangles, n):
    f = modes(simply_supported(n, n, 1.0, 0.7, triangles=triangles), 6)
    np.testing.assert_allclose(f, navier_hz(1.0, 0.7, STEEL, 6), rtol=0.01)


@pytest.mark.parametrize("triangles, n", [(False, 32), (True, 48)])
def test_thick_plate_converges_to_mindlin_not_kirchhoff(triangles, n):
    """a/t = 10: shear deformation and rotary inertia lower the modes 5-26 % below Kirchhoff's; the same elements
    (no switch, no locking) converge to Mindlin's exact solution."""
    thick = ShellProperty(thickness=0.1, e=2.1e11, nu=0.3, rho=7850.0)
    exact = mindlin_hz(1.0, 0.7, thick, 6)
    assert np.all(navier_hz(1.0, 0.7, thick, 6) > 1.05 * exact)
    coarse, fine = (modes(simply_supported(k, k, 1.0, 0.7, thick, triangles=triangles), 6) for k in (n // 2, n))
    assert np.all(np.abs(fine / exact - 1) < np.abs(coarse / exact - 1) / 3)
    np.testing.assert_allclose(fine, exact, rtol=0.01)


@pytest.mark.parametrize("triangles", [False, True])
def test_cantilever_plate_against_leissa(triangles):
    truth = leissa_hz(1.0, STEEL, CANTILEVER)
    f = {n: modes(cantilever(n, 1.0, triangles=triangles), 6) for n in (8, 16, 24)}
    np.testing.assert_allclose(f[24], truth, rtol=0.01)
    # converged: the change from 16 to 24 elements a side is smaller than from 8 to 16
    assert np.all(np.abs(f[24] - f[16]) < np.abs(f[16] - f[8]))


def test_free_plate_six_rigid_modes_then_leissa():
    nodes, shells = grid(24, 24, 1.0, 1.0)
    f = modes(FEMesh(nodes, shells, shell_properties={"plate": STEEL}), 12)
    assert np.all(f[:6] < 1e-3 * f[6])
    np.testing.assert_allclose(f[6:], leissa_hz(1.0, STEEL, FREE), rtol=0.01)


def test_simply_supported_mode_shapes_are_navier_sines():
    """The first three shapes' w at the nodes against sin(mπx/a) sin(nπy/b) of modes (1,1), (2,1), (1,2) (for
    a = 1, b = 0.7: the lowest three), MAC > 0.999."""
    mesh = simply_supported(24, 24, 1.0, 0.7)
    m = assemble(mesh)
    _, phi = sparse_modes(m.stiffness, m.mass, 3)
    rows = [k for k, (_, d) in enumerate(m.dofs) if d == "z"]
    xy = np.array([mesh.nodes[m.dofs[k][0]][:2] for k in rows])
    for shape, (i, j) in zip(phi[rows].T, [(1, 1), (2, 1), (1, 2)]):
        truth = np.sin(i * np.pi * xy[:, 0]) * np.sin(j * np.pi * xy[:, 1] / 0.7)
        assert (shape @ truth) ** 2 / ((shape @ shape) * (truth @ truth)) > 0.999


def test_mixed_quads_and_triangles_in_one_plate():
    """Half the simply supported plate in quads, half in triangles, one property: both kinds in one assembly
    meet along a line of shared nodes without a gap."""
    quads = simply_supported(32, 32, 1.0, 0.7)
    tris = simply_supported(32, 32, 1.0, 0.7, triangles=True)
    left = [s for s in quads.shells if float(quads.nodes[s[1][0]][0]) < 0.5]
    right = [s for s in tris.shells if min(float(tris.nodes[n][0]) for n in s[1]) >= 0.5]
    mixed = type(quads)(quads.nodes, tuple(left + right), shell_properties=quads.shell_properties,
                        fixed=quads.fixed)
    exact = navier_hz(1.0, 0.7, STEEL, 6)
    error = modes(mixed, 6) / exact - 1
    assert np.all(error > 0) and error.max() < 0.012     # 0.15-0.99 %: between all quads (0.10-0.82 %) and
    assert np.all(error < modes(tris, 6) / exact - 1 + 2e-4)    # all triangles (0.20-1.34 %)
