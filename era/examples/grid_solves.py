"""Cheaper solves of the grid model for explain's speed, each checked against the path it replaces
(tests/discrepancy/test_fast_fits.py): solves shared by parameter set, the matrices assembled on a kept sparse
pattern, the self-weight solve superposed for added masses, and the attachment modes that make a Rayleigh-Ritz
approximation follow a local change (GridModel.ritz)."""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import replace

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from .. import fem


class SolveCache:
    """Solves shared by a model and every model derived from it by ``with_params`` (one explain() run asks for
    the same parameters more than once: a fit's last trial and its result, a profile's centre, a re-fit's start).

    Keyed by the full parameter set (the perturbation is the family's own); holds the self-weight forces per set
    of weight-moving parameters (_STATIC_PARAMS) and each model's lowest modes. Bounded: the oldest entries go
    first. Counters (machine-independent cost figures): n_solves (eigensolutions), n_ritz (Rayleigh-Ritz
    approximations), n_statics (in-plane self-weight solves), n_hits (modes served from the cache)."""

    def __init__(self, max_entries: int = 256):
        self.max_entries = max_entries
        self.modes, self.statics = OrderedDict(), OrderedDict()
        self.n_solves = self.n_ritz = self.n_statics = self.n_hits = 0

    @staticmethod
    def put(store: OrderedDict, key, value, limit: int):
        store[key] = value
        store.move_to_end(key)
        while len(store) > limit:
            store.popitem(last=False)

    def counts(self) -> dict:
        return {"solves": self.n_solves, "ritz": self.n_ritz, "statics": self.n_statics, "hits": self.n_hits}


def param_key(params: dict, names=None) -> tuple:
    """A hashable key of a model's parameters (all, or those in ``names``)."""
    return tuple((k, params[k]) for k in sorted(params) if names is None or k in names)


def assemble_grid(frame: fem.PlaneFrame, axial_force, cache: SolveCache) -> fem.Assembled:
    """fem.assemble_out_of_plane with the DOF map and the sparse pattern kept per mesh (the split joints and
    which of their springs are finite): the same matrices, entry for entry, without rebuilding the sparse
    structure at every parameter change (tests/discrepancy/test_fast_fits.py checks them against it)."""
    stiff = np.asarray(frame.link_stiffness, float)
    rigid = np.isinf(stiff)
    li, comp = np.nonzero(np.isfinite(stiff) & (stiff != 0))
    key = ("pattern", frame.n_nodes, frame.links.tobytes(), rigid.tobytes(), li.tobytes(), comp.tobytes(),
           frame.bars.tobytes())
    pattern = cache.statics.get(key)
    if pattern is None:
        dofs, n_dof = fem.dof_map(frame.n_nodes, frame.links, rigid)
        edofs = np.concatenate([dofs[frame.bars[:, 0]], dofs[frame.bars[:, 1]]], axis=1)
        a, b = dofs[frame.links[li, 0], comp], dofs[frame.links[li, 1], comp]
        rows = np.concatenate([np.repeat(edofs, 6, axis=1).ravel(), a, b, a, b, dofs.ravel()])
        cols = np.concatenate([np.tile(edofs, (1, 6)).ravel(), a, b, b, a, dofs.ravel()])
        mrows = np.concatenate([np.repeat(edofs, 6, axis=1).ravel(), dofs[:, 0]])
        mcols = np.concatenate([np.tile(edofs, (1, 6)).ravel(), dofs[:, 0]])

        def compress(r, c):     # each triplet's place in the CSC data of the summed matrix
            order = np.lexsort((r, c))
            rc = np.stack([c[order], r[order]])
            new = np.r_[True, np.any(rc[:, 1:] != rc[:, :-1], axis=0)]
            slot = np.empty(r.size, int)
            slot[order] = np.cumsum(new) - 1
            indptr = np.searchsorted(c[order][new], np.arange(n_dof + 1))
            return slot, r[order][new], indptr

        pattern = (dofs, n_dof, compress(rows, cols), compress(mrows, mcols))
        cache.put(cache.statics, key, pattern, 4 * cache.max_entries)
    dofs, n_dof, (ks, ki, kp), (ms, mi, mp) = pattern
    L, c, s = frame.bar_geometry()
    ke = fem.elements.grillage_stiffness(L, c, s, frame.EI_out, frame.GJ)
    if axial_force is not None:
        ke = ke + fem.elements.grillage_geometric(L, c, s, axial_force, frame.r2)
    k = stiff[li, comp]
    kv = np.concatenate([ke.reshape(-1), k, k, -k, -k, np.asarray(frame.node_springs, float).ravel()])
    me = fem.elements.grillage_mass(L, c, s, frame.mass_per_length, frame.rho_ip)
    mv = np.concatenate([me.reshape(-1), frame.node_mass])
    K = scipy.sparse.csc_matrix((np.bincount(ks, kv, ki.size), ki, kp), shape=(n_dof, n_dof))
    M = scipy.sparse.csc_matrix((np.bincount(ms, mv, mi.size), mi, mp), shape=(n_dof, n_dof))
    return fem.Assembled(K=K, M=M, dofs=dofs)


