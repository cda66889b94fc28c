"""What each effect changes in a MatrixModel's matrices (docs/effects.md#matrices), as keywords: the one place
both explain's model of the matrices (era.discrepancy.matrix_model) and the patch (era.models.patch) read.

Keywords (EFFECT_DEFAULTS): stiffness_factor s (the whole stiffness); point_mass_at (a node) + point_mass m (on
each of its free translations); spring_at ("node:direction") + spring_stiffness k (a spring to ground on that
DOF); part_at ("part:name") + part_factor θ (that part's stiffness); part_mass_at ("part:name") +
part_mass_factor θ_m (that part's mass); distributed_mass d (the mass scaled by 1 + d / total mass):

    K' = s (K + (θ − 1) K_part) + k e eᵀ
    M' = (1 + d / m_total) M + (θ_m − 1) M_part + m Σ_translations e eᵀ
"""

from __future__ import annotations

import numpy as np
import scipy.sparse

from ..errors import DataError
from .matrix import DIRECTIONS, TRANSLATIONS, MatrixModel

EFFECT_DEFAULTS = dict(stiffness_factor=1.0, point_mass_at=None, point_mass=0.0, spring_at=None,
                       spring_stiffness=0.0, part_at=None, part_factor=1.0, part_mass_at=None, part_mass_factor=1.0,
                       distributed_mass=0.0)
PART = "part:"      # a part's place: "part:deck" (a node's place is its label, a DOF's "node:direction")


def dof_place(node, direction) -> str:
    return f"{node}:{direction}"


def split_dof(place) -> tuple[str, str]:
    """(node, direction) of a DOF place "node:direction"."""
    node, _, d = str(place).rpartition(":")
    if not node or d not in DIRECTIONS:
        raise DataError(f"spring_at {place!r}: give a DOF as 'node:direction', direction one of x .. rz.")
    return node, d


def part_name(place, parts: dict) -> str:
    name = str(place)
    name = name[len(PART):] if name.startswith(PART) else name
    if name not in parts:
        raise DataError(f"no part {name!r} in the model; its parts are {', '.join(parts) or 'none'}.")
    return name


def mass_rows(model: MatrixModel, node) -> np.ndarray:
    """The rows of a node's free translations (where a point mass acts)."""
    rows = [model.dof_index[(str(node), d)] for d in TRANSLATIONS if (str(node), d) in model.dof_index]
    if not rows:
        raise DataError(f"node {node} has no free translation in the model: a point mass there does not move.")
    return np.array(rows, dtype=int)


def pieces(model: MatrixModel, params: dict) -> dict:
    """The changes ``params`` make, as pieces the full and the reduced solutions both assemble:
    {"s", "k_part" (sparse or None), "theta", "m_part", "theta_m", "mass_scale", "spring" (row, k) or None,
    "mass" (rows, m) or None}."""
    p = {**EFFECT_DEFAULTS, **params}
    out = {"s": float(p["stiffness_factor"]), "k_part": None, "theta": 1.0, "m_part": None, "theta_m": 1.0,
           "mass_scale": 1.0, "spring": None, "mass": None}
    if p["part_at"] is not None and p["part_factor"] != 1.0:
        out["k_part"] = model.parts[part_name(p["part_at"], model.parts)]
        out["theta"] = float(p["part_factor"])
    if p["part_mass_at"] is not None and p["part_mass_factor"] != 1.0:
        out["m_part"] = model.part_masses[part_name(p["part_mass_at"], model.part_masses)]
        out["theta_m"] = float(p["part_mass_factor"])
    if p["distributed_mass"]:
        out["mass_scale"] = 1.0 + float(p["distributed_mass"]) / model.total_mass()
    if p["spring_at"] is not None and p["spring_stiffness"]:
        out["spring"] = (model.index(*split_dof(p["spring_at"])), float(p["spring_stiffness"]))
    if p["point_mass_at"] is not None and p["point_mass"]:
        out["mass"] = (mass_rows(model, p["point_mass_at"]), float(p["point_mass"]))
    for key in ("s", "theta", "theta_m", "mass_scale"):
        if not np.isfinite(out[key]) or out[key] <= 0:
            raise DataError(f"{key} = {out[key]:g}: a factor on a matrix must be positive and finite.")
    return out


def changed_matrices(model: MatrixModel, params: dict) -> tuple[scipy.sparse.csr_matrix, scipy.sparse.csr_matrix]:
    """(K', M') of ``model`` with the effects ``params`` (keywords of EFFECT_DEFAULTS) put in."""
    q = pieces(model, params)
    n = model.n_dofs
    k = model.stiffness if q["k_part"] is None else model.stiffness + (q["theta"] - 1.0) * q["k_part"]
    k = q["s"] * k
    if q["spring"] is not None:
        row, value = q["spring"]
        k = k + scipy.sparse.csr_matrix(([value], ([row], [row])), shape=(n, n))
    m = q["mass_scale"] * model.mass
    if q["m_part"] is not None:
        m = m + (q["theta_m"] - 1.0) * q["m_part"]
    if q["mass"] is not None:
        rows, value = q["mass"]
        m = m + scipy.sparse.csr_matrix((np.full(rows.size, value), (rows, rows)), shape=(n, n))
    return k.tocsr(), m.tocsr()
