"""Element matrices of the straight 3-D Euler-Bernoulli frame element (12 DOF), batched over elements.

Each node carries (u, v, w, θx, θy, θz): three translations (m) and three rotations (rad, right-hand rule), in
local axes (x along the element from node i to node j, y and z the section's principal axes) or in global axes.
Axial bar, St-Venant torsion (linear shapes), Euler-Bernoulli bending in the x-y plane (v, θz = dv/dx) and in the
x-z plane (w, θy = -dw/dx) with Hermite cubics; consistent mass with the torsional inertia ρ I_p and without the
rotary inertia of bending; geometric stiffness of a constant axial force N (tension > 0) from the same shapes,
with the Wagner term N I_p/A in twist.

Sources: J. S. Przemieniecki, *Theory of Matrix Structural Analysis* (McGraw-Hill 1968; Dover 1985), ch. 5
(stiffness of the space-frame element), ch. 11 (consistent mass, incl. torsion) and ch. 15 (geometric
stiffness); R. D. Cook, D. S. Malkus, M. E. Plesha, R. J. Witt, *Concepts and Applications of Finite Element
Analysis*, 4th ed. (Wiley 2002), §2.4, §11.3 and §18.3. Inputs are arrays of shape (e,); outputs (e, 12, 12)
matrices or (e, 12) vectors.
"""

from __future__ import annotations

import numpy as np

from .elements import hermite

_AXIAL, _TWIST = (0, 6), (3, 9)
_BEND_XY = (1, 5, 7, 11)            # (v1, θz1, v2, θz2): θz = +dv/dx
_BEND_XZ = (2, 4, 8, 10)            # (w1, θy1, w2, θy2): θy = -dw/dx
_FLIP = np.array([1.0, -1.0, 1.0, -1.0])


def _pair(a: np.ndarray, diag: float, off: float) -> np.ndarray:
    """a · [[diag, off], [off, diag]], (e, 2, 2)."""
    return a[:, None, None] * np.array([[diag, off], [off, diag]])


def _put(k: np.ndarray, dofs: tuple, block: np.ndarray) -> None:
    k[:, np.ix_(dofs, dofs)[0], np.ix_(dofs, dofs)[1]] += block


def _local(L, axial, twist, bend_y, bend_z) -> np.ndarray:
    """Assemble the four uncoupled actions: axial and twist (e, 2, 2); bending patterns (e, 4, 4) in (v, dv/dx)."""
    k = np.zeros((L.size, 12, 12))
    _put(k, _AXIAL, axial)
    _put(k, _TWIST, twist)
    _put(k, _BEND_XY, bend_z)                                   # about z: deflection v
    _put(k, _BEND_XZ, _FLIP[:, None] * bend_y * _FLIP[None, :])  # about y: deflection w, θy = -dw/dx
    return k


def local_stiffness(L, EA, GJ, EIy, EIz) -> np.ndarray:
    """Elastic stiffness in local axes: EA/L, GJ/L, EI/L³ · [12, 6L, -12, 6L; ...] in each bending plane.

    L (m), EA (N), GJ, EIy (about local y), EIz (about local z) in N·m².
    """
    L, EA, GJ, EIy, EIz = (np.asarray(a, float) for a in (L, EA, GJ, EIy, EIz))
    h = hermite(L, 12, 6, -12, 6, 4, 2) / L[:, None, None] ** 3
    return _local(L, _pair(EA / L, 1, -1), _pair(GJ / L, 1, -1), EIy[:, None, None] * h, EIz[:, None, None] * h)


def local_mass(L, m, rho_ip) -> np.ndarray:
    """Consistent mass in local axes: m L/6 [2 1; 1 2] axial, ρI_p L/6 [2 1; 1 2] twist, m L/420 · [156, 22L, 54,
    -13L; ...] in each bending plane. m = mass per length (kg/m), rho_ip = ρ I_p (kg·m)."""
    L, m, rho_ip = (np.asarray(a, float) for a in (L, m, rho_ip))
    h = (m * L / 420)[:, None, None] * hermite(L, 156, 22, 54, -13, 4, -3)
    return _local(L, _pair(m * L / 6, 2, 1), _pair(rho_ip * L / 6, 2, 1), h, h)


