"""The candidate effects for an era.Frame (wrapped in FrameModel); docs/effects.md says what each changes
physically. The grid family's library is effects_grid.grid_effects."""

from __future__ import annotations

import math

import numpy as np

from ..structure import Frame
from .effects import EffectSpec, Param, member_stiffness
from .frame_model import ALL_MEMBERS, FrameModel


def _member_ei_over_l(frame: Frame, ends, weak: bool = True) -> float:
    """The largest bending EI/L (N·m/rad) of the given (member, side) ends: the stiffness a spring there meets.
    EI about the weak axis (a support's spring acts on both bendings: the weaker is felt) or, weak=False, about
    local y (a joint spring: bending in the plane of the section's depth, vertical by default)."""
    vals = []
    for k, _ in ends:
        i, j, sec, _ = frame.members[k]
        s = frame.sections[sec]
        ei = s.e * (min(s.iy, s.iz) if weak else s.iy)
        vals.append(ei / np.linalg.norm(np.subtract(frame.nodes[j], frame.nodes[i])))
    return max(vals) if vals else 1.0


def frame_effects(model: FrameModel | Frame) -> tuple:
    """The candidate effects for a frame (docs/effects.md), relative to the nominal FrameModel ``model``.

    Priors (log-normal) scale with the structure, so one library serves a bench-top strip and a building frame:
    a support's rotational spring centred at 10 EI/L of the members it holds (1σ: a factor e² ≈ 7.4), a pinned
    bearing's vertical spring at 100 EI/L³; a joint spring at 10 EI/L of its beams (same width); a point mass at
    5 % of the structure's mass (1σ a factor e^1.2 ≈ 3.3); a member 0.7 times as stiff as drawn (1σ a factor
    e^0.5); spread mass 10 % of the structure's (a factor 3.3). Located effects list every candidate place:
    supports that restrain bending (or the vertical), nodes where a beam meets another member, nodes that move,
    every member, and the group of all members (ALL_MEMBERS, ("*",)): the structure softer than drawn beyond
    the ±1.5 % of E the nuisance allows (a thinner strip, a lower E), which frequencies and shapes cannot tell
    from spread mass: without known impulse inputs the two then share the posterior and the verdict is ambiguous.

    Parameters
    ----------
    model : FrameModel
        The nominal model (:meth:`FrameModel.of`).

    Returns
    -------
    list of EffectSpec
        "none" first, then each candidate effect with its parameters' priors and its places.

    Examples
    --------
    >>> strip = era.Section.rectangle(0.05, 0.01)
    >>> frame = era.Frame(nodes={"1": (0, 0, 0), "2": (0.5, 0, 0), "3": (1, 0, 0)},
    ...                   members=[("1", "2", "strip"), ("2", "3", "strip")], sections={"strip": strip},
    ...                   supports={"1": "fixed"}, sensors=[("2", "z"), ("3", "z")])
    >>> effects = era.frame_effects(era.FrameModel.of(frame))
    >>> [(effect.name, effect.locations) for effect in effects]  # doctest: +NORMALIZE_WHITESPACE
    [('none', None), ('support_flexibility', ('1',)), ('point_mass', ('2', '3')),
     ('member_stiffness', (('1', '2'), ('2', '3'), ('*',))), ('distributed_mass', None)]
    """
    if not isinstance(model, FrameModel):
        model = FrameModel.of(model)
    fr = model.frame
    total = fr.total_mass_kg
    out = [EffectSpec("none", summary="the nominal model is right up to a global stiffness factor")]
    if fr.gravity is not None and not model.params["gravity"] and not any("cable" in s for s in fr.supports.values()):
        out.append(EffectSpec("gravity_stiffening", fixed={"gravity": True},
                              summary="the self-weight's axial forces change the stiffness"))
    at_support = lambda n: [(k, s) for k, m in enumerate(fr.members) for s in (0, 1) if m[s] == n]   # noqa: E731
    fixed = tuple(n for n, s in fr.supports.items() if all(math.isinf(s.get(k, 0.0))
                                                          for k in model.bending_rotations(n)))
    up = ("kx", "ky", "kz")[int(np.argmax(np.abs(fr.vertical)))]
    pinned = tuple(n for n, s in fr.supports.items() if n not in fixed and math.isinf(s.get(up, 0.0)))
    if fixed:
        ei_l = np.median([_member_ei_over_l(fr, at_support(n)) for n in fixed])
        out.append(EffectSpec(
            "support_flexibility", (Param("support_rotation_stiffness", True, np.log(10 * ei_l), 2.0, "N·m/rad"),),
            location_keyword="support_at", locations=fixed, trial={"support_rotation_stiffness": 10 * ei_l},
            trial_power=-1.0, summary="a support is rotationally flexible (a spring instead of a clamp)"))
    elif pinned:
        ei_l3 = np.median([_member_ei_over_l(fr, at_support(n)) for n in pinned]) / np.mean(
            [np.linalg.norm(np.subtract(fr.nodes[j], fr.nodes[i])) for i, j, *_ in fr.members]) ** 2
        out.append(EffectSpec(
            "support_flexibility", (Param("support_vertical_stiffness", True, np.log(100 * ei_l3), 2.0, "N/m"),),
            location_keyword="support_at", locations=pinned, trial={"support_vertical_stiffness": 100 * ei_l3},
            trial_power=-1.0, summary="a bearing is flexible vertically (a spring instead of a rigid support)"))
    joints = tuple(n for n in fr.node_ids if n not in fr.supports and fr.beam_ends(n)
                   and len(at_support(n)) >= 2 and not _collinear(fr, n))
    if joints:
        ei_l = np.median([_member_ei_over_l(fr, fr.beam_ends(n), weak=False) for n in joints])
        # the screening's trial spring: softer than every joint drawn semi-rigid, so that at such a joint too
        # it makes the connection more flexible than drawn (the linearised screening cannot act backwards)
        trial = min([10 * ei_l] + [0.3 * fr.joint_springs[n] for n in joints if n in fr.joint_springs])
        out.append(EffectSpec(
            "joint_flexibility", (Param("joint_stiffness", True, np.log(10 * ei_l), 2.0, "N·m/rad"),),
            location_keyword="joint_at", locations=joints, trial={"joint_stiffness": trial}, trial_power=-1.0,
            summary="a beam-to-column connection is semi-rigid"))
    moving = tuple(n for n in fr.node_ids if not (n in fr.supports and all(
        math.isinf(fr.supports[n].get(k, 0.0)) for k in ("kx", "ky", "kz"))))
    out += [
        EffectSpec("point_mass", (Param("point_mass_kg", True, np.log(0.05 * total), 1.2, "kg"),),
                   location_keyword="point_mass_at", locations=moving, trial={"point_mass_kg": 0.05 * total},
                   summary="a concentrated mass is attached",
                   caveat="The mass is the equivalent point mass at the node."),
        member_stiffness(tuple((m[0], m[1]) for m in fr.members if len(fr.members) > 1) + (ALL_MEMBERS,), 0.7, 0.5,
                         "a member is less stiff than drawn (damage, a crack, a wrong section)"),
        EffectSpec("distributed_mass", (Param("distributed_mass_kg", True, np.log(0.1 * total), 1.2, "kg"),),
                   summary="there is extra mass spread over the members",
                   caveat="Spread mass lowers the modes as a softer material would; only the prior on E (±1.5 %) "
                          "and, with known impulse inputs, the modal constants tell them apart."),
    ]
    return tuple(out)


def _collinear(frame: Frame, node: str) -> bool:
    dirs = []
    for i, j, *_ in frame.members:
        if node in (i, j):
            d = np.subtract(frame.nodes[j], frame.nodes[i])
            dirs.append(d / np.linalg.norm(d))
    return all(np.linalg.norm(np.cross(dirs[0], d)) < 1e-6 for d in dirs[1:])
