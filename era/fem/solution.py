"""The FE solution of a 3-D frame as described (era.Frame, era/structure/): its arrays for the numerics
(era.fem.space.SpaceFrame, one element per member), the mesh and its lowest modes with a fixed sign convention, the
modes of every node, and Rayleigh-Ritz modes in the span of another frame's modes.

Each function takes the described frame and reads only its public fields and methods (era.Frame delegates to
these and keeps the solutions it has computed); nothing here imports era.structure.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg

from . import space

#: The keys of a support's springs to ground, in DOF order: kx, ky, kz (N/m), rx, ry, rz (N·m/rad).
SUPPORT_KEYS = ("kx", "ky", "kz", "rx", "ry", "rz")
#: The sign convention of every solved mode: r = 1 + sin(a·k + b), k = 0, 1, ... over the nodes' translations, and
#: each shape's sign makes r·u ≥ 0 (a generic vector: no mode is orthogonal to it by symmetry).
SIGN_SEED = (1.7, 0.3)


def space_frame(frame) -> space.SpaceFrame:
    """The numerics' arrays of an era.Frame ``frame``, one element per member (era.fem.space.SpaceFrame)."""
    index = {n: k for k, n in enumerate(frame.nodes)}
    xyz = np.array(list(frame.nodes.values()))
    ends = np.array([[index[m[0]], index[m[1]]] for m in frame.members])
    orient = np.array([m[3] if m[3] is not None else (np.nan,) * 3 for m in frame.members])
    default = np.isnan(orient[:, 0])
    orient[default] = space.beam3d.default_orientation(xyz[ends[default, 1]] - xyz[ends[default, 0]])
    secs = [frame.sections[m[2]] for m in frame.members]
    prop = lambda f: np.array([f(s) for s in secs])   # noqa: E731
    n = len(frame.nodes)
    restrained, springs, cable, mass = np.zeros((n, 6), bool), np.zeros((n, 6)), np.zeros(n), np.zeros(n)
    for node, spec in frame.supports.items():
        k = index[node]
        for a, key in enumerate(SUPPORT_KEYS):
            v = spec.get(key, 0.0)
            restrained[k, a] |= math.isinf(v)
            springs[k, a] = 0.0 if math.isinf(v) else v
        if "cable" in spec:
            cable[k] = spec["cable"]
            restrained[k, int(np.flatnonzero(frame.gravity)[0])] = True
    for node, kg in frame.masses.items():
        mass[index[node]] = kg
    end_k, end_axes = _end_springs(frame, xyz, ends)
    return space.SpaceFrame(
        coords=xyz, elements=ends, orientation=orient, member=np.arange(len(frame.members)),
        EA=prop(lambda s: s.e * s.area), GJ=prop(lambda s: s.g * s.j), EIy=prop(lambda s: s.e * s.iy),
        EIz=prop(lambda s: s.e * s.iz),
        m=prop(lambda s: s.mass_per_length) + np.array([frame.added_mass_per_length.get(m[2], 0.0)
                                                         for m in frame.members]),
        rho_ip=prop(lambda s: s.density * s.ip),
        r2=prop(lambda s: s.ip / s.area), node_mass=mass, restrained=restrained, springs=springs, cable_m=cable,
        n_user=n, names=tuple(frame.nodes), end_springs=end_k, end_axes=end_axes)


def _end_springs(frame, xyz, ends):
    """(e, 2) end springs (inf = rigid) and (e, 2, 3) their axes, from joint_springs; None when all rigid."""
    if not frame.joint_springs:
        return None, None
    k = np.full(ends.shape, np.inf)
    axes = np.zeros(ends.shape + (3,))
    for node, stiffness in frame.joint_springs.items():
        for member, side in frame.beam_ends(node):
            d = xyz[ends[member, 1]] - xyz[ends[member, 0]]
            normal = np.cross(frame.vertical, d)
            k[member, side] = stiffness
            axes[member, side] = normal / np.linalg.norm(normal)
    return k, axes


