"""The lowest modes of a structural model's stiffness and mass, K φ = λ M φ, sparse or dense.

One solver for every model the project builds or reads (shell meshes, Nastran decks, matrices from any FE
program): shift-inverted about a shift σ below the spectrum, so that rigid-body modes (λ ≈ 0 of a free-free model)
and massless DOFs (a singular M: rotations without rotary inertia) need no special input. Small problems are solved
densely; large ones with ARPACK's Lanczos on a sparse LU of K - σM, with a Sturm-sequence count (the inertia of
K - τM) that catches members of a repeated eigenvalue Lanczos missed and finds them in a deflated second pass.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from ..core.blas import single_threaded_blas
from ..errors import DataError

DENSE_LIMIT = 600         # up to this many DOFs a dense LAPACK solve is faster and surer than Lanczos


def _matrix(a, name: str):
    if scipy.sparse.issparse(a):
        return scipy.sparse.csc_matrix(a, dtype=float)
    a = np.asarray(a, dtype=float)
    if a.ndim != 2:
        raise DataError(f"The {name} matrix must be 2-D (n, n); it has shape {a.shape}.")
    return a


def _check(K, M, n_modes: int) -> int:
    n = K.shape[0]
    for a, name in ((K, "stiffness"), (M, "mass")):
        if a.shape[0] != a.shape[1]:
            raise DataError(f"The {name} matrix must be square; it is {a.shape[0]} x {a.shape[1]}.")
        data = a.data if scipy.sparse.issparse(a) else a
        if not np.all(np.isfinite(data)):
            raise DataError(f"The {name} matrix holds NaN or infinite values; check the model's properties.")
        scale = float(np.abs(data).max()) if data.size else 0.0
        diff = a - a.T
        asym = float(abs(diff).max()) if diff.shape[0] else 0.0
        if asym > 1e-8 * scale:
            raise DataError(f"The {name} matrix is not symmetric (largest |A - Aᵀ| = {asym:.3g} against entries up "
                            f"to {scale:.3g}); give the full symmetric matrix, not one triangle.")
    if M.shape != K.shape:
        raise DataError(f"The stiffness ({K.shape[0]} x {K.shape[1]}) and mass ({M.shape[0]} x {M.shape[1]}) "
                        "matrices must have the same size: one row and column per free DOF.")
    if n == 0:
        raise DataError("The model has no free DOF: every DOF is constrained.")
    if not 1 <= int(n_modes) <= n:
        raise DataError(f"Ask for between 1 and {n} modes (the model's DOF count); {n_modes} were asked.")
    return n


def default_shift(K, M) -> float:
    """A shift σ (rad²/s² in the model's time unit) a little below zero: 1e-10 of the stiffest DOF's K_ii/M_ii
    over the DOFs with mass, so it scales with any consistent unit system. Far enough from λ = 0 that K - σM is
    regular for a free-free model, close enough that the lowest modes are the best separated."""
    k, m = np.asarray(K.diagonal(), float), np.asarray(M.diagonal(), float)
    massive = m > 1e-12 * max(float(np.abs(m).max()), 1e-300)
    if not massive.any():
        raise DataError("The mass matrix is zero: the model has no mass, so it has no modes; check the densities.")
    top = float(np.max(np.abs(k[massive]) / m[massive]))
    return -max(1e-10 * top, 1e-30)


def _finish(lam: np.ndarray, phi: np.ndarray, M) -> tuple[np.ndarray, np.ndarray]:
    order = np.argsort(lam)
    lam, phi = lam[order], phi[:, order]
    mm = np.einsum("ij,ij->j", phi, M @ phi)
    phi = phi / np.sqrt(np.abs(mm))[None, :]
    big = np.argmax(np.abs(phi), axis=0)                       # a fixed sign: the largest entry positive
    phi = phi * np.sign(phi[big, np.arange(phi.shape[1])])[None, :]
    return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi), phi


def _singular_error() -> DataError:
    return DataError("The model has a DOF with neither stiffness nor mass (or a mechanism without mass), so K - σM "
                     "is singular; fix or constrain the loose DOF (an unconnected rotation, a node no element "
                     "touches).")


def _dense(K, M, n_modes: int, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    k = K.toarray() if scipy.sparse.issparse(K) else K
    m = M.toarray() if scipy.sparse.issparse(M) else M
    n = k.shape[0]
    try:   # μ = 1/(λ - σ) of M φ = μ (K - σM) φ: the lowest λ are the largest μ, massless DOFs μ = 0
        mu, phi = scipy.linalg.eigh(m, k - sigma * m, subset_by_index=[n - n_modes, n - 1], check_finite=False)
    except np.linalg.LinAlgError:
        raise _singular_error() from None
    if np.any(mu <= 1e-14 * np.abs(mu).max()):
        rank = int(np.sum(np.diag(m) > 0))
        raise DataError(f"Only about {rank} DOFs carry mass, fewer than the {n_modes} modes asked; ask for fewer "
                        "modes or add the missing mass (densities, point masses).")
    return _finish(sigma + 1.0 / mu, phi, M)


def _symmetric_lu(A):
    """A sparse LU of a symmetric A with one symmetric ordering and no row pivoting (then LU = LDLᵀ up to
    scaling: half the fill of a general LU on shell meshes, and U's diagonal carries A's inertia), or None when
    SuperLU pivoted anyway or failed."""
    try:
        lu = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(A), permc_spec="MMD_AT_PLUS_A",
                                      diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError:
        return None
    return lu if np.array_equal(lu.perm_r, lu.perm_c) else None


def _negative_count(K, M, tau: float) -> int | None:
    """The number of eigenvalues below τ (Sylvester's law of inertia on an LDLᵀ of K - τM), or None."""
    lu = _symmetric_lu(K - tau * M)
    return None if lu is None else int(np.sum(lu.U.diagonal() < 0))


def _lanczos(K, M, n_modes: int, sigma: float, lu, found: np.ndarray | None = None,
             found_mu: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """n_modes largest μ of (K - σM)⁻¹ M, deflated of the M-orthonormal vectors ``found`` (their μ go to 0)."""
    n = K.shape[0]

    def solve(y):
        x = lu.solve(y)
        if found is not None:
            x = x - found @ (found_mu * (found.T @ y))
        return x

    op = scipy.sparse.linalg.LinearOperator((n, n), matvec=solve, dtype=float)
    ncv = min(n, max(2 * n_modes + 1, n_modes + 32))
    # ARPACK's own steps are BLAS-2 products on (n, ncv) blocks: threads only add their start-up and spinning
    # (6 s of 8 on a 20,000-DOF plate while the other core was busy, 0.1 s with one thread)
    with single_threaded_blas():
        return scipy.sparse.linalg.eigsh(K, n_modes, M, sigma=sigma, which="LM", OPinv=op, ncv=ncv, tol=1e-10,
                                         v0=1.0 + np.sin(1.7 * np.arange(n) + 0.3))


def _sparse(K, M, n_modes: int, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    K, M = scipy.sparse.csc_matrix(K), scipy.sparse.csc_matrix(M)
    lu = _symmetric_lu(K - sigma * M)
    if lu is None or not np.all(np.isfinite(lu.U.diagonal())) or np.any(lu.U.diagonal() == 0):
        try:    # a general LU with partial pivoting: slower, but sure
            lu = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(K - sigma * M))
        except RuntimeError:
            raise _singular_error() from None
    try:
        lam, phi = _lanczos(K, M, n_modes, sigma, lu)
    except scipy.sparse.linalg.ArpackNoConvergence:
        raise DataError("The eigensolver did not converge; check the model for loose DOFs or give a shift just "
                        "below the lowest frequency you expect.") from None
    if not np.all(np.isfinite(lam)) or np.any(lam > 1e250):
        raise _singular_error()
    order = np.argsort(lam)
    lam, phi = lam[order], phi[:, order]
    # Lanczos from one start vector may miss members of a repeated eigenvalue (a free-free model's six rigid
    # modes): count the eigenvalues below the highest one found and fetch the missing ones from a deflated run.
    # One factorisation at a time: the count's replaces the solver's, which is made again only if needed.
    del lu
    tau = sigma + (lam[-1] - sigma) * (1 - 1e-6)
    below = _negative_count(K, M, tau)
    missing = 0 if below is None else below - int(np.sum(lam < tau))
    if missing > 0:
        lu = _symmetric_lu(K - sigma * M) or scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(K - sigma * M))
        lam, phi = _finish_pass(K, M, sigma, lu, lam, phi, missing)
    return lam[:n_modes], phi[:, :n_modes]


def _finish_pass(K, M, sigma, lu, lam, phi, missing):
    phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, M @ phi))[None, :]
    more_lam, more_phi = _lanczos(K, M, missing, sigma, lu, found=phi, found_mu=1.0 / (lam - sigma))
    lam = np.concatenate([lam, more_lam])
    phi = np.concatenate([phi, more_phi], axis=1)
    order = np.argsort(lam)
    return lam[order], phi[:, order]


