"""A 3-D frame as arrays: meshing, assembly, the self-weight solve and the lowest modes (6 DOF per node, SI).

``SpaceFrame`` is what :class:`era.Frame` hands to the numerics: nodes, elements with their section constants and
orientation, and per-node supports, springs, hanging cables and lumped masses. Its first ``n_user`` nodes are the
user's nodes; :func:`subdivide` appends the interior nodes of each member. Element matrices: :mod:`era.fem.beam3d`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from ..errors import DataError
from ..words import counted
from . import beam3d
from .sparse import diagonal, scatter

DOF_NAMES = ("translation along x", "translation along y", "translation along z",
             "rotation about x", "rotation about y", "rotation about z")
_PROPS = ("EA", "GJ", "EIy", "EIz", "m", "rho_ip", "r2")
# Largest k·h (wavenumber × element length) that keeps an element's frequency error below 0.05 %: Hermite cubic
# bending (error ≈ (kh)⁴/1480) and linear axial/twist shapes (error ≈ (kh)²/24), both with consistent mass; from
# the dispersion relation of an infinite chain of elements (tests/fem/test_beam3d.py checks both numbers).
KH_BENDING, KH_LINEAR = 0.927, 0.1095


@dataclass(frozen=True, eq=False)
class SpaceFrame:
    """Nodes, elements and node attributes of a 3-D frame (SI units).

    coords (n, 3) m; elements (e, 2) node indices; orientation (e, 3) the direction of each element's local z
    (see beam3d.element_axes); member (e,) the user's member each element belongs to; EA (N), GJ, EIy, EIz (N·m²),
    m (kg/m), rho_ip (kg·m), r2 = I_p/A (m²), each (e,); node_mass (n,) kg on the three translations; restrained
    (n, 6) bool; springs (n, 6) to ground on (x, y, z, rx, ry, rz), N/m and N·m/rad; cable_m (n,) length of a
    cable the node hangs from (0 = none); the first n_user nodes are the user's, named by ``names``.
    end_springs (e, 2) N·m/rad, inf = rigid (None: all rigid), with end_axes (e, 2, 3) unit vectors: a semi-rigid
    element end hangs on a rotational spring about that axis, its other five DOFs tied to the node; :func:`subdivide`
    turns each into a hinge: hinges = (node, end node, axis (3,), k, penalty of the tied DOFs) per spring.
    """

    coords: np.ndarray
    elements: np.ndarray
    orientation: np.ndarray
    member: np.ndarray
    EA: np.ndarray
    GJ: np.ndarray
    EIy: np.ndarray
    EIz: np.ndarray
    m: np.ndarray
    rho_ip: np.ndarray
    r2: np.ndarray
    node_mass: np.ndarray
    restrained: np.ndarray
    springs: np.ndarray
    cable_m: np.ndarray
    n_user: int
    names: tuple
    end_springs: np.ndarray | None = None
    end_axes: np.ndarray | None = None
    hinges: tuple = ()

    @cached_property
    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        """Element length L (e,) m and rotation R (e, 3, 3)."""
        return beam3d.element_axes(self.coords[self.elements[:, 0]], self.coords[self.elements[:, 1]],
                                   self.orientation)

    @property
    def n_nodes(self) -> int:
        return self.coords.shape[0]

    @property
    def supported(self) -> bool:
        return bool(self.restrained.any() or (self.springs > 0).any() or (self.cable_m > 0).any())

    def edofs(self) -> np.ndarray:
        """(e, 12) global DOF numbers of each element (node-major, 6 per node)."""
        n = 6 * self.elements[:, :, None] + np.arange(6)
        return n.reshape(-1, 12)


def subdivide(frame: SpaceFrame, counts: np.ndarray) -> SpaceFrame:
    """Split element k of ``frame`` (one element per member) into counts[k] equal elements; interior nodes are
    appended after the existing ones, member by member."""
    counts = np.asarray(counts, int)
    a, b = frame.coords[frame.elements[:, 0]], frame.coords[frame.elements[:, 1]]
    coords, elements, start = [frame.coords], [], frame.n_nodes
    for k, c in enumerate(counts):
        t = np.arange(1, c)[:, None] / c
        coords.append(a[k] + t * (b[k] - a[k]))
        chain = np.r_[frame.elements[k, 0], start + np.arange(c - 1), frame.elements[k, 1]]
        elements.append(np.column_stack([chain[:-1], chain[1:]]))
        start += c - 1
    n_new = start - frame.n_nodes
    rep = np.repeat(np.arange(counts.size), counts)
    pad = lambda x: np.concatenate([x, np.zeros((n_new,) + x.shape[1:], x.dtype)])   # noqa: E731
    mesh = SpaceFrame(coords=np.concatenate(coords), elements=np.concatenate(elements),
                      orientation=frame.orientation[rep], member=frame.member[rep],
                      **{p: getattr(frame, p)[rep] for p in _PROPS},
                      node_mass=pad(frame.node_mass), restrained=pad(frame.restrained), springs=pad(frame.springs),
                      cable_m=pad(frame.cable_m), n_user=frame.n_user, names=frame.names)
    if frame.end_springs is None or np.all(np.isinf(frame.end_springs)):
        return mesh
    last = np.cumsum(counts) - 1                       # element k of the member's chain at its end j
    first = last - counts + 1
    return _release(mesh, [(first[k], 0, frame.end_springs[k, 0], frame.end_axes[k, 0]) for k in range(counts.size)]
                    + [(last[k], 1, frame.end_springs[k, 1], frame.end_axes[k, 1]) for k in range(counts.size)])


def _release(mesh: SpaceFrame, ends: list) -> SpaceFrame:
    """Give each semi-rigid element end (element, 0 | 1, k N·m/rad, axis (3,)) its own node at the same place,
    tied to the original node by a hinge: a rotational spring k about the axis, the other five DOFs tied by a
    penalty 1e4 × the element's stiffest axial/rotational term (relative error of the tie ~1e-5)."""
    ends = [e for e in ends if np.isfinite(e[2])]
    elements = mesh.elements.copy()
    L = mesh.axes[0]
    coords, hinges = [mesh.coords], []
    n = mesh.n_nodes
    for el, side, k, axis in ends:
        node = elements[el, side]
        coords.append(mesh.coords[node][None])
        elements[el, side] = n
        penalty = 1e4 * np.array([mesh.EA[el] / L[el],
                                  max(mesh.GJ[el], 4 * mesh.EIy[el], 4 * mesh.EIz[el]) / L[el]])
        hinges.append((int(node), n, np.asarray(axis, float), float(k), penalty))
        n += 1
    extra = len(ends)
    pad = lambda x: np.concatenate([x, np.zeros((extra,) + x.shape[1:], x.dtype)])   # noqa: E731
    return SpaceFrame(coords=np.concatenate(coords), elements=elements, orientation=mesh.orientation,
                      member=mesh.member, **{p: getattr(mesh, p) for p in _PROPS}, node_mass=pad(mesh.node_mass),
                      restrained=pad(mesh.restrained), springs=pad(mesh.springs), cable_m=pad(mesh.cable_m),
                      n_user=mesh.n_user, names=mesh.names, hinges=tuple(hinges))


