"""What the explain parameters do to a matrix model (era.models.changes, MatrixExplainModel), against closed
forms: a tip mass on an Euler-Bernoulli cantilever whose rotations carry no mass (the frequency equation of a
cantilever with a tip mass), a part's stiffness factor on a spring chain (frequencies × √θ), a spring to ground
on a one-storey chain; the reduced model (nominal modes plus static deflections) and the full solve alike."""

import numpy as np
import pytest
import scipy.optimize

import era
from era.discrepancy import MatrixExplainModel
from era.errors import DataError

N, LENGTH, EI, RHO_A = 40, 2.0, 1.0e4, 3.0


def cantilever():
    h = LENGTH / N
    ke = EI / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                               [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    K = np.zeros((2 * N + 2, 2 * N + 2))
    for e in range(N):
        K[2 * e:2 * e + 4, 2 * e:2 * e + 4] += ke
    mass = np.zeros(2 * N + 2)
    mass[0::2] = RHO_A * h
    mass[-2] = RHO_A * h / 2
    keep = np.arange(2, 2 * N + 2)
    dofs = [(str(i), d) for i in range(1, N + 1) for d in ("z", "ry")]
    sensors = [(str(i), "z") for i in range(4, N + 1, 4)]
    return era.MatrixModel(K[np.ix_(keep, keep)], np.diag(mass[keep]), dofs, sensors=sensors)


def tip_mass_frequencies(ratio: float, n: int = 3) -> np.ndarray:
    """Roots βL of 1 + cos cosh + ratio βL (cos sinh − sin cosh) = 0 (ratio = tip mass / beam mass), in Hz."""
    g = lambda b: 1 + np.cos(b) * np.cosh(b) + ratio * b * (np.cos(b) * np.sinh(b) - np.sin(b) * np.cosh(b))  # noqa: E731
    grid = np.linspace(0.1, 12, 2000)
    roots = [scipy.optimize.brentq(g, a, b) for a, b in zip(grid[:-1], grid[1:]) if g(a) * g(b) < 0][:n]
    return np.array(roots) ** 2 / (2 * np.pi) * np.sqrt(EI / (RHO_A * LENGTH**4))


@pytest.mark.parametrize("reduced", [True, False])
def test_a_tip_mass_on_a_cantilever_with_massless_rotations_gives_the_closed_form(reduced):
    model = MatrixExplainModel.of(cantilever(), cantilever().sensors, reduced=reduced)
    beam_mass = RHO_A * LENGTH
    heavy = model.with_params(point_mass_at=str(N), point_mass=0.5 * beam_mass)
    np.testing.assert_allclose(heavy.modes(3)[0], tip_mass_frequencies(0.5), rtol=3e-3)
    np.testing.assert_allclose(model.modes(3)[0], tip_mass_frequencies(0.0), rtol=3e-3)


def test_a_part_factor_scales_its_share_and_a_ground_spring_adds_to_one_dof():
    k, m = 400.0, 2.0
    K = np.array([[2 * k, -k], [-k, k]])
    model = era.MatrixModel(K, m * np.eye(2), [("1", "x"), ("2", "x")], parts={"all": K}, sensors=[("2", "x")])
    explain_model = MatrixExplainModel.of(model, model.sensors, reduced=False)
    base = explain_model.modes(2)[0]
    np.testing.assert_allclose(explain_model.with_params(part_at="part:all", part_factor=1.44).modes(2)[0],
                               1.2 * base, rtol=1e-10)
    # a spring k_g from the top to ground: K = [[2k, -k], [-k, k + k_g]]
    kg = 300.0
    lam = np.linalg.eigvalsh(np.array([[2 * k, -k], [-k, k + kg]]) / m)
    got = explain_model.with_params(spring_at="2:x", spring_stiffness=kg).modes(2)[0]
    np.testing.assert_allclose(got, np.sqrt(lam) / (2 * np.pi), rtol=1e-10)
    with pytest.raises(DataError, match="no part 'deck'"):
        explain_model.with_params(part_at="part:deck", part_factor=0.5).modes(1)
    with pytest.raises(DataError, match="node 2 has no free translation|no free z DOF"):
        explain_model.with_params(spring_at="2:z", spring_stiffness=1.0).modes(1)


def test_the_parts_scatter_enters_as_a_frames_members_does():
    """Each part's share of the strain energy adds up to 1 where the parts make the whole stiffness, and the
    shapes' sensitivity to a part's stiffness (modal superposition) is the full solves' central difference."""
    def chain_k(ks):
        a = np.zeros((4, 4))
        for i, kk in enumerate(ks):
            a[i, i] += kk
            if i:
                a[i - 1, i - 1] += kk
                a[i - 1, i] -= kk
                a[i, i - 1] -= kk
        return a
    parts = {"low": chain_k([100, 150, 0, 0]), "high": chain_k([0, 0, 120, 80])}
    model = era.MatrixModel(chain_k([100, 150, 120, 80]), np.diag([1.0, 1.2, 0.9, 1.1]),
                            [(i, "x") for i in range(1, 5)], parts=parts, sensors=[(i, "x") for i in range(1, 5)])
    em = MatrixExplainModel.of(model, model.sensors, reduced=False)
    assert em.default_member_scatter == 0.02
    np.testing.assert_allclose(em.member_energy_fractions(3).sum(axis=0), 1.0, rtol=1e-10)
    _, s0 = em.modes(3)
    p0 = s0 / np.linalg.norm(s0, axis=0)

    def unit(theta):
        s = em.with_params(part_at="part:low", part_factor=theta).modes(3)[1]
        s = s / np.linalg.norm(s, axis=0)
        return s * np.sign(np.sum(s * p0, axis=0))

    np.testing.assert_allclose(em.member_shape_sensitivity(3)[0], (unit(1.0001) - unit(0.9999)) / 0.0002, atol=1e-6)
