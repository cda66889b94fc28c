"""Each modelled card's fields as a record (records.py), with Nastran's defaults and rules for blank fields; an
error names the file, line, card and field. :data:`READERS` maps card names to their reader."""

from __future__ import annotations

import re

import numpy as np

from .records import (
    BushCard, CompositeCard, CoordCard, GridCard, LineCard, LineSection, MassCard, MaterialCard, OrthotropicCard,
    RigidCard, ShellCard, ShellSection, SpcCard, SpringCard)
from .sections import DIMENSIONS, section_properties
from .values import BulkCard, nastran_real


def _xyz(c: BulkCard, i: int, what: str, default: float | None = 0.0) -> np.ndarray:
    return np.array([c.real(i + k, f"{what}{k + 1}", default) for k in range(3)])


def grdset(c: BulkCard) -> dict:
    """GRDSET (blank) CP (3 blanks) CD PS: the defaults of the GRIDs' blank CP, CD and PS fields."""
    return {"cp": c.integer(1, "CP", 0), "cd": c.integer(5, "CD", 0), "ps": c.text(6)}


def grid(c: BulkCard, defaults: dict | None = None) -> GridCard:
    """GRID ID CP X1 X2 X3 CD PS (PS, the permanent constraints, is read by :func:`grid_spc`); blank CP and CD
    take the GRDSET's ``defaults``."""
    d = defaults or {}
    return GridCard(c.integer(0, "ID"), c.integer(1, "CP", d.get("cp", 0)), _xyz(c, 2, "X"),
                    c.integer(5, "CD", d.get("cd", 0)), c)


def grid_spc(c: BulkCard, defaults: dict | None = None) -> list[SpcCard]:
    """The permanent single-point constraints of a GRID (its PS field, or the GRDSET's), as an SPC that every set
    includes."""
    ps = c.text(6) or (defaults or {}).get("ps", "")
    return [SpcCard(-1, c.integer(0, "ID"), c.components(6, "PS", ps), c)] if ps else []


def cord2(c: BulkCard) -> CoordCard:
    """CORD2R, CORD2C or CORD2S CID RID A1 A2 A3 B1 B2 B3 / C1 C2 C3."""
    return CoordCard(c.integer(0, "CID"), c.integer(1, "RID", 0), _xyz(c, 2, "A"), _xyz(c, 5, "B"),
                     _xyz(c, 8, "C"), c, c.name[-1])


def cord1(c: BulkCard) -> list[CoordCard]:
    """CORD1R, CORD1C or CORD1S CIDA G1A G2A G3A CIDB G1B G2B G3B: one or two frames, each by three grids (the
    origin, a point on the z axis, a point in the x-z plane)."""
    out, zero = [], np.zeros(3)
    for base in (0, 4):
        if base and c.blank(base):
            break
        grids = tuple(c.integer(base + k, f"G{k}{'AB'[base // 4]}") for k in (1, 2, 3))
        if len(set(grids)) < 3:
            raise c.error(f"its grids {grids} are not three different grids")
        out.append(CoordCard(c.integer(base, f"CID{'AB'[base // 4]}"), 0, zero, zero, zero, c, c.name[-1], grids))
    return out


def line_element(c: BulkCard) -> LineCard:
    """CBAR/CBEAM EID PID GA GB X1|G0 X2 X3 OFFT / PA PB W1A W2A W3A W1B W2B W3B; CROD EID PID G1 G2."""
    eid = c.integer(0, "EID")
    pid = c.integer(1, "PID", eid)
    ga, gb = c.integer(2, "GA"), c.integer(3, "GB")
    zero = np.zeros(3)
    if c.name == "CROD":
        return LineCard("CROD", eid, pid, ga, gb, None, None, zero, zero, "GGG", c)
    offt = (c.text(7) or "GGG").upper()
    if c.name == "CBEAM" and nastran_real(offt) is not None:
        offt = "GGG"  # CBEAM's field 9 may hold BIT (a real) instead of OFFT
    if not re.fullmatch(r"[GB][GBO][GBO]", offt):
        raise c.error(f"OFFT '{offt}' is not one of Nastran's codes (GGG, BGG, GGO, ...)")
    if c.text(8) not in ("", "0") or c.text(9) not in ("", "0"):
        raise c.error("pin flags PA/PB are not modelled; release the end with a separate grid and an RBE2 "
                      "or remove the pin flags")
    first = c.text(4)
    if re.fullmatch(r"[+-]?\d+", first) and c.blank(5) and c.blank(6):
        vector, g0 = None, c.integer(4, "G0")
    elif first:
        vector, g0 = _xyz(c, 4, "X"), None
    else:
        raise c.error("the orientation (X1, X2, X3 or G0) is blank; give the vector v or a grid G0")
    wa, wb = _xyz(c, 10, "WA", 0.0), _xyz(c, 13, "WB", 0.0)
    if "O" in offt[1:] and (wa.any() or wb.any()):
        raise c.error(f"offsets in the element frame (OFFT '{offt}') are not read; give them in the grids' "
                      "frames (OFFT GGG)")
    return LineCard(c.name, eid, pid, ga, gb, vector, g0, wa, wb, offt, c)