def hinge_stiffness(frame: SpaceFrame, n: int) -> scipy.sparse.csc_matrix:
    """(n, n) stiffness of the hinges: k (v_b - v_a)² per tied or sprung direction v of each hinge."""
    rows, cols, vals = [], [], []
    for a, b, axis, k, (p_t, p_r) in frame.hinges:
        basis = np.linalg.svd(axis[None, :])[2]          # axis first, then two normals
        for block, directions, stiff in ((0, np.eye(3), [p_t] * 3), (3, basis, [k, p_r, p_r])):
            for v, s in zip(directions, stiff):
                dofs = np.r_[6 * a + block + np.arange(3), 6 * b + block + np.arange(3)]
                vec = np.r_[-v, v]
                rows.append(np.repeat(dofs, 6))
                cols.append(np.tile(dofs, 6))
                vals.append(s * np.outer(vec, vec).ravel())
    if not rows:
        return scipy.sparse.csc_matrix((n, n))
    return scipy.sparse.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def stiffness(frame: SpaceFrame, axial_force: np.ndarray | None = None) -> scipy.sparse.csc_matrix:
    """K (6n, 6n): elastic + springs to ground, plus the geometric stiffness of ``axial_force`` (e,) N if given."""
    L, R = frame.axes
    k = beam3d.local_stiffness(L, frame.EA, frame.GJ, frame.EIy, frame.EIz)
    if axial_force is not None:
        k = k + beam3d.local_geometric(L, axial_force, frame.r2)
    K = scatter(beam3d.to_global(k, R), frame.edofs(), 6 * frame.n_nodes, diagonal(frame.springs.ravel()))
    return K + hinge_stiffness(frame, 6 * frame.n_nodes) if frame.hinges else K


