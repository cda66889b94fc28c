"""The NASA Langley flexible grid (Juang & Pappa 1985, Fig. 2 and Table 1) as a grillage finite-element model.

A 10 ft × 7 ft grid of aluminium bars 2 in × 1/4 in, riveted at 1 ft intervals (11 × 8 = 88 joints), hanging
in a vertical plane from two cables on the top bar 3 ft either side of the centre. x runs along the bars
(0..10 ft), y up from the bottom bar (0..7 ft); w is the out-of-plane motion the nine sensors measure.

Physics: Euler-Bernoulli bending about the thin direction, St-Venant torsion of the flat strip, consistent
mass (era.fem). Gravity: an in-plane static solve of the self-weight gives each bar's axial force, whose
geometric stiffness holds the swing, yaw and rocking suspension modes; each cable adds a pendulum spring
T/L on w where it is attached.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
import scipy.linalg

from .. import fem
from ..errors import EraError
from ..discrepancy.protocol import RitzModes, joint_rows
from ..core.geometry import Geometry
from ..words import listed
# the layout (joints, members, sensors, indices) is era/examples/grid_layout.py; its names are read from here too
from .grid_layout import (
    AIR_JET_FT, CABLES_FT, FT, JOINTS_FT, MEMBERS_FT, N_HORIZONTAL, N_SEGMENTS, NX, NY, SEGMENT_JOINTS, SENSORS_FT,
    joint_index, segment_index)
from .grid_solves import SolveCache, assemble_grid, attachments, changed_nodes, param_key, grid_self_weight

SAMPLE_RATE_HZ = 32.0
TABLE1_HZ = np.array([0.362, 0.612, 1.425, 2.331, 2.826, 4.936, 5.476, 6.429, 7.047, 9.841])
BAR = fem.flat_bar(width_m=2 * 0.0254, thickness_m=0.25 * 0.0254, E=68.9e9, nu=0.33, rho=2700.0)
# parameters the in-plane self-weight solve depends on (its forces are reused when none of these change)
_STATIC_PARAMS = ("distributed_mass_kg", "point_mass_kg", "point_mass_at", "elements_per_bar", "member_at",
                  "member_factor")
DEFAULTS = dict(gravity=True, joint_stiffness=None, torsion_factor=1.0, cable_length_m=0.51,
                distributed_mass_kg=0.0, point_mass_kg=0.0, point_mass_at=None, loose_joint_at=None,
                loose_joint_stiffness=None, stiffness_factor=1.0, elements_per_bar=1, member_at=None,
                member_factor=1.0)
_SIGN_REFERENCE = 1.0 + np.sin(1.7 * np.arange(NX * NY) + 0.3)   # fixed, no symmetry of the grid


@dataclass(frozen=True, eq=False)
class GridPerturbation:
    """Fine-grained departures from the nominal grid (used by the truth generator of era.examples.grid_simulation).

    Attributes
    ----------
    ei_factor, gj_factor : (157,)
        Multipliers on the out-of-plane EI and on GJ of each 1-ft segment (order of SEGMENT_JOINTS).
    segment_mass_kg : (157,)
        Extra non-structural mass spread along each segment, kg.
    joint_compliance : (88, 2)
        Extra rotational compliance (rad/(N·m)) about (x, y) between the two crossing bars at each joint.
    point_masses : tuple of (x_ft, y_ft, kg)
        Lumped masses at mesh nodes (joints, or segment interior points that the mesh has).
    cable_factor : (2,)
        Multipliers on the length of the left and right cable.
    ground_springs : (88,)
        Springs from each joint's w to the ground, N/m (e.g. a snagged lead: not a candidate effect).
    """

    ei_factor: np.ndarray = field(default_factory=lambda: np.ones(N_SEGMENTS))
    gj_factor: np.ndarray = field(default_factory=lambda: np.ones(N_SEGMENTS))
    segment_mass_kg: np.ndarray = field(default_factory=lambda: np.zeros(N_SEGMENTS))
    joint_compliance: np.ndarray = field(default_factory=lambda: np.zeros((NX * NY, 2)))
    point_masses: tuple = ()
    cable_factor: np.ndarray = field(default_factory=lambda: np.ones(2))
    ground_springs: np.ndarray = field(default_factory=lambda: np.zeros(NX * NY))


def _check_params(p: dict) -> dict:
    unknown = set(p) - set(DEFAULTS)
    if unknown:
        raise EraError(f"nasa_grid: unknown {'parameters' if len(unknown) > 1 else 'parameter'} "
                       f"{listed(sorted(unknown), quote=True)}; known: {listed(sorted(DEFAULTS), quote=True)}.")
    p = {**DEFAULTS, **p}
    g = p["gravity"]
    if not (isinstance(g, (bool, np.bool_)) or (isinstance(g, (int, float)) and 0 <= g <= 1)):
        raise EraError(f"gravity must be True, False or a fraction in [0, 1], got {g!r}.")
    for name in ("torsion_factor", "cable_length_m", "stiffness_factor"):
        if not (np.isfinite(p[name]) and p[name] > 0):
            raise EraError(f"{name} must be a positive number, got {p[name]!r}.")
    for name in ("distributed_mass_kg", "point_mass_kg"):
        if not (np.isfinite(p[name]) and p[name] >= 0):
            raise EraError(f"{name} must be a non-negative number of kg, got {p[name]!r}.")
    for name in ("joint_stiffness", "loose_joint_stiffness"):
        if p[name] is not None and not (np.isfinite(p[name]) and p[name] > 0):
            raise EraError(f"{name} must be None (rigid) or a positive stiffness in N·m/rad, got {p[name]!r}.")
    if p["point_mass_kg"] > 0 and p["point_mass_at"] is None:
        raise EraError("point_mass_kg > 0 needs point_mass_at=(x_ft, y_ft), the joint that carries the mass.")
    if (p["loose_joint_at"] is None) != (p["loose_joint_stiffness"] is None):
        raise EraError("loose_joint_at and loose_joint_stiffness go together: give both or neither.")
    for name in ("point_mass_at", "loose_joint_at"):
        if p[name] is not None:
            joint_index(p[name])
            p[name] = tuple(float(v) for v in p[name])
    if p["member_at"] is not None:
        segment_index(p["member_at"])
        p["member_at"] = tuple(tuple(float(v) for v in j) for j in p["member_at"])
    if not (np.isfinite(p["member_factor"]) and p["member_factor"] > 0):
        raise EraError(f"member_factor must be a positive number, got {p['member_factor']!r}.")
    ne = p["elements_per_bar"]
    if isinstance(ne, bool) or not isinstance(ne, (int, np.integer)) or not 1 <= ne <= 8:
        raise EraError(f"elements_per_bar must be an integer from 1 to 8, got {ne!r}.")
    return p


def _build_frame(p: dict, pert: GridPerturbation) -> fem.PlaneFrame:
    """Mesh the grid. Nodes 0..87 are the joints (index iy·11 + ix; at a semi-rigid joint, the horizontal bar's
    node); then one node per semi-rigid joint for the vertical bar, linked to the first; then segment interiors."""
    compliance = np.array(pert.joint_compliance, float)
    if p["joint_stiffness"] is not None:
        compliance += 1.0 / p["joint_stiffness"]
    if p["loose_joint_at"] is not None:
        compliance[joint_index(p["loose_joint_at"])] += 1.0 / p["loose_joint_stiffness"]
    split = np.flatnonzero(compliance.max(axis=1) > 0)      # joints whose two bars get their own nodes
    xy = [JOINTS_FT]
    v_node = np.arange(NX * NY)                               # node used by the vertical bar at each joint
    v_node[split] = NX * NY + np.arange(split.size)
    xy.append(JOINTS_FT[split])
    n0 = NX * NY + split.size
    ne = p["elements_per_bar"]
    ends = SEGMENT_JOINTS.copy()
    ends[N_HORIZONTAL:] = v_node[ends[N_HORIZONTAL:]]
    t = np.arange(1, ne) / ne
    a_ft, b_ft = JOINTS_FT[SEGMENT_JOINTS[:, 0]], JOINTS_FT[SEGMENT_JOINTS[:, 1]]
    xy.append((a_ft[:, None] * (1 - t)[:, None] + b_ft[:, None] * t[:, None]).reshape(-1, 2))
    chain = np.empty((N_SEGMENTS, ne + 1), int)      # node chain along each segment, joint to joint
    chain[:, 0], chain[:, -1] = ends[:, 0], ends[:, 1]
    chain[:, 1:-1] = n0 + np.arange(N_SEGMENTS)[:, None] * (ne - 1) + np.arange(ne - 1)
    bars = np.stack([chain[:, :-1], chain[:, 1:]], axis=-1).reshape(-1, 2)
    seg_of_bar = np.repeat(np.arange(N_SEGMENTS), ne)
    n = n0 + N_SEGMENTS * (ne - 1)
    nodes_ft = np.concatenate(xy)
    E = BAR.E * p["stiffness_factor"]
    G = BAR.G * p["stiffness_factor"] * p["torsion_factor"]
    seg_mass = np.asarray(pert.segment_mass_kg, float) + p["distributed_mass_kg"] / N_SEGMENTS
    node_mass = np.zeros(n)
    masses = list(pert.point_masses)
    if p["point_mass_kg"] > 0:
        masses.append((*p["point_mass_at"], p["point_mass_kg"]))
    for x, y, kg in masses:
        hit = np.flatnonzero(np.hypot(nodes_ft[:, 0] - x, nodes_ft[:, 1] - y) < 1e-9)
        if hit.size == 0:
            raise EraError(f"A point mass at ({x:g}, {y:g}) ft is not on a node of this mesh "
                           f"(elements_per_bar={ne}); put it at a joint or refine the mesh.")
        node_mass[hit[0]] += kg
    member = np.ones(N_SEGMENTS)            # member_stiffness: E and G of one segment scaled together
    if p["member_at"] is not None:
        member[segment_index(p["member_at"])] = p["member_factor"]
    scale = member[seg_of_bar]
    ones = np.ones(bars.shape[0])
    with np.errstate(divide="ignore"):
        k_links = np.where(compliance[split] > 0, 1.0 / compliance[split], np.inf)
    frame = fem.PlaneFrame(
        nodes_m=nodes_ft * FT, bars=bars,
        EI_out=E * BAR.i_out * np.asarray(pert.ei_factor)[seg_of_bar] * scale,
        GJ=G * BAR.j_torsion * np.asarray(pert.gj_factor)[seg_of_bar] * scale,
        EA=E * BAR.area * scale, EI_in=E * BAR.i_in * scale,
        mass_per_length=BAR.mass_per_length + seg_mass[seg_of_bar] / FT,
        rho_ip=BAR.rho * BAR.i_polar * ones, r2=BAR.i_polar / BAR.area * ones,
        links=np.stack([split, v_node[split]], axis=1),
        link_stiffness=np.column_stack([np.full(split.size, np.inf), k_links]),
        node_mass=node_mass, node_springs=np.zeros((n, 3)))
    return frame


@dataclass(frozen=True, eq=False)
class GridModel:
    """The grid FE model for one set of parameters (see :func:`nasa_grid`). Immutable; results are cached, and
    shared with the models derived by ``with_params`` (:class:`SolveCache`, ``.cache``)."""

    _params: dict
    perturbation: GridPerturbation = field(default_factory=GridPerturbation, repr=False)
    _statics: tuple | None = field(default=None, repr=False)   # (axial force, cable tensions) to reuse
    cache: SolveCache = field(default_factory=SolveCache, repr=False, compare=False)

    @property
    def params(self) -> dict:
        """The keyword arguments of :func:`nasa_grid` that built this model (a copy)."""
        return dict(self._params)

    sensors = property(lambda self: SENSORS_FT.copy(), doc="(9, 2) sensor (x_ft, y_ft), in channel order.")
    joints_ft = property(lambda self: JOINTS_FT.copy(), doc="(88, 2) joint (x_ft, y_ft), index iy·11 + ix.")
    members_ft = property(lambda self: MEMBERS_FT, doc="The 157 members ((x1, y1), (x2, y2)) ft (member_at).")

    def with_params(self, **changes) -> "GridModel":
        """A new model with some parameters changed (the perturbation, if any, is kept).

        When only stiffness-like parameters change, the in-plane self-weight solve is reused: its forces depend
        on the weights and the mesh only (links are rigid in the plane; a uniform E scale leaves forces as they are).
        """
        params = _check_params({**self._params, **changes})
        same_weights = all(params[k] == self._params[k] for k in _STATIC_PARAMS)
        reuse = self.__dict__["_system"][4] if same_weights and "_system" in self.__dict__ else None
        return GridModel(params, self.perturbation, reuse, self.cache)

    @cached_property
    def _system(self):
        frame = _build_frame(self._params, self.perturbation)
        cables = [joint_index(c) for c in CABLES_FT]
        key = param_key(self._params, _STATIC_PARAMS)
        statics = self._statics or self.cache.statics.get(key)
        if statics is None:
            p = self._params
            statics = grid_self_weight(frame, [(cables[0], True, True), (cables[1], False, True)], self.cache,
                                  param_key(p, ("elements_per_bar", "member_at", "member_factor")),
                                  1.0 / N_SEGMENTS / FT, p["distributed_mass_kg"],
                                  p["point_mass_kg"],
                                  joint_index(p["point_mass_at"]) if p["point_mass_kg"] > 0 else None)
        self.cache.put(self.cache.statics, key, statics, 4 * self.cache.max_entries)
        axial_force, tension = statics
        lengths = self._params["cable_length_m"] * np.asarray(self.perturbation.cable_factor, float)
        springs = np.zeros((frame.n_nodes, 3))
        springs[:NX * NY, 0] = self.perturbation.ground_springs
        springs[cables, 0] += tension / lengths           # pendulum stiffness T/L of each cable
        frame = replace(frame, node_springs=springs)
        axial = axial_force * float(self._params["gravity"])
        system = assemble_grid(frame, axial if self._params["gravity"] else None, self.cache)
        return frame, system, tension, system.dofs[:NX * NY, 0], (axial_force, tension)

    @property
    def frame(self) -> fem.PlaneFrame:
        """The meshed structure (SI units)."""
        return self._system[0]

    @property
    def cable_tension_n(self) -> np.ndarray:
        """(2,) tension of the left and right cable, N (from the in-plane self-weight solve)."""
        return self._system[2].copy()

    @property
    def total_mass_kg(self) -> float:
        return self.frame.total_mass()

    def _solved(self, n_modes: int) -> tuple:
        """(f (≥ n,), φ (n_dof, ≥ n), w rows of the joints (88,)): this model's own, or the family cache's."""
        own = self.__dict__.get("_mode_cache")
        if own is not None and own[0].size >= n_modes:
            return own
        key = param_key(self._params)
        hit = self.cache.modes.get(key)
        if hit is not None and hit[0].size >= n_modes:
            self.cache.n_hits += 1
            self.cache.modes.move_to_end(key)
        else:
            _, system, _, w_joint, _ = self._system
            f, phi = fem.lowest_modes(system.K, system.M, n_modes)
            self.cache.n_solves += 1
            # Sign: positive projection on a fixed generic vector (not "largest entry positive", which is a
            # coin toss for the grid's symmetric and antisymmetric modes), so identical models agree exactly.
            phi = phi * np.where(_SIGN_REFERENCE @ phi[w_joint] < 0, -1.0, 1.0)
            hit = (f, phi, w_joint)
            self.cache.put(self.cache.modes, key, hit, self.cache.max_entries)
        self.__dict__["_mode_cache"] = hit
        return hit

    def dof_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Lowest modes on every DOF: frequencies (n,) Hz and mass-normalised shapes (n_dof, n) (1/√kg on w)."""
        f, phi, _ = self._solved(n_modes)
        return f[:n_modes].copy(), phi[:, :n_modes].copy()

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised w at the 88 joints (88, n), 1/√kg."""
        f, phi, w_joint = self._solved(n_modes)
        return f[:n_modes].copy(), phi[w_joint, :n_modes]

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised w at the nine sensors (9, n), 1/√kg (rows in sensor order)."""
        f, w = self.node_modes(n_modes)
        return f, w[[joint_index(s) for s in SENSORS_FT]]

    def ritz(self, reference: "GridModel", n_modes: int, attach: bool = True) -> "RitzModes | None":
        """This model's modes in the span of the ``reference`` model's lowest ``n_modes`` modes (Rayleigh-Ritz: a
        small dense eigenproblem instead of a solve, for screening many places of a local change and for the
        trials of a fit), or None when this model is not the reference plus changes on the same mesh (other
        mesh, or a joint of the reference's that this one keeps rigid) or when the basis would be more than a
        quarter of the DOFs (every joint split), no cheaper than a solve.

        A joint this model splits (a loose joint) and the reference does not: the reference's shapes move both
        bars' nodes together, and the split node's rotations are added as extra basis vectors (the relative
        rotation the spring allows). ``attach``: where the change is local (a few members' stiffness or mass, a
        node's mass or spring, a split joint), the reference's static responses to unit loads on those nodes'
        DOFs join the basis (attachment modes, the residual flexibility the truncated modes miss), so a
        local stiffness change moves the shapes as a solve does; a global change (E, GJ of every bar) is
        carried by the modes themselves."""
        _, system, _, w_joint, _ = self._system
        ref_frame, ref_system = reference._system[0], reference._system[1]
        frame = self._system[0]
        split, split_ref = frame.links[:, 0].tolist(), ref_frame.links[:, 0].tolist()
        if (self._params["elements_per_bar"] != reference._params["elements_per_bar"]
                or not set(split_ref) <= set(split)):
            return None
        n_joint, n_split, n_split_ref = NX * NY, len(split), len(split_ref)
        # each node of this model ↔ the reference node that moves with it
        node_ref = np.arange(frame.n_nodes)
        node_ref[n_joint:n_joint + n_split] = [n_joint + split_ref.index(j) if j in split_ref else j for j in split]
        node_ref[n_joint + n_split:] -= n_split - n_split_ref
        dofs, dofs_ref = system.dofs, ref_system.dofs
        phi = reference.dof_modes(n_modes)[1]
        if attach:
            local = changed_nodes(frame, ref_frame, node_ref, [j for j in split if j not in split_ref])
            if local is None:
                return None
            if local.size:
                phi = np.column_stack([phi, attachments(reference.__dict__, ref_system, local, phi)])
        lifted = np.zeros((system.K.shape[0], phi.shape[1]))
        lifted[dofs.ravel()] = phi[dofs_ref[node_ref].ravel()]
        new = sorted(set(dofs[n_joint:n_joint + n_split].ravel().tolist())
                     - set(dofs[[n_joint + k for k, j in enumerate(split) if j in split_ref]].ravel().tolist())
                     - set(dofs[:n_joint].ravel().tolist()))
        if lifted.shape[1] + len(new) > 0.25 * lifted.shape[0]:
            return None         # every joint split (joint flexibility): no cheaper than a solve
        basis = np.column_stack([lifted, np.eye(lifted.shape[0])[:, new]]) if new else lifted
        k = basis.T @ (system.K @ basis)
        m = basis.T @ (system.M @ basis)
        lam, v = scipy.linalg.eigh(0.5 * (k + k.T), 0.5 * (m + m.T), check_finite=False)
        f = np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)
        self.cache.n_ritz += 1
        w = (basis @ v)[w_joint]
        return RitzModes(f, w, w[[joint_index(s) for s in SENSORS_FT]])

    def screening_ritz(self, reference: "GridModel", n_modes: int) -> "RitzModes | None":
        """:meth:`ritz` in the reference's modes alone, without attachment modes: the approximation the place
        screening (ranking.screen_locations) was calibrated with. With attachments, a loose joint's screened
        misfit ranks places differently (a blind loose joint at (10, 2), seed 3, fell out of the places fitted)."""
        return self.ritz(reference, n_modes, attach=False)

    # the rest of the model protocol explain relies on (era.discrepancy.protocol.ExplainModel)
    has_ritz = True                 # .ritz approximates a variant's modes in a solved model's
    node_labels = ()                # node_modes' rows are the 88 joints, index iy·11 + ix
    default_member_scatter = 0.0    # the 157 bars' scatter averages out (in ErrorLevels.freq_floor)
    # no model-form allowance: the floors (ErrorLevels) were calibrated against the grid's simulated tests, whose
    # truths scatter the bars, joints and cables about this model (era.examples.grid_simulation)
    default_model_form = (0.0, 0.0)

    @property
    def exact(self) -> "GridModel":
        """The model itself: every parameter set is solved in full."""
        return self

    def modal_rows(self, input_locations) -> tuple | None:
        """Rows of node_modes (joints) at the nine sensors and at the input points ((x_ft, y_ft) each), or None
        when an input is not at a joint."""
        return joint_rows(JOINTS_FT, SENSORS_FT, input_locations)

    def member_energy_fractions(self, n_modes: int = 10) -> None:
        """None: the grid's members are not described one by one for the scatter (see default_member_scatter)."""
        return None

    def member_shape_sensitivity(self, n_modes: int = 10) -> None:
        return None

    def member_scale_sensitivity(self, node_rows, n_modes: int = 10) -> None:
        return None

    def geometry(self) -> Geometry:
        """The 88 joints in metres (z = 0), the 157 segments as edges, the nine channels along +z."""
        xyz = np.column_stack([JOINTS_FT * FT, np.zeros(NX * NY)])
        return Geometry(node_ids=np.arange(1, NX * NY + 1), coordinates=xyz, edges=SEGMENT_JOINTS,
                        channel_nodes=np.array([joint_index(s) for s in SENSORS_FT]),
                        channel_directions=np.tile([0.0, 0.0, 1.0], (len(SENSORS_FT), 1)), units="m")


