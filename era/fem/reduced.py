"""A reduced model of a nominal frame: every local change a small dense eigenproblem, not a re-mesh and a solve.

The nominal's mesh is assembled once (elastic stiffness K_e, ground springs, mass M, the mass of 1 kg/m spread over
every member) and factored once (K on the free DOFs). Its lowest ``n_basis`` modes Φ (6·n_nodes, r) are the
basis, extended for each configuration of places by static vectors (Craig & Bampton 1968; Craig & Kurdila,
*Fundamentals of Structural Dynamics*, 2nd ed., Wiley 2006, §14.5):

- a support made flexible: a constraint mode per released DOF (the DOF moved by one unit, the rest of the
  structure following statically: x_f = -K_ff⁻¹ K_fd), or K⁻¹ e_d for a DOF that already moved;
- a semi-rigid joint: each beam end at the node gets its own relative rotation θ about the spring's axis (the
  other five DOFs tied exactly), so the element's end rotation is the node's plus θ·axis; one constraint mode
  per end (θ = 1, x = -K_ff⁻¹ C, C = Pᵀ k_e a the forces a unit θ causes);
- a point mass: the residual attachment modes K⁻¹ e of unit loads on the node's three translations;
- a member's stiffness: the attachment modes K⁻¹ e of unit loads on every DOF of the member's elements (its
  ΔK = (θ - 1) Σ k_e acts there only), or, to screen many members, the modes alone (within ~2 %).

Every parameter enters linearly, so each configuration's projected pieces are computed once and a trial is
K_r = sf (K_e + (θ - 1) K_member) + K_springs + k_s K_support + k_j K_joint [+ K_g + m K_g,point + μ K_g,spread],
M_r = M + m M_point + μ M_spread,
a dense generalized eigenproblem of ~30-40 unknowns. Frequencies are upper bounds (Rayleigh-Ritz); the accuracy
against the full solve is tested per effect in tests/fem/test_reduced.py. Under gravity the self-weight's geometric
stiffness (and hanging cables' pendulum springs) is linear in the weight: the nominal's, plus per kg of a point
mass or per kg/m spread, each from one static solve (era.fem.space.self_weight's); the redistribution of the
axial forces by a changed member or spring is left out (a second-order change). Nominal joint springs (a frame
drawn with semi-rigid connections, Frame.joint_springs) are in the nominal's mesh already as hinges (each beam end
its own node, era.fem.space.subdivide's release of the joint): their stiffness is a fixed part of K, projected
once; a joint effect at such a node re-springs its hinges (the relative rotations are DOFs already: one static vector
per hinge, the unit couple's, for the spring's change) instead of adding relative rotations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse

from . import beam3d, space
from .solution import SIGN_SEED
from .sparse import scatter



def reducible(frame) -> bool:
    """True when :class:`ReducedFrame` can stand for this era.Frame (a fixed mesh; supported, or free without
    gravity: its static vectors then come from the shifted, self-equilibrated solve of :meth:`ReducedFrame._static`)."""
    return frame.elements_per_member is not None and (bool(frame.supports) or frame.gravity is None)


@dataclass(frozen=True, eq=False)
class Pieces:
    """The projected pieces of one configuration (q×q each, in the M-orthonormal reduced coordinates): elastic
    stiffness ``ke`` (at the nominal sections), ground springs ``kg``, unit springs on the released support DOFs
    (``k_rot``, ``k_vert``) and on the joint's relative rotations (``k_joint``), the mass ``m``, a unit point mass
    ``m_point`` and 1 kg/m spread over every member ``m_spread``; ``user`` (3·n_user, q) the user nodes'
    translations; ``basis``: Q (the coordinates), T (the basis over the mesh's DOFs), ends {element: (12, q) its
    DOF values with the hinge} and the members' projections computed so far."""

    ke: np.ndarray
    kg: np.ndarray
    k_rot: np.ndarray
    k_vert: np.ndarray
    k_joint: np.ndarray
    k_geo: np.ndarray
    k_geo_point: np.ndarray
    k_geo_spread: np.ndarray
    m: np.ndarray
    m_point: np.ndarray
    m_spread: np.ndarray
    user: np.ndarray
    basis: dict