def local_geometric(L, N, r2) -> np.ndarray:
    """Geometric stiffness of a constant axial force N (N, tension > 0): N/(30L) · [36, 3L, -36, 3L; 3L, 4L², -3L,
    -L²; ...] in each bending plane, N r²/L [1 -1; -1 1] in twist (r² = I_p/A, m²); nothing axial."""
    L, N, r2 = (np.asarray(a, float) for a in (L, N, r2))
    h = (N / (30 * L))[:, None, None] * hermite(L, 36, 3, -36, 3, 4, -1)
    return _local(L, np.zeros((L.size, 2, 2)), _pair(N * r2 / L, 1, -1), h, h)


def element_axes(xi: np.ndarray, xj: np.ndarray, orientation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Length L (e,) m and rotation R (e, 3, 3) whose rows are the local x, y, z axes in global coordinates.

    x runs from node i to node j; z is the part of ``orientation`` (e, 3) normal to x (the section's local z, the
    "depth" direction), y = z × x. The orientation must not be parallel to the element (checked by the caller).
    """
    d = np.asarray(xj, float) - np.asarray(xi, float)
    L = np.linalg.norm(d, axis=1)
    ex = d / L[:, None]
    v = np.asarray(orientation, float)
    ez = v - np.einsum("ij,ij->i", v, ex)[:, None] * ex
    ez /= np.linalg.norm(ez, axis=1)[:, None]
    ey = np.cross(ez, ex)
    return L, np.stack([ex, ey, ez], axis=1)


def default_orientation(axis: np.ndarray) -> np.ndarray:
    """The default local-z direction of members along ``axis`` (e, 3): global +Z (depth vertical, local y
    horizontal), or global +X for a member within 1e-6 rad of vertical."""
    axis = np.asarray(axis, float)
    unit = axis / np.linalg.norm(axis, axis=1)[:, None]
    vertical = np.abs(unit[:, 2]) > 1.0 - 5e-13
    return np.where(vertical[:, None], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])


def _transform(R: np.ndarray) -> np.ndarray:
    t = np.zeros((R.shape[0], 12, 12))
    for b in range(4):
        t[:, 3 * b:3 * b + 3, 3 * b:3 * b + 3] = R
    return t


def to_global(k_local: np.ndarray, R: np.ndarray) -> np.ndarray:
    """Tᵀ k T with T = diag(R, R, R, R): element matrices (e, 12, 12) from local to global axes."""
    t = _transform(R)
    return np.swapaxes(t, 1, 2) @ k_local @ t


def uniform_load(L, R, q) -> np.ndarray:
    """Consistent nodal loads (e, 12) in global axes of a uniform load q (e, 3) N/m (global components) along
    each element: q L/2 on each node's translations, ±q L²/12 end moments."""
    L = np.asarray(L, float)
    ql = np.einsum("eij,ej->ei", R, np.asarray(q, float))           # local (qx, qy, qz)
    f = np.zeros((L.size, 12))
    f[:, [0, 1, 2]] = f[:, [6, 7, 8]] = ql * (L / 2)[:, None]
    m = ql * (L**2 / 12)[:, None]
    f[:, 5], f[:, 11] = m[:, 1], -m[:, 1]                            # qy bends about z
    f[:, 4], f[:, 10] = -m[:, 2], m[:, 2]                            # qz bends about y (θy = -dw/dx)
    return np.einsum("eji,ej->ei", _transform(R), f)


def axial_force(L, R, EA, u_elem) -> np.ndarray:
    """Axial force N (e,) N, tension > 0, from global end displacements u_elem (e, 12)."""
    du = np.asarray(u_elem, float)[:, 6:9] - np.asarray(u_elem, float)[:, 0:3]
    return np.asarray(EA, float) * np.einsum("ei,ei->e", R[:, 0], du) / np.asarray(L, float)