def grid_self_weight(frame: fem.PlaneFrame, supports: list, cache: SolveCache, structure: tuple, spread_per_bar: float,
                spread_kg: float, point_kg: float, point_joint: int | None) -> tuple:
    """(axial force (e,), support vertical reactions (2,)) of the in-plane self-weight solve (fem.self_weight).

    The solve is linear in the weights, so once a ``structure`` (the mesh and member stiffnesses, as a key) has
    been solved for one set of weights, the next sets are sums of unit solves kept in the cache: the bare
    structure, 1 kg spread over every bar (``spread_per_bar`` kg/m per kg), 1 kg at a joint. A fit of a point or
    spread mass then costs no more statics solves. ``spread_kg``, ``point_kg`` at ``point_joint``: the frame's
    own added masses, which the bare structure leaves out."""
    c = cache

    def solve(f):
        c.n_statics += 1
        out = fem.self_weight(f, supports)
        return np.r_[out.axial_force, out.reactions[:, 1]]

    unit = c.statics.get(("unit",) + structure)
    if unit is None:
        if ("seen",) + structure not in c.statics:     # the first weights on this structure: one solve
            c.put(c.statics, ("seen",) + structure, True, 4 * c.max_entries)
            x = solve(frame)
            return x[:-2], x[-2:]
        node_mass = frame.node_mass.copy()
        if point_kg > 0:
            node_mass[point_joint] -= point_kg
        spread = np.full(frame.bars.shape[0], spread_per_bar)
        bare = replace(frame, mass_per_length=frame.mass_per_length - spread_kg * spread, node_mass=node_mass)
        unit = {"frame": bare, "bare": solve(bare), "joints": {}}
        # a frame must have mass on every bar: unit loads as differences (1 kg against ~42 kg: no rounding)
        unit["spread"] = solve(replace(bare, mass_per_length=bare.mass_per_length + spread)) - unit["bare"]
        c.put(c.statics, ("unit",) + structure, unit, 4 * c.max_entries)
    x = unit["bare"] + spread_kg * unit["spread"]
    if point_kg > 0:
        if point_joint not in unit["joints"]:
            bare = unit["frame"]
            m = bare.node_mass.copy()
            m[point_joint] += 1.0
            unit["joints"][point_joint] = solve(replace(bare, node_mass=m)) - unit["bare"]
        x = x + point_kg * unit["joints"][point_joint]
    return x[:-2], x[-2:]


