"""A small cantilever plate of CalculiX bricks, solved by CalculiX itself (``ccx``, run as a separate program): its
matrices (``*FREQUENCY, SOLVER=MATRIXSTORAGE``), and its frequencies and mode shapes at chosen nodes with
effects hidden in it (a point mass: a MASS element; a spring to ground: a SPRING2 element to a clamped node).
A test helper, no tests."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np

CCX = shutil.which("ccx")
NX, NY = 10, 6              # elements along x (0.6 m) and y (0.4 m); one through the 10 mm thickness
SIZE = (0.6, 0.4, 0.01)


def node(i: int, j: int, k: int) -> int:
    return 1 + i + (NX + 1) * (j + (NY + 1) * k)


def plate_deck(step: str, *, e_scale: float = 1.0, extra: str = "") -> str:
    """The input deck of the plate (C3D8 bricks, steel, the x = 0 edge clamped) with ``step``'s cards."""
    lx, ly, t = SIZE
    out = ["*NODE, NSET=NALL"]
    out += [f"{node(i, j, k)}, {lx * i / NX!r}, {ly * j / NY!r}, {t * k!r}"
            for k in range(2) for j in range(NY + 1) for i in range(NX + 1)]
    out.append("*ELEMENT, TYPE=C3D8, ELSET=EALL")
    for j in range(NY):
        for i in range(NX):
            ids = [node(i, j, 0), node(i + 1, j, 0), node(i + 1, j + 1, 0), node(i, j + 1, 0),
                   node(i, j, 1), node(i + 1, j, 1), node(i + 1, j + 1, 1), node(i, j + 1, 1)]
            out.append(f"{1 + i + NX * j}, " + ", ".join(map(str, ids)))
    out += ["*ELSET, ELSET=ROOT"] + [str(1 + i + NX * j) for j in range(NY) for i in range(NX // 2)]
    out += ["*ELSET, ELSET=TIP"] + [str(1 + i + NX * j) for j in range(NY) for i in range(NX // 2, NX)]
    out += ["*NSET, NSET=FIX"] + [str(node(0, j, k)) for k in range(2) for j in range(NY + 1)]
    root, tip = (e_scale, e_scale) if np.ndim(e_scale) == 0 else e_scale
    for name, scale in (("ROOT", root), ("TIP", tip)):
        out += [f"*MATERIAL, NAME=STEEL{name}", "*ELASTIC", f"{210e9 * scale!r}, 0.3", "*DENSITY", "7850.",
                f"*SOLID SECTION, ELSET={name}, MATERIAL=STEEL{name}"]
    out += [extra, "*BOUNDARY", "FIX, 1, 3", "*STEP", step,
            "*END STEP"]
    return "\n".join(x for x in out if x) + "\n"


def run(folder: Path, job: str, deck: str) -> Path:
    """Run ``ccx job`` in ``folder`` on ``deck``; the path of its .dat."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{job}.inp").write_text(deck)
    done = subprocess.run([CCX, job], cwd=folder, capture_output=True, text=True, timeout=120,
                          env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    if "*ERROR" in done.stdout or done.returncode != 0:
        raise RuntimeError(f"ccx {job} failed: {done.stdout[-2000:]}")
    return folder / f"{job}.dat"


def matrices(folder: Path, job: str = "plate", **kw) -> Path:
    """Run the plate with SOLVER=MATRIXSTORAGE; the .sti's path."""
    run(folder, job, plate_deck("*FREQUENCY, SOLVER=MATRIXSTORAGE\n10", **kw))
    return folder / f"{job}.sti"


def frequencies(dat: Path) -> np.ndarray:
    """The frequencies (Hz) ccx prints in its .dat's eigenvalue table."""
    text = Path(dat).read_text()
    table = text.split("E I G E N V A L U E   O U T P U T")[1].split("P A R T I C I P A T I O N")[0]
    rows = [ln.split() for ln in table.splitlines() if re.match(r"^\s+\d+\s+[-\d.]", ln)]
    return np.array([float(r[3]) for r in rows])


def modes(folder: Path, job: str, n_modes: int, sensors, *, mass=None, spring=None, e_scale=1.0):
    """Frequencies (n,) Hz and shapes (p, n) at ``sensors`` ((node, direction) each) of the plate with a point
    mass (node, kg) and/or a spring to ground (node, direction, N/m) hidden in it, solved by ccx."""
    extra, nset = [], sorted({int(n) for n, _ in sensors})
    if mass is not None:
        extra += ["*ELEMENT, TYPE=MASS, ELSET=EMASS", f"90001, {mass[0]}", "*MASS, ELSET=EMASS", f"{mass[1]!r}"]
    if spring is not None:
        dof = "xyz".index(spring[1]) + 1
        extra += ["*ELEMENT, TYPE=SPRING2, ELSET=ESPRING", f"90002, {spring[0]}, {node(0, 0, 0)}",
                  "*SPRING, ELSET=ESPRING", f"{dof}, {dof}", f"{spring[2]!r}"]
    extra += ["*NSET, NSET=SENSORS"] + [str(n) for n in nset]
    step = f"*FREQUENCY\n{n_modes}\n*NODE PRINT, NSET=SENSORS\nU"
    dat = run(folder, job, plate_deck(step, e_scale=e_scale, extra="\n".join(extra)))
    f = frequencies(dat)
    blocks = dat.read_text().split("displacements (vx,vy,vz)")[1:]
    shapes = np.zeros((len(sensors), len(blocks)))
    for j, block in enumerate(blocks):
        u = {}
        for ln in block.splitlines()[1:]:
            parts = ln.split()
            if len(parts) == 4 and parts[0].isdigit():
                u[int(parts[0])] = [float(x) for x in parts[1:]]
        for p, (n, d) in enumerate(sensors):
            shapes[p, j] = u[int(n)]["xyz".index(d)]
    return f, shapes
