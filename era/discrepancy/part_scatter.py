"""The model-form scatter of an FE model given as matrices or a deck, as a correlated error of every fit.

A drawn model's parts (a deck's PSHELL regions, a web, a flange) are each known to a few per cent, a deck's shell
thicknesses too (a plate's bending goes with T³), and its springs to ground (the supports) to a few tens of per
cent. Each such error is one draw that moves every mode's frequency, shape and modal constants together. Added per
mode in quadrature (weights.with_member_scatter, the frames' rule: many members, whose errors average out), it is
too loose where the modes agree and blind to the pattern: regions a few per cent apart, or edge springs a tenth
off, change the shapes near a seam or an edge as a spring or a mass there would, and one place wins a fit it
should share with its neighbours. Here each cause is a nuisance marginalised in every fit (linearised about the
nominal, correlated.py): the residuals' covariance gains G Gᵀ, G (n_r, n_causes) their change per 1σ of each
cause, by differences on the nominal's reduced model (two solves per part and thickness, one per spring).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..models.changes import PART, dof_place
from ..models.matrix import DIRECTIONS
from .correlated import correlated_errors
from .deck_model import DeckExplainModel
from .fitting import TRIAL_FAILURES, ErrorLevels, ModeWeights, mode_residuals
from .matrix_model import MatrixExplainModel
from .measured import MeasuredModes
from .protocol import ExplainModel

#: the relative step of a factor for the differences (small against the scatter: the residuals are linear there,
#: and large against the solver's rounding)
STEP = 0.005
#: relative 1σ of a deck's PSHELL thickness (a plate's bending goes with T³: 6 % on its bending stiffness), and of a
#: deck's spring to ground (a support's stiffness is rarely known better than that; the issue's model-form scatter
#: of shells: thickness and E ±2 %, boundary springs); ErrorLevels(thickness_scatter=..., support_scatter=...)
#: override them
THICKNESS_SCATTER = 0.02
SUPPORT_SCATTER = 0.1


def part_places(model: ExplainModel) -> tuple:
    """("part:name", ...) of the model's parts when it is a matrix model or a deck with parts, else ()."""
    if isinstance(model, DeckExplainModel):
        parts = model.deck_model.parts
    elif isinstance(model, MatrixExplainModel):
        parts = model.model.parts
    else:
        return ()
    return tuple(PART + name for name in (parts or {}))


@dataclass(frozen=True)
class Cause:
    """One scatter cause: ``label`` ("part:PSHELL 2", "PSHELL 2 T", "17:z"), ``changes(e)`` the model's keywords
    for a relative change e of it, its relative 1σ ``sigma``, and ``central`` (False: a difference on one side,
    e ≥ 0, for a change the other way may make a mechanism)."""

    label: str
    changes: Callable[[float], dict]
    sigma: float
    central: bool = True


def _stiffness(place: str) -> Callable[[float], dict]:
    """A part's stiffness × (1 + e)."""
    return lambda e: {"part_at": place, "part_factor": 1.0 + e}


def _thickness(place: str) -> Callable[[float], dict]:
    """A plate part's thickness × (1 + e): its bending stiffness × (1 + 3e), its mass × (1 + e)."""
    return lambda e: {"part_at": place, "part_factor": 1.0 + 3.0 * e, "part_mass_at": place,
                      "part_mass_factor": 1.0 + e}


def _support(place: str, k: float) -> Callable[[float], dict]:
    """A spring to ground of stiffness k, e × k of it (one side: less may make a mechanism)."""
    return lambda e: {"spring_at": place, "spring_stiffness": e * k}


def causes(model: ExplainModel, errors: ErrorLevels) -> list:
    """Every scatter cause (:class:`Cause`): each part's stiffness (errors.member_scatter, its E); on a deck each
    PSHELL's thickness (its part's bending stiffness × (1 + 3e) and its mass × (1 + e): a plate's bending goes with
    T³, and the part's stiffness on the reduced model costs no re-assembly; membrane parts are overstated, which
    only widens) and each spring to ground (ErrorLevels.thickness_scatter, support_scatter; None: this module's
    constants)."""
    out = [Cause(p, _stiffness(p), float(errors.member_scatter or 0.0)) for p in part_places(model)]
    if isinstance(model, DeckExplainModel):
        t = THICKNESS_SCATTER if errors.thickness_scatter is None else errors.thickness_scatter
        k = SUPPORT_SCATTER if errors.support_scatter is None else errors.support_scatter
        masses = model.deck_model.part_masses or {}
        for pid in sorted(model.deck.shell_sections):
            p = f"PSHELL {pid}"
            if p in (model.deck_model.parts or {}) and p in masses:
                out.append(Cause(f"{p} T", _thickness(PART + p), t))
        for s in model.deck.springs.values():
            if not s.g2 and s.c1 and (str(s.g1), DIRECTIONS[s.c1 - 1]) in model.nominal.model.dof_index:
                place = dof_place(str(s.g1), DIRECTIONS[s.c1 - 1])
                out.append(Cause(place, _support(place, s.k), k, central=False))
    return [c for c in out if c.sigma]


def scatter_sensitivity(model: ExplainModel, w: ModeWeights, fm: MeasuredModes, n_model: int,
                        errors: ErrorLevels) -> np.ndarray:
    """(n_r, n_causes) the change of the normalised residuals (fitting.mode_residuals at ``w``) per 1σ of each
    cause about ``model``; a cause whose changed model cannot be solved: a zero column."""
    r0 = mode_residuals(model, fm, w, n_model)[0]
    cols = []
    for c in causes(model, errors):
        try:
            if c.central:
                up, down = (mode_residuals(model.with_params(**c.changes(s * STEP)), fm, w, n_model)[0]
                            for s in (1.0, -1.0))
                cols.append(c.sigma * (up - down) / (2.0 * STEP))
            else:
                up = mode_residuals(model.with_params(**c.changes(STEP)), fm, w, n_model)[0]
                cols.append(c.sigma * (up - r0) / STEP)
        except TRIAL_FAILURES:      # that cause cannot scatter the model into something solvable: no error from it
            cols.append(np.zeros(r0.size))
    return np.column_stack(cols) if cols else np.zeros((r0.size, 0))


def with_part_scatter(w: ModeWeights, errors: ErrorLevels, model: ExplainModel, fm: MeasuredModes,
                      n_model: int) -> ModeWeights | None:
    """The weights with the scatter of :func:`causes` (each part's stiffness at ErrorLevels.member_scatter, the
    model's default when None; a deck's thicknesses and supports) as a correlated error of every residual; None
    when the model has no parts or no part scatter (the caller then keeps weights.with_member_scatter's rule)."""
    scatter = errors.member_scatter
    if scatter is None:
        scatter = model.default_member_scatter
    if not part_places(model) or not scatter:
        return None
    g = scatter_sensitivity(model, w, fm, n_model, dataclasses.replace(errors, member_scatter=scatter))
    return dataclasses.replace(w, correlated=correlated_errors(g))
