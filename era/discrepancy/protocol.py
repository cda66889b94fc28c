"""The model protocol explain() relies on, written down: what a model must answer to be explained.

Two models implement :class:`ExplainModel` in full: the NASA grid (era.examples.grid.GridModel) and an era.Frame
(:class:`era.discrepancy.frame_model.FrameModel`). A model of your own needs only the core, :class:`Model`
(.params, .sensors, .with_params(**changes), .modes(n), .node_modes(n)); :func:`as_explain_model` wraps it in
:class:`PlainModel`, which answers the rest with "not available" (no Rayleigh-Ritz shortcut: every trial is
solved; no member scatter; its candidate places are its ``joints_ft`` when it has them).

:class:`RitzModes` is the one type of approximate modes (Rayleigh-Ritz in a solved model's modes) both models
return from .ritz: it answers .modes(n) and .node_modes(n) as a model does, which is all the residuals need.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np


class Modes(Protocol):
    """Anything with modes: a model, or a model's approximate modes (:class:`RitzModes`)."""

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised shapes at the sensors (n_sensors, n)."""
        ...

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised shapes at every node row (n_rows, n)."""
        ...


class Model(Modes, Protocol):
    """The core a model of your own must offer (see tests/discrepancy/test_explain_generic.py: a spring chain).

    params : {keyword: value} of the current parameter set (with ``stiffness_factor``, the global nuisance);
    sensors : one entry per output channel, in channel order; with_params : a new model with some keywords
    changed (the effects of the library are keywords: EffectSpec.fixed, Param.name, location_keyword)."""

    @property
    def params(self) -> dict[str, Any]: ...

    @property
    def sensors(self) -> Any: ...

    def with_params(self, **changes: Any) -> Any: ...


@runtime_checkable
class ExplainModel(Model, Protocol):
    """The whole protocol: the core plus what makes explain fast and honest on the grid and on frames.

    joints_ft : (n_places, 2) the default candidate places of located effects whose EffectSpec lists none (the
        grid's joints (x_ft, y_ft)); (0, 2) when every located effect lists its own places (a frame);
    node_labels : one label per row of node_modes ("7:x", ...), or () when the rows are plain node indices;
    has_ritz : True when .ritz can approximate a trial's modes (else it always answers None: every trial solved);
    exact : the same parameter set solved in full (a frame's variants are solved in the nominal's reduced model
        until then); the model itself when it has no shortcut;
    default_member_scatter : relative 1σ of each member's stiffness when ErrorLevels.member_scatter is None (0:
        none, the grid's 157 bars average out);
    default_model_form : (relative frequency 1σ, shape-component 1σ) of the model-form allowance when
        ErrorLevels.model_form is None (see ErrorLevels);
    ritz(reference, n_modes) : this model's modes in the span of the solved ``reference``'s lowest n_modes
        (:class:`RitzModes`), or None when it cannot (then the trial is solved);
    screening_ritz : the approximation used to screen places (ranking.screen_locations);
    modal_rows(input_locations) : (sensor rows (p,), input rows (m,)) of node_modes, to compare measured modal
        constants, or None when the inputs are not model nodes;
    member_energy_fractions(n) (n_members, n), member_shape_sensitivity(n) (n_members, p, n),
    member_scale_sensitivity(node_rows, n) (n_members, n): the members' share of each mode's strain energy and
        the sensitivities of the unit shapes and of the modal constants' size to each member's stiffness; None
        when the model does not describe its members one by one (then member scatter is not added).
    """

    @property
    def joints_ft(self) -> np.ndarray: ...

    @property
    def node_labels(self) -> tuple[str, ...]: ...

    @property
    def has_ritz(self) -> bool: ...

    @property
    def exact(self) -> ExplainModel: ...

    @property
    def default_member_scatter(self) -> float: ...

    @property
    def default_model_form(self) -> tuple[float, float]: ...

    def with_params(self, **changes: Any) -> ExplainModel: ...

    def ritz(self, reference: Any, n_modes: int) -> RitzModes | None: ...

    def screening_ritz(self, reference: Any, n_modes: int) -> RitzModes | None: ...

    def modal_rows(self, input_locations: Any) -> tuple | None: ...

    def member_energy_fractions(self, n_modes: int = 10) -> np.ndarray | None: ...

    def member_shape_sensitivity(self, n_modes: int = 10) -> np.ndarray | None: ...

    def member_scale_sensitivity(self, node_rows: Any, n_modes: int = 10) -> np.ndarray | None: ...


