"""The engineer's FE model as matrices: stiffness and mass of the free DOFs, what each DOF is, and (optionally)
where the nodes are and which part of the stiffness belongs to which part of the structure.

Any FE program can write these (docs/fe-models.md says how): :class:`MatrixModel` checks them once, with errors
that say what is wrong and what to do, and solves their lowest modes with era.fem.eigen.sparse_modes (a
singular mass matrix, massless rotations for instance, is allowed).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse

from ..errors import DataError
from ..words import counted, listed

#: The six directions of a DOF, in the order FE programs number them (1-6: Nastran components, CalculiX, ANSYS).
DIRECTIONS = ("x", "y", "z", "rx", "ry", "rz")
TRANSLATIONS = DIRECTIONS[:3]
#: Unit systems by name: the unit of mass, force and length (time always in seconds, frequencies in Hz).
UNIT_SYSTEMS = {
    "SI": {"mass": "kg", "force": "N", "length": "m"},
    "N-mm-t": {"mass": "t", "force": "N", "length": "mm"},
    "kip-in-s": {"mass": "kip·s²/in", "force": "kip", "length": "in"},
    "lbf-in-s": {"mass": "lbf·s²/in", "force": "lbf", "length": "in"},
}
#: Relative asymmetry tolerated in K and M (round-off of the program that wrote them); the mean of the two
#: triangles is kept.
SYMMETRY_TOL = 1e-6


def direction_of(value) -> str:
    """A DOF direction as one of DIRECTIONS: "x".."rz" in any case, or 1-6 (the programs' numbering)."""
    text = str(value).strip().lower()
    if text in DIRECTIONS:
        return text
    if text in ("1", "2", "3", "4", "5", "6"):
        return DIRECTIONS[int(text) - 1]
    raise DataError(f"unknown direction {value!r}: give one of {listed(DIRECTIONS, quote=True)} (or 1-6).")


def _square(matrix, what: str, n: int | None = None) -> scipy.sparse.csr_matrix:
    """``matrix`` as a symmetric CSR matrix of floats, checked: square, finite, symmetric, n × n when given."""
    try:
        a = scipy.sparse.csr_matrix(matrix, dtype=float) if scipy.sparse.issparse(matrix) else \
            scipy.sparse.csr_matrix(np.asarray(matrix, dtype=float))
    except (TypeError, ValueError) as exc:
        raise DataError(f"{what}: not a matrix of numbers ({exc}).") from None
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise DataError(f"{what} is {a.shape[0]} × {a.shape[1]}; it must be square (n × n, n the free DOFs).")
    if n is not None and a.shape[0] != n:
        raise DataError(f"{what} is {a.shape[0]} × {a.shape[1]} but the model has {counted(n, 'DOF')}; give it "
                        "over the same DOFs in the same order.")
    if not np.all(np.isfinite(a.data)):
        raise DataError(f"{what} holds NaN or infinite entries.")
    a.eliminate_zeros()
    scale = float(np.max(np.abs(a.data))) if a.nnz else 0.0
    skew = abs(a - a.T)
    worst = float(skew.max()) if skew.nnz else 0.0
    if worst > SYMMETRY_TOL * scale:
        i, j = (int(v[0]) for v in (skew == worst).nonzero())
        raise DataError(f"{what} is not symmetric: entries ({i + 1}, {j + 1}) and ({j + 1}, {i + 1}) differ by "
                        f"{worst:.3g} (largest entry {scale:.3g}). Write the full symmetric matrix (or one "
                        "triangle declared 'symmetric' in Matrix Market).")
    return ((a + a.T) * 0.5).tocsr()


@dataclass(frozen=True, eq=False, init=False)
class MatrixModel:
    """An FE model given as its matrices over the free DOFs.

    Made from matrices, or read by :func:`era.load_model` (Matrix Market, CalculiX, Nastran).

    Parameters
    ----------
    stiffness : (n, n) sparse or dense matrix
        Symmetric, in any consistent unit system (``units``); the supports are the DOFs left out.
    mass : (n, n) sparse or dense matrix
        Symmetric, in the same units. It may be singular (massless DOFs, e.g. rotations of a lumped-mass
        model).
    dofs : sequence of (node, direction), n of them
        One per row: node a label (ints are stored as str), direction one of "x", "y", "z", "rx", "ry", "rz"
        (or 1-6).
    coordinates : dict, optional
        {node: (x, y, z)} in the model's length unit; when given, every node of ``dofs`` needs one (nodes without
        free DOFs, the supported ones, may be listed too).
    parts : dict, optional
        {name: (n, n) the stiffness of that part}; the parts together are at most ``stiffness`` (each diagonal
        entry of their sum at most the whole's).
    part_masses : dict, optional
        {name: (n, n) the mass of that part} (a part heavier or lighter than modelled).
    name : str, optional
        A label for reports (default "model").
    units : str or dict, optional
        A name of UNIT_SYSTEMS or {"mass": ..., "force": ..., "length": ...} (default SI).
    sensors : sequence of (node, direction), optional
        The test's points, one per output channel (a direction may carry a sign, "-z"), for era.explain; ()
        when the test is matched later (:meth:`with_sensors`).

    Raises
    ------
    era.DataError
        For matrices that are not square, symmetric and finite, DOFs that do not match their rows, or parts that
        exceed the whole.

    Examples
    --------
    A chain of six masses and springs, fixed at its base: its frequencies are
    2 sqrt(k/m) sin((2j - 1) π / 26) / 2π (j = 1, 2, ...):

    >>> k = 1e5 * (2 * np.eye(6) - np.eye(6, k=1) - np.eye(6, k=-1))  # six 1 kg masses on springs of 100 kN/m
    >>> k[-1, -1] = 1e5  # the top is free; below node 1 the chain is fixed to ground
    >>> dofs = [(str(i + 1), "z") for i in range(6)]
    >>> model = era.MatrixModel(k, np.eye(6), dofs, sensors=dofs)
    >>> frequency_hz, shapes = model.modes(3)
    >>> print(np.round(frequency_hz, 2), shapes.shape)
    [12.13 35.69 57.18] (6, 3)
    >>> print(np.round(2 * np.sqrt(1e5) * np.sin((2 * np.arange(1, 4) - 1) * np.pi / 26) / (2 * np.pi), 2))
    [12.13 35.69 57.18]
    """

    stiffness: scipy.sparse.csr_matrix
    mass: scipy.sparse.csr_matrix
    dofs: tuple
    coordinates: dict | None = None
    parts: dict = field(default_factory=dict)
    part_masses: dict = field(default_factory=dict)
    name: str = "model"
    units: dict = field(default_factory=lambda: dict(UNIT_SYSTEMS["SI"]))
    sensors: tuple = ()

    def __init__(self, stiffness, mass, dofs, *, coordinates=None, parts=None, part_masses=None,
                 name: str = "model", units="SI", sensors=()):
        k = _square(stiffness, "the stiffness matrix")
        n = k.shape[0]
        m = _square(mass, "the mass matrix", n)
        dofs = _dofs(dofs, n)
        if np.any(m.diagonal() < 0) or np.any(k.diagonal() < 0):
            which = "mass" if np.any(m.diagonal() < 0) else "stiffness"
            i = int(np.argmin((m if which == "mass" else k).diagonal()))
            raise DataError(f"the {which} matrix has a negative diagonal entry at DOF {i + 1} {dofs[i]}: a "
                            f"{which} matrix has none; check its sign and units.")
        if not m.nnz or m.diagonal().max() <= 0:
            raise DataError("the mass matrix is zero: give the model's mass (a density, lumped masses).")
        set_ = object.__setattr__
        set_(self, "stiffness", k)
        set_(self, "mass", m)
        set_(self, "dofs", dofs)
        set_(self, "coordinates", _coordinates(coordinates, dofs))
        set_(self, "parts", _parts(parts, k, n, dofs, "parts", "stiffness"))
        set_(self, "part_masses", _parts(part_masses, m, n, dofs, "part_masses", "mass"))
        set_(self, "name", str(name))
        set_(self, "units", _units(units))
        points = tuple((str(n).strip(), str(d).strip().lower()) for n, d in (sensors or ()))
        self.at(points)      # each a free DOF, else an error naming it
        set_(self, "sensors", points)

    @property
    def n_dofs(self) -> int:
        return len(self.dofs)

    @property
    def nodes(self) -> tuple:
        """The nodes with free DOFs, in the order of their first DOF."""
        return tuple(dict.fromkeys(n for n, _ in self.dofs))

    @property
    def node_ids(self) -> tuple:
        """The nodes with free DOFs (as era.Frame.node_ids)."""
        return self.nodes

    @property
    def dof_index(self) -> dict:
        """{(node, direction): row}."""
        cache = self.__dict__.get("_index")
        if cache is None:
            cache = self.__dict__["_index"] = {d: i for i, d in enumerate(self.dofs)}
        return cache

    def index(self, node, direction) -> int:
        """The row of (node, direction); DataError when it is not a free DOF of the model.

        Parameters
        ----------
        node : str or int
            The node label.
        direction : str or int
            "x", "y", "z", "rx", "ry", "rz" (or 1-6).
        """
        key = (str(node).strip(), direction_of(direction))
        got = self.dof_index.get(key)
        if got is None:
            where = "no free DOF" if key[0] not in set(self.nodes) else f"no free {key[1]} DOF"
            raise DataError(f"node {key[0]} has {where} in the model {self.name}: give a node and direction of "
                            "its dofs (a supported DOF is not in the matrices).")
        return got

    def rows(self, direction: str) -> np.ndarray:
        """The rows of every free DOF along ``direction``.

        Parameters
        ----------
        direction : str
            "x", "y", "z", "rx", "ry" or "rz".
        """
        d = direction_of(direction)
        return np.array([i for i, (_, a) in enumerate(self.dofs) if a == d], dtype=int)

    def total_mass(self) -> float:
        """The mass that moves with a rigid translation, the largest over x, y, z (rᵀ M r, r = 1 on that
        direction's free DOFs), in the model's mass unit."""
        out = 0.0
        for d in TRANSLATIONS:
            r = np.zeros(self.n_dofs)
            r[self.rows(d)] = 1.0
            out = max(out, float(r @ (self.mass @ r)))
        return out

    def with_matrices(self, stiffness=None, mass=None) -> "MatrixModel":
        """The same DOFs, coordinates, parts and units with another stiffness and/or mass matrix.

        Parameters
        ----------
        stiffness : (n, n) sparse or dense matrix, optional
            The new stiffness (default this model's).
        mass : (n, n) sparse or dense matrix, optional
            The new mass (default this model's).
        """
        return MatrixModel(self.stiffness if stiffness is None else stiffness, self.mass if mass is None else mass,
                           self.dofs, coordinates=self.coordinates, parts=self.parts, part_masses=self.part_masses,
                           name=self.name, units=self.units, sensors=self.sensors)

    def with_sensors(self, sensors) -> "MatrixModel":
        """The same model seen at the test's points ((node, direction) per output channel).

        Parameters
        ----------
        sensors : sequence of (node, direction)
            One per output channel (a direction may carry a sign, "-z").
        """
        out = type(self).__new__(type(self))       # a reader's subclass (a Nastran deck's model) stays one
        out.__dict__.update({k: v for k, v in self.__dict__.items() if not k.startswith("_")})
        points = tuple((str(n).strip(), str(d).strip().lower()) for n, d in (sensors or ()))
        self.at(points)
        object.__setattr__(out, "sensors", points)
        return out

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """The lowest ``n_modes`` modes: frequencies (n,) Hz and mass-normalised shapes (n_dofs, n) (φᵀ M φ = 1
        in the model's units), from era.fem.eigen.sparse_modes; cached.

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        from ..fem.eigen import sparse_modes
        cache = self.__dict__.setdefault("_modes", {})
        got = next((v for k, v in cache.items() if k >= n_modes), None)
        if got is None:
            n = int(min(n_modes, self.n_dofs))
            got = cache[n] = sparse_modes(self.stiffness, self.mass, n)
        f, phi = got
        return np.asarray(f)[:n_modes].copy(), np.asarray(phi)[:, :n_modes].copy()

    def at(self, points) -> np.ndarray:
        """Rows of the given points ((node, direction) each; a direction may carry a sign, "-z"), and their
        signs: (rows (p,), signs (p,)).

        Parameters
        ----------
        points : sequence of (node, direction)
            A direction may carry a sign, "-z".
        """
        rows, signs = [], []
        for node, d in points:
            text = str(d).strip()
            sign = -1.0 if text.startswith("-") else 1.0
            rows.append(self.index(node, text.lstrip("+-")))
            signs.append(sign)
        return np.array(rows, dtype=int), np.array(signs)


def _dofs(dofs, n: int) -> tuple:
    try:
        pairs = [tuple(d) for d in dofs]
    except TypeError:
        raise DataError("dofs: give one (node, direction) pair per row of the matrices.") from None
    if len(pairs) != n:
        raise DataError(f"dofs lists {counted(len(pairs), 'DOF')} but the matrices are {n} × {n}: give one "
                        "(node, direction) per row, in the matrices' order.")
    out = []
    for i, p in enumerate(pairs):
        if len(p) != 2:
            raise DataError(f"dofs row {i + 1} is {p!r}; give (node, direction).")
        node = str(p[0]).strip()
        if not node:
            raise DataError(f"dofs row {i + 1} has an empty node label.")
        try:
            out.append((node, direction_of(p[1])))
        except DataError as exc:
            raise DataError(f"dofs row {i + 1} (node {node}): {exc}") from None
    seen: dict = {}
    for i, d in enumerate(out):
        if d in seen:
            raise DataError(f"dofs rows {seen[d] + 1} and {i + 1} are both node {d[0]} direction {d[1]}: each DOF "
                            "is one row. (CalculiX writes such rows for beams and shells, which it expands into "
                            "bricks: export a model of solids, springs and masses, or use Matrix Market.)")
        seen[d] = i
    return tuple(out)


def _coordinates(coordinates, dofs) -> dict | None:
    if coordinates is None:
        return None
    out = {}
    for node, xyz in dict(coordinates).items():
        v = np.asarray(xyz, dtype=float).reshape(-1)
        if v.size not in (2, 3) or not np.all(np.isfinite(v)):
            raise DataError(f"coordinates of node {node}: give (x, y, z) as three finite numbers, got {xyz!r}.")
        out[str(node).strip()] = tuple(float(x) for x in np.r_[v, 0.0][:3])
    missing = [n for n in dict.fromkeys(n for n, _ in dofs) if n not in out]
    if missing:
        raise DataError(f"coordinates give no position for {counted(len(missing), 'node')} with free DOFs "
                        f"({listed(missing[:5])}{', ...' if len(missing) > 5 else ''}): give every node, or none.")
    return out


def _parts(parts, whole, n: int, dofs, what: str, kind: str) -> dict:
    out = {}
    for name, p in dict(parts or {}).items():
        name = str(name).strip()
        if not name:
            raise DataError(f"{what}: a part has an empty name.")
        out[name] = _square(p, f"the {kind} matrix of part {name!r}", n)
    if out:
        total = sum(out.values()).diagonal()
        diag = whole.diagonal()
        over = total - diag > 1e-6 * np.maximum(np.abs(diag), np.abs(total).max() * 1e-12)
        if np.any(over):
            i = int(np.argmax(total - diag))
            raise DataError(f"{what}: at DOF {i + 1} {dofs[i]} the parts' {kind} adds up to {total[i]:.4g}, more "
                            f"than the whole model's {diag[i]:.4g}: a part is larger than the whole. Give each "
                            f"part's own {kind} matrix (its elements only), over the model's DOFs.")
    return out


def _units(units) -> dict:
    if isinstance(units, str):
        if units not in UNIT_SYSTEMS:
            raise DataError(f"units {units!r}: give one of {listed(UNIT_SYSTEMS, quote=True)} or "
                            "{'mass': ..., 'force': ..., 'length': ...}.")
        return dict(UNIT_SYSTEMS[units])
    u = dict(units)
    if set(u) != {"mass", "force", "length"}:
        raise DataError("units: give {'mass': ..., 'force': ..., 'length': ...} (time is in seconds).")
    return {k: str(v) for k, v in u.items()}
