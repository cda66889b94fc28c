"""Element matrices of straight bars lying in the x-y plane, batched over elements.

Out-of-plane (grillage) element: 3 DOF per node, global (w, θx, θy); w along +z, rotations about the
global x and y axes (right-hand rule, so ∂w/∂x = -θy and ∂w/∂y = θx). Locally each node carries
(w, β, φ): β = dw/ds the bending slope along the bar, φ the twist about the bar axis. Euler-Bernoulli
bending (Hermite cubics), St-Venant torsion (linear), consistent mass, geometric stiffness of a
constant axial force N (tension > 0).

In-plane frame element: 3 DOF per node, global (u, v, θz): axial bar plus Euler-Bernoulli bending in
the plane, used for the static self-weight solve.

Every function takes per-element arrays of shape (e,) and returns (e, 6, 6) matrices in global axes.
"""

from __future__ import annotations

import numpy as np

_BEND = (0, 1, 3, 4)   # local (w1, β1, w2, β2) inside (w1, β1, φ1, w2, β2, φ2)
_TWIST = (2, 5)        # local (φ1, φ2)


def hermite(L: np.ndarray, a, b, c, d, e, f) -> np.ndarray:
    """The symmetric 4×4 pattern [[a, bL, c, dL], [bL, eL², -dL, fL²], [c, -dL, a, -bL], [dL, fL², -bL, eL²]]."""
    z = np.ones_like(L)
    rows = [[a * z, b * L, c * z, d * L],
            [b * L, e * L**2, -d * L, f * L**2],
            [c * z, -d * L, a * z, -b * L],
            [d * L, f * L**2, -b * L, e * L**2]]
    return np.moveaxis(np.array(rows), -1, 0)


def _place(bend: np.ndarray | None, twist: np.ndarray | None, n: int) -> np.ndarray:
    k = np.zeros((n, 6, 6))
    if bend is not None:
        k[:, np.ix_(_BEND, _BEND)[0], np.ix_(_BEND, _BEND)[1]] = bend
    if twist is not None:
        k[:, np.ix_(_TWIST, _TWIST)[0], np.ix_(_TWIST, _TWIST)[1]] = twist
    return k


def _two_node(L: np.ndarray, coef: np.ndarray) -> np.ndarray:
    """coef/L · [[1, -1], [-1, 1]]"""
    one = coef / L
    return np.moveaxis(np.array([[one, -one], [-one, one]]), -1, 0)


def grillage_rotation(c: np.ndarray, s: np.ndarray) -> np.ndarray:
    """T (e, 6, 6) with local (w, β, φ) = T · global (w, θx, θy) at both nodes; (c, s) = bar direction cosines."""
    t3 = np.zeros((c.size, 3, 3))
    t3[:, 0, 0] = 1.0
    t3[:, 1, 1], t3[:, 1, 2] = s, -c     # β = dw/ds = s θx - c θy
    t3[:, 2, 1], t3[:, 2, 2] = c, s      # φ = twist about the bar axis
    t = np.zeros((c.size, 6, 6))
    t[:, :3, :3] = t3
    t[:, 3:, 3:] = t3
    return t


def _to_global(k_local: np.ndarray, t: np.ndarray) -> np.ndarray:
    return np.swapaxes(t, 1, 2) @ k_local @ t


def grillage_stiffness(L, c, s, EI, GJ) -> np.ndarray:
    """Elastic stiffness: EI/L³ Hermite bending + GJ/L torsion; EI in N·m², GJ in N·m², L in m."""
    L, EI, GJ = (np.asarray(v, float) for v in (L, EI, GJ))
    bend = (EI / L**3)[:, None, None] * hermite(L, 12, 6, -12, 6, 4, 2)
    return _to_global(_place(bend, _two_node(L, GJ), L.size), grillage_rotation(c, s))


