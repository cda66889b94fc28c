"""Laminated shells by classical lamination theory: plies of orthotropic (or isotropic) material stacked through
the thickness give the shell's membrane A, coupling B and bending D stiffness, its transverse shear stiffness and
its mass per area with the first and second moments (:class:`LaminateProperty`, :func:`stack`).

Axes: x, y in the shell's plane along the element's material axes (era.fem.shell: a quad's mean 1-2 direction,
a triangle's 1-2 side), z along its normal from the reference surface (the nodes' plane). A ply's angle θ turns
its fibre direction 1 from x towards y. Strains are engineering (γxy = ∂u/∂y + ∂v/∂x); with ε(z) = ε0 + z κ the
resultants are N = A ε0 + B κ, M = B ε0 + D κ (R. M. Jones, *Mechanics of Composite Materials*, 2nd ed., 1999,
eqs. 2.93 and 4.22; J. N. Reddy, *Mechanics of Laminated Composite Plates and Shells*, 2nd ed., 2004, ch. 3).
Transverse shear: Σ κ Ḡ_k t_k, the plies' (G13, G23) turned to the element's axes, with κ = 5/6 (first-order
shear deformation theory, as the isotropic shell's).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SHEAR_FACTOR = 5.0 / 6.0


@dataclass(frozen=True, eq=False)
class Ply:
    """One ply: in-plane moduli e1 (along its fibres), e2, Poisson's ratio nu12, shear moduli g12, g13, g23
    (force per area), density rho (mass per volume), thickness t (length), angle_deg of its fibres from the
    element's x axis towards y."""

    e1: float
    e2: float
    nu12: float
    g12: float
    g13: float
    g23: float
    rho: float
    t: float
    angle_deg: float = 0.0


@dataclass(frozen=True, eq=False)
class LaminateProperty:
    """A shell section as its resultant stiffness and inertia per area, about the reference surface (the nodes).

    membrane A, coupling B, bending D : (3, 3) on (εx, εy, γxy) and (κx, κy, κxy); shear : (2, 2) on (γxz, γyz);
    thickness : the laminate's whole thickness (length); mass : ∫ρ dz + nsm (mass per area), first : ∫ρ z dz,
    rotary : ∫ρ z² dz (the rotations' inertia per area); name : for messages.
    """

    membrane: np.ndarray
    coupling: np.ndarray
    bending: np.ndarray
    shear: np.ndarray
    thickness: float
    mass: float
    first: float
    rotary: float
    name: str = "laminate"


def ply_stiffness(p: Ply) -> tuple[np.ndarray, np.ndarray]:
    """The ply's plane-stress stiffness Q̄ (3, 3) on (εx, εy, γxy) and transverse shear (2, 2) on (γxz, γyz), in
    the element's axes: Q̄ = Tᵀ Q T with T the engineering-strain rotation to the ply's axes."""
    nu21 = p.nu12 * p.e2 / p.e1
    d = 1.0 - p.nu12 * nu21
    q = np.array([[p.e1 / d, p.nu12 * p.e2 / d, 0.0], [p.nu12 * p.e2 / d, p.e2 / d, 0.0], [0.0, 0.0, p.g12]])
    c, s = np.cos(np.radians(p.angle_deg)), np.sin(np.radians(p.angle_deg))
    t = np.array([[c * c, s * s, c * s], [s * s, c * c, -c * s], [-2 * c * s, 2 * c * s, c * c - s * s]])
    r = np.array([[c, s], [-s, c]])
    return t.T @ q @ t, r.T @ np.diag([p.g13, p.g23]) @ r


def stack(plies, z0: float | None = None, nsm: float = 0.0, name: str = "laminate") -> LaminateProperty:
    """Stack ``plies`` (Ply, from the bottom up) with the bottom surface at z = ``z0`` (None: −half the whole
    thickness, the reference surface at mid-thickness); ``nsm`` mass per area added to the translations."""
    plies = list(plies)
    if not plies:
        raise ValueError("a laminate needs at least one ply")
    for p in plies:
        if not (p.t > 0 and p.e1 > 0 and p.e2 > 0 and p.g12 > 0 and p.g13 > 0 and p.g23 > 0 and p.rho >= 0
                and p.nu12 ** 2 * p.e2 / p.e1 < 1):
            raise ValueError(f"ply {p} is not physical: thickness, moduli > 0, rho >= 0, nu12² E2/E1 < 1")
    total = sum(p.t for p in plies)
    z = (-total / 2 if z0 is None else float(z0)) + np.concatenate([[0.0], np.cumsum([p.t for p in plies])])
    a, b, d, h = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((2, 2))
    m = [float(nsm), 0.0, 0.0]
    for k, p in enumerate(plies):
        q, g = ply_stiffness(p)
        z1, z2 = z[k], z[k + 1]
        a += q * (z2 - z1)
        b += q * (z2 ** 2 - z1 ** 2) / 2
        d += q * (z2 ** 3 - z1 ** 3) / 3
        h += SHEAR_FACTOR * g * (z2 - z1)
        for power in range(3):
            m[power] += p.rho * (z2 ** (power + 1) - z1 ** (power + 1)) / (power + 1)
    return LaminateProperty(a, b, d, h, total, m[0], m[1], m[2], name)
