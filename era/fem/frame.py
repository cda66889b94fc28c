"""A planar frame or grillage: nodes, bars, links between coincident nodes, springs and point masses.

Assembly of the out-of-plane (grillage) matrices and the lowest modes by ``scipy.linalg.eigh``.
All quantities in SI units (m, kg, N, Pa, rad).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.csgraph
import scipy.sparse.linalg

from ..errors import EraError
from . import elements
from .sparse import scatter


@dataclass(frozen=True, eq=False)
class PlaneFrame:
    """A structure of straight bars in the x-y plane.

    Attributes
    ----------
    nodes_m : (n, 2)
        Node coordinates x, y in metres.
    bars : (e, 2) int
        Node indices of each bar element.
    EI_out, GJ, EA, EI_in : (e,)
        Out-of-plane bending, torsion, axial and in-plane bending rigidities (N·m², N·m², N, N·m²).
    mass_per_length : (e,)
        kg/m, structural plus any non-structural mass carried by the bar.
    rho_ip : (e,)
        Twist inertia per length ρ I_p (kg·m).
    r2 : (e,)
        I_p / A (m²), for the Wagner term of the geometric stiffness in twist.
    links : (l, 2) int
        Pairs of coincident nodes joined by a connection (e.g. a riveted joint between two bars that cross).
        In the plane a link is rigid; out of the plane ``link_stiffness`` applies.
    link_stiffness : (l, 3)
        Stiffness of each link on (w, θx, θy): N/m, N·m/rad, N·m/rad; ``inf`` ties the two DOFs together.
    node_mass : (n,)
        Lumped point masses, kg, acting on w (and on the in-plane weight).
    node_springs : (n, 3)
        Springs to ground on (w, θx, θy): N/m, N·m/rad, N·m/rad.
    """

    nodes_m: np.ndarray
    bars: np.ndarray
    EI_out: np.ndarray
    GJ: np.ndarray
    EA: np.ndarray
    EI_in: np.ndarray
    mass_per_length: np.ndarray
    rho_ip: np.ndarray
    r2: np.ndarray
    links: np.ndarray
    link_stiffness: np.ndarray
    node_mass: np.ndarray
    node_springs: np.ndarray

    def __post_init__(self):
        for name in self.__dataclass_fields__:
            dtype = int if name in ("bars", "links") else float
            object.__setattr__(self, name, np.asarray(getattr(self, name), dtype=dtype))
        n = np.asarray(self.nodes_m).shape[0]
        e = np.asarray(self.bars).shape[0]
        for name in ("EI_out", "GJ", "EA", "EI_in", "mass_per_length", "rho_ip", "r2"):
            if np.shape(getattr(self, name)) != (e,):
                raise EraError(f"PlaneFrame: `{name}` must have one value per bar ({e}), got shape {np.shape(getattr(self, name))}.")
        if np.shape(self.node_mass) != (n,) or np.shape(self.node_springs) != (n, 3):
            raise EraError(f"PlaneFrame: node_mass must be ({n},) and node_springs ({n}, 3).")
        links = self.links.reshape(-1, 2)
        if np.shape(self.link_stiffness) != (links.shape[0], 3):
            raise EraError("PlaneFrame: link_stiffness must be (number of links, 3).")
        if np.any(self.EI_out <= 0) or np.any(self.GJ <= 0) or np.any(self.mass_per_length <= 0):
            raise EraError("PlaneFrame: bending and torsion rigidities and the mass per length must be positive.")
        object.__setattr__(self, "links", links)

    @property
    def n_nodes(self) -> int:
        return self.nodes_m.shape[0]

    def bar_geometry(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Length L (m) and direction cosines c, s of every bar, each (e,)."""
        d = self.nodes_m[self.bars[:, 1]] - self.nodes_m[self.bars[:, 0]]
        L = np.hypot(d[:, 0], d[:, 1])
        if np.any(L <= 0):
            raise EraError("PlaneFrame: a bar has zero length (its two nodes coincide).")
        return L, d[:, 0] / L, d[:, 1] / L

    def total_mass(self) -> float:
        """Bars plus point masses, kg."""
        L, _, _ = self.bar_geometry()
        return float(self.mass_per_length @ L + self.node_mass.sum())


