"""Flat shell elements (CQUAD4, CTRIA3): membrane with drilling rotations plus Reissner-Mindlin bending, batched.

Each node carries (u, v, w, θx, θy, θz) in the basic frame. Within an element, a local frame puts the element in
its x-y plane: a quad's mean plane (normal along the cross product of its diagonals, x along its mean 1-2
direction); a warped quad's nodes are projected onto that plane and joined to the real nodes by rigid offsets
(u_p = u + θ × d), which keeps the six rigid-body motions exact. A mid-surface offset (Nastran's ZOFFS) is one
more such link along the normal. A laminate (era.fem.laminate) adds the membrane-bending coupling B and the mass's
first moment.

- Membrane: bilinear (quad, with Wilson's incompatible modes condensed out so that it bends in its plane without
  locking: a stiffener's web) or constant-strain (triangle) displacements with the Hughes-Brezzi drilling rotation,
  a penalty γ ∫ (θz - ½(∂v/∂x - ∂u/∂y))² t dA at the full Gauss rule (no zero-energy mode). T. J. R. Hughes,
  F. Brezzi, *On drilling degrees of freedom*, CMAME 72 (1989) 105-121, suggest γ = G; era.fem takes G/100
  because a beam on the shell's nodes bends about the shell's normal through that rotation: an eccentric
  stiffener on RBE2s came out 6-11 % stiff against CalculiX's shell webs with γ = G, within 1 % with G/100.
- Bending: rotations interpolated like the displacements, β = (θy, -θx); bending stiffness D = E t³/12(1-ν²).
- Transverse shear: assumed covariant strains tied at the edge midpoints, constant tangential shear along each
  edge, so the element does not lock as t → 0 (thick and thin plates alike): MITC4 for the quad (K. J. Bathe, E.
  N. Dvorkin, IJNME 21 (1985) 367-383) and MITC3 for the triangle (P. S. Lee, K. J. Bathe, Computers & Structures
  82 (2004) 945-962); shear modulus κ G t with κ = 5/6.
- Mass: consistent, ρ t + nsm on the translations and ρ t³/12 on all three rotations (the rotary inertia of
  Mindlin bending; the same small value on the drilling rotation keeps M regular).

Quads are integrated with 2 x 2 Gauss points, triangles with the 3 mid-side points (exact for their quadratics).
Inputs: xyz (e, 4, 3) or (e, 3, 3) in the basic frame; outputs (e, 24, 24) or (e, 18, 18).
"""

from __future__ import annotations

import numpy as np

from ..errors import DataError
from ..words import counted

