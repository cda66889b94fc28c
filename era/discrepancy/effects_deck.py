"""The candidate effects for a Nastran deck (DeckExplainModel): the matrix model's library (era.discrepancy.
effects_matrix: point mass, springs to ground, a part's stiffness or mass, spread mass) and a property of the deck
off by a factor (a PSHELL's thickness, a MAT1's E, a bar or beam section's I, a PROD's A), re-assembled."""

from __future__ import annotations

from ..models.nastran.mesh import change_key, property_keys
from .deck_model import PROPERTY, DeckExplainModel
from .effects import EffectSpec, Param
from .effects_matrix import matrix_effects


def deck_effects(model: DeckExplainModel) -> tuple:
    r"""The effects library of a deck, relative to the nominal ``model``.

    matrix_effects of the deck's matrices, then "property_factor" at every property change (property_keys;
    places "property:PSHELL 3 T"), its factor log-normal centred at 1 with 1σ a factor e^0.3 (a thickness or
    modulus 30 % off is already a gross error of the deck), its places compared at T = 2 as a part's are. A MAT1's
    E is left out where one property alone uses that material for all its stiffness: the factor then changes
    exactly that part's stiffness matrix, which part_stiffness offers already (one change as two candidates would
    split its probability and read as ambiguous).

    Parameters
    ----------
    model : DeckExplainModel
        The nominal deck (:meth:`DeckExplainModel.of`).

    Returns
    -------
    list of EffectSpec
        "none" first, then each candidate effect with its parameters' priors and its places.

    Examples
    --------
    >>> import os, tempfile
    >>> deck = ["BEGIN BULK"] + [f"GRID,{i + 1},,{0.25 * i},0.,0." for i in range(5)]
    >>> deck += [f"CBAR,{i + 1},1,{i + 1},{i + 2},0.,0.,1." for i in range(4)]
    >>> deck += ["PBAR,1,1,5.-4,4.17-9,1.04-7,1.46-8", "MAT1,1,2.+11,,0.3,7850.", "SPC1,1,123456,1", "ENDDATA"]
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "strip.bdf")
    ...     with open(path, "w") as file:
    ...         _ = file.write("\n".join(deck) + "\n")
    ...     strip = era.load_model(path)
    >>> effects = era.deck_effects(era.DeckExplainModel.of(strip, [("3", "z"), ("5", "z")]))
    >>> [(effect.name, effect.locations) for effect in effects[-3:]]
    [('part_mass', ('part:PBAR 1',)), ('distributed_mass', None), ('property_factor', ('property:PBAR 1 I',))]
    """
    parts = model.nominal.model.parts or {}
    keys = tuple(k for k in property_keys(model.deck) if k not in one_part_materials(model.deck, parts))
    out = list(matrix_effects(model.nominal))
    if keys:
        out.append(EffectSpec(
            "property_factor", (Param("property_factor", True, 0.0, 0.3, ""),), location_keyword="property_at",
            locations=tuple(PROPERTY + k for k in keys), trial={"property_factor": 0.8}, trial_power=-1.0,
            summary="a property of the deck is off by a factor (the card's value times the factor)",
            place_temperature=2.0, either_way=True))
    return tuple(out)


def one_part_materials(deck, parts) -> set:
    """The keys "MAT1 m E" of the materials that one property of ``deck`` alone uses, for all its stiffness (a
    PSHELL with membrane and bending material m, a bar, beam or rod section of m, a PSOLID of m, a PCOMP of plies
    of m alone), where that property is one of ``parts`` ({"PSHELL 3": stiffness, ...}): E (with G) times a factor is then that part's stiffness times it."""
    users: dict = {}
    for pid, sec in deck.shell_sections.items():
        for mid in {sec.mid1, sec.mid2} - {None}:
            users.setdefault(mid, []).append((f"PSHELL {pid}", sec.mid1 == sec.mid2))
    for pid, sec in deck.line_sections.items():
        users.setdefault(sec.mid, []).append((f"{sec.kind} {pid}", True))
    for pid, sec in deck.solid_sections.items():
        users.setdefault(sec.mid, []).append((f"PSOLID {pid}", True))
    for pid, sec in deck.composites.items():     # all its stiffness only when every ply is of that MAT1
        mids = {m for m, _, _ in sec.plies}
        for mid in mids:
            users.setdefault(mid, []).append((f"PCOMP {pid}", len(mids) == 1))
    return {change_key("MAT1", mid, "E") for mid, used in users.items()
            if len(used) == 1 and used[0][1] and used[0][0] in parts}
