"""The user's description of a frame-like structure and its validation: :class:`Frame` (SI units).

A Frame is nodes, straight members with a section each (era/structure/sections.py), supports, known lumped masses,
the sensors in the data's channel order and, optionally, gravity. ``Frame.modes(n)`` meshes the members and returns
the lowest modes at the sensors, mass-normalised, like ``nasa_grid().modes``: the FE solution is
era/fem/solution.py's (era.fem.space.converged_mesh), which the Frame caches.

Local axes of a member: x from its first node to its second; z along the member's orientation vector (the optional
4th item of a member; default global +Z, or +X for a vertical member) made normal to x; y = z × x. So by default a
horizontal member's local z is vertical and its local y horizontal. ``Section.iy`` is about local y (bending that
moves the member along z), ``Section.iz`` about local z; a rectangle's ``depth`` runs along local z.

The file format (JSON or TOML) is era/structure/file.py's.

A section is given by its constants (``ip``, the polar moment, defaults to iy + iz) or by ``shape`` (rectangle,
circle, tube, square_tube) with that helper's keywords. A support is "fixed" (all six DOFs), "pinned" (three
translations) or a table of springs to ground: kx, ky, kz (N/m) and rx, ry, rz (N·m/rad), each a number or
"fixed"; ``cable``: L (m) hangs the node from a cable of length L along gravity (held along gravity; the pendulum
stiffness T/L on the two other translations, T the cable's tension from the self-weight; needs gravity along a
global axis).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field
from collections.abc import Mapping
from types import MappingProxyType

import numpy as np

from ..errors import DataError
from ..fem import solution, space
from ..fem.solution import SUPPORT_KEYS
from ..words import counted
from .file import frame_from_dict, frame_to_dict, load_frame, save_frame
from .sections import Section

DIRECTIONS = {s + a: (-1.0 if s else 1.0) * np.eye(3)[i] for i, a in enumerate("xyz") for s in ("", "-")}
UNITS_M = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "ft": 0.3048, "in": 0.0254, "inch": 0.0254, "feet": 0.3048}


def _support(node: str, spec, gravity) -> dict:
    """Canonical support: {key: stiffness or inf} over SUPPORT_KEYS, plus "cable": length (m)."""
    if spec == "fixed":
        return dict.fromkeys(SUPPORT_KEYS, math.inf)
    if spec == "pinned":
        return dict.fromkeys(SUPPORT_KEYS[:3], math.inf)
    if not isinstance(spec, Mapping) or not spec:
        raise DataError(f"Frame: support at node {node} must be 'fixed', 'pinned' or a table of springs "
                        f"{SUPPORT_KEYS} (N/m, N·m/rad; a value may be 'fixed') and/or cable (m), got {spec!r}.")
    out = {}
    for key, value in spec.items():
        if key not in SUPPORT_KEYS + ("cable",):
            raise DataError(f"Frame: support at node {node}: unknown key {key!r}; use {SUPPORT_KEYS} or cable.")
        v = math.inf if value == "fixed" and key != "cable" else value
        ok = isinstance(v, numbers.Real) and not isinstance(v, bool) and v >= 0
        if not ok or (key == "cable" and not 0 < v < math.inf):
            raise DataError(f"Frame: support at node {node}: {key} must be a stiffness ≥ 0 or 'fixed' "
                            f"(cable: a length > 0 in m), got {value!r}.")
        out[key] = float(v)
    if "cable" in out and (gravity is None or np.count_nonzero(gravity) != 1):
        raise DataError(f"Frame: the cable at node {node} needs gravity along a global axis, e.g. (0, 0, -9.81).")
    return out


def _positive(v, what: str, unit: str, zero: bool = False) -> float:
    ok = isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v) and (v >= 0 if zero else v > 0)
    if not ok:
        raise DataError(f"Frame: {what} must be a number of {unit} {'≥' if zero else '>'} 0, got {v!r}.")
    return float(v)


def _vector(x) -> np.ndarray:
    """x as a finite (3,) float array, or NaNs when it is not three numbers."""
    try:
        v = np.asarray(x, float)
    except (TypeError, ValueError):
        return np.full(3, np.nan)
    return v if v.shape == (3,) else np.full(3, np.nan)


def _direction(node: str, d):
    if isinstance(d, str):
        if d.strip().lower() not in DIRECTIONS:
            raise DataError(f"Frame: sensor at node {node}: direction {d!r} is not one of {sorted(DIRECTIONS)}.")
        return d.strip().lower()
    v = _vector(d)
    if not (np.all(np.isfinite(v)) and np.linalg.norm(v) > 0):
        raise DataError(f"Frame: sensor at node {node}: direction {d!r} is not x, y, z, -x, ... or a 3-vector.")
    return tuple(float(x) for x in v / np.linalg.norm(v))


@dataclass(frozen=True, eq=False)
class Frame:
    """A 3-D frame of straight Euler-Bernoulli members, SI units (see the module docstring for every field's form).

    Parameters
    ----------
    nodes : mapping
        {id: (x, y, z)} in m.
    members : sequence of tuple
        (node i, node j, section name[, local-z vector]) per member.
    sections : mapping
        {name: Section}.
    supports : mapping, optional
        {node: "fixed" | "pinned" | {kx..rz: N/m or N·m/rad or "fixed", cable: m}}.
    masses : mapping, optional
        {node: kg}, lumped masses.
    sensors : sequence of tuple, optional
        (node, "x" | "-x" | ... | (dx, dy, dz)) per output channel, in the data's channel order.
    gravity : (3,) array_like, optional
        m/s², or None; with it, the geometric stiffness of the self-weight's axial forces.
    elements_per_member : int or sequence of int, optional
        None (default) for the automatic mesh (era.fem.space.converged_mesh: the lowest max(10, n) frequencies
        converged to 0.1 %), a count for every member, or one count per member (e.g. ``element_counts()`` of a
        nominal model, to keep its mesh in variants).
    joint_springs : mapping, optional
        {node: N·m/rad}: a semi-rigid beam-to-column connection at the node (docs/effects.md): every beam end
        there (a member not along the vertical, -gravity or else +Z) hangs on a rotational spring about the
        horizontal axis normal to the beam (bending in the vertical plane that contains it), its other five DOFs
        rigid; columns stay continuous.
    added_mass_per_length : mapping, optional
        {section name: kg/m}: non-structural mass (it weighs too, and has no rotary inertia).

    Raises
    ------
    era.DataError
        For a malformed field (an unknown node, section or support key, a negative stiffness), saying what to change.

    Examples
    --------
    A 1 m steel strip (50 × 10 mm) clamped at one end: its first frequency is 1.8751² / 2π · sqrt(EI / (m L⁴)):

    >>> strip = era.Section.rectangle(0.05, 0.01)
    >>> frame = era.Frame(nodes={"1": (0, 0, 0), "2": (0.5, 0, 0), "3": (1, 0, 0)},
    ...                   members=[("1", "2", "strip"), ("2", "3", "strip")], sections={"strip": strip},
    ...                   supports={"1": "fixed"}, sensors=[("2", "z"), ("3", "z")])
    >>> frequency_hz, shapes = frame.modes(3)
    >>> print(np.round(frequency_hz, 2), shapes.shape)
    [ 8.15 40.77 51.1 ]  (2, 3)
    >>> print(f"{1.8751**2 / (2 * np.pi) * np.sqrt(strip.e * strip.iy / strip.mass_per_length):.2f}")
    8.15
    """

    nodes: Mapping
    members: tuple
    sections: Mapping
    supports: Mapping = field(default_factory=dict)
    masses: Mapping = field(default_factory=dict)
    sensors: tuple = ()
    gravity: tuple | None = None
    elements_per_member: int | tuple | None = None
    joint_springs: Mapping = field(default_factory=dict)
    added_mass_per_length: Mapping = field(default_factory=dict)

    def __post_init__(self):
        put = lambda name, value: object.__setattr__(self, name, value)   # noqa: E731
        nodes = {}
        for k, xyz in dict(self.nodes).items():
            v = _vector(xyz)
            if not np.all(np.isfinite(v)):
                raise DataError(f"Frame: node {k} must have three finite coordinates (x, y, z) in m, got {xyz!r}.")
            nodes[str(k)] = tuple(float(x) for x in v)
        if not nodes:
            raise DataError("Frame: no nodes.")
        put("nodes", MappingProxyType(nodes))
        sections = {str(k): v if isinstance(v, Section) else Section.from_dict(v)
                    for k, v in dict(self.sections).items()}
        put("sections", MappingProxyType(sections))
        g = None if self.gravity is None else np.asarray(self.gravity, float)
        if g is not None and not (g.shape == (3,) and np.all(np.isfinite(g)) and np.any(g != 0)):
            raise DataError(f"Frame: gravity must be None or a non-zero (gx, gy, gz) in m/s², got {self.gravity!r}.")
        put("gravity", None if g is None else tuple(float(x) for x in g))
        members, size = [], max(1.0, float(np.abs(np.array(list(nodes.values()))).max()))
        for k, m in enumerate(self.members):
            if not isinstance(m, (list, tuple)) or len(m) not in (3, 4):
                raise DataError(f"Frame: member {k} must be (node i, node j, section[, orientation]), got {m!r}.")
            i, j, sec = str(m[0]), str(m[1]), str(m[2])
            for n in (i, j):
                if n not in nodes:
                    raise DataError(f"Frame: member {k} ({i}-{j}) goes to node {n}, which is not in nodes.")
            if sec not in sections:
                raise DataError(f"Frame: member {k} ({i}-{j}) has unknown section {sec!r}; known: {sorted(sections)}.")
            axis = np.subtract(nodes[j], nodes[i])
            length = float(np.linalg.norm(axis))
            if length <= 1e-9 * size:
                raise DataError(f"Frame: member {k} ({i}-{j}) has zero length: its nodes coincide.")
            orient = None if len(m) == 3 or m[3] is None else _vector(m[3])
            if orient is not None:
                if not np.all(np.isfinite(orient)) or \
                        np.linalg.norm(np.cross(orient, axis / length)) < 1e-6 * np.linalg.norm(orient):
                    raise DataError(f"Frame: member {k} ({i}-{j}): orientation {m[3]!r} must be a 3-vector not "
                                    "parallel to the member.")
                orient = tuple(float(x) for x in orient)
            members.append((i, j, sec, orient))
        if not members:
            raise DataError("Frame: no members.")
        put("members", tuple(members))
        used = {n for m in members for n in m[:2]}
        if len(used) < len(nodes):
            lonely = sorted(set(nodes) - used)
            raise DataError(f"Frame: node {lonely[0]} is on no member: add a member or remove the node "
                            f"({counted(len(lonely), 'such node')}).")
        supports = {self._known(n, "support"): MappingProxyType(_support(str(n), s, self.gravity))
                    for n, s in dict(self.supports).items()}
        put("supports", MappingProxyType(supports))
        masses = {}
        for n, kg in dict(self.masses).items():
            if isinstance(kg, bool) or not isinstance(kg, numbers.Real) or not 0 <= kg < math.inf:
                raise DataError(f"Frame: mass at node {n} must be a number of kg ≥ 0, got {kg!r}.")
            masses[self._known(n, "mass")] = float(kg)
        put("masses", MappingProxyType(masses))
        sensors = []
        for s in self.sensors:
            if not isinstance(s, (list, tuple)) or len(s) != 2:
                raise DataError(f"Frame: a sensor must be (node, direction), got {s!r}.")
            sensors.append((self._known(s[0], "sensor"), _direction(str(s[0]), s[1])))
        put("sensors", tuple(sensors))
        e = self.elements_per_member
        if e is not None:
            single = isinstance(e, (int, np.integer)) and not isinstance(e, bool)
            counts = [e] if single else list(e) if isinstance(e, (list, tuple)) else []
            valid = all(isinstance(c, (int, np.integer)) and not isinstance(c, bool) and c >= 1 for c in counts)
            if not (counts and valid and (single or len(counts) == len(members))):
                raise DataError(f"Frame: elements_per_member must be None (automatic), an integer ≥ 1 or one such "
                                f"integer per member ({len(members)}), got {e!r}.")
            put("elements_per_member", int(e) if single else tuple(int(c) for c in counts))
        put("joint_springs", MappingProxyType({self._known(n, "joint spring"): _positive(k, f"joint spring at node {n}",
                                                                                        "N·m/rad")
                                               for n, k in dict(self.joint_springs).items()}))
        extra = {}
        for name, kg in dict(self.added_mass_per_length).items():
            if str(name) not in sections:
                raise DataError(f"Frame: added mass per length for unknown section {name!r}; "
                                f"known: {sorted(sections)}.")
            extra[str(name)] = _positive(kg, f"added mass per length of section {name}", "kg/m", zero=True)
        put("added_mass_per_length", MappingProxyType(extra))

    def _known(self, node, what: str) -> str:
        if str(node) not in self.nodes:
            raise DataError(f"Frame: {what} at node {node}, which is not in nodes.")
        return str(node)

    @property
    def node_ids(self) -> tuple:
        """The node ids in order: the rows of :meth:`node_modes`."""
        return tuple(self.nodes)

    @property
    def sensor_directions(self) -> np.ndarray:
        """(p, 3) unit vector each sensor measures along, global axes."""
        return np.array([DIRECTIONS[d] if isinstance(d, str) else d for _, d in self.sensors], float).reshape(-1, 3)

    def space_frame(self) -> space.SpaceFrame:
        """The numerics' arrays, one element per member (era.fem.solution.space_frame)."""
        return solution.space_frame(self)

    @property
    def n_rigid_modes(self) -> int:
        """6 when the frame is free (no support, spring or cable, and no gravity: a structure hung on soft cords
        the model leaves out): its lowest six modes are the rigid-body motions at 0 Hz; else 0. explain and the
        app's comparison leave them out: no measured mode is paired with a rigid-body motion."""
        got = self.__dict__.get("_n_rigid_modes")
        if got is None:
            got = self.__dict__["_n_rigid_modes"] = 0 if (
                self.gravity is not None or self.space_frame().supported) else 6
        return got

    @property
    def vertical(self) -> np.ndarray:
        """(3,) unit vector up: against gravity when given, else +Z."""
        return np.array([0.0, 0.0, 1.0]) if self.gravity is None else -np.array(self.gravity) / np.linalg.norm(
            self.gravity)

    def beam_ends(self, node: str) -> list:
        """(member index, 0 | 1) of every beam end (member not along the vertical) at ``node``."""
        ends = self.__dict__.get("_beam_ends")
        if ends is None:     # once per frame: explain asks for every node's, and for each candidate joint
            xyz = np.array([np.subtract(self.nodes[j], self.nodes[i]) for i, j, *_ in self.members])
            unit = xyz / np.linalg.norm(xyz, axis=1)[:, None]
            beam = np.linalg.norm(np.cross(unit, self.vertical), axis=1) > 1e-6
            ends = self.__dict__["_beam_ends"] = {}
            for k in np.flatnonzero(beam):
                for side, n in enumerate(self.members[k][:2]):
                    ends.setdefault(n, []).append((int(k), side))
        return list(ends.get(node, []))

    def solution(self, n_modes: int = 10) -> tuple[space.SpaceFrame, space.SpaceModes]:
        """The mesh and its lowest modes (cached; at least n_modes), signs fixed by a generic reference vector
        (era.fem.solution.solve).

        The automatic mesh is chosen for the lowest max(10, n_modes) modes, so modes(3) is a prefix of modes(10);
        a fixed ``elements_per_member`` solves for exactly the modes asked (or reuses a larger solve)."""
        if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or n_modes < 1:
            raise DataError(f"Frame: the number of modes must be a positive integer, got {n_modes!r}.")
        cache = self.__dict__.setdefault("_solutions", {})
        if self.elements_per_member is None:
            target = max(10, int(n_modes))
        else:
            target = min((k for k in cache if k >= n_modes), default=int(n_modes))
        if target not in cache:
            cache[target] = solution.solve(self, target)
        return cache[target]

    def ritz_modes(self, reference: "Frame", n_basis: int = 30) -> tuple[np.ndarray, np.ndarray] | None:
        """This frame's modes in the span of ``reference``'s lowest ``n_basis`` modes (Rayleigh-Ritz, for screening
        many places of a local change): frequencies (r,) Hz and translations (n_nodes, 3, r) as :meth:`node_modes`,
        or None when the two are not meshed alike (era.fem.solution.ritz_modes)."""
        return solution.ritz_modes(self, reference, n_basis)

    def element_counts(self, n_modes: int = 10) -> tuple:
        """Elements of each member in the mesh that :meth:`modes` (n_modes) uses, in member order.

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        return solution.element_counts(self, n_modes)

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised translations (n_nodes, 3, n) of every node (rows in
        ``node_ids`` order, columns x, y, z), 1/√kg.

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        return solution.node_modes(self, n_modes)

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised shapes at the sensors (n_sensors, n), 1/√kg, rows in sensor
        order (each sensor's node translation along its direction).

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        f, u = self.node_modes(n_modes)
        return f, self.at_sensors(u)

    def at_sensors(self, u: np.ndarray) -> np.ndarray:
        """The sensors' shapes (..., n_sensors, r) from node translations ``u`` (..., n_nodes, 3, r) in node order,
        each sensor's node translation along its direction."""
        index = {n: k for k, n in enumerate(self.nodes)}
        rows = [index[n] for n, _ in self.sensors]
        if not rows:
            return np.zeros(u.shape[:-3] + (0, u.shape[-1]))
        return np.einsum("sc,...scn->...sn", self.sensor_directions, u[..., rows, :, :])

    @property
    def total_mass_kg(self) -> float:
        """Members plus lumped masses, kg."""
        lengths = [np.linalg.norm(np.subtract(self.nodes[j], self.nodes[i])) for i, j, *_ in self.members]
        return float(sum(L * (self.sections[m[2]].mass_per_length + self.added_mass_per_length.get(m[2], 0.0))
                         for L, m in zip(lengths, self.members))
                     + sum(self.masses.values()))

    def __reduce__(self):
        """Pickled as its file format (to_dict), rebuilt (and checked again) by from_dict: the mapping fields are
        read-only proxies, which do not pickle, and the cached solutions are left behind (process pools)."""
        return self.__class__.from_dict, (self.to_dict(),)

    def to_dict(self) -> dict:
        """The file format of era/structure/file.py (JSON-ready: no inf, no numpy types)."""
        return frame_to_dict(self)

    @classmethod
    def from_dict(cls, d: dict) -> "Frame":
        """A Frame from the file format (as read from JSON or TOML); unknown keys are refused.

        Parameters
        ----------
        d : dict
            The file format of era/structure/file.py.
        """
        return frame_from_dict(d, cls)

    def save(self, path) -> None:
        """Write the model as JSON (era/structure/file.py).

        Parameters
        ----------
        path : str or os.PathLike
            The JSON file to write.
        """
        save_frame(self, path)

    @classmethod
    def load(cls, path) -> "Frame":
        """Read a model from JSON, or from TOML when the name ends in .toml.

        Parameters
        ----------
        path : str or os.PathLike
            A JSON file, or a TOML file when the name ends in .toml.
        """
        return load_frame(path, cls)

    @classmethod
    def from_geometry(cls, geometry, section: Section, supports: dict | None = None, masses: dict | None = None,
                      gravity=None, elements_per_member: int | None = None) -> "Frame":
        """Members from an era.Geometry's trace lines, all of ``section``; sensors from its channels.

        Node ids are the geometry's labels as strings; coordinates are converted to metres from ``units`` (m, mm,
        cm, ft, in); repeated trace lines count once and nodes on no trace line are left out. Each channel becomes
        a sensor at its node along its direction ("x", "-z", ... when along an axis); a channel with no node or
        direction, or at a node on no trace line, is an error: the sensors must follow the data's channels.

        Parameters
        ----------
        geometry : Geometry
            The test's nodes, trace lines and channels.
        section : Section
            The section of every member.
        supports : dict, optional
            {node: support} as :class:`Frame`'s, node ids as strings.
        masses : dict, optional
            {node: kg}.
        gravity : (3,) array_like, optional
            m/s², or None.
        elements_per_member : int, optional
            As :class:`Frame`'s (None: the automatic mesh).
        """
        scale = UNITS_M.get(str(geometry.units).strip().lower())
        if scale is None:
            raise DataError(f"Frame.from_geometry: unknown length unit {geometry.units!r}; known: {sorted(UNITS_M)}.")
        ids = [str(i) for i in geometry.node_ids]
        edges = {tuple(sorted(map(int, e))) for e in geometry.edges if e[0] != e[1]}
        if not edges:
            raise DataError("Frame.from_geometry: the geometry has no trace lines to make members of.")
        used = sorted({i for e in edges for i in e})
        nodes = {ids[i]: tuple(float(x) * scale for x in geometry.coordinates[i]) for i in used}
        sensors = []
        for ch, (node, direction) in enumerate(zip(geometry.channel_nodes, geometry.channel_directions)):
            if node < 0 or not np.any(direction):
                raise DataError(f"Frame.from_geometry: channel {ch + 1} has no node or direction in the geometry.")
            if ids[node] not in nodes:
                raise DataError(f"Frame.from_geometry: channel {ch + 1} measures node {ids[node]}, which is on no "
                                "trace line.")
            axis = [k for k, v in DIRECTIONS.items() if np.allclose(v, direction, atol=1e-9)]
            sensors.append((ids[node], axis[0] if axis else tuple(direction)))
        return cls(nodes=nodes, members=[(ids[a], ids[b], "section") for a, b in sorted(edges)],
                   sections={"section": section}, supports=supports or {}, masses=masses or {}, sensors=sensors,
                   gravity=gravity, elements_per_member=elements_per_member)
