"""CalculiX's matrix storage as a MatrixModel.

``*FREQUENCY, SOLVER=MATRIXSTORAGE`` makes ccx write, instead of solving, the matrices of the free DOFs (after
its *BOUNDARY conditions) in three text files (learnt by running ccx 2.20 on solid models):

- ``job.sti``, ``job.mas``: the stiffness and mass, one nonzero per line, ``row column value`` (1-based), the
  upper triangle only (row ≤ column);
- ``job.dof``: one line per row, ``node.direction`` (direction 1-3 the translations, 4-6 the rotations).

ccx expands beam and shell elements into 20-node bricks and writes the expanded model's rows; their ``.dof``
then names one node and direction on several rows, which MatrixModel refuses with that reason. Coordinates come
from ``job.inp``'s ``*NODE`` lines when that file sits beside them (else from ``coordinates.csv``, if any).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse

from ..errors import DataError
from ..words import listed
from .matrix import DIRECTIONS, MatrixModel
from .sources import read_coordinates


def _triangle(files, name: str, n: int) -> scipy.sparse.csr_matrix:
    """The symmetric matrix of an upper-triangle ``row column value`` listing (1-based) of an n-DOF model."""
    try:
        v = np.array(files.read(name).split(), dtype=float)
    except ValueError:
        raise DataError(f"{name} in {files.label}: every line must be 'row column value' (numbers).") from None
    if v.size % 3:
        raise DataError(f"{name} in {files.label}: {v.size} numbers is not a whole number of 'row column value' "
                        "lines; the file is truncated.")
    v = v.reshape(-1, 3)
    r, c = v[:, 0].astype(np.int64) - 1, v[:, 1].astype(np.int64) - 1
    if v.size and (min(r.min(), c.min()) < 0 or max(r.max(), c.max()) >= n):
        raise DataError(f"{name} in {files.label} refers to row {int(max(r.max(), c.max())) + 1} but the .dof file "
                        f"lists {n} rows; give the three files of one ccx run.")
    off = r != c
    rows = np.r_[r, c[off]]
    cols = np.r_[c, r[off]]
    return scipy.sparse.csr_matrix((np.r_[v[:, 2], v[off, 2]], (rows, cols)), shape=(n, n))


def read_dof_file(text: str, name: str = "job.dof") -> list[tuple[str, str]]:
    """(node, direction) per line of a CalculiX ``.dof`` file (``node.direction``)."""
    out = []
    for k, line in enumerate(text.split(), start=1):
        node, _, d = line.partition(".")
        if not node.isdigit() or d not in ("1", "2", "3", "4", "5", "6"):
            what = "a temperature DOF (0)" if d == "0" else repr(line)
            raise DataError(f"{name} line {k} is {what}; each line must be node.direction with direction 1-6 "
                            "(a structural model).")
        out.append((node, DIRECTIONS[int(d) - 1]))
    return out


def inp_nodes(text: str) -> dict:
    """{node: (x, y, z)} from the ``*NODE`` blocks of a CalculiX/Abaqus input deck."""
    out, inside = {}, False
    for line in text.splitlines():
        s = line.strip()
        if not s or s.startswith("**"):
            continue
        if s.startswith("*"):
            inside = s.upper().split(",")[0].strip() == "*NODE"
            continue
        if inside:
            fields = [f.strip() for f in s.split(",") if f.strip()]
            try:
                out[fields[0]] = tuple(float(x) for x in (fields[1:4] + ["0", "0"])[:3])
            except (ValueError, IndexError):
                continue
    return out


def calculix_model(files, job: str) -> MatrixModel:
    """The MatrixModel of CalculiX job ``job`` from ``files`` (era.models.files.Files)."""
    names = {ext: files.find(f"{job}{ext}") for ext in (".sti", ".mas", ".dof")}
    missing = [f"{job}{ext}" for ext, n in names.items() if n is None]
    if missing:
        raise DataError(f"{files.label} has no {listed(missing)}: ccx writes {job}.sti, {job}.mas and {job}.dof "
                        "together for a step '*FREQUENCY, SOLVER=MATRIXSTORAGE'; give all three.")
    dofs = read_dof_file(files.text(names[".dof"]), names[".dof"])
    k = _triangle(files, names[".sti"], len(dofs))
    m = _triangle(files, names[".mas"], len(dofs))
    coords = None
    inp = files.find(f"{job}.inp")
    if inp is not None:
        coords = inp_nodes(files.text(inp)) or None
        if coords is not None and any(n not in coords for n, _ in dofs):
            coords = None       # ccx's own internal nodes (C3D8I's incompatible modes, expanded elements)
    elif files.find("coordinates.csv") is not None:
        coords = read_coordinates(files, files.find("coordinates.csv"))
    try:
        return MatrixModel(k, m, dofs, coordinates=coords, name=job)
    except DataError as exc:
        raise DataError(f"CalculiX job {job} in {files.label}: {exc}") from None
