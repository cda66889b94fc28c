"""A simulated vibration test of the NASA grid with a hidden physical effect (the truth of simulation vs test).

The truth is deliberately NOT the nominal model of :func:`era.examples.grid.nasa_grid`: a finer mesh, a few per cent of
random scatter in each bar segment's EI and GJ, a ~1 % error in E, the hidden effect parametrised differently
from the candidate that ``era.explain`` fits (scattered per-joint springs for one global spring, a mass patch
over several nodes for a point mass, unequal cables for one length, ...), sensor gain errors, modal damping
0.3-1 %, measurement noise. The records are free decays of the nine sensors (w, mm) sampled at 32 Hz, computed
by modal superposition of every truth mode below 0.85 × Nyquist (the anti-alias band).
"""

from __future__ import annotations

import functools

import numpy as np

from ..core.data import ResponseData
from ..errors import EraError
from .grid import (
    AIR_JET_FT, CABLES_FT, JOINTS_FT, MEMBERS_FT, N_HORIZONTAL, N_SEGMENTS, NX, NY, SAMPLE_RATE_HZ, SEGMENT_JOINTS,
    SENSORS_FT, GridModel, GridPerturbation, joint_index, nasa_grid, segment_index)

EFFECTS = ("joint_flexibility", "torsion_stiffness", "cable_length", "distributed_mass", "point_mass",
           "loose_joint", "gravity_stiffening", "member_stiffness")
OUTSIDE_LIBRARY = ("damaged_bar", "ground_spring")
DEFAULT_INPUTS_FT = ((10, 0), (0, 7), (3, 2), (7, 5), (0, 4), (6, 1))
_BORDER_JOINTS = [tuple(float(v) for v in j) for j in JOINTS_FT.tolist()
                  if j[0] in (0, NX - 1) or j[1] in (0, NY - 1)]
LOOSE_JOINT_LIMIT_PCT = 0.55


@functools.lru_cache(maxsize=4)
def _rigid_frequencies(n_modes: int) -> np.ndarray:
    return nasa_grid().modes(n_modes)[0]


def loose_joint_signature_pct(at, stiffness: float, n_modes: int = 12) -> float:
    """How far one loose joint moves the modes: max over the first ``n_modes`` of |f_loose / f_rigid − 1|, %.

    At most ~0.8 % (a corner turned into a hinge), 0.3-0.75 % along the border, 0.05-0.2 % inside, where four
    continuous bars cross and each still carries its own bending. The 3 % scatter of the bars' stiffness leaves
    up to ~0.4 % between the truth and the best nominal, so a loose joint is detectable only where this
    signature exceeds LOOSE_JOINT_LIMIT_PCT (0.55 %, measured with tests/bench/bench_explain.py).
    """
    f0 = _rigid_frequencies(n_modes)
    f1 = nasa_grid().with_params(loose_joint_at=tuple(at), loose_joint_stiffness=float(stiffness)).modes(n_modes)[0]
    return float(100 * np.max(np.abs(f1 / f0 - 1)))


_KEYS = {"none": (), "joint_flexibility": ("joint_stiffness",), "torsion_stiffness": ("torsion_factor",),
         "cable_length": ("cable_length_m",), "distributed_mass": ("distributed_mass_kg",),
         "point_mass": ("point_mass_kg", "point_mass_at"), "loose_joint": ("loose_joint_stiffness", "loose_joint_at"),
         "gravity_stiffening": (), "member_stiffness": ("member_factor", "member_at"),
         "damaged_bar": ("bar", "ei_factor"), "ground_spring": ("stiffness_n_per_m", "at")}


def _parse(effect) -> tuple[str, dict]:
    if effect is None:
        return "none", {}
    if isinstance(effect, str):
        name, given = effect, {}
    elif isinstance(effect, dict) and "name" in effect:
        name, given = effect["name"], {k: v for k, v in effect.items() if k != "name"}
    else:
        raise EraError(f"effect must be None, a name or a dict with a 'name', got {effect!r}.")
    if name not in EFFECTS + OUTSIDE_LIBRARY + ("none",):
        raise EraError(f"Unknown effect {name!r}; choose from {', '.join(EFFECTS + OUTSIDE_LIBRARY)} or None.")
    unknown = set(given) - set(_KEYS[name])
    if unknown:
        raise EraError(f"Effect {name!r} has no parameter {sorted(unknown)}; it takes {list(_KEYS[name]) or 'none'}.")
    return name, dict(given)


