"""A named effect written back as Nastran bulk data: the engineer INCLUDEs it in the deck.

- a point mass: CONM2 (its mass divided by PARAM WTMASS, as Nastran multiplies it back);
- a spring to ground at a grid's component: CELAS1 with its PELAS;
- a property off by a factor: the changed card with the deck's own id (PSHELL T; MAT1 E and G together, or RHO;
  PBAR/PBEAM I1 and I2, A or J; a PBARL/PBEAML becomes the PBAR/PBEAM of its section; PROD A), which replaces
  the deck's card: the patch lists them at its top, :func:`write_patched_deck` writes a copy of the deck with
  them commented out and the patch included;
- a part (a property's elements) stiffer or heavier: its property card pointing at a new MAT1 with E, G and RHO
  scaled, its NSM scaled (:func:`deck_patch_for` turns explain's parameters into these).

New cards take ids above the deck's largest (elements, properties, materials), so they never collide with it. Cards are
written in large field (16 characters a value: 10 significant digits).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ...errors import DataError
from ..matrix import DIRECTIONS, direction_of
from .deck import Deck
from .mesh import CHANGEABLE
from .sections import DIMENSIONS
from .values import BulkCard

#: the name of the patch file write_patched_deck includes
PATCH_FILE = "era_patch.bdf"


@dataclass(frozen=True)
class DeckPatch:
    """Bulk data for a deck: ``text`` (the file to INCLUDE) and ``replaces`` ((file, first line, last line, card
    name and id), ...) the deck's cards the patch's changed properties replace (comment them out)."""

    text: str
    replaces: tuple = ()


def _value(v) -> str:
    if isinstance(v, str):
        return v
    if isinstance(v, int):
        return str(v)
    return f"{float(v):.9E}"


def large_field(name: str, values) -> str:
    """One card in large field: ``NAME*`` then 4 values of 16 characters a line, ``*`` continuations."""
    vals = [_value(v) if v is not None else "" for v in values]
    for v in vals:
        if len(v) > 16:
            raise ValueError(f"{v!r} does not fit a large field")
    lines, first = [], True
    for k in range(0, max(len(vals), 1), 4):
        chunk = "".join(v.rjust(16) if v else " " * 16 for v in vals[k:k + 4])
        lines.append(((name + "*").ljust(8) if first else "*".ljust(8)) + chunk)
        first = False
    return "\n".join(line.rstrip() for line in lines)


def _replacement(deck: Deck, key: str, factor: float) -> tuple[BulkCard, str]:
    """(the deck's card, its changed card as text) for a change key "PSHELL 3 T" and factor."""
    card_name, pid, field = key.split()
    pid = int(pid)
    if card_name == "PSHELL":
        p = deck.shell_sections[pid]
        fields = list(p.card.fields) + [""] * 8
        fields[2] = p.t * factor
        return p.card, large_field("PSHELL", _trim(fields))
    if card_name == "MAT1":
        m = deck.materials[pid]
        fields = list(m.card.fields) + [""] * 5
        if field == "E":
            fields[1], fields[2], fields[3] = m.e * factor, m.g * factor, m.nu
        else:
            fields[4] = m.rho * factor
        return m.card, large_field("MAT1", _trim(fields))
    s = deck.line_sections[pid]
    f = {k: (factor if k == field else 1.0) for k in ("I", "A", "J")}
    if s.kind == "PROD":
        fields = list(s.card.fields) + [""] * 4
        fields[2] = s.area * f["A"]
        return s.card, large_field("PROD", _trim(fields))
    a, i1, i2, j = s.area * f["A"], s.i1 * f["I"], s.i2 * f["I"], s.j * f["J"]
    if s.kind in ("PBAR", "PBARL"):
        if s.kind == "PBAR":
            fields = list(s.card.fields) + [""] * 8
            fields[2:6] = [a, i1, i2, j]
            return s.card, large_field("PBAR", _trim(fields))
        return s.card, large_field("PBAR", [s.pid, s.mid, a, i1, i2, j, s.nsm])
    return s.card, large_field("PBEAM", [s.pid, s.mid, a, i1, i2, 0.0, j, s.nsm])


def _trim(fields: list) -> list:
    while fields and (fields[-1] == "" or fields[-1] is None):
        fields.pop()
    return fields


def _part_cards(deck: Deck, name: str, k_factor: float, m_factor: float, factors: dict, mid: int):
    """(the property card, its replacement text, the new MAT1's text) for a part ("PSHELL 3", "PBAR 7") whose
    stiffness is times k_factor and mass times m_factor: the property points at a new MAT1 ``mid`` with E and G
    times k_factor (and any factor on the old material's E), RHO times m_factor, and its NSM times m_factor."""
    card_name, pid = name.split()
    table = {"PSHELL": deck.shell_sections, "PSOLID": deck.solid_sections}.get(card_name, deck.line_sections)
    prop = table.get(int(pid))
    if prop is None or (card_name not in ("PSHELL", "PSOLID") and prop.kind != card_name):
        raise DataError(f"part {name!r} is not a property whose change the patch writes; those are the deck's "
                        "PSHELL, PSOLID, PBAR, PBARL, PBEAM, PBEAML and PROD cards (a PCOMP's plies are not "
                        "rewritten: change its materials by hand).")
    old = deck.materials[prop.mid1 if card_name == "PSHELL" else prop.mid]
    e_factor = float(factors.get(f"MAT1 {old.mid} E", 1.0)) * k_factor
    rho_factor = float(factors.get(f"MAT1 {old.mid} RHO", 1.0)) * m_factor
    material = large_field("MAT1", [mid, old.e * e_factor, old.g * e_factor, old.nu, old.rho * rho_factor])
    fields = list(prop.card.fields) + [""] * 10
    if card_name == "PSHELL":
        fields[1], fields[3] = mid, mid
        if fields[5] not in ("", None):
            fields[5] = mid
        fields[7] = prop.nsm * m_factor
    elif card_name == "PSOLID":
        fields[1] = mid
    else:
        fields[1] = mid
        nsm_at = {"PBAR": 6, "PBEAM": 7, "PROD": 5}.get(prop.kind)
        if nsm_at is None:       # PBARL, PBEAML: NSM after the dimensions
            nsm_at = 8 + DIMENSIONS[prop.shape]
        fields[nsm_at] = prop.nsm * m_factor
    return prop.card, large_field(prop.card.name, _trim(fields)), material


def deck_patch(deck: Deck, *, masses=(), springs=(), factors=None, parts=None, title: str = "") -> DeckPatch:
    """The bulk data that adds effects to ``deck``.

    masses : ((grid, mass), ...) or ((grid, mass, (Ixx, Iyy, Izz)), ...) in the model's units (WTMASS applied);
    springs : ((grid, direction, k), ...) springs to ground, direction "x".."rz" (or 1-6) in the grid's
        displacement frame, k in force per length (or moment per radian);
    factors : {"PSHELL 3 T": 0.9, "MAT1 1 E": 1.1, "PBAR 7 I": 0.5, ...} (era.models.nastran.mesh.CHANGEABLE);
    parts : {"PSHELL 3": (stiffness factor, mass factor), ...}: a part stiffer or heavier than modelled, written
        as its property card pointing at a new MAT1 (E, G and RHO scaled) with its NSM scaled;
    title : a comment line at the top (what the effect is, e.g. the explanation's sentence).
    """
    eid, pid, mid = deck.max_ids["element"], deck.max_ids["property"], deck.max_ids["material"]
    title = title.replace("×", "x").replace("·", "*").encode("ascii", "replace").decode()   # decks are ASCII
    head = [f"$ era patch for {Path(deck.path).name}" + (f": {title}" if title else "")]
    body, replaces = [], []
    for item in masses:
        grid, mass = int(item[0]), float(item[1])
        inertia = [float(x) / deck.wtmass for x in (item[2] if len(item) > 2 else (0.0, 0.0, 0.0))]
        _grid(deck, grid)
        eid += 1
        body.append(large_field("CONM2", [eid, grid, 0, mass / deck.wtmass, 0.0, 0.0, 0.0, "",
                                          inertia[0], 0.0, inertia[1], 0.0, 0.0, inertia[2]]))
    for grid, direction, k in springs:
        grid = int(grid)
        _grid(deck, grid)
        component = DIRECTIONS.index(direction_of(direction)) + 1
        eid, pid = eid + 1, pid + 1
        body.append(large_field("CELAS1", [eid, pid, grid, component]))
        body.append(large_field("PELAS", [pid, float(k)]))
    for key, factor in (factors or {}).items():
        words = key.split()
        if len(words) != 3 or words[2] not in CHANGEABLE.get(words[0], ()):
            raise DataError(f"{key!r} is not a property change a patch can write (see CHANGEABLE).")
        card, text = _replacement(deck, key, float(factor))
        head.append(f"$ replaces {card.name} {card.fields[0]} ({card.file}, line {card.line}): comment it out")
        replaces.append((card.file, card.line, card.last_line or card.line, card.name, card.fields[0]))
        body.append(text)
    replaced = {(r[3], r[4]) for r in replaces}
    for name, (k_factor, m_factor) in (parts or {}).items():
        mid += 1
        card, text, material = _part_cards(deck, str(name), float(k_factor), float(m_factor), factors or {}, mid)
        if (card.name, card.fields[0]) in replaced:
            raise DataError(f"{card.name} {card.fields[0]} is changed twice (a property factor and a part factor); "
                            "name one of the two.")
        head.append(f"$ replaces {card.name} {card.fields[0]} ({card.file}, line {card.line}): comment it out")
        replaces.append((card.file, card.line, card.last_line or card.line, card.name, card.fields[0]))
        body += [material, text]
    return DeckPatch("\n".join(head + body) + "\n", tuple(replaces))


def deck_patch_for(deck: Deck, params: dict, title: str = "") -> DeckPatch:
    """The patch of explain's parameters (an updated DeckExplainModel's .params: point_mass_at/point_mass,
    spring_at "grid:direction"/spring_stiffness, part_at and part_mass_at "part:PSHELL 3" with their factors,
    property_at "property:PSHELL 3 T"/property_factor); the global stiffness factor, a nuisance, is not written.
    Spread mass (distributed_mass) has no card of its own: DataError says to scale PARAM WTMASS instead."""
    p = dict(params)
    if p.get("distributed_mass"):
        raise DataError("spread mass is not written as a card: multiply PARAM WTMASS by (1 + the spread mass / "
                        "the structure's mass) in the deck.")
    masses = [(p["point_mass_at"], p["point_mass"])] if p.get("point_mass_at") is not None and p.get(
        "point_mass") else []
    springs = []
    if p.get("spring_at") is not None and p.get("spring_stiffness"):
        grid, _, d = str(p["spring_at"]).rpartition(":")
        springs.append((grid, d, p["spring_stiffness"]))
    factors = {}
    if p.get("property_at") is not None and p.get("property_factor", 1.0) != 1.0:
        factors[str(p["property_at"]).removeprefix("property:")] = p["property_factor"]
    parts: dict = {}
    for at, key, slot in (("part_at", "part_factor", 0), ("part_mass_at", "part_mass_factor", 1)):
        if p.get(at) is not None and p.get(key, 1.0) != 1.0:
            name = str(p[at]).removeprefix("part:")
            pair = list(parts.get(name, (1.0, 1.0)))
            pair[slot] = float(p[key])
            parts[name] = tuple(pair)
    return deck_patch(deck, masses=masses, springs=springs, factors=factors, parts=parts, title=title)


def _grid(deck: Deck, grid: int) -> None:
    if grid not in deck.grids:
        raise DataError(f"grid {grid} is not in the deck {Path(deck.path).name}; a patch adds to existing grids.")


def write_patched_deck(deck: Deck, patch: DeckPatch, folder) -> Path:
    """A copy of the deck's files in ``folder`` (same names, includes kept relative), the replaced cards'
    lines commented out ("$era$ "), the patch written to era_patch.bdf and included before ENDDATA (at the end
    without one). Returns the new main file's path."""
    folder = Path(folder)
    main = Path(deck.path)
    files = {main.name} | {f for f, *_ in patch.replaces} | _included(deck)
    cut: dict = {}
    for f, first, last, *_ in patch.replaces:
        cut.setdefault(f, set()).update(range(first, last + 1))
    for name in files:
        source = main.parent / name
        lines = source.read_bytes().decode("latin-1").splitlines()
        lines = ["$era$ " + t if k + 1 in cut.get(name, ()) else t for k, t in enumerate(lines)]
        if name == main.name:
            at = next((k for k, t in enumerate(lines) if t.strip().upper().startswith("ENDDATA")), len(lines))
            lines.insert(at, f"INCLUDE '{PATCH_FILE}'")
        target = folder / name
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(("\n".join(lines) + "\n").encode("latin-1"))
    (folder / PATCH_FILE).write_text(patch.text, encoding="latin-1")
    return folder / main.name


def _included(deck: Deck) -> set:
    """The deck's files other than the main one (every file a modelled card came from)."""
    tables = (deck.grids, deck.frames, deck.lines, deck.shells, deck.line_sections, deck.shell_sections,
              deck.materials, deck.masses, deck.springs, deck.bushes, deck.rigid, deck.composites, deck.orthotropic,
              deck.interpolations, deck.solids, deck.solid_sections)
    out = {r.card.file for t in tables for r in t.values()} | {s.card.file for s in (*deck.constraints,
                                                                                     *deck.equations)}
    return {f for f in out if not Path(f).is_absolute() and ".." not in Path(f).parts}
