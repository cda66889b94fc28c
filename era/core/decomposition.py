"""The eigen-decomposition of a realization (eq. 40): the modes' eigenvalues, shapes, amplitudes and histories,
the repeated modes (clusters of poles that the data cannot tell apart, and the basis of their eigenspace that
makes the shapes most real), the continuous eigenvalues (eq. 41) and the modes' order. era.core.modal builds the
ModalModel on it."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from . import indicators, lapack

#: |z| below this is treated as this (z = 0 has no logarithm); such a pole decays within one sample.
_TINY_Z = 1e-300


@dataclass(frozen=True)
class ModalDecomposition:
    """Per-mode arrays of an eigen-decomposition, one entry per mode (a conjugate pair is one mode).

    z : (modes,) complex discrete eigenvalues (the member with Im z ≥ 0); shapes : (p, modes) complex;
    amplitudes : (modes, m) complex; histories : (modes, s·m) modal amplitude histories ψ^{-1} W;
    (None when the decomposition was asked without them: the sweep forms them for all orders at once);
    is_pair : (modes,) bool, True for a complex-conjugate pair;
    right : (n, modes) complex, the eigenvectors ψ_j; left : (modes, n) complex, the matching rows of ψ^{-1}
    (scaled with the shapes, so left_j A = z_j left_j and left_j right_j = 1 still hold).
    """

    z: np.ndarray
    shapes: np.ndarray
    amplitudes: np.ndarray
    histories: np.ndarray | None
    is_pair: np.ndarray
    right: np.ndarray | None = None
    left: np.ndarray | None = None


def decompose(A: np.ndarray, B: np.ndarray, C: np.ndarray, W=None) -> ModalDecomposition:
    """Eigen-decompose A ψ = ψ z (eq. 40) and express B, C and the state history W in modal coordinates.

    Parameters
    ----------
    A : (n, n) real; B : (n, m) real; C : (p, n) real
    W : (n, s·m) real: the state at the column shifts (its first m columns are the initial state B for ERA
        and A1). Its rows projected on the left eigenvectors are the modal histories of eq. 44.
        Or a pair (root (n,), basis (s·m, n)) standing for W = diag(root) basis^T (ERA's D^{1/2} Q_n^T),
        which saves forming W. None: no histories (``histories`` is None; γ then needs them from elsewhere,
        era.core.sweep forms those of every order of a sweep in a few large products).

    Shapes are scaled so that their largest component is 1 (real), and amplitudes inversely, so the product
    shapes·amplitudes (the response) is unchanged and shapes are comparable across orders.
    """
    # LAPACK without the GIL (era.core.lapack), so the orders of a sweep run in parallel threads
    z, right, left = lapack.eig_kept(A)  # every real eigenvalue and one member (Im z > 0) of each pair
    is_pair = z.imag > 0
    z = np.where(is_pair, z, z.real + 0j)
    shapes = C @ right
    if shapes.size:  # normalise: largest shape component = 1 (left rows inversely, before the products)
        big = shapes[np.argmax(np.abs(shapes), axis=0), np.arange(shapes.shape[1])]
        scale = np.where(np.abs(big) > 0, big, 1.0)
        shapes, right, left = shapes / scale, right / scale, left * scale[:, None]
    amplitudes = _times_real(left, B)
    if W is None:
        histories = None
    elif isinstance(W, tuple):
        root, basis = W
        histories = _times_real(left * root[None, :], basis.T)
    else:
        histories = _times_real(left, W)
    return ModalDecomposition(z=z, shapes=shapes, amplitudes=amplitudes, histories=histories, is_pair=is_pair,
                              right=right, left=left)


def _normalised(dec: ModalDecomposition) -> ModalDecomposition:
    """Each shape scaled so that its largest component is 1 (real), the amplitudes, histories and left
    eigenvectors inversely: the response and every indicator are unchanged."""
    shapes = dec.shapes
    if not shapes.size:
        return dec
    big = shapes[np.argmax(np.abs(shapes), axis=0), np.arange(shapes.shape[1])]
    scale = np.where(np.abs(big) > 0, big, 1.0)
    return replace(dec, shapes=shapes / scale, amplitudes=dec.amplitudes * scale[:, None],
                   histories=None if dec.histories is None else dec.histories * scale[:, None],
                   right=None if dec.right is None else dec.right / scale,
                   left=None if dec.left is None else dec.left * scale[:, None])


def modal_sum(z: np.ndarray, shapes: np.ndarray, amplitudes: np.ndarray, is_pair: np.ndarray,
              n_samples: int) -> np.ndarray:
    """Y(k) = Σ_pairs 2 Re(c_j z_j^k b_j) + Σ_real c_j z_j^k b_j for k = 0..n_samples-1 (eq. 35 in modal form):
    shape (n_samples, p, m)."""
    weight = np.where(is_pair, 2.0, 1.0)
    zk = indicators.powers(z, np.arange(n_samples)).T * weight  # (N, modes)
    p, m = shapes.shape[0], amplitudes.shape[1]
    residues = np.einsum("pj,jm->jpm", shapes, amplitudes).reshape(-1, p * m)  # (modes, p m)
    with np.errstate(over="ignore", invalid="ignore"):
        y = zk.real @ residues.real - zk.imag @ residues.imag  # Re(zk @ residues) as two real products
    return y.reshape(n_samples, p, m)


#: Eigenvalues closer than this (|Δz|, relative to |z|) are one repeated eigenvalue whatever their uncertainty:
#: round-off splits an exactly repeated pair by ~1e-9 in the examples (Case II).
REPEATED_Z_FLOOR = 1e-7

#: Two poles are one cluster when |z_i - z_j| ≤ CLUSTER_SIGMAS · sqrt(σ_i² + σ_j²), σ the std of z ...
CLUSTER_SIGMAS = 3.0

#: ... and both are determined to better than this relative standard deviation of s (noise poles, whose own
#: scatter is large, are never rotated: that would make their shapes look real).
CLUSTER_MAX_RELATIVE_STD = 0.01

#: Only poles with a neighbour within this |Δz| are candidates (their uncertainty is computed for the test).
CLUSTER_SCREEN = 5e-3


def cluster_candidates(z: np.ndarray, is_pair: np.ndarray) -> np.ndarray:
    """(modes,) bool: poles with a pole of the same kind (pair or real) within CLUSTER_SCREEN in z."""
    near = (np.abs(z[:, None] - z[None, :]) <= CLUSTER_SCREEN) & (is_pair[:, None] == is_pair[None, :])
    np.fill_diagonal(near, False)
    return near.any(axis=1)


def repeated_clusters(z: np.ndarray, is_pair: np.ndarray, z_std: np.ndarray, dt: float) -> list[np.ndarray]:
    """Groups (of ≥ 2 mode indices) of poles closer than their estimation uncertainty: a repeated eigenvalue.

    Poles i, j are linked when they are of the same kind and |z_i - z_j| ≤ max(CLUSTER_SIGMAS·sqrt(σ_i² + σ_j²),
    REPEATED_Z_FLOOR·|z_i|), with both σ/(|z| |s| Δτ) ≤ CLUSTER_MAX_RELATIVE_STD (σ the standard deviation of z,
    NaN where not computed), and |z_i - z_j| ≤ CLUSTER_SCREEN; the clusters are the connected groups.
    """
    z = np.asarray(z, dtype=complex)
    k = z.size
    if k < 2:
        return []
    if not cluster_candidates(z, np.asarray(is_pair)).any() and not np.any(REPEATED_Z_FLOOR > CLUSTER_SCREEN):
        return []  # nothing within the screen: no pair can be linked
    sigma = np.where(np.isfinite(z_std), z_std, np.inf)
    s_mag = np.abs(continuous_eigenvalues(z, dt)) * dt  # |s| Δτ ≈ |dz/z| per unit relative change of s
    rel = sigma / np.maximum(np.abs(z) * s_mag, 1e-300)
    determined = rel <= CLUSTER_MAX_RELATIVE_STD
    dist = np.abs(z[:, None] - z[None, :])
    with np.errstate(invalid="ignore"):
        floor = REPEATED_Z_FLOOR * np.abs(z)[:, None]
        tol = np.maximum(CLUSTER_SIGMAS * np.hypot(sigma[:, None], sigma[None, :]), floor)
        tol = np.where(determined[:, None] & determined[None, :], tol, floor)
    # within the screen too, so that a model with every σ computed and one with only the candidates' agree
    linked = (dist <= np.minimum(tol, CLUSTER_SCREEN)) & (is_pair[:, None] == is_pair[None, :])
    label = np.arange(k)
    for _ in range(k):  # connected components by label propagation (k is small)
        new = np.array([label[linked[i] | (np.arange(k) == i)].min() for i in range(k)])
        if np.array_equal(new, label):
            break
        label = new
    return [np.flatnonzero(label == g) for g in np.unique(label) if np.count_nonzero(label == g) > 1]


def align_repeated(dec: ModalDecomposition, clusters) -> ModalDecomposition:
    """Rotate the basis of each repeated eigenvalue's eigenspace so that its shapes are as real as possible.

    For a cluster of k modes with shapes Φ (p × k), the eigensolver returns an arbitrary complex combination
    of the true modes inside their eigenspace (any basis of it is an eigenbasis), so μ of each column is
    meaningless. The real k-dimensional subspace closest to span(Φ) is spanned by the k leading left singular
    vectors U_k of the real p × 2k matrix [Re Φ, Im Φ] (exactly span(Φ) when the true modes are real); the new
    basis is Φ T with T = Φ^+ U_k (k × k), so the new shapes are (nearly) real and μ ≈ 1 whatever basis the
    solver returned. The eigenvectors, left eigenvectors, amplitudes and histories are transformed together
    (ψ T, T^{-1} ψ^{-1}, T^{-1} b, T^{-1} q): shapes·amplitudes, hence the reconstruction, are unchanged when
    the eigenvalues are equal. When they differ (by less than their uncertainty), each new mode takes the
    diagonal of T^{-1} diag(z) T (their mean, for a well-conditioned T), which moves the reconstruction by
    O(|Δz|), inside the uncertainty. A cluster of k modes needs p ≥ k sensors; with p = k (Case II's two
    sensors) every basis of R^p is real and μ is 1 trivially.
    """
    if not clusters:
        return dec
    z, shapes, amps = dec.z.copy(), dec.shapes.copy(), dec.amplitudes.copy()
    hist = None if dec.histories is None else dec.histories.copy()
    right = None if dec.right is None else dec.right.copy()
    left = None if dec.left is None else dec.left.copy()
    p = shapes.shape[0]
    for idx in clusters:
        k = len(idx)
        if k > p:
            continue
        phi = shapes[:, idx]
        u, _, _ = np.linalg.svd(np.hstack([phi.real, phi.imag]), full_matrices=False)
        t, *_ = np.linalg.lstsq(phi, u[:, :k].astype(complex), rcond=None)
        if not np.all(np.isfinite(t)) or np.linalg.cond(t) > 1e8:
            continue
        ti = np.linalg.inv(t)
        z[idx] = np.diag(ti @ np.diag(z[idx]) @ t)
        shapes[:, idx] = phi @ t
        amps[idx] = ti @ amps[idx]
        if hist is not None:
            hist[idx] = ti @ hist[idx]
        if right is not None:
            right[:, idx] = right[:, idx] @ t
            left[idx] = ti @ left[idx]
    pair = dec.is_pair
    z = np.where(pair, z, z.real + 0j)
    return _normalised(replace(dec, z=z, shapes=shapes, amplitudes=amps, histories=hist, right=right, left=left))


def _times_real(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """complex (k, n) @ real (n, q) as one real product of twice the rows (half the work of a complex one)."""
    k = left.shape[0]
    both = np.concatenate([left.real, left.imag]) @ right
    return both[:k] + 1j * both[k:]


def continuous_eigenvalues(z: np.ndarray, dt: float) -> np.ndarray:
    """s = ln(z)/Δτ (eq. 41, principal branch, k = 1): rad/s, the member with Im s ≥ 0 of each pair.

    Frequencies above the Nyquist limit 1/(2Δτ) Hz cannot be told from their aliases: the principal
    branch puts every pole in 0 ≤ Im s ≤ π/Δτ. A real negative z gives Im s = π/Δτ (Nyquist). z = 0 is
    taken as |z| = 1e-300 (a pole that dies within one sample), so no logarithm of zero is taken.
    """
    z = np.asarray(z, dtype=complex)
    mag = np.abs(z)
    safe = np.where(mag < _TINY_Z, _TINY_Z + 0j, z)
    return np.log(safe) / dt


def mode_order(z: np.ndarray, dt: float, group: np.ndarray | None = None) -> np.ndarray:
    """The order of a model's modes: by frequency Im s, then |s| (s = ln(z)/Δτ); with ``group`` (an int per
    mode, e.g. each mode's model order in a sweep) by group first, so each group is sorted as its own model."""
    s = continuous_eigenvalues(z, dt)
    keys = (np.abs(s), s.imag) if group is None else (np.abs(s), s.imag, group)
    return np.lexsort(keys)