def _parse_all(effect) -> list:
    """[(name, given), ...]: one effect, or a list/tuple of several hidden together (each at most once)."""
    out = [_parse(e) for e in effect] if isinstance(effect, (list, tuple)) else [_parse(effect)]
    names = [n for n, _ in out if n != "none"]
    if len(set(names)) != len(names):
        raise EraError(f"Each hidden effect can be given once, got {names}.")
    return [(n, g) for n, g in out if n != "none"] or [("none", {})]


MEMBER_LIMIT_PCT = 1.0


@functools.lru_cache(maxsize=8)
def member_signatures_pct(factor: float = 0.2, n_modes: int = 12) -> np.ndarray:
    """(157,) how far one cracked member (EI × ``factor``, GJ × √factor) moves the modes beyond what a global stiffness
    factor can take up: max over the first n_modes of |r_j / median(r) − 1|, r = f_member / f_nominal, %, per
    member in MEMBERS_FT order. At factor 0.2: 0.1 % for the quietest interior members, 1.4 % at best; a
    member is drawn as damaged only where this exceeds MEMBER_LIMIT_PCT (1 %; the bars' scatter leaves up to
    ~0.4 % between the truth and the best nominal)."""
    f0 = _rigid_frequencies(n_modes)
    out = []
    for k in range(N_SEGMENTS):
        ei, gj = np.ones(N_SEGMENTS), np.ones(N_SEGMENTS)
        ei[k], gj[k] = factor, np.sqrt(factor)
        model = GridModel(nasa_grid().params, GridPerturbation(ei_factor=ei, gj_factor=gj))
        r = model.modes(n_modes)[0] / f0
        out.append(100 * np.max(np.abs(r / np.median(r) - 1)))
    return np.array(out)


def _segments_of_bar(orientation: str, at_ft: float) -> np.ndarray:
    """Segments of one physical bar: horizontal ('x', y_ft) or vertical ('y', x_ft)."""
    a = JOINTS_FT[SEGMENT_JOINTS[:, 0]]
    horizontal = np.arange(N_SEGMENTS) < N_HORIZONTAL
    if orientation == "x":
        return np.flatnonzero(horizontal & (a[:, 1] == at_ft))
    return np.flatnonzero(~horizontal & (a[:, 0] == at_ft))