def sparse_modes(stiffness, mass, n_modes: int, *, shift: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The lowest ``n_modes`` modes of K φ = λ M φ.

    Parameters
    ----------
    stiffness, mass : (n, n) symmetric, sparse (scipy.sparse) or dense, of the free DOFs. Any consistent unit
        system (N-m-kg-s, N-mm-t-s, lbf-in-(lbf·s²/in)-s); frequencies come out per the system's time unit. M may
        be singular (massless DOFs); K may be singular where M is not (a free-free model's rigid-body modes).
    n_modes : how many of the lowest modes.
    shift : σ (rad² per time unit²) of the shift-invert, below the lowest wanted eigenvalue λ = ω²; default a
        small negative value scaled to the model (:func:`default_shift`). The modes nearest σ are returned.

    Returns
    -------
    frequency_hz : (n_modes,) ascending, per time unit (Hz for seconds); rigid-body modes come out near 0.
    shapes : (n, n_modes) mass-normalised (φᵀ M φ = 1), largest entry of each positive.

    Raises
    ------
    DataError : non-square, mismatched, non-symmetric or non-finite matrices; a DOF with neither stiffness nor
        mass; more modes asked than DOFs with mass.
    """
    K, M = _matrix(stiffness, "stiffness"), _matrix(mass, "mass")
    n = _check(K, M, n_modes)
    n_modes = int(n_modes)
    sigma = default_shift(K, M) if shift is None else float(shift)
    if n <= DENSE_LIMIT or n_modes >= n // 3:
        return _dense(K, M, n_modes, sigma)
    lam, phi = _sparse(K, M, n_modes, sigma)
    return _finish(lam, phi, M)
