"""Ambient records of physical structures whose modes are known independently of any identification: a chain of
masses and springs (a shear building) with modal damping, its truth the eigenvalues of its own state matrix
(scipy.linalg.eig of [[0, I], [-M⁻¹K, -M⁻¹C]]), its response simulated exactly (zero-order-hold discretization
of the continuous system, white modal forces), plus white sensor noise. Used by tests/core/test_oma_coverage.py
and tests/bench/bench_oma_uncertainty.py."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
from scipy.signal import lfilter


@dataclass(frozen=True)
class Structure:
    """M, K, C (n, n); frequency_hz (n,) damped, damping_ratio (n,) from eig of the state matrix, by frequency;
    shapes (n, n) mass-normalized undamped shapes (columns); force (n,) the modal force level of each mode."""

    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    force: np.ndarray


def shear_building(n: int, lowest_hz: float, highest_hz: float, damping, strength, seed: int = 0) -> Structure:
    """An n-storey shear building with masses and stiffnesses drawn at random (seed) and scaled so its modes lie
    in [lowest_hz, highest_hz]; modal damping ``damping`` (n,) (C = M Φ diag(2 ζ ω) Φᵀ M) and modal forces
    scaled so each mode's acceleration rms is ``strength`` (n,) relative units (10 × weaker: 0.1)."""
    rng = np.random.default_rng(seed)
    m = rng.uniform(0.8, 1.2, n)
    k = rng.uniform(0.6, 1.4, n)
    K = np.diag(k + np.r_[k[1:], 0.0]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    M = np.diag(m)
    w2, phi = scipy.linalg.eigh(K, M)
    # squeeze the spectrum into the band: K' = M Φ diag(ω'²) Φᵀ M keeps the shapes, sets the frequencies
    w = np.sqrt(w2)
    lo, hi = 2 * np.pi * lowest_hz, 2 * np.pi * highest_hz
    w_new = lo * (hi / lo) ** ((w - w[0]) / max(w[-1] - w[0], 1e-12)) if n > 1 else np.array([lo])
    K = M @ phi @ np.diag(w_new ** 2) @ phi.T @ M
    zeta = np.broadcast_to(np.asarray(damping, float), (n,))
    C = M @ phi @ np.diag(2 * zeta * w_new) @ phi.T @ M
    a = np.broadcast_to(np.asarray(strength, float), (n,)) * np.sqrt(zeta / w_new)  # accel. variance ∝ a² ω / ζ
    f_hz, z_true = state_modes(M, K, C)
    return Structure(M=M, K=K, C=C, frequency_hz=f_hz, damping_ratio=z_true, shapes=phi, force=a / a.max())


def state_matrix(M, K, C) -> np.ndarray:
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])


def state_modes(M, K, C) -> tuple[np.ndarray, np.ndarray]:
    """Damped frequencies (Hz) and damping ratios of the eigenvalues λ of the state matrix (Im λ > 0), by
    frequency: f = Im λ / 2π, ζ = -Re λ / |λ| (the definitions era.ModalModel reports)."""
    lam = scipy.linalg.eigvals(state_matrix(M, K, C))
    lam = np.sort_complex(lam[lam.imag > 0])
    lam = lam[np.argsort(lam.imag)]
    return lam.imag / (2 * np.pi), -lam.real / np.abs(lam)


