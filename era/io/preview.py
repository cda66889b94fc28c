"""What was read, before anything is converted: the import step's view of one or several files.

:func:`preview` reads the files (era.io.read), applies the person's choices (era.io.choices.choose) and returns a
:class:`Preview`: every channel with its name, unit, node, direction and role, the sampling, the records' lengths,
the conversion ``kind="auto"`` would pick, and a thinned plot of the first record of every channel. A file without
a sampling interval is still shown (against the sample number), with the reason kept in ``problem`` so the person
can give the sample rate.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ..errors import DataError
from . import read
from .choices import channel_indices, choose
from .records import Records, guess_kind

#: Points per plotted channel at most (min/max pairs of equal bins keep every peak visible).
MAX_POINTS = 2000
#: The step the preview reads files without a sampling interval with (Δt = 1: against the sample number), as the
#: readers describe it ("Δt = 1 s (1 Hz) given", LVM's "Δt = 1 s (1 Hz, given)"): said as what it is instead.
_STAND_IN_STEP = re.compile(r"Δt = 1 s \(1 Hz(\) given|, given\))")


@dataclass(frozen=True)
class Channel:
    """One channel as read. index : its position in the file(s) (what ``drop``/``forces`` take); node : the test
    geometry's node label or None; direction : "+X", "-Z", ... (or a vector) or None; force : measures the
    excitation (time records) ; dropped : left out by the person's choice."""

    index: int
    name: str
    unit: str
    node: int | None
    direction: str | None
    force: bool
    dropped: bool


@dataclass(frozen=True)
class Preview:
    """The import step's view of the files.

    files, format : the file names and the format read. domain : "time", "pulse" or "frequency".
    step : Δt (s) or Δf (Hz), None when the files carry no sampling interval and none was given (``problem`` then
        says so and ``x`` counts samples). start : abscissa of the first kept sample (s or Hz).
    channels : every channel of the files (dropped ones too); references : the inputs of FRFs/impulse responses.
    n_records, n_samples : records (several files or runs) and the samples of each after ``start_sample``.
    kind : the conversion "auto" picks for these records (see era.io.records.to_response).
    described : what was read and done, for the dataset's summary.
    x : (n_points,) abscissa of the plot, s or Hz (or sample numbers when step is None).
    traces : (n_channels, n_points) first record of every channel in ``channels`` order, thinned (|FRF| for the
        first reference; the samples before ``start_sample`` included, so the cut is visible).
    problem, problem_option : a DataError that still stops the import (e.g. no sampling interval), and the option
        that fixes it. geometry_nodes : nodes of the test geometry in the files (UFF 15/2411, a SignalCalc setup).
    proposed_band_hz : (low, high) Hz, the band the test's setup proposes for FRFs (a SignalCalc setup.csv's fMin and
        fMax), or None.
    read : the files as read (era.io.read), for era.io.convert to make the dataset without reading them again;
        None when they were read with a stand-in sampling interval or resampled because of ``problem``.
    """

    files: list
    format: str
    domain: str
    step: float | None
    start: float
    channels: list
    references: list
    n_records: int
    n_samples: list
    kind: str
    described: list
    x: np.ndarray
    traces: np.ndarray
    problem: str | None = None
    problem_option: str | None = None
    geometry_nodes: int = 0
    proposed_band_hz: tuple | None = None
    read: object = None


def _direction(d: np.ndarray) -> str | None:
    d = np.asarray(d, float)
    if not np.any(d):
        return None
    k = int(np.argmax(np.abs(d)))
    if np.isclose(abs(d[k]), 1.0) and np.allclose(np.delete(d, k), 0.0):
        return ("+" if d[k] > 0 else "-") + "XYZ"[k]
    return "(" + ", ".join(f"{v:.3g}" for v in d) + ")"