def mass(frame: SpaceFrame) -> scipy.sparse.csc_matrix:
    """Consistent M (6n, 6n) plus the lumped masses on each node's translations."""
    L, R = frame.axes
    lumped = np.zeros((frame.n_nodes, 6))
    lumped[:, :3] = frame.node_mass[:, None]
    me = beam3d.to_global(beam3d.local_mass(L, frame.m, frame.rho_ip), R)
    return scatter(me, frame.edofs(), 6 * frame.n_nodes, diagonal(lumped.ravel()))


def factor(A) -> scipy.sparse.linalg.SuperLU:
    """Sparse LU of a symmetric positive definite matrix: minimum degree on A + Aᵀ, diagonal pivots, SuperLU's
    symmetric mode (~40× faster than the default COLAMD with partial pivoting on a 200-node frame)."""
    A = scipy.sparse.csc_matrix(A)
    try:
        return scipy.sparse.linalg.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                        options={"SymmetricMode": True})
    except RuntimeError:                                   # a zero pivot: let SuperLU pivot
        return scipy.sparse.linalg.splu(A)


@dataclass(frozen=True, eq=False)
class Statics:
    """Linear static solve of the self-weight: axial_force (e,) N (tension > 0); reactions (n, 6) N and N·m on the
    restrained DOFs (force of the support on the structure); displacement (n, 6) m and rad."""

    axial_force: np.ndarray
    reactions: np.ndarray
    displacement: np.ndarray


def self_weight(frame: SpaceFrame, gravity: np.ndarray) -> Statics:
    """Solve K u = f for the consistent weight of the members and the lumped masses under ``gravity`` (3,) m/s².

    Springs and restraints carry the load; hanging cables act as restraints along gravity. Directions in which the
    structure is a mechanism but carries no load (e.g. out of the plane of a hanging planar grid, held later by
    the geometric stiffness) are regularised by springs of 1e-11 × diag(K); a load on such a direction is an error.
    """
    g = np.asarray(gravity, float)
    L, R = frame.axes
    n = 6 * frame.n_nodes
    fe = beam3d.uniform_load(L, R, np.outer(frame.m, g))
    f = np.bincount(frame.edofs().ravel(), weights=fe.ravel(), minlength=n)
    f.reshape(-1, 6)[:, :3] += np.outer(frame.node_mass, g)
    K = stiffness(frame)
    free = ~frame.restrained.ravel()
    kff = K[free][:, free]
    # sized by the elastic diagonal: a joint spring's ties (a 1e4 × penalty) would make it a real spring
    elastic = K - hinge_stiffness(frame, n) if frame.hinges else K
    reg = 1e-11 * np.abs(elastic[free][:, free].diagonal())
    u = np.zeros(n)
    u[free] = factor(kff + scipy.sparse.diags(reg)).solve(f[free])
    if not np.all(np.isfinite(u)) or np.linalg.norm(reg * u[free]) > 1e-4 * np.linalg.norm(f):
        moved = np.argmax(np.abs(u.reshape(-1, 6)[:frame.n_user, :3]).max(axis=1))
        raise DataError(f"Frame: the supports do not carry the self-weight under gravity {tuple(g)}: node "
                        f"{frame.names[moved]} falls freely; add a support, a spring or a cable along gravity.")
    reactions = np.where(frame.restrained, (K @ u - f).reshape(-1, 6), 0.0)
    return Statics(axial_force=beam3d.axial_force(L, R, frame.EA, u[frame.edofs()]),
                   reactions=reactions, displacement=u.reshape(-1, 6))


