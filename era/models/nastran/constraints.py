"""The assembled mesh of a deck made into Nastran's model: displacement frames (CD), CONM2 masses, CELAS springs,
RBE2, RBE3, MPC and SPC constraints in the grids' own frames, PARAM WTMASS, and AUTOSPC (a DOF without stiffness is held,
as Nastran's default for modes does).

Every DOF of a grid is numbered in its displacement frame: u_basic = A u_cd with A the frame's axes for the
translations and for the rotations. An RBE2's dependent components (in their grid's frame) are eliminated through
u_d = u_i + θ_i × (x_d - x_i), θ_d = θ_i; SPC components are dropped.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse

from ...errors import DataError
from ...fem.mesh import DIRECTIONS
from ...words import counted
from .coords import rectangular
from .deck import Deck
from .equations import equation_rows


@dataclass(frozen=True, eq=False)
class Reduced:
    """The free DOFs' stiffness and mass (csr (n, n)), their labels ((grid, direction), ...), each property's
    stiffness and mass {name: csr}, and notes (sentences) on what was held."""

    stiffness: scipy.sparse.csr_matrix
    mass: scipy.sparse.csr_matrix
    dofs: tuple
    parts: dict
    part_masses: dict
    notes: tuple


def _rotation(labels: list, cd_axes: dict) -> scipy.sparse.csr_matrix:
    """A (6N, 6N): u_basic = A u_cd, block-diagonal, the identity for grids in basic."""
    n = 6 * len(labels)
    turned = [i for i, label in enumerate(labels) if label in cd_axes]
    plain = np.setdiff1d(np.arange(n), (6 * np.array(turned, dtype=int)[:, None] + np.arange(6)).ravel())
    rows, cols, vals = [plain], [plain], [np.ones(plain.size)]
    r, c = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
    for i in turned:
        a = cd_axes[labels[i]]
        for half in (0, 3):
            rows.append(6 * i + half + r.ravel())
            cols.append(6 * i + half + c.ravel())
            vals.append(a.ravel())
    return scipy.sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                   shape=(n, n))


def _block(label: str, cd_axes: dict) -> np.ndarray:
    a = cd_axes.get(label, np.eye(3))
    out = np.zeros((6, 6))
    out[:3, :3] = out[3:, 3:] = a
    return out


def _conm2(deck: Deck, index: dict, positions: dict, cd_axes: dict, frames: dict, n: int):
    """The CONM2 masses (n, n) in the grids' displacement frames."""
    out = scipy.sparse.lil_matrix((n, n))
    for m in deck.masses.values():
        label = str(m.node)
        if m.cid == -1:
            r, axes = np.asarray(m.offset, float) - positions[label], np.eye(3)
        else:
            axes = rectangular(frames, m.cid, m.card).axes
            r = axes @ np.asarray(m.offset, float)
        inertia = axes @ m.inertia @ axes.T
        skew = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
        # the mass at x + r moves with u + θ × r = u - skew(r) θ: M6 = Sᵀ diag(m, m, m, I) S
        s = np.eye(6)
        s[:3, 3:] = -skew
        m6 = s.T @ np.diag([m.mass] * 3 + [0.0] * 3) @ s
        m6[3:, 3:] += inertia
        b = _block(label, cd_axes)
        k = 6 * index[label]
        out[k:k + 6, k:k + 6] += b.T @ m6 @ b
    return out.tocsr()


def _springs(deck: Deck, index: dict, n: int):
    rows, cols, vals = [], [], []
    for s in deck.springs.values():
        dofs = [6 * index[str(g)] + c - 1 for g, c in ((s.g1, s.c1), (s.g2, s.c2)) if g and c]
        if len(dofs) == 1:
            rows.append(dofs[0]), cols.append(dofs[0]), vals.append(s.k)
        elif len(dofs) == 2:
            i, j = dofs
            rows += [i, j, i, j]
            cols += [i, j, j, i]
            vals += [s.k, s.k, -s.k, -s.k]
    return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(n, n))


def _bushes(deck: Deck, index: dict, cd_axes: dict, frames: dict, n: int):
    """The CBUSH stiffness (n, n) in the grids' displacement frames: diag(K1..K6) along the bush's frame CID,
    between GA and GB or from GA to ground."""
    out = scipy.sparse.lil_matrix((n, n))
    for b in deck.bushes.values():
        axes = rectangular(frames, b.cid, b.card).axes
        k6 = np.zeros((6, 6))
        k6[:3, :3] = axes @ np.diag(b.k[:3]) @ axes.T
        k6[3:, 3:] = axes @ np.diag(b.k[3:]) @ axes.T
        ends = [str(b.ga)] + ([str(b.gb)] if b.gb else [])
        for i, gi in enumerate(ends):
            for j, gj in enumerate(ends):
                sign = 1.0 if i == j else -1.0
                block = _block(gi, cd_axes).T @ (sign * k6) @ _block(gj, cd_axes)
                a, c = 6 * index[gi], 6 * index[gj]
                out[a:a + 6, c:c + 6] += block
    return out.tocsr()


