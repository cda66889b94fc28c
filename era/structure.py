"""The user's description of a frame-like structure: :class:`Section`, :class:`Frame` (SI units).

A Frame is nodes, straight members with a section each, supports, known lumped masses, the sensors in the data's
channel order and, optionally, gravity. ``Frame.modes(n)`` meshes the members (era.fem.space.converged_mesh) and
returns the lowest modes at the sensors, mass-normalised, like ``nasa_grid().modes``.

Local axes of a member: x from its first node to its second; z along the member's orientation vector (the optional
4th item of a member; default global +Z, or +X for a vertical member) made normal to x; y = z × x. So by default a
horizontal member's local z is vertical and its local y horizontal. ``Section.iy`` is about local y (bending that
moves the member along z), ``Section.iz`` about local z; a rectangle's ``depth`` runs along local z.

The file format (JSON or TOML) is era/io/frame_file.py's.

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
from dataclasses import dataclass, field, fields
from collections.abc import Mapping
from types import MappingProxyType

import numpy as np
import scipy.linalg

from .errors import DataError
from .fem import space

MATERIALS = {   # nominal handbook values: E (Pa), Poisson's ratio, density (kg/m³)
    "steel": (200e9, 0.29, 7850.0), "stainless_steel": (193e9, 0.29, 8000.0),
    "aluminium": (68.9e9, 0.33, 2700.0), "aluminum": (68.9e9, 0.33, 2700.0), "titanium": (114e9, 0.34, 4430.0),
}
SUPPORT_KEYS = ("kx", "ky", "kz", "rx", "ry", "rz")
DIRECTIONS = {s + a: (-1.0 if s else 1.0) * np.eye(3)[i] for i, a in enumerate("xyz") for s in ("", "-")}
UNITS_M = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "ft": 0.3048, "in": 0.0254, "inch": 0.0254, "feet": 0.3048}
_SIGN_SEED = (1.7, 0.3)


def _material(material, e, g, density) -> dict:
    if material not in MATERIALS:
        raise DataError(f"Section: unknown material {material!r}; known: {sorted(MATERIALS)} (or give e, g, density).")
    e0, nu, rho0 = MATERIALS[material]
    e = e0 if e is None else e
    return dict(e=e, g=e / (2 * (1 + nu)) if g is None else g, density=rho0 if density is None else density)


@dataclass(frozen=True)
class Section:
    """Section and material constants of a member, SI units.

    area A (m²); iy, iz second moments about the local y and z axes (m⁴); j St-Venant torsion constant (m⁴);
    e, g Young's and shear moduli (Pa); density ρ (kg/m³); ip polar moment for the torsional inertia ρ I_p and the
    Wagner term (m⁴, default iy + iz).
    """

    area: float
    iy: float
    iz: float
    j: float
    e: float
    g: float
    density: float
    ip: float | None = None

    def __post_init__(self):
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name == "ip" and v is None:
                v = float(self.iy) + float(self.iz)
            try:
                v = float(v)
            except (TypeError, ValueError):
                raise DataError(f"Section: {f.name} must be a number, got {v!r}.") from None
            if not (math.isfinite(v) and v > 0):
                raise DataError(f"Section: {f.name} must be positive and finite, got {v!r}.")
            object.__setattr__(self, f.name, v)

    @property
    def mass_per_length(self) -> float:
        """ρ A, kg/m."""
        return self.density * self.area

    @classmethod
    def rectangle(cls, width: float, depth: float, material: str = "steel", *, e=None, g=None, density=None):
        """Solid width (along local y) × depth (along local z), m. J of a solid rectangle from Roark's Formulas for
        Stress and Strain (torsion table): J = a b³ (1/3 - 0.21 (b/a)(1 - b⁴/(12 a⁴))), a ≥ b the sides, within
        0.5 %."""
        a, b = max(width, depth), min(width, depth)
        j = a * b**3 * (1 / 3 - 0.21 * b / a * (1 - b**4 / (12 * a**4)))
        return cls(area=width * depth, iy=width * depth**3 / 12, iz=depth * width**3 / 12, j=j,
                   **_material(material, e, g, density))

    @classmethod
    def circle(cls, diameter: float, material: str = "steel", *, e=None, g=None, density=None):
        """Solid round bar of this diameter (m): I = π d⁴/64, J = I_p = 2I."""
        i = math.pi * diameter**4 / 64
        return cls(area=math.pi * diameter**2 / 4, iy=i, iz=i, j=2 * i, **_material(material, e, g, density))

    @classmethod
    def tube(cls, diameter: float, wall: float, material: str = "steel", *, e=None, g=None, density=None):
        """Round tube, outer diameter and wall thickness (m): I = π (D⁴ - d⁴)/64, J = I_p = 2I."""
        d = diameter - 2 * wall
        i = math.pi * (diameter**4 - d**4) / 64
        return cls(area=math.pi * (diameter**2 - d**2) / 4, iy=i, iz=i, j=2 * i, **_material(material, e, g, density))

    @classmethod
    def square_tube(cls, width: float, wall: float, material: str = "steel", *, e=None, g=None, density=None):
        """Square hollow section, outer width and wall (m): I = (b⁴ - (b-2t)⁴)/12; J = t (b-t)³ (Bredt, thin
        wall)."""
        b, t = width, wall
        i = (b**4 - (b - 2 * t) ** 4) / 12
        return cls(area=b**2 - (b - 2 * t) ** 2, iy=i, iz=i, j=t * (b - t) ** 3, **_material(material, e, g, density))

    @classmethod
    def from_dict(cls, d: dict) -> "Section":
        """From the constants, or from {"shape": "rectangle" | "circle" | "tube" | "square_tube", ...keywords}."""
        d = dict(d)
        shape = d.pop("shape", None)
        try:
            if shape is None:
                return cls(**d)
            if shape not in ("rectangle", "circle", "tube", "square_tube"):
                raise DataError(f"Section: unknown shape {shape!r}; known: rectangle, circle, tube, square_tube.")
            return getattr(cls, shape)(**d)
        except TypeError as exc:
            raise DataError(f"Section: {exc}") from None


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
    """A 3-D frame of straight Euler-Bernoulli members (see the module docstring for every field's form).

    nodes {id: (x, y, z) m}; members [(node i, node j, section name[, local-z vector])]; sections {name: Section};
    supports {node: "fixed" | "pinned" | {kx..rz: N/m or N·m/rad or "fixed", cable: m}}; masses {node: kg};
    sensors [(node, "x" | "-x" | ... | (dx, dy, dz))] in the data's channel order; gravity (3,) m/s² or None (with
    it, the geometric stiffness of the self-weight's axial forces); elements_per_member: None for the automatic
    mesh (era.fem.space.converged_mesh: the lowest max(10, n) frequencies converged to 0.1 %), a count for every
    member, or one count per member (e.g. ``element_counts()`` of a nominal model, to keep its mesh in variants).
    joint_springs {node: N·m/rad}: a semi-rigid beam-to-column connection at the node (docs/effects.md): every
    beam end there (a member not along the vertical, -gravity or else +Z) hangs on a rotational spring about the
    horizontal axis normal to the beam (bending in the vertical plane that contains it), its other five DOFs
    rigid; columns stay continuous. added_mass_per_length {section name: kg/m}: non-structural mass (it weighs
    too, and has no rotary inertia).
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
                            f"({len(lonely)} such node(s)).")
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
        """The numerics' arrays, one element per member (era.fem.space.SpaceFrame)."""
        index = {n: k for k, n in enumerate(self.nodes)}
        xyz = np.array(list(self.nodes.values()))
        ends = np.array([[index[m[0]], index[m[1]]] for m in self.members])
        orient = np.array([m[3] if m[3] is not None else (np.nan,) * 3 for m in self.members])
        default = np.isnan(orient[:, 0])
        orient[default] = space.beam3d.default_orientation(xyz[ends[default, 1]] - xyz[ends[default, 0]])
        secs = [self.sections[m[2]] for m in self.members]
        prop = lambda f: np.array([f(s) for s in secs])   # noqa: E731
        n = len(self.nodes)
        restrained, springs, cable, mass = np.zeros((n, 6), bool), np.zeros((n, 6)), np.zeros(n), np.zeros(n)
        for node, spec in self.supports.items():
            k = index[node]
            for a, key in enumerate(SUPPORT_KEYS):
                v = spec.get(key, 0.0)
                restrained[k, a] |= math.isinf(v)
                springs[k, a] = 0.0 if math.isinf(v) else v
            if "cable" in spec:
                cable[k] = spec["cable"]
                restrained[k, int(np.flatnonzero(self.gravity)[0])] = True
        for node, kg in self.masses.items():
            mass[index[node]] = kg
        end_k, end_axes = self._end_springs(xyz, ends)
        return space.SpaceFrame(
            coords=xyz, elements=ends, orientation=orient, member=np.arange(len(self.members)),
            EA=prop(lambda s: s.e * s.area), GJ=prop(lambda s: s.g * s.j), EIy=prop(lambda s: s.e * s.iy),
            EIz=prop(lambda s: s.e * s.iz),
            m=prop(lambda s: s.mass_per_length) + np.array([self.added_mass_per_length.get(m[2], 0.0)
                                                             for m in self.members]),
            rho_ip=prop(lambda s: s.density * s.ip),
            r2=prop(lambda s: s.ip / s.area), node_mass=mass, restrained=restrained, springs=springs, cable_m=cable,
            n_user=n, names=tuple(self.nodes), end_springs=end_k, end_axes=end_axes)

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

    def _end_springs(self, xyz, ends):
        """(e, 2) end springs (inf = rigid) and (e, 2, 3) their axes, from joint_springs; None when all rigid."""
        if not self.joint_springs:
            return None, None
        k = np.full(ends.shape, np.inf)
        axes = np.zeros(ends.shape + (3,))
        for node, stiffness in self.joint_springs.items():
            for member, side in self.beam_ends(node):
                d = xyz[ends[member, 1]] - xyz[ends[member, 0]]
                normal = np.cross(self.vertical, d)
                k[member, side] = stiffness
                axes[member, side] = normal / np.linalg.norm(normal)
        return k, axes

    def solution(self, n_modes: int = 10) -> tuple[space.SpaceFrame, space.SpaceModes]:
        """The mesh and its lowest modes (cached; at least n_modes), signs fixed by a generic reference vector.

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
            frame = self.space_frame()
            g = None if self.gravity is None else np.array(self.gravity)
            if self.elements_per_member is None:
                mesh, result = space.converged_mesh(frame, target, g)
            else:
                mesh = space.subdivide(frame, np.broadcast_to(self.elements_per_member, len(self.members)))
                result = space.solve_modes(mesh, target, g)
            u = result.shapes[:frame.n_user, :3]
            ref = 1.0 + np.sin(_SIGN_SEED[0] * np.arange(u.shape[0] * 3) + _SIGN_SEED[1])
            sign = np.where(ref @ u.reshape(-1, target) < 0, -1.0, 1.0)
            cache[target] = (mesh, space.SpaceModes(result.frequency_hz, result.shapes * sign, result.axial_force))
        return cache[target]

    def ritz_modes(self, reference: "Frame", n_basis: int = 30) -> tuple[np.ndarray, np.ndarray] | None:
        """This frame's modes in the span of ``reference``'s lowest ``n_basis`` modes (Rayleigh-Ritz: one small
        dense eigenproblem instead of a sparse solve), for screening many places of a local change. Frequencies
        (r,) Hz and translations (n_nodes, 3, r) as :meth:`node_modes`; frequencies are bounds from above, within
        0.5 % for a local mass or stiffness change. None unless both frames are meshed the same (a fixed
        ``elements_per_member``, the same joint springs: a spring adds nodes) and this frame holds every DOF the
        reference holds (a flexible support needs shapes that bend at the base: solve it)."""
        counts = self.elements_per_member
        if (counts is None or counts != reference.elements_per_member
                or set(self.joint_springs) != set(reference.joint_springs)):
            return None
        ref_mesh, ref = reference.solution(n_basis)
        mesh = space.subdivide(self.space_frame(), np.broadcast_to(counts, len(self.members)))
        if mesh.n_nodes != ref_mesh.n_nodes:
            return None
        K, M, _ = space.system(mesh, None if self.gravity is None else np.array(self.gravity))
        free = ~mesh.restrained.ravel()
        if np.any(free & ref_mesh.restrained.ravel()):  # a support made flexible: the reference's shapes, all
            return None                                   # still at its base, cannot bend there; solve instead
        basis = ref.shapes.reshape(6 * mesh.n_nodes, -1)[:, :n_basis].copy()
        basis[~free] = 0.0  # what this frame holds does not move
        b = basis[free]
        k = b.T @ (K[free][:, free] @ b)
        m = b.T @ (M[free][:, free] @ b)
        lam, v = scipy.linalg.eigh(0.5 * (k + k.T), 0.5 * (m + m.T), check_finite=False)
        shapes = (basis @ v).reshape(mesh.n_nodes, 6, -1)
        return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi), shapes[:len(self.nodes), :3]

    def element_counts(self, n_modes: int = 10) -> tuple:
        """Elements of each member in the mesh that :meth:`modes` (n_modes) uses, in member order."""
        mesh, _ = self.solution(n_modes)
        return tuple(int(c) for c in np.bincount(mesh.member, minlength=len(self.members)))

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised translations (n_nodes, 3, n) of every node (rows in
        ``node_ids`` order, columns x, y, z), 1/√kg."""
        _, result = self.solution(n_modes)
        u = result.shapes[:len(self.nodes), :3, :n_modes].copy()
        # the eigensolver's round-off (~1e-16 of the mode) where the motion is zero (a planar frame's out-of-plane
        # modes at its nodes' in-plane DOFs) made exact: a unit-normalised sensor shape of it would be random
        u[np.abs(u) < 1e-10 * np.abs(u).max(axis=(0, 1))] = 0.0
        return result.frequency_hz[:n_modes].copy(), u

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised shapes at the sensors (n_sensors, n), 1/√kg, rows in sensor
        order (each sensor's node translation along its direction)."""
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
        """The file format of era/io/frame_file.py (JSON-ready: no inf, no numpy types)."""
        from .io.frame_file import frame_to_dict
        return frame_to_dict(self)

    @classmethod
    def from_dict(cls, d: dict) -> "Frame":
        """A Frame from the file format (as read from JSON or TOML); unknown keys are refused."""
        from .io.frame_file import frame_from_dict
        return frame_from_dict(d, cls)

    def save(self, path) -> None:
        """Write the model as JSON (era/io/frame_file.py)."""
        from .io.frame_file import save_frame
        save_frame(self, path)

    @classmethod
    def load(cls, path) -> "Frame":
        """Read a model from JSON, or from TOML when the name ends in .toml."""
        from .io.frame_file import load_frame
        return load_frame(path, cls)

    @classmethod
    def from_geometry(cls, geometry, section: Section, supports: dict | None = None, masses: dict | None = None,
                      gravity=None, elements_per_member: int | None = None) -> "Frame":
        """Members from an era.Geometry's trace lines, all of ``section``; sensors from its channels.

        Node ids are the geometry's labels as strings; coordinates are converted to metres from ``units`` (m, mm,
        cm, ft, in); repeated trace lines count once and nodes on no trace line are left out. Each channel becomes
        a sensor at its node along its direction ("x", "-z", ... when along an axis); a channel with no node or
        direction, or at a node on no trace line, is an error: the sensors must follow the data's channels.
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
