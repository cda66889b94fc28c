"""era.MatrixModel: matrices of the free DOFs from any FE program, checked with clear errors, solved in any
consistent unit system and with massless DOFs. Truths are closed-form (a spring-mass chain, Euler-Bernoulli
cantilever frequencies), not era's own elements."""

import numpy as np
import pytest
import scipy.sparse

import era
from era.errors import DataError


def chain(n: int, k: float, m: float):
    """A fixed-free chain of n equal masses m joined by equal springs k: (K, M) tridiagonal."""
    main = np.full(n, 2 * k)
    main[-1] = k
    K = scipy.sparse.diags([main, np.full(n - 1, -k), np.full(n - 1, -k)], [0, 1, -1])
    return K, m * scipy.sparse.eye(n)


def chain_frequencies(n: int, k: float, m: float) -> np.ndarray:
    """ω_j = 2 √(k/m) sin((2j − 1) π / (2 (2n + 1))), in Hz."""
    j = np.arange(1, n + 1)
    return 2 * np.sqrt(k / m) * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1))) / (2 * np.pi)


def test_a_kip_inch_second_shear_building_has_the_closed_form_frequencies():
    # ten storeys of 200 kip each (m = W/g = 200 / 386.09 kip·s²/in), storey stiffness 500 kip/in
    m, k = 200 / 386.09, 500.0
    K, M = chain(10, k, m)
    model = era.MatrixModel(K, M, [(f"F{i + 1}", "x") for i in range(10)], units="kip-in-s")
    f, phi = model.modes(4)
    np.testing.assert_allclose(f, chain_frequencies(10, k, m)[:4], rtol=1e-9)
    np.testing.assert_allclose(phi.T @ (M @ phi), np.eye(4), atol=1e-9)        # mass-normalised
    assert model.units == {"mass": "kip·s²/in", "force": "kip", "length": "in"}
    assert model.total_mass() == pytest.approx(10 * m)


def test_a_cantilever_with_massless_rotations_converges_to_euler_bernoulli():
    # lumped translational mass only: every rotation is a massless DOF (a singular mass matrix)
    n, length, ei, rho_a = 60, 2.0, 1.0e4, 3.0
    h = length / n
    ke = ei / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                               [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    K = np.zeros((2 * n + 2, 2 * n + 2))
    for e in range(n):
        K[2 * e:2 * e + 4, 2 * e:2 * e + 4] += ke
    mass = np.zeros(2 * n + 2)
    mass[0::2] = rho_a * h
    mass[-2] = rho_a * h / 2
    keep = np.arange(2, 2 * n + 2)                  # node 0 clamped
    dofs = [(str(i), d) for i in range(1, n + 1) for d in ("z", "ry")]
    model = era.MatrixModel(K[np.ix_(keep, keep)], np.diag(mass[keep]), dofs)
    beta_l = np.array([1.8751040687, 4.6940911330, 7.8547574382])
    exact = beta_l**2 / (2 * np.pi) * np.sqrt(ei / (rho_a * length**4))
    np.testing.assert_allclose(model.modes(3)[0], exact, rtol=2e-3)


@pytest.mark.parametrize("change, words", [
    (lambda K, M, d: (K[:3], M, d), "square"),
    (lambda K, M, d: (K + np.triu(np.ones_like(K), 1), M, d), "not symmetric"),
    (lambda K, M, d: (K, M, d[:3] + [d[0]]), "both node 1 direction x"),
    (lambda K, M, d: (K, M, d[:3] + [("9", "w")]), "unknown direction 'w'"),
    (lambda K, M, d: (K, M, d[:3]), "lists 3 DOFs but the matrices are 4 × 4"),
    (lambda K, M, d: (K, -M, d), "negative diagonal"),
    (lambda K, M, d: (K, 0 * M, d), "mass matrix is zero"),
    (lambda K, M, d: (K * np.nan, M, d), "NaN"),
])
def test_bad_matrices_get_an_error_saying_what_to_fix(change, words):
    K, M = chain(4, 100.0, 1.0)
    dofs = [(i + 1, "x") for i in range(4)]
    K, M, dofs = change(K.toarray(), M.toarray(), dofs)
    with pytest.raises(DataError, match=words):
        era.MatrixModel(K, M, dofs)


def test_parts_add_up_to_at_most_the_whole_and_coordinates_cover_every_node():
    K, M = chain(4, 100.0, 1.0)
    dofs = [(i + 1, "x") for i in range(4)]
    whole = era.MatrixModel(K, M, dofs, parts={"half": 0.5 * K}, coordinates={i + 1: (i, 0, 0) for i in range(5)})
    assert whole.nodes == ("1", "2", "3", "4") and set(whole.parts) == {"half"}
    with pytest.raises(DataError, match="larger than the whole"):
        era.MatrixModel(K, M, dofs, parts={"a": 0.7 * K, "b": 0.7 * K})
    with pytest.raises(DataError, match="no position for 1 node"):
        era.MatrixModel(K, M, dofs, coordinates={1: (0, 0, 0), 2: (1, 0, 0), 3: (2, 0, 0)})
    with pytest.raises(DataError, match="node 7 has no free DOF"):
        era.MatrixModel(K, M, dofs, sensors=[("7", "x")])
    assert era.MatrixModel(K, M, dofs).with_sensors([(4, "-X")]).sensors == (("4", "-x"),)
