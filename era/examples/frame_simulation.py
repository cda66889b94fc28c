"""Blind simulated tests of era.Frame models: a truth that differs from the nominal, an effect hidden in it.

The truth is the nominal frame with every member's E and G scattered (``scatter``, 1σ), twice the nominal's mesh,
and the hidden effect (FrameModel parameters: a support spring, a joint spring, a point mass, a softer member,
spread mass). Measured modes are the truth's lowest modes that the sensors see (sensor norm ≥ 15 % of the
largest), with frequency noise, shape noise and sensor gain errors.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..discrepancy.frame_model import FrameModel
from ..discrepancy.measured import MeasuredModes, modes_from_arrays
from ..core.data import ResponseData
from ..structure import Frame


@dataclass(frozen=True)
class FrameTruth:
    """What was hidden: effect name ("none", ...), its FrameModel parameters, the scatter factors (n_members,),
    the sensor gains (p,), and the truth FrameModel."""

    effect: str
    params: dict
    scatter: np.ndarray
    gains: np.ndarray
    model: FrameModel


def truth_model(frame: Frame, params: dict, *, scatter: float = 0.02, rng=None, refine: int = 2) -> tuple:
    """The truth FrameModel: per-member E, G factors 1 + N(0, scatter²), ``refine`` × the nominal's elements; each
    member's non-structural mass (``frame.added_mass_per_length``, kg/m) follows it to its renamed section."""
    rng = np.random.default_rng(rng)
    counts = np.array(frame.element_counts(10)) * refine
    factors = 1.0 + scatter * rng.standard_normal(len(frame.members))
    sections = dict(frame.sections)
    members = []
    for k, ((i, j, sec, orient), a) in enumerate(zip(frame.members, factors)):
        s = frame.sections[sec]
        sections[f"{sec}#{k}"] = dataclasses.replace(s, e=s.e * a, g=s.g * a)
        members.append((i, j, f"{sec}#{k}", orient))
    extra = {f"{sec}#{k}": frame.added_mass_per_length[sec] for k, (_, _, sec, _) in enumerate(frame.members)
             if sec in frame.added_mass_per_length}
    truth = dataclasses.replace(frame, sections=sections, members=members, added_mass_per_length=extra,
                                elements_per_member=tuple(counts.tolist()))
    return FrameModel.of(truth, gravity=params.pop("gravity", True) if params else True, reduced=False).with_params(
        **params), factors


def simulate_frame_test(frame: Frame, effect: str = "none", params: dict | None = None, *, seed: int = 0,
                        n_modes: int = 6, scatter: float = 0.02, freq_noise: float = 0.001,
                        shape_noise: float = 0.01, gain_std: float = 0.02) -> tuple[MeasuredModes, FrameTruth]:
    """Measured modes of ``frame`` with ``effect`` hidden (FrameModel parameters ``params``, e.g.
    {"point_mass_at": "3", "point_mass_kg": 0.2}), and what was hidden.

    frequency noise: relative 1σ; shape noise: 1σ of each component of a unit-norm shape; gain_std: 1σ of each
    sensor's calibration factor (a common factor per sensor across modes).
    """
    rng = np.random.default_rng(seed)
    model, factors = truth_model(frame, dict(params or {}), scatter=scatter, rng=rng)
    f, s = model.modes(n_modes + 8)
    norm = np.linalg.norm(s, axis=0)
    seen = np.flatnonzero(norm >= 0.15 * norm.max())[:n_modes]
    f, s = f[seen], s[:, seen]
    gains = 1.0 + gain_std * rng.standard_normal(s.shape[0])
    s = s / np.linalg.norm(s, axis=0) * gains[:, None]
    s = s + shape_noise * rng.standard_normal(s.shape)
    f = f * (1.0 + freq_noise * rng.standard_normal(f.size))
    return modes_from_arrays(f, s), FrameTruth(effect, dict(params or {}), factors, gains, model)


def simulate_frame_records(frame: Frame, effect: str = "none", params: dict | None = None, *, seed: int = 0,
                           inputs=(0,), n_modes: int = 12, zeta: float = 0.01, n_samples: int = 2000,
                           scatter: float = 0.02, noise: float = 0.01, gain_std: float = 0.02,
                           known_inputs: bool = False) -> tuple[ResponseData, FrameTruth]:
    """Pulse responses of ``frame`` with ``effect`` hidden (as :func:`simulate_frame_test`'s truth), for ERA.

    Unit impulses (1 N·s) at the sensors numbered in ``inputs``, along their directions; the truth's lowest
    ``n_modes`` modes with damping ratio ``zeta``, sampled at 2.5 × the highest of them (dt s) for
    ``n_samples``; each sensor's gain off by 1 + N(0, gain_std²), Gaussian noise of ``noise`` × each record's
    RMS. Returns ResponseData (n_samples, p, m) in m per N·s, outputs in frame.sensors order, and the truth.
    known_inputs: data.meta["input_locations"] holds each impulse's (node, direction), so explain also fits the
    modal constants (the absolute mass scale); False leaves them out (frequencies and shapes only).
    """
    rng = np.random.default_rng(seed)
    model, factors = truth_model(frame, dict(params or {}), scatter=scatter, rng=rng)
    f, s = model.modes(n_modes)                                   # (n,), (p, n) mass-normalised
    dt = 1.0 / (2.5 * f.max())
    w = 2 * np.pi * f
    wd = w * np.sqrt(1 - zeta**2)
    t = np.arange(n_samples)[:, None] * dt
    h = np.exp(-zeta * w * t) * np.sin(wd * t) / wd                # (N, n) modal impulse responses
    gains = 1.0 + gain_std * rng.standard_normal(s.shape[0])
    y = np.einsum("tn,pn,mn->tpm", h, s * gains[:, None], s[list(inputs)])
    rms = np.sqrt((y**2).mean(axis=0))
    y = y + noise * rms * rng.standard_normal(y.shape)
    names = [f"{n} {d}" for n, d in frame.sensors]
    data = ResponseData(markov=y, dt=dt, outputs=tuple(names), inputs=tuple(f"impulse {names[a]}" for a in inputs),
                        output_units=("m",) * len(names), input_units=("N·s",) * len(inputs),
                        meta={"source": "era.examples.frame_simulation.simulate_frame_records", "seed": seed})
    if known_inputs:
        data.meta["input_locations"] = tuple(tuple(frame.sensors[a]) for a in inputs)
    return data, FrameTruth(effect, dict(params or {}), factors, gains, model)
