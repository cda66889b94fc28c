"""PCOMP laminates of MAT8 (orthotropic) or MAT1 (isotropic) plies as era.fem laminated shell sections.

Nastran's rules: a ply's angle is measured from the element's material x axis (here the element's own x axis:
a quad's mean G1→G2 direction, a triangle's G1→G2 side; a CQUAD4/CTRIA3 THETA or MCID other than 0 is refused
for a composite), Z0 is the bottom surface's distance from the grids' plane (−T/2 when blank), a MAT8 without
G1Z, G2Z is rigid in transverse shear (taken as 1000 × G12: stiff enough that the shear flexibility is lost in the
round-off of a thin plate's frequencies, soft enough for the MITC elements' conditioning), a MAT1 ply has its own
G in transverse shear. PARAM WTMASS multiplies the mass per area.
"""

from __future__ import annotations

from ...fem.laminate import LaminateProperty, Ply, stack
from .coords import require

#: a MAT8 without transverse shear moduli: rigid in Nastran, this many times G12 here
RIGID_SHEAR = 1000.0


def _ply(deck, mid: int, t: float, angle: float, card, factors: dict) -> Ply:
    if mid in deck.orthotropic:
        if mid in deck.materials:
            raise card.error(f"material {mid} is both a MAT1 and a MAT8; give each material its own id")
        m = deck.orthotropic[mid]
        rigid = RIGID_SHEAR * m.g12
        return Ply(m.e1, m.e2, m.nu12, m.g12, m.g1z or rigid, m.g2z or rigid, m.rho * deck.wtmass, t, angle)
    m = require(deck.materials, mid, "material (MAT1 or MAT8)", card)
    fe = factors.get(f"MAT1 {mid} E", 1.0)
    if not (m.e > 0 and m.g > 0):
        raise m.card.error("a ply's MAT1 needs E and G (or NU) > 0")
    e, g = m.e * fe, m.g * fe
    return Ply(e, e, m.nu, g, g, g, m.rho * factors.get(f"MAT1 {mid} RHO", 1.0) * deck.wtmass, t, angle)


def composite_property(deck, pid: int, factors: dict) -> LaminateProperty:
    """The laminated section of PCOMP ``pid`` of ``deck`` (its MAT1 plies' E and RHO times ``factors``
    {"MAT1 1 E": 1.1, ...}); DataError naming the card for a missing or unphysical ply material."""
    p = deck.composites[pid]
    plies = [_ply(deck, mid, t, angle, p.card, factors) for mid, t, angle in p.plies]
    try:
        return stack(plies, p.z0, p.nsm * deck.wtmass, name=f"PCOMP {pid}")
    except ValueError as err:
        raise p.card.error(str(err)) from None