def cable_springs(frame: SpaceFrame, gravity: np.ndarray, reactions: np.ndarray) -> np.ndarray:
    """(6n,) pendulum springs T/L on the translations normal to gravity of every node hanging from a cable, with T
    the cable's tension (the support's reaction against gravity) and L its length."""
    g = np.asarray(gravity, float)
    down = g / np.linalg.norm(g)
    out = np.zeros((frame.n_nodes, 6))
    for i in np.flatnonzero(frame.cable_m > 0):
        tension = -reactions[i, :3] @ down
        if tension <= 0:
            raise DataError(f"Frame: the cable at node {frame.names[i]} would push (tension {tension:.3g} N): "
                            "a cable can only hang the structure.")
        out[i, :3] = tension / frame.cable_m[i] * (1.0 - down**2)   # down is along a global axis
    return out.ravel()


def _buckling_error(value: str) -> DataError:
    return DataError(f"Frame buckles under its self-weight (lowest eigenvalue {value} rad²/s², < 0): gravity "
                     "exceeds the buckling load; check the supports, sections and gravity.")


def _stiffest(K, M) -> float:
    """max K_ii / M_ii (rad²/s²) over the DOFs that carry mass: the top of the spectrum's scale. A joint spring's
    node keeps no element of its own (each beam end moved to its hinge node), so its DOFs are massless; they do
    not count (over them the ratio is infinite, which made every eigenvalue look like zero)."""
    k, m = K.diagonal(), M.diagonal()
    massive = m > 1e-12 * m.max()
    return float(np.max(k[massive] / m[massive]))


