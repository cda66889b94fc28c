"""How well the data determine each pole: standard deviations of frequency and damping propagated to first order
from the scatter of the Hankel matrices (the covariance-driven SSI literature: Reynders, Pintelon & De Roeck 2008;
Döhler & Mevel 2013), evaluated without ever forming the covariance of H.

The first-order step (matrix pencil perturbation, Hua & Sarkar 1990)
-------------------------------------------------------------------
An order-n ERA pole z_j is an eigenvalue of the pencil (H(1), H(0)) restricted to the leading singular subspaces:
with ψ_j the right eigenvector of A (eq. 34, balanced form) and w_j the matching row of ψ^{-1},

    a_j = w_j D_n^{-1/2} P_n^T  (1, r p),     b_j = Q_n D_n^{-1/2} ψ_j  (s m, 1),     a_j H(0) b_j = 1,

and a_j (H(1) - z_j H(0)) b_j = 0. A perturbation ΔH(0), ΔH(1) of the Hankel matrices moves the pole by

    Δz_j = a_j (ΔH(1) - z_j ΔH(0)) b_j                                                       (1)

to first order; the change of the singular subspaces P_n, Q_n (the SVD's own sensitivity, which Reynders et al.
propagate explicitly) drops out of (1) because (H(1) - z_j H(0)) vanishes on b_j and a_j. Both Hankel matrices are
built from the same samples Y(k) (eq. 16), so (1) is a linear functional of the sample errors E(k):

    Δz_j = Σ_k ⟨G_j(k), E(k)⟩,   G_j(k) = G0_j(k - 1) - z_j G0_j(k),
    G0_j(k) = Σ_{j_i + t_l = k} a_j[i] b_j[l]^T

(p × m blocks a_j[i], b_j[l] of a_j and b_j; :func:`pole_functionals` computes G by FFT convolution over the
shifts).
Its variance needs the covariance of the E(k), which comes from the data in one of two ways:

* **Residual blocks** (:func:`residual_covariance`, the default; one record). The errors are estimated by the
  residual R(k) = Y(k) - Ŷ(k) of the order-n model over the samples H(0) and H(1) use. The samples are split into
  consecutive blocks of L samples, long enough that the residual is uncorrelated from one block to the next
  (L from the residual's own autocorrelation: L = 1 for white noise), and the sum of the functional over each
  block is one independent draw: Cov(Re Δz, Im Δz) = Σ_blocks s s^T with s = Σ_{k in block} ⟨G_j(k), R(k)⟩,
  times
  n_obs / (n_obs - n (p + m)) for the parameters the fit absorbed. This is the heteroscedasticity- and
  (within L) autocorrelation-consistent "sandwich" estimate: no noise level or spectrum is assumed, only that
  errors more than L samples apart are independent. A single pulse response or free decay cannot be split into
  records (its signal decays), which is why its blocks are taken in the residual and not in Y.
* **Records** (:func:`record_covariance`). When Y is the mean of n_b independent records (repeated hits, averaged
  free decays, NExT segments), the scatter of the records about their mean is the sample covariance of H that
  Reynders et al. use, evaluated through (1): Cov = Σ_b s_b s_b^T / (n_b (n_b - 1)),
  s_b = Σ_k ⟨G_j(k), Y_b(k) - Y(k)⟩.
  No model residual and no independence in time are needed; n_b should be ≥ 10 or so for a stable estimate.
  Identification uses it by itself when the data carry at least MIN_RECORDS = 5 records (ResponseData.records,
  filled by era.markov from several comparable records), and says which was used (ModalModel.uncertainty_source).

Frequency and damping follow from z by the chain rule through s = ln(z)/Δτ (eq. 41); :func:`modal_std`.
95 % intervals are ±1.96 σ (first-order Gaussian); tests/core/test_uncertainty.py checks their coverage on
synthetic data of known noise over 200 draws.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft

#: two-sided 95 % normal quantile: a 95 % interval is value ± Z95 · std.
Z95 = 1.959963984540054

#: fewest records whose scatter replaces the residual blocks (Identification.pole_covariance). The variance from
#: n_b records has n_b - 1 degrees of freedom: at 5 its own relative error is about 1/√(2·4) = 35 % and a
#: ±1.96 σ interval still holds the truth in about 88 % of cases (Student's t at 4 degrees of freedom); at 2 or 3
#: it would be 70 %+ and 60-75 %, worse than the residual blocks (≥ 20 blocks) of the mean record.
MIN_RECORDS = 5

#: modes handled per FFT batch in pole_functionals (bounds the memory at ~ chunk · n_fft · p · m complex numbers).
_CHUNK = 16


@dataclass(frozen=True)
class PoleCovariance:
    """The first-order covariance of each discrete pole.

    z_cov : (k, 2, 2) covariance of (Re z_j, Im z_j); method : "residual blocks" or "records";
    n_blocks : independent blocks (or records) it was estimated from; block_length : samples per block (1 for
    records).
    """

    z_cov: np.ndarray
    method: str
    n_blocks: int
    block_length: int

    @property
    def source(self) -> str:
        """Where σ came from, for tables and reports: "σ from N records" or "σ from one record's residuals"."""
        return source_label(self.n_blocks if self.method == "records" else 0)


def source_label(n_records: int, segments: bool = False) -> str:
    """"σ from N records" when the scatter of n_records ≥ 2 records is used ("σ from N segments of the record"
    when they are consecutive segments of one record, era.markov_from_ambient), else "σ from one record's
    residuals"."""
    if n_records < 2:
        return "σ from one record's residuals"
    return f"σ from {n_records} segments of the record" if segments else f"σ from {n_records} records"


