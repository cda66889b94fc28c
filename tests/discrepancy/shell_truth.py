"""Blind truths for era.explain on plates and shells, solved by CalculiX (``ccx`` run as a separate program, its S8R
shells expanded into solids): a test helper, no tests.

Two structures, each a Nastran deck the engineer gives explain (read by era.models.nastran, solved by era.fem):

- "plate": an aluminium plate 0.6 × 0.4 m, 3 mm, on elastic supports (CELAS2 springs to ground: z along both
  short edges, 160 kN/m per metre, x and y at the corners), three PSHELLs (root, middle, tip thirds along x), each
  with its own MAT1; 21 × 14 CQUAD4, 30 z sensors;
- "panel": the stiffened panel of tests/models/nastran_decks.stiffened_panel (plate and two 20 mm shell webs,
  clamped along x = 0), the webs on their own MAT1, and a spring to ground (CELAS2, z) under each tip corner;
  18 × 12 CQUAD4 on the plate, 17 z sensors.

The meshes are fine enough that the nominal misses CalculiX by about 2 % at most over the measured modes with
nothing hidden and no scatter (at 12 × 8 MITC4 quads the plate's sixth mode is 3 % stiff, more than the scatter
tested: there a thickness 17 % over in the middle third read as its stiffness 56 % over, case 34), and coarse
enough that every node is a candidate place (explain thins meshes above 400 nodes to one node per cell, and names
that node for an effect at its neighbour: era.discrepancy.effects_matrix.MAX_PLACES).

The truth is the same structure written for ccx (tests/fem/calculix.py: quadratic S8R shells on mid-edge nodes,
SPRING2 elements to a held node for the springs, MASS elements) with model-form scatter drawn per case: every
PSHELL region's thickness and E uniform within ±2 %, every boundary spring within ±10 %; and one hidden effect
(or none) drawn from those explain offers on a deck: a point mass at a node, a spring to ground (z) at a node, a
part stiffer or softer (its E), a part heavier or lighter (its density), a PSHELL's thickness off by a factor.
Measured: the lowest modes the z sensors see, with opensees_truth.measure's noise (0.2 % on frequencies, 1 %
gains and shape noise).

A case is an opensees_truth.TruthCase with ``frame`` the nominal deck (an era NastranModel with its sensors), so
confusion.matrix and confusion.score class it as they class the frames' cases.
"""

from __future__ import annotations

import functools
import sys
import tempfile
from pathlib import Path
from types import SimpleNamespace

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent / "fem"), str(HERE.parent / "models"), str(HERE)]
from calculix import frequencies, frequency_inp, run  # noqa: E402
from nastran_decks import deck_text, stiffened_panel  # noqa: E402
from opensees_truth import TruthCase, measure  # noqa: E402

from era.fem.mesh import FEMesh, ShellProperty  # noqa: E402
from era.models.nastran import read_bdf  # noqa: E402

FAMILIES = ("plate", "panel")
LABELS = ("none", "point_mass", "ground_spring_z", "part_stiffness", "part_mass", "thickness")
N_MODES = 8                   # modes measured
ALU = (70e9, 0.33, 2700.0)
_DOF = {"x": 1, "y": 2, "z": 3}