@dataclass(frozen=True, eq=False)
class RitzModes:
    """Approximate modes (GridModel.ritz, FrameModel.ritz): frequencies (r,) Hz, mass-normalised shapes at every
    node row (n_rows, r) (the grid's 88 joints' w; a frame's node translations, 3·n_nodes rows) and at the
    sensors (n_sensors, r); .node_modes(n) and .modes(n) as the model's."""

    frequency_hz: np.ndarray
    node_w: np.ndarray
    sensor_w: np.ndarray

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        return self.frequency_hz[:n_modes].copy(), self.node_w[:, :n_modes].copy()

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        return self.frequency_hz[:n_modes].copy(), self.sensor_w[:, :n_modes].copy()


@dataclass(frozen=True, eq=False)
class PlainModel:
    """A model of your own (:class:`Model`) as an :class:`ExplainModel`: every trial solved, no member scatter.

    model : the wrapped model; joints_ft : (n, 2) its default candidate places (its own ``joints_ft``)."""

    model: Any
    joints_ft: np.ndarray

    @property
    def params(self) -> dict[str, Any]:
        return dict(self.model.params)

    @property
    def sensors(self) -> Any:
        return self.model.sensors

    @property
    def node_labels(self) -> tuple[str, ...]:
        return ()

    @property
    def default_member_scatter(self) -> float:
        return 0.0

    @property
    def default_model_form(self) -> tuple[float, float]:
        return (0.0, 0.0)

    @property
    def has_ritz(self) -> bool:
        return False

    @property
    def exact(self) -> PlainModel:
        return self

    def with_params(self, **changes: Any) -> PlainModel:
        return PlainModel(self.model.with_params(**changes), self.joints_ft)

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        f, s = self.model.modes(n_modes)
        return np.asarray(f), np.asarray(s)

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        f, w = self.model.node_modes(n_modes)
        return np.asarray(f), np.asarray(w)

    def ritz(self, reference: Any, n_modes: int) -> RitzModes | None:
        return None

    def screening_ritz(self, reference: Any, n_modes: int) -> RitzModes | None:
        return None

    def modal_rows(self, input_locations: Any) -> tuple | None:
        """Rows of node_modes at the sensors and the inputs: the joints (joints_ft) each stands on."""
        return joint_rows(self.joints_ft, self.sensors, input_locations)

    def member_energy_fractions(self, n_modes: int = 10) -> np.ndarray | None:
        return None

    def member_shape_sensitivity(self, n_modes: int = 10) -> np.ndarray | None:
        return None

    def member_scale_sensitivity(self, node_rows: Any, n_modes: int = 10) -> np.ndarray | None:
        return None


def joint_rows(joints_ft: np.ndarray, sensors: Any, input_locations: Any) -> tuple | None:
    """(sensor rows, input rows): the index of the joint (a row of ``joints_ft`` (n, 2)) each sensor and each
    input point stands on, or None when one of them stands on no joint (within 1e-6 ft)."""
    xy = np.asarray(joints_ft, float)
    if xy.size == 0:
        return None

    def row(at: Any) -> int | None:
        d = np.linalg.norm(xy - np.asarray(at, float)[:2], axis=1)
        return int(np.argmin(d)) if d.min() < 1e-6 else None

    try:
        rows = [row(s) for s in sensors], [row(a) for a in input_locations]
    except (TypeError, ValueError):
        return None
    return None if None in rows[0] or None in rows[1] else rows


def as_explain_model(model: Any) -> ExplainModel:
    """``model`` itself when it implements the whole protocol, else wrapped in :class:`PlainModel` (its places
    are its ``joints_ft`` when it has them, else none: its located effects then list their own)."""
    if isinstance(model, ExplainModel):
        return model
    joints = getattr(model, "joints_ft", None)     # the one optional attribute a model of one's own may give
    return PlainModel(model, np.zeros((0, 2)) if joints is None else np.asarray(joints, float))


def scale_sensitivity(u: np.ndarray, du: np.ndarray, node_rows) -> np.ndarray:
    """(n_e, n) d ln‖P_j‖ / d a_e: how the size of mode j's modal constants moves per unit relative change of
    parameter e, from node-row shapes ``u`` (rows, n) and their changes ``du`` (n_e, rows, n); ``node_rows``: per
    constant, its rows of ``u`` (ModeWeights.node_rows). Rows where a mode does not move add nothing."""
    out = np.zeros((du.shape[0], u.shape[1]))
    for rows in node_rows:
        a, da = u[np.asarray(rows, int)], du[:, np.asarray(rows, int)]
        nn = np.sum(a**2, axis=0)
        out += np.where(nn > 1e-300, np.einsum("rj,erj->ej", a, da) / np.where(nn > 1e-300, nn, 1.0), 0.0)
    return out