def _truth_model(effects: list, rng, *, elements_per_bar: int, scatter: float, e_error: float):
    """The truth GridModel and, per hidden effect, (name, parameters in the candidate's terms, location,
    description); the nominal params; the stiffness factor."""
    ei = np.exp(scatter * rng.standard_normal(N_SEGMENTS))
    gj = np.exp(scatter * rng.standard_normal(N_SEGMENTS))
    stiffness_factor = 1.0 + rng.choice([-1.0, 1.0]) * e_error * rng.uniform(0.7, 1.3)
    params = dict(elements_per_bar=elements_per_bar, stiffness_factor=stiffness_factor)
    pert = dict(ei_factor=ei, gj_factor=gj, joint_compliance=np.zeros((NX * NY, 2)))
    sign = rng.choice([-1.0, 1.0])
    nominal, hidden = {}, []
    for name, given in effects:
        location, reported = None, {}
        how = "no hidden effect: only mesh, stiffness scatter and E error separate the truth from the nominal"
        if name == "joint_flexibility":
            k = float(given.get("joint_stiffness", np.exp(rng.uniform(np.log(200), np.log(800)))))
            c = np.exp(0.3 * rng.standard_normal((NX * NY, 2)))           # per-joint, per-axis scatter ±30 %
            pert["joint_compliance"] = pert["joint_compliance"] + c / c.mean() / k    # mean compliance 1/k exactly
            reported = {"joint_stiffness": k}
            how = (f"every joint semi-rigid, springs scattered ±30 % per joint and axis, mean compliance "
                   f"1/{k:.0f} rad/(N·m)")
        elif name == "torsion_stiffness":
            f = float(given.get("torsion_factor", 1 + sign * rng.uniform(0.07, 0.15)))
            params["torsion_factor"] = f
            reported = {"torsion_factor": f}
            how = f"GJ of all bars × {f:.3f} (on top of the segment scatter)"
        elif name == "cable_length":
            L = float(given.get("cable_length_m", 0.51 * (1 + sign * rng.uniform(0.1, 0.25))))
            d = rng.uniform(0.01, 0.03)
            params["cable_length_m"] = L
            pert["cable_factor"] = np.array([1 + d, 1 - d])                  # the two cables are not equal
            reported = {"cable_length_m": L}
            how = f"cables {L * (1 + d):.3f} m and {L * (1 - d):.3f} m long (mean {L:.3f} m)"
        elif name == "distributed_mass":
            kg = float(given.get("distributed_mass_kg", rng.uniform(1.5, 3.0)))
            w = np.exp(0.3 * rng.standard_normal(N_SEGMENTS))                # uneven, not uniform
            pert["segment_mass_kg"] = kg * w / w.sum()
            reported = {"distributed_mass_kg": kg}
            how = f"{kg:.2f} kg spread unevenly (±30 % per segment) over all bars"
        elif name == "point_mass":
            kg = float(given.get("point_mass_kg", rng.uniform(0.8, 2.0)))
            at = tuple(given.get("point_mass_at", JOINTS_FT[rng.integers(NX * NY)]))
            pert["point_masses"] = _mass_patch(at, kg, elements_per_bar)
            reported, location = {"point_mass_kg": kg, "point_mass_at": tuple(map(float, at))}, tuple(map(float, at))
            how = f"a {kg:.2f} kg patch: 70 % on joint {location}, 30 % on the nearest mesh nodes around it"
        elif name == "loose_joint":
            k = float(given.get("loose_joint_stiffness", np.exp(rng.uniform(np.log(3.0), np.log(30.0)))))
            if "loose_joint_at" in given:
                at = tuple(given["loose_joint_at"])
            else:  # a border joint whose looseness stands above the bars' scatter (the detection limit)
                seen = [j for j in _BORDER_JOINTS if loose_joint_signature_pct(j, k) >= LOOSE_JOINT_LIMIT_PCT]
                at = seen[rng.integers(len(seen))]
            pert["joint_compliance"] = pert["joint_compliance"].copy()
            pert["joint_compliance"][joint_index(at)] += 1.0 / (k * np.array([0.9, 1.1]))   # unequal about x, y
            reported, location = ({"loose_joint_stiffness": k, "loose_joint_at": tuple(map(float, at))},
                                  tuple(map(float, at)))
            how = f"joint {location} semi-rigid: {0.9 * k:.1f} N·m/rad about x, {1.1 * k:.1f} about y"
        elif name == "gravity_stiffening":
            nominal = {"gravity": False}    # the truth hangs in gravity; the model handed to explain() lacks it
            reported = {"gravity": True}
            how = ("the grid hangs in gravity (as always); the nominal model to compare with omits the self-weight "
                   "tension")
        elif name == "member_stiffness":
            # a cracked member: bending stiffness mostly gone, torsion less (√ of the bending factor), where it
            # stands above the bars' scatter (the candidate scales E and G together: a different parametrisation)
            f = float(given.get("member_factor", round(rng.uniform(0.1, 0.3), 2)))
            if "member_at" in given:
                at = tuple(tuple(float(v) for v in j) for j in given["member_at"])
            else:
                seen = np.flatnonzero(member_signatures_pct(f) >= MEMBER_LIMIT_PCT)
                at = MEMBERS_FT[seen[rng.integers(seen.size)]]
            k = segment_index(at)
            ei[k] *= f
            gj[k] *= np.sqrt(f)
            reported, location = {"member_factor": f, "member_at": at}, at
            how = (f"the member between joints {at[0]} and {at[1]} ft is cracked: EI × {f:.2f}, GJ × "
                   f"{np.sqrt(f):.2f}")
        elif name == "damaged_bar":
            orientation, at = given.get("bar", (("x", "y")[rng.integers(2)], None))
            if at is None:
                at = float(rng.integers(NY if orientation == "x" else NX))
            factor = float(given.get("ei_factor", 0.5))
            segs = _segments_of_bar(orientation, float(at))
            if segs.size == 0:
                raise EraError(f"damaged_bar: no bar ({orientation!r}, {at}); use ('x', y_ft) or ('y', x_ft).")
            ei[segs] *= factor
            reported = {"bar": (orientation, float(at)), "ei_factor": factor}
            how = (f"outside the library: the {'horizontal' if orientation == 'x' else 'vertical'} bar at "
                   f"{'y' if orientation == 'x' else 'x'} = {float(at):g} ft has EI × {factor:g}")
        elif name == "ground_spring":
            k = float(given.get("stiffness_n_per_m", np.exp(rng.uniform(np.log(30.0), np.log(150.0)))))
            at = given.get("at")
            if at is None:
                at = tuple(JOINTS_FT[rng.integers(NX * NY)])
                # a spring to ground where a cable hangs is that cable's pendulum spring T/L made stiffer: in the
                # library (cable_length), not outside it, so no random draw puts one there
                while tuple(map(float, at)) in CABLES_FT:
                    at = tuple(JOINTS_FT[rng.integers(NX * NY)])
            at = tuple(at)
            springs = np.zeros(NX * NY)
            springs[joint_index(at)] = k
            pert["ground_springs"] = springs
            reported, location = {"stiffness_n_per_m": k, "at": tuple(map(float, at))}, tuple(map(float, at))
            how = f"outside the library: joint {location} tied to the ground by a {k:.0f} N/m spring (a snagged lead)"
        hidden.append({"name": name, "parameters": reported, "location": location, "description": how,
                       "in_library": name not in OUTSIDE_LIBRARY})
    truth = GridModel(nasa_grid(**params).params, GridPerturbation(**pert))
    return truth, hidden, nominal, stiffness_factor