def pole_functionals(left: np.ndarray, right: np.ndarray, z: np.ndarray, row_shifts: np.ndarray,
                     col_shifts: np.ndarray, errors: np.ndarray) -> np.ndarray:
    """Each sample's share of the first-order pole change: ⟨G_j(k), E(k)⟩ for every mode j, error set and sample k.

    G_j(k) = G0_j(k - 1) - z_j G0_j(k) with G0_j the convolution over the shifts of the blocks of a_j and b_j
    (module docstring), computed by FFT in single precision (the result is a standard deviation: 1e-6 relative
    is plenty) and contracted with the errors chunk by chunk, so G is never held for all modes at once.

    Parameters
    ----------
    left : (modes, r p) complex, the a_j; right : (modes, s m) complex, the b_j^T; z : (modes,) poles.
    row_shifts, col_shifts : (r,), (s,) int, the shifts of eq. 16.
    errors : (sets, T, p, m) real, T = j_{r-1} + t_{s-1} + 2: error estimates of the samples Y(0..T-1)
        (residuals, or records minus their mean).

    Returns
    -------
    (modes, sets, T) complex; summed over k it is Δz_j for that error set.
    """
    modes = left.shape[0]
    sets, t, p, m = errors.shape
    r, s = len(row_shifts), len(col_shifts)
    length = int(row_shifts[-1] + col_shifts[-1] + 1)  # G0 at k = 0 .. j_{r-1} + t_{s-1}
    if t != length + 1:
        raise ValueError(f"errors cover {t} samples; H(0) and H(1) use {length + 1}.")
    n_fft = scipy.fft.next_fast_len(length)
    e = np.ascontiguousarray(errors.transpose(0, 2, 3, 1), dtype=np.float32)  # (sets, p, m, T): time last
    out = np.zeros((modes, sets, t), dtype=complex)
    for lo in range(0, modes, _CHUNK):
        hi = min(lo + _CHUNK, modes)
        a = np.zeros((hi - lo, p, n_fft), dtype=np.complex64)
        b = np.zeros((hi - lo, m, n_fft), dtype=np.complex64)
        a[:, :, row_shifts] = left[lo:hi].reshape(hi - lo, r, p).transpose(0, 2, 1)
        b[:, :, col_shifts] = right[lo:hi].reshape(hi - lo, s, m).transpose(0, 2, 1)
        fa, fb = scipy.fft.fft(a, axis=-1), scipy.fft.fft(b, axis=-1)
        g0 = scipy.fft.ifft(fa[:, :, None, :] * fb[:, None, :, :], axis=-1, overwrite_x=True)[..., :length]
        g0 = g0.reshape(hi - lo, p * m, length)
        ee = e.reshape(sets, p * m, t)
        # sample k enters H(1) where H(0) has k - 1: ⟨G0(k-1), E(k)⟩ - z ⟨G0(k), E(k)⟩
        for k in range(sets):
            out[lo:hi, k, 1:] += np.einsum("jck,ck->jk", g0, ee[k, :, 1:])
            out[lo:hi, k, :-1] -= z[lo:hi, None] * np.einsum("jck,ck->jk", g0, ee[k, :, :-1])
    return out


def block_sums(per_sample: np.ndarray, block_length: int) -> np.ndarray:
    """Sums of (modes, T) over consecutive blocks of ``block_length`` samples: (modes, blocks)."""
    t = per_sample.shape[1]
    n_blocks = t // block_length
    head = per_sample[:, :n_blocks * block_length].reshape(per_sample.shape[0], n_blocks, block_length).sum(axis=2)
    if t > n_blocks * block_length:  # the remainder is one more (shorter) block
        head = np.concatenate([head, per_sample[:, n_blocks * block_length:].sum(axis=1, keepdims=True)], axis=1)
    return head


def _outer_real(sums: np.ndarray) -> np.ndarray:
    """Σ_β [Re s, Im s] [Re s, Im s]^T per mode: (modes, 2, 2)."""
    parts = np.stack([sums.real, sums.imag], axis=1)  # (modes, 2, blocks)
    return np.einsum("jab,jcb->jac", parts, parts)


