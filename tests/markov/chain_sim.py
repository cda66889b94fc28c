"""A known structure for the pulse-response tests: a 3-mass spring chain with exact modes."""

from __future__ import annotations

import numpy as np
import scipy.signal


def continuous_chain():
    """Masses 1 kg, springs 1e4 N/m (ground-m1-m2-m3), damping 2e-4 K + 0.05 M.

    Returns (A (6, 6), B (6, 3), f_hz (3,), zeta (3,)): state [x; v], force on each mass in; damped
    frequencies and damping ratios of the three modes, ascending.
    """
    k = 1e4 * np.array([[2, -1, 0], [-1, 2, -1], [0, -1, 1.0]])
    c = 2e-4 * k + 0.05 * np.eye(3)
    a = np.block([[np.zeros((3, 3)), np.eye(3)], [-k, -c]])
    b = np.vstack([np.zeros((3, 3)), np.eye(3)])
    s = np.linalg.eigvals(a)
    s = s[s.imag > 0]
    s = s[np.argsort(s.imag)]
    return a, b, s.imag / 2 / np.pi, -s.real / np.abs(s)


def chain(dt: float = 0.01):
    """The chain sampled by zero-order hold: (Ad, Bd, C, D, f_hz, zeta); acceleration of every mass out, m/s² per N."""
    a, b, f, zeta = continuous_chain()
    c, d = a[3:], b[3:]  # acceleration = the velocity rows of the state equation
    ad, bd, cd, dd, _ = scipy.signal.cont2discrete((a, b, c, d), dt, method="zoh")
    return ad, bd, cd, dd, f, zeta


def simulate(ad, bd, cd, dd, u: np.ndarray) -> np.ndarray:
    """Outputs (N, p) of the discrete system to inputs (N, m) from rest."""
    _, y, _ = scipy.signal.dlsim((ad, bd, cd, dd, 1.0), u)
    return y


def hammer_decay(n: int = 1500, hit: int = 2, dt: float = 0.01) -> tuple[np.ndarray, np.ndarray]:
    """Acceleration (n, 3) of the chain after a unit hammer pulse on mass ``hit`` at sample 20 (20 pre-trigger
    samples), and the chain's damped frequencies in Hz: the free decay the reader tests write into files."""
    ad, bd, cd, dd, f_modes, _ = chain(dt)
    u = np.zeros((n, 3))
    u[20, hit] = 1.0
    return simulate(ad, bd, cd, dd, u), f_modes
