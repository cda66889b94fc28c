"""Patch tests of the grillage elements against closed-form beam, shaft, string and chain results."""

import numpy as np
import pytest
import scipy.linalg

from era import fem
from era.errors import EraError

BAR = fem.flat_bar(0.0508, 0.00635, E=68.9e9, nu=0.33, rho=2700.0)


def straight_frame(n_el, length, angle_deg=0.0, section=BAR, EI=None):
    """n_el elements along a straight line through the origin at angle_deg in the x-y plane."""
    c, s = np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))
    r = np.linspace(0, length, n_el + 1)
    ones = np.ones(n_el)
    return fem.PlaneFrame(nodes_m=np.column_stack([r * c, r * s]), bars=np.column_stack([np.arange(n_el), np.arange(1, n_el + 1)]),
                     EI_out=(section.E * section.i_out if EI is None else EI) * ones, GJ=section.G * section.j_torsion * ones,
                     EA=section.E * section.area * ones, EI_in=section.E * section.i_in * ones,
                     mass_per_length=section.mass_per_length * ones, rho_ip=section.rho * section.i_polar * ones,
                     r2=section.i_polar / section.area * ones, links=np.zeros((0, 2), int),
                     link_stiffness=np.zeros((0, 3)), node_mass=np.zeros(n_el + 1), node_springs=np.zeros((n_el + 1, 3)))


def constrained_modes(system, fixed_dofs, n):
    """Lowest n modes with some DOFs held at zero (rows and columns removed)."""
    keep = np.setdiff1d(np.arange(system.K.shape[0]), fixed_dofs)
    K, M = system.K.toarray()[np.ix_(keep, keep)], system.M.toarray()[np.ix_(keep, keep)]
    return fem.lowest_modes(K, M, n)[0]


@pytest.mark.parametrize("angle", [0.0, 90.0, 30.0])
def test_cantilever_bending_matches_euler_bernoulli_in_any_direction(angle):
    L = 1.2
    system = fem.assemble_out_of_plane(straight_frame(12, L, angle))
    f = constrained_modes(system, system.dofs[0], 6)
    beta_l = np.array([1.87510407, 4.69409113, 7.85475744])
    exact = beta_l**2 / (2 * np.pi) * np.sqrt(BAR.E * BAR.i_out / (BAR.mass_per_length * L**4))
    bending = f[np.argsort(np.abs(f[:, None] - exact[None]).min(axis=1))[:3]]
    np.testing.assert_allclose(np.sort(bending), exact, rtol=2e-4)


def test_cantilever_torsion_of_a_flat_strip():
    L = 0.6
    system = fem.assemble_out_of_plane(straight_frame(40, L))
    f = constrained_modes(system, system.dofs[0], 12)
    exact = np.array([1, 3]) / (4 * L) * np.sqrt(BAR.G * BAR.j_torsion / (BAR.rho * BAR.i_polar))
    for fe in exact:
        assert np.min(np.abs(f / fe - 1)) < 2e-3      # linear twist elements converge as h²


def test_flat_bar_torsion_constant_and_mass():
    # J of a 2 in × 1/4 in strip: w t³/3 (1 - 0.63 t/w) to within the series' last term
    assert BAR.j_torsion == pytest.approx(0.0508 * 0.00635**3 / 3 * (1 - 0.63 / 8), rel=1e-6)
    assert BAR.mass_per_length == pytest.approx(2700 * 0.0508 * 0.00635)
    with pytest.raises(EraError):
        fem.flat_bar(0.05, -0.01, 70e9, 0.3, 2700)


def test_consistent_mass_carries_the_total_mass_in_translation():
    frame = straight_frame(7, 2.0, 37.0)
    system = fem.assemble_out_of_plane(frame)
    w = np.zeros(system.K.shape[0])
    w[system.dofs[:, 0]] = 1.0
    assert w @ (system.M @ w) == pytest.approx(frame.total_mass(), rel=1e-12)
    assert np.allclose(system.K @ w, 0.0, atol=1e-9)         # rigid translation stores no strain energy


def test_taut_string_frequencies_from_the_geometric_stiffness():
    L, T = 2.0, 500.0
    frame = straight_frame(60, L, 20.0, EI=1e-6)             # a string: negligible bending stiffness
    system = fem.assemble_out_of_plane(frame, axial_force=np.full(60, T))
    f = constrained_modes(system, np.r_[system.dofs[0, 0], system.dofs[-1, 0]], 20)
    exact = np.arange(1, 4) / (2 * L) * np.sqrt(T / BAR.mass_per_length)
    for fe in exact:
        assert np.min(np.abs(f / fe - 1)) < 2e-3


