"""The 3-D frame element (era.fem.beam3d) against closed-form statics, rigid motions and its dispersion."""

import numpy as np
import pytest
import scipy.optimize

from era.fem import beam3d, space
from era.fem.elements import hermite

RNG = np.random.default_rng(3)


def random_elements(n=5):
    xi, xj = RNG.normal(size=(n, 3)), RNG.normal(size=(n, 3))
    L, R = beam3d.element_axes(xi, xj, RNG.normal(size=(n, 3)))
    props = dict(EA=RNG.uniform(1, 2, n) * 1e6, GJ=RNG.uniform(1, 2, n) * 1e2, EIy=RNG.uniform(1, 2, n) * 1e2,
                 EIz=RNG.uniform(1, 2, n) * 1e3)
    return xi, xj, L, R, props


def test_axes_are_orthonormal_right_handed_with_x_along_the_member_and_z_towards_the_orientation():
    xi, xj, L, R, _ = random_elements()
    np.testing.assert_allclose(R @ np.swapaxes(R, 1, 2), np.broadcast_to(np.eye(3), R.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0)
    np.testing.assert_allclose(R[:, 0] * L[:, None], xj - xi, atol=1e-12)
    # default: a horizontal member's local z is global Z, a vertical member's is global X
    axes = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 2.0], [0, 0, -1.0], [1.0, 1.0, 1.0]])
    _, R = beam3d.element_axes(np.zeros((5, 3)), axes, beam3d.default_orientation(axes))
    np.testing.assert_allclose(R[:2, 2], [[0, 0, 1], [0, 0, 1]])
    np.testing.assert_allclose(R[2:4, 2], [[1, 0, 0], [1, 0, 0]])
    assert R[4, 2, 2] > 0 and abs(R[4, 1, 2]) < 1e-12           # local y horizontal


def test_rigid_motions_store_no_energy_and_the_mass_carries_the_members_mass_and_inertia():
    xi, xj, L, R, p = random_elements()
    k = beam3d.to_global(beam3d.local_stiffness(L, p["EA"], p["GJ"], p["EIy"], p["EIz"]), R)
    kg = beam3d.to_global(beam3d.local_geometric(L, np.full(L.size, 40.0), np.full(L.size, 0.3)), R)
    m_len, rho_ip = RNG.uniform(1, 3, L.size), RNG.uniform(0.1, 0.2, L.size)
    m = beam3d.to_global(beam3d.local_mass(L, m_len, rho_ip), R)
    for e in range(L.size):
        rigid = space.rigid_body_modes(np.vstack([xi[e], xj[e]]))          # (12, 6)
        np.testing.assert_allclose(k[e] @ rigid, 0.0, atol=1e-8 * np.abs(k[e]).max())
        np.testing.assert_allclose(kg[e] @ rigid[:, :3], 0.0, atol=1e-10)  # translations: no geometric energy
        np.testing.assert_allclose(k[e], k[e].T, atol=1e-9 * np.abs(k[e]).max())
        assert np.all(np.linalg.eigvalsh(k[e])[6:] > 0)                    # six rigid modes, six strains
        trans = rigid[:, :3].T @ m[e] @ rigid[:, :3]
        np.testing.assert_allclose(trans, m_len[e] * L[e] * np.eye(3), rtol=1e-12, atol=1e-12)
        twist = np.zeros(12)
        twist[[3, 4, 5, 9, 10, 11]] = np.tile(R[e, 0], 2)                 # unit rotation about the member axis
        assert twist @ m[e] @ twist == pytest.approx(rho_ip[e] * L[e], rel=1e-12)


def test_cantilever_tip_loads_give_the_beam_formulas_in_any_orientation():
    """P L³/(3 EI) in both planes, T L/(GJ) in twist, N L/(EA) axially, for a member pointing anywhere."""
    xi, xj, L, R, p = random_elements(3)
    k = beam3d.to_global(beam3d.local_stiffness(L, p["EA"], p["GJ"], p["EIy"], p["EIz"]), R)
    for e in range(3):
        kff = k[e][6:, 6:]                                                  # node i clamped
        ex, ey, ez = R[e]
        cases = [(np.r_[ey, 0, 0, 0], ey, L[e]**3 / (3 * p["EIz"][e])),    # force along y: bends about z
                 (np.r_[ez, 0, 0, 0], ez, L[e]**3 / (3 * p["EIy"][e])),
                 (np.r_[ex, 0, 0, 0], ex, L[e] / p["EA"][e])]
        for f, along, flex in cases:
            u = np.linalg.solve(kff, f)
            assert u[:3] @ along == pytest.approx(flex, rel=1e-10)
        u = np.linalg.solve(kff, np.r_[0, 0, 0, ex])
        assert u[3:] @ ex == pytest.approx(L[e] / p["GJ"][e], rel=1e-10)


def test_uniform_load_is_statically_equivalent():
    xi, xj, L, R, _ = random_elements(4)
    q = RNG.normal(size=(4, 3))
    f = beam3d.uniform_load(L, R, q)
    np.testing.assert_allclose(f[:, :3] + f[:, 6:9], q * L[:, None], atol=1e-12)
    # moments about node i: r_j × F_j + M_i + M_j = ∫ r × q = (L/2) e_x × q L
    mom = np.cross(xj - xi, f[:, 6:9]) + f[:, 3:6] + f[:, 9:12]
    np.testing.assert_allclose(mom, np.cross((xj - xi) / 2, q * L[:, None]), atol=1e-12)


def test_axial_force_of_a_stretch():
    xi, xj, L, R, p = random_elements(2)
    u = np.zeros((2, 12))
    u[:, 6:9] = 1e-3 * R[:, 0]
    np.testing.assert_allclose(beam3d.axial_force(L, R, p["EA"], u), p["EA"] * 1e-3 / L)


def _bloch_error(kh, stiffness, mass):
    """Relative frequency error of a wave of wavenumber k in an infinite chain of elements of length 1."""
    e = np.exp(1j * kh)
    n = stiffness.shape[0] // 2
    kb = stiffness[:n, :n] + stiffness[n:, n:] + stiffness[:n, n:] * e + stiffness[n:, :n] / e
    mb = mass[:n, :n] + mass[n:, n:] + mass[:n, n:] * e + mass[n:, :n] / e
    lam = np.sort(np.linalg.eigvals(np.linalg.solve(mb, kb)).real)[0]
    exact = kh**2 if n == 2 else kh     # bending ω = k² √(EI/m); bar ω = k √(EA/m), all constants 1
    return np.sqrt(lam) / exact - 1


def test_mesh_rule_limits_are_0p05_percent_waves_of_the_element():
    one = np.ones(1)
    k_beam, m_beam = hermite(one, 12, 6, -12, 6, 4, 2)[0], hermite(one, 156, 22, 54, -13, 4, -3)[0] / 420
    bend = _bloch_error(space.KH_BENDING, k_beam, m_beam)
    bar = _bloch_error(space.KH_LINEAR, np.array([[1.0, -1], [-1, 1]]), np.array([[2.0, 1], [1, 2]]) / 6)
    assert bend == pytest.approx(5e-4, rel=0.01) and bar == pytest.approx(5e-4, rel=0.01)
    # consistent mass errs high (upper bound): the rule's frequencies from a coarse mesh are conservative
    root = scipy.optimize.brentq(lambda x: _bloch_error(x, k_beam, m_beam) - 1e-3, 0.5, 2)
    assert root > space.KH_BENDING