_G = 1.0 / np.sqrt(3.0)
_QUAD_R, _QUAD_S = np.array([-1.0, 1.0, 1.0, -1.0]), np.array([-1.0, -1.0, 1.0, 1.0])
_QUAD_GAUSS = [(r, s, 1.0) for s in (-_G, _G) for r in (-_G, _G)]
_TRIA_POINTS = [(0.5, 0.0, 1 / 6), (0.5, 0.5, 1 / 6), (0.0, 0.5, 1 / 6)]   # weights sum to ½, the reference area
SHEAR_FACTOR = 5.0 / 6.0
DRILL_FACTOR = 0.01
TRIA_STABILITY = 0.1


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _frame(xyz: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rotation R (e, 3, 3) whose rows are the local axes, local 2-D coordinates (e, n, 2), and each node's
    offset d = projected - real (e, n, 3)."""
    if xyz.shape[1] == 4:
        normal = np.cross(xyz[:, 2] - xyz[:, 0], xyz[:, 3] - xyz[:, 1])
        side = xyz[:, 1] + xyz[:, 2] - xyz[:, 0] - xyz[:, 3]
    else:
        normal = np.cross(xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0])
        side = xyz[:, 1] - xyz[:, 0]
    area2 = np.linalg.norm(normal, axis=1)
    size = np.max(np.linalg.norm(xyz - xyz[:, :1], axis=2), axis=1)
    if np.any(area2 <= 1e-10 * size**2):
        bad = counted(np.sum(area2 <= 1e-10 * size**2), "shell element")
        raise DataError(f"{bad} without area (collinear or coincident nodes); check the connectivity.")
    ez = normal / area2[:, None]
    ex = _unit(side - np.einsum("ei,ei->e", side, ez)[:, None] * ez)
    ey = np.cross(ez, ex)
    R = np.stack([ex, ey, ez], axis=1)
    centre = xyz.mean(axis=1, keepdims=True)
    local = np.einsum("eij,enj->eni", R, xyz - centre)
    offset = -local[:, :, 2:3] * ez[:, None, :]
    return R, local[:, :, :2], offset


def _to_basic(k: np.ndarray, R: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """Tᵀ k T with, per node, [u_loc; θ_loc] = [[R, -R S(d)], [0, R]] [u; θ] (S(d) θ = d × θ)."""
    e, n = offset.shape[:2]
    S = np.zeros((e, n, 3, 3))
    S[:, :, 0, 1], S[:, :, 0, 2] = -offset[:, :, 2], offset[:, :, 1]
    S[:, :, 1, 0], S[:, :, 1, 2] = offset[:, :, 2], -offset[:, :, 0]
    S[:, :, 2, 0], S[:, :, 2, 1] = -offset[:, :, 1], offset[:, :, 0]
    T = np.zeros((e, 6 * n, 6 * n))
    for a in range(n):
        T[:, 6 * a:6 * a + 3, 6 * a:6 * a + 3] = R
        T[:, 6 * a + 3:6 * a + 6, 6 * a + 3:6 * a + 6] = R
        T[:, 6 * a:6 * a + 3, 6 * a + 3:6 * a + 6] = -R @ S[:, a]
    return np.swapaxes(T, 1, 2) @ k @ T


def _materials(prop, e: int) -> dict:
    """The section's stiffness per area (membrane, coupling, bending (3, 3), shear (2, 2), drill) and inertia per
    area (m_t translations, m_1 first moment, m_r rotations), of a ShellProperty or a LaminateProperty."""
    if hasattr(prop, "membrane"):                   # a laminate (era.fem.laminate): its resultants as given
        return {"membrane": prop.membrane, "coupling": prop.coupling, "bending": prop.bending,
                "shear": prop.shear, "drill": DRILL_FACTOR * prop.membrane[2, 2], "m_t": prop.mass,
                "m_1": prop.first, "m_r": prop.rotary, "t": prop.thickness}
    t, E, nu = float(prop.thickness), float(prop.e), float(prop.nu)
    if not (t > 0 and E > 0 and -1 < nu < 0.5 and prop.rho >= 0 and prop.nsm >= 0):
        raise DataError(f"Shell property {prop} is not physical: thickness and E must be > 0, -1 < nu < 0.5, "
                        "rho and nsm >= 0.")
    plane = np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]]) * E / (1 - nu**2)
    G = E / (2 * (1 + nu))
    return {"membrane": plane * t, "coupling": None, "bending": plane * t**3 / 12,
            "shear": SHEAR_FACTOR * G * t * np.eye(2), "drill": DRILL_FACTOR * G * t, "m_t": prop.rho * t + prop.nsm,
            "m_1": 0.0, "m_r": prop.rho * t**3 / 12, "t": t}


def _density(mat: dict) -> np.ndarray:
    """(6, 6) inertia per area on a point's (u, v, w, θx, θy, θz): with u(z) = u + z θy and v(z) = v − z θx, the
    first moment m_1 couples u with θy and v with θx (an offset or unsymmetric section)."""
    rho = np.diag([mat["m_t"]] * 3 + [mat["m_r"]] * 3)
    rho[0, 4] = rho[4, 0] = mat["m_1"]
    rho[1, 3] = rho[3, 1] = -mat["m_1"]
    return rho


def _point_b(N, dNx, dNy, J, gamma_rs):
    """Membrane (e, 3, d), drilling (e, d), bending (e, 3, d) and Cartesian shear (e, 2, d) strain rows at one
    point, from the shape functions N (n,), their x-y derivatives (e, n) and the covariant shear rows (e, 2, d)."""
    e, n = dNx.shape
    d = 6 * n
    Bm, Bb = np.zeros((e, 3, d)), np.zeros((e, 3, d))
    bd = np.zeros((e, d))
    u, v, tx, ty, tz = (slice(k, d, 6) for k in (0, 1, 3, 4, 5))
    Bm[:, 0, u], Bm[:, 1, v], Bm[:, 2, u], Bm[:, 2, v] = dNx, dNy, dNy, dNx
    bd[:, tz], bd[:, u], bd[:, v] = N, 0.5 * dNy, -0.5 * dNx
    Bb[:, 0, ty], Bb[:, 1, tx], Bb[:, 2, ty], Bb[:, 2, tx] = dNx, -dNy, dNy, -dNx
    Bs = np.linalg.solve(J, gamma_rs)
    return Bm, bd, Bb, Bs


def _covariant(N, dNr, dNs, J, n: int) -> np.ndarray:
    """Rows (e, 2, 6n) of the covariant shear strains γ_r = ∂w/∂r + β·g_r, γ_s = ∂w/∂s + β·g_s at a point,
    β = (θy, -θx) interpolated by N (n,), g_r, g_s the rows of J (e, 2, 2)."""
    e = J.shape[0]
    g = np.zeros((e, 2, 6 * n))
    for row, dN in ((0, dNr), (1, dNs)):
        g[:, row, 2::6] = dN
        g[:, row, 3::6] = -N[None, :] * J[:, row, 1:2]
        g[:, row, 4::6] = N[None, :] * J[:, row, 0:1]
    return g


def _quad_shapes(r: float, s: float):
    N = 0.25 * (1 + r * _QUAD_R) * (1 + s * _QUAD_S)
    return N, 0.25 * _QUAD_R * (1 + s * _QUAD_S), 0.25 * _QUAD_S * (1 + r * _QUAD_R)


def _jacobian(local, dNr, dNs):
    return np.stack([dNr @ local, dNs @ local], axis=1)     # (e, 2, 2): rows (x_r, y_r), (x_s, y_s)


def _incompatible(r: float, s: float, J0: np.ndarray, det0: np.ndarray, det: np.ndarray) -> np.ndarray:
    """Membrane strain rows (e, 3, 4) of Wilson's incompatible modes 1 - r², 1 - s² in u and v (DOFs a1u, a2u,
    a1v, a2v), with Taylor's centre Jacobian and det J0 / det J scaling so that a patch of distorted quads still
    passes the constant-strain test (R. L. Taylor, P. J. Beresford, E. L. Wilson, IJNME 10 (1976) 1211-1219)."""
    dP = np.linalg.solve(J0, np.broadcast_to(np.array([[-2 * r, 0.0], [0.0, -2 * s]]), J0.shape))
    dP = dP * (det0 / det)[:, None, None]
    B = np.zeros((J0.shape[0], 3, 4))
    B[:, 0, 0:2], B[:, 1, 2:4], B[:, 2, 0:2], B[:, 2, 2:4] = dP[:, 0], dP[:, 1], dP[:, 1], dP[:, 0]
    return B


def _integrate(points, local, mat, shapes, shear, incompatible: bool = False):
    """Sum the local stiffness and mass over the integration points; ``shear(r, s, J)`` gives the assumed
    covariant shear rows. With ``incompatible``, the quad's membrane gets Wilson's incompatible modes, condensed
    out: the bilinear quad then bends in its plane without shear locking (exact for a rectangle)."""
    e, n = local.shape[:2]
    k, m = np.zeros((e, 6 * n, 6 * n)), np.zeros((e, 6 * n, 6 * n))
    k_ci, k_ii = np.zeros((e, 6 * n, 4)), np.zeros((e, 4, 4))
    rho = _density(mat)
    _, dNr0, dNs0 = shapes(0.0, 0.0)
    J0 = _jacobian(local, dNr0, dNs0)
    det0 = np.linalg.det(J0)
    for r, s, w in points:
        N, dNr, dNs = shapes(r, s)
        J = _jacobian(local, dNr, dNs)
        det = np.linalg.det(J)
        if np.any(det <= 0):
            raise DataError(f"{counted(np.sum(det <= 0), 'shell element')} inverted or too distorted (a corner "
                            "angle of 180° or more, or nodes out of order around the edge); renumber or remesh.")
        dN = np.linalg.solve(J, np.stack([np.broadcast_to(dNr, (e, n)), np.broadcast_to(dNs, (e, n))], axis=1))
        Bm, bd, Bb, Bs = _point_b(N, dN[:, 0], dN[:, 1], J, shear(r, s, J))
        dA = (w * det)[:, None, None]
        DBm = mat["membrane"] @ Bm
        k += dA * (np.swapaxes(Bm, 1, 2) @ DBm + np.swapaxes(Bb, 1, 2) @ mat["bending"] @ Bb
                   + np.swapaxes(Bs, 1, 2) @ (mat["shear"] @ Bs) + mat["drill"] * bd[:, :, None] * bd[:, None, :])
        if mat["coupling"] is not None:          # N = A ε + B κ, M = B ε + D κ
            BBb = mat["coupling"] @ Bb
            k += dA * (np.swapaxes(Bm, 1, 2) @ BBb + np.swapaxes(BBb, 1, 2) @ Bm)
            DBm = DBm + mat["coupling"] @ Bb     # the incompatible modes' strain couples with κ as well
        if incompatible:
            Bi = _incompatible(r, s, J0, det0, det)
            k_ci += dA * (np.swapaxes(DBm, 1, 2) @ Bi)
            k_ii += dA * (np.swapaxes(Bi, 1, 2) @ mat["membrane"] @ Bi)
        m += dA * np.kron(np.outer(N, N), rho)[None]          # the shapes are the same in every element
    if incompatible:
        k -= k_ci @ np.linalg.solve(k_ii, np.swapaxes(k_ci, 1, 2))
        k = 0.5 * (k + np.swapaxes(k, 1, 2))
    return k, m


def _offset(R: np.ndarray, offset: np.ndarray, zoffs) -> np.ndarray:
    """The nodes' rigid offsets (e, n, 3) with each element's mid-surface moved by zoffs (e,) along its normal."""
    if zoffs is None:
        return offset
    return offset + np.asarray(zoffs, float).reshape(-1, 1, 1) * R[:, None, 2, :]


def quad4_batch(xyz: np.ndarray, prop, zoffs=None) -> tuple[np.ndarray, np.ndarray]:
    """MITC4 stiffness and consistent mass (e, 24, 24) of quads with corners xyz (e, 4, 3), one ShellProperty
    (or LaminateProperty); zoffs (e,) the mid-surfaces' offsets from the nodes along the normals (None: 0), a rigid
    link from each node to the element's own, as Nastran's ZOFFS."""
    xyz = np.asarray(xyz, float).reshape(-1, 4, 3)
    R, local, offset = _frame(xyz)
    offset = _offset(R, offset, zoffs)
    mat = _materials(prop, len(xyz))
    # tying points: γ_r at the mid-points of the edges s = ∓1, γ_s at those of r = ∓1
    tie = {}
    for key, (r, s) in {"A": (0.0, -1.0), "C": (0.0, 1.0), "D": (-1.0, 0.0), "B": (1.0, 0.0)}.items():
        N, dNr, dNs = _quad_shapes(r, s)
        tie[key] = _covariant(N, dNr, dNs, _jacobian(local, dNr, dNs), 4)

    def shear(r, s, J):
        g_r = 0.5 * (1 - s) * tie["A"][:, 0] + 0.5 * (1 + s) * tie["C"][:, 0]
        g_s = 0.5 * (1 - r) * tie["D"][:, 1] + 0.5 * (1 + r) * tie["B"][:, 1]
        return np.stack([g_r, g_s], axis=1)

    k, m = _integrate(_QUAD_GAUSS, local, mat, _quad_shapes, shear, incompatible=True)
    return _to_basic(k, R, offset), _to_basic(m, R, offset)


def _tria_shapes(r: float, s: float):
    return np.array([1 - r - s, r, s]), np.array([-1.0, 1.0, 0.0]), np.array([-1.0, 0.0, 1.0])


def tria3_batch(xyz: np.ndarray, prop, zoffs=None) -> tuple[np.ndarray, np.ndarray]:
    """MITC3 stiffness and consistent mass (e, 18, 18) of triangles with corners xyz (e, 3, 3), one
    ShellProperty (or LaminateProperty); zoffs as for quad4_batch."""
    xyz = np.asarray(xyz, float).reshape(-1, 3, 3)
    R, local, offset = _frame(xyz)
    offset = _offset(R, offset, zoffs)
    mat = _materials(prop, len(xyz))
    g1 = _covariant(*_tria_shapes(0.5, 0.0), _jacobian(local, *_tria_shapes(0.5, 0.0)[1:]), 3)
    g2 = _covariant(*_tria_shapes(0.0, 0.5), _jacobian(local, *_tria_shapes(0.0, 0.5)[1:]), 3)
    g3 = _covariant(*_tria_shapes(0.5, 0.5), _jacobian(local, *_tria_shapes(0.5, 0.5)[1:]), 3)
    # γ_r = γ_r¹ + c s, γ_s = γ_s² - c r: constant tangential shear along each edge (the hypotenuse's at point 3)
    c = (g2[:, 1] - g1[:, 0]) - (g3[:, 1] - g3[:, 0])

    def shear(r, s, J):
        return np.stack([g1[:, 0] + c * s, g2[:, 1] - c * r], axis=1)

    t2 = float(mat["t"]) ** 2
    h2 = np.max(np.sum((local - np.roll(local, 1, axis=1)) ** 2, axis=2), axis=1)
    mat = dict(mat, shear=mat["shear"][None] * (t2 / (t2 + TRIA_STABILITY * h2))[:, None, None])
    k, m = _integrate(_TRIA_POINTS, local, mat, _tria_shapes, shear)
    return _to_basic(k, R, offset), _to_basic(m, R, offset)


def quad4_matrices(xyz, prop) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and consistent mass (24, 24) of one CQUAD4 with corners xyz (4, 3) (basic frame, in order around
    the edge), DOFs per node x y z rx ry rz."""
    k, m = quad4_batch(np.asarray(xyz, float).reshape(1, 4, 3), prop)
    return k[0], m[0]


def tria3_matrices(xyz, prop) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and consistent mass (18, 18) of one CTRIA3 with corners xyz (3, 3), DOFs per node x y z rx ry
    rz."""
    k, m = tria3_batch(np.asarray(xyz, float).reshape(1, 3, 3), prop)
    return k[0], m[0]
