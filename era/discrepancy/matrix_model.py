"""An FE model given as matrices (era.models.MatrixModel) as a model explain() can change: its parameters are
the effects of era.models.changes (a point mass, a spring to ground, a part's stiffness or mass off by a factor,
spread mass) and its modes come, as a frame's do, from the nominal's reduced model: the nominal's lowest modes
plus the static deflections under a unit load at the DOFs the parameters change (a Rayleigh-Ritz basis, one
small dense eigenproblem per parameter set). ``.exact`` is the same parameter set solved in full (a sparse
eigensolve), which explain uses for the named set's parameters and the report.

Locations: a node label for a point mass, "node:direction" for a spring to ground, "part:name" for a part.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from ..errors import DataError
from ..fem.eigen import sparse_modes
from ..models.changes import EFFECT_DEFAULTS, changed_matrices, part_name, pieces
from ..models.matrix import TRANSLATIONS, MatrixModel
from ..words import listed
from .frame_model import MODEL_FORM
from .protocol import RitzModes, scale_sensitivity

#: A mode of the nominal is rigid when its frequency is below this fraction of the highest basis mode's.
RIGID = 1e-4


def _solve_subspace(k: np.ndarray, m: np.ndarray, n_modes: int, shift: float,
                    scale: float) -> tuple[np.ndarray, np.ndarray]:
    """The lowest n_modes of k y = λ m y (r, r) in a Ritz basis: shift-inverted, m y = μ (k + c m) y, so that
    directions without mass (μ = 0) drop out instead of breaking the solve; (λ (n,), y (r, n), yᵀ m y = 1).
    scale : the size of the structure's own reduced stiffness, below which a direction counts as dependent (a
    spring far stiffer than the structure must not make the others look dependent)."""
    try:     # the usual case, M positive definite in the basis: one generalised eigenproblem
        lam, y = scipy.linalg.eigh(k, m, subset_by_index=[0, n_modes - 1], check_finite=False)
        if lam[0] > -1e-8 * scale and lam.size == n_modes:
            return lam, y
    except (np.linalg.LinAlgError, ValueError):
        pass
    g = k + shift * m
    d, v = scipy.linalg.eigh(0.5 * (g + g.T))
    if d.max() <= 0:
        raise np.linalg.LinAlgError("the reduced stiffness is not positive")
    keep = d > 1e-12 * scale
    if np.any(d < -1e-8 * scale):
        raise np.linalg.LinAlgError("the reduced stiffness is indefinite (a negative spring or factor)")
    w = v[:, keep] / np.sqrt(d[keep])
    mu, z = np.linalg.eigh(w.T @ m @ w)
    order = np.argsort(-mu)[:n_modes]
    mu, y = mu[order], w @ z[:, order]
    if mu.size < n_modes or np.any(mu <= 1e-14 * max(mu.max(), 1e-300)):
        raise np.linalg.LinAlgError("fewer modes with mass than asked in the reduced model")
    y = y / np.sqrt(np.maximum(np.einsum("ij,ij->j", y, m @ y), 1e-300))
    return 1.0 / mu - shift, y


@dataclass(frozen=True, eq=False)
class MatrixExplainModel:
    """A MatrixModel with the explain parameters (era.models.changes.EFFECT_DEFAULTS); immutable, modes cached.

    Made by :meth:`of`; :meth:`with_params` gives a variant (point_mass_at + point_mass, spring_at +
    spring_stiffness, part_at + part_factor, part_mass_at + part_mass_factor, distributed_mass,
    stiffness_factor).

    Parameters
    ----------
    model : MatrixModel
        The nominal model.
    sensors : tuple of (node, direction)
        The test's points, one per output channel (a direction may carry a sign, "-z").
    reduced : bool, optional
        Solve parameter sets in the nominal's reduced model (False: every one in full, ``.exact``).

    Examples
    --------
    >>> k = 1e5 * (2 * np.eye(6) - np.eye(6, k=1) - np.eye(6, k=-1))  # six 1 kg masses on springs of 100 kN/m
    >>> k[-1, -1] = 1e5  # the top is free; below node 1 the chain is fixed to ground
    >>> dofs = [(str(i + 1), "z") for i in range(6)]
    >>> model = era.MatrixModel(k, np.eye(6), dofs, sensors=dofs)
    >>> nominal = era.MatrixExplainModel.of(model, dofs)
    >>> print(np.round(nominal.modes(2)[0], 2))
    [12.13 35.69]
    >>> print(np.round(nominal.with_params(point_mass_at="4", point_mass=0.5).exact.modes(2)[0], 2))
    [11.54 35.53]
    """

    model: MatrixModel
    sensors: tuple
    _params: dict = field(default_factory=dict)
    _shared: dict = field(default_factory=dict)
    reduced: bool = True

    @classmethod
    def of(cls, model: MatrixModel, sensors=None, reduced: bool = True) -> "MatrixExplainModel":
        """The nominal model of ``model`` seen at ``sensors``.

        Parameters
        ----------
        model : MatrixModel
            The engineer's model.
        sensors : sequence of (node, direction)
            One per output channel, in channel order (era.explain passes the model's own ``sensors``, or the
            points the data's output labels name).
        reduced : bool, optional
            Solve parameter sets in the nominal's reduced model (default True).

        Returns
        -------
        MatrixExplainModel

        Raises
        ------
        era.DataError
            When there are no sensors, or a sensor is not a free DOF of the model.
        """
        points = tuple((str(n).strip(), str(d).strip().lower()) for n, d in (sensors or ()))
        if not points:
            raise DataError("explain: the matrix model has no sensors: give the test's points as (node, direction) "
                            "per output channel, in channel order (MatrixExplainModel.of(model, sensors)).")
        model.at(points)     # every point is a free DOF of the model, else a DataError naming it
        return cls(model, points, dict(EFFECT_DEFAULTS), {}, reduced)

    @property
    def params(self) -> dict:
        return dict(self._params)

    @property
    def exact(self) -> "MatrixExplainModel":
        """The same parameter set, solved in full (a sparse eigensolve of the changed matrices)."""
        return self if not self.reduced else MatrixExplainModel(self.model, self.sensors, self._params,
                                                                self._shared, False)

    def with_params(self, **changes) -> "MatrixExplainModel":
        unknown = set(changes) - set(EFFECT_DEFAULTS)
        if unknown:
            raise DataError(f"MatrixExplainModel: unknown {'parameters' if len(unknown) > 1 else 'parameter'} "
                            f"{listed(sorted(unknown), quote=True)}; known: "
                            f"{listed(sorted(EFFECT_DEFAULTS), quote=True)}.")
        return MatrixExplainModel(self.model, self.sensors, {**self._params, **changes}, self._shared, self.reduced)

    @property
    def changed(self) -> MatrixModel:
        """The MatrixModel these parameters describe (the nominal with the effects put in)."""
        k, m = changed_matrices(self.model, self._params)
        return self.model.with_matrices(k, m)

    # -- the nominal's basis -------------------------------------------------------------------------------
    def _basis(self, n_modes: int) -> tuple:
        """(λ (r,), Φ (n_dofs, r), n_rigid): the nominal's lowest r = max(36, n + 16) modes, shared."""
        got = self._shared.get("basis")
        if got is None or got[0].size < n_modes + 10 + got[2]:
            r = min(max(36, n_modes + 16 + (got[2] if got else 0)), self.model.n_dofs)
            f, phi = sparse_modes(self.model.stiffness, self.model.mass, r)
            n_rigid = int(np.sum(f < RIGID * f.max()))
            got = self._shared["basis"] = ((2 * np.pi * f) ** 2, phi, n_rigid)
            self._shared.pop("projected", None)
        return got

    @property
    def n_rigid(self) -> int:
        return self._basis(1)[2]

    def nominal_basis(self) -> tuple[np.ndarray, np.ndarray]:
        """The nominal's elastic basis modes: λ (r,) (rad/s)² and mass-normalised shapes (n_dofs, r)."""
        lam, phi, r = self._basis(1)
        return lam[r:], phi[:, r:]

    def _projected(self, extra: tuple) -> dict:
        """The Ritz basis T (nominal modes, then the static deflections at the ``extra`` rows) and its projected
        nominal matrices, cached per set of rows."""
        lam, phi, _ = self._basis(1)
        cache = self._shared.setdefault("projected", {})
        got = cache.get(extra)
        if got is not None:
            return got
        k, m = self.model.stiffness, self.model.mass
        t = phi
        if extra:
            lu = self._shared.get("lu")
            shift = self._shift()
            if lu is None:
                lu = self._shared["lu"] = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(k + shift * m))
            e = np.zeros((self.model.n_dofs, len(extra)))
            e[list(extra), np.arange(len(extra))] = 1.0
            a = lu.solve(e)
            a = a - phi @ (phi.T @ (m @ a))              # M-orthogonal to the modes
            a = a / np.maximum(np.linalg.norm(a, axis=0), 1e-300) * np.linalg.norm(phi[:, 0])
            t = np.hstack([phi, a])
        got = cache[extra] = {"t": t, "k": t.T @ (k @ t), "m": t.T @ (m @ t), "parts": {}}
        if len(cache) > 64:          # places screened long ago
            cache.pop(next(iter(cache)))
        return got

    def _shift(self) -> float:
        lam = self._basis(1)[0]
        return 1e-3 * float(lam[min(self.n_rigid, lam.size - 1)]) if lam.size else 1.0

    def _reduced_modes(self, n_modes: int, screen: bool = False):
        """(λ (n,), y (r, n), T (n_dofs, r) cached with its rows) of this parameter set in the reduced model,
        every mode (rigid ones too): the shapes are T y. None when the basis is too small for n_modes."""
        lam0, _, n_rigid = self._basis(n_modes)
        if lam0.size < n_modes + 10:
            return None
        q = pieces(self.model, self._params)
        extra: list[int] = []
        if not screen:
            if q["spring"] is not None:
                extra.append(q["spring"][0])
            if q["mass"] is not None:
                extra += [int(r) for r in q["mass"][0]]
        proj = self._projected(tuple(extra))
        t = proj["t"]
        k_r = proj["k"]
        if q["k_part"] is not None:
            k_r = k_r + (q["theta"] - 1.0) * self._part(proj, "k", self._params["part_at"], q["k_part"])
        k_r = q["s"] * k_r
        m_r = q["mass_scale"] * proj["m"]
        if q["m_part"] is not None:
            m_r = m_r + (q["theta_m"] - 1.0) * self._part(proj, "m", self._params["part_mass_at"], q["m_part"])
        if q["spring"] is not None:
            row, value = q["spring"]
            k_r = k_r + value * np.outer(t[row], t[row])
        if q["mass"] is not None:
            rows, value = q["mass"]
            m_r = m_r + value * t[rows].T @ t[rows]
        lam, y = _solve_subspace(k_r, m_r, n_modes, self._shift(), float(np.max(np.abs(np.diag(proj["k"])))))
        if "rows" not in proj:     # the basis at the sensors and the translations: all explain reads
            proj["rows"] = (self._at_sensors(t), t[self._translation_rows])
        return lam, y, proj["rows"]

    def _part(self, proj: dict, kind: str, place, matrix) -> np.ndarray:
        key = (kind, str(place))
        if key not in proj["parts"]:
            proj["parts"][key] = proj["t"].T @ (matrix @ proj["t"])
        return proj["parts"][key]

    def _all_modes(self, n_modes: int) -> tuple:
        """Frequencies (n,) Hz of the elastic modes (rigid ones left out), their mass-normalised shapes at the
        sensors (p, n), and at the free translations as (basis rows (t, r), coefficients (r, n)) or as the shapes
        (t, n) with None; cached. The translations are formed only when asked (:meth:`node_modes`)."""
        cache = self.__dict__.setdefault("_modes", {})
        got = next((v for k, v in cache.items() if k >= n_modes), None)
        if got is None:
            r = self.n_rigid
            red = self._reduced_modes(n_modes + r) if self.reduced else None
            if red is None:
                k, m = changed_matrices(self.model, self._params)
                f, phi = sparse_modes(k, m, min(n_modes + r, self.model.n_dofs))
                f, sensors, nodes = np.asarray(f), self._at_sensors(phi), (phi[self._translation_rows][:, r:], None)
            else:
                f = np.sqrt(np.clip(red[0], 0.0, None)) / (2 * np.pi)
                sensors, nodes = red[2][0] @ red[1], (red[2][1], red[1][:, r:])
            got = cache[n_modes] = (f[r:], sensors[:, r:], nodes)
        return got[0][:n_modes], got[1][:, :n_modes], got[2]

    # -- what explain asks ---------------------------------------------------------------------------------
    @property
    def _translation_rows(self) -> np.ndarray:
        got = self._shared.get("translations")
        if got is None:
            got = self._shared["translations"] = np.array(
                [i for i, (_, d) in enumerate(self.model.dofs) if d in TRANSLATIONS], dtype=int)
        return got

    def _at_sensors(self, shapes: np.ndarray) -> np.ndarray:
        got = self._shared.get("sensor_rows")
        if got is None:
            got = self._shared["sensor_rows"] = self.model.at(self.sensors)
        return shapes[got[0]] * got[1][:, None]

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised shapes at the sensors (n_sensors, n).

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        f, sensors, _ = self._all_modes(n_modes)
        return f.copy(), sensors.copy()

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised shapes at every free translation (rows: node_labels).

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        f, _, (rows, y) = self._all_modes(n_modes)
        return f.copy(), (rows[:, :n_modes].copy() if y is None else rows @ y[:, :n_modes])

    @property
    def node_labels(self) -> tuple:
        """"node:x" per row of :meth:`node_modes` (the free translations, in the model's DOF order)."""
        return tuple(f"{self.model.dofs[i][0]}:{self.model.dofs[i][1]}" for i in self._translation_rows)

    def ritz(self, reference: "MatrixExplainModel", n_modes: int) -> RitzModes | None:
        """This parameter set in the span of the shared nominal's modes alone (no static deflections): the
        screening of places; None when the two models do not share a nominal."""
        if self._shared is not reference._shared or not self.reduced:
            return None
        r = self.n_rigid
        lam0 = self._basis(1)[0]
        red = self._reduced_modes(max(1, lam0.size - 10), screen=True)
        if red is None:
            return None
        f = np.sqrt(np.clip(red[0][r:], 0.0, None)) / (2 * np.pi)
        y = red[1][:, r:]
        # the translations only when explain compares modal constants (modal_rows was asked): the screening's
        # largest product otherwise, for nothing
        nodes = red[2][1] @ y if self._shared.get("node_rows") else np.zeros((0, y.shape[1]))
        return RitzModes(f, nodes, red[2][0] @ y)

    def screening_ritz(self, reference: "MatrixExplainModel", n_modes: int) -> RitzModes | None:
        return self.ritz(reference, n_modes)

    has_ritz = True

    @property
    def joints_ft(self) -> np.ndarray:
        """(0, 2): every located effect of a matrix model lists its own places."""
        return np.zeros((0, 2))

    def modal_rows(self, input_locations) -> tuple | None:
        """Rows of node_modes at the sensors and at the input points ((node, direction) each), or None when one
        of them is not a free translation of the model."""
        self._shared["node_rows"] = True     # explain compares modal constants: the screening forms translations
        index = {(self.model.dofs[i][0], self.model.dofs[i][1]): k for k, i in enumerate(self._translation_rows)}

        def row(node, d):
            return None if not isinstance(d, str) or d.startswith("-") else index.get((str(node), d))

        try:
            rows = [row(n, d) for n, d in self.sensors], [row(n, d) for n, d in input_locations]
        except (TypeError, ValueError):
            return None
        return None if None in rows[0] or None in rows[1] else rows

    default_model_form = MODEL_FORM    # an FE model misses its structure as a drawn frame does (see MODEL_FORM)

    @property
    def default_member_scatter(self) -> float:
        """0.02 (the parts' stiffness known to ±2 %, 1σ, as a frame's members) when the model has parts, else 0."""
        return 0.02 if self.model.parts else 0.0

    def _part_modal(self, n_modes: int) -> tuple:
        """The nominal's elastic basis: λ (r,), its shapes at the sensors (p, r) and the translations (t, r), and
        Φᵀ K_part Φ (n_parts, r, r) of each part (cached); r ≥ n_modes."""
        got = self._shared.get("part_modal")
        if got is None or got[0].size < n_modes:
            self._basis(n_modes)
            lam, phi = self.nominal_basis()
            cross = np.array([phi.T @ (p @ phi) for p in self.model.parts.values()])
            got = self._shared["part_modal"] = (lam, self._at_sensors(phi), phi[self._translation_rows], cross)
        return got

    def member_energy_fractions(self, n_modes: int = 10) -> np.ndarray | None:
        """(n_parts, n) each part's share of each nominal mode's strain energy (φᵀ K_part φ / φᵀ K φ), None
        without parts."""
        if not self.model.parts:
            return None
        lam, _, _, cross = self._part_modal(n_modes)
        return np.einsum("ejj->ej", cross)[:, :n_modes] / np.maximum(lam[:n_modes], 1e-300)

    def _shape_change(self, n_modes: int, rows: int) -> tuple:
        """Shapes u (rows, n) and their changes du (n_parts, rows, n) per unit relative change of each part's
        stiffness, dφ_j = Σ_{k≠j} φ_k (φ_kᵀ K_e φ_j)/(λ_j − λ_k) over the basis (Fox & Kapoor 1968);
        rows 1: at the sensors, 2: at the translations."""
        lam, *shapes, cross = self._part_modal(n_modes)
        u = shapes[rows - 1]
        diff = lam[None, :] - lam[:, None]
        apart = np.abs(diff) > 1e-9 * lam.max()
        inv = np.where(apart, 1.0 / np.where(apart, diff, 1.0), 0.0)
        return u[:, :n_modes], np.einsum("rk,ekj,kj->erj", u, cross, inv)[:, :, :n_modes]

    def member_shape_sensitivity(self, n_modes: int = 10) -> np.ndarray | None:
        """(n_parts, p, n) d ψ_j / d a_e of the unit-norm sensor shapes per unit relative change of part e's
        stiffness (as FrameModel.member_shape_sensitivity for members); None without parts."""
        if not self.model.parts:
            return None
        s, ds = self._shape_change(n_modes, 1)
        norm = np.linalg.norm(s, axis=0)
        seen = norm > 1e-9 * max(norm.max(), 1e-300)
        psi = s / np.where(seen, norm, 1.0)
        dpsi = (ds - psi[None] * np.einsum("pj,epj->ej", psi, ds)[:, None, :]) / np.where(seen, norm, 1.0)
        return np.where(seen[None, None, :], dpsi, 0.0)

    def member_scale_sensitivity(self, node_rows, n_modes: int = 10) -> np.ndarray | None:
        """(n_parts, n) d ln‖P_j‖ / d a_e of the modal constants' size at ``node_rows`` (rows of node_modes) per
        unit relative change of part e's stiffness; None without parts."""
        if not self.model.parts:
            return None
        u, du = self._shape_change(n_modes, 2)
        return scale_sensitivity(u, du, node_rows)

    def part_place(self, place) -> str:
        """A part's place, "part:name", checked against the model's parts.

        Parameters
        ----------
        place : str
            "part:name" or the part's name.
        """
        return "part:" + part_name(place, self.model.parts)
