"""What the modelled cards say, one frozen record per card, in the deck's own units and ids (read by cards.py,
used by mesh.py and patch.py). Each keeps its BulkCard (``card``) so that errors found later still name the file
and line."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .values import BulkCard


@dataclass(frozen=True, eq=False)
class GridCard:
    """GRID: id, the frame its coordinates are given in (cp, 0: basic), xyz (3,), the frame of its displacement
    components (cd, 0: basic)."""

    id: int
    cp: int
    xyz: np.ndarray
    cd: int
    card: BulkCard


@dataclass(frozen=True, eq=False)
class CoordCard:
    """CORD2R/C/S: frame ``id`` of ``kind`` "R", "C" or "S" defined in frame ``rid`` by its origin a, a point b on
    its z axis and a point c in its x-z plane (each (3,), in frame rid's coordinates); CORD1R/C/S: the same points
    as three grids ``grids`` (a, b, c unused, rid 0)."""

    id: int
    rid: int
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    card: BulkCard
    kind: str = "R"
    grids: tuple[int, int, int] | None = None


@dataclass(frozen=True, eq=False)
class LineCard:
    """CBAR, CBEAM or CROD: element ``eid`` of property ``pid`` between grids ga and gb.

    vector : the orientation vector v (3,) as written, or None; g0 : the grid v points to (instead of the
    vector), or None; offset_a, offset_b : the end offsets WA, WB (3,) (zero when none); offt : Nastran's OFFT
    code, the frames of v, WA and WB (G: the grid's displacement frame, B: basic), "GGG" by default."""

    kind: str
    eid: int
    pid: int
    ga: int
    gb: int
    vector: np.ndarray | None
    g0: int | None
    offset_a: np.ndarray
    offset_b: np.ndarray
    offt: str
    card: BulkCard


@dataclass(frozen=True, eq=False)
class ShellCard:
    """CQUAD4 (4 grids) or CTRIA3 (3 grids) of property ``pid``; theta : its material angle THETA or frame MCID
    (a number; 0 when blank), zoffs : the offset of its mid-surface from the grids' plane along its normal."""

    kind: str
    eid: int
    pid: int
    nodes: tuple[int, ...]
    card: BulkCard
    theta: float = 0.0
    zoffs: float = 0.0


@dataclass(frozen=True, eq=False)
class LineSection:
    """PBAR, PBARL, PBEAM, PBEAML or PROD: material ``mid``, area, I1 (about element z), I2, J (L², L⁴), nsm
    (mass per length); ``shape`` the PBARL/PBEAML type ("" when given by values)."""

    kind: str
    pid: int
    mid: int
    area: float
    i1: float
    i2: float
    j: float
    nsm: float
    shape: str
    card: BulkCard


@dataclass(frozen=True, eq=False)
class ShellSection:
    """PSHELL: membrane material mid1 and thickness t, bending material mid2 (None: no bending stiffness) with
    bending_ratio = 12 I / t³, nsm (mass per area)."""

    pid: int
    mid1: int | None
    t: float
    mid2: int | None
    bending_ratio: float
    nsm: float
    card: BulkCard


@dataclass(frozen=True, eq=False)
class MaterialCard:
    """MAT1 with the Nastran rule for a blank field applied: E, G, nu (two given: the third is E/(2(1+nu)) or
    its inverse; one given: nu = 0 or G = 0), rho (mass per volume)."""

    mid: int
    e: float
    g: float
    nu: float
    rho: float
    card: BulkCard


@dataclass(frozen=True, eq=False)
class MassCard:
    """CONM2: mass at ``node``, offset (3,) from it and inertia (3, 3) about the mass's centre, both in frame
    ``cid`` (0: basic; -1: the offset is the mass's position in basic)."""

    eid: int
    node: int
    cid: int
    mass: float
    offset: np.ndarray
    inertia: np.ndarray
    card: BulkCard


@dataclass(frozen=True, eq=False)
class SpringCard:
    """CELAS1 (with a PELAS) or CELAS2: stiffness k between component c1 of g1 and c2 of g2 (g2 None: to
    ground); components are digits 1-6 in each grid's displacement frame."""

    eid: int
    k: float
    g1: int
    c1: int
    g2: int | None
    c2: int
    card: BulkCard


@dataclass(frozen=True, eq=False)
class SpcCard:
    """One grid's components held by SPC or SPC1 set ``sid`` (digits 1-6 in its displacement frame)."""

    sid: int
    node: int
    components: str
    card: BulkCard


@dataclass(frozen=True, eq=False)
class RigidCard:
    """RBE2: the dependent grids ``dependent`` follow the independent grid ``independent`` as a rigid body in
    ``components`` (digits 1-6 of the dependent grids)."""

    eid: int
    independent: int
    components: str
    dependent: tuple[int, ...]
    card: BulkCard


@dataclass(frozen=True, eq=False)
class BushCard:
    """CBUSH with its PBUSH: stiffness k (6,) along the axes of frame ``cid`` (K1-K3 translations, K4-K6
    rotations) between grids ga and gb (gb None: to ground); only zero-length bushes (gb blank or at ga) with a
    CID are read."""

    eid: int
    k: np.ndarray
    ga: int
    gb: int | None
    cid: int
    card: BulkCard


@dataclass(frozen=True, eq=False)
class OrthotropicCard:
    """MAT8: a ply material, moduli e1 (fibres), e2, nu12, g12, transverse shear g1z, g2z (None: blank, Nastran's
    rigid transverse shear), rho (mass per volume)."""

    mid: int
    e1: float
    e2: float
    nu12: float
    g12: float
    g1z: float | None
    g2z: float | None
    rho: float
    card: BulkCard


@dataclass(frozen=True, eq=False)
class CompositeCard:
    """PCOMP: plies ((mid, thickness, angle in degrees), ...) from the bottom up, as the whole laminate (LAM SYM
    already mirrored), z0 the bottom surface's distance from the grids' plane (None: −half the thickness), nsm
    (mass per area)."""

    pid: int
    z0: float | None
    nsm: float
    plies: tuple
    card: BulkCard


@dataclass(frozen=True, eq=False)
class MpcCard:
    """MPC set ``sid``: Σ a_k u(g_k, c_k) = 0 over ``terms`` ((grid, component digit, a), ...), the first term's
    DOF the dependent one (components in each grid's displacement frame)."""

    sid: int
    terms: tuple
    card: BulkCard


@dataclass(frozen=True, eq=False)
class InterpolationCard:
    """RBE3: the reference grid ``ref``'s components ``refc`` follow the weighted least-squares rigid motion of the
    independent grids, ``groups`` ((weight, components, (grids...)), ...)."""

    eid: int
    ref: int
    refc: str
    groups: tuple
    card: BulkCard


@dataclass(frozen=True, eq=False)
class SolidCard:
    """CHEXA (8 grids), CPENTA (6) or CTETRA (4) of PSOLID ``pid``."""

    kind: str
    eid: int
    pid: int
    nodes: tuple[int, ...]
    card: BulkCard


@dataclass(frozen=True, eq=False)
class SolidSection:
    """PSOLID: its material ``mid`` (a MAT1)."""

    pid: int
    mid: int
    card: BulkCard