def plate(nx: int = 21, ny: int = 14) -> dict:
    """The plate on springs: {"nodes", "shells": [(region, conn)], "regions": {region: (pid, t, E, nu, rho)},
    "springs": [(node, direction, k)], "clamped": [], "sensors": [(node, "z")]}; a region is a PSHELL id."""
    a, b, t = 0.6, 0.4, 0.003
    gid = {(i, j): 1 + i + j * (nx + 1) for j in range(ny + 1) for i in range(nx + 1)}
    nodes = {str(g): (a * i / nx, b * j / ny, 0.0) for (i, j), g in gid.items()}
    shells = [(1 + 3 * i // nx, tuple(str(gid[c]) for c in ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1))))
              for j in range(ny) for i in range(nx)]
    springs = [(str(gid[i, j]), "z", 2.0e4 * 8 / ny) for i in (0, nx) for j in range(ny + 1)]   # 160 kN/m/m
    springs += [(str(gid[i, j]), d, 1.0e7) for i in (0, nx) for j in (0, ny) for d in ("x", "y")]
    sensors = [(str(gid[round(nx * fx), round(ny * fy)]), "z") for fx in np.arange(1, 12, 2) / 12
               for fy in np.arange(5) / 4]
    return dict(nodes=nodes, shells=shells, regions={p: (p, t, *ALU) for p in (1, 2, 3)}, springs=springs,
                clamped=[], sensors=sensors)


def panel(nx: int = 18, ny: int = 12) -> dict:
    """The stiffened panel (plate PSHELL 1, webs PSHELL 2), clamped at x = 0, on a spring under each tip corner;
    the same dict as :func:`plate`."""
    _, s = stiffened_panel(nx, ny)
    shells = [(1 if p == "plate" else 2, conn) for p, conn in s["shells"]]
    tip = [n for n, x in s["nodes"].items() if x[0] == 0.6 and x[2] == 0.0 and x[1] in (0.0, 0.4)]
    plate_nodes = [n for n, x in s["nodes"].items() if x[2] == 0.0 and x[0] > 0 and n not in tip]
    return dict(nodes=s["nodes"], shells=shells, regions={1: (1, *s["plate"]), 2: (2, *s["web"])},
                springs=[(n, "z", 2.0e4) for n in tip], clamped=s["clamped"],
                sensors=[(n, "z") for n in plate_nodes[len(plate_nodes) // 34::len(plate_nodes) // 17][:17]])


STRUCTURES = {"plate": plate, "panel": panel}


def deck_cards(s: dict) -> list:
    """The nominal Nastran deck: GRID, CQUAD4 per region (PSHELL id = MAT1 id = region), CELAS2 to ground, SPC1."""
    cards = [("GRID", [int(n), None, *x]) for n, x in s["nodes"].items()]
    cards += [("CQUAD4", [k + 1, pid, *map(int, conn)]) for k, (pid, conn) in enumerate(s["shells"])]
    for pid, t, e, nu, rho in s["regions"].values():
        cards += [("PSHELL", [pid, pid, t, pid]), ("MAT1", [pid, e, None, nu, rho])]
    cards += [("CELAS2", [90001 + k, kk, int(n), _DOF[d]]) for k, (n, d, kk) in enumerate(s["springs"])]
    if s["clamped"]:
        cards.append(("SPC1", [1, 123456, *map(int, s["clamped"])]))
    return cards


@functools.lru_cache(maxsize=None)
def nominal(family: str, folder: str, mesh: tuple = ()):
    """The deck explain is given (read by era.models.nastran.read_bdf), with its z sensors; ``mesh`` (nx, ny)
    the structure's elements along x and y (default its function's)."""
    s = STRUCTURES[family](*mesh)
    path = Path(folder) / f"{family}{'x'.join(map(str, mesh))}.bdf"
    path.write_text(deck_text(deck_cards(s), "large"))
    return read_bdf(path).with_sensors(s["sensors"])


def ccx_modes(s: dict, regions: dict, springs: list, folder: Path, mass=None, n_modes: int = N_MODES + 6):
    """Frequencies (n,) Hz and z shapes at every node (n_nodes, n) in s["nodes"] order of the structure solved
    by ccx: ``regions`` {pid: ShellProperty}, ``springs`` [(node, direction, k)] to ground, an optional point
    mass (node, kg)."""
    mesh = FEMesh(s["nodes"], tuple((f"r{p}", conn) for p, conn in s["shells"]), (),
                  {f"r{p}": prop for p, prop in regions.items()},
                  fixed=tuple((n, d) for n in s["clamped"] for d in ("x", "y", "z", "rx", "ry", "rz")))
    ids = {label: i + 1 for i, label in enumerate(mesh.nodes)}
    head, step = frequency_inp(mesh, n_modes).split("*STEP", 1)
    ground = 900000
    extra = [f"*NODE, NSET=GROUND\n{ground}, -1.0, -1.0, -1.0"]
    for k, (n, d, kk) in enumerate(springs):
        extra += [f"*ELEMENT, TYPE=SPRING2, ELSET=SP{k}", f"{800001 + k}, {ids[n]}, {ground}",
                  f"*SPRING, ELSET=SP{k}", f"{_DOF[d]}, {_DOF[d]}", f"{kk!r}"]
    if mass is not None:
        extra += ["*ELEMENT, TYPE=MASS, ELSET=EMASS", f"799999, {ids[mass[0]]}", "*MASS, ELSET=EMASS",
                  f"{mass[1]!r}"]
    extra += ["*BOUNDARY", f"{ground}, 1, 3", "*NSET, NSET=OUT"] + [str(ids[n]) for n in s["nodes"]]
    step = step.replace("*END STEP", "*NODE PRINT, NSET=OUT\nU\n*END STEP")
    dat = run("\n".join([head.rstrip()] + extra) + "\n*STEP" + step, folder)
    f = frequencies(dat)
    blocks = dat.split("displacements (vx,vy,vz)")[1:]
    rows = {ids[n]: k for k, n in enumerate(s["nodes"])}
    u = np.zeros((len(rows), len(blocks)))
    for j, block in enumerate(blocks):
        for p in (ln.split() for ln in block.splitlines()[1:]):
            if len(p) == 4 and p[0].isdigit() and int(p[0]) in rows:
                u[rows[int(p[0])], j] = float(p[3])
    return f, u


def _effect(label: str, s: dict, rng, total_kg: float) -> tuple:
    """(truth (kind, place, size) or None, region factors {pid: {"t"|"e"|"rho": factor}}, mass, spring)."""
    free = [n for n in s["nodes"] if n not in s["clamped"] and s["nodes"][n][2] == 0.0
            and n not in {m for m, *_ in s["springs"]}]
    node = free[int(rng.integers(len(free)))]
    region = sorted(s["regions"])[int(rng.integers(len(s["regions"])))]
    factor = lambda lo, hi: float(np.exp(rng.uniform(np.log(lo), np.log(hi))) ** rng.choice((-1, 1)))  # noqa: E731
    if label == "none":
        return None, {}, None, None
    if label == "point_mass":
        kg = float(total_kg * np.exp(rng.uniform(np.log(0.02), np.log(0.10))))
        return ("point_mass", node, kg), {}, (node, kg), None
    if label == "ground_spring_z":
        k = float(np.exp(rng.uniform(np.log(5e3), np.log(5e4))))
        return ("ground_spring_z", f"{node}:z", k), {}, None, (node, "z", k)
    if label == "part_stiffness":
        c = factor(1.25, 1.6)
        return ("part_stiffness", f"part:PSHELL {region}", c), {region: {"e": c}}, None, None
    if label == "part_mass":
        c = factor(1.25, 1.6)
        return ("part_mass", f"part:PSHELL {region}", c), {region: {"rho": c}}, None, None
    if label == "thickness":
        c = factor(1.15, 1.35)
        return ("property_factor", f"property:PSHELL {region} T", c), {region: {"t": c}}, None, None
    raise ValueError(f"unknown effect label {label!r}; known: {LABELS}")


def make_case(index: int, folder: str, scatter: float = 1.0, mesh: tuple = (),
              hidden: dict | None = None) -> TruthCase:
    """Blind case ``index``: family and effect label cycled (every label on both structures), the places, sizes,
    model-form scatter and noise drawn from a generator seeded by the index; ``scatter`` multiplies the
    model-form scatter (0: only the formulation and mesh differ); ``mesh`` as :func:`nominal`'s; ``hidden``
    {"label": ..., "truth": (kind, place, size), "regions": {pid: {"t"|"e"|"rho": factor}}, "mass": (node, kg),
    "spring": (node, direction, k)} (regions, mass and spring optional) hides that effect instead of the drawn
    one (the scatter and noise still drawn from the index)."""
    family = FAMILIES[index % len(FAMILIES)]
    label = LABELS[index // len(FAMILIES) % len(LABELS)]
    s = STRUCTURES[family](*mesh)
    model = nominal(family, folder, tuple(mesh))
    rng = np.random.default_rng([index, 38])
    truth, changes, mass, spring = _effect(label, s, rng, model.total_mass())
    if hidden is not None:
        label, truth, changes = hidden["label"], hidden["truth"], hidden.get("regions", {})
        mass, spring = hidden.get("mass"), hidden.get("spring")
    regions = {}
    for pid, (_, t, e, nu, rho) in s["regions"].items():
        c = changes.get(pid, {})
        scat = 1.0 + scatter * rng.uniform(-0.02, 0.02, 2)
        regions[pid] = ShellProperty(t * scat[0] * c.get("t", 1.0), e * scat[1] * c.get("e", 1.0), nu,
                                     rho * c.get("rho", 1.0))
    springs = [(n, d, k * (1.0 + scatter * rng.uniform(-0.10, 0.10))) for n, d, k in s["springs"]]
    springs += [spring] if spring else []
    with tempfile.TemporaryDirectory(dir=folder) as tmp:
        f, u = ccx_modes(s, regions, springs, Path(tmp), mass)
    at = [list(s["nodes"]).index(n) for n, _ in s["sensors"]]
    data, f_true = measure(SimpleNamespace(at_sensors=lambda v: v[at]), f, u, rng, N_MODES)
    effects = [truth] if truth else []
    where = f"{truth[0]} {truth[1]} {truth[2]:.3g}" if truth else "nothing"
    return TruthCase(f"{family}/{label}/#{index}: {where}", family, index, model, data, {"effects": effects},
                     label=label, frequency_hz=f_true)


def equivalent(effect, model) -> list:
    """The (kind, place) pairs a named effect's places stand for in the truth's terms, best first: a MAT1's E on
    a deck where that material belongs to one PSHELL only is that part's stiffness (the same matrices), so
    "property:MAT1 2 E" of "property_factor" is "part:PSHELL 2" of "part_stiffness"; any other place as named."""
    from confusion import places_of
    owners = {m: [p for p, sec in model.deck.shell_sections.items() if sec.mid1 == m] for m in model.deck.materials}
    out = []
    for p in places_of(effect):
        text = str(p)
        if effect.name == "property_factor" and text.startswith("property:MAT1 ") and text.endswith(" E"):
            mid = int(text.split()[1])
            if len(owners.get(mid, ())) == 1:
                out.append(("part_stiffness", f"part:PSHELL {owners[mid][0]}"))
                continue
        out.append((effect.name, p))
    return out
