"""The simulated systems of the paper's section V (Case I, eqs. 58-60; Case II, eqs. 64-67), as ResponseData."""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..core.data import ResponseData

DT_S = 0.05  # the paper's sample time interval


def _blocks(pairs) -> np.ndarray:
    """Λ of eq. 55: diagonal 2 × 2 blocks [[δ, ω], [-ω, δ]] (eq. 57) for (δ, ω) in pairs."""
    return scipy.linalg.block_diag(*[np.array([[d, w], [-w, d]]) for d, w in pairs])


def free_decays(lam: np.ndarray, c: np.ndarray, g0: np.ndarray, n_samples: int, dt: float = DT_S) -> np.ndarray:
    """y(kΔτ) = C exp(Λ k Δτ) g(t0) of eqs. 55-56 for k = 0..N-1: shape (N, p, m) (g0 is (n, m))."""
    step = scipy.linalg.expm(lam * dt)
    out = np.empty((n_samples, c.shape[0], g0.shape[1]))
    x = np.array(g0, dtype=float)
    for k in range(n_samples):
        out[k] = c @ x
        x = step @ x
    return out


def case_1_eigenvalues() -> np.ndarray:
    """Eq. 58: s_j = -0.01 j + i j, j = 1..5 (rad/s)."""
    j = np.arange(1, 6)
    return -0.01 * j + 1j * j


def case_2_eigenvalues() -> np.ndarray:
    """Eqs. 64-65: the pair -0.01 + i twice, then -0.01 j + i j for j = 3, 4, 5 (rad/s)."""
    return np.array([-0.01 + 1j, -0.01 + 1j, -0.03 + 3j, -0.04 + 4j, -0.05 + 5j])


def case_1(n_samples: int = 200) -> ResponseData:
    """Case I: single sensor (eq. 59), single initial condition (eq. 60), five distinct modes (eq. 58)."""
    lam = _blocks([(s.real, s.imag) for s in case_1_eigenvalues()])
    c = np.array([[1, 0, 1, 0, 1, 0, 1, 0, 1, 0]], dtype=float)
    g0 = np.array([[0, 1, 0, 1, 0, 1, 0, 1, 0, 1]], dtype=float).T
    return ResponseData(free_decays(lam, c, g0, n_samples), DT_S, outputs=("sensor 1",), inputs=("IC 1",),
                        meta={"name": "Juang & Pappa 1985, Case I"})


def case_2(n_samples: int = 200, mimo: bool = True) -> ResponseData:
    """Case II: a repeated pair (eqs. 64-65). MIMO: two sensors (eq. 66), two initial conditions (eq. 67);
    ``mimo=False`` keeps the first sensor and the first initial condition, which see one copy only."""
    lam = _blocks([(s.real, s.imag) for s in case_2_eigenvalues()])
    c = np.array([[1, 0, 1, 0, 1, 0, 1, 0, 1, 0], [0, 0, 1, 0, 1, 0, 1, 0, 1, 0]], dtype=float)
    g0 = np.array([[0, 1, 0, 1, 0, 1, 0, 1, 0, 1], [0, 0, 0, 1, 0, 1, 0, 1, 0, 1]], dtype=float).T
    if not mimo:
        c, g0 = c[:1], g0[:, :1]
    p, m = c.shape[0], g0.shape[1]
    return ResponseData(free_decays(lam, c, g0, n_samples), DT_S,
                        outputs=tuple(f"sensor {i + 1}" for i in range(p)),
                        inputs=tuple(f"IC {i + 1}" for i in range(m)),
                        meta={"name": f"Juang & Pappa 1985, Case II ({'MIMO' if mimo else 'SISO'})"})