def ambient(structure: Structure, dt: float, duration_s: float, noise: float = 0.05, seed: int = 0,
            sensors=None) -> np.ndarray:
    """(N, p) accelerations of ``sensors`` (default every mass) under independent white modal forces, exact for
    the zero-order-held force (so the correlations decay with exp(λ Δτ) exactly), plus white noise of
    ``noise`` × each channel's rms."""
    s = structure
    n = s.M.shape[0]
    sensors = np.arange(n) if sensors is None else np.asarray(sensors)
    Minv = np.linalg.inv(s.M)
    A = state_matrix(s.M, s.K, s.C)
    B = np.vstack([np.zeros((n, n)), s.shapes * s.force[None, :]])  # M⁻¹ (M Φ diag(a)) = Φ diag(a)
    Cy = np.hstack([-Minv @ s.K, -Minv @ s.C])[sensors]
    D = (s.shapes * s.force[None, :])[sensors]
    big = np.zeros((3 * n, 3 * n))
    big[:2 * n, :2 * n], big[:2 * n, 2 * n:] = A * dt, B * dt
    e = scipy.linalg.expm(big)
    Ad, Bd = e[:2 * n, :2 * n], e[:2 * n, 2 * n:]
    lam, V = np.linalg.eig(Ad)
    Vinv = np.linalg.inv(V)
    rng = np.random.default_rng(seed)
    keep = int(round(duration_s / dt))
    steps = keep + keep // 10 + 1  # a start-up transient first (the state starts at rest), dropped below
    w = rng.standard_normal((steps, n)) / np.sqrt(dt)  # white force of unit two-sided PSD
    drive = (Vinv @ Bd) @ w.T  # (2n, N)
    eta = np.empty((2 * n, steps), dtype=complex)
    for i in range(2 * n):
        eta[i, 0] = 0.0
        eta[i, 1:] = lfilter([1.0], [1.0, -lam[i]], drive[i, :-1])
    y = ((Cy @ V) @ eta).real.T + w @ D.T
    y = y[steps - keep:]
    rms = np.sqrt(np.mean(y ** 2, axis=0, keepdims=True))
    return y + rng.standard_normal(y.shape) * rms * noise


def pulse(structure: Structure, dt: float, duration_s: float, inputs=(0,), noise: float = 0.05,
          seed: int = 0) -> np.ndarray:
    """(N, n, m) acceleration pulse responses Y(k) = C A_d^(k-1) B_d, k = 1..N, to unit zero-order-held force
    pulses at the masses ``inputs`` (a hammer test's impulse responses, or free decays), plus white noise of
    ``noise`` × each output's rms."""
    s = structure
    n = s.M.shape[0]
    Minv = np.linalg.inv(s.M)
    A = state_matrix(s.M, s.K, s.C)
    B = np.vstack([np.zeros((n, n)), Minv])[:, list(inputs)]
    Cy = np.hstack([-Minv @ s.K, -Minv @ s.C])
    big = np.zeros((2 * n + B.shape[1],) * 2)
    big[:2 * n, :2 * n], big[:2 * n, 2 * n:] = A * dt, B * dt
    e = scipy.linalg.expm(big)
    Ad, Bd = e[:2 * n, :2 * n], e[:2 * n, 2 * n:]
    steps = int(round(duration_s / dt))
    y = np.empty((steps, n, B.shape[1]))
    x = Bd.copy()
    for k in range(steps):
        y[k] = Cy @ x
        x = Ad @ x
    rng = np.random.default_rng(seed)
    rms = np.sqrt(np.mean(y ** 2, axis=(0, 2), keepdims=True))
    return y + rng.standard_normal(y.shape) * rms * noise


def accelerance(structure: Structure, frequencies_hz, inputs=(0,), noise: float = 0.05,
                seed: int = 0) -> np.ndarray:
    """(K, n, m) FRFs H(f) = -ω² (K - ω² M + iω C)⁻¹ of acceleration to force at ``inputs`` (e^{-iωt} sign
    convention: the dynamic stiffness K - ω² M + iω C), plus complex white noise of ``noise`` × each output's
    rms over the lines."""
    s = structure
    w = 2 * np.pi * np.asarray(frequencies_hz, float)
    h = np.stack([-(wk ** 2) * np.linalg.inv(s.K - wk ** 2 * s.M + 1j * wk * s.C)[:, list(inputs)] for wk in w])
    rng = np.random.default_rng(seed)
    rms = np.sqrt(np.mean(np.abs(h) ** 2, axis=(0, 2), keepdims=True))
    return h + (rng.standard_normal(h.shape) + 1j * rng.standard_normal(h.shape)) * rms * noise / np.sqrt(2)