def _eigen(K, M, n_modes: int, rigid: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Lowest eigenpairs λ (rad²/s²), φ of K φ = λ M φ, both solved shift-inverted about σ = -1 so that small λ
    keep their relative accuracy next to stiff elements (plain dense eigh loses ~1e-4 on a fine mesh): sparse
    Lanczos (ARPACK) above 200 DOFs, dense LAPACK on the pencil (M, K + M) below; plain eigh only if K + M is not
    positive definite (buckling), to report the negative λ.

    rigid : (n, 6) M-orthonormal rigid-body modes of a free structure, or None. They are moved to λ = c above the
    spectrum of interest (K + c (MR)(MR)ᵀ, inverted by the Woodbury identity) because a Lanczos run from one start
    vector can miss members of a six-fold zero eigenvalue; the caller prepends them at λ = 0.
    """
    n = K.shape[0]
    c = _stiffest(K, M)
    U = None if rigid is None else M @ rigid
    if n > 200 and n_modes < n // 4:
        try:
            lu = factor(K + M)
            symmetric = np.array_equal(lu.perm_r, lu.perm_c)    # no row pivots: U's diagonal is D of LDLᵀ
            if symmetric and np.any(lu.U.diagonal() < 0):       # so its signs are K + M's inertia: some λ < -1
                raise _buckling_error("below -1")
            solve = lu.solve
            if U is not None:
                au = lu.solve(U)
                cap = np.linalg.inv(np.eye(U.shape[1]) / c + U.T @ au)
                woodbury = lambda x: (y := lu.solve(x)) - au @ (cap @ (U.T @ y))   # noqa: E731

                def solve(x):   # K + M is nearly singular along the rigid modes: refine twice against K_c + M
                    y = woodbury(x)
                    for _ in range(2):
                        y = y + woodbury(x - K @ y - M @ y - c * (U @ (U.T @ y)))
                    return y
            op = scipy.sparse.linalg.LinearOperator((n, n), matvec=solve, dtype=float)
            lam, phi = scipy.sparse.linalg.eigsh(K, n_modes, M, sigma=-1.0, which="LM", tol=1e-12, OPinv=op,
                                                 v0=1.0 + np.sin(1.7 * np.arange(n) + 0.3))
            kphi = K @ phi
            if np.abs(kphi - (M @ phi) * lam).max() <= 1e-6 * np.abs(kphi).max():   # else: too ill-conditioned
                return lam, phi
        except (scipy.sparse.linalg.ArpackError, RuntimeError):
            pass
    k, m = K.toarray(), M.toarray()
    if U is not None:
        k = k + c * U @ U.T
    try:
        mu, phi = scipy.linalg.eigh(m, k + m, subset_by_index=[n - n_modes, n - 1], check_finite=False)
        return 1.0 / mu - 1.0, phi
    except np.linalg.LinAlgError:
        return scipy.linalg.eigh(k, m, subset_by_index=[0, n_modes - 1], check_finite=False)


@dataclass(frozen=True, eq=False)
class SpaceModes:
    """frequency_hz (k,); shapes (n, 6, k) mass-normalised over all nodes of the mesh (1/√kg per m or rad);
    axial_force (e,) N of the self-weight (zeros without gravity)."""

    frequency_hz: np.ndarray
    shapes: np.ndarray
    axial_force: np.ndarray


def rigid_body_modes(coords: np.ndarray) -> np.ndarray:
    """(6n, 6): unit translations along x, y, z and small rotations about x, y, z through the centroid."""
    r = coords - coords.mean(axis=0)
    out = np.zeros((coords.shape[0], 6, 6))
    for a in range(3):
        out[:, a, a] = 1.0
        axis = np.eye(3)[a]
        out[:, :3, 3 + a] = np.cross(axis, r)
        out[:, 3 + a, 3 + a] = 1.0
    return out.reshape(-1, 6)


def _mechanism_error(frame: SpaceFrame, zero: np.ndarray, free: np.ndarray) -> DataError:
    """Name the freest DOF of the zero-stiffness motions (after removing the six rigid motions a free structure may
    have): the user's node and DOF that moves most within them, rotations weighted by twice the structure's size."""
    full = np.zeros((6 * frame.n_nodes, zero.shape[1]))
    full[free] = zero
    rigid = rigid_body_modes(frame.coords)
    part = full - rigid @ np.linalg.lstsq(rigid, full, rcond=None)[0]
    u, sv, _ = np.linalg.svd(part if not frame.supported else full, full_matrices=False)
    basis = u[:, sv > 1e-6 * sv.max()]
    size = np.linalg.norm(np.ptp(frame.coords, axis=0))   # |ω × r| ≤ |ω| size: a rigid rotation is named as one
    freedom = np.linalg.norm(basis, axis=1).reshape(-1, 6)[:frame.n_user] * np.r_[np.ones(3), np.full(3, 2 * size)]
    node, dof = np.unravel_index(np.argmax(freedom), freedom.shape)
    rigid_note = (" (the whole structure moves as a rigid body)" if frame.supported
                  and np.linalg.norm(part) < 1e-6 * np.linalg.norm(full) else "")
    return DataError(f"Frame is a mechanism: node {frame.names[node]} {DOF_NAMES[dof]} is free: add a support or "
                     f"a member{rigid_note}; {counted(basis.shape[1], 'zero-stiffness motion')} among the lowest modes.")


def system(frame: SpaceFrame, gravity: np.ndarray | None = None) -> tuple:
    """(K, M, axial force (e,) N): the meshed frame's stiffness (with the self-weight's geometric stiffness and the
    cables' pendulum springs when ``gravity`` (3,) m/s² is given) and mass, over all 6·n_nodes DOFs."""
    axial = np.zeros(frame.elements.shape[0])
    K = stiffness(frame)
    if gravity is not None:
        statics = self_weight(frame, gravity)
        axial = statics.axial_force
        K = stiffness(frame, axial) + scipy.sparse.diags(cable_springs(frame, gravity, statics.reactions))
    return K, mass(frame), axial


def solve_modes(frame: SpaceFrame, n_modes: int, gravity: np.ndarray | None = None) -> SpaceModes:
    """The ``n_modes`` lowest modes of the meshed frame, with the geometric stiffness of the self-weight when
    ``gravity`` (3,) m/s² is given. A free structure (no support, spring or cable) may have its six rigid-body
    modes at 0 Hz; any other zero-stiffness motion raises a DataError naming a free DOF; a negative eigenvalue
    (buckling under the self-weight) raises too."""
    K, M, axial = system(frame, gravity)
    free = ~frame.restrained.ravel()
    kff, mff = K[free][:, free], M[free][:, free]
    n_free = int(free.sum())
    if n_modes > n_free:
        raise DataError(f"Frame: asked for {n_modes} modes of a model with {n_free} free DOFs.")
    rigid = None
    if not (frame.supported or gravity is not None):          # free: six rigid modes at 0 Hz, known exactly
        r = rigid_body_modes(frame.coords)[free]
        rigid = r @ np.linalg.inv(np.linalg.cholesky(r.T @ (mff @ r))).T   # M-orthonormal
    n_elastic = n_modes - (0 if rigid is None else 6)
    lam, phi = np.zeros(0), np.zeros((n_free, 0))
    if n_elastic > 0:
        lam, phi = _eigen(kff, mff, n_elastic, rigid)
        order = np.argsort(lam)
        lam, phi = lam[order], phi[:, order]
        tol = 1e-14 * _stiffest(kff, mff)                  # rigid modes come out at ≲ 1e-16 × that
        zero = np.abs(lam) < tol
        if zero.any():
            raise _mechanism_error(frame, phi[:, zero], free)
        if lam[0] < -tol:
            raise _buckling_error(f"{lam[0]:.3g}")
    if rigid is not None:
        lam = np.r_[np.zeros(6), lam][:n_modes]
        phi = np.column_stack([rigid, phi])[:, :n_modes]
    phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, mff @ phi))
    full = np.zeros((6 * frame.n_nodes, n_modes))
    full[free] = phi
    return SpaceModes(frequency_hz=np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi),
                      shapes=full.reshape(frame.n_nodes, 6, n_modes), axial_force=axial)


