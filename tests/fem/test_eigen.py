"""era.fem.sparse_modes against closed forms and plain LAPACK: spring-mass chains (fixed-free, free-free, two
identical chains for repeated eigenvalues), massless DOFs, the dense and the sparse path, bad input."""

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse

from era.errors import DataError
from era.fem import sparse_modes


def chain(n, k=1.0e6, m=2.0, grounded=True):
    """n equal masses m joined by springs k, the first grounded (fixed-free) or not (free-free)."""
    main = np.full(n, 2 * k)
    main[-1] = k
    if not grounded:
        main[0] = k
    K = scipy.sparse.diags([main, -k * np.ones(n - 1), -k * np.ones(n - 1)], [0, 1, -1], format="csc")
    return K, scipy.sparse.identity(n, format="csc") * m


def fixed_free_hz(n, j, k=1.0e6, m=2.0):
    return 2 * np.sqrt(k / m) * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1))) / (2 * np.pi)


def free_free_hz(n, j, k=1.0e6, m=2.0):
    return 2 * np.sqrt(k / m) * np.sin(j * np.pi / (2 * n)) / (2 * np.pi)


@pytest.mark.parametrize("n", [50, 3000])      # the dense and the sparse path
def test_fixed_free_chain_matches_closed_form(n):
    K, M = chain(n)
    f, phi = sparse_modes(K, M, 8)
    np.testing.assert_allclose(f, fixed_free_hz(n, np.arange(1, 9)), rtol=1e-9)
    np.testing.assert_allclose(phi.T @ (M @ phi), np.eye(8), atol=1e-9)
    lam = (2 * np.pi * f) ** 2                                               # each shape is its frequency's
    assert np.abs(K @ phi - (M @ phi) * lam).max() < 1e-6 * np.abs(K @ phi).max()
    assert np.all(np.abs(phi).max(axis=0) == phi.max(axis=0))               # largest entry positive


@pytest.mark.parametrize("n", [50, 3000])
def test_free_free_chain_rigid_mode_near_zero(n):
    K, M = chain(n, grounded=False)
    f, _ = sparse_modes(K, M, 5)
    assert f[0] < 1e-6 * f[1]
    np.testing.assert_allclose(f[1:], free_free_hz(n, np.arange(1, 5)), rtol=1e-8)


def test_repeated_eigenvalues_are_all_found():
    """Two identical free-free chains: every eigenvalue twice, the rigid one too (Lanczos from one start vector
    can miss a copy; the Sturm count finds it)."""
    K, M = chain(2000, grounded=False)
    f, phi = sparse_modes(scipy.sparse.block_diag([K, K]), scipy.sparse.block_diag([M, M]), 6)
    assert f[0] < 1e-6 * f[2] and f[1] < 1e-6 * f[2]
    np.testing.assert_allclose(f[2:], np.repeat(free_free_hz(2000, np.arange(1, 3)), 2), rtol=1e-8)
    assert np.linalg.matrix_rank(phi, tol=1e-6 * np.abs(phi).max()) == 6
    K2, M2 = scipy.sparse.block_diag([K, K]), scipy.sparse.block_diag([M, M])
    assert np.abs(K2 @ phi - (M2 @ phi) * (2 * np.pi * f) ** 2).max() < 1e-6 * np.abs(K2 @ phi).max()


@pytest.mark.parametrize("n", [60, 900])
def test_massless_dofs_match_static_condensation(n):
    """Every third DOF massless (a singular M): the truth condenses them out statically (exact for massless
    DOFs) and solves the rest with plain LAPACK."""
    K, _ = chain(n)
    rng = np.random.default_rng(3)
    m = rng.uniform(1.0, 3.0, n)
    m[::3] = 0.0
    f, phi = sparse_modes(K, scipy.sparse.diags(m), 5)
    k = K.toarray()
    a, b = np.flatnonzero(m > 0), np.flatnonzero(m == 0)
    kc = k[np.ix_(a, a)] - k[np.ix_(a, b)] @ np.linalg.solve(k[np.ix_(b, b)], k[np.ix_(b, a)])
    lam = scipy.linalg.eigh(kc, np.diag(m[a]), eigvals_only=True, subset_by_index=[0, 4])
    np.testing.assert_allclose(f, np.sqrt(lam) / (2 * np.pi), rtol=1e-8)


def test_any_consistent_unit_system():
    """The same chain in kip-inch-second units (stiffness and mass scaled alike) has the same frequencies."""
    K, M = chain(1200)
    f_si = sparse_modes(K, M, 4)[0]
    f_us = sparse_modes(K * 5.71e-6, M * 5.71e-6, 4)[0]
    np.testing.assert_allclose(f_us, f_si, rtol=1e-9)


def test_dense_arrays_accepted():
    K, M = chain(30)
    np.testing.assert_allclose(sparse_modes(K.toarray(), M.toarray(), 3)[0], fixed_free_hz(30, np.arange(1, 4)),
                               rtol=1e-9)


@pytest.mark.parametrize("K, M, n, message", [
    (np.ones((3, 2)), np.eye(3), 1, "square"),
    (np.eye(3), np.eye(4), 1, "same size"),
    (np.array([[2.0, 1.0], [0.0, 2.0]]), np.eye(2), 1, "not symmetric"),
    (np.array([[np.nan, 0.0], [0.0, 1.0]]), np.eye(2), 1, "NaN"),
    (np.eye(3), np.eye(3), 4, "between 1 and 3"),
    (np.eye(3), np.zeros((3, 3)), 1, "no mass"),
    (np.diag([1.0, 0.0, 1.0]), np.diag([1.0, 0.0, 1.0]), 1, "neither stiffness nor mass"),
])
def test_bad_input_is_named(K, M, n, message):
    with pytest.raises(DataError, match=message):
        sparse_modes(K, M, n)