def shell_element(c: BulkCard) -> ShellCard:
    """CQUAD4 EID PID G1 G2 G3 G4 THETA|MCID ZOFFS; CTRIA3 EID PID G1 G2 G3 THETA|MCID ZOFFS (the corner
    thicknesses T1-T4 must be blank: the property's thickness is used)."""
    eid = c.integer(0, "EID")
    n = 4 if c.name == "CQUAD4" else 3
    nodes = tuple(c.integer(2 + k, f"G{k + 1}") for k in range(n))
    if any(not c.blank(k) for k in range(14 - n, 14)):      # T1 ... after the continuation's TFLAG
        raise c.error("corner thicknesses T1 ... are not read; give the thickness on the PSHELL")
    return ShellCard(c.name, eid, c.integer(1, "PID", eid), nodes, c, c.real(2 + n, "THETA/MCID", 0.0),
                     c.real(3 + n, "ZOFFS", 0.0))


def pbar(c: BulkCard) -> LineSection:
    """PBAR PID MID A I1 I2 J NSM (the stress points and shear factors are not used)."""
    return LineSection("PBAR", c.integer(0, "PID"), c.integer(1, "MID"), c.real(2, "A", 0.0), c.real(3, "I1", 0.0),
                       c.real(4, "I2", 0.0), c.real(5, "J", 0.0), c.real(6, "NSM", 0.0), "", c)


def pbeam(c: BulkCard) -> LineSection:
    """PBEAM PID MID A I1 I2 I12 J NSM: the section at end A, for the whole length."""
    return LineSection("PBEAM", c.integer(0, "PID"), c.integer(1, "MID"), c.real(2, "A"), c.real(3, "I1", 0.0),
                       c.real(4, "I2", 0.0), c.real(6, "J", 0.0), c.real(7, "NSM", 0.0), "", c)


def pbarl(c: BulkCard) -> LineSection:
    """PBARL/PBEAML PID MID GROUP TYPE / DIM1 ... NSM (end A's dimensions for a PBEAML)."""
    shape = c.text(3).upper()
    if shape not in DIMENSIONS:
        raise c.error(f"the section TYPE '{shape}' is not read; use one of {', '.join(DIMENSIONS)} or a PBAR")
    n = DIMENSIONS[shape]
    dims = [c.real(8 + k, f"DIM{k + 1}") for k in range(n)]
    try:
        area, i1, i2, j = section_properties(shape, dims)
    except ValueError as err:
        raise c.error(str(err)) from None
    return LineSection(c.name, c.integer(0, "PID"), c.integer(1, "MID"), area, i1, i2, j,
                       c.real(8 + n, "NSM", 0.0), shape, c)


def prod(c: BulkCard) -> LineSection:
    """PROD PID MID A J C NSM."""
    return LineSection("PROD", c.integer(0, "PID"), c.integer(1, "MID"), c.real(2, "A"), 0.0, 0.0,
                       c.real(3, "J", 0.0), c.real(5, "NSM", 0.0), "", c)


def pshell(c: BulkCard) -> ShellSection:
    """PSHELL PID MID1 T MID2 12I/T³ MID3 TS/T NSM; MID1 and MID2 must name the same material (or be blank)."""
    mid1 = c.integer(1, "MID1", 0) or None
    mid2 = c.integer(3, "MID2", 0) or None
    if mid1 and mid2 and mid1 != mid2:
        raise c.error(f"MID1 {mid1} and MID2 {mid2} differ: a plate of two materials is not modelled")
    mid2 = None if mid2 == -1 else mid2
    return ShellSection(c.integer(0, "PID"), mid1, c.real(2, "T"), mid2, c.real(4, "12I/T**3", 1.0),
                        c.real(7, "NSM", 0.0), c)