def grillage_mass(L, c, s, m_per_length, rho_ip) -> np.ndarray:
    """Consistent mass: translational m L/420 · Hermite pattern, torsional ρ I_p L/6 · [[2, 1], [1, 2]].

    m_per_length (kg/m) may include non-structural mass; rho_ip = ρ I_p (kg·m) is the twist inertia.
    Rotary inertia of bending is neglected (Euler-Bernoulli).
    """
    L, m, rip = (np.asarray(v, float) for v in (L, m_per_length, rho_ip))
    bend = (m * L / 420)[:, None, None] * hermite(L, 156, 22, 54, -13, 4, -3)
    a = rip * L / 6
    twist = np.moveaxis(np.array([[2 * a, a], [a, 2 * a]]), -1, 0)
    return _to_global(_place(bend, twist, L.size), grillage_rotation(c, s))


def grillage_geometric(L, c, s, N, r2) -> np.ndarray:
    """Geometric stiffness of a constant axial force N (N, tension > 0).

    Bending: N/(30 L) · [[36, 3L, -36, 3L], [3L, 4L², -3L, -L²], ...] (consistent, cubic shapes).
    Twist (Wagner): N r²/L · [[1, -1], [-1, 1]] with r² = I_p / A of a doubly symmetric section.
    """
    L, N, r2 = (np.asarray(v, float) for v in (L, N, r2))
    bend = (N / (30 * L))[:, None, None] * hermite(L, 36, 3, -36, 3, 4, -1)
    return _to_global(_place(bend, _two_node(L, N * r2), L.size), grillage_rotation(c, s))


def frame_rotation(c: np.ndarray, s: np.ndarray) -> np.ndarray:
    """T (e, 6, 6) with local (axial, transverse, θz) = T · global (u, v, θz) at both nodes."""
    t3 = np.zeros((c.size, 3, 3))
    t3[:, 0, 0], t3[:, 0, 1] = c, s
    t3[:, 1, 0], t3[:, 1, 1] = -s, c
    t3[:, 2, 2] = 1.0
    t = np.zeros((c.size, 6, 6))
    t[:, :3, :3] = t3
    t[:, 3:, 3:] = t3
    return t


def frame_stiffness(L, c, s, EA, EI) -> np.ndarray:
    """In-plane frame stiffness: EA/L axial bar + EI/L³ Hermite bending in the plane."""
    L, EA, EI = (np.asarray(v, float) for v in (L, EA, EI))
    k = np.zeros((L.size, 6, 6))
    ax = (0, 3)
    k[:, np.ix_(ax, ax)[0], np.ix_(ax, ax)[1]] = _two_node(L, EA)
    bd = (1, 2, 4, 5)
    k[:, np.ix_(bd, bd)[0], np.ix_(bd, bd)[1]] = (EI / L**3)[:, None, None] * hermite(L, 12, 6, -12, 6, 4, 2)
    return _to_global(k, frame_rotation(c, s))


def frame_uniform_load(L, c, s, qx, qy) -> np.ndarray:
    """Consistent nodal loads (e, 6) in global (u, v, θz) of a uniform load (qx, qy) N/m along each bar."""
    L, qx, qy = (np.asarray(v, float) for v in (L, qx, qy))
    qa, qt = c * qx + s * qy, -s * qx + c * qy
    local = np.stack([qa * L / 2, qt * L / 2, qt * L**2 / 12, qa * L / 2, qt * L / 2, -qt * L**2 / 12], axis=1)
    return np.einsum("eji,ej->ei", frame_rotation(c, s), local)


def frame_axial_force(L, c, s, EA, u_elem) -> np.ndarray:
    """Axial force N (e,) (tension > 0) from global end displacements u_elem (e, 6)."""
    c, s = np.asarray(c, float), np.asarray(s, float)
    du = (u_elem[:, 3] - u_elem[:, 0]) * c + (u_elem[:, 4] - u_elem[:, 1]) * s
    return np.asarray(EA, float) * du / np.asarray(L, float)
