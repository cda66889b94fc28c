"""The singular value decomposition of H(0) (eq. 22): dense LAPACK, or a randomized one for large matrices."""

from __future__ import annotations

import numpy as np
import scipy.linalg

from .errors import EraError

#: H(0) switches to the randomized path when min(shape)² · max(shape) exceeds this (about 3-5 s of dense
#: gesdd on one core of this machine; 900 × 2392 is 1.9e9 and takes about 0.6 s).
DENSE_SVD_WORK_LIMIT = 8e9


def dense_svd(h: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Thin SVD ``h = P diag(d) Q^T`` with LAPACK's divide-and-conquer driver (gesdd).

    Falls back to the slower but more robust gesvd driver when gesdd does not converge.

    Returns
    -------
    P : (rows, k), d : (k,) descending, Q : (cols, k) with k = min(rows, cols).
    """
    try:
        u, d, vt = scipy.linalg.svd(h, full_matrices=False, lapack_driver="gesdd", check_finite=False)
    except np.linalg.LinAlgError:
        u, d, vt = scipy.linalg.svd(h, full_matrices=False, lapack_driver="gesvd", check_finite=False)
    return u, d, vt.T


def randomized_svd(
    h: np.ndarray, rank: int, oversample: int | None = None, power_iterations: int = 4, seed: int = 0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Leading ``rank`` singular triplets of ``h`` by randomized subspace iteration (Halko, Martinsson & Tropp 2011).

    A Gaussian test matrix of ``rank + oversample`` columns is pushed through ``power_iterations`` rounds of
    ``h h^T`` with re-orthonormalisation, then the small projected matrix is decomposed exactly. For the steep
    singular value spectra of structural pulse responses the leading values agree with the dense SVD to about
    machine precision (tests/test_svd.py); the seed makes the result repeatable.

    Returns
    -------
    P : (rows, rank), d : (rank,) descending, Q : (cols, rank).
    """
    rows, cols = h.shape
    rank = int(min(rank, rows, cols))
    width = min(rank + (oversample if oversample is not None else max(20, rank // 2)), rows, cols)
    rng = np.random.default_rng(seed)
    basis, _ = np.linalg.qr(h @ rng.standard_normal((cols, width)))
    for _ in range(power_iterations):
        z, _ = np.linalg.qr(h.T @ basis)
        basis, _ = np.linalg.qr(h @ z)
    u_small, d, vt = np.linalg.svd(basis.T @ h, full_matrices=False)
    return (basis @ u_small[:, :rank]), d[:rank], vt[:rank].T


def choose_method(shape: tuple[int, int], method: str) -> str:
    """``"dense"`` or ``"randomized"`` for ``method`` in {"auto", "dense", "randomized"}."""
    if method not in ("auto", "dense", "randomized"):
        raise EraError(f"`svd` must be 'auto', 'dense' or 'randomized', got {method!r}.")
    if method != "auto":
        return method
    small, large = sorted(shape)
    return "dense" if small * small * large <= DENSE_SVD_WORK_LIMIT else "randomized"
