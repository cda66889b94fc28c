"""Truths for era.explain solved by independent code (OpenSees, openseespy): a test helper, no tests.

A truth is the structure an engineer describes as an era.Frame (the nominal model explain is given), built again
in OpenSees with different element formulations, mesh and joint details, with model-form scatter drawn per seed,
with effects hidden in it, and "measured" as identified modes with noise. What differs from era/fem on purpose:

- members: ``elasticBeamColumn`` chains of ``n_sub`` elements each (era: its own Hermite elements, its own mesh),
  lumped translational mass with the torsional inertia ρ·I_p lumped on all three rotations of each mesh node
  (era: consistent mass); bracing rods (``Frame`` members of a section called "rod") as ``corotTruss`` bars;
- joints: rigid end zones along each member (0-3 % of its length at each end) and a lateral eccentricity of its
  axis (1σ 0.3 % of its length), both as ``geomTransf -jntOffset``; supports as stiff ``zeroLength`` springs to
  ground (era: the DOFs removed); cables as tensioned ``corotTruss`` bars whose tension comes from a static
  gravity analysis with ``PDelta`` beams (era: T/L springs from its own statics);
- scatter per member (1σ): E and G 2 %, I 1 %, density 1 %, on top of a global E bias of 1 %;
- effects solved as OpenSees details: a support's spring, a beam end released onto a ``zeroLength`` rotational
  spring, a lumped mass with some rotary inertia, a member's E scaled (or, for "damage", a crack: the middle
  element of the member with its I reduced), non-structural mass lumped on the mesh nodes; and two effects that
  are not in explain's library: a tuned mass (a mass on a spring) and a spring to ground at a free node.

Measured: the truth's lowest ``n_modes`` modes that the sensors see, frequencies with 0.2 % noise (1σ), shapes
with a 1 % gain error per sensor and 1 % noise per component of the unit-norm shape
(:func:`era.discrepancy.modes_from_arrays`). One case takes 0.05-0.5 s; :func:`make_case` caches per process.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import openseespy.opensees as ops

from era.discrepancy import modes_from_arrays
from era.discrepancy.measured import MeasuredModes
from era.examples.frames import nasa_grid_frame, portal
from era.structure import Frame, Section

OUTSIDE = ("tuned_mass", "ground_spring")     # effects explain's frame library cannot name
_AXES = {"x": 0, "y": 1, "z": 2}


@dataclass
class TruthCase:
    """One blind test: ``frame`` the nominal era.Frame the engineer gives explain; ``data`` the measured modes
    (MeasuredModes: frequencies (k,) Hz, unit-norm shapes (p, k) in frame.sensors order) to pass as
    ``era.explain(case.data, case.frame)``; ``truth`` {"effects": [(kind, place, size), ...]} what was hidden:
    kind a frame_effects name or "outside"; place a node id, a member (node i, node j), or None; size in SI (kg,
    N·m/rad, N/m, a stiffness factor, or the outside effect's own size). ``label`` names the row of the confusion
    matrix ("none", "point_mass", ..., "two", "damage", "outside"); ``era_params`` the same effects as
    era.discrepancy.frame_model.FrameModel parameters (for the team's own generator,
    era.examples.frame_simulation), None when the library cannot express them; ``frequency_hz`` the truth's
    noiseless frequencies of the measured modes."""

    name: str
    family: str
    seed: int
    frame: Frame
    data: MeasuredModes
    truth: dict
    label: str = ""
    era_params: dict | None = None
    frequency_hz: np.ndarray | None = None


# ---------------------------------------------------------------- the structures (nominal era.Frame models)

def footbridge(panels: int = 5, panel_m: float = 2.0, depth_m: float = 1.5, width_m: float = 2.0) -> Frame:
    """A steel truss footbridge: two Pratt trusses (x-z planes y = 0 "L" and y = width "R"), bottom nodes b0..b5,
    top t1..t4, floor beams across every bottom node carrying the deck (300 kg on each bottom node), top struts,
    plan-bracing rods in the bottom plane (section "rod": a truss bar in the truth), pinned at the four ends;
    sensors z on both bottom chords, y at two top nodes and one bottom node."""
    chord, web = Section.square_tube(0.15, 0.008), Section.square_tube(0.10, 0.006)
    beam, strut, rod = Section.square_tube(0.15, 0.006), Section.tube(0.08, 0.004), Section.tube(0.06, 0.004)
    nodes, members = {}, []
    for s, y in (("L", 0.0), ("R", width_m)):
        for k in range(panels + 1):
            nodes[f"b{k}{s}"] = (k * panel_m, y, 0.0)
        for k in range(1, panels):
            nodes[f"t{k}{s}"] = (k * panel_m, y, depth_m)
        members += [(f"b{k}{s}", f"b{k + 1}{s}", "chord") for k in range(panels)]
        members += [(f"t{k}{s}", f"t{k + 1}{s}", "chord") for k in range(1, panels - 1)]
        members += [(f"b{k}{s}", f"t{k}{s}", "web") for k in range(1, panels)]
        members += [(f"b0{s}", f"t1{s}", "web"), (f"t{panels - 1}{s}", f"b{panels}{s}", "web")]
        for k in range(1, panels - 1):      # Pratt: diagonals fall towards mid-span
            members.append((f"t{k}{s}", f"b{k + 1}{s}", "web") if k < panels / 2 else
                           (f"t{k + 1}{s}", f"b{k}{s}", "web"))
    members += [(f"b{k}L", f"b{k}R", "beam") for k in range(panels + 1)]
    members += [(f"t{k}L", f"t{k}R", "strut") for k in range(1, panels)]
    members += [(f"b{k}L", f"b{k + 1}R", "rod") for k in range(panels)]
    sensors = [(f"b{k}L", "z") for k in range(1, panels)] + [("b2R", "z"), ("b4R", "z"), ("t2L", "y"),
                                                             ("t3R", "y"), ("b3R", "y")]
    return Frame(nodes=nodes, members=members,
                 sections={"chord": chord, "web": web, "beam": beam, "strut": strut, "rod": rod},
                 supports={n: "pinned" for n in ("b0L", "b0R", f"b{panels}L", f"b{panels}R")},
                 masses={n: 300.0 for n in nodes if n.startswith("b")}, sensors=sensors)


FAMILIES = {"grid": nasa_grid_frame, "footbridge": footbridge, "portal": portal}
N_SUB = {"grid": 3, "footbridge": 4, "portal": 6}
N_MODES = {"grid": 6, "footbridge": 5, "portal": 6}   # the footbridge: the lowest five it sees clearly


# ---------------------------------------------------------------- the OpenSees model

@dataclass(frozen=True)
class ModelForm:
    """Model-form scatter of one truth: per member (n_members,) factors on E (and G), on I (both axes) and on
    density; rigid end zones (n_members, 2) as fractions of the member's length; lateral eccentricity of each
    member's axis (n_members, 3) m; elements per member."""

    e: np.ndarray
    i: np.ndarray
    rho: np.ndarray
    rigid_end: np.ndarray
    offset: np.ndarray
    n_sub: int = 4

    @classmethod
    def draw(cls, frame: Frame, rng, n_sub: int = 4, scale: float = 1.0) -> "ModelForm":
        """Drawn with the numpy Generator (or seed) ``rng``; ``scale`` 0: no scatter, only the formulation."""
        rng = np.random.default_rng(rng)
        n = len(frame.members)
        axes = np.array([np.subtract(frame.nodes[j], frame.nodes[i]) for i, j, *_ in frame.members])
        lengths = np.linalg.norm(axes, axis=1)
        lateral = rng.standard_normal((n, 3))
        lateral -= np.sum(lateral * axes, axis=1)[:, None] * axes / lengths[:, None] ** 2
        return cls(e=(1 + scale * 0.01 * rng.standard_normal()) * (1 + scale * 0.02 * rng.standard_normal(n)),
                   i=1 + scale * 0.01 * rng.standard_normal(n), rho=1 + scale * 0.01 * rng.standard_normal(n),
                   rigid_end=scale * rng.uniform(0.0, 0.03, (n, 2)),
                   offset=scale * 0.003 * lengths[:, None] * lateral, n_sub=n_sub)


def _member_index(frame: Frame, at) -> int:
    a, b = (str(v) for v in at)
    return next(k for k, (i, j, *_) in enumerate(frame.members) if {i, j} == {a, b})


class _Builder:
    """Tags and lumped masses while one OpenSees model is built."""

    def __init__(self, frame: Frame):
        ops.wipe()
        ops.model("basic", "-ndm", 3, "-ndf", 6)
        self.frame, self.node, self.mass, self.next_tag, self.stabilisers = frame, {}, {}, [1, 1, 1], []
        for name, xyz in frame.nodes.items():
            self.node[name] = self.new_node(xyz)
        self.materials = {}

    def tag(self, kind: int) -> int:     # kind 0: nodes, 1: elements, 2: transformations
        self.next_tag[kind] += 1
        return self.next_tag[kind] - 1

    def new_node(self, xyz, fixed: bool = False) -> int:
        t = self.tag(0)
        ops.node(t, *map(float, xyz))
        if fixed:
            ops.fix(t, 1, 1, 1, 1, 1, 1)
        self.mass[t] = np.zeros(6)
        return t

    def material(self, k: float) -> int:
        if k not in self.materials:
            self.materials[k] = 100 + len(self.materials)
            ops.uniaxialMaterial("Elastic", self.materials[k], float(k))
        return self.materials[k]

    def spring(self, a: int, b: int, dofs, k, stabiliser: bool = False) -> None:
        """A zeroLength element from node a to b with stiffness k (or one per dof) on global dofs (1..6)."""
        ks = np.broadcast_to(k, len(dofs))
        t = self.tag(1)
        ops.element("zeroLength", t, a, b, "-mat", *[self.material(float(v)) for v in ks], "-dir", *dofs)
        if stabiliser:
            self.stabilisers.append(t)

    def ground(self, a: int, dofs, k, stabiliser: bool = False) -> None:
        self.spring(self.new_node(ops.nodeCoord(a), fixed=True), a, dofs, k, stabiliser)


def _penalties(frame: Frame) -> tuple[float, float]:
    """Stiff-spring values (N/m, N·m/rad) for rigid supports and links: 1e4 × the stiffest member's EA/L, EI/L."""
    s_l = [(frame.sections[sec], np.linalg.norm(np.subtract(frame.nodes[j], frame.nodes[i])))
           for i, j, sec, _ in frame.members]
    return 1e4 * max(s.e * s.area / L for s, L in s_l), 1e4 * max(s.e * max(s.iy, s.iz) / L for s, L in s_l)


def _orientation(axis: np.ndarray, given) -> list:
    """The local x-z plane's vector: the member's own, else era.Frame's default (+Z, or +X for a vertical)."""
    return list(given) if given is not None else (
        [1.0, 0.0, 0.0] if abs(axis[2]) > (1 - 1e-9) * np.linalg.norm(axis) else [0.0, 0.0, 1.0])


def _members(b: _Builder, form: ModelForm, effects: list, gravity: bool) -> None:
    """Each member as a chain of elasticBeamColumn elements (rods: one corotTruss), lumped masses on its nodes."""
    frame = b.frame
    crack = {_member_index(frame, e["at"]): e["factor"] for e in effects if e["kind"] == "damage"}
    soft = {_member_index(frame, e["at"]): e["factor"] for e in effects if e["kind"] == "member_stiffness"}
    spread = sum(e["kg"] for e in effects if e["kind"] == "distributed_mass")
    total_length = sum(np.linalg.norm(np.subtract(frame.nodes[j], frame.nodes[i])) for i, j, *_ in frame.members)
    released = {}
    for e in effects:
        if e["kind"] == "joint_flexibility":
            for k, side in frame.beam_ends(str(e["at"])):
                released[(k, side)] = e["k"]
    for k, (i, j, name, orient) in enumerate(frame.members):
        s = frame.sections[name]
        xi, xj = np.array(frame.nodes[i]), np.array(frame.nodes[j])
        length = float(np.linalg.norm(xj - xi))
        e_mod = s.e * form.e[k] * soft.get(k, 1.0)
        g_mod = s.g * form.e[k] * soft.get(k, 1.0)
        m_per_l = s.mass_per_length * form.rho[k] + frame.added_mass_per_length.get(name, 0.0) + spread / total_length
        ends = [b.node[i], b.node[j]]
        for side in (0, 1):                      # a released beam end: its own node on a rotational spring
            if (k, side) in released:
                node = ends[side]
                axis = np.cross(frame.vertical, xj - xi)
                dof = 4 + int(np.argmax(np.abs(axis)))
                assert np.sum(np.abs(axis) > 1e-9 * np.abs(axis).max()) == 1, "joint springs on global axes only"
                ends[side] = b.new_node(ops.nodeCoord(node))
                ops.equalDOF(node, ends[side], *[d for d in range(1, 7) if d != dof])
                b.spring(node, ends[side], [dof], released[(k, side)])
        if name == "rod":
            t = b.tag(1)
            ops.uniaxialMaterial("Elastic", 10000 + t, e_mod)
            ops.element("corotTruss", t, ends[0], ends[1], s.area, 10000 + t)
            for n in ends:
                b.mass[n][:3] += 0.5 * m_per_l * length
            continue
        a = length * form.rigid_end[k]
        unit = (xj - xi) / length
        pi, pj = xi + a[0] * unit + form.offset[k], xj - a[1] * unit + form.offset[k]
        chain = [ends[0]] + [b.new_node(pi + (pj - pi) * q / form.n_sub) for q in range(1, form.n_sub)] + [ends[1]]
        pts = [pi + (pj - pi) * q / form.n_sub for q in range(form.n_sub + 1)]
        vecxz = _orientation(xj - xi, orient)
        piece = length * (1 - a.sum()) / form.n_sub
        for q in range(form.n_sub):
            tt = b.tag(2)
            off_i = pts[q] - np.array(ops.nodeCoord(chain[q]))
            off_j = pts[q + 1] - np.array(ops.nodeCoord(chain[q + 1]))
            ops.geomTransf("PDelta" if gravity else "Linear", tt, *vecxz, "-jntOffset", *off_i, *off_j)
            i_fac = form.i[k] * (crack.get(k, 1.0) if q == form.n_sub // 2 else 1.0)
            ops.element("elasticBeamColumn", b.tag(1), chain[q], chain[q + 1], s.area, e_mod, g_mod, s.j,
                        s.iy * i_fac, s.iz * i_fac, tt)
            share = piece + (a[0] * length if q == 0 else 0) + (a[1] * length if q == form.n_sub - 1 else 0)
            for n, w in ((chain[q], 0.5), (chain[q + 1], 0.5)):
                b.mass[n][:3] += w * m_per_l * share
                b.mass[n][3:] += w * s.density * form.rho[k] * s.ip * share


def _supports(b: _Builder, effects: list, gravity: bool) -> None:
    frame = b.frame
    k_lin, k_rot = _penalties(frame)
    flex = {str(e["at"]): e for e in effects if e["kind"] == "support_flexibility"}
    up = int(np.argmax(np.abs(frame.vertical)))
    for node, spec in frame.supports.items():
        n = b.node[node]
        if "cable" in spec:                        # a tensioned bar from a fixed point above, along -gravity
            top = b.new_node(np.array(ops.nodeCoord(n)) + spec["cable"] * frame.vertical, fixed=True)
            t = b.tag(1)
            ops.uniaxialMaterial("Elastic", 10000 + t, 200e9)
            ops.element("corotTruss", t, top, n, k_lin * spec["cable"] / 200e9 / 1e2, 10000 + t)
        for d, key in enumerate(("kx", "ky", "kz", "rx", "ry", "rz")):
            v = spec.get(key, 0.0)
            if node in flex and "rotation" in flex[node] and d >= 3 and d != 3 + up and math.isinf(v):
                v = flex[node]["rotation"]
            if node in flex and "vertical" in flex[node] and d == up and math.isinf(v):
                v = flex[node]["vertical"]
            if v > 0:
                b.ground(n, [d + 1], (k_lin if d < 3 else k_rot) if math.isinf(v) else v)
    if gravity:     # springs across gravity hold the unstressed structure (no load there), removed after it
        across = [d + 1 for d in range(3) if d != int(np.argmax(np.abs(frame.gravity)))]
        for n in list(b.node.values()):
            b.ground(n, across, 1e-6 * k_lin, stabiliser=True)


def _extras(b: _Builder, effects: list) -> None:
    for node, kg in b.frame.masses.items():       # the nominal's lumped masses, as drawn
        b.mass[b.node[node]][:3] += kg
    for e in effects:
        if e["kind"] == "point_mass":              # a block: its mass and some rotary inertia (5 cm radius)
            b.mass[b.node[str(e["at"])]] += np.r_[[e["kg"]] * 3, [e["kg"] * 0.05**2] * 3]
        elif e["kind"] == "tuned_mass":            # a mass on a spring along one axis, tuned to e["hz"]
            host = b.node[str(e["at"])]
            d = _AXES[e["dir"]] + 1
            t = b.new_node(ops.nodeCoord(host))
            ops.fix(t, *[0 if q == d else 1 for q in range(1, 7)])
            b.mass[t][d - 1] = e["kg"]
            b.spring(host, t, [d], e["kg"] * (2 * np.pi * e["hz"]) ** 2)
        elif e["kind"] == "ground_spring":
            b.ground(b.node[str(e["at"])], [_AXES[e["dir"]] + 1], e["k"])


def solve(frame: Frame, form: ModelForm, effects: list = (), n_modes: int = 14) -> tuple[np.ndarray, np.ndarray]:
    """The truth's lowest ``n_modes`` modes in OpenSees: frequencies (n,) Hz and node translations
    (n_nodes, 3, n) of the frame's nodes (frame.node_ids order), each mode scaled to a largest translation of 1.
    ``effects``: dicts {"kind": ..., "at": node or (i, j), size keyword}, see :func:`make_case`. With gravity,
    a static gravity analysis (PDelta beams, corotational cables) comes first, so the cables' tension and the
    members' axial forces stiffen the modes."""
    effects = list(effects)
    gravity = frame.gravity is not None
    b = _Builder(frame)
    _members(b, form, effects, gravity)
    _supports(b, effects, gravity)
    _extras(b, effects)
    for t, m in b.mass.items():
        if np.any(m):
            ops.mass(t, *np.maximum(m, 0.0))
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("UmfPack")
    if gravity:
        ops.timeSeries("Constant", 1)
        ops.pattern("Plain", 1, 1)
        for t, m in b.mass.items():
            if m[0] > 0:
                ops.load(t, *(m[0] * np.array(frame.gravity)), 0.0, 0.0, 0.0)
        ops.test("NormDispIncr", 1e-10, 30)
        ops.algorithm("Newton")
        ops.integrator("LoadControl", 1.0)
        ops.analysis("Static")
        if ops.analyze(1) != 0:
            raise RuntimeError("OpenSees: the gravity analysis did not converge")
        ops.loadConst("-time", 0.0)
        for t in b.stabilisers:
            ops.remove("element", t)
    lam = np.array(ops.eigen("-genBandArpack", n_modes))
    f = np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)
    tags = [b.node[n] for n in frame.node_ids]
    u = np.array([[ops.nodeEigenvector(t, m + 1)[:3] for m in range(n_modes)] for t in tags]).transpose(0, 2, 1)
    ref = 1.0 + np.sin(1.7 * np.arange(u[..., 0].size) + 0.3)     # a fixed sign per mode (ARPACK's is arbitrary)
    u *= np.where(ref @ u.reshape(-1, n_modes) < 0, -1.0, 1.0) / np.abs(u).max(axis=(0, 1))
    ops.wipe()
    return f, u


def measure(frame: Frame, f: np.ndarray, u: np.ndarray, rng, n_modes: int = 6, freq_noise: float = 0.002,
            shape_noise: float = 0.01, gain_std: float = 0.01) -> tuple[MeasuredModes, np.ndarray]:
    """The lowest ``n_modes`` modes the sensors see (their shape's norm ≥ 15 % of the best-seen mode's, modes
    scaled to a largest translation of 1) with identification noise; and their noiseless frequencies (Hz)."""
    s = frame.at_sensors(u)
    norm = np.linalg.norm(s, axis=0)
    seen = np.flatnonzero((norm >= 0.15 * norm.max()) & (f > 1e-3))[:n_modes]
    f, s = f[seen], s[:, seen]
    gains = 1.0 + gain_std * rng.standard_normal(s.shape[0])
    s = s / np.linalg.norm(s, axis=0) * gains[:, None]
    s = s + shape_noise * rng.standard_normal(s.shape)
    return modes_from_arrays(f * (1.0 + freq_noise * rng.standard_normal(f.size)), s), f


# ---------------------------------------------------------------- the cases

def _library(frame: Frame) -> dict:
    """Per family: candidate places and sizes of each effect (places drawn per seed from these lists)."""
    total = frame.total_mass_kg
    members = [(i, j) for i, j, *_ in frame.members]
    if "7,2" in frame.nodes:                                        # the grid
        return dict(point_mass=(("7,2", "3,5", "9,1", "5,6", "1,3"), 1.5), member=(members, 0.5),
                    distributed=0.1 * total, crack=0.1, tuned=(("6,3", "4,6", "8,2"), 1.0, 3),
                    ground=(("2,2", "9,5", "5,1"), "z", 150.0), support=None, joint=None)
    if "b0L" in frame.nodes:                                        # the footbridge
        return dict(point_mass=(("b2R", "b3L", "t2L", "b1L", "t3R"), 0.05 * total),
                    member=([m for m in members if frame.members[members.index(m)][2] in ("chord", "web")], 0.5),
                    distributed=0.1 * total, crack=0.1, tuned=(("b3L", "b2R"), 0.02 * total, 0),
                    ground=(("t2R", "t3L"), "y", 2e5), support=(("b0L", "b5R", "b5L"), "vertical", 2e7),
                    joint=(("t2L", "t3R", "t1L"), 2e5))
    return dict(point_mass=(("E", "B", "C"), 30.0), member=(members, 0.6), distributed=60.0, crack=0.15,
                tuned=(("E",), 10.0, 1), ground=(("B", "C"), "x", 5e4), support=(("A", "D"), "rotation", 3e5),
                joint=(("C", "B"), 3e5))


LABELS = ("none", "point_mass", "member_stiffness", "support_flexibility", "joint_flexibility", "distributed_mass",
          "two", "damage", "tuned_mass (outside)", "ground_spring (outside)")


def _effects(frame: Frame, label: str, rng, nominal_hz: np.ndarray) -> list:
    """The hidden effects of one case (dicts for :func:`solve`), places drawn with ``rng``."""
    lib = _library(frame)
    pick = lambda seq: seq[int(rng.integers(len(seq)))]      # noqa: E731
    point = lambda: {"kind": "point_mass", "at": pick(lib["point_mass"][0]),  # noqa: E731
                     "kg": float(lib["point_mass"][1])}
    member = lambda kind, factor: {"kind": kind, "at": pick(lib["member"][0]), "factor": factor}  # noqa: E731
    if label.startswith(("support", "joint", "tuned", "ground")):
        places, *size = lib[label.split("_")[0]]
    make = {
        "none": lambda: [], "point_mass": lambda: [point()],
        "member_stiffness": lambda: [member("member_stiffness", lib["member"][1])],
        "support_flexibility": lambda: [{"kind": "support_flexibility", "at": pick(places), size[0]: size[1]}],
        "joint_flexibility": lambda: [{"kind": "joint_flexibility", "at": pick(places), "k": size[0]}],
        "distributed_mass": lambda: [{"kind": "distributed_mass", "kg": float(lib["distributed"])}],
        "two": lambda: [point(), member("member_stiffness", lib["member"][1])],   # the footbridge
        "damage": lambda: [member("damage", lib["crack"])],
        "tuned_mass (outside)": lambda: [{"kind": "tuned_mass", "at": pick(places), "dir": "z", "kg": float(size[0]),
                                          "hz": float(nominal_hz[size[1]]) * 1.05}],
        "ground_spring (outside)": lambda: [{"kind": "ground_spring", "at": pick(places), "dir": size[0],
                                             "k": size[1]}]}
    if label not in make:
        raise ValueError(f"unknown effect label {label!r}; known: {LABELS}")
    return make[label]()


def applicable(family: str) -> tuple:
    """The effect labels that make sense for a family (the grid hangs on cables: no support to loosen, and its
    joint springs act in its plane, which its out-of-plane sensors cannot see)."""
    lib = _library(FAMILIES[family]())
    return tuple(x for x in LABELS if not (x == "support_flexibility" and lib["support"] is None)
                 and not (x == "joint_flexibility" and lib["joint"] is None))


def _truth_of(effects: list, n_sub: int) -> tuple[list, dict | None]:
    """(kind, place, size) per effect, and the same as FrameModel parameters (None when not expressible)."""
    out, params = [], {}
    for e in effects:
        k, at = e["kind"], e.get("at")
        if k in OUTSIDE:
            out.append(("outside", str(at), k))
            params = None
            continue
        if k in ("member_stiffness", "damage"):
            # a crack in one of n elements: the member's bending compliance grows by (1/factor - 1)/n
            size = e["factor"] if k == "member_stiffness" else 1.0 / (1.0 + (1.0 / e["factor"] - 1.0) / n_sub)
            k, place, keys = "member_stiffness", tuple(at), ("member_at", "member_factor")
        else:
            size = e.get("kg", e.get("k", e.get("rotation", e.get("vertical"))))
            place = None if at is None else str(at)
            keys = {"point_mass": ("point_mass_at", "point_mass_kg"), "joint_flexibility": ("joint_at",
                    "joint_stiffness"), "distributed_mass": (None, "distributed_mass_kg"),
                    "support_flexibility": ("support_at", "support_rotation_stiffness" if "rotation" in e else
                                            "support_vertical_stiffness")}[k]
        out.append((k, place, size))
        if params is not None:
            params.update({keys[1]: size, **({keys[0]: place} if keys[0] else {})})
    return out, params


@functools.lru_cache(maxsize=None)
def _nominal_hz(family: str) -> np.ndarray:
    frame = FAMILIES[family]()
    return solve(frame, ModelForm.draw(frame, None, N_SUB[family], 0.0), n_modes=N_MODES[family] + 8)[0]


@functools.lru_cache(maxsize=None)
def make_case(family: str, label: str, seed: int, scale: float = 1.0) -> TruthCase:
    """One blind test of ``family`` ("grid", "footbridge", "portal") with the effect ``label`` (one of
    :func:`applicable`) hidden; the model-form scatter drawn from (family, seed), the same for every label, places
    and noise from (family, label, seed); ``scale`` multiplies the scatter (0: only the formulation differs)."""
    frame = FAMILIES[family]()
    # one structure per (family, seed): every effect of a seed is hidden in the same scattered truth; the places
    # and the identification noise are drawn per case
    form = ModelForm.draw(frame, [seed, list(FAMILIES).index(family)], N_SUB[family], scale)
    rng = np.random.default_rng([seed, LABELS.index(label), list(FAMILIES).index(family)])
    effects = _effects(frame, label, rng, _nominal_hz(family))
    f, u = solve(frame, form, effects, n_modes=N_MODES[family] + 8)
    data, f_true = measure(frame, f, u, rng, N_MODES[family])
    truth, params = _truth_of(effects, form.n_sub)
    where = ", ".join(f"{k} {p if not isinstance(p, tuple) else '-'.join(p)}" for k, p, _ in truth) or "nothing"
    return TruthCase(f"{family}/{label}/s{seed}: {where}", family, seed, frame, data, {"effects": truth},
                     label=label, era_params=params, frequency_hz=f_true)


def cases(families=tuple(FAMILIES), seeds=(0,), labels=None, scale: float = 1.0) -> list:
    """Every case of these families, seeds and effect labels (default: each family's :func:`applicable`)."""
    return [make_case(fam, lab, s, scale) for fam in families for lab in (labels or applicable(fam))
            if lab in applicable(fam) for s in seeds]
