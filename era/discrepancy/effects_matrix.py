"""The candidate effects for an FE model given as matrices (era.models.MatrixModel, wrapped in
MatrixExplainModel); docs/effects.md#matrices says what each changes physically."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import scipy.spatial

from ..models.changes import PART, dof_place
from ..models.matrix import TRANSLATIONS
from .effects import EffectSpec, Param
from .matrix_model import MatrixExplainModel

#: Located effects list at most this many nodes; a larger mesh is thinned to nodes spread evenly over the
#: structure (with coordinates: one node per cell of a grid of about this many cells), which the screening ranks,
#: and the nodes near the best of them are screened in a second pass (EffectSpec.nearby).
MAX_PLACES = 400


@dataclass(frozen=True)
class Places:
    """A located effect's candidate nodes: ``nodes`` (every one, or those kept when thinned), ``nearby``
    ({kept node: (the nodes left out near it, nearest first)}, None when nothing was thinned) and ``words`` (a
    sentence for the effect's caveat saying how the places were chosen, "" when every node is a place)."""

    nodes: tuple
    nearby: dict | None = None
    words: str = ""

    def of(self, place) -> tuple:
        """(places, nearby) with each node turned into a place by ``place(node)`` (None: not a place)."""
        keep = {n: place(n) for n in self.nodes}
        places = tuple(p for p in keep.values() if p is not None)
        if self.nearby is None:
            return places, None
        near = {keep[n]: tuple(q for q in map(place, self.nearby[n]) if q is not None)
                for n in self.nodes if keep[n] is not None}
        return places, near


def spread(model: MatrixExplainModel, nodes: tuple, max_places: int = MAX_PLACES) -> Places:
    """The candidate places among ``nodes``: all of them if there are at most ``max_places``, else about that
    many spread over the structure, with the nodes left out near each (Places.nearby, which the ranking screens
    around the best): with coordinates, the node nearest each occupied cell's centre of a box grid with cells
    about as many as ``max_places`` over the directions the nodes span (a direction thinner than a cell, a
    plate's thickness, is not cut), and near it every node within a cell's size (or more: as far as the node
    farthest from every kept one); without coordinates every k-th node in the model's order, and near it the
    k − 1 on each side."""
    if len(nodes) <= max_places:
        return Places(tuple(nodes))
    xyz = model.model.coordinates
    if xyz is None:
        step = int(np.ceil(len(nodes) / max_places))
        every = range(0, len(nodes), step)
        near = {nodes[i]: tuple(nodes[j] for d in range(1, step) for j in (i + d, i - d) if 0 <= j < len(nodes))
                for i in every}
        return Places(tuple(nodes[i] for i in every), near,
                      f" The candidate places were one node in {step} of {len(nodes)}, in the model's order (it has "
                      "no coordinates to spread them by), then the nodes beside the best of them in that order.")
    p = np.array([xyz[n] for n in nodes], float)
    lo, hi = p.min(axis=0), p.max(axis=0)
    span = hi - lo
    used = span > 1e-9 * max(float(np.max(span)), 1e-300)
    while True:     # the cell's size over the directions spanned by more than a cell
        cell = (float(np.prod(span[used])) / max_places) ** (1.0 / max(int(used.sum()), 1))
        thin = used & (span < cell)
        if not thin.any() or thin.sum() == used.sum():
            break
        used &= ~thin
    key = np.floor(np.where(used, p - lo, 0.0) / max(cell, 1e-300)).astype(np.int64)
    centre = lo + (key + 0.5) * cell
    dist = np.linalg.norm(np.where(used, p - centre, 0.0), axis=1)
    best: dict = {}
    for i, k in enumerate(map(tuple, key)):
        if k not in best or dist[i] < dist[best[k]]:
            best[k] = i
    kept = sorted(best.values())
    # every node near at least one kept node: the reach is a cell, or more where the cells alias the mesh's
    # rows and leave a node farther than a cell from every kept one
    reach = 1.000001 * max(cell, float(np.max(scipy.spatial.cKDTree(p[kept]).query(p)[0])))
    tree = scipy.spatial.cKDTree(p)
    is_kept = np.zeros(len(nodes), bool)
    is_kept[kept] = True
    near = {}
    for i in kept:
        js = np.array(tree.query_ball_point(p[i], reach), int)
        js = js[~is_kept[js]]
        js = js[np.argsort(np.linalg.norm(p[js] - p[i], axis=1), kind="stable")]
        near[nodes[i]] = tuple(nodes[j] for j in js)
    unit = model.model.units["length"]
    return Places(tuple(nodes[i] for i in kept), near,
                  f" The candidate places were {len(kept)} of the {len(nodes)} nodes, one per cell of {cell:.3g} "
                  f"{unit}, then every node within {reach:.3g} {unit} of the best of them.")


def _static_stiffness(model: MatrixExplainModel, rows) -> np.ndarray:
    """The stiffness a spring to ground meets at each of ``rows``: 1 / Σ φ_i(row)² / λ_i over the nominal's
    elastic basis modes (a lower bound of the static flexibility, so an upper estimate of the stiffness), in the
    model's force / length (or force · length / rad) units."""
    lam, phi = model.nominal_basis()
    flex = np.sum(phi[np.asarray(rows, int)] ** 2 / lam[None, :], axis=1)
    return 1.0 / np.maximum(flex, 1e-300)


def _springs(model: MatrixExplainModel, nodes: Places, directions: tuple, unit: str, what: str) -> list:
    """One ground-spring candidate per direction (their stiffness scales differ by orders: a plate is 1000 times
    stiffer in its plane than across it), each with its prior centred at the median stiffness a spring meets
    there; together they weigh as one candidate (prior odds 1/n each)."""
    m = model.model
    out = []
    for d in directions:
        places, near = nodes.of(lambda n: dof_place(n, d) if (n, d) in m.dof_index else None)   # noqa: B023
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
                    "leaves free)", caveat="The spring is the equivalent grounded spring on that DOF." + nodes.words,
            nearby=near))
    return [dataclasses.replace(s, prior_log_odds=-float(np.log(len(out)))) for s in out]