def correlation_length(residual: np.ndarray, max_length: int) -> int:
    """Block length L in samples: the first lag at which the residual's autocorrelation (pooled over channels)
    is within noise (|ρ| < 3/√(samples·channels)), capped at ``max_length``; 1 for white noise."""
    e = residual.reshape(residual.shape[0], -1)
    energy = float(np.sum(e * e))
    if energy == 0.0:
        return 1
    threshold = 3.0 / np.sqrt(e.size)
    for lag in range(1, max(1, max_length)):
        rho = float(np.sum(e[lag:] * e[:-lag])) / energy
        if abs(rho) < threshold:
            return lag
    return max(1, max_length)


def residual_covariance(left: np.ndarray, right: np.ndarray, z: np.ndarray, row_shifts: np.ndarray,
                        col_shifts: np.ndarray, residual: np.ndarray, n_parameters: int,
                        block_length: int | None = None, min_blocks: int = 20) -> PoleCovariance:
    """Pole covariance from the residual of the model over the samples (residual blocks; module docstring).

    Parameters
    ----------
    left, right, z, row_shifts, col_shifts : as in :func:`pole_functionals`.
    residual : (T, p, m) real, Y(k) - Ŷ(k) over the samples H(0) and H(1) use.
    n_parameters : parameters fitted, n (p + m) for an order-n realization (degrees-of-freedom correction).
    block_length : samples per block; default :func:`correlation_length`, at most T / min_blocks.
    """
    t = residual.shape[0]
    if block_length is None:
        block_length = correlation_length(residual, max(1, t // min_blocks))
    block_length = int(max(1, block_length))
    per_sample = pole_functionals(left, right, z, row_shifts, col_shifts, residual[None])[:, 0]
    cov = _outer_real(block_sums(per_sample, block_length))
    n_obs = residual.size
    if n_obs > 2 * n_parameters:
        cov = cov * (n_obs / (n_obs - n_parameters))
    return PoleCovariance(z_cov=cov, method="residual blocks", n_blocks=-(-t // block_length),
                          block_length=block_length)


def record_covariance(left: np.ndarray, right: np.ndarray, z: np.ndarray, row_shifts: np.ndarray,
                      col_shifts: np.ndarray, records: np.ndarray) -> PoleCovariance:
    """Pole covariance of a mean of independent records (Reynders et al. 2008; module docstring).

    records : (n_b, ≥T, p, m) real, the records whose mean is the identified Y. Their scatter about the mean,
    divided by n_b (n_b - 1), is the covariance of the mean's errors.
    """
    records = np.asarray(records, dtype=float)
    n_b = records.shape[0]
    if n_b < 2:
        raise ValueError("record_covariance needs at least 2 records.")
    t = int(row_shifts[-1] + col_shifts[-1] + 2)
    dev = records[:, :t] - records[:, :t].mean(axis=0)
    sums = pole_functionals(left, right, z, row_shifts, col_shifts, dev).sum(axis=2)  # (modes, n_b)
    return PoleCovariance(z_cov=_outer_real(sums) / (n_b * (n_b - 1)), method="records", n_blocks=n_b,
                          block_length=1)


def modal_std(z: np.ndarray, z_cov: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Standard deviations of the damped frequency (Hz) and of the damping ratio, each (modes,), from the
    covariance (modes, 2, 2) of (Re z, Im z), through s = ln(z)/Δτ (eq. 41), f = Im s / 2π, ζ = -Re s / |s|."""
    z = np.asarray(z, dtype=complex)
    c = 1.0 / (np.where(z == 0, 1e-300, z) * dt)  # ds = c dz
    jac_s = np.empty(z.shape + (2, 2))
    jac_s[:, 0, 0], jac_s[:, 0, 1] = c.real, -c.imag
    jac_s[:, 1, 0], jac_s[:, 1, 1] = c.imag, c.real
    s = np.log(np.where(z == 0, 1e-300, z)) / dt
    mag = np.abs(s)
    safe = np.where(mag > 0, mag, 1.0)
    grad_f = jac_s[:, 1, :] / (2 * np.pi)  # f = Im s / 2π
    grad_zeta = np.stack([-(s.imag**2) / safe**3, s.real * s.imag / safe**3], axis=1)  # ∂ζ/∂(Re s, Im s)
    grad_zeta = np.einsum("ja,jab->jb", grad_zeta, jac_s)
    var_f = np.einsum("ja,jab,jb->j", grad_f, z_cov, grad_f)
    var_zeta = np.einsum("ja,jab,jb->j", grad_zeta, z_cov, grad_zeta)
    return np.sqrt(np.maximum(var_f, 0.0)), np.sqrt(np.maximum(var_zeta, 0.0))
