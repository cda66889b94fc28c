"""The cards of solid elements, each as a record (records.py): CHEXA, CPENTA, CTETRA with their corner grids only,
and PSOLID; an error names the file, line and card."""

from __future__ import annotations

from .records import SolidCard, SolidSection
from .values import BulkCard

#: corner grids and the most grids (with the mid-side ones) of each solid
CORNERS = {"CHEXA": (8, 20), "CPENTA": (6, 15), "CTETRA": (4, 10)}


def solid_element(c: BulkCard) -> SolidCard:
    """CHEXA EID PID G1 ... G8, CPENTA EID PID G1 ... G6, CTETRA EID PID G1 ... G4; mid-side grids (CHEXA's
    G9-G20, ...) are refused: the elements are linear."""
    corners, most = CORNERS[c.name]
    eid = c.integer(0, "EID")
    nodes = tuple(c.integer(2 + k, f"G{k + 1}") for k in range(corners))
    if any(not c.blank(2 + k) for k in range(corners, most)):
        raise c.error(f"mid-side grids (G{corners + 1} ...) are not read: the {c.name} is modelled with its "
                      f"{corners} corners; leave them blank or use the linear element")
    if len(set(nodes)) < corners:
        raise c.error(f"its grids {nodes} repeat a grid")
    return SolidCard(c.name, eid, c.integer(1, "PID", eid), nodes, c)


def psolid(c: BulkCard) -> SolidSection:
    """PSOLID PID MID (CORDM, IN, STRESS, ISOP, FCTN do not change an isotropic linear element's matrices)."""
    return SolidSection(c.integer(0, "PID"), c.integer(1, "MID"), c)