def changed_nodes(frame: fem.PlaneFrame, ref: fem.PlaneFrame, node_ref: np.ndarray, new_splits,
                  most: int = 12) -> np.ndarray:
    """Reference nodes where ``frame`` differs from ``ref`` locally (GridModel.ritz): the nodes of bars whose
    stiffness or mass departs from the change shared by every bar (E, GJ scaled globally is not local), nodes
    whose lumped mass or ground spring changed, joints split anew. Empty when more than ``most`` nodes change
    (a change that widespread is for the modes to carry); None when the springs of many joints changed by more
    than 5 % (every joint's relative rotation would be needed: no cheaper than a solve)."""
    out = set(int(j) for j in new_splits)
    ref_links = {int(j): k for k, j in enumerate(ref.links[:, 0])}
    sprung, rel = 0, 0.0
    for k, j in enumerate(frame.links[:, 0].tolist()):     # a spring that changed at a joint split in both
        a, b = frame.link_stiffness[k], ref.link_stiffness[ref_links[j]] if j in ref_links else None
        if b is not None and not np.array_equal(a, b):
            out |= set(node_ref[frame.links[k]].tolist())
            sprung += 1
            fin = np.isfinite(b) & (b > 0)
            rel = max(rel, float(np.max(np.abs(a[fin] / b[fin] - 1.0), initial=0.0)) if np.isfinite(a[fin]).all()
                      else np.inf)
    if sprung > most // 2:     # the springs of many joints changed: a few per cent is for the modes to carry,
        return np.zeros(0, int) if rel <= 0.05 else None     # more needs every joint's relative rotation
    ratio = (np.stack([frame.EI_out, frame.GJ, frame.mass_per_length, frame.rho_ip])
             / np.stack([ref.EI_out, ref.GJ, ref.mass_per_length, ref.rho_ip]))
    shared = np.median(ratio, axis=1, keepdims=True)
    odd = np.flatnonzero(np.any(np.abs(ratio - shared) > 1e-9 * np.abs(shared), axis=0))
    if odd.size > most:
        return np.zeros(0, int)
    out |= set(node_ref[frame.bars[odd].ravel()].tolist())
    mass = np.bincount(node_ref, frame.node_mass, ref.n_nodes)
    springs = np.stack([np.bincount(node_ref, frame.node_springs[:, i], ref.n_nodes) for i in range(3)], axis=1)
    out |= set(np.flatnonzero(np.abs(mass - ref.node_mass) > 1e-12).tolist())
    out |= set(np.flatnonzero(np.any(np.abs(springs - ref.node_springs) > 1e-9 * np.abs(ref.node_springs).max(),
                                     axis=1)).tolist())
    return np.array(sorted(out), int) if len(out) <= most else np.zeros(0, int)


def attachments(store: dict, system: fem.Assembled, nodes: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Static responses (K + M)⁻¹ e of a model (its ``system``) to unit loads on every DOF of ``nodes``, with
    their part in the span of its mass-normalised modes ``phi`` removed, orthonormalised; (n_dof, ≤ 3·len(nodes)).
    ``store``: a dict of the model's own (its factorisation and the attachments asked for, which a fit's trials
    ask for again and again)."""
    kept = store.setdefault("_attached", {})
    key = (nodes.tobytes(), phi.shape[1])
    if key in kept:
        return kept[key]
    lu = store.get("_shifted_lu")
    if lu is None:   # K + M: non-singular even with a free swing (gravity off), and the same span
        lu = store["_shifted_lu"] = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(system.K + system.M))
    cols = system.dofs[nodes].ravel()
    e = np.zeros((system.K.shape[0], cols.size))
    e[cols, np.arange(cols.size)] = 1.0
    a = lu.solve(e)
    a -= phi @ (phi.T @ (system.M @ a))
    q, r = np.linalg.qr(a)
    keep = np.abs(np.diag(r)) > 1e-8 * max(np.abs(np.diag(r)).max(), 1e-300)
    if len(kept) > 64:
        kept.clear()
    kept[key] = q[:, keep]
    return kept[key]