def matrix_effects(model) -> tuple:
    """The candidate effects for a matrix model (docs/effects.md#matrices), relative to the nominal ``model``.

    Priors (log-normal) scale with the structure, as frame_effects' do: a point mass at 5 % of the structure's
    moving mass (1σ a factor e^1.2 ≈ 3.3); a spring to ground, one candidate per direction
    (ground_spring_x ... ground_spring_rz, together weighed as one), centred at the median stiffness a spring
    meets at that direction's DOFs (1 / Σ φ²/λ over the nominal's modes; 1σ a factor e² ≈ 7.4); a part's
    stiffness or mass 1 times as modelled (1σ a factor e^0.5); spread mass 10 % of the structure's (a factor
    3.3). Places: every node with a free translation (a mass), every free DOF (a spring), every part; a mesh with
    more than MAX_PLACES such nodes is thinned evenly over the structure and the nodes near the best thinned ones
    are screened in a second pass (:func:`spread`).

    Parameters
    ----------
    model : MatrixExplainModel or MatrixModel
        The nominal; a MatrixModel with ``sensors`` is wrapped (MatrixExplainModel.of).

    Returns
    -------
    list of EffectSpec
        "none" first, then each candidate effect with its parameters' priors and its places.

    Examples
    --------
    >>> k = 1e5 * (2 * np.eye(6) - np.eye(6, k=1) - np.eye(6, k=-1))  # six 1 kg masses on springs of 100 kN/m
    >>> k[-1, -1] = 1e5  # the top is free; below node 1 the chain is fixed to ground
    >>> dofs = [(str(i + 1), "z") for i in range(6)]
    >>> model = era.MatrixModel(k, np.eye(6), dofs, sensors=dofs)
    >>> [(effect.name, effect.locations) for effect in era.matrix_effects(model)]  # doctest: +NORMALIZE_WHITESPACE
    [('none', None), ('point_mass', ('1', '2', '3', '4', '5', '6')),
     ('ground_spring_z', ('1:z', '2:z', '3:z', '4:z', '5:z', '6:z')), ('distributed_mass', None)]
    """
    if not isinstance(model, MatrixExplainModel):
        model = MatrixExplainModel.of(model, getattr(model, "sensors", None))
    m = model.model
    total = m.total_mass()
    u = m.units
    moving = spread(model, tuple(n for n in m.nodes if any((n, d) in m.dof_index for d in TRANSLATIONS)))
    out = [EffectSpec("none", summary="the nominal model is right up to a global stiffness factor"),
           EffectSpec("point_mass", (Param("point_mass", True, np.log(0.05 * total), 1.2, u["mass"]),),
                      location_keyword="point_mass_at", locations=moving.nodes, trial={"point_mass": 0.05 * total},
                      summary="a concentrated mass is attached", nearby=moving.nearby,
                      caveat="The mass is the equivalent point mass on the node's translations." + moving.words)]
    out += _springs(model, moving, TRANSLATIONS, f"{u['force']}/{u['length']}", "translational")
    out += _springs(model, spread(model, m.nodes), ("rx", "ry", "rz"), f"{u['force']}·{u['length']}/rad",
                    "rotational")
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