def elements_needed(frame: SpaceFrame, omega: float, axial_force: np.ndarray | None = None) -> np.ndarray:
    """Elements per member (one element per member in ``frame``) that keep every element's wavenumber at the
    circular frequency ``omega`` (rad/s) within KH_BENDING and KH_LINEAR, the waves of EI k⁴ - N k² = ∓m ω² and
    (GJ + N r²) k² = ρI_p ω² with the member's axial force N (N, tension > 0, one per member). In bending the
    larger root counts: the travelling wave in compression, the evanescent one in tension (the boundary layer of length
    √(EI/N) at a clamp or a joint of a tensioned member); with N = 0 both are (m ω²/EI)^¼."""
    L = frame.axes[0]
    n = (0.0 if axial_force is None else np.asarray(axial_force, float)) * np.ones_like(L)
    w2 = omega**2
    need = np.zeros_like(L)
    for EI in (frame.EIy, frame.EIz):
        k2 = (np.abs(n) + np.sqrt(n**2 + 4 * EI * frame.m * w2)) / (2 * EI)
        need = np.maximum(need, np.sqrt(k2) * L / KH_BENDING)
    k_axial = omega * np.sqrt(frame.m / frame.EA)
    k_twist = omega * np.sqrt(frame.rho_ip / np.maximum(frame.GJ + n * frame.r2, 1e-3 * frame.GJ))
    need = np.maximum(need, np.maximum(k_axial, k_twist) * L / KH_LINEAR)
    return np.maximum(1, np.ceil(need - 1e-9)).astype(int)


def converged_mesh(frame: SpaceFrame, n_modes: int, gravity: np.ndarray | None = None,
                   max_rounds: int = 6) -> tuple[SpaceFrame, SpaceModes]:
    """Mesh each member so that the lowest ``n_modes`` frequencies are converged to 0.1 %, and its modes.

    Rule: start from a coarse mesh (one element per member, more if the model has too few DOFs), solve, and give
    each member enough elements that every bending, axial and twist wave at the highest of those frequencies has
    k·h within the 0.05 % limits (KH_BENDING, KH_LINEAR). Repeat with the refined mesh until no member needs more.
    A coarse mesh's frequencies lie above the converged ones (Rayleigh-Ritz with consistent mass), so the rule
    errs on the fine side, and a mode's error is an energy-weighted mean of its elements' (≤ 0.05 % each): the
    first ``n_modes`` are within 0.1 % of the converged values (tests/fem: cantilever, chain, frames vs fine meshes).
    """
    n_members = frame.elements.shape[0]
    counts = np.full(n_members, max(1, int(np.ceil((3 * n_modes + 12) / (6 * n_members)))))
    for _ in range(max_rounds):
        mesh = subdivide(frame, counts)
        result = solve_modes(mesh, n_modes, gravity)
        # a member's force for the rule: its most compressive value, or its greatest tension
        omega = 2 * np.pi * result.frequency_hz[-1]
        least, most = np.full(n_members, np.inf), np.full(n_members, -np.inf)
        np.minimum.at(least, mesh.member, result.axial_force)
        np.maximum.at(most, mesh.member, result.axial_force)
        axial = np.where(least < 0, least, most)
        need = elements_needed(frame, omega, axial)
        if np.all(need <= counts):
            return mesh, result
        counts = np.maximum(counts, need)
    return mesh, result
