"""A deck's elements as an era.fem mesh (FEMesh) in basic coordinates, with properties changed by factors.

Shells: PSHELL t, MAT1 E and nu, mass rho t + NSM per area; PCOMP laminates (composites.py); ZOFFS a rigid offset
of the element's mid-surface from its grids along its normal. CHEXA, CPENTA, CTETRA: era.fem.solid's linear solids
of the PSOLID's MAT1 (a grid only solids reach has no rotational stiffness: AUTOSPC holds its rotations). CBAR and CBEAM: Euler-Bernoulli beams with I1 about
element z (bending in plane 1, the plane of the orientation vector v) and I2 about y, J, mass rho A + NSM per
length; an end offset is a rigid link (an RBE2) from the grid to the beam's end. CROD: a beam with A and J only.
The masses, springs, constraints and displacement frames are applied by constraints.py on the assembled matrices.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import DataError
from ...fem.mesh import BeamProperty, FEMesh, ShellProperty
from ...fem.solid import SolidProperty
from .composites import composite_property
from .coords import displacement_axes, rectangular, require, resolve
from .deck import Deck

#: the properties a factor may change: {card: (field, ...)}; "I" is both bending inertias of a beam section
CHANGEABLE = {"PSHELL": ("T",), "MAT1": ("E", "RHO"), "PBAR": ("I", "A", "J"), "PBARL": ("I", "A", "J"),
              "PBEAM": ("I", "A", "J"), "PBEAML": ("I", "A", "J"), "PROD": ("A",)}


@dataclass(frozen=True, eq=False)
class DeckMesh:
    """A deck as an era.fem mesh and the rest of what its matrices need.

    mesh : the elements (FEMesh; every grid a mass, spring or rigid element touches listed with a zero mass so
        that its DOFs are assembled); positions : {grid label: (3,) basic}; cd_axes : {grid label: (3, 3)} axes of
        the displacement frames that are not basic; rigid : ((independent label, (dependent labels), components
        "123456"), ...) the RBE2s and the beams' offset links (components in the dependents' frames).
    """

    mesh: FEMesh
    positions: dict
    cd_axes: dict
    rigid: tuple


def change_key(card: str, pid: int, field: str) -> str:
    """The name of a changed property: change_key("PSHELL", 3, "T") -> "PSHELL 3 T"."""
    return f"{card} {pid} {field}"


def property_keys(deck: Deck) -> tuple[str, ...]:
    """Every property a factor can change in ``deck``, the one field each candidate effect varies: "PSHELL 3 T"
    (thickness), "MAT1 1 E" (E and G), "PBAR 7 I" (I1 and I2 of any bar or beam section), "PROD 5 A"."""
    keys = [change_key("PSHELL", p, "T") for p in sorted(deck.shell_sections)]
    keys += [change_key("MAT1", m, "E") for m in sorted(deck.materials)]
    keys += [change_key(s.kind, p, "A" if s.kind == "PROD" else "I") for p, s in sorted(deck.line_sections.items())]
    return tuple(keys)


def deck_mesh(deck: Deck, factors: dict | None = None, thicker: tuple = ()) -> DeckMesh:
    """The deck's elements as a FEMesh, each property multiplied by ``factors`` {change_key: factor}; the
    PSHELLs whose ids are in ``thicker`` twice as thick (reader.py takes their bending part from the difference).

    Raises DataError (naming the card) for a reference to a missing grid, property or material, or a property
    this reader does not model (a PSHELL without bending)."""
    factors = dict(factors or {})
    _check_factors(deck, factors)
    frames, pos = resolve(deck.grids, deck.frames)
    cd = displacement_axes(deck.grids, frames, pos)
    nodes = {str(g): tuple(x) for g, x in pos.items()}
    shells, offsets, beams, shell_props, beam_props, rigid = [], [], [], {}, {}, []
    composite = sorted({"PCOMPG", "PSHEAR"} & set(deck.skipped))
    for e in deck.shells.values():
        if e.pid in deck.composites:
            if e.pid in deck.shell_sections:
                raise e.card.error(f"property {e.pid} is both a PSHELL and a PCOMP; give each its own id")
            if e.theta:
                raise e.card.error("a material angle THETA or frame MCID on a composite element is not read; give "
                                   "the plies' angles from the element's G1-G2 side and leave THETA blank")
            name = f"PCOMP {e.pid}"
            if name not in shell_props:
                shell_props[name] = composite_property(deck, e.pid, factors)
        else:
            if e.pid not in deck.shell_sections and composite:
                raise e.card.error(f"its property {e.pid} is no PSHELL or PCOMP of the deck; "
                                   f"{' and '.join(composite)} (ply-by-ply composites, shear panels) are not "
                                   "modelled: give an equivalent PSHELL or PCOMP")
            prop = require(deck.shell_sections, e.pid, "property (PSHELL or PCOMP)", e.card)
            name = f"PSHELL {e.pid}"
            if name not in shell_props:
                shell_props[name] = _shell_property(deck, prop, factors, 2.0 if e.pid in thicker else 1.0)
        for g in e.nodes:
            require(deck.grids, g, "GRID", e.card)
        shells.append((name, tuple(str(g) for g in e.nodes)))
        offsets.append(e.zoffs)
    solids, solid_props = [], {}
    for e in deck.solids.values():
        p = require(deck.solid_sections, e.pid, "PSOLID", e.card)
        name = f"PSOLID {e.pid}"
        if name not in solid_props:
            e_, _, nu, rho = _material(deck, p.mid, p.card, factors)
            solid_props[name] = SolidProperty(e_, nu, rho * deck.wtmass)
        for g in e.nodes:
            require(deck.grids, g, "GRID", e.card)
        solids.append((name, tuple(str(g) for g in e.nodes)))
    for e in deck.lines.values():
        prop = require(deck.line_sections, e.pid, "property (PBAR, PBARL, PBEAM, PBEAML, PROD)", e.card)
        name = f"{prop.kind} {e.pid}"
        if name not in beam_props:
            beam_props[name] = _beam_property(deck, prop, factors)
        ends = []
        for g, w, which in ((e.ga, e.offset_a, 1), (e.gb, e.offset_b, 2)):
            require(deck.grids, g, "GRID", e.card)
            w = np.asarray(w, float)
            if e.offt[which] == "G" and g in cd:
                w = cd[g] @ w
            if not w.any():
                ends.append(str(g))
                continue
            label = f"{g}@{e.kind}{e.eid}{'ab'[which - 1]}"
            nodes[label] = tuple(pos[g] + w)
            rigid.append((str(g), (label,), "123456"))
            ends.append(label)
        xa, xb = np.array(nodes[ends[0]]), np.array(nodes[ends[1]])
        if np.linalg.norm(xb - xa) == 0:
            raise e.card.error("both ends are at one point; a bar needs a length")
        beams.append((name, ends[0], ends[1], _orientation(e, xa, xb, pos, cd)))
    for r in deck.rigid.values():
        for g in (r.independent, *r.dependent):
            require(deck.grids, g, "GRID", r.card)
        rigid.append((str(r.independent), tuple(str(g) for g in r.dependent), r.components))
    touched = {str(m.node) for m in deck.masses.values()} | {str(s.g1) for s in deck.springs.values()} | {
        str(s.g2) for s in deck.springs.values() if s.g2} | {n for r in rigid for n in (r[0], *r[1])} | {
        str(g) for b in deck.bushes.values() for g in (b.ga, b.gb) if g} | {
        str(g) for m in deck.equations for g, _, _ in m.terms} | {
        str(g) for r in deck.interpolations.values() for g in (r.ref, *(g for _, _, gs in r.groups for g in gs))}
    for b in deck.bushes.values():
        for g in (b.ga, b.gb):
            if g:
                require(deck.grids, g, "GRID", b.card)
        if b.gb and np.linalg.norm(pos[b.gb] - pos[b.ga]) > 1e-9 * (1 + np.linalg.norm(pos[b.ga])):
            raise b.card.error("GA and GB are apart: only a zero-length bush (GB blank or at GA) is read; model "
                               "a bush with length as a CBAR or springs on coincident grids")
        rectangular(frames, b.cid, b.card)
    for m in deck.masses.values():
        require(deck.grids, m.node, "GRID", m.card)
    for m in deck.equations:
        for g, _, _ in m.terms:
            require(deck.grids, g, "GRID", m.card)
    for r in deck.interpolations.values():
        for g in (r.ref, *(g for _, _, gs in r.groups for g in gs)):
            require(deck.grids, g, "GRID", r.card)
    for s in deck.springs.values():
        for g in (s.g1, s.g2):
            if g:
                require(deck.grids, g, "GRID", s.card)
    mesh = FEMesh(nodes, tuple(shells), tuple(beams), shell_props, beam_props,
                  masses=tuple((n, 0.0, (0.0, 0.0, 0.0)) for n in sorted(touched)),
                  shell_offsets=tuple(offsets) if any(offsets) else (), solids=tuple(solids),
                  solid_properties=solid_props)
    return DeckMesh(mesh, nodes, {str(g): a for g, a in cd.items()}, tuple(rigid))


def _check_factors(deck: Deck, factors: dict) -> None:
    tables = {"PSHELL": deck.shell_sections, "MAT1": deck.materials}
    for key, f in factors.items():
        card, pid, field = (key.split() + ["", "", ""])[:3]
        table = tables.get(card, {k: v for k, v in deck.line_sections.items() if v.kind == card})
        if field not in CHANGEABLE.get(card, ()) or not pid.isdigit() or int(pid) not in table:
            raise DataError(f"{key!r} is not a property of the deck that a factor can change: give "
                            "'PSHELL <id> T', 'MAT1 <id> E' or 'RHO', 'PBAR <id> I', 'A' or 'J' (or PBARL, "
                            "PBEAM, PBEAML), 'PROD <id> A'.")
        if not np.isfinite(f) or f <= 0:
            raise DataError(f"the factor on {key} is {f}; give a positive number.")


def _material(deck: Deck, mid: int, card, factors: dict) -> tuple[float, float, float, float]:
    """(E, G, nu, rho) of MAT1 ``mid`` with its factors."""
    m = require(deck.materials, mid, "MAT1", card)
    fe = factors.get(change_key("MAT1", mid, "E"), 1.0)
    return m.e * fe, m.g * fe, m.nu, m.rho * factors.get(change_key("MAT1", mid, "RHO"), 1.0)


def _shell_property(deck: Deck, p, factors: dict, scale: float = 1.0) -> ShellProperty:
    if p.mid1 is None or p.mid2 is None:
        raise p.card.error("a membrane-only or bending-only PSHELL (MID1 or MID2 blank) is not modelled; give "
                           "the same MAT1 as MID1 and MID2")
    if p.bending_ratio <= 0:
        raise p.card.error(f"12I/T**3 = {p.bending_ratio:g}; give a positive ratio (1.0 for a solid plate)")
    e, _, nu, rho = _material(deck, p.mid1, p.card, factors)
    t = p.t * factors.get(change_key("PSHELL", p.pid, "T"), 1.0) * scale
    return ShellProperty(t, e, nu, rho * deck.wtmass, p.nsm * deck.wtmass)


def _beam_property(deck: Deck, p, factors: dict) -> BeamProperty:
    e, g, _, rho = _material(deck, p.mid, p.card, factors)
    f = {k: factors.get(change_key(p.kind, p.pid, k), 1.0) for k in ("I", "A", "J")}
    return BeamProperty(p.area * f["A"], p.i2 * f["I"], p.i1 * f["I"], p.j * f["J"], e, g, rho * deck.wtmass,
                        p.nsm * deck.wtmass)


def _orientation(e, xa: np.ndarray, xb: np.ndarray, pos: dict, cd: dict) -> np.ndarray:
    """The element's local z in basic (FEMesh's orientation lies in the local x-z plane; Nastran's v in x-y)."""
    x = (xb - xa) / np.linalg.norm(xb - xa)
    if e.kind == "CROD":
        v = np.eye(3)[int(np.argmin(np.abs(x)))]
    elif e.g0 is not None:
        if e.g0 not in pos:
            raise e.card.error(f"its orientation grid G0 {e.g0} is not in the deck")
        v = pos[e.g0] - pos[e.ga]
    else:
        v = np.asarray(e.vector, float)
        if e.offt[0] == "G" and e.ga in cd:
            v = cd[e.ga] @ v
    z = np.cross(x, v)
    if np.linalg.norm(z) <= 1e-9 * np.linalg.norm(v) or not np.linalg.norm(v):
        raise e.card.error("its orientation vector is parallel to the element (or zero); give v across it")
    return z / np.linalg.norm(z)