def dof_map(n_nodes: int, links: np.ndarray, tied: np.ndarray) -> tuple[np.ndarray, int]:
    """Global DOF number of each node's 3 DOFs (n, 3) after tying linked DOFs, and the DOF count.

    tied : (l, 3) bool, which components of each link are rigid ties (the two DOFs become one).
    """
    li, comp = np.nonzero(np.asarray(tied, bool).reshape(-1, 3))
    a, b = 3 * links[li, 0] + comp, 3 * links[li, 1] + comp
    graph = scipy.sparse.coo_matrix((np.ones(a.size), (a, b)), shape=(3 * n_nodes, 3 * n_nodes))
    n_dof, label = scipy.sparse.csgraph.connected_components(graph, directed=False)
    # Renumber in order of first appearance, so that an untied model numbers node by node.
    _, first = np.unique(label, return_index=True)
    rank = np.empty(n_dof, int)
    rank[np.argsort(first)] = np.arange(n_dof)
    return rank[label].reshape(n_nodes, 3), int(n_dof)


@dataclass(frozen=True, eq=False)
class Assembled:
    """Out-of-plane system matrices.

    K = K_elastic + K_geometric + springs and the consistent mass M, sparse (n_dof, n_dof); ``dofs`` (n_nodes, 3)
    maps each node's (w, θx, θy) to its row.
    """

    K: scipy.sparse.csc_matrix
    M: scipy.sparse.csc_matrix
    dofs: np.ndarray


def assemble_out_of_plane(frame: PlaneFrame, axial_force: np.ndarray | None = None) -> Assembled:
    """Stiffness (elastic + geometric from ``axial_force`` (e,) N, tension > 0) and consistent mass."""
    L, c, s = frame.bar_geometry()
    stiff = np.asarray(frame.link_stiffness, float)
    dofs, n_dof = dof_map(frame.n_nodes, frame.links, np.isinf(stiff))
    edofs = np.concatenate([dofs[frame.bars[:, 0]], dofs[frame.bars[:, 1]]], axis=1)
    ke = elements.grillage_stiffness(L, c, s, frame.EI_out, frame.GJ)
    if axial_force is not None:
        ke = ke + elements.grillage_geometric(L, c, s, axial_force, frame.r2)
    # Springs between linked nodes (finite components) as 2×2 blocks k·[[1, -1], [-1, 1]], then springs to ground.
    li, comp = np.nonzero(np.isfinite(stiff) & (stiff != 0))
    a, b, k = dofs[frame.links[li, 0], comp], dofs[frame.links[li, 1], comp], stiff[li, comp]
    grounded = np.asarray(frame.node_springs, float).ravel()
    rows = np.concatenate([a, b, a, b, dofs.ravel()])
    cols = np.concatenate([a, b, b, a, dofs.ravel()])
    vals = np.concatenate([k, k, -k, -k, grounded])
    K = scatter(ke, edofs, n_dof, (rows, cols, vals))
    me = elements.grillage_mass(L, c, s, frame.mass_per_length, frame.rho_ip)
    M = scatter(me, edofs, n_dof, (dofs[:, 0], dofs[:, 0], frame.node_mass))
    return Assembled(K=K, M=M, dofs=dofs)


def lowest_modes(K, M, n_modes: int, shift: float = -1.0) -> tuple[np.ndarray, np.ndarray]:
    """The ``n_modes`` lowest modes of K φ = ω² M φ: frequencies (n_modes,) Hz and mass-normalised φ (n_dof, n_modes).

    K, M : (n_dof, n_dof) symmetric, sparse or dense; M positive definite, K positive semi-definite.
    shift : ω² (rad²/s²) below every eigenvalue, for the sparse shift-invert Lanczos solve (ARPACK), which is
        several times faster than dense LAPACK above ~200 DOFs; small problems go to ``scipy.linalg.eigh``.
    Tiny negative eigenvalues of rigid-body modes (round-off) are reported as 0 Hz.
    """
    n = K.shape[0]
    if not 1 <= n_modes <= n:
        raise EraError(f"lowest_modes: asked for {n_modes} modes of a model with {n} DOFs.")
    lam = None
    if n > 200 and n_modes < n // 4:
        try:
            lam, phi = scipy.sparse.linalg.eigsh(scipy.sparse.csc_matrix(K), n_modes, scipy.sparse.csc_matrix(M),
                                                 sigma=shift, which="LM", tol=1e-12,
                                                 v0=1.0 + np.sin(1.7 * np.arange(n) + 0.3))   # fixed start: repeatable
        except (scipy.sparse.linalg.ArpackError, RuntimeError):
            lam = None
    if lam is None:
        dense = [x.toarray() if scipy.sparse.issparse(x) else np.asarray(x) for x in (K, M)]
        lam, phi = scipy.linalg.eigh(*dense, subset_by_index=[0, n_modes - 1], check_finite=False)
    order = np.argsort(lam)
    lam, phi = lam[order], phi[:, order]
    phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, M @ phi))   # φᵀ M φ = 1
    return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi), phi
