"""The modal model: eigensolution of a realization (eqs. 40-41), its indicators, reduction and reconstruction."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg

from . import indicators
from .errors import EraError
from .selection import kept_modes

#: |z| below this is treated as this (z = 0 has no logarithm); such a pole decays within one sample.
_TINY_Z = 1e-300


@dataclass(frozen=True)
class ModalDecomposition:
    """Per-mode arrays of an eigen-decomposition, one entry per mode (a conjugate pair is one mode).

    z : (modes,) complex discrete eigenvalues (the member with Im z ≥ 0); shapes : (p, modes) complex;
    amplitudes : (modes, m) complex; histories : (modes, s·m) modal amplitude histories ψ^{-1} W;
    is_pair : (modes,) bool, True for a complex-conjugate pair.
    """

    z: np.ndarray
    shapes: np.ndarray
    amplitudes: np.ndarray
    histories: np.ndarray
    is_pair: np.ndarray


def decompose(A: np.ndarray, B: np.ndarray, C: np.ndarray, W: np.ndarray) -> ModalDecomposition:
    """Eigen-decompose A ψ = ψ z (eq. 40) and express B, C and the state history W in modal coordinates.

    Parameters
    ----------
    A : (n, n) real; B : (n, m) real; C : (p, n) real
    W : (n, s·m) real: the state at the column shifts (its first m columns are the initial state B for ERA
        and A1). Its rows projected on the left eigenvectors are the modal histories of eq. 44.

    Shapes are scaled so that their largest component is 1 (real), and amplitudes inversely, so the product
    shapes·amplitudes (the response) is unchanged and shapes are comparable across orders.
    """
    z_all, psi = scipy.linalg.eig(A, check_finite=False)
    keep = z_all.imag >= 0  # LAPACK returns exact conjugate pairs and exactly real eigenvalues
    try:
        left = scipy.linalg.inv(psi, check_finite=False)[keep]  # rows of ψ^{-1} for the kept modes
    except (np.linalg.LinAlgError, ValueError):
        left = np.linalg.pinv(psi)[keep]  # defective A (a Jordan block): best effort
    z = z_all[keep]
    is_pair = z.imag > 0
    z = np.where(is_pair, z, z.real + 0j)
    shapes = C @ psi[:, keep]
    amplitudes = _times_real(left, B)
    histories = _times_real(left, W)
    # normalise: largest shape component = 1
    if shapes.size:
        big = shapes[np.argmax(np.abs(shapes), axis=0), np.arange(shapes.shape[1])]
        scale = np.where(np.abs(big) > 0, big, 1.0)
        shapes = shapes / scale
        amplitudes = amplitudes * scale[:, None]
        histories = histories * scale[:, None]
    return ModalDecomposition(z=z, shapes=shapes, amplitudes=amplitudes, histories=histories, is_pair=is_pair)


def _times_real(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """complex (k, n) @ real (n, q) as two real products (half the work of a complex one)."""
    return (left.real @ right) + 1j * (left.imag @ right)


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

    Modes are sorted by frequency (then by |s|).
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
                       mpc=self.mpc[idx], contribution=self.contribution[idx], is_pair=pair)

    # ---- reconstruction (eq. 35) ---------------------------------------------------------------
    def reconstruct(self, n_samples: int) -> np.ndarray:
        """Y(k) = C A^k B for k = 0..n_samples-1 from the modes (eq. 35), shape (n_samples, p, m).

        Summed in modal form: Y(k) = Σ_pairs 2 Re(c_j z_j^k b_j) + Σ_real c_j z_j^k b_j.
        """
        n_samples = int(n_samples)
        if n_samples < 0:
            raise EraError(f"`n_samples` must be ≥ 0, got {n_samples}.")
        weight = np.where(self.is_pair, 2.0, 1.0)
        zk = indicators.powers(self.z, np.arange(n_samples)).T * weight  # (N, modes)
        p, m = self.shapes.shape[0], self.amplitudes.shape[1]
        residues = np.einsum("pj,jm->jpm", self.shapes, self.amplitudes).reshape(-1, p * m)  # (modes, p m)
        with np.errstate(over="ignore", invalid="ignore"):
            y = zk.real @ residues.real - zk.imag @ residues.imag  # Re(zk @ residues) as two real products
        return y.reshape(n_samples, p, m)

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


def build_model(A, B, C, W, dt, row_shifts, col_shifts, outputs=(), inputs=(), method="ERA") -> ModalModel:
    """The ModalModel of the realization (A, B, C) whose state history at the column shifts is W (n, s·m)."""
    dec = decompose(A, B, C, W)
    gamma = indicators.emac(dec.histories, dec.z, col_shifts, B.shape[1])
    mu = indicators.mpc(dec.shapes)
    contrib = indicators.contribution(dec.shapes, dec.amplitudes, dec.z, row_shifts, col_shifts, dec.is_pair)
    s = continuous_eigenvalues(dec.z, dt)
    order = np.lexsort((np.abs(s), s.imag))
    return ModalModel(A=A, B=B, C=C, dt=dt, z=dec.z[order], shapes=dec.shapes[:, order],
                      amplitudes=dec.amplitudes[order], emac=gamma[order], mpc=mu[order],
                      contribution=contrib[order], is_pair=dec.is_pair[order], outputs=tuple(outputs),
                      inputs=tuple(inputs), method=method)
