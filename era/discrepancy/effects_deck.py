"""The candidate effects for a Nastran deck (era.models.nastran.model.DeckModel): a property off by a factor (a
PSHELL's thickness, a MAT1's E, a bar section's I), a point mass at a grid, a spring to ground at a grid and
direction, a part stiffer or softer than modelled."""

from __future__ import annotations

import numpy as np

from ..models.nastran.model import DeckModel, property_keys
from .effects import EffectSpec, Param


def deck_effects(model: DeckModel, spring_places: tuple | None = None) -> tuple:
    """The effects library of a deck, relative to the nominal ``model``.

    Priors (log-normal): a property factor centred at 1 (1σ: a factor e^0.3, a thickness or modulus 30 % off
    is already a gross error), a point mass at 5 % of the moving mass (1σ a factor e^1.2), a spring to ground at
    the stiffness of the stiffest free DOF of the model's diagonal / 100 (1σ a factor e²), a part 0.7 times as
    stiff as modelled (1σ e^0.5). Places: every property change (property_keys), every grid with a free
    translation, ``spring_places`` ("grid direction" strings; default every free translation of the grids
    next to a constraint... here: every free translation), every part."""
    m = model.matrices()
    total = m.total_mass()
    grids = tuple(dict.fromkeys(g for g, d in m.dofs if d in ("x", "y", "z")))
    springs = spring_places or tuple(f"{g} {d}" for g, d in m.dofs if d in ("x", "y", "z"))
    k_scale = float(np.max(m.stiffness.diagonal())) / 100
    return (
        EffectSpec("none", summary="the deck is right up to a global stiffness factor"),
        EffectSpec("property_factor", (Param("property_factor", True, 0.0, 0.3, ""),),
                   location_keyword="property_at", locations=property_keys(model.deck),
                   trial={"property_factor": 0.8}, trial_power=-1.0,
                   summary="a property of the deck is off by a factor", place_temperature=2.0),
        EffectSpec("point_mass", (Param("point_mass_kg", True, float(np.log(0.05 * total)), 1.2, "kg"),),
                   location_keyword="point_mass_at", locations=grids, trial={"point_mass_kg": 0.05 * total},
                   summary="a concentrated mass is attached",
                   caveat="The mass is the equivalent point mass at the grid."),
        EffectSpec("ground_spring", (Param("spring_stiffness", True, float(np.log(k_scale)), 2.0, "N/m"),),
                   location_keyword="spring_at", locations=springs, trial={"spring_stiffness": k_scale},
                   summary="a grid is held by a spring to ground (a support or fixture)"),
        EffectSpec("part_stiffness", (Param("part_factor", True, float(np.log(0.7)), 0.5, ""),),
                   location_keyword="part_at", locations=tuple(sorted(m.parts)), trial={"part_factor": 0.7},
                   trial_power=-1.0, summary="a part is less stiff than modelled", place_temperature=2.0),
    )
