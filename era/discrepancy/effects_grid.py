"""The candidate effects for the hanging NASA grid (era.examples.grid.nasa_grid); docs/effects.md says what each
changes physically. The frame family's library is effects_frame.frame_effects."""

from __future__ import annotations

import numpy as np

from typing import Protocol

from .effects import EffectSpec, Param, member_stiffness
from .protocol import ExplainModel


class GridFamily(ExplainModel, Protocol):
    """The grid model's protocol: the model protocol plus its 157 members ((x1, y1), (x2, y2)) ft (member_at)."""

    @property
    def members_ft(self) -> tuple: ...


def grid_effects(model: GridFamily) -> tuple:
    """The candidate effects for the hanging grid (era.examples.grid.nasa_grid), relative to the nominal ``model``.

    gravity_stiffening is a candidate only when the nominal leaves gravity out; relative parameters (torsion
    factor, cable length) are centred on the nominal's values with a ±20 % (1σ) prior; stiffnesses and masses
    have broad log priors (1σ = a factor e^2 ≈ 7.4 for stiffnesses, e^1.2 ≈ 3.3 for masses), centred at 1000
    N·m/rad for all joints, 30 N·m/rad for one loose joint, 2 kg spread, 1 kg concentrated.
    """
    p = model.params
    out = [EffectSpec("none", summary="the nominal model is right up to a global stiffness factor")]
    if not p.get("gravity", True):
        out.append(EffectSpec("gravity_stiffening", fixed={"gravity": True},
                              summary="the self-weight tension of the hanging grid stiffens it out of plane"))
    out += [
        EffectSpec("joint_flexibility", (Param("joint_stiffness", True, np.log(1000.0), 2.0, "N·m/rad"),),
                   summary="the riveted joints are semi-rigid"),
        EffectSpec("torsion_stiffness",
                   (Param("torsion_factor", True, np.log(p.get("torsion_factor", 1.0)), 0.2, ""),),
                   summary="the torsional stiffness GJ of the flat bars differs from the model"),
        EffectSpec("cable_length", (Param("cable_length_m", True, np.log(p.get("cable_length_m", 0.51)), 0.2, "m"),),
                   summary="the suspension cables have a different length"),
        EffectSpec("distributed_mass", (Param("distributed_mass_kg", True, np.log(2.0), 1.2, "kg"),),
                   summary="there is extra mass spread over the grid",
                   caveat="Spread mass lowers the elastic modes exactly as a softer material would; what tells "
                          "them apart is the prior on E (±1.5 %) and, with known impulse inputs, the modal "
                          "constants, whose absolute scale is only as good as the sensors' calibration (see ±)."),
        # model_form: on blind simulated tests (a 70/30 patch over ±3 in, scattered bars) the equivalent point
        # mass reads 0-8 % low (the footprint ~2 %, the scatter the rest), beyond the posterior's ±3 %
        EffectSpec("point_mass", (Param("point_mass_kg", True, np.log(1.0), 1.2, "kg", model_form=0.08),),
                   location_keyword="point_mass_at", trial={"point_mass_kg": 1.0},
                   caveat="The mass is the equivalent point mass at the joint: a mass spread over a few inches "
                          "around it, or scatter in the stiffness of the bars near it, reads a few per cent low.",
                   summary="a concentrated mass is attached"),
        # a loose joint is well below the bars' own EI/L ≈ 250 N·m/rad: 1σ spans 4-220 N·m/rad
        EffectSpec("loose_joint", (Param("loose_joint_stiffness", True, np.log(30.0), 2.0, "N·m/rad"),),
                   location_keyword="loose_joint_at", trial={"loose_joint_stiffness": 30.0}, trial_power=-1.0,
                   caveat="Below about 50 N·m/rad the joint acts as a hinge and the modes hardly change with its "
                          "stiffness: the data say where the joint is and bound how stiff it can be, not its value.",
                   summary="one joint is loose (a rotational spring instead of a rigid connection)"),
        # damage is not what an engineer suspects first in a test article: prior odds 1:4 against each of the
        # others, 157 places (each 1/157 a priori, against 1/88 for a joint) and a broad factor (1σ: 0.18-1.4
        # around 0.5). A cracked member next to a joint looks much like a loose joint there: the odds keep the
        # loose joint's detection, and a crack the data clearly prefer still wins by its evidence
        member_stiffness(model.members_ft, 0.5, 1.0, "one member is less stiff than drawn (a crack, damage, a wrong "
                                               "section)", prior_log_odds=float(np.log(0.25))),
    ]
    return tuple(out)
