"""A deck's linear constraint equations as rows u_dependent = Σ coefficient × u_independent over the grids' DOFs in
their displacement frames: MPC (Σ A u = 0, the first DOF dependent) and RBE3.

RBE3: the reference grid's motion is the rigid-body motion (u, θ) that fits the independent grids' listed
components best in the weighted least-squares sense, min Σ w (y_obs − y_rigid)², with a rotation component's
weight times Lc², Lc the mean distance of the independent grids from the reference (Nastran's scaling, which makes
the fit independent of the length unit); the reference grid's REFC components are that motion's. Only the
reference grid is moved: RBE3 adds no stiffness, and its mass and loads reach the independent grids.
"""

from __future__ import annotations

import numpy as np

from ...errors import DataError


def _block(label: str, cd_axes: dict) -> np.ndarray:
    """(6, 6) u_basic = block u_cd of one grid."""
    a = cd_axes.get(label, np.eye(3))
    out = np.zeros((6, 6))
    out[:3, :3] = out[3:, 3:] = a
    return out


def _skew(r: np.ndarray) -> np.ndarray:
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def interpolation_rows(r, index: dict, positions: dict, cd_axes: dict) -> list:
    """[(dependent DOF, [(independent DOF, coefficient), ...]), ...] of one RBE3 ``r`` (InterpolationCard), DOFs
    numbered 6 × index[grid] + component − 1."""
    ref = str(r.ref)
    x_ref = np.asarray(positions[ref], float)
    rows, weights, dofs = [], [], []
    grids = [str(g) for _, _, gs in r.groups for g in gs]
    if ref in grids:
        raise r.card.error(f"its reference grid {ref} is also an independent grid; give them apart")
    lc = np.mean([np.linalg.norm(np.asarray(positions[g]) - x_ref) for g in grids]) or 1.0
    for weight, comps, gs in r.groups:
        if weight <= 0:
            raise r.card.error(f"a weight is {weight:g}; give positive weights")
        for g in map(str, gs):
            link = np.eye(6)
            link[:3, 3:] = -_skew(np.asarray(positions[g], float) - x_ref)   # u_g = u + θ × (x_g − x_ref)
            seen = _block(g, cd_axes).T @ link              # the grid's CD components of the rigid motion
            for c in comps:
                rows.append(seen[int(c) - 1])
                weights.append(weight * (lc ** 2 if int(c) > 3 else 1.0))
                dofs.append(6 * index[g] + int(c) - 1)
    s, w = np.array(rows), np.array(weights)
    normal = s.T @ (w[:, None] * s)
    u, sv, vt = np.linalg.svd(normal)
    free = vt[sv <= 1e-10 * sv[0]]                          # rigid motions the independent grids do not see
    fit = np.linalg.pinv(normal, rcond=1e-10) @ (s.T * w)   # (6, observations): (u, θ) of the reference
    out_rows = _block(ref, cd_axes).T @ fit
    out = []
    for c in r.refc:
        row = _block(ref, cd_axes).T[int(c) - 1]
        if free.size and np.abs(free @ row).max() > 1e-8:
            raise r.card.error(f"its independent grids' components do not determine component {c} of the "
                               f"reference grid {ref} (too few grids or components, or grids on a line)")
        coef = out_rows[int(c) - 1]
        keep = np.abs(coef) > 1e-14 * np.abs(coef).max()
        out.append((6 * index[ref] + int(c) - 1, list(zip(np.array(dofs)[keep], coef[keep]))))
    return out


def mpc_rows(m, index: dict) -> tuple:
    """(dependent DOF, [(independent DOF, coefficient), ...]) of one MPC equation ``m`` (MpcCard)."""
    (g1, c1, a1), rest = m.terms[0], m.terms[1:]
    return 6 * index[str(g1)] + c1 - 1, [(6 * index[str(g)] + c - 1, -a / a1) for g, c, a in rest if a != 0.0]


def equation_rows(deck, index: dict, positions: dict, cd_axes: dict) -> list:
    """Every MPC and RBE3 row of ``deck`` (see interpolation_rows); DataError naming the card when a grid is not
    in the model."""
    out = []
    for m in deck.equations:
        for g, _, _ in m.terms:
            if str(g) not in index:
                raise DataError(f"{m.card.where()}: GRID {g} is not in the deck. Add it or correct the MPC.")
        out.append(mpc_rows(m, index))
    for r in deck.interpolations.values():
        for g in (r.ref, *(g for _, _, gs in r.groups for g in gs)):
            if str(g) not in index:
                raise DataError(f"{r.card.where()}: GRID {g} is not in the deck. Add it or correct the RBE3.")
        out += interpolation_rows(r, index, positions, cd_axes)
    return out
