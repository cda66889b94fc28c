"""era.load_model: an FE model from files, whichever program wrote them.

- a folder or a ``.zip`` with ``K.mtx`` and ``M.mtx`` (Matrix Market), ``dofs.csv`` (``node,direction`` per row,
  the header line optional), optional ``coordinates.csv`` (``node,x,y,z``), ``parts/<name>.mtx`` (a part's
  stiffness) and ``part_masses/<name>.mtx`` (its mass), optional ``units.txt`` (a name of UNIT_SYSTEMS);
- CalculiX's matrix storage (``*FREQUENCY, SOLVER=MATRIXSTORAGE``): ``job.sti``, ``job.mas``, ``job.dof``, in a
  folder or a ``.zip`` or named directly (era.models.calculix);
- a Nastran bulk-data deck (``.bdf``, ``.dat``, ``.nas``): era.models.nastran.read_bdf.

Limits (era.models.sources): at most 2 GiB of uncompressed content per call (``max_bytes``), 10,000 zip
entries, 5,000,000 DOFs; a zip bomb is refused before it inflates.
"""

from __future__ import annotations

from pathlib import Path, PurePosixPath

from ..errors import DataError
from ..io.inflate import Budget
from ..words import counted, listed
from .calculix import calculix_model
from .matrix import MatrixModel
from .sources import MAX_BYTES, Files, read_coordinates, read_dofs, read_mtx

NASTRAN = (".bdf", ".dat", ".nas")
CALCULIX = (".sti", ".mas", ".dof")


def _matrix_market(files: Files) -> MatrixModel:
    need = {"K.mtx": "the stiffness", "M.mtx": "the mass", "dofs.csv": "the DOF list"}
    found = {n: files.find(n) for n in need}
    missing = [n for n, f in found.items() if f is None]
    if missing:
        raise DataError(f"{files.label} has no {listed(missing)}: a matrix model needs K.mtx (stiffness), M.mtx "
                        "(mass) and dofs.csv (node,direction per row) (docs/fe-models.md).")
    k = read_mtx(files, found["K.mtx"], "the stiffness")
    m = read_mtx(files, found["M.mtx"], "the mass")
    dofs = read_dofs(files, found["dofs.csv"])
    coords = files.find("coordinates.csv")
    parts, part_masses = {}, {}
    for stored in files.names:
        path = PurePosixPath(stored)
        if len(path.parts) == 2 and path.suffix.lower() == ".mtx":
            if path.parts[0].lower() == "parts":
                parts[path.stem] = read_mtx(files, stored, f"part {path.stem}")
            elif path.parts[0].lower() == "part_masses":
                part_masses[path.stem] = read_mtx(files, stored, f"part {path.stem}'s mass")
    units = files.find("units.txt")
    try:
        return MatrixModel(k, m, dofs, coordinates=None if coords is None else read_coordinates(files, coords),
                           parts=parts, part_masses=part_masses, name=files.path.stem,
                           units="SI" if units is None else files.text(units).strip())
    except DataError as exc:
        raise DataError(f"{files.label}: {exc}") from None


def load_model(path, *, max_bytes: int | None = MAX_BYTES) -> MatrixModel:
    r"""The engineer's FE model from files (see the module docstring and docs/fe-models.md).

    Parameters
    ----------
    path : str or os.PathLike
        A folder or ``.zip`` (Matrix Market files ``K.mtx``, ``M.mtx``, ``dofs.csv``, or CalculiX's
        ``.sti``/``.mas``/``.dof``), one of CalculiX's three files, or a Nastran deck (``.bdf``, ``.dat``,
        ``.nas``).
    max_bytes : int, optional
        The uncompressed bytes this call may read (None: no limit; default MAX_BYTES).

    Returns
    -------
    MatrixModel
        A Nastran deck gives an era.models.nastran.NastranModel (a MatrixModel that keeps its cards).

    Raises
    ------
    era.DataError
        Naming the file and what to do.
    era.TooLargeError
        Past ``max_bytes``.

    Examples
    --------
    A steel strip (50 × 10 mm, 1 m) clamped at grid 1, as a free-field Nastran deck of four CBARs:

    >>> import os, tempfile
    >>> deck = ["BEGIN BULK"] + [f"GRID,{i + 1},,{0.25 * i},0.,0." for i in range(5)]
    >>> deck += [f"CBAR,{i + 1},1,{i + 1},{i + 2},0.,0.,1." for i in range(4)]
    >>> deck += ["PBAR,1,1,5.-4,4.17-9,1.04-7,1.46-8", "MAT1,1,2.+11,,0.3,7850.", "SPC1,1,123456,1", "ENDDATA"]
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "strip.bdf")
    ...     with open(path, "w") as file:
    ...         _ = file.write("\n".join(deck) + "\n")
    ...     strip = era.load_model(path)
    >>> strip.n_dofs, strip.nodes
    (24, ('2', '3', '4', '5'))
    >>> print(np.round(strip.modes(1)[0], 2))
    [8.16]
    """
    path = Path(path)
    if not path.exists():
        raise DataError(f"{path} does not exist: give a folder or .zip with K.mtx, M.mtx and dofs.csv, CalculiX's "
                        "job.sti, or a Nastran deck.")
    suffix = path.suffix.lower()
    if suffix in NASTRAN:
        try:
            from .nastran import read_bdf  # the bulk-data reader is large: loaded when a deck is read
        except ImportError:
            raise DataError(f"{path.name}: this installation has no Nastran reader (era.models.nastran); export "
                            "the model's matrices instead (docs/fe-models.md).") from None
        return read_bdf(path)
    budget = Budget(max_bytes)
    if suffix in CALCULIX:
        return calculix_model(Files(path.parent, budget), path.stem)
    if not path.is_dir() and suffix != ".zip":
        raise DataError(f"{path.name}: load_model reads a folder or .zip of matrices, CalculiX's .sti/.mas/.dof or "
                        f"a Nastran deck ({listed(NASTRAN)}), not {suffix or 'a file without a suffix'}.")
    files = Files(path, budget)
    if files.find("K.mtx") is None:
        jobs = sorted({PurePosixPath(n).stem for n in files.names if n.lower().endswith(".sti")})
        if len(jobs) == 1:
            return calculix_model(files, jobs[0])
        if len(jobs) > 1:
            raise DataError(f"{path.name} holds the matrices of {counted(len(jobs), 'CalculiX job')} "
                            f"({listed(jobs)}); give one job's files.")
    return _matrix_market(files)