def mat1(c: BulkCard) -> MaterialCard:
    """MAT1 MID E G NU RHO; one blank of E, G, NU follows from E = 2 (1 + NU) G; two blank: they are 0."""
    e, g, nu = c.optional_real(1, "E"), c.optional_real(2, "G"), c.optional_real(3, "NU")
    if e is None and g is None:
        raise c.error("E and G are both blank; give E (and NU)")
    if e is not None and g is not None and nu is None:
        nu = e / (2 * g) - 1
    elif e is not None and nu is not None and g is None:
        g = e / (2 * (1 + nu))
    elif g is not None and nu is not None and e is None:
        e = 2 * (1 + nu) * g
    return MaterialCard(c.integer(0, "MID"), e or 0.0, g or 0.0, nu or 0.0, c.real(4, "RHO", 0.0), c)


def conm2(c: BulkCard) -> MassCard:
    """CONM2 EID G CID M X1 X2 X3 / I11 I21 I22 I31 I32 I33 (the products enter with a minus sign)."""
    i11, i21, i22, i31, i32, i33 = (c.real(8 + k, n, 0.0) for k, n in
                                    enumerate(("I11", "I21", "I22", "I31", "I32", "I33")))
    inertia = np.array([[i11, -i21, -i31], [-i21, i22, -i32], [-i31, -i32, i33]])
    return MassCard(c.integer(0, "EID"), c.integer(1, "G"), c.integer(2, "CID", 0), c.real(3, "M", 0.0),
                    _xyz(c, 4, "X"), inertia, c)


def _component(c: BulkCard, i: int, what: str) -> int:
    digits = c.components(i, what, "0")
    if len(digits) != 1:
        raise c.error(f"{what} '{digits}' must be one component digit")
    return int(digits)


def celas(c: BulkCard, pelas: dict) -> SpringCard:
    """CELAS1 EID PID G1 C1 G2 C2 (k from PELAS ``pelas`` {pid: (k, card)}) or CELAS2 EID K G1 C1 G2 C2."""
    eid = c.integer(0, "EID")
    if c.name == "CELAS2":
        k = c.real(1, "K")
    else:
        pid = c.integer(1, "PID", eid)
        if pid not in pelas:
            raise c.error(f"PELAS {pid} is not in the deck")
        k = pelas[pid]
    g1, g2 = c.integer(2, "G1", 0), c.integer(4, "G2", 0)
    c1, c2 = _component(c, 3, "C1"), _component(c, 5, "C2")
    if not g1 and g2:
        g1, c1, g2, c2 = g2, c2, 0, 0
    if not g1:
        raise c.error("both grids are blank; give G1 and C1")
    return SpringCard(eid, k, g1, c1, g2 or None, c2, c)


def pelas(c: BulkCard) -> list[tuple[int, float]]:
    """PELAS PID1 K1 GE1 S1 PID2 K2 GE2 S2: [(pid, k), ...]."""
    out = [(c.integer(0, "PID1"), c.real(1, "K1"))]
    if not c.blank(4):
        out.append((c.integer(4, "PID2"), c.real(5, "K2")))
    return out


def spc(c: BulkCard) -> list[SpcCard]:
    """SPC SID G1 C1 D1 G2 C2 D2 (enforced values D must be zero: a modal model has no enforced motion)."""
    sid, out = c.integer(0, "SID"), []
    for base in (1, 4):
        if c.blank(base):
            continue
        if c.real(base + 2, f"D{1 + base // 4}", 0.0) != 0.0:
            raise c.error("an enforced displacement D is not zero; modes need the support held at zero")
        out.append(SpcCard(sid, c.integer(base, "G"), c.components(base + 1, "C"), c))
    return out


def spc1(c: BulkCard) -> list[SpcCard]:
    """SPC1 SID C G1 G2 ... or SPC1 SID C G1 THRU G2."""
    sid, comps = c.integer(0, "SID"), c.components(1, "C")
    return [SpcCard(sid, g, comps, c) for g in _ids(c, 2)]