def _mass_patch(at, kg: float, elements_per_bar: int) -> tuple:
    """A mass spread over a joint (70 %) and the nearest mesh nodes along its bars (30 %), not a point."""
    j = JOINTS_FT[joint_index(at)]
    if elements_per_bar < 2:
        return ((*j, kg),)
    h = 1.0 / elements_per_bar
    around = [j + d for d in ((h, 0), (-h, 0), (0, h), (0, -h))
              if 0 <= j[0] + d[0] <= NX - 1 and 0 <= j[1] + d[1] <= NY - 1]
    return ((*j, 0.7 * kg),) + tuple((*p, 0.3 * kg / len(around)) for p in around)


def free_decays(f_hz, zeta, phi_out, q0, v0, dt: float, n_samples: int) -> np.ndarray:
    """Modal superposition of damped free decays: (n_samples, p, m).

    f_hz, zeta : (r,) undamped natural frequencies (Hz) and damping ratios; phi_out : (p, r) mode shapes at the
    outputs; q0, v0 : (r, m) initial modal displacements and velocities of the m decays.
    q_r(t) = e^{-ζωt} [q0 cos ω_d t + (v0 + ζ ω q0)/ω_d sin ω_d t].
    """
    w = 2 * np.pi * np.asarray(f_hz, float)
    wd = w * np.sqrt(1 - np.asarray(zeta) ** 2)
    t = np.arange(n_samples)[:, None] * dt
    env, cos, sin = np.exp(-zeta * w * t), np.cos(wd * t), np.sin(wd * t)          # (N, r)
    q = (env * cos)[:, :, None] * q0 + (env * sin / wd)[:, :, None] * (v0 + (zeta * w)[:, None] * q0)
    return np.einsum("pr,nrm->npm", phi_out, q)


