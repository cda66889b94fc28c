"""The candidate effects for an FE model given as matrices (era.models.MatrixModel, wrapped in
MatrixExplainModel); docs/effects.md#matrices says what each changes physically."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..models.changes import PART, dof_place
from ..models.matrix import TRANSLATIONS
from .effects import EffectSpec, Param
from .matrix_model import MatrixExplainModel

#: Located effects list at most this many nodes; a larger mesh is thinned to nodes spread evenly over the
#: structure (with coordinates: one node per cell of a grid of about this many cells), which the screening ranks.
MAX_PLACES = 400


def spread(model: MatrixExplainModel, nodes: tuple, max_places: int = MAX_PLACES) -> tuple:
    """(places, words): ``nodes`` if there are at most ``max_places`` (words ""), else about that many spread
    over the structure, and a sentence saying so: with coordinates, the node nearest each occupied cell's centre
    of a box grid with cells about as many as ``max_places``; without, every k-th node in the model's order."""
    if len(nodes) <= max_places:
        return nodes, ""
    xyz = model.model.coordinates
    if xyz is None:
        step = int(np.ceil(len(nodes) / max_places))
        return nodes[::step], (f" The candidate places were every {step}th node of {len(nodes)} (the model has no "
                               "coordinates to spread them by): the effect may sit at a node between them.")
    p = np.array([xyz[n] for n in nodes])
    lo, hi = p.min(axis=0), p.max(axis=0)
    span = np.where(hi - lo > 1e-9 * max(float(np.max(hi - lo)), 1e-300), hi - lo, 0.0)
    used = span > 0
    cell = (float(np.prod(span[used])) / max_places) ** (1.0 / max(int(used.sum()), 1))
    key = np.floor((p - lo) / max(cell, 1e-300)).astype(np.int64)
    centre = lo + (key + 0.5) * cell
    dist = np.linalg.norm(np.where(used, p - centre, 0.0), axis=1)
    best: dict = {}
    for i, k in enumerate(map(tuple, key)):
        if k not in best or dist[i] < dist[best[k]]:
            best[k] = i
    words = (f" The candidate places were {len(best)} of the {len(nodes)} nodes, one per cell of "
             f"{cell:.3g} {model.model.units['length']}: the effect is within about that distance of the node named.")
    return tuple(nodes[i] for i in sorted(best.values())), words


def _static_stiffness(model: MatrixExplainModel, rows) -> np.ndarray:
    """The stiffness a spring to ground meets at each of ``rows``: 1 / Σ φ_i(row)² / λ_i over the nominal's
    elastic basis modes (a lower bound of the static flexibility, so an upper estimate of the stiffness), in the
    model's force / length (or force · length / rad) units."""
    lam, phi = model.nominal_basis()
    flex = np.sum(phi[np.asarray(rows, int)] ** 2 / lam[None, :], axis=1)
    return 1.0 / np.maximum(flex, 1e-300)


def _springs(model: MatrixExplainModel, nodes: tuple, directions: tuple, unit: str, what: str,
             thinned: str) -> list:
    """One ground-spring candidate per direction (their stiffness scales differ by orders: a plate is 1000 times
    stiffer in its plane than across it), each with its prior centred at the median stiffness a spring meets
    there; together they weigh as one candidate (prior odds 1/n each)."""
    m = model.model
    out = []
    for d in directions:
        places = tuple(dof_place(n, d) for n in nodes if (n, d) in m.dof_index)
        if not places:
            continue
        ks = _static_stiffness(model, [m.dof_index[(p.rsplit(":", 1)[0], d)] for p in places])
        k = float(np.median(ks))
        # the screening's trial: a tenth of the softest places' stiffness, so that the change it makes grows
        # linearly with the spring at nearly every place (a spring as stiff as the place pins it instead)
        trial = 0.1 * float(np.quantile(ks, 0.05))
        out.append(EffectSpec(
            f"ground_spring_{d}", (Param("spring_stiffness", True, np.log(k), 2.0, unit),),
            location_keyword="spring_at", locations=places, trial={"spring_stiffness": trial}, trial_power=1.0,
            summary=f"a {what} spring to ground in {d} holds the structure (a support or attachment the model "
                    "leaves free)", caveat="The spring is the equivalent grounded spring on that DOF." + thinned))
    return [dataclasses.replace(s, prior_log_odds=-float(np.log(len(out)))) for s in out]


def matrix_effects(model) -> tuple:
    """The candidate effects for a matrix model (docs/effects.md#matrices), relative to the nominal ``model``
    (a MatrixExplainModel; a MatrixModel with ``sensors`` is wrapped).

    Priors (log-normal) scale with the structure, as frame_effects' do: a point mass at 5 % of the structure's
    moving mass (1σ a factor e^1.2 ≈ 3.3); a spring to ground, one candidate per direction
    (ground_spring_x ... ground_spring_rz, together weighed as one), centred at the median stiffness a spring
    meets at that direction's DOFs (1 / Σ φ²/λ over the nominal's modes; 1σ a factor e² ≈ 7.4); a part's
    stiffness or mass 1 times as modelled (1σ a factor e^0.5); spread mass 10 % of the structure's (a factor
    3.3). Places: every node with a free translation (a mass), every free DOF
    (a spring), every part; a mesh with more than MAX_PLACES such nodes is thinned evenly over the structure
    (:func:`spread`).
    """
    if not isinstance(model, MatrixExplainModel):
        model = MatrixExplainModel.of(model, getattr(model, "sensors", None))
    m = model.model
    total = m.total_mass()
    u = m.units
    moving, thinned = spread(model, tuple(n for n in m.nodes if any((n, d) in m.dof_index for d in TRANSLATIONS)))
    out = [EffectSpec("none", summary="the nominal model is right up to a global stiffness factor"),
           EffectSpec("point_mass", (Param("point_mass", True, np.log(0.05 * total), 1.2, u["mass"]),),
                      location_keyword="point_mass_at", locations=moving, trial={"point_mass": 0.05 * total},
                      summary="a concentrated mass is attached",
                      caveat="The mass is the equivalent point mass on the node's translations." + thinned)]
    out += _springs(model, moving, TRANSLATIONS, f"{u['force']}/{u['length']}", "translational", thinned)
    every, thinned_all = spread(model, m.nodes)
    out += _springs(model, every, ("rx", "ry", "rz"), f"{u['force']}·{u['length']}/rad", "rotational", thinned_all)
    if m.parts:
        out.append(EffectSpec(
            "part_stiffness", (Param("part_factor", True, 0.0, 0.5, ""),), location_keyword="part_at",
            locations=tuple(PART + p for p in m.parts), trial={"part_factor": 0.7}, trial_power=-1.0,
            summary="a part is stiffer or softer than modelled (its stiffness matrix times a factor)",
            place_temperature=2.0, either_way=True))
    if m.part_masses:
        out.append(EffectSpec(
            "part_mass", (Param("part_mass_factor", True, 0.0, 0.5, ""),), location_keyword="part_mass_at",
            locations=tuple(PART + p for p in m.part_masses), trial={"part_mass_factor": 1.3}, trial_power=1.0,
            summary="a part is heavier or lighter than modelled (its mass matrix times a factor)", either_way=True))
    out.append(EffectSpec(
        "distributed_mass", (Param("distributed_mass", True, np.log(0.1 * total), 1.2, u["mass"]),),
        summary="there is extra mass spread over the structure in proportion to its own",
        caveat="Spread mass lowers the modes as a softer structure would; only the prior on the stiffness "
               "(±1.5 %) and, with known impulse inputs, the modal constants tell them apart."))
    return tuple(out)
