"""explain on a Nastran deck against blind CalculiX truths: a stiffened panel (plate and two shell webs, the deck
tests/models/nastran_decks.stiffened_panel) with an effect hidden in the structure CalculiX solves (S8R shells
expanded into solids, a separate program) and model-form scatter (the plate's E +2 %, the webs' -1 %): what
explain names from the deck read by era.models.nastran.

Run: nice python3 tests/bench/bench_explain_deck.py            (every case, a few minutes on a shared machine)
 or: python3 -m pytest -s tests/bench/bench_explain_deck.py    (fails on a confident wrong name)
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent / "models"), str(HERE.parent / "fem")]
from calculix import frequencies, frequency_inp, run  # noqa: E402
from nastran_decks import deck_text, stiffened_panel  # noqa: E402

from era import explain  # noqa: E402
from era.discrepancy import modes_from_arrays  # noqa: E402
from era.fem.mesh import FEMesh, ShellProperty  # noqa: E402
from era.models.nastran import read_bdf  # noqa: E402

NX, NY = 16, 12
#: name: (web thickness factor, extra mass (node label, kg) or None, truth's expected (effect, place) or None)
CASES = {
    # measured (2026-11-27): ambiguous, property_factor PSHELL 2 T 0.71 at 81 %, the webs' part stiffness 19 %
    "thin webs": (0.75, None, ("property_factor", "property:PSHELL 2 T")),
    # measured: explained, the mass at its grid, 0.078 ± 0.003 kg
    "a point mass": (1.0, ("1", 0.08), ("point_mass", None)),
    # measured: no significant discrepancy
    "nothing": (1.0, None, None),
}


def ccx_modes(s: dict, web_factor: float, mass, sensors, folder: Path, n_modes: int = 8):
    """Frequencies and shapes at ``sensors`` ((label, "z") each) of the panel solved by ccx: the webs'
    thickness times web_factor, model-form scatter on E, an optional point mass (MASS element)."""
    plate = ShellProperty(s["plate"][0], s["plate"][1] * 1.02, s["plate"][2], s["plate"][3])
    web = ShellProperty(s["web"][0] * web_factor, s["web"][1] * 0.99, s["web"][2], s["web"][3])
    mesh = FEMesh(s["nodes"], tuple(s["shells"]), (), {"plate": plate, "web": web},
                  fixed=tuple((n, d) for n in s["clamped"] for d in ("x", "y", "z", "rx", "ry", "rz")))
    ids = {label: i + 1 for i, label in enumerate(mesh.nodes)}
    inp = frequency_inp(mesh, n_modes)
    extra = ["*NSET, NSET=SENSORS"] + [str(ids[n]) for n, _ in sensors]
    if mass is not None:
        extra = ["*ELEMENT, TYPE=MASS, ELSET=EMASS", f"90001, {ids[mass[0]]}", "*MASS, ELSET=EMASS",
                 f"{mass[1]!r}"] + extra
    head, step = inp.split("*STEP", 1)
    step = step.replace("*END STEP", "*NODE PRINT, NSET=SENSORS\nU\n*END STEP")
    dat = run("\n".join([head.rstrip()] + extra) + "\n*STEP" + step, folder)
    f = frequencies(dat)
    blocks = dat.split("displacements (vx,vy,vz)")[1:]
    shapes = np.zeros((len(sensors), len(blocks)))
    for j, block in enumerate(blocks):
        u = {int(p[0]): [float(x) for x in p[1:]] for p in (ln.split() for ln in block.splitlines()[1:])
             if len(p) == 4 and p[0].isdigit()}
        for k, (n, d) in enumerate(sensors):
            shapes[k, j] = u[ids[n]]["xyz".index(d)]
    return f, shapes


def case(name: str, folder: Path) -> tuple[str, str, float]:
    web_factor, mass, truth = CASES[name]
    cards, s = stiffened_panel(NX, NY)
    path = folder / "panel.bdf"
    path.write_text(deck_text(cards, "large"))
    plate_nodes = [n for n, x in s["nodes"].items() if x[2] == 0.0 and x[0] > 0]
    picks = plate_nodes[len(plate_nodes) // 14 // 2::len(plate_nodes) // 14][:14]
    sensors = [(n, "z") for n in picks]
    mass = (picks[-1], mass[1]) if mass is not None else None
    f, shapes = ccx_modes(s, web_factor, mass, sensors, folder / name.replace(" ", "_"))
    model = read_bdf(path).with_sensors(sensors)
    t0 = time.perf_counter()
    r = explain(modes_from_arrays(f[:6], shapes[:, :6], frequency_std_hz=0.002 * f[:6]), model,
                extra_model_modes=3)
    named = [(e.name, e.location) for e in r.effects] if r.verdict == "explained" else []
    if truth is None:
        verdict = "right" if not named else "wrong"
    elif not named:
        verdict = "honest"
    elif named[0][0] == truth[0] and (truth[1] is None or named[0][1] == truth[1]):
        verdict = "right"
    else:
        verdict = "wrong"
    print(f"{name:14s} {r.verdict:28s} {named} -> {verdict} ({time.perf_counter() - t0:.0f} s)")
    if r.effect is not None:
        print("   ", r.effect.description)
    return name, verdict, time.perf_counter() - t0


def test_no_confident_wrong_name_on_the_deck(tmp_path):
    results = [case(name, tmp_path) for name in CASES]
    assert not [r for r in results if r[1] == "wrong"]


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as tmp:
        for name in CASES:
            case(name, Path(tmp))
