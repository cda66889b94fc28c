"""A deck's modelled cards gathered by id, its solution parameters and what it holds that is not modelled."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

from ...errors import DataError
from ...words import counted
from . import cards as read
from . import equation_cards, solid_cards
from .fields import BulkData, read_bulk
from .values import BulkCard

#: cards that hold solution or output requests, never stiffness or mass: said apart in the notes
SOLUTION_CARDS = {"EIGRL", "EIGR", "EIGB", "PARAM", "MDLPRM", "USET", "USET1", "DTI", "NLPARM", "TSTEP", "FREQ",
                  "FREQ1", "FREQ2", "TABDMP1", "DMIG", "MONPNT1", "ENDDATA"}
_FRAMES = ("CORD2R", "CORD2C", "CORD2S")
_TABLES = {"GRID": "grids", **dict.fromkeys(_FRAMES, "frames"), "CBAR": "lines", "CBEAM": "lines", "CROD": "lines",
           "CQUAD4": "shells", "CTRIA3": "shells", "PBAR": "line_sections", "PBARL": "line_sections",
           "PBEAM": "line_sections", "PBEAML": "line_sections", "PROD": "line_sections", "PSHELL": "shell_sections",
           "MAT1": "materials", "CONM2": "masses", "RBE2": "rigid", "PCOMP": "composites",
           "MAT8": "orthotropic", "CHEXA": "solids", "CPENTA": "solids", "CTETRA": "solids",
           "PSOLID": "solid_sections"}
_READERS = {"GRID": read.grid, **dict.fromkeys(_FRAMES, read.cord2), "CBAR": read.line_element,
            "CBEAM": read.line_element, "CROD": read.line_element, "CQUAD4": read.shell_element, "CTRIA3": read.shell_element,
            "PBAR": read.pbar, "PBARL": read.pbarl, "PBEAM": read.pbeam, "PBEAML": read.pbarl, "PROD": read.prod,
            "PSHELL": read.pshell, "MAT1": read.mat1, "CONM2": read.conm2, "RBE2": read.rbe2, "PCOMP": read.pcomp,
            "MAT8": read.mat8, "CHEXA": solid_cards.solid_element, "CPENTA": solid_cards.solid_element,
            "CTETRA": solid_cards.solid_element, "PSOLID": solid_cards.psolid}
#: every card read into the model
MODELLED = tuple(sorted(set(_READERS) | {"CORD1R", "CORD1C", "CORD1S", "CELAS1", "CELAS2", "PELAS", "CBUSH",
                                         "PBUSH", "SPC", "SPC1", "GRDSET", "PARAM WTMASS", "MPC", "MPCADD",
                                         "RBE3"}))


@dataclass(frozen=True, eq=False)
class Deck:
    """The modelled cards of a deck, each table {id: record} (records.py), and what the rest of it says.

    composites (PCOMP by property id) and orthotropic (MAT8 by material id) hold the laminated shells;
    equations : the MPC records of the set the case control selects (through MPCADD; every MPC when it selects
    none); interpolations : the RBE3 records by element id; solids (CHEXA, CPENTA, CTETRA by element id) and
    solid_sections (PSOLID);
    grids, frames (CORD1R/C/S, CORD2R/C/S by frame id), lines (CBAR, CBEAM, CROD by element id), shells (CQUAD4,
    CTRIA3), line_sections (PBAR, PBARL, PBEAM, PBEAML, PROD by property id), shell_sections (PSHELL), materials
    (MAT1), masses (CONM2), springs (CELAS1, CELAS2), bushes (CBUSH with its PBUSH), rigid (RBE2); constraints :
    the SPC/SPC1 records of the set the case control selects (every set when it selects none) and the GRIDs' permanent constraints (PS); wtmass : PARAM WTMASS
    (1.0 when absent), the factor on every mass; skipped : {card name: count} of the cards not modelled;
    notes : sentences about how the deck was read; path : its main file; max_ids : {"element", "property",
    "material", "grid", "set"} the largest id of each kind in the deck (a patch takes new ids above them).
    """

    grids: dict
    frames: dict
    lines: dict
    shells: dict
    line_sections: dict
    shell_sections: dict
    materials: dict
    masses: dict
    springs: dict
    bushes: dict
    rigid: dict
    constraints: tuple
    wtmass: float
    skipped: dict
    notes: tuple[str, ...]
    path: str
    max_ids: dict
    composites: dict = field(default_factory=dict)
    orthotropic: dict = field(default_factory=dict)
    equations: tuple = ()
    interpolations: dict = field(default_factory=dict)
    solids: dict = field(default_factory=dict)
    solid_sections: dict = field(default_factory=dict)

    def __repr__(self) -> str:
        sizes = ", ".join(counted(len(t), one, many) for one, many, t in (
            ("grid", None, self.grids), ("line element", None, self.lines), ("shell", None, self.shells),
            ("mass", "masses", self.masses), ("spring", None, self.springs), ("bush", "bushes", self.bushes),
            ("RBE2", "RBE2s", self.rigid)) if t)
        return f"Deck({self.path!r}: {sizes})"

    def unmodelled_sentence(self) -> str:
        """The cards not modelled, by name and count, in one sentence ("" when every card was modelled)."""
        if not self.skipped:
            return ""
        shown = ", ".join(f"{name} ({n})" for name, n in sorted(self.skipped.items()))
        solution = sorted(set(self.skipped) & SOLUTION_CARDS)
        other = sorted(set(self.skipped) - SOLUTION_CARDS)
        why = []
        if other:
            why.append(f"{'it is' if len(other) == 1 else 'they are'} left out of the model "
                       f"({', '.join(other)})")
        if solution:
            why.append(f"solution and output requests ({', '.join(solution)}) do not change the modes")
        return (f"Not modelled: {counted(sum(self.skipped.values()), 'card')} of the deck, {shown}; "
                f"{' and '.join(why)}.")


def read_deck(path) -> Deck:
    """Read a Nastran bulk-data deck (and its includes) into its modelled cards (:class:`Deck`)."""
    return build_deck(read_bulk(path))


def build_deck(bulk: BulkData) -> Deck:
    """Gather the cards of ``bulk`` by id; DataError (naming file, line and card) on a duplicate id."""
    tables: dict[str, dict] = {name: {} for name in set(_TABLES.values()) | {"springs", "bushes",
                                                                             "interpolations"}}
    skipped: Counter = Counter()
    spcs, pelas, celas, notes = [], {}, [], list(bulk.notes)
    pbush, cbush, mpcs, mpcadds = {}, [], [], {}
    wtmass = 1.0
    defaults = next((read.grdset(c) for c in bulk.cards if c.name == "GRDSET"), {})
    for card in bulk.cards:
        name = card.name
        if name == "GRID":
            record = read.grid(card, defaults)
            _put(tables["grids"], record.id, record, card)
            spcs += read.grid_spc(card, defaults)
        elif name in _READERS:
            record = _READERS[name](card)
            _put(tables[_TABLES[name]], _key(record), record, card)
        elif name in ("CORD1R", "CORD1C", "CORD1S"):
            for record in read.cord1(card):
                _put(tables["frames"], record.id, record, card)
        elif name == "MPC":
            mpcs.append(equation_cards.mpc_card(card))
        elif name == "MPCADD":
            sid, joined = equation_cards.mpcadd(card)
            mpcadds.setdefault(sid, []).extend(joined)
        elif name == "RBE3":
            record = equation_cards.rbe3(card)
            _put(tables["interpolations"], record.eid, record, card)
        elif name in ("SPC", "SPC1"):
            spcs += read.spc(card) if name == "SPC" else read.spc1(card)
        elif name == "PELAS":
            pelas.update(read.pelas(card))
        elif name in ("CELAS1", "CELAS2"):
            celas.append(card)
        elif name == "PBUSH":
            key, k = read.pbush(card)
            pbush[key] = k
        elif name == "CBUSH":
            cbush.append(card)
        elif name == "PARAM" and card.text(0).upper() == "WTMASS":
            wtmass = card.real(1, "WTMASS")
        elif name == "GRDSET":
            continue
        else:
            skipped[name] += 1
    for card in celas:
        record = read.celas(card, pelas)
        _put(tables["springs"], record.eid, record, card)
    for card in cbush:
        bush = read.cbush(card, pbush)
        _put(tables["bushes"], bush.eid, bush, card)
    chosen = [s for s in spcs if s.sid == -1 or bulk.case_spc is None or s.sid == bulk.case_spc]
    sets = sorted({s.sid for s in spcs if s.sid != -1})
    if bulk.case_spc is None and len(sets) > 1:
        notes.append(f"The case control selects no SPC set; every set is applied ({', '.join(map(str, sets))}).")
    elif bulk.case_spc is not None and bulk.case_spc not in sets:
        notes.append(f"The case control selects SPC set {bulk.case_spc}, which the deck does not define: "
                     "the model is free.")
    equations = _mpc_set(mpcs, mpcadds, bulk.case_mpc, notes)
    if wtmass != 1.0:
        notes.append(f"PARAM WTMASS {wtmass:g} multiplies every mass.")
    max_ids = {
        "element": max([0, *tables["lines"], *tables["shells"], *tables["masses"], *tables["springs"],
                        *tables["bushes"], *tables["rigid"], *tables["interpolations"],
                        *tables["solids"]]),
        "property": max([0, *tables["line_sections"], *tables["shell_sections"], *tables["composites"], *pelas,
                         *pbush, *tables["solid_sections"]]),
        "material": max([0, *tables["materials"], *tables["orthotropic"]]),
        "grid": max([0, *tables["grids"]]),
        "set": max([0, *sets, *(m.sid for m in mpcs), *mpcadds]),
    }
    return Deck(tables["grids"], tables["frames"], tables["lines"], tables["shells"], tables["line_sections"],
                tables["shell_sections"], tables["materials"], tables["masses"], tables["springs"],
                tables["bushes"], tables["rigid"], tuple(chosen), wtmass, dict(skipped), tuple(notes), bulk.path,
                max_ids, composites=tables["composites"], orthotropic=tables["orthotropic"], equations=equations,
                interpolations=tables["interpolations"], solids=tables["solids"],
                solid_sections=tables["solid_sections"])


def _mpc_set(mpcs: list, mpcadds: dict, chosen: int | None, notes: list) -> tuple:
    """The MPC records that apply: the case control's set (an MPC set or an MPCADD of sets), or every MPC when it
    selects none (a note when there are several sets), as for SPC."""
    sets = sorted({m.sid for m in mpcs})
    if chosen is None:
        if len(sets) > 1:
            notes.append(f"The case control selects no MPC set; every set is applied ({', '.join(map(str, sets))}).")
        return tuple(mpcs)
    wanted, todo = set(), [chosen]
    while todo:
        sid = todo.pop()
        if sid in wanted:
            continue
        wanted.add(sid)
        todo += mpcadds.get(sid, [])
    if not wanted & set(sets):
        notes.append(f"The case control selects MPC set {chosen}, which the deck does not define: no MPC applies.")
    return tuple(m for m in mpcs if m.sid in wanted)


def _key(record) -> int:
    for attr in ("id", "eid", "pid", "mid"):
        if hasattr(record, attr):
            return getattr(record, attr)
    raise AttributeError(record)


def _put(table: dict, key: int, record, card: BulkCard) -> None:
    old = table.get(key)
    if old is not None:
        raise DataError(f"{card.where()}: id {key} is used twice (also {old.card.where()}). Give each "
                        f"{card.name} its own id.")
    table[key] = record