def solve(frame, n_modes: int) -> tuple[space.SpaceFrame, space.SpaceModes]:
    """The mesh of an era.Frame ``frame`` and its lowest ``n_modes`` modes, signs fixed by a generic reference
    vector (:data:`SIGN_SEED`): the automatic mesh (era.fem.space.converged_mesh) when ``frame.elements_per_member``
    is None, else that many elements per member. era.Frame.solution caches it."""
    model = space_frame(frame)
    g = None if frame.gravity is None else np.array(frame.gravity)
    if frame.elements_per_member is None:
        mesh, result = space.converged_mesh(model, n_modes, g)
    else:
        mesh = space.subdivide(model, np.broadcast_to(frame.elements_per_member, len(frame.members)))
        result = space.solve_modes(mesh, n_modes, g)
    u = result.shapes[:model.n_user, :3]
    ref = 1.0 + np.sin(SIGN_SEED[0] * np.arange(u.shape[0] * 3) + SIGN_SEED[1])
    sign = np.where(ref @ u.reshape(-1, n_modes) < 0, -1.0, 1.0)
    return mesh, space.SpaceModes(result.frequency_hz, result.shapes * sign, result.axial_force)


def ritz_modes(frame, reference, n_basis: int = 30) -> tuple[np.ndarray, np.ndarray] | None:
    """The modes of an era.Frame ``frame`` in the span of ``reference``'s lowest ``n_basis`` modes (Rayleigh-Ritz:
    one small dense eigenproblem instead of a sparse solve), for screening many places of a local change. Frequencies
    (r,) Hz and translations (n_nodes, 3, r) as :func:`node_modes`; frequencies are bounds from above, within
    0.5 % for a local mass or stiffness change. None unless both frames are meshed the same (a fixed
    ``elements_per_member``, the same joint springs: a spring adds nodes) and this frame holds every DOF the
    reference holds (a flexible support needs shapes that bend at the base: solve it)."""
    counts = frame.elements_per_member
    if (counts is None or counts != reference.elements_per_member
            or set(frame.joint_springs) != set(reference.joint_springs)):
        return None
    ref_mesh, ref = reference.solution(n_basis)
    mesh = space.subdivide(space_frame(frame), np.broadcast_to(counts, len(frame.members)))
    if mesh.n_nodes != ref_mesh.n_nodes:
        return None
    K, M, _ = space.system(mesh, None if frame.gravity is None else np.array(frame.gravity))
    free = ~mesh.restrained.ravel()
    if np.any(free & ref_mesh.restrained.ravel()):  # a support made flexible: the reference's shapes, all
        return None                                   # still at its base, cannot bend there; solve instead
    basis = ref.shapes.reshape(6 * mesh.n_nodes, -1)[:, :n_basis].copy()
    basis[~free] = 0.0  # what this frame holds does not move
    b = basis[free]
    k = b.T @ (K[free][:, free] @ b)
    m = b.T @ (M[free][:, free] @ b)
    lam, v = scipy.linalg.eigh(0.5 * (k + k.T), 0.5 * (m + m.T), check_finite=False)
    shapes = (basis @ v).reshape(mesh.n_nodes, 6, -1)
    return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi), shapes[:len(frame.nodes), :3]


def node_modes(frame, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies (n,) Hz and mass-normalised translations (n_nodes, 3, n) of every node of an era.Frame ``frame``
    (rows in ``frame.node_ids`` order, columns x, y, z), 1/√kg."""
    _, result = frame.solution(n_modes)
    u = result.shapes[:len(frame.nodes), :3, :n_modes].copy()
    # the eigensolver's round-off (~1e-16 of the mode) where the motion is zero (a planar frame's out-of-plane
    # modes at its nodes' in-plane DOFs) made exact: a unit-normalised sensor shape of it would be random
    u[np.abs(u) < 1e-10 * np.abs(u).max(axis=(0, 1))] = 0.0
    return result.frequency_hz[:n_modes].copy(), u


def element_counts(frame, n_modes: int = 10) -> tuple:
    """Elements of each member of an era.Frame ``frame`` in the mesh its modes(n_modes) use, in member order."""
    mesh, _ = frame.solution(n_modes)
    return tuple(int(c) for c in np.bincount(mesh.member, minlength=len(frame.members)))