def test_hanging_chain_from_self_weight_statics():
    """A flexible bar hanging from a pin: ω_n = (j0,n / 2) √(g/L), j0,n the zeros of Bessel J0."""
    L, n_el = 1.5, 60
    frame = straight_frame(n_el, L, -90.0, EI=1e-7)          # node 0 at the top, the bar hangs down
    statics = fem.self_weight(frame, [(0, True, True)])
    assert statics.reactions[0, 1] == pytest.approx(frame.total_mass() * fem.G_STANDARD, rel=1e-9)
    mid_depth = (np.arange(n_el) + 0.5) / n_el * L            # tension = weight of the chain below
    np.testing.assert_allclose(statics.axial_force, BAR.mass_per_length * fem.G_STANDARD * (L - mid_depth), rtol=1e-6)
    system = fem.assemble_out_of_plane(frame, statics.axial_force)
    f = constrained_modes(system, [system.dofs[0, 0]], 40)
    exact = np.array([2.40482556, 5.52007811, 8.65372791]) / 2 * np.sqrt(fem.G_STANDARD / L) / (2 * np.pi)
    for fe in exact:
        assert np.min(np.abs(f / fe - 1)) < 5e-3


def test_bar_on_two_cables_swings_as_a_pendulum():
    """A horizontal bar hung by its ends from cables of length Lc: springs T/Lc give f = √(g/Lc)/2π."""
    frame = straight_frame(10, 1.0, EI=1e4)                  # a stiff bar: the swing is a rigid translation
    statics = fem.self_weight(frame, [(0, True, True), (10, False, True)])
    assert statics.reactions[:, 1].sum() == pytest.approx(frame.total_mass() * fem.G_STANDARD, rel=1e-9)
    Lc = 0.4
    springs = np.zeros((11, 3))
    springs[[0, 10], 0] = statics.reactions[:, 1] / Lc
    from dataclasses import replace
    system = fem.assemble_out_of_plane(replace(frame, node_springs=springs), statics.axial_force)
    f, _ = fem.lowest_modes(system.K, system.M, 3)      # twist about the bar's own axis is free (0 Hz)
    assert f[0] < 1e-2
    assert f[1] == pytest.approx(np.sqrt(fem.G_STANDARD / Lc) / (2 * np.pi), rel=1e-4)
    assert f[2] == pytest.approx(np.sqrt(3) * f[1], rel=1e-3)   # rocking: k L²/2 against m L²/12 (+ bending)


def test_sparse_and_dense_eigensolvers_agree():
    frame = straight_frame(80, 3.0)                           # 243 DOFs: the sparse shift-invert path
    system = fem.assemble_out_of_plane(frame, axial_force=np.full(80, 50.0))
    f_sparse, phi = fem.lowest_modes(system.K, system.M, 8)
    lam = scipy.linalg.eigh(system.K.toarray(), system.M.toarray(), eigvals_only=True, subset_by_index=[0, 7])
    np.testing.assert_allclose(f_sparse[3:], np.sqrt(lam[3:]) / (2 * np.pi), rtol=1e-6)
    np.testing.assert_allclose(phi.T @ (system.M @ phi), np.eye(8), atol=1e-8)


def test_links_tie_w_and_spring_the_rotations():
    """Two half-bars joined by a link: a stiff link gives the continuous beam, a soft one a hinge."""
    whole = straight_frame(8, 1.0)
    system = fem.assemble_out_of_plane(whole)
    f_whole = constrained_modes(system, system.dofs[0], 3)
    nodes = np.vstack([whole.nodes_m[:5], whole.nodes_m[4:]])    # node 5 duplicates node 4
    bars = np.array([[i, i + 1] for i in range(4)] + [[i, i + 1] for i in range(5, 9)])
    def linked(k):
        fr = fem.PlaneFrame(nodes_m=nodes, bars=bars, EI_out=whole.EI_out, GJ=whole.GJ, EA=whole.EA, EI_in=whole.EI_in,
                       mass_per_length=whole.mass_per_length, rho_ip=whole.rho_ip, r2=whole.r2,
                       links=[[4, 5]], link_stiffness=[[np.inf, k, k]], node_mass=np.zeros(10),
                       node_springs=np.zeros((10, 3)))
        s = fem.assemble_out_of_plane(fr)
        return constrained_modes(s, s.dofs[0], 3)
    np.testing.assert_allclose(linked(np.inf), f_whole, rtol=1e-10)
    np.testing.assert_allclose(linked(1e7), f_whole, rtol=1e-4)
    assert np.all(linked(10.0) < f_whole * (1 - 1e-3))
