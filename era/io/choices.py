"""What a person says about records that the files cannot: where the record starts, which channels to leave out and
which channels measure the excitation.

The import step of a test tool (Testlab's or ME'scope's) asks exactly this after reading a file: a trigger with
pre-trigger samples to cut, a spare or broken channel to drop, the hammer or shaker force channel that the file does
not mark. :func:`choose` applies those choices to :class:`Records` before the conversion to Markov parameters.
Channels are named by their name in the file or by their position (0-based int).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import DataError
from .records import MIN_SAMPLES, Records


def channel_index(rec: Records, channel, option: str) -> int:
    """The position of ``channel`` (its name in the file, or a 0-based int) among the records' channels/outputs."""
    names = list(rec.outputs)
    if isinstance(channel, (int, np.integer)) and not isinstance(channel, bool):
        if not 0 <= int(channel) < len(names):
            raise DataError(f"`{option}`: channel {int(channel)} does not exist; the channels are numbered 0 to "
                            f"{len(names) - 1} ({', '.join(names[:12])}{' ...' if len(names) > 12 else ''}).",
                            option=option)
        return int(channel)
    if isinstance(channel, str) and channel in names:
        if names.count(channel) > 1:
            raise DataError(f"`{option}`: several channels are named {channel!r}; give their positions (0-based) "
                            "instead of the name.", option=option)
        return names.index(channel)
    raise DataError(f"`{option}`: no channel {channel!r}; the channels are {', '.join(map(repr, names[:12]))}"
                    f"{' ...' if len(names) > 12 else ''}.", option=option)


def channel_indices(rec: Records, channels, option: str) -> list[int]:
    """Sorted positions of ``channels`` (names or 0-based ints; one or a list; None = none)."""
    if channels is None:
        return []
    if isinstance(channels, (str, int, np.integer)):
        channels = [channels]
    return sorted({channel_index(rec, c, option) for c in channels})


def choose(rec: Records, *, start_sample: int | None = None, drop=None, forces=None, points=None) -> Records:
    """Records with the person's choices applied.

    start_sample : samples to skip at the start of every record (a pre-trigger, the samples before the hit);
        time histories and impulse responses only. The first kept sample keeps its time (``start`` moves on).
    drop : channels (names or 0-based positions) left out: time channels, or outputs of FRFs/impulse responses.
    forces : the channels (names or positions) that measure the excitation (hammer, shaker force), replacing what
        the file's units and names suggested; time histories only. An empty list says that no channel is a force.
    points : where the channels are (era.core.points): {channel (name or 0-based position): point label ("4X": node 4
        along X)}, time histories only. A force channel's point is where the structure was struck or driven
        (``input_points``), a response channel's where it was measured (``output_points``); see
        era.io.records.to_response. Channels not named have no known point.
    Returns a new Records; ``described`` says what was done. DataError (with ``option`` set) for a choice that does
    not fit the records.
    """
    notes = []
    values, start = list(rec.values), rec.start
    if start_sample:
        k = int(start_sample)
        if k < 0:
            raise DataError(f"`start_sample` must be 0 or more, got {k}.", option="start_sample")
        if rec.domain == "frequency":
            raise DataError("`start_sample` applies to time records; these are FRFs (leave it at 0).",
                            option="start_sample")
        shortest = min(len(v) for v in values)
        if k > shortest - MIN_SAMPLES:
            raise DataError(f"`start_sample` {k} leaves fewer than {MIN_SAMPLES} samples of the {shortest} in the "
                            "shortest record; choose a smaller start.", option="start_sample")
        values = [v[k:] for v in values]
        start = rec.start + k * rec.step
        notes.append(f"the first {k} samples of every record skipped (the records start at {start:.6g} s)")
    force = rec.force
    if forces is not None:
        if rec.domain != "time":
            raise DataError("`forces` marks excitation channels among time histories; FRFs and impulse responses "
                            "already name their references.", option="forces")
        force = np.zeros(len(rec.outputs), bool)
        force[channel_indices(rec, forces, "forces")] = True
        notes.append("force channels: " + (", ".join(np.array(rec.outputs)[force]) if force.any() else "none"))
    labels = (rec.points or {}).get("channel_points")  # the file's (an HDF5 ``points`` attribute), if any
    labels = None if labels is None else list(labels)
    if points:
        if rec.domain != "time":
            raise DataError("`points` places the channels of time histories; FRFs and impulse responses take their "
                            "points from the file (UFF 58 nodes, a SignalCalc setup.csv).", option="points")
        if not isinstance(points, dict):
            raise DataError("`points` is {channel: point label}, e.g. {0: '4X'}.", option="points")
        labels = [""] * len(rec.outputs)  # the person's replace the file's, as ``forces`` do
        for channel, label in points.items():
            labels[channel_index(rec, int(channel) if str(channel).isdigit() else channel, "points")] = \
                str(label).strip()
        notes.append("points: " + ", ".join(f"{rec.outputs[i]} at {x}" for i, x in enumerate(labels) if x))
    gone = channel_indices(rec, drop, "drop")
    keep = np.setdiff1d(np.arange(len(rec.outputs)), gone)
    if gone:
        if not len(keep):
            raise DataError("`drop` leaves no channel; keep at least one response.", option="drop")
        axis = 1  # channels: the columns of a time record, the outputs (N, p, m) of FRFs and impulse responses
        values = [np.take(v, keep, axis=axis) for v in values]
        notes.append("channels dropped: " + ", ".join(rec.outputs[i] for i in gone))

    def pick(seq):
        return tuple(seq[i] for i in keep) if seq is not None and len(seq) else seq

    return replace(rec, values=values, start=start, outputs=pick(rec.outputs), output_units=pick(rec.output_units),
                   force=force[keep] if force is not None else None,
                   nodes=rec.nodes[keep] if rec.nodes is not None else None,
                   directions=rec.directions[keep] if rec.directions is not None else None,
                   points=rec.points if labels is None else
                   dict(rec.points or {}, channel_points=tuple(labels[i] for i in keep)),
                   described=list(rec.described) + notes)


def renumber(rec: Records, drop, channels, option: str) -> list:
    """``channels`` (names, or 0-based positions as read) as positions among the channels left after ``drop``:
    what a conversion option such as NExT's ``references`` must be given once channels are dropped."""
    if channels is None:
        return None
    gone = set(channel_indices(rec, drop, "drop"))
    keep = [i for i in range(len(rec.outputs)) if i not in gone]
    out = []
    for i in channel_indices(rec, channels, option):
        if i in gone:
            raise DataError(f"`{option}`: channel {rec.outputs[i]!r} is dropped; keep it or choose another.",
                            option=option)
        out.append(keep.index(i))
    return out
