"""Linear solid elements (CHEXA 8, CPENTA 6, CTETRA 4): isotropic elasticity, consistent mass, batched.

Each node carries the three translations (u, v, w) in the basic frame. Nodes in Nastran's (and CalculiX's)
order: a hexahedron's G1-G4 one face and G5-G8 the opposite one (G5 over G1), a wedge's G1-G3 one triangle and
G4-G6 the other, a tetrahedron's G1-G3 a face and G4 off it; either orientation of the faces is accepted.

- Hexahedron: trilinear, 2 × 2 × 2 Gauss points, with Wilson's nine incompatible modes (1 − ξ², 1 − η², 1 − ζ² in
  u, v and w) condensed out and Taylor's centre Jacobian, so that it bends without shear locking and passes the
  patch test (E. L. Wilson et al. 1973; R. L. Taylor et al., IJNME 10 (1976) 1211-1219); CalculiX's C3D8I.
- Wedge: linear triangle × linear line, 3 × 2 points (CalculiX's C3D6 interpolation).
- Tetrahedron: constant strain, exact one-point stiffness and the exact consistent mass.
Inputs: xyz (e, n, 3); outputs (e, 3n, 3n).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import DataError
from ..words import counted

_G = 1.0 / np.sqrt(3.0)
_HEX = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                 [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], float)
_HEX_POINTS = [((a, b, c), 1.0) for c in (-_G, _G) for b in (-_G, _G) for a in (-_G, _G)]
_WEDGE_POINTS = [((r, s, z), 1 / 6) for z in (-_G, _G) for r, s in ((1 / 6, 1 / 6), (2 / 3, 1 / 6), (1 / 6, 2 / 3))]
_TET_POINTS = [((a, b, c), 1 / 24) for a, b, c in
               [(0.1381966011250105, 0.1381966011250105, 0.1381966011250105),
                (0.5854101966249685, 0.1381966011250105, 0.1381966011250105),
                (0.1381966011250105, 0.5854101966249685, 0.1381966011250105),
                (0.1381966011250105, 0.1381966011250105, 0.5854101966249685)]]


@dataclass(frozen=True)
class SolidProperty:
    """An isotropic solid (Nastran PSOLID with a MAT1): Young's modulus e, Poisson's ratio nu, density rho."""

    e: float
    nu: float
    rho: float


def _elasticity(p: SolidProperty) -> np.ndarray:
    """D (6, 6) on (εx, εy, εz, γxy, γyz, γzx)."""
    if not (p.e > 0 and -1 < p.nu < 0.5 and p.rho >= 0):
        raise DataError(f"Solid property {p} is not physical: E > 0, -1 < nu < 0.5, rho >= 0.")
    lam = p.e * p.nu / ((1 + p.nu) * (1 - 2 * p.nu))
    g = p.e / (2 * (1 + p.nu))
    d = np.zeros((6, 6))
    d[:3, :3] = lam
    d[range(3), range(3)] += 2 * g
    d[range(3, 6), range(3, 6)] = g
    return d


def _shapes(kind: str, r: float, s: float, t: float) -> tuple[np.ndarray, np.ndarray]:
    """N (n,) and dN/d(r, s, t) (3, n) at a point of the reference element."""
    if kind == "hex":
        n = 0.125 * (1 + r * _HEX[:, 0]) * (1 + s * _HEX[:, 1]) * (1 + t * _HEX[:, 2])
        d = 0.125 * np.array([_HEX[:, 0] * (1 + s * _HEX[:, 1]) * (1 + t * _HEX[:, 2]),
                              _HEX[:, 1] * (1 + r * _HEX[:, 0]) * (1 + t * _HEX[:, 2]),
                              _HEX[:, 2] * (1 + r * _HEX[:, 0]) * (1 + s * _HEX[:, 1])])
        return n, d
    if kind == "wedge":
        tri, dtri = np.array([1 - r - s, r, s]), np.array([[-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]])
        lo, hi = 0.5 * (1 - t), 0.5 * (1 + t)
        n = np.concatenate([tri * lo, tri * hi])
        d = np.vstack([np.concatenate([dtri * lo, dtri * hi], axis=1), np.concatenate([-0.5 * tri, 0.5 * tri])])
        return n, d
    return np.array([1 - r - s - t, r, s, t]), np.array([[-1.0, 1, 0, 0], [-1.0, 0, 1, 0], [-1.0, 0, 0, 1]])


def _strain(dN: np.ndarray) -> np.ndarray:
    """B (e, 6, 3n) from the Cartesian derivatives dN (e, 3, n)."""
    e, _, n = dN.shape
    b = np.zeros((e, 6, 3 * n))
    x, y, z = dN[:, 0], dN[:, 1], dN[:, 2]
    b[:, 0, 0::3], b[:, 1, 1::3], b[:, 2, 2::3] = x, y, z
    b[:, 3, 0::3], b[:, 3, 1::3] = y, x
    b[:, 4, 1::3], b[:, 4, 2::3] = z, y
    b[:, 5, 0::3], b[:, 5, 2::3] = z, x
    return b


def solid_batch(xyz: np.ndarray, prop: SolidProperty, incompatible: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and consistent mass (e, 3n, 3n) of solids with corners xyz (e, n, 3), n = 8 (hexahedra), 6
    (wedges) or 4 (tetrahedra), one SolidProperty; DOFs per node x, y, z. ``incompatible`` False: the plain
    trilinear hexahedron (CalculiX's C3D8), which locks in bending."""
    xyz = np.asarray(xyz, float)
    e, n = xyz.shape[:2]
    kind = {8: "hex", 6: "wedge", 4: "tet"}[n]
    points = {"hex": _HEX_POINTS, "wedge": _WEDGE_POINTS, "tet": _TET_POINTS}[kind]
    d = _elasticity(prop)
    # a mirrored numbering (faces the other way round) turns the Jacobian's sign: mirror it back
    _, d0 = _shapes(kind, *((0.0, 0.0, 0.0) if kind == "hex" else (1 / 3, 1 / 3, 0.0) if kind == "wedge"
                            else (0.25, 0.25, 0.25)))
    j0 = np.einsum("in,enj->eij", d0, xyz)
    flip = np.linalg.det(j0) < 0
    if flip.any():
        order = {"hex": np.array([3, 2, 1, 0, 7, 6, 5, 4]), "wedge": np.array([0, 2, 1, 3, 5, 4]),
                 "tet": np.array([0, 2, 1, 3])}[kind]
        xyz = np.where(flip[:, None, None], xyz[:, order], xyz)
        j0 = np.einsum("in,enj->eij", d0, xyz)
    k, m = np.zeros((e, 3 * n, 3 * n)), np.zeros((e, 3 * n, 3 * n))
    k_ci, k_ii = np.zeros((e, 3 * n, 9)), np.zeros((e, 9, 9))
    det0 = np.linalg.det(j0)
    for (r, s, t), w in points:
        N, dr = _shapes(kind, r, s, t)
        jac = np.einsum("in,enj->eij", dr, xyz)
        det = np.linalg.det(jac)
        if np.any(det <= 0):
            raise DataError(f"{counted(int(np.sum(det <= 0)), 'solid element')} inverted or too distorted (its "
                            "nodes out of Nastran's order); renumber or remesh.")
        b = _strain(np.linalg.solve(jac, np.broadcast_to(dr, (e, 3, n))))
        dv = (w * det)[:, None, None]
        db = d @ b
        k += dv * (np.swapaxes(b, 1, 2) @ db)
        m += dv * np.kron(np.outer(N, N), np.eye(3))[None] * prop.rho
        if kind == "hex" and incompatible:
            dp = np.linalg.solve(j0, np.broadcast_to(np.diag([-2 * r, -2 * s, -2 * t]), (e, 3, 3)))
            bi = _strain(dp * (det0 / det)[:, None, None])
            k_ci += dv * (np.swapaxes(db, 1, 2) @ bi)
            k_ii += dv * (np.swapaxes(bi, 1, 2) @ d @ bi)
    if kind == "hex" and incompatible:
        k -= k_ci @ np.linalg.solve(k_ii, np.swapaxes(k_ci, 1, 2))
        k = 0.5 * (k + np.swapaxes(k, 1, 2))
    if flip.any():
        back = np.argsort(order)
        idx = (3 * back[:, None] + np.arange(3)).ravel()
        k = np.where(flip[:, None, None], k[:, idx][:, :, idx], k)
        m = np.where(flip[:, None, None], m[:, idx][:, :, idx], m)
    return k, m