def nasa_grid(*, gravity=True, joint_stiffness=None, torsion_factor=1.0, cable_length_m=0.51,
              distributed_mass_kg=0.0, point_mass_kg=0.0, point_mass_at=None, loose_joint_at=None,
              loose_joint_stiffness=None, stiffness_factor=1.0, elements_per_bar=1, member_at=None,
              member_factor=1.0) -> GridModel:
    """The NASA Langley grid; each keyword switches on one candidate effect (docs/effects.md).

    Parameters
    ----------
    gravity : bool or float in [0, 1]
        Geometric stiffness of the self-weight tension in the bars ("gravity_stiffening"); a fraction scales
        it. False drops it while the cables keep their pendulum springs T/L: the swing mode (rotation about
        the top bar) then falls to 0 Hz.
    joint_stiffness : float or None
        Rotational spring, N·m/rad, about x and about y between the two bars at every riveted joint
        ("joint_flexibility"); None = rigid joints.
    torsion_factor : float
        Multiplier on GJ of the flat bars ("torsion_stiffness").
    cable_length_m : float
        Length of both cables, m ("cable_length"); each gives a spring T/L on w at its attachment.
    distributed_mass_kg : float
        Extra non-structural mass spread uniformly along all bars, kg ("distributed_mass"); it also weighs.
        Beware: its frequencies and shapes equal those of stiffness_factor = M/(M + m) to < 0.01 % (mass and
        weight scale together, so only E/ρ matters); only mass-scaled amplitudes (a calibrated input) tell
        the two apart.
    point_mass_kg, point_mass_at : float, (x_ft, y_ft)
        A lumped mass on w at one joint ("point_mass").
    loose_joint_at, loose_joint_stiffness : (x_ft, y_ft), float
        One joint semi-rigid with this rotational stiffness, N·m/rad ("loose_joint"). Its effect saturates
        below ~50 N·m/rad (a hinge) and is under-resolved by 1-ft elements: fit its stiffness with
        elements_per_bar=2 (the 1-ft mesh biases it low by up to a factor 2).
    stiffness_factor : float
        Multiplier on E (so on EI, GJ and EA): the global-stiffness nuisance parameter.
    elements_per_bar : int
        Elements per 1-ft segment between joints (mesh refinement).
    member_at, member_factor : ((x1, y1), (x2, y2)) ft, float
        One member (the 1-ft segment between two neighbouring joints) with its element stiffness scaled by
        member_factor: E and G together, so both bendings, torsion and axial ("member_stiffness", a damaged or
        wrongly drawn member); mass unchanged.

    Returns
    -------
    GridModel with .modes(n), .node_modes(n), .sensors, .joints_ft, .params, .with_params(**changes), .geometry().
    One build plus modes(10) takes a few ms (tests/bench).
    """
    return GridModel(_check_params(dict(
        gravity=gravity, joint_stiffness=joint_stiffness, torsion_factor=torsion_factor,
        cable_length_m=cable_length_m, distributed_mass_kg=distributed_mass_kg, point_mass_kg=point_mass_kg,
        point_mass_at=point_mass_at, loose_joint_at=loose_joint_at, loose_joint_stiffness=loose_joint_stiffness,
        stiffness_factor=stiffness_factor, elements_per_bar=elements_per_bar, member_at=member_at,
        member_factor=member_factor)))