def simulate_grid_test(effect=None, seed: int = 0, duration_s: float = 40.0, noise: float = 0.03, *,
                       excitation: str = "impulse", inputs_ft=DEFAULT_INPUTS_FT, dwell_hz=None,
                       elements_per_bar: int = 4, scatter: float = 0.03, e_error: float = 0.01,
                       gain_error: float = 0.02, damping=(0.003, 0.01)) -> tuple[ResponseData, dict]:
    """Simulate a free-decay test of the grid with a hidden effect.

    Parameters
    ----------
    effect : None, str, dict, or a list of them (several effects hidden together, drawn in that order)
        None (no effect), one of EFFECTS, or one outside the library: "damaged_bar" (one whole bar, EI × 0.5)
        or "ground_spring" (one joint's w tied to the ground, 30-150 N/m); "member_stiffness" is a cracked
        member (EI × 0.1-0.3, GJ × its square root) where its signature exceeds MEMBER_LIMIT_PCT
        (member_signatures_pct);
        a dict {"name": ..., parameter: value} fixes parameters, named as nasa_grid's keywords
        (joint_stiffness, torsion_factor, cable_length_m, distributed_mass_kg, point_mass_kg and point_mass_at,
        loose_joint_stiffness and loose_joint_at; member_stiffness: member_factor (of EI), member_at
        ((x1, y1), (x2, y2)); damaged_bar: bar=("x", y_ft) or ("y", x_ft), ei_factor;
        ground_spring: at=(x_ft, y_ft), stiffness_n_per_m).
        Parameters not given are drawn from ``seed``, above the detection limits of explain; a loose joint
        (3-30 N·m/rad) only where its signature exceeds LOOSE_JOINT_LIMIT_PCT (see loose_joint_signature_pct).
        "gravity_stiffening": the truth hangs in gravity as always; ``truth["nominal_params"]`` is
        {"gravity": False}, i.e. the model to hand to explain() is nasa_grid(gravity=False).
    seed : int
        Everything random (parameters, scatter, damping, gains, noise) follows from it.
    duration_s : float
        Record length, s (N = duration_s × 32 samples).
    noise : float
        Gaussian noise standard deviation as a fraction of each record's RMS (per output and decay).
    excitation : "impulse" or "dwell"
        "impulse": unit out-of-plane impulses (1 N·s) at ``inputs_ft`` joints, so data are pulse responses
        Y[k] = C A^k B. "dwell": the paper's air jet at (10, 0), harmonic at each of ``dwell_hz`` (default
        the first 8 truth frequencies) until steady state, then switched off: free decays from 8 initial
        conditions.
    elements_per_bar, scatter, e_error, gain_error, damping
        Truth mesh (4 elements per 1-ft bar: 3-in elements, so a mass patch spans ±3 in around its joint, the
        footprint of a 1-2 kg block), lognormal σ of segment EI and GJ, |error| of E, σ of sensor gains, ζ range.

    Returns
    -------
    data : ResponseData (N, 9, m), dt = 1/32 s, outputs in model.sensors order, w in mm;
        data.meta["input_locations"] : the m input joints (x_ft, y_ft).
    truth : dict with "frequency_hz" (r,), "damping_ratio" (r,), "shapes" (9, r) and "node_shapes" (88, r)
        mass-normalised (1/√kg, no gain errors) for every mode in the band, "effect" {name ("none" when
        no effect), parameters (in the candidate's terms), location, description, in_library (False only for
        effects the candidate library cannot represent)} of the first hidden effect, "effects" (one such dict per
        hidden effect, in the order given), "nominal_params" (for nasa_grid), "stiffness_factor", "gains" (9,),
        "inputs_ft", "model" (the truth GridModel), "seed".
    """
    effects = _parse_all(effect)
    if excitation not in ("impulse", "dwell"):
        raise EraError(f"excitation must be 'impulse' or 'dwell', got {excitation!r}.")
    if not (duration_s > 0 and 0 <= noise < 1):
        raise EraError("duration_s must be positive and noise a fraction in [0, 1).")
    rng = np.random.default_rng(seed)
    truth_model, hidden, nominal, sf = _truth_model(
        effects, rng, elements_per_bar=elements_per_bar, scatter=scatter, e_error=e_error)
    dt = 1.0 / SAMPLE_RATE_HZ
    f_all, phi_nodes = truth_model.node_modes(30)
    band = f_all < 0.85 * SAMPLE_RATE_HZ / 2
    f, phi_nodes = f_all[band], phi_nodes[:, band]
    zeta = rng.uniform(*damping, size=f.size)
    phi_sens = phi_nodes[[joint_index(s) for s in SENSORS_FT]]
    if excitation == "impulse":
        inputs = [tuple(map(float, a)) for a in inputs_ft]
        v0 = phi_nodes[[joint_index(a) for a in inputs]].T                   # (r, m): q̇(0+) = φ_j · 1 N·s
        q0 = np.zeros_like(v0)
        labels = tuple(f"impulse at ({a[0]:g},{a[1]:g}) ft" for a in inputs)
    else:
        omega = 2 * np.pi * np.asarray(f[:8] if dwell_hz is None else dwell_hz, float)
        inputs = [AIR_JET_FT] * omega.size
        w = 2 * np.pi * f
        h = phi_nodes[joint_index(AIR_JET_FT)][:, None] / (w[:, None] ** 2 - omega ** 2
                                                           + 2j * (zeta * w)[:, None] * omega)   # 1 N force
        q0, v0 = h.real, (1j * omega * h).real
        labels = tuple(f"air jet at {x / 2 / np.pi:.3f} Hz" for x in omega)
    n = int(round(duration_s * SAMPLE_RATE_HZ))
    y = 1e3 * free_decays(f, zeta, phi_sens, q0, v0, dt, n)                   # m -> mm
    gains = 1 + gain_error * rng.standard_normal(len(SENSORS_FT))
    y = y * gains[None, :, None]
    rms = np.sqrt((y ** 2).mean(axis=0))
    y = y + noise * rms * rng.standard_normal(y.shape)
    data = ResponseData(markov=y, dt=dt, outputs=tuple(f"w({x:g},{yy:g}) ft" for x, yy in SENSORS_FT),
                        inputs=labels, output_units=("mm",) * len(SENSORS_FT),
                        input_units=("N·s" if excitation == "impulse" else "N",) * len(labels),
                        meta={"source": "era.examples.grid_simulation.simulate_grid_test", "seed": seed, "excitation": excitation,
                              "input_locations": tuple(inputs)})
    truth = {"frequency_hz": f, "damping_ratio": zeta, "shapes": phi_sens, "node_shapes": phi_nodes,
             "effect": hidden[0], "effects": tuple(hidden),
             "nominal_params": nominal, "stiffness_factor": sf, "gains": gains, "inputs_ft": tuple(inputs),
             "noise": noise, "model": truth_model, "seed": seed}
    return data, truth
