"""CalculiX (``ccx``, Debian's calculix-ccx) as an independent solver for the tests: write an input deck, run ccx
as a separate program in a temporary folder, read its eigenvalues back.

CalculiX expands shells (S4, S3) and beams (B31) into 3-D solids internally, so its answers share no code and
little theory with era.fem's flat MITC shells and Euler-Bernoulli beams: a truth for the tests, not a twin.

    inp = frequency_inp(mesh, 10, beam_rect={"stiffener": (0.02, 0.006)})
    f_hz = frequencies(run(inp, tmp_path))
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np

_NUMBER = r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?"
_DOF = {"x": 1, "y": 2, "z": 3, "rx": 4, "ry": 5, "rz": 6}


def run(inp: str, folder: Path, name: str = "job", timeout: float = 300.0) -> str:
    """Run ``ccx`` on the deck ``inp`` in ``folder``; return the text of its ``.dat`` output. Raises
    RuntimeError with ccx's own last words when it fails (ccx exits 0 even on some errors, so both are checked)."""
    exe = shutil.which("ccx")
    if exe is None:
        raise RuntimeError("ccx (CalculiX) is not installed: apt-get install calculix-ccx")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.inp").write_text(inp)
    done = subprocess.run([exe, "-i", name], cwd=folder, capture_output=True, text=True, timeout=timeout,
                          env={"OMP_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    dat = folder / f"{name}.dat"
    if done.returncode != 0 or "*ERROR" in done.stdout or not dat.exists():
        tail = "\n".join((done.stdout + done.stderr).strip().splitlines()[-15:])
        raise RuntimeError(f"ccx failed (exit {done.returncode}):\n{tail}")
    return dat.read_text()


def frequencies(dat: str) -> np.ndarray:
    """The eigenfrequencies (cycles per time unit: Hz for seconds) of the first ``*FREQUENCY`` step in a ``.dat``
    text, ascending. The table after "E I G E N V A L U E   O U T P U T" holds rows ``mode, eigenvalue,
    ω (rad/time), f (cycles/time), imaginary part``."""
    start = dat.find("E I G E N V A L U E   O U T P U T")
    if start < 0:
        raise ValueError("no eigenvalue output in the .dat file")
    out = []
    row = re.compile(rf"^\s*(\d+)\s+({_NUMBER})\s+({_NUMBER})\s+({_NUMBER})\s+({_NUMBER})\s*$")
    for line in dat[start:].splitlines()[1:]:
        m = row.match(line)
        if m:
            out.append(float(m.group(4)))
        elif out and not line.strip():
            break
    return np.array(out)


def node_ids(mesh) -> dict:
    """{label: ccx node number} as frequency_inp numbers an era.fem FEMesh's nodes."""
    return {label: i + 1 for i, label in enumerate(mesh.nodes)}


def displacements(dat: str, points) -> np.ndarray:
    """The mode shapes (p, n) at ``points`` ((ccx node number, "x" | "y" | "z") each) from a ``.dat`` text whose
    deck asked ``*NODE PRINT ... U`` (frequency_inp's ``printed``): one "displacements (vx,vy,vz)" table per mode,
    rows ``node, ux, uy, uz`` (for a shell's node ccx prints its reference node's translation)."""
    blocks = dat.split("displacements (vx,vy,vz)")[1:]
    out = np.zeros((len(points), len(blocks)))
    for j, block in enumerate(blocks):
        u = {}
        for line in block.splitlines()[1:]:
            parts = line.split()
            if len(parts) == 4 and parts[0].isdigit():
                u[int(parts[0])] = [float(x) for x in parts[1:]]
            elif u and not line.strip():
                break
        for p, (n, d) in enumerate(points):
            out[p, j] = u[int(n)]["xyz".index(d)]
    return out


def frequency_inp(mesh, n_modes: int, beam_rect: dict | None = None, quadratic: bool = True,
                  printed: tuple = (), layers: dict | None = None, offsets: dict | None = None) -> str:
    """A ccx deck of an era.fem FEMesh's lowest ``n_modes`` modes: shells per ShellProperty, beams with a
    rectangular section per BeamProperty (``beam_rect`` {name: (depth along the beam's orientation vector, width)};
    ccx's own torsion and inertias of that rectangle are used, not the property's), MASS elements for point
    masses (no rotary inertia), SPC as *BOUNDARY. Springs, RBE2 and non-structural mass are not written.

    quadratic : S8R/S6 shells and B32 beams on mid-edge nodes added at the edges' mid-points (held where both
        ends are held), far more accurate than ccx's linear S4/S3/B31 on the same mesh; else the linear ones.
    printed : node labels whose translations ccx prints for every mode (read them with :func:`displacements`).
    layers : {shell property name: ((t, e1, e2, nu12, g12, g13, g23, rho, angle_deg), ...) from the bottom up}:
        that property as ``*SHELL SECTION, COMPOSITE`` of transversely isotropic plies (E3 = E2, ν13 = ν12,
        G23 from ν23), each turned by its angle about the shell's normal (global z: flat shells in the x-y plane).
    offsets : {shell property name: ccx's OFFSET, the reference surface's offset from the mid-surface in
        thicknesses (OFFSET = 0.5: the nodes on the top surface; Nastran's ZOFFS = −OFFSET·t)}.
    """
    if mesh.springs or mesh.rigid or any(p.nsm for p in mesh.shell_properties.values()):
        raise ValueError("frequency_inp writes no springs, RBE2 or non-structural mass")
    ids = node_ids(mesh)
    xyz = {label: np.asarray(x, float) for label, x in mesh.nodes.items()}
    held = {}
    for n, d in mesh.fixed:
        held.setdefault(n, set()).add(d)
    mid: dict = {}

    def middle(n1, n2) -> int:   # one shared node per edge
        key = frozenset((n1, n2))
        if key not in mid:
            mid[key] = len(ids) + len(mid) + 1
            xyz[mid[key]] = 0.5 * (xyz[n1] + xyz[n2])
            held[mid[key]] = held.get(n1, set()) & held.get(n2, set())
        return mid[key]

    def ring(conn) -> list:
        ids_ = [ids[n] for n in conn]
        if quadratic:
            ids_ += [middle(conn[k], conn[(k + 1) % len(conn)]) for k in range(len(conn))]
        return ids_

    body, sections = [], []
    eid = 0
    for name, p in mesh.shell_properties.items():
        for nn, kind in ((4, "S8R" if quadratic else "S4"), (3, "S6" if quadratic else "S3")):
            conns = [c for pname, c in mesh.shells if pname == name and len(c) == nn]
            if not conns:
                continue
            body.append(f"*ELEMENT, TYPE={kind}, ELSET=E{kind}_{name}")
            for c in conns:
                eid += 1
                body.append(f"{eid}, " + ", ".join(map(str, ring(c))))
            offset = f", OFFSET={offsets[name]:.12g}" if name in (offsets or {}) else ""
            if name in (layers or {}):
                sections += [f"*SHELL SECTION, ELSET=E{kind}_{name}, COMPOSITE{offset}"]
                sections += [f"{ply[0]:.12g}, , M_{name}_{k}, O_{name}_{k}" for k, ply in enumerate(layers[name])]
            else:
                sections += [f"*SHELL SECTION, ELSET=E{kind}_{name}, MATERIAL=M_{name}{offset}",
                             f"{p.thickness:.12g}"]
        if name in (layers or {}):
            for k, (_, e1, e2, nu12, g12, g13, g23, rho, angle) in enumerate(layers[name]):
                c, s_ = np.cos(np.radians(angle)), np.sin(np.radians(angle))
                body += [f"*ORIENTATION, NAME=O_{name}_{k}", f"{c:.15g}, {s_:.15g}, 0, {-s_:.15g}, {c:.15g}, 0",
                         f"*MATERIAL, NAME=M_{name}_{k}", "*ELASTIC, TYPE=ENGINEERING CONSTANTS",
                         f"{e1:.12g}, {e2:.12g}, {e2:.12g}, {nu12:.12g}, {nu12:.12g}, {e2 / (2 * g23) - 1:.12g}, "
                         f"{g12:.12g}, {g13:.12g}", f"{g23:.12g}, 0", "*DENSITY", f"{rho:.12g}"]
        else:
            body += _material(name, p.e, p.nu, p.rho)
    for name, p in mesh.beam_properties.items():
        beams = [b for b in mesh.beams if b[0] == name]
        depth, width = (beam_rect or {})[name]
        # ccx takes one section direction per element set: one set per distinct orientation
        for k, v in enumerate(sorted({tuple(np.round(np.asarray(b[3], float), 12)) for b in beams})):
            body.append(f"*ELEMENT, TYPE={'B32' if quadratic else 'B31'}, ELSET=B_{name}_{k}")
            for b in beams:
                if tuple(np.round(np.asarray(b[3], float), 12)) == v:
                    eid += 1
                    ends = [ids[b[1]], middle(b[1], b[2]), ids[b[2]]] if quadratic else [ids[b[1]], ids[b[2]]]
                    body.append(f"{eid}, " + ", ".join(map(str, ends)))
            sections += [f"*BEAM SECTION, ELSET=B_{name}_{k}, MATERIAL=M_{name}, SECTION=RECT",
                         f"{depth:.12g}, {width:.12g}", ", ".join(f"{c:.12g}" for c in v)]
        body += _material(name, p.e, p.e / (2 * p.g) - 1, p.rho)
    for k, (node, mass, _) in enumerate(mesh.masses):
        eid += 1
        body += [f"*ELEMENT, TYPE=MASS, ELSET=PM{k}", f"{eid}, {ids[node]}", f"*MASS, ELSET=PM{k}", f"{mass:.12g}"]
    lines = ["*HEADING", "era.fem test model", "*NODE"]
    lines += [f"{ids.get(n, n)}, " + ", ".join(f"{c:.12g}" for c in x) for n, x in xyz.items()]
    lines += body + sections
    bc = [(ids.get(n, n), _DOF[d]) for n, ds in held.items() for d in sorted(ds, key=_DOF.get)]
    if bc:
        lines += ["*BOUNDARY"] + [f"{n}, {d}, {d}" for n, d in bc]
    if printed:
        lines += ["*NSET, NSET=PRINTED"] + [str(ids[n]) for n in printed]
    lines += ["*STEP", "*FREQUENCY", f"{int(n_modes)}"]
    lines += ["*NODE PRINT, NSET=PRINTED", "U"] if printed else []
    lines += ["*END STEP"]
    return "\n".join(lines) + "\n"


def _material(name: str, e: float, nu: float, rho: float) -> list:
    return [f"*MATERIAL, NAME=M_{name}", "*ELASTIC", f"{e:.12g}, {nu:.12g}", "*DENSITY", f"{rho:.12g}"]
