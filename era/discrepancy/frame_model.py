"""An era.Frame as a model explain() can change: its parameters and their modes (the frame effect library, with
the candidate places, is effects_frame.frame_effects).

explain() needs a model that implements era.discrepancy.protocol.ExplainModel. :class:`FrameModel` gives it to an
era.Frame without changing it: each parameter set is a new Frame (a section scaled, a spring, a mass, ...) that keeps the
nominal's mesh (``Frame.element_counts``). Its modes come from the nominal's reduced model (era.fem.reduced: the
nominal's 30 modes plus static vectors for the places the parameters name, one small dense eigenproblem per
parameter set) when the frame allows it; ``.exact`` is the same parameter set solved in full, which explain uses
for the finalists (:func:`refit_exact`) and the report.

Locations: a node id (str) for effects at a node or a support, a tuple (node i, node j) for a member.
Parameters are SI (docs/effects.md says what each effect changes).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import DataError
from ..fem import space
from ..fem.reduced import ReducedFrame, reducible
from ..structure import Frame, Section
from ..words import listed
from .effects import Param
from .fitting import TRIAL_FAILURES, fit_effect
from .protocol import RitzModes, scale_sensitivity

DEFAULTS = dict(stiffness_factor=1.0, gravity=True, support_at=None, support_rotation_stiffness=None,
                support_vertical_stiffness=None, joint_at=None, joint_stiffness=None, point_mass_at=None,
                point_mass_kg=0.0, member_at=None, member_factor=1.0, distributed_mass_kg=0.0)
#: The model-form allowance of a frame described by hand (ErrorLevels.model_form, model_form_shape): 1.3 % (1σ) on
#: each frequency, 0.019 on each unit-shape component, on top of the floors and the members' 2 % scatter.
#: Calibrated once against truths solved by independent code (OpenSees: other elements and mesh, rigid end zones,
#: joint eccentricities, lumped mass, sections and materials scattered; the grid, a truss footbridge and a portal)
#: with nothing hidden, seeds 10-15 (not those of the confusion matrix): for each structure, the allowance that
#: makes its nominal's mean χ² per frequency (per shape component) 1; the constant covers 9 structures in 10
#: (the 90th percentile of the 18: 1.26 %, 0.0189), not the average one (tests/bench/bench_explain_model_form.py,
#: docs/explain-accuracy.md).
MODEL_FORM = (0.013, 0.019)
ALL_MEMBERS = ("*",)     # member_stiffness of the group of every member (the whole structure softer than drawn)


def _scaled(sec: Section, factor: float) -> Section:
    return dataclasses.replace(sec, e=sec.e * factor, g=sec.g * factor)


@dataclass(frozen=True, eq=False)
class FrameModel:
    """An era.Frame with the explain parameters (DEFAULTS) applied; immutable, modes cached.

    Made by :meth:`of`; :meth:`with_params` gives a variant. The parameters: stiffness_factor (E and G of every
    section); gravity (geometric stiffness of the self-weight, when the frame has a gravity vector); support_at +
    support_rotation_stiffness (N·m/rad on both bending rotations of a fixed support) or support_vertical_stiffness
    (N/m on the vertical translation of a pinned one); joint_at + joint_stiffness (N·m/rad, Frame.joint_springs);
    point_mass_at + point_mass_kg; member_at (i, j) + member_factor (its E and G; member_at ALL_MEMBERS: every
    member); distributed_mass_kg (spread uniformly by length over every member).

    Parameters
    ----------
    frame : Frame
        The nominal frame (its mesh is fixed to ``element_counts`` of the nominal, for ``n_mesh`` modes).

    Examples
    --------
    >>> strip = era.Section.rectangle(0.05, 0.01)
    >>> frame = era.Frame(nodes={"1": (0, 0, 0), "2": (0.5, 0, 0), "3": (1, 0, 0)},
    ...                   members=[("1", "2", "strip"), ("2", "3", "strip")], sections={"strip": strip},
    ...                   supports={"1": "fixed"}, sensors=[("2", "z"), ("3", "z")])
    >>> nominal = era.FrameModel.of(frame)
    >>> print(np.round(nominal.modes(2)[0], 2))
    [ 8.15 40.77]
    >>> print(np.round(nominal.with_params(point_mass_at="3", point_mass_kg=0.5).modes(2)[0], 2))  # 0.5 kg at tip
    [ 6.62 33.12]
    """

    frame: Frame
    _params: dict = field(default_factory=dict)
    _shared: dict | None = None

    @classmethod
    def of(cls, frame: Frame, n_mesh: int = 10, gravity: bool = True, reduced: bool = True) -> "FrameModel":
        """The nominal FrameModel of ``frame``, its mesh fixed to the automatic mesh for ``n_mesh`` modes.

        era.DataError when the frame has no sensors.

        Parameters
        ----------
        frame : Frame
            The structure, with its sensors.
        n_mesh : int, optional
            The number of elastic modes the mesh is converged for (default 10).
        gravity : bool, optional
            Include the self-weight's geometric stiffness when the frame has a gravity vector (default True).
        reduced : bool, optional
            Solve variants in the nominal's reduced model where it applies (era.fem.reduced; default True).
        """
        if not frame.sensors:
            raise DataError("explain: the Frame has no sensors: list (node, direction) for each output channel.")
        if frame.elements_per_member is None:    # meshed for n_mesh elastic modes (a free frame's rigid ones on top)
            frame = dataclasses.replace(frame, elements_per_member=frame.element_counts(n_mesh + frame.n_rigid_modes))
        on = bool(gravity and frame.gravity is not None)
        return cls(frame, {**DEFAULTS, "gravity": on}, {"gravity": on} if reduced else None)

    @property
    def exact(self) -> "FrameModel":
        """The same parameter set, solved in full (the mesh assembled and a sparse eigensolve)."""
        return self if self._shared is None else FrameModel(self.frame, self._params, None)

    @property
    def params(self) -> dict:
        return dict(self._params)

    @property
    def sensors(self) -> tuple:
        return self.frame.sensors

    def with_params(self, **changes) -> "FrameModel":
        unknown = set(changes) - set(DEFAULTS)
        if unknown:
            raise DataError(f"FrameModel: unknown {'parameters' if len(unknown) > 1 else 'parameter'} "
                            f"{listed(sorted(unknown), quote=True)}; known: {listed(sorted(DEFAULTS), quote=True)}.")
        return FrameModel(self.frame, {**self._params, **changes}, self._shared)

    @property
    def updated_frame(self) -> Frame:
        """The era.Frame these parameters describe (the nominal with the effect put in), e.g. to save."""
        cache = self.__dict__.get("_frame")
        if cache is None:
            cache = self.__dict__["_frame"] = self._build()
        return cache

    def _build(self) -> Frame:
        p, fr = self._params, self.frame
        sections = {k: _scaled(s, p["stiffness_factor"]) for k, s in fr.sections.items()}
        members = list(fr.members)
        if tuple(p["member_at"] or ()) == ALL_MEMBERS:
            sections = {k: _scaled(s, p["member_factor"]) for k, s in sections.items()}
        elif p["member_at"] is not None and p["member_factor"] != 1.0:
            k = self.member_index(p["member_at"])
            i, j, sec, orient = members[k]
            name = f"{sec}@{i}-{j}"
            sections[name] = _scaled(sections[sec], p["member_factor"])
            members[k] = (i, j, name, orient)
        supports = {n: dict(s) for n, s in fr.supports.items()}
        if p["support_at"] is not None:
            spec = supports[str(p["support_at"])]
            if p["support_rotation_stiffness"] is not None:
                for key in self.bending_rotations(str(p["support_at"])):
                    spec[key] = float(p["support_rotation_stiffness"])
            if p["support_vertical_stiffness"] is not None:
                spec[("kx", "ky", "kz")[int(np.argmax(np.abs(fr.vertical)))]] = float(p["support_vertical_stiffness"])
        masses = dict(fr.masses)
        if p["point_mass_at"] is not None and p["point_mass_kg"] > 0:
            masses[str(p["point_mass_at"])] = masses.get(str(p["point_mass_at"]), 0.0) + float(p["point_mass_kg"])
        joints = dict(fr.joint_springs)
        if p["joint_at"] is not None and p["joint_stiffness"] is not None:
            joints[str(p["joint_at"])] = float(p["joint_stiffness"])
        added = dict(fr.added_mass_per_length)
        if p["distributed_mass_kg"] > 0:
            per_m = float(p["distributed_mass_kg"]) / self.total_length_m
            for name in {m[2] for m in members}:
                added[name] = added.get(name, 0.0) + per_m
        return dataclasses.replace(fr, sections=sections, members=tuple(members),
                                   supports={n: {k: ("fixed" if math.isinf(v) else v) for k, v in s.items()}
                                             for n, s in supports.items()},
                                   masses=masses, joint_springs=joints, added_mass_per_length=added,
                                   gravity=fr.gravity if p["gravity"] else None)

    @property
    def total_length_m(self) -> float:
        got = self.frame.__dict__.get("_total_length_m")     # the members do not change between variants
        if got is None:
            nodes = self.frame.nodes
            got = self.frame.__dict__["_total_length_m"] = float(sum(
                np.linalg.norm(np.subtract(nodes[j], nodes[i])) for i, j, *_ in self.frame.members))
        return got

    def member_index(self, at) -> int:
        a, b = (str(n) for n in at)
        for k, (i, j, *_) in enumerate(self.frame.members):
            if {i, j} == {a, b}:
                return k
        raise DataError(f"FrameModel: no member between nodes {a} and {b}.")

    def bending_rotations(self, node: str) -> tuple:
        """The two support keys of the rotations about the horizontal axes (bending of a column at its base)."""
        up = int(np.argmax(np.abs(self.frame.vertical)))
        return tuple(k for a, k in enumerate(("rx", "ry", "rz")) if a != up)

    @property
    def n_rigid(self) -> int:
        """6 for a free structure (no support, spring or cable, no gravity: it hangs on soft cords the model leaves
        out), whose six rigid-body modes come first at 0 Hz; 0 otherwise. :meth:`modes`, :meth:`node_modes` and
        :meth:`ritz` leave them out: no measured mode is paired with a rigid-body motion."""
        return self.frame.n_rigid_modes

    # the modes
    def _reduced(self, n_modes: int, screen: bool = False):
        """(f (n,), translations (n_user, 3, n)) from the reduced model, or None when it does not apply (no
        reduced model, a spring made rigid, more modes than its basis answers well).
        screen: a changed member in the nominal's modes alone (to rank places), not with its attachment modes."""
        if self._shared is None:
            return None
        cache = self.__dict__.setdefault("_screen_modes" if screen else "_reduced_modes", {})
        got = next((v for k, v in cache.items() if k >= n_modes), None)
        if got is not None:
            return got[0][:n_modes], got[1][..., :n_modes]
        p, fr = self._params, self.frame
        cables = any("cable" in s for s in fr.supports.values())
        if cables and not p["gravity"]:
            return None
        if "reduced" not in self._shared:
            # the basis: the nominal's modes (its gravity as FrameModel.of was given it), 30 of them or 10 more
            # than the first request asks (the modes explain compares)
            basis = fr if self._shared["gravity"] or fr.gravity is None else dataclasses.replace(fr, gravity=None)
            self._shared["reduced"] = ReducedFrame(basis, max(30, n_modes + 10), fr.gravity) if (
                reducible(fr) and not (cables and not self._shared["gravity"])) else None
        red = self._shared["reduced"]
        values = [p[k] for k in ("stiffness_factor", "member_factor", "point_mass_kg", "distributed_mass_kg",
                                 "support_rotation_stiffness", "support_vertical_stiffness", "joint_stiffness")]
        if red is None or not all(v is None or math.isfinite(v) for v in values) or red.n_basis < n_modes + 10:
            return None
        support, joint, mass_at, member = self._places()
        if member == "all":     # every member: a scaling, but for nominal joint springs (hinges), which stay
            extend = "all" if red.mesh.hinges else None
        else:
            extend = None if screen or member is None else member
        pieces = red.pieces(support, joint, mass_at, extend)
        got = red.modes(n_modes, pieces, stiffness_factor=p["stiffness_factor"],
                        member=member, member_factor=p["member_factor"],
                        k_rot=p["support_rotation_stiffness"] or 0.0, k_vert=p["support_vertical_stiffness"] or 0.0,
                        k_joint=p["joint_stiffness"] or 0.0, point_mass_kg=p["point_mass_kg"] if mass_at else 0.0,
                        spread_kg_per_m=p["distributed_mass_kg"] / self.total_length_m,
                        gravity=bool(p["gravity"] and fr.gravity is not None))
        cache[n_modes] = got
        return got

    def _places(self) -> tuple:
        """The reduced model's configuration of these parameters: support (node, released rotation keys, released
        vertical keys) or None, joint node, point-mass node (or None each), member index, "all" or None."""
        p, fr = self._params, self.frame
        support = None
        if p["support_at"] is not None:
            node = str(p["support_at"])
            up = ("kx", "ky", "kz")[int(np.argmax(np.abs(fr.vertical)))]
            support = (node, self.bending_rotations(node) if p["support_rotation_stiffness"] is not None else (),
                       (up,) if p["support_vertical_stiffness"] is not None else ())
        joint = str(p["joint_at"]) if p["joint_at"] is not None and p["joint_stiffness"] is not None else None
        mass_at = str(p["point_mass_at"]) if p["point_mass_at"] is not None and p["point_mass_kg"] > 0 else None
        for at in (support and support[0], joint, mass_at):
            if at is not None and at not in fr.nodes:
                raise DataError(f"FrameModel: no node {at!r} in the frame.")
        member: int | str | None = None
        if tuple(p["member_at"] or ()) == ALL_MEMBERS:
            member = "all"
        elif p["member_at"] is not None and p["member_factor"] != 1.0:
            member = self.member_index(p["member_at"])
        return support, joint, mass_at, member

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised translations (3·n_nodes, n), rows node-major (x, y, z of each
        node in Frame.node_ids order), 1/√kg.

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        r = self.n_rigid
        got = self._reduced(n_modes + r)
        f, u = self.updated_frame.node_modes(n_modes + r) if got is None else got
        return f[r:], u.reshape(-1, u.shape[-1])[:, r:]

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """The lowest ``n_modes`` elastic modes: frequencies (n,) Hz and the sensors' shapes (n_sensors, n).

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        r = self.n_rigid
        got = self._reduced(n_modes + r)
        if got is None:
            f, s = self.updated_frame.modes(n_modes + r)
            return f[r:], s[:, r:]
        f, u = got
        return f[r:], self.frame.at_sensors(u[..., r:])

    def ritz(self, reference: "FrameModel", n_modes: int) -> "RitzModes | None":
        """This model's modes in the span of ``reference``'s lowest ``n_modes`` modes (Frame.ritz_modes), for
        screening places (ranking.screen_locations); None when the two are not meshed alike. On the reduced path
        (the reference's own reduced model), the reduced model's modes with a changed member in the nominal's
        modes alone (ReducedFrame.pieces without its attachment modes), as many as its basis answers well."""
        if self._shared is not None and self._shared is reference._shared:
            red = self._shared.get("reduced")     # as many modes as its basis answers well
            got = self._reduced(red.n_basis - 10 if red is not None else max(1, n_modes - 10), screen=True)
            if got is not None:
                f, u = got[0][self.n_rigid:], got[1][..., self.n_rigid:]
                return RitzModes(f, u.reshape(-1, u.shape[-1]), self.frame.at_sensors(u))
        got = self.updated_frame.ritz_modes(reference.updated_frame, n_modes)
        if got is None:
            return None
        f, u = got[0][self.n_rigid:], got[1][..., self.n_rigid:]
        return RitzModes(f, u.reshape(-1, u.shape[-1]), self.updated_frame.at_sensors(u))

    def screening_ritz(self, reference: "FrameModel", n_modes: int) -> "RitzModes | None":
        """The approximation used to screen places: :meth:`ritz` itself."""
        return self.ritz(reference, n_modes)

    has_ritz = True     # .ritz approximates a variant's modes (the reduced model, or Frame.ritz_modes)

    @property
    def joints_ft(self) -> np.ndarray:
        """(0, 2): a frame's located effects list their own places (node ids, members), not grid joints."""
        return np.zeros((0, 2))

    @property
    def node_labels(self) -> tuple:
        """Label of each row of :meth:`node_modes`: "node:x", "node:y", "node:z"."""
        return tuple(f"{n}:{a}" for n in self.frame.node_ids for a in "xyz")

    def modal_rows(self, input_locations) -> tuple | None:
        """Rows of node_modes at the sensors and at the given input points ((node, direction) each), or None when
        a sensor or an input is not along a global axis."""
        index = {n: k for k, n in enumerate(self.frame.node_ids)}

        def row(node, d):
            if not isinstance(d, str) or d.startswith("-") or str(node) not in index:
                return None
            return 3 * index[str(node)] + "xyz".index(d)

        try:
            rows = [row(n, d) for n, d in self.frame.sensors], [row(n, d) for n, d in input_locations]
        except (TypeError, ValueError):
            return None
        return None if None in rows[0] or None in rows[1] else rows

    @property
    def total_mass_kg(self) -> float:
        return self.updated_frame.total_mass_kg

    default_member_scatter = 0.02     # ErrorLevels.member_scatter when not given: members known to ±2 % (1σ)
    default_model_form = MODEL_FORM   # ErrorLevels.model_form(_shape) when not given (see MODEL_FORM)

    def member_energy_fractions(self, n_modes: int = 10) -> np.ndarray:
        """(n_members, n) each member's share of each mode's elastic strain energy (columns sum to 1 over the
        members; springs, hinges and geometric stiffness left out)."""
        _, _, cross = self._member_modal_stiffness(n_modes)
        out = np.einsum("ejj->ej", cross)[:, :n_modes]
        return out / np.maximum(out.sum(axis=0, keepdims=True), 1e-300)

    def member_shape_sensitivity(self, n_modes: int = 10, n_basis: int = 30) -> np.ndarray:
        """(n_members, p, n) d ψ_j / d a_e: how each unit-norm sensor shape ψ_j moves per unit relative change a_e
        of member e's E and G (its elastic stiffness K_e), by modal superposition over the lowest
        max(n, n_basis) modes (Fox & Kapoor 1968; mass unchanged): dφ_j = Σ_{k≠j} φ_k (φ_kᵀ K_e φ_j)/(λ_j − λ_k),
        then projected normal to ψ_j. Zero for modes the sensors do not see. With members known to ±σ each,
        ψ_j's components scatter by σ √(Σ_e (dψ_j/da_e)²) (the shapes' share of the model-form error)."""
        u, du = self._node_mode_sensitivity(n_modes, n_basis)
        on = lambda x: self.frame.at_sensors(x.reshape(x.shape[:-2] + (-1, 3, x.shape[-1])))    # noqa: E731
        s, ds = on(u), on(du)
        norm = np.linalg.norm(s, axis=0)
        seen = norm > 1e-9 * max(norm.max(), 1e-300)
        psi = s / np.where(seen, norm, 1.0)
        dpsi = (ds - psi[None] * np.einsum("pj,epj->ej", psi, ds)[:, None, :]) / np.where(seen, norm, 1.0)
        return np.where(seen[None, None, :], dpsi, 0.0)

    def member_scale_sensitivity(self, node_rows, n_modes: int = 10, n_basis: int = 30) -> np.ndarray:
        """(n_members, n) d ln‖P_j‖ / d a_e: how the size of mode j's modal constants P_j = φ_j(sensors) φ_j(inputs)ᵀ
        (node_rows: their rows of node_modes, as ModeWeights.node_rows) moves per unit relative change of member
        e's E and G (mass-normalised φ: the mass does not change, the share of the mode's motion at those points
        does). By the same modal superposition as :meth:`member_shape_sensitivity`."""
        u, du = self._node_mode_sensitivity(n_modes, n_basis)
        return scale_sensitivity(u, du, node_rows)

    def _node_mode_sensitivity(self, n_modes: int, n_basis: int) -> tuple:
        """Node translations u (3·n_nodes, n) and their changes du (n_members, 3·n_nodes, n) per unit relative
        change of each member's stiffness, dφ_j = Σ_{k≠j} φ_k (φ_kᵀ K_e φ_j)/(λ_j − λ_k) over max(n, n_basis)
        modes."""
        f, u, cross = self._member_modal_stiffness(max(n_modes, n_basis))
        lam = (2 * np.pi * f) ** 2
        diff = lam[None, :] - lam[:, None]                        # [k, j] = λ_j − λ_k
        apart = np.abs(diff) > 1e-9 * lam.max()
        inv = np.where(apart, 1.0 / np.where(apart, diff, 1.0), 0.0)
        return u[:, :n_modes], np.einsum("rk,ekj,kj->erj", u, cross, inv)[:, :, :n_modes]

    def _member_modal_stiffness(self, n_modes: int) -> tuple:
        """f (n,) Hz, the nodes' mass-normalised translations (3·n_nodes, n) and Φᵀ K_e Φ (n_members, n, n) of
        each member's elastic stiffness K_e, from one full solve of this parameter set (cached)."""
        cache = self.__dict__.setdefault("_member_modal", {})
        got = next((v for k, v in cache.items() if k >= n_modes), None)
        if got is None:
            frame, r = self.updated_frame, self.n_rigid      # the elastic modes, as :meth:`modes` gives them
            mesh, result = frame.solution(n_modes + r)
            n = min(int(n_modes), result.frequency_hz.size - r)
            L, R = mesh.axes
            k = space.beam3d.to_global(space.beam3d.local_stiffness(L, mesh.EA, mesh.GJ, mesh.EIy, mesh.EIz), R)
            u = result.shapes.reshape(-1, result.shapes.shape[-1])[mesh.edofs()][:, :, r:r + n]     # (e, 12, n)
            per_element = np.einsum("eik,eij,ejn->ekn", u, k, u)
            cross = np.zeros((len(self.frame.members), n, n))
            np.add.at(cross, mesh.member, per_element)
            f, u = frame.node_modes(n + r)
            got = cache[n] = (f[r:], u.reshape(-1, n + r)[:, r:], cross)
        f, u, cross = got
        return f[:n_modes], u[:, :n_modes], cross[:, :n_modes, :n_modes]


def refit_exact(model: FrameModel, found, nuisance: Param, measured, w, n_model: int, min_share: float = 0.05,
                max_places: int = 1):
    """The search's named set (era.discrepancy.search.Search) re-fitted in the full model, from the reduced
    model's optimum (a few Gauss-Newton steps, each 1 + n_parameters full solves): the reported parameters,
    uncertainties and gap are the full model's. So are the last named effect's other places that hold at least
    ``min_share`` of its place probability, the ``max_places`` most probable of them (re-fitted there too; the
    rest keep their reduced evidence, which the model-form allowance makes as good: 0.1 % against 1.3 %). The
    screening, the ranking of candidates and the search stay the reduced model's."""
    fit = found.fit
    if fit is None or fit.model.exact is fit.model:     # solved in full already: nothing to re-fit
        return found
    def refit(at):
        try:
            return fit_effect(model.exact, fit.spec, nuisance, measured, w, n_model, location=at, u0=fit.u)
        except TRIAL_FAILURES:     # the full model cannot be solved there: the reduced model's fit stands
            return None

    def _evidence(f, le):
        return le if f is None else f.log_evidence

    exact = refit(fit.location)
    if exact is None:
        return found
    last = found.named[-1]
    if len(last.locations) < 2 or all(q < min_share for _, _, q in last.locations[1:]):
        return dataclasses.replace(found, fit=exact)
    places = [(exact.location, exact.log_evidence)] + [
        (at, _evidence(refit(at) if q >= min_share and k < max_places else None, le))
        for k, (at, le, q) in enumerate(last.locations[1:], start=1)]
    les = np.array([le for _, le in places])
    t_place = found.specs[-1].place_temperature     # as ranking.place_posterior weighs the places
    share = np.exp((les - les.max()) / t_place)
    share /= share.sum()
    order = np.argsort(-les, kind="stable")
    if order[0] != 0:    # (rare) the full model prefers another place: the named place and its probabilities stay
        # the search's, its parameters are re-fitted there
        return dataclasses.replace(found, fit=exact)
    last = dataclasses.replace(last, locations=tuple((places[i][0], float(les[i]), float(share[i])) for i in order))
    return dataclasses.replace(found, fit=exact, named=found.named[:-1] + (last,))