def thin(y: np.ndarray, max_points: int = MAX_POINTS) -> np.ndarray:
    """Sample positions of ``y`` (n, c) to plot: every sample when few, else each bin's smallest and largest value
    of the first channel's envelope over all channels (peaks stay visible). Returns sorted int indices."""
    n = len(y)
    if n <= max_points:
        return np.arange(n)
    bins = max_points // 2
    edges = np.linspace(0, n, bins + 1).astype(int)
    a = np.abs(y).max(axis=1) if y.ndim > 1 else np.abs(y)
    idx = [edges[:-1]]
    for lo, hi in zip(edges[:-1], edges[1:]):
        seg = a[lo:hi]
        idx.append(np.array([lo + int(np.argmax(seg))]))
    return np.unique(np.concatenate(idx))


def preview(source, format: str | None = None, *, name: str | None = None, dt: float | None = None,
            start_sample: int | None = None, drop=None, forces=None, max_points: int = MAX_POINTS,
            max_bytes: int | None = None, **how) -> Preview:
    """Read ``source`` as era.load would (same arguments; no conversion) and describe it for the import step.

    Raises DataError when the files cannot be read at all; a missing sampling interval is not raised but returned
    in ``problem`` (the records are then shown against the sample number).
    """
    problem = option = None
    try:
        got = read(source, format, name=name, dt=dt, max_bytes=max_bytes, **how)
    except DataError as exc:
        if exc.option not in ("dt", "resample"):
            raise
        problem, option = str(exc), exc.option
        for src in source if isinstance(source, (list, tuple)) else [source]:
            if hasattr(src, "seek"):  # a file object was read once already
                src.seek(0)
        # show the samples: without a step (against the sample number), or as they would be resampled
        again = dict(dt=1.0) if option == "dt" else dict(dt=dt, resample=True)
        got = read(source, format, name=name, max_bytes=max_bytes, **{**how, **again})
    if got.npz is not None:
        d = got.npz.data
        rec = Records(domain="pulse", values=[d.markov], step=d.dt, start=d.dt, outputs=tuple(d.outputs),
                      output_units=tuple(d.output_units or ()), inputs=tuple(d.inputs),
                      input_units=tuple(d.input_units or ()), described=list(got.npz.source.get("records", [])))
    elif got.records is None:
        raise DataError(f"{got.labels[0]}: the file holds geometry or modes but no response records; upload the "
                        "measured responses.")
    else:
        rec = got.records
    chosen = choose(rec, start_sample=start_sample, drop=drop, forces=forces)
    gone = set(channel_indices(rec, drop, "drop"))
    force = rec.force
    if forces is not None:
        force = np.zeros(len(rec.outputs), bool)
        force[channel_indices(rec, forces, "forces")] = True
    channels = []
    for i, nm in enumerate(rec.outputs):
        node = int(rec.nodes[i]) if rec.nodes is not None and int(rec.nodes[i]) else None
        channels.append(Channel(
            index=i, name=str(nm), unit=str(rec.output_units[i]) if len(rec.output_units) > i else "",
            node=node, direction=_direction(rec.directions[i]) if rec.directions is not None else None,
            force=bool(force[i]) if force is not None else False,
            dropped=i in gone))
    first = rec.values[0]
    if rec.domain == "frequency":
        y = np.abs(first[:, :, 0])
    elif rec.domain == "pulse":
        y = first[:, :, 0]
    else:
        y = first
    idx = thin(y, max_points)
    step = None if option == "dt" else rec.step
    x = (rec.start + idx * rec.step) if step is not None else idx.astype(float)
    return Preview(
        files=list(got.labels), format=got.format, domain=rec.domain, step=step,
        start=chosen.start if step is not None else float(start_sample or 0), channels=channels,
        references=list(rec.inputs), n_records=len(chosen.values), n_samples=[len(v) for v in chosen.values],
        kind=guess_kind(chosen),
        described=[_STAND_IN_STEP.sub("no sampling interval in the file", d) for d in chosen.described] if problem
        else list(chosen.described) + list(rec.conversions), x=np.asarray(x, float),
        traces=np.asarray(y[idx].T, float),
        problem=problem, problem_option=option,
        geometry_nodes=len(got.parts[0]) if got.parts is not None else 0,
        proposed_band_hz=(rec.points or {}).get("proposed_band_hz"), read=None if problem else got)