def _elimination(labels, index, positions, cd_axes, rigid, held,
                 equations=()) -> tuple[scipy.sparse.csr_matrix, np.ndarray]:
    """C (6N, n_free) with u_cd = C u_free, and the kept DOFs (n_free,) in the full numbering; ``equations``
    [(dependent DOF, [(independent DOF, coefficient), ...]), ...] the MPC and RBE3 rows (equations.py)."""
    n = 6 * len(labels)
    dependent = np.zeros(n, bool)
    rows, cols, vals = [], [], []
    for ind, deps, comps in rigid:
        i = index[ind]
        ai = _block(ind, cd_axes)
        for dep in deps:
            if dep == ind:
                continue
            r = np.asarray(positions[dep]) - np.asarray(positions[ind])
            link = np.eye(6)
            link[:3, 3:] = -np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
            rel = _block(dep, cd_axes).T @ link @ ai
            for c in comps:
                row = 6 * index[dep] + int(c) - 1
                if dependent[row]:
                    raise DataError(f"grid {dep} component {c} depends on two rigid elements (RBE2); a DOF may "
                                    "follow one independent grid only.")
                dependent[row] = True
                nz = np.flatnonzero(np.abs(rel[int(c) - 1]) > 1e-15)
                rows += [row] * nz.size
                cols += list(6 * i + nz)
                vals += list(rel[int(c) - 1, nz])
    for row, terms in equations:
        where = f"grid {labels[row // 6]} component {row % 6 + 1}"
        if dependent[row]:
            raise DataError(f"{where} is the dependent DOF of two constraints (RBE2, RBE3, MPC); a DOF may "
                            "depend on one only.")
        if held[row]:
            raise DataError(f"{where} is both held by an SPC and the dependent DOF of an MPC or RBE3; hold an "
                            "independent DOF instead.")
        dependent[row] = True
        rows += [row] * len(terms)
        cols += [int(j) for j, _ in terms]
        vals += [float(v) for _, v in terms]
    ident = np.flatnonzero(~dependent)
    C = scipy.sparse.csr_matrix((np.concatenate([np.ones(ident.size), vals]),
                                 (np.concatenate([ident, rows]).astype(int), np.concatenate([ident, cols]).astype(int))),
                                shape=(n, n))
    for _ in range(32):    # chains: the dependent grid of one RBE2 is the independent grid of another
        if C[:, dependent].nnz == 0:
            break
        C = (C @ C).tocsr()
    else:
        raise DataError("RBE2, RBE3 or MPC form a loop (a DOF depends on itself through others); break the loop.")
    keep = ~dependent & ~held
    kept = np.flatnonzero(keep)
    return C[:, kept].tocsr(), kept


def reduce(deck: Deck, dm, assembled, frames: dict) -> Reduced:
    """The deck's free-DOF matrices from the assembled mesh ``assembled`` (era.fem.mesh.assemble of
    ``dm.mesh``, no constraints in it) and the DeckMesh ``dm``; ``frames`` {cid: CoordFrame} (coords.py)."""
    labels = list(dict.fromkeys(node for node, _ in assembled.dofs))
    index = {label: i for i, label in enumerate(labels)}
    n = 6 * len(labels)
    order = np.array([6 * index[node] + DIRECTIONS.index(d) for node, d in assembled.dofs])
    perm = scipy.sparse.csr_matrix((np.ones(n), (order, np.arange(n))), shape=(n, n))  # full <- assembled
    A = _rotation(labels, dm.cd_axes)

    def to_cd(k):
        full = perm @ k @ perm.T
        return (A.T @ full @ A).tocsr()

    held = np.zeros(n, bool)
    for s in deck.constraints:
        label = str(s.node)
        if label in index:
            for c in s.components:
                if c != "0":
                    held[6 * index[label] + int(c) - 1] = True
    C, kept = _elimination(labels, index, dm.positions, dm.cd_axes, dm.rigid, held,
                           equation_rows(deck, index, dm.positions, dm.cd_axes))
    Ct = C.T.tocsr()

    def reduced(k):
        return (Ct @ k @ C).tocsr()

    extra_m = _conm2(deck, index, dm.positions, dm.cd_axes, frames, n) * deck.wtmass
    k_parts = {name: reduced(to_cd(k)) for name, k in assembled.part_stiffness.items()}
    m_parts = {name: reduced(to_cd(m)) for name, m in assembled.part_mass.items()}
    K = reduced(to_cd(assembled.stiffness) + _springs(deck, index, n) + _bushes(deck, index, dm.cd_axes, frames, n))
    M = reduced(to_cd(assembled.mass) + extra_m)
    diag = K.diagonal()
    live = diag > 1e-12 * max(float(np.abs(diag).max()) if diag.size else 0.0, 1e-300)
    notes = []
    if not live.all():
        dead = [f"{labels[kept[i] // 6]} {DIRECTIONS[kept[i] % 6]}" for i in np.flatnonzero(~live)]
        notes.append(f"AUTOSPC: {counted(len(dead), 'DOF')} without stiffness held "
                     f"({', '.join(dead[:6])}{' ...' if len(dead) > 6 else ''}).")
        keep = np.flatnonzero(live)
        K, M = K[keep][:, keep].tocsr(), M[keep][:, keep].tocsr()
        k_parts = {k: v[keep][:, keep].tocsr() for k, v in k_parts.items()}
        m_parts = {k: v[keep][:, keep].tocsr() for k, v in m_parts.items()}
        kept = kept[keep]
    dofs = tuple((labels[i // 6], DIRECTIONS[i % 6]) for i in kept)
    return Reduced(K, M, dofs, k_parts, m_parts, tuple(notes))
