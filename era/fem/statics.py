"""In-plane static solve of a frame under its own weight: the axial forces that stiffen it out of plane."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from ..errors import EraError
from . import elements
from .frame import PlaneFrame, dof_map

G_STANDARD = 9.80665  # m/s²


@dataclass(frozen=True, eq=False)
class SelfWeight:
    """Result of :func:`self_weight`.

    axial_force : (e,) N, tension > 0, constant along each bar element (the mean of the exact linear variation).
    reactions : (k, 2) N, support forces (Fx, Fy) at each support in the order given (Fy > 0 holds the frame up).
    displacement : (n, 3) in-plane (u, v, θz) of every node (m, m, rad).
    """

    axial_force: np.ndarray
    reactions: np.ndarray
    displacement: np.ndarray


def self_weight(frame: PlaneFrame, supports: list[tuple[int, bool, bool]], g: float = G_STANDARD) -> SelfWeight:
    """Linear in-plane static solve of ``frame`` hanging in the x-y plane with gravity along -y.

    Parameters
    ----------
    supports : list of (node, fix_u, fix_v)
        Pin supports; together they must remove the three in-plane rigid-body motions (e.g. two hanger
        points with v fixed and one of them with u fixed).
    g : float
        Gravitational acceleration, m/s².

    Loads: the consistent self-weight of every bar (mass_per_length · g, non-structural mass included)
    and the weight of the point masses. Links are rigid in the plane.
    """
    L, c, s = frame.bar_geometry()
    dofs, n_dof = dof_map(frame.n_nodes, frame.links, np.ones((frame.links.shape[0], 3), bool))
    edofs = np.concatenate([dofs[frame.bars[:, 0]], dofs[frame.bars[:, 1]]], axis=1)
    ke = elements.frame_stiffness(L, c, s, frame.EA, frame.EI_in)
    q = frame.mass_per_length * g
    fe = elements.frame_uniform_load(L, c, s, np.zeros_like(q), -q)
    f = np.bincount(edofs.ravel(), weights=fe.ravel(), minlength=n_dof)
    np.add.at(f, dofs[:, 1], -frame.node_mass * g)
    fixed = np.zeros(n_dof, bool)
    for node, fu, fv in supports:
        fixed[dofs[node, 0]] |= bool(fu)
        fixed[dofs[node, 1]] |= bool(fv)
    # Assemble K_ff directly from the element triplets (slicing a sparse matrix costs more than the solve).
    number = np.cumsum(~fixed) - 1
    rows, cols = np.repeat(edofs, 6, axis=1).ravel(), np.tile(edofs, (1, 6)).ravel()
    vals = ke.reshape(-1)
    keep = ~fixed[rows] & ~fixed[cols]
    n_free = int((~fixed).sum())
    kff = scipy.sparse.csc_matrix((vals[keep], (number[rows[keep]], number[cols[keep]])), shape=(n_free, n_free))
    u = np.zeros(n_dof)
    try:
        u[~fixed] = scipy.sparse.linalg.spsolve(kff, f[~fixed])
        if not np.isfinite(u).all() or np.linalg.norm(kff @ u[~fixed] - f[~fixed]) > 1e-8 * np.linalg.norm(f):
            raise np.linalg.LinAlgError
    except (np.linalg.LinAlgError, RuntimeError) as exc:
        raise EraError("self_weight: the supports do not hold the frame in its plane (singular stiffness); "
                       "fix v at two points and u at one.") from exc
    r = np.bincount(rows, weights=vals * u[cols], minlength=n_dof) - f      # K u - f: the support reactions
    reactions = np.array([[r[dofs[node, 0]] if fu else 0.0, r[dofs[node, 1]] if fv else 0.0]
                          for node, fu, fv in supports])
    axial = elements.frame_axial_force(L, c, s, frame.EA, u[edofs])
    return SelfWeight(axial_force=axial, reactions=reactions, displacement=u[dofs])
