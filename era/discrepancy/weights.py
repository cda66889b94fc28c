"""The error levels of one explanation beyond ERA's spread: which modes are nearly repeated (their shapes are
compared as a plane), which node rows the modal constants are compared at, and the members' stiffness scatter
added to the frequencies, shapes and modal constants (a drawn model's members are known to a few per cent)."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..core.correlation import ModePairing, pair_modes
from ..words import counted
from .fitting import ErrorLevels, ModeWeights
from .measured import MeasuredModes, node_direction
from .protocol import ExplainModel, Modes


def pair(model: Modes, measured: MeasuredModes, n_model: int, **kw) -> ModePairing:
    f, shapes = model.modes(n_model)
    return pair_modes(measured.frequency_hz, measured.shapes, f, shapes, **kw)


def node_rows(model: ExplainModel, measured: MeasuredModes):
    """Rows of model.node_modes at the sensors and at the measured inputs, or None when the modal constants
    cannot be compared (no known inputs, or an input that is not a model node)."""
    if measured.modal_constants is None:
        return None
    rows = model.modal_rows(measured.input_locations)
    p = measured.modal_constants.shape[0]       # struck points added as sensors (struck_sensors) come after them
    return None if rows is None else (rows[0][:p], rows[1])


def frame_point(label: str, node_ids) -> tuple | None:
    """(node id, direction) of an era.Frame that a point label names (:func:`measured.node_direction`: "4X",
    "4 x", "E -z"), or None when it names no node of ``node_ids``."""
    at = node_direction(label)
    return at if at is not None and at[0] in set(node_ids) else None


def struck_sensors(frame, measured: MeasuredModes) -> tuple:
    """(frame, measured, words): the struck points that name a node and direction of ``frame`` (an era.Frame, or
    an era.MatrixModel: a free DOF of it) added after its sensors, and their shapes after the outputs'
    (MeasuredModes.with_struck); the points that do not map, or the reason none is compared, in one sentence
    ("" when all are). Unchanged without struck points."""
    labels = measured.struck_points
    if not labels:
        return frame, measured, ""
    if measured.struck_shapes is None:
        return frame, measured, (f"The {len(labels)} struck points are not compared: none of the struck points is "
                                 "also measured (a driving point), so their shapes cannot be scaled to the sensors'.")
    have = {(str(n), d.lstrip("-")) for n, d in frame.sensors if isinstance(d, str)}
    free = getattr(frame, "dof_index", None)       # a matrix model: only its free DOFs
    keep, sensors, missing = [], [], []
    for i, label in enumerate(labels):
        at = frame_point(label, frame.node_ids)
        if at is not None and free is not None and (at[0], at[1].lstrip("-")) not in free:
            at = None
        if at is None:
            missing.append(str(label))
        elif (at[0], at[1].lstrip("-")) not in have:
            have.add((at[0], at[1].lstrip("-")))
            keep.append(i)
            sensors.append(at)
    many = len(missing) > 1
    words = ("" if not missing else f"{counted(len(missing), 'struck point')} "
             f"({', '.join(missing[:5])}{', ...' if len(missing) > 5 else ''}) {'name' if many else 'names'} no node "
             f"and direction of the model and {'are' if many else 'is'} left out of the shape comparison.")
    if not keep:
        return frame, measured, words
    points = tuple(frame.sensors) + tuple(sensors)
    frame = frame.with_sensors(points) if free is not None else dataclasses.replace(frame, sensors=points)
    return frame, measured.with_struck(keep), words


def close_modes(model: ExplainModel, measured: MeasuredModes, n_model: int, close: float) -> np.ndarray:
    """(k,) True for measured modes with a neighbour within ``close`` (relative), among the measured modes or
    among the nominal model's modes next to their partner: nearly repeated modes."""
    f = measured.frequency_hz
    rel = np.abs(f[:, None] - f[None, :]) / f[:, None]
    np.fill_diagonal(rel, np.inf)
    out = rel.min(axis=1) <= close
    p = pair(model, measured, n_model, max_freq_error=1.0)
    fa = np.clip(np.nan_to_num(model.modes(n_model)[0]), 0.0, None)
    for i, j in zip(p.measured_index, p.model_index):
        others = np.delete(fa, j)
        if others.size and np.min(np.abs(others - fa[j])) <= close * max(fa[j], 1e-12):
            out[i] = True
    return out


def with_member_scatter(w: ModeWeights, errors: ErrorLevels, model: ExplainModel, fm: MeasuredModes, n_model: int):
    """The weights with the members' stiffness scatter added (ErrorLevels.member_scatter, or the model's
    ``default_member_scatter``), through each measured mode's nominal partner: to its frequency by the partner's
    strain-energy shares, to its shape components by the shape's sensitivity to each member
    (``member_shape_sensitivity``; capped at ``close_shape_sigma``, which already frees a nearly repeated pair),
    and to its modal constants' size (``member_scale_sensitivity``, correlated across modes) when they are fitted."""
    scatter = errors.member_scatter
    if scatter is None:
        scatter = model.default_member_scatter
    share = model.member_energy_fractions(n_model) if scatter else None     # (n_members, n_model)
    if share is None:
        return w
    rel = 0.5 * scatter * np.sqrt(np.sum(share**2, axis=0))          # (n_model,) relative 1σ of each frequency
    pairing = pair(model, fm, n_model, max_freq_error=1.0)
    per_mode = np.full(fm.n_modes, rel.max())
    per_mode[pairing.measured_index] = rel[pairing.model_index]
    w = dataclasses.replace(w, sigma_f=np.hypot(w.sigma_f, per_mode * fm.frequency_hz))
    d = model.member_shape_sensitivity(n_model)                       # (n_members, p, n_model)
    if d is None:
        return w
    comp = np.minimum(scatter * np.sqrt(np.mean(np.sum(d**2, axis=0), axis=0)), errors.close_shape_sigma)
    per_shape = np.full(fm.n_modes, comp.max())
    per_shape[pairing.measured_index] = comp[pairing.model_index]
    w = dataclasses.replace(w, sigma_s=np.hypot(w.sigma_s, per_shape))
    whitener = w.scale_whitener
    g = None if whitener is None else model.member_scale_sensitivity(w.node_rows, n_model)
    if whitener is None or g is None:                                   # g: (n_members, n_model)
        return w
    # the modal constants' sizes move with the shapes at the sensors and inputs, together across modes (each
    # member's scatter is one draw for all of them): scatter² GᵀG joins their covariance, as the gains' does
    per = np.zeros((g.shape[0], fm.n_modes))
    per[:, pairing.measured_index] = g[:, pairing.model_index]
    unwhite = np.linalg.inv(whitener)
    cov = unwhite @ unwhite.T + scatter**2 * per.T @ per
    return dataclasses.replace(w, scale_whitener=np.linalg.inv(np.linalg.cholesky(cov)))
