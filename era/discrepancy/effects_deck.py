"""The candidate effects for a Nastran deck (DeckExplainModel): the matrix model's library (era.discrepancy.
effects_matrix: point mass, springs to ground, a part's stiffness or mass, spread mass) and a property of the deck
off by a factor (a PSHELL's thickness, a MAT1's E, a bar or beam section's I, a PROD's A), re-assembled."""

from __future__ import annotations

from ..models.nastran.mesh import property_keys
from .deck_model import PROPERTY, DeckExplainModel
from .effects import EffectSpec, Param
from .effects_matrix import matrix_effects


def deck_effects(model: DeckExplainModel) -> tuple:
    """The effects library of a deck, relative to the nominal ``model``: matrix_effects of the deck's matrices,
    then "property_factor" at every property change (property_keys; places "property:PSHELL 3 T"), its factor
    log-normal centred at 1 with 1σ a factor e^0.3 (a thickness or modulus 30 % off is already a gross error of
    the deck), its places compared at T = 2 as a part's are."""
    keys = property_keys(model.deck)
    out = list(matrix_effects(model.nominal))
    if keys:
        out.append(EffectSpec(
            "property_factor", (Param("property_factor", True, 0.0, 0.3, ""),), location_keyword="property_at",
            locations=tuple(PROPERTY + k for k in keys), trial={"property_factor": 0.8}, trial_power=-1.0,
            summary="a property of the deck is off by a factor (the card's value times the factor)",
            place_temperature=2.0))
    return tuple(out)
