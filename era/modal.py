"""The modal model: eigensolution of a realization (eqs. 40-41), its indicators, reduction and reconstruction."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from . import indicators, lapack
from .errors import EraError
from .selection import kept_modes

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
        era.sweep forms those of every order of a sweep in a few large products).

    Shapes are scaled so that their largest component is 1 (real), and amplitudes inversely, so the product
    shapes·amplitudes (the response) is unchanged and shapes are comparable across orders.
    """
    # LAPACK without the GIL (era.lapack), so the orders of a sweep run in parallel threads
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


@dataclass(frozen=True, eq=False)
class ModalModel:
    """A realized discrete-time model x(k+1) = A x(k) + B u(k), y(k) = C x(k) and its modes.

    Attributes
    ----------
    A : (n, n), B : (n, m), C : (p, n)
        Real, discrete time, sampling interval ``dt`` seconds. From :meth:`Identification.realize` in the
        balanced form of eq. 34; after :meth:`select`, in real modal form (2 × 2 blocks as in eq. 57).
    dt : float
        Δτ in seconds.
    z : (modes,) complex
        Discrete eigenvalues, one per mode (the member with Im z ≥ 0 of each pair).
    shapes : (p, modes) complex
        Sensor modal displacements E_p^T P_d ψ (eq. 46), largest component 1.
    amplitudes : (modes, m) complex
        Initial modal amplitudes ψ^{-1} Q^T E_m (eq. 42), scaled so that shapes·amplitudes is the response.
    emac, mpc : (modes,)
        Modal amplitude coherence γ and modal phase collinearity μ, each in [0, 1].
    contribution : (modes,)
        Each mode's Frobenius norm in H(0) (units of the singular values): see indicators.contribution.
    is_pair : (modes,) bool
        True for a complex-conjugate pair, False for a real pole.
    outputs, inputs : tuple of str
        Channel labels (p and m).
    method : str
        "ERA", "A1" or "A2".
    frequency_std_hz, damping_std : (modes,)
        Standard deviation of the damped frequency (Hz) and of the damping ratio that the data determine, to
        first order from the scatter of the Hankel matrices (era.uncertainty: residual blocks of the record,
        or the records' scatter). A 95 % interval is value ± 1.96·std (:meth:`frequency_interval_hz`,
        :meth:`damping_interval`). NaN where not computed (A1/A2, or ``uncertainty=False``). For a repeated
        mode (a cluster, see era.modal.align_repeated) the largest of the cluster's.
    uncertainty_source : str
        Which covariance gave them: "σ from N records" (the scatter of independent records) or "σ from one
        record's residuals" (residual blocks); "" when not computed.
    points : tuple of str
        A label per measured point, each once (issue 26): by default the outputs. A test whose inputs were at known
        points (a roving hammer) or a merge of several setups (era.merge_setups) adds the struck points and the
        roving sensors.
    point_shapes : (n_points, modes) complex
        The mode shape at each of ``points``, largest component 1: by default ``shapes``.

    Modes are sorted by frequency (then by |s|). Modes whose eigenvalues coincide within their uncertainty (a
    repeated mode) are given the basis of their eigenspace that makes their shapes most real (align_repeated).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    dt: float
    z: np.ndarray
    shapes: np.ndarray
    amplitudes: np.ndarray
    emac: np.ndarray
    mpc: np.ndarray
    contribution: np.ndarray
    is_pair: np.ndarray
    outputs: tuple = ()
    inputs: tuple = ()
    method: str = "ERA"
    frequency_std_hz: np.ndarray | None = None
    damping_std: np.ndarray | None = None
    uncertainty_source: str = ""
    points: tuple = ()
    point_shapes: np.ndarray | None = None

    def __post_init__(self):
        if not self.points and self.point_shapes is None:  # by default the points are the sensors
            object.__setattr__(self, "points", tuple(self.outputs))
            object.__setattr__(self, "point_shapes", self.shapes)

    # ---- derived modal parameters -------------------------------------------------------------
    @property
    def order(self) -> int:
        """n, the state dimension."""
        return self.A.shape[0]

    @property
    def n_modes(self) -> int:
        return len(self.z)

    @property
    def eigenvalues(self) -> np.ndarray:
        """Continuous-time eigenvalues s (rad/s), shape (modes,): s = ln(z)/Δτ (eq. 41), Im s ≥ 0."""
        return continuous_eigenvalues(self.z, self.dt)

    @property
    def frequency_hz(self) -> np.ndarray:
        """Damped natural frequency Im(s)/2π in Hz, shape (modes,); 0 for a real positive pole.

        The paper's eq. 41 reads the damped frequency off Im s. Modes above the Nyquist frequency
        1/(2Δτ) alias below it; a real negative z sits at the Nyquist frequency.
        """
        return self.eigenvalues.imag / (2 * np.pi)

    @property
    def natural_frequency_hz(self) -> np.ndarray:
        """Undamped natural frequency |s|/2π in Hz, shape (modes,) (what a finite-element model gives)."""
        return np.abs(self.eigenvalues) / (2 * np.pi)

    def frequency_interval_hz(self, level_z: float = 1.959963984540054) -> tuple[np.ndarray, np.ndarray]:
        """(low, high) of the 95 % interval frequency_hz ± 1.96 σ (``level_z`` another normal quantile), Hz."""
        f, sd = self.frequency_hz, self._std(self.frequency_std_hz)
        return f - level_z * sd, f + level_z * sd

    def damping_interval(self, level_z: float = 1.959963984540054) -> tuple[np.ndarray, np.ndarray]:
        """(low, high) of the 95 % interval damping_ratio ± 1.96 σ."""
        z, sd = self.damping_ratio, self._std(self.damping_std)
        return z - level_z * sd, z + level_z * sd

    def standard_deviations(self) -> tuple[np.ndarray, np.ndarray]:
        """(frequency_std_hz (modes,) Hz, damping_std (modes,)): NaN where the data determined none (or all NaN
        when no uncertainty was computed)."""
        return self._std(self.frequency_std_hz), self._std(self.damping_std)

    def _std(self, value) -> np.ndarray:
        return np.full(self.n_modes, np.nan) if value is None else np.asarray(value, dtype=float)

    @property
    def damping_ratio(self) -> np.ndarray:
        """Damping ratio ζ = -Re(s)/|s|, shape (modes,); negative for a growing (unstable) mode, 0 when s = 0."""
        s = self.eigenvalues
        mag = np.abs(s)
        out = np.zeros(len(s))
        np.divide(-s.real, mag, out=out, where=mag > 0)
        return out

    # ---- model reduction (section III) ---------------------------------------------------------
    def select(self, indices=None, *, min_emac: float | None = None, min_mpc: float | None = None,
               min_contribution: float | None = None, physical_only: bool = False) -> "ModalModel":
        """The reduced model that keeps some modes (model reduction, section III).

        Parameters
        ----------
        indices : sequence of int or bool mask, optional
            Modes to keep (positions in this model's mode order). Default: all.
        min_emac, min_mpc : float in [0, 1], optional
            Keep only modes with γ ≥ min_emac and μ ≥ min_mpc.
        min_contribution : float, optional
            Keep only modes whose contribution is at least this fraction of the largest one.
        physical_only : bool
            Keep only complex pairs that decay (0 < ζ < 1).

        The rule is :func:`era.selection.kept_modes` (named modes AND thresholds).

        Returns
        -------
        ModalModel in real modal form: each pair a 2 × 2 block [[Re z, -Im z], [Im z, Re z]], each real
        pole a 1 × 1 block. Its indicators are those of the kept modes.
        """
        return self._subset(kept_modes(self, indices, min_emac=min_emac, min_mpc=min_mpc,
                                       min_contribution=min_contribution, physical_only=physical_only))

    def channel(self, output: int, input: int) -> "ModalModel":
        """The one-channel view: output ``output`` (0..p-1) for input ``input`` (0..m-1), shape (1, 1).

        C keeps that output's row and B that input's column, shapes and amplitudes likewise, so the view
        reconstructs exactly that channel of :meth:`reconstruct` (p·m times less work). γ, μ and the
        contribution stay those of the whole model (they judge a mode, not a channel).
        """
        p, m = self.shapes.shape[0], self.amplitudes.shape[1]
        for value, size, name in ((output, p, "output"), (input, m, "input")):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value < size:
                raise EraError(f"`{name}` must be 0..{size - 1} (this model has {size} {name}s), got {value!r}.")
        i, j = int(output), int(input)
        return replace(self, B=self.B[:, j:j + 1], C=self.C[i:i + 1], shapes=self.shapes[i:i + 1],
                       amplitudes=self.amplitudes[:, j:j + 1], outputs=self.outputs[i:i + 1],
                       inputs=self.inputs[j:j + 1])

    def _subset(self, idx: np.ndarray) -> "ModalModel":
        z, c, b, pair = self.z[idx], self.shapes[:, idx], self.amplitudes[idx], self.is_pair[idx]
        n = int(np.sum(np.where(pair, 2, 1)))
        p, m = self.shapes.shape[0], self.amplitudes.shape[1]
        A, B, C = np.zeros((n, n)), np.zeros((n, m)), np.zeros((p, n))
        k = 0
        for j in range(len(idx)):
            if pair[j]:
                # ξ = x1 + i x2 with ξ(k+1) = z ξ(k) + b u and y = 2 Re(c ξ)
                A[k:k + 2, k:k + 2] = [[z[j].real, -z[j].imag], [z[j].imag, z[j].real]]
                B[k], B[k + 1] = b[j].real, b[j].imag
                C[:, k], C[:, k + 1] = 2 * c[:, j].real, -2 * c[:, j].imag
                k += 2
            else:
                A[k, k], B[k], C[:, k] = z[j].real, b[j].real, c[:, j].real
                k += 1
        return replace(self, A=A, B=B, C=C, z=z, shapes=c, amplitudes=b, emac=self.emac[idx],
                       point_shapes=None if self.point_shapes is None else self.point_shapes[:, idx],
                       mpc=self.mpc[idx], contribution=self.contribution[idx], is_pair=pair,
                       frequency_std_hz=self._std(self.frequency_std_hz)[idx],
                       damping_std=self._std(self.damping_std)[idx])

    # ---- reconstruction (eq. 35) ---------------------------------------------------------------
    def reconstruct(self, n_samples: int) -> np.ndarray:
        """Y(k) = C A^k B for k = 0..n_samples-1 from the modes (eq. 35), shape (n_samples, p, m).

        Summed in modal form: Y(k) = Σ_pairs 2 Re(c_j z_j^k b_j) + Σ_real c_j z_j^k b_j.
        """
        n_samples = int(n_samples)
        if n_samples < 0:
            raise EraError(f"`n_samples` must be ≥ 0, got {n_samples}.")
        return modal_sum(self.z, self.shapes, self.amplitudes, self.is_pair, n_samples)

    def fit_error(self, markov) -> np.ndarray:
        """Normalised RMS error of the reconstruction against measured Y, per channel: shape (p, m).

        ``markov`` is an (N, p, m) array or a ResponseData. The error of channel (i, j) is
        ‖Y_ij - Ŷ_ij‖ / ‖Y_ij‖ over the N samples (0 is a perfect fit; the fit in percent is 100 (1 - e)).
        A channel that is zero throughout gets 0 if the reconstruction is zero too, else inf.
        """
        y = np.asarray(getattr(markov, "markov", markov), dtype=float)
        if y.ndim != 3 or y.shape[1:] != (self.shapes.shape[0], self.amplitudes.shape[1]):
            raise EraError(f"The measured data have shape {y.shape}; this model reconstructs (N, "
                           f"{self.shapes.shape[0]}, {self.amplitudes.shape[1]}).")
        err = np.linalg.norm(y - self.reconstruct(y.shape[0]), axis=0)
        ref = np.linalg.norm(y, axis=0)
        out = np.where(err == 0, 0.0, np.inf)
        np.divide(err, ref, out=out, where=ref > 0)
        return out


def mode_order(z: np.ndarray, dt: float, group: np.ndarray | None = None) -> np.ndarray:
    """The order of a model's modes: by frequency Im s, then |s| (s = ln(z)/Δτ); with ``group`` (an int per
    mode, e.g. each mode's model order in a sweep) by group first, so each group is sorted as its own model."""
    s = continuous_eigenvalues(z, dt)
    keys = (np.abs(s), s.imag) if group is None else (np.abs(s), s.imag, group)
    return np.lexsort(keys)


def build_model(A, B, C, W, dt, row_shifts, col_shifts, outputs=(), inputs=(), method="ERA", *,
                dec: ModalDecomposition | None = None, frequency_std_hz=None, damping_std=None,
                uncertainty_source: str = "") -> ModalModel:
    """The ModalModel of the realization (A, B, C) whose state history at the column shifts is W (n, s·m).

    ``dec`` is its decomposition when the caller already has it (aligned for repeated modes,
    Identification.model); frequency_std_hz, damping_std : (modes,) in the order of ``dec``, or None.
    """
    if dec is None:
        dec = decompose(A, B, C, W)
    nan = np.full(dec.z.size, np.nan)
    f_std = nan if frequency_std_hz is None else np.asarray(frequency_std_hz, dtype=float)
    d_std = nan if damping_std is None else np.asarray(damping_std, dtype=float)
    growth = indicators.powers(dec.z, col_shifts)  # z_j^{t_i}, shared by γ and the contribution
    gamma = indicators.emac(dec.histories, dec.z, col_shifts, B.shape[1], growth)
    mu = indicators.mpc(dec.shapes)
    contrib = indicators.contribution(dec.shapes, dec.amplitudes, dec.z, row_shifts, col_shifts, dec.is_pair,
                                      growth)
    order = mode_order(dec.z, dt)
    return ModalModel(A=A, B=B, C=C, dt=dt, z=dec.z[order], shapes=dec.shapes[:, order],
                      amplitudes=dec.amplitudes[order], emac=gamma[order], mpc=mu[order],
                      contribution=contrib[order], is_pair=dec.is_pair[order], outputs=tuple(outputs),
                      inputs=tuple(inputs), method=method, frequency_std_hz=f_std[order], damping_std=d_std[order],
                      uncertainty_source=uncertainty_source)
