"""One flat shell element and small patches of them: the six rigid-body motions are free of strain energy, a
patch of distorted elements reproduces a constant membrane strain and a constant curvature exactly, the mass is
the element's."""

import numpy as np
import pytest

from era.errors import DataError
from era.fem import ShellProperty
from era.fem.shell import quad4_batch, quad4_matrices, tria3_batch, tria3_matrices

PROP = ShellProperty(thickness=0.01, e=2.0e11, nu=0.3, rho=7850.0, nsm=3.0)
WARPED = np.array([[0.0, 0.0, 0.0], [1.2, 0.1, 0.05], [1.0, 0.9, -0.04], [-0.1, 1.1, 0.03]])


def rotated(xyz):
    c, s = np.cos, np.sin
    a, b = 0.7, -0.4
    R = np.array([[c(a), -s(a), 0], [s(a), c(a), 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, c(b), -s(b)],
                                                                             [0, s(b), c(b)]])
    return xyz @ R.T + [3.0, -1.0, 2.0]


def rigid_motions(xyz):
    """(6n, 6): unit translations and small rotations about the origin, in x y z rx ry rz per node."""
    out = np.zeros((len(xyz), 6, 6))
    for a in range(3):
        out[:, a, a] = 1.0
        out[:, :3, 3 + a] = np.cross(np.eye(3)[a], xyz)
        out[:, 3 + a, 3 + a] = 1.0
    return out.reshape(-1, 6)


@pytest.mark.parametrize("xyz, element", [
    (WARPED * [1, 1, 0], quad4_matrices), (WARPED, quad4_matrices), (rotated(WARPED), quad4_matrices),
    (WARPED[:3], tria3_matrices), (rotated(WARPED[:3]), tria3_matrices)])
def test_free_element_has_six_rigid_body_modes(xyz, element):
    k, m = element(xyz, PROP)
    assert np.allclose(k, k.T, atol=1e-12 * np.abs(k).max())
    w = np.linalg.eigvalsh(k)
    assert np.all(np.abs(w[:6]) < 1e-10 * w[-1]) and w[6] > 1e-9 * w[-1]     # six zeros, no spurious seventh
    rigid = rigid_motions(xyz)
    assert np.abs(k @ rigid).max() < 1e-10 * np.abs(k).max()                 # and they are the rigid motions
    assert np.all(np.linalg.eigvalsh(m) > 0)


@pytest.mark.parametrize("element", [quad4_matrices, tria3_matrices])
def test_translational_mass_is_the_elements(element):
    xyz = rotated(WARPED * [1, 1, 0])[: 4 if element is quad4_matrices else 3]
    _, m = element(xyz, PROP)
    area = 0.5 * np.linalg.norm(np.cross(xyz[2] - xyz[0], xyz[-1] - xyz[1] if len(xyz) == 4 else xyz[1] - xyz[0]))
    u = np.tile([1.0, 0, 0, 0, 0, 0], len(xyz))
    assert u @ m @ u == pytest.approx((PROP.rho * PROP.thickness + PROP.nsm) * area, rel=1e-12)


# MacNeal & Harder's patch (NAFEMS/Finite Elements in Analysis and Design 1, 1985): a 0.24 x 0.12 rectangle with
# four distorted interior nodes
OUTER = np.array([[0.0, 0.0], [0.24, 0.0], [0.24, 0.12], [0.0, 0.12]])
INNER = np.array([[0.04, 0.02], [0.18, 0.03], [0.16, 0.08], [0.08, 0.08]])
QUADS = [(0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7), (4, 5, 6, 7)]


def patch(triangles: bool):
    xyz = np.hstack([np.vstack([OUTER, INNER]), np.zeros((8, 1))])
    conn = [c for q in QUADS for c in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))] if triangles else QUADS
    prop = ShellProperty(thickness=0.001, e=1.0e6, nu=0.25, rho=1.0)
    batch = tria3_batch if triangles else quad4_batch
    k_e, _ = batch(xyz[np.array(conn)], prop)
    K = np.zeros((48, 48))
    for c, k in zip(conn, k_e):
        d = (6 * np.array(c)[:, None] + np.arange(6)).ravel()
        K[np.ix_(d, d)] += k
    return xyz, K


def solve_patch(K, exact):
    """Hold the four outer nodes at the exact field; the inner nodes' DOFs from K u = 0."""
    outer, inner = np.arange(24), np.arange(24, 48)
    u = exact.copy()
    u[inner] = np.linalg.solve(K[np.ix_(inner, inner)], -K[np.ix_(inner, outer)] @ exact[outer])
    return u


@pytest.mark.parametrize("triangles", [False, True])
def test_patch_reproduces_constant_membrane_strain(triangles):
    xyz, K = patch(triangles)
    x, y = xyz[:, 0], xyz[:, 1]
    exact = np.zeros((8, 6))
    exact[:, 0], exact[:, 1] = 1e-3 * (x + y / 2), 1e-3 * (y + x / 2)   # εx = εy = 1e-3, γxy = 1e-3, no rotation
    u = solve_patch(K, exact.ravel())
    np.testing.assert_allclose(u, exact.ravel(), atol=1e-12)


@pytest.mark.parametrize("triangles", [False, True])
def test_patch_reproduces_constant_curvature(triangles):
    """w = 1e-3 (x² + xy + y²)/2 with zero shear: θx = ∂w/∂y, θy = -∂w/∂x, all curvatures constant."""
    xyz, K = patch(triangles)
    x, y = xyz[:, 0], xyz[:, 1]
    exact = np.zeros((8, 6))
    exact[:, 3], exact[:, 4] = 1e-3 * (y + x / 2), -1e-3 * (x + y / 2)
    exact[:, 2] = 1e-3 * (x**2 + x * y + y**2) / 2
    u = solve_patch(K, exact.ravel()).reshape(8, 6)
    np.testing.assert_allclose(u[4:, 3:5], exact[4:, 3:5], atol=1e-9)


def test_degenerate_elements_are_refused():
    with pytest.raises(DataError, match="without area"):
        tria3_matrices([[0, 0, 0], [1, 0, 0], [2, 0, 0]], PROP)
    with pytest.raises(DataError, match="inverted or too distorted"):
        quad4_matrices([[0, 0, 0], [1, 0, 0], [0.1, 0.1, 0], [0, 1, 0]], PROP)  # a re-entrant corner
    with pytest.raises(DataError, match="not physical"):
        quad4_matrices(WARPED, ShellProperty(thickness=0.0, e=1.0, nu=0.3, rho=1.0))
