"""The cards of linear constraint equations, each as a record (records.py): MPC (one equation), MPCADD (a set made
of sets) and RBE3 (an interpolation element), with Nastran's field layout; an error names the file, line and card."""

from __future__ import annotations

from .records import InterpolationCard, MpcCard
from .values import BulkCard, nastran_real


def mpc_card(c: BulkCard) -> MpcCard:
    """MPC SID G1 C1 A1 G2 C2 A2 / (blank) G3 C3 A3 G4 C4 A4 / ...: the equation Σ A u = 0, G1's component C1
    the dependent DOF (A1 not 0)."""
    terms = []
    for line in range(0, max(1, (len(c.fields) + 7) // 8)):
        for base in (8 * line + 1, 8 * line + 4):
            if c.blank(base):
                continue
            k = len(terms) + 1
            comp = c.components(base + 1, f"C{k}")
            if len(comp) != 1 or comp == "0":
                raise c.error(f"C{k} '{comp}' must be one component digit 1-6")
            terms.append((c.integer(base, f"G{k}"), int(comp), c.real(base + 2, f"A{k}", 0.0)))
    if not terms or terms[0][2] == 0.0:
        raise c.error("the first term's coefficient A1 is blank or 0; the first DOF is the dependent one")
    return MpcCard(c.integer(0, "SID"), tuple(terms), c)


def mpcadd(c: BulkCard) -> tuple[int, list[int]]:
    """MPCADD SID S1 S2 ...: (sid, [the sets it joins])."""
    sets = [c.integer(k, f"S{k}") for k in range(1, len(c.fields)) if not c.blank(k)]
    if not sets:
        raise c.error("no MPC sets S1 ...")
    return c.integer(0, "SID"), sets


def rbe3(c: BulkCard) -> InterpolationCard:
    """RBE3 EID (blank) REFGRID REFC WT1 C1 G1,1 G1,2 ... WT2 C2 G2,1 ...: a weight (a real) starts each group of
    independent grids; "UM" (moved dependent DOFs) is refused, a trailing "ALPHA" is ignored."""
    texts = [t.strip().upper() for t in c.fields]
    if "UM" in texts:
        raise c.error("the UM fields (dependent DOFs moved to independent grids) are not read; leave them out")
    end = texts.index("ALPHA") if "ALPHA" in texts else len(texts)
    groups, k = [], 4
    while k < end:
        if not texts[k]:
            k += 1
            continue
        weight = nastran_real(texts[k]) if "." in texts[k] or "E" in texts[k] else None
        if weight is None:
            raise c.error(f"field {k + 2} '{c.fields[k]}' should be a weight WT (a real with a decimal point)")
        comps = c.components(k + 1, f"C{len(groups) + 1}")
        grids, k = [], k + 2
        while k < end and not ("." in texts[k] or "E" in texts[k]):
            if texts[k]:
                grids.append(c.integer(k, "G"))
            k += 1
        if not grids:
            raise c.error(f"the weight group {len(groups) + 1} names no grid")
        groups.append((weight, comps, tuple(grids)))
    if not groups:
        raise c.error("no independent grids (WT1 C1 G1,1 ...)")
    return InterpolationCard(c.integer(0, "EID"), c.integer(2, "REFGRID"), c.components(3, "REFC"), tuple(groups), c)
