"""Known modal systems as test data: pulse responses with chosen modes and noise (for tests, benchmarks, demos)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.data import ResponseData


@dataclass(frozen=True)
class SyntheticTruth:
    """The modes a synthetic data set was made from: frequency_hz (modes,) damped, damping_ratio (modes,),
    shapes (p, modes) real, residues (modes, m) complex, snr_db (None without noise)."""

    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    residues: np.ndarray
    snr_db: float | None


def modal_response(frequency_hz, damping_ratio, n_outputs: int, n_inputs: int, n_samples: int, dt: float,
                   snr_db: float | None = None, seed: int = 0, shapes=None) -> tuple[ResponseData, SyntheticTruth]:
    """Pulse responses Y(k) = Σ_j 2 Re(φ_j z_j^k r_j), k = 0..N-1, of normal modes with noise.

    Parameters
    ----------
    frequency_hz, damping_ratio : (modes,)
        Damped natural frequencies (Hz, below the Nyquist limit 1/(2 dt)) and damping ratios.
    n_outputs, n_inputs : int
        p and m.
    n_samples : int
        N.
    dt : float
        Sampling interval in seconds.
    snr_db : float, optional
        Signal-to-noise ratio: white Gaussian noise of standard deviation rms(Y_i)·10^(-snr/20) is added to
        each output channel i.
    seed : int
        Seed of the shapes, residues and noise.
    shapes : (p, modes) real, optional
        Mode shapes; default random (normal distribution). Repeated frequencies with different shapes
        make a repeated mode that only several inputs can resolve.

    Returns
    -------
    ResponseData, SyntheticTruth
    """
    f = np.asarray(frequency_hz, dtype=float)
    zeta = np.broadcast_to(np.asarray(damping_ratio, dtype=float), f.shape)
    rng = np.random.default_rng(seed)
    phi = rng.standard_normal((n_outputs, f.size)) if shapes is None else np.asarray(shapes, dtype=float)
    residues = rng.standard_normal((f.size, n_inputs)) + 1j * rng.standard_normal((f.size, n_inputs))
    wd = 2 * np.pi * f
    wn = wd / np.sqrt(1 - zeta**2)
    s = -zeta * wn + 1j * wd
    zk = np.exp(np.outer(np.arange(n_samples) * dt, s))  # (N, modes)
    y = 2 * np.einsum("kj,pj,jm->kpm", zk, phi, residues).real
    if snr_db is not None:
        rms = np.sqrt(np.mean(y**2, axis=(0, 2), keepdims=True))
        y = y + rng.standard_normal(y.shape) * rms * 10 ** (-snr_db / 20)
    truth = SyntheticTruth(frequency_hz=f, damping_ratio=np.array(zeta), shapes=phi, residues=residues,
                           snr_db=snr_db)
    return ResponseData(y, dt), truth


def ambient_response(frequency_hz, damping_ratio, n_outputs: int, n_samples: int, dt: float,
                     snr_db: float | None = None, seed: int = 0, shapes=None) -> tuple[np.ndarray, SyntheticTruth]:
    """Outputs of normal modes driven by white noise (an ambient test), for era.markov_from_ambient.

    Each mode's complex modal coordinate follows η_j(k+1) = z_j η_j(k) + w_j(k) with z_j = exp(s_j Δτ) and w_j
    complex white noise of unit variance (independent modal forces), and y(k) = Σ_j 2 Re(φ_j η_j(k)); so the
    output correlations decay with the poles s_j (James et al.'s NExT). Parameters as :func:`modal_response`
    (``snr_db``: white measurement noise on each channel).

    Returns
    -------
    y : (n_samples, p) float; SyntheticTruth (residues: ones, as the forces are unit white noise)
    """
    from scipy.signal import lfilter

    f = np.asarray(frequency_hz, dtype=float)
    zeta = np.broadcast_to(np.asarray(damping_ratio, dtype=float), f.shape)
    rng = np.random.default_rng(seed)
    phi = rng.standard_normal((n_outputs, f.size)) if shapes is None else np.asarray(shapes, dtype=float)
    wd = 2 * np.pi * f
    s = -zeta * wd / np.sqrt(1 - zeta**2) + 1j * wd
    z = np.exp(s * dt)
    w = rng.standard_normal((f.size, n_samples)) + 1j * rng.standard_normal((f.size, n_samples))
    eta = np.stack([lfilter([1.0], [1.0, -zj], wj) for zj, wj in zip(z, w)])  # (modes, N)
    y = 2 * (phi @ eta).real.T
    if snr_db is not None:
        rms = np.sqrt(np.mean(y**2, axis=0, keepdims=True))
        y = y + rng.standard_normal(y.shape) * rms * 10 ** (-snr_db / 20)
    truth = SyntheticTruth(frequency_hz=f, damping_ratio=np.array(zeta), shapes=phi,
                           residues=np.ones((f.size, 1), complex), snr_db=snr_db)
    return y, truth