def rbe2(c: BulkCard) -> RigidCard:
    """RBE2 EID GN CM GM1 GM2 ... (THRU allowed; a trailing real ALPHA is ignored)."""
    deps = tuple(_ids(c, 3, stop_at_real=True))
    if not deps:
        raise c.error("no dependent grids GM")
    return RigidCard(c.integer(0, "EID"), c.integer(1, "GN"), c.components(2, "CM"), deps, c)


def _ids(c: BulkCard, start: int, stop_at_real: bool = False) -> list[int]:
    """Grid ids from field ``start`` on: a list with blanks skipped, or "G1 THRU G2"."""
    texts = [t.strip().upper() for t in c.fields[start:]]
    if len(texts) >= 3 and texts[1] == "THRU":
        lo, hi = c.integer(start, "G1"), c.integer(start + 2, "G2")
        if hi < lo:
            raise c.error(f"THRU runs backwards ({lo} THRU {hi})")
        return list(range(lo, hi + 1))
    out = []
    for k, t in enumerate(texts):
        if not t:
            continue
        if stop_at_real and "." in t:
            break
        out.append(c.integer(start + k, "G"))
    return out


def pbush(c: BulkCard) -> tuple[int, np.ndarray]:
    """PBUSH PID "K" K1 ... K6 (the damping and other lines are not used): (pid, k (6,))."""
    texts = [t.strip().upper() for t in c.fields]
    if "K" not in texts:
        raise c.error("no K line; give the stiffness K1 ... K6")
    at = texts.index("K") + 1
    return c.integer(0, "PID"), np.array([c.real(at + i, f"K{i + 1}", 0.0) for i in range(6)])


def cbush(c: BulkCard, pbushes: dict) -> BushCard:
    """CBUSH EID PID GA GB GO/X1 X2 X3 CID: a zero-length bush (GB blank or at GA's place) in frame CID."""
    eid = c.integer(0, "EID")
    pid = c.integer(1, "PID", eid)
    if pid not in pbushes:
        raise c.error(f"PBUSH {pid} is not in the deck")
    if c.blank(7):
        raise c.error("CID is blank: only a bush whose stiffness axes are a frame (CID 0 for basic, or a CORD2R) "
                      "is read; give CID")
    gb = c.integer(3, "GB", 0) or None
    return BushCard(eid, pbushes[pid], c.integer(2, "GA"), gb, c.integer(7, "CID"), c)


def mat8(c: BulkCard) -> OrthotropicCard:
    """MAT8 MID E1 E2 NU12 G12 G1Z G2Z RHO (the thermal and strength fields are not used)."""
    e1, e2, g12 = c.real(1, "E1"), c.real(2, "E2"), c.real(4, "G12")
    if e1 <= 0 or e2 <= 0 or g12 <= 0:
        raise c.error("E1, E2 and G12 must be positive")
    return OrthotropicCard(c.integer(0, "MID"), e1, e2, c.real(3, "NU12", 0.0), g12, c.optional_real(5, "G1Z"),
                           c.optional_real(6, "G2Z"), c.real(7, "RHO", 0.0), c)


def pcomp(c: BulkCard) -> CompositeCard:
    """PCOMP PID Z0 NSM SB FT TREF GE LAM / MID1 T1 THETA1 SOUT1 MID2 T2 ... : a blank MID or T repeats the ply
    before; LAM blank (every ply listed) or SYM (the plies listed are the lower half, mirrored about the middle)."""
    lam = c.text(7).upper()
    if lam not in ("", "SYM"):
        raise c.error(f"LAM '{lam}' is not read (blank and SYM are); list every ply with LAM blank")
    plies, mid, t = [], None, None
    for base in range(8, len(c.fields), 4):
        if all(c.blank(base + k) for k in range(3)):
            continue
        mid = c.integer(base, f"MID{len(plies) + 1}", mid)
        t = c.real(base + 1, f"T{len(plies) + 1}", t)
        if t is None or t <= 0:
            raise c.error(f"ply {len(plies) + 1} has no positive thickness T")
        plies.append((mid, t, c.real(base + 2, f"THETA{len(plies) + 1}", 0.0)))
    if not plies:
        raise c.error("no plies (MID1 T1 THETA1 ...)")
    if lam == "SYM":
        plies += plies[::-1]
    return CompositeCard(c.integer(0, "PID"), c.optional_real(1, "Z0"), c.real(2, "NSM", 0.0), tuple(plies), c)