class ReducedFrame:
    """The reduced model of a nominal era.Frame (see the module docstring); :meth:`modes` for one parameter set.

    frame : the nominal era.Frame (``reducible``): its modes are the basis (with the geometric stiffness of its
    self-weight when it has gravity); n_basis : nominal modes in the basis (fewer for a small model); gravity :
    (3,) m/s² or None, the gravity whose geometric stiffness a parameter set may switch on (default the frame's).
    """

    def __init__(self, frame, n_basis: int = 30, gravity=None):
        counts = np.broadcast_to(frame.elements_per_member, len(frame.members))
        mesh = space.subdivide(frame.space_frame(), counts)
        self.mesh = mesh
        L, R = mesh.axes
        self.k_el = beam3d.to_global(beam3d.local_stiffness(L, mesh.EA, mesh.GJ, mesh.EIy, mesh.EIz), R)
        self.m_el = beam3d.to_global(beam3d.local_mass(L, mesh.m, mesh.rho_ip), R)
        self.m_unit = beam3d.to_global(beam3d.local_mass(L, np.ones_like(L), np.zeros_like(L)), R)
        n = 6 * mesh.n_nodes
        self.edofs = mesh.edofs()
        self.K_el = scatter(self.k_el, self.edofs, n)
        self.M = space.mass(mesh)
        self.M_spread = scatter(self.m_unit, self.edofs, n)
        self.springs = mesh.springs.ravel().copy()
        self.free = ~mesh.restrained.ravel()
        # the nominal's joint springs: its hinges' springs and ties, a fixed part of K (not scaled with E)
        self.K_hinge = space.hinge_stiffness(mesh, n) if mesh.hinges else None
        K = (self.K_el + scipy.sparse.diags(self.springs)).tocsc()
        if self.K_hinge is not None:
            K = (K + self.K_hinge).tocsc()
        g = frame.gravity if gravity is None else gravity
        self.g = None if g is None else np.asarray(g, float)
        self.K_geo = self.K_geo_spread = None
        if self.g is not None:     # geometric stiffness (and cables' pendulum springs) of the weight, linear in it
            free = self.free
            kff = K[free][:, free]
            self._elastic = space.factor(kff + scipy.sparse.diags(1e-11 * np.abs(kff.diagonal())))
            nominal = space.self_weight(mesh, self.g)
            self.K_geo = self._geometric(nominal.axial_force, nominal.reactions)
            fe = beam3d.uniform_load(L, R, np.outer(np.ones_like(L), self.g))
            unit = np.bincount(self.edofs.ravel(), weights=fe.ravel(), minlength=n)
            self.K_geo_spread = self._geometric(*self._weight(unit))
            if frame.gravity is not None:
                K = (K + self.K_geo).tocsc()
        self.K = K
        r = int(min(n_basis, self.free.sum()))
        _, modes = frame.solution(r)
        self.phi = modes.shapes.reshape(n, -1)[:, :r]
        # a free structure (no support, spring or cable; no gravity): K is singular along its six rigid motions,
        # which are the basis' first six modes (0 Hz). Static vectors are then those of the self-equilibrated
        # load (its rigid-body part taken off) solved with K + σM, σ the lowest elastic eigenvalue, and kept
        # free of rigid motion (inertia relief; Craig & Kurdila §14.6): they differ from K⁺f by components
        # along the lowest modes, which the basis holds already
        self.rigid = None
        if not (mesh.supported or self.g is not None) and r > 6:
            self.rigid = self.phi[self.free, :6]
            sigma = max((2 * np.pi * float(modes.frequency_hz[6])) ** 2, 1e-6)
            self.lu = space.factor((K + sigma * self.M)[self.free][:, self.free])
        else:
            self.lu = space.factor(K[self.free][:, self.free])
        # the modes' products with each operator, once: a configuration multiplies only its static vectors
        self._phi_products = {id(A): (A @ self.phi, self.phi.T @ (A @ self.phi))
                              for A in (self.K_el, self.M, self.M_spread, self.K_geo, self.K_geo_spread,
                                        self.K_hinge)
                              if A is not None}
        self.n_user = mesh.n_user
        self.user_rows = (6 * np.arange(self.n_user)[:, None] + np.arange(3)).ravel()
        self.frame = frame
        self._cache = {}

    def _weight(self, f: np.ndarray) -> tuple:
        """Axial forces (e,) N and reactions (n_nodes, 6) of a load f (6·n_nodes,) on the elastic structure
        (era.fem.space.self_weight's regularised solve, linear)."""
        u = np.zeros(f.size)
        u[self.free] = self._elastic.solve(f[self.free])
        L, R = self.mesh.axes
        axial = beam3d.axial_force(L, R, self.mesh.EA, u[self.edofs])
        reactions = np.where(self.mesh.restrained, (self.K_el @ u + self.springs * u - f).reshape(-1, 6), 0.0)
        return axial, reactions

    def _geometric(self, axial: np.ndarray, reactions: np.ndarray):
        """The geometric stiffness of these axial forces plus the cables' pendulum springs T/L of these
        reactions (era.fem.space.cable_springs, without its checks: a load's share may unload a cable)."""
        L, R = self.mesh.axes
        kg = scatter(beam3d.to_global(beam3d.local_geometric(L, axial, self.mesh.r2), R), self.edofs,
                     self.K_el.shape[0])
        down = self.g / np.linalg.norm(self.g)
        cable = np.zeros((self.mesh.n_nodes, 6))
        hang = self.mesh.cable_m > 0
        cable[hang, :3] = (-(reactions[hang, :3] @ down) / self.mesh.cable_m[hang])[:, None] * (1.0 - down**2)
        return (kg + scipy.sparse.diags(cable.ravel())).tocsc()

    @property
    def n_basis(self) -> int:
        return self.phi.shape[1]

    def _static(self, rhs: np.ndarray) -> np.ndarray:
        """(n,) or (n, c) x with K_ff x_f = rhs_f, zero on the restrained DOFs."""
        x = np.zeros(rhs.shape)
        f = rhs[self.free]
        if self.rigid is not None:     # free: the load's rigid-body part off, the answer's too (M-orthonormal R)
            mf = self.M[self.free][:, self.free]
            f = f - mf @ (self.rigid @ (self.rigid.T @ f))
            y = self.lu.solve(np.ascontiguousarray(f))
            x[self.free] = y - self.rigid @ (self.rigid.T @ (mf @ y))
            return x
        x[self.free] = self.lu.solve(np.ascontiguousarray(f))
        return x

    def _hinges(self, node: str) -> list:
        """(element, side, axis (3,)) of every beam end at ``node`` (Frame.joint_springs' springs)."""
        fr, mesh = self.frame, self.mesh
        k = fr.node_ids.index(node)
        out = []
        for member, side in fr.beam_ends(node):
            els = np.flatnonzero(mesh.member == member)
            el = next(e for e in els if mesh.elements[e, side] == k)
            i, j = fr.members[member][:2]
            normal = np.cross(fr.vertical, np.subtract(fr.nodes[j], fr.nodes[i]))
            out.append((int(el), side, normal / np.linalg.norm(normal)))
        return out

    def pieces(self, support=None, joint=None, mass_at=None, member=None) -> Pieces:
        """The projected pieces for a configuration: support (node, released keys of the rotations, of the
        vertical) or None; joint node or None; point-mass node or None; a member index whose attachment modes
        join the basis, "all" (every member: the nominal hinges' static vectors join it) or None. Cached."""
        key = (support, joint, mass_at, member)
        got = self._cache.pop(key, None)
        if got is None:
            got = self._build(support, joint, mass_at, member)
            while len(self._cache) >= 32:           # least recently used out: a configuration holds its basis
                self._cache.pop(next(iter(self._cache)))
        self._cache[key] = got
        return got

    def _build(self, support, joint, mass_at, member) -> Pieces:
        n = self.K.shape[0]
        index = {name: k for k, name in enumerate(self.frame.node_ids)}
        loads, rot_dofs, vert_dofs, resprung, released = [], [], [], [], []   # loads: the static vectors' rhs
        if support is not None:
            node, rot_keys, vert_keys = support
            for keys, dofs in ((rot_keys, rot_dofs), (vert_keys, vert_dofs)):
                for key in keys:
                    d = 6 * index[node] + ("kx", "ky", "kz", "rx", "ry", "rz").index(key)
                    dofs.append(d)
                    if self.free[d]:              # a DOF that already moved: the spring's static correction
                        resprung.append(d)
                        loads.append(np.eye(1, n, d).ravel())
                    else:                         # a released DOF: its constraint mode (d moved by 1)
                        released.append((len(loads), d))
                        loads.append(-self.K[:, [d]].toarray().ravel())
        free = self.free.copy()
        free[rot_dofs + vert_dofs] = True
        # a joint with nominal hinges: their relative rotations (q,) rows r, re-sprung; else new ends' θ
        rehinged = [h for h in self.mesh.hinges if joint is not None and h[0] == index[joint]]
        hinges = self._hinges(joint) if joint is not None and not rehinged else []
        for el, side, axis in hinges:       # θ = 1 at this end, the structure following statically
            a = np.zeros(12)
            a[6 * side + 3:6 * side + 6] = axis
            c = np.zeros(n)
            np.add.at(c, self.edofs[el], self.k_el[el] @ a)
            loads.append(-c)
        couples = [self._couple(h) for h in rehinged]   # the unit couple across a hinge: its spring's change
        loads += couples
        if mass_at is not None:
            loads += [np.eye(1, n, d).ravel() for d in 6 * index[mass_at] + np.arange(3) if free[d]]
        if member == "all":       # every member's E relative to the nominal's joint springs: their hinges bend
            loads += [self._couple(h) for h in self.mesh.hinges]
        elif member is not None:
            dofs = np.unique(self.edofs[self.mesh.member == member])
            loads += [np.eye(1, n, d).ravel() for d in dofs[free[dofs]]]
        X = self._static(np.column_stack(loads)) if loads else np.zeros((n, 0))   # one solve, every rhs
        for k, d in released:
            X[d, k] = 1.0
        T = np.column_stack([self.phi, X])
        T[~free] = 0.0
        q = T.shape[1]
        theta = np.zeros((len(hinges), q))        # the ends' relative rotations in the basis' coordinates
        first = self.n_basis + len(rot_dofs) + len(vert_dofs)
        theta[np.arange(len(hinges)), first + np.arange(len(hinges))] = 1.0
        ke, m, m_spread = (self._project(A, T) for A in (self.K_el, self.M, self.M_spread))
        zero = np.zeros((q, q))
        k_geo = k_geo_point = k_geo_spread = zero
        if self.g is not None:
            k_geo, k_geo_spread = self._project(self.K_geo, T), self._project(self.K_geo_spread, T)
            if mass_at is not None:     # the weight of 1 kg there: its axial forces' geometric stiffness
                f = np.zeros(n)
                f[6 * index[mass_at] + np.arange(3)] = self.g
                k_geo_point = T.T @ (self._geometric(*self._weight(f)) @ T)
        sprung = np.flatnonzero(self.springs)
        kg = T[sprung].T @ (self.springs[sprung, None] * T[sprung])
        if self.K_hinge is not None:
            kg = kg + self._project(self.K_hinge, T)
        for c, (*_, k_nominal, _) in zip(couples, rehinged):    # cᵀ T: the hinge's relative rotation
            r = c @ T
            theta = np.vstack([theta, r])
            kg -= k_nominal * np.outer(r, r)
        hinged = {}
        for j, (el, side, axis) in enumerate(hinges):
            a = np.zeros(12)
            a[6 * side + 3:6 * side + 6] = axis
            u0 = T[self.edofs[el]]
            u = u0 + np.outer(a, theta[j])
            hinged[el] = u
            for mat, out in ((self.k_el, ke), (self.m_el, m), (self.m_unit, m_spread)):
                out += u.T @ mat[el] @ u - u0.T @ mat[el] @ u0
        for d in resprung:        # the nominal spring on a DOF that gets the effect's spring instead
            kg -= self.springs[d] * np.outer(T[d], T[d])
        unit = lambda dofs: sum((np.outer(T[d], T[d]) for d in dofs), np.zeros((q, q)))   # noqa: E731
        m_point = unit(6 * index[mass_at] + np.arange(3)) if mass_at is not None else np.zeros((q, q))
        # M-orthonormal coordinates of the nominal (drops the static vectors the modes already span)
        # columns scaled to unit mass first: a static vector's M-norm is ~1e-8 of a mode's
        scale = 1.0 / np.sqrt(np.clip(np.diag(m), 1e-300, None))
        w, V = np.linalg.eigh(0.5 * (m + m.T) * np.outer(scale, scale))
        keep = w > 1e-10 * w.max()
        Q = scale[:, None] * V[:, keep] / np.sqrt(w[keep])
        P = lambda A: Q.T @ A @ Q   # noqa: E731
        return Pieces(ke=P(ke), kg=P(kg), k_rot=P(unit(rot_dofs)), k_vert=P(unit(vert_dofs)),
                      k_joint=P(theta.T @ theta), k_geo=P(k_geo), k_geo_point=P(k_geo_point),
                      k_geo_spread=P(k_geo_spread), m=P(m), m_point=P(m_point), m_spread=P(m_spread),
                      user=T[self.user_rows] @ Q, basis={"Q": Q, "T": T, "ends": hinged, "members": {}})

    def _couple(self, hinge) -> np.ndarray:
        """(n,) unit moments about a hinge's axis, opposite on its two nodes (its relative rotation's load)."""
        a, b, axis, *_ = hinge
        c = np.zeros(self.K.shape[0])
        c[6 * a + 3:6 * a + 6], c[6 * b + 3:6 * b + 6] = -axis, axis
        return c

    def _project(self, A, T: np.ndarray) -> np.ndarray:
        """Tᵀ A T for T = [Φ, X], from the cached Φ products: only the static vectors X are multiplied."""
        a_phi, phi_a_phi = self._phi_products[id(A)]
        X = T[:, self.n_basis:]
        ax = A @ X
        top = np.column_stack([phi_a_phi, a_phi.T @ X])
        return np.vstack([top, np.column_stack([top[:, self.n_basis:].T, T[:, self.n_basis:].T @ ax])])

    def member_stiffness(self, pieces: Pieces, member: int) -> np.ndarray:
        """(q, q) the projected elastic stiffness of one user member's elements (at the nominal section)."""
        got = pieces.basis["members"].get(member)
        if got is None:
            T, Q, ends = pieces.basis["T"], pieces.basis["Q"], pieces.basis["ends"]
            out = np.zeros((T.shape[1], T.shape[1]))
            for el in np.flatnonzero(self.mesh.member == member):
                u = ends.get(el, T[self.edofs[el]])
                out += u.T @ self.k_el[el] @ u
            got = pieces.basis["members"][member] = Q.T @ out @ Q
        return got

    def modes(self, n_modes: int, pieces: Pieces, stiffness_factor=1.0, member=None, member_factor=1.0,
              k_rot=0.0, k_vert=0.0, k_joint=0.0, point_mass_kg=0.0, spread_kg_per_m=0.0, gravity=False):
        """Frequencies (n,) Hz and mass-normalised translations (n_user, 3, n) of the user nodes, 1/√kg.

        member : a user member index, "all" (every member) or None; the other arguments are SI (N·m/rad, N/m,
        kg, kg/m)."""
        ke = pieces.ke
        if member == "all":
            ke = member_factor * ke
        elif member is not None and member_factor != 1.0:
            ke = ke + (member_factor - 1.0) * self.member_stiffness(pieces, member)
        K = stiffness_factor * ke + pieces.kg + k_rot * pieces.k_rot + k_vert * pieces.k_vert + k_joint * pieces.k_joint
        if gravity:   # the axial forces of the nominal's weight and of the added masses' (their redistribution by
            # a changed member, spring or joint is left out: second order for the screening, the fit's
            # winner is re-fitted in full)
            K = K + pieces.k_geo + point_mass_kg * pieces.k_geo_point + spread_kg_per_m * pieces.k_geo_spread
        M = pieces.m + point_mass_kg * pieces.m_point + spread_kg_per_m * pieces.m_spread
        n = min(int(n_modes), K.shape[0])
        lam, v = scipy.linalg.eigh(0.5 * (K + K.T), 0.5 * (M + M.T), subset_by_index=[0, n - 1],
                                   check_finite=False)
        u = pieces.user @ v
        # round-off of the dense solve (~1e-16) where the full solve has exact zeros (a planar frame's
        # out-of-plane modes at in-plane nodes): a unit-normalised sensor shape of it would be random
        u[np.abs(u) < 1e-10 * np.abs(u).max(axis=0)] = 0.0
        ref = 1.0 + np.sin(SIGN_SEED[0] * np.arange(u.shape[0]) + SIGN_SEED[1])
        u = u * np.where(ref @ u < 0, -1.0, 1.0)
        return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi), u.reshape(self.n_user, 3, n)
