"""Named arrays (MATLAB, HDF5, .npy) as time records: which array is the data, which gives the sampling.

The binary readers (npy.py, mat.py, hdf5.py) list what a file holds as :class:`Var` (name, shape, a reader that
checks the bytes are there before it allocates); :func:`records_from_vars` picks the data and the sampling by name:

- sampling, by (case-insensitive) name: a time vector ``t``, ``time``, ``time_s``, ``tt`` (s, checked even); a
  sampling interval ``dt``, ``ts``, ``delta_t``, ``sampling_interval``, ``wf_increment`` (s); a sample rate ``fs``,
  ``sf``, ``srate``, ``sample_rate``, ``sampling_rate``, ``samplerate`` (Hz); from variables or attributes;
  otherwise the caller's ``dt``;
- data: every other real numeric array of 1 or 2 dimensions; one is taken as it is, several 1-D arrays of one length
  as channels; anything else is ambiguous and the caller says ``variable="acc"`` (or a list of names, read side by
  side as channels);
- a 2-D array holds its channels along the shorter side unless ``orientation`` ("rows"/"columns") says otherwise;
  a first channel that increases at every sample is a time axis (checked even), as in headerless text.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import DataError
from ..words import counted, sampling
from .records import MIN_SAMPLES, Records, force_channels, hammer_channel
from .text import ORIENTATIONS
from .timebase import UnevenClock, binary_resolution, even_step as _even_step_any

#: Largest array read from a binary file, in bytes (as for NPZ).
MAX_ARRAY_BYTES = 2 << 30
TIME_NAMES = ("t", "time", "times", "time_s", "t_s", "tt", "timevector", "time_vector")
DT_NAMES = ("dt", "ts", "delta_t", "deltat", "sampling_interval", "sample_interval", "wf_increment", "dx", "delta_x")
FS_NAMES = ("fs", "sf", "srate", "sample_rate", "sampling_rate", "samplerate", "sampling_frequency", "fsamp",
            "rate")


@dataclass
class Var:
    """A named array in a file, not read yet. name: as the user chooses it (MAT name, HDF5 path); shape; kind: the
    numpy dtype kind ('f', 'i', 'u', 'c', 'b', or '?' for what is not a plain array); read: () -> ndarray, checked
    against the bytes the file holds; attrs: units ("units", str or one per channel), channel names ("channels"),
    the channels' points ("points", one label per channel, era.core.points) and sampling (dt/fs names above) stored
    with it."""

    name: str
    shape: tuple
    kind: str
    read: Callable[[], np.ndarray]
    attrs: dict = field(default_factory=dict)

    @property
    def key(self) -> str:
        return self.name.rsplit("/", 1)[-1].lower()


def check_size(shape, itemsize: int, held: int, where: str, compressed: bool = False) -> None:
    """DataError unless ``shape`` × ``itemsize`` bytes can come from ``held`` bytes of the file (1032:1 at most for
    zlib-compressed data) and stay under MAX_ARRAY_BYTES. Called before anything is allocated."""
    promised = int(np.prod(shape, dtype=np.float64)) * itemsize
    limit = held * 1032 if compressed else held
    if promised > limit:
        raise DataError(f"{where}: the header promises shape {tuple(shape)} ({promised} bytes) but the file holds "
                        f"{held} bytes for it; the file is truncated or its header is wrong.")
    if promised > MAX_ARRAY_BYTES:
        raise DataError(f"{where}: {promised / 2**30:.1f} GiB is above the {MAX_ARRAY_BYTES / 2**30:.0f} GiB limit.")


def _scalar(value, where: str, what: str) -> float:
    a = np.asarray(value)
    if a.dtype.kind not in "fiu" or a.size != 1:
        raise DataError(f"{where}: `{what}` must be one number, got {a.dtype} of shape {a.shape}.")
    x = float(a.reshape(-1)[0])
    if not (np.isfinite(x) and x > 0):
        raise DataError(f"{where}: `{what}` = {x!r} is not a positive number.")
    return x


def _pick(vars_: list[Var], variable, label: str) -> list[Var]:
    timing = set(TIME_NAMES + DT_NAMES + FS_NAMES)
    if variable is not None:
        wanted = [variable] if isinstance(variable, str) else list(variable)
        by_name = {v.name: v for v in vars_} | {v.name.lstrip("/"): v for v in vars_}
        missing = [w for w in wanted if w not in by_name]
        if missing:
            raise DataError(f"{label}: no array named {', '.join(map(repr, missing))}; the file holds "
                            f"{_listing(vars_)}.", option="variable")
        return [by_name[w] for w in wanted]
    data = [v for v in vars_ if v.key not in timing and v.kind in "fiu" and 1 <= len(v.shape) <= 2
            and max(v.shape, default=0) >= MIN_SAMPLES]
    if not data:
        raise DataError(f"{label}: no numeric array of at least {MIN_SAMPLES} samples; the file holds "
                        f"{_listing(vars_)}.")
    if len(data) == 1 or (all(len(v.shape) == 1 or min(v.shape) == 1 for v in data)
                          and len({max(v.shape) for v in data}) == 1):
        return data
    raise DataError(f"{label}: several arrays could be the data: {_listing(data)}; choose with "
                    f"variable={data[0].name!r} (or a list of names read side by side as channels).", option="variable")


def _listing(vars_: list[Var]) -> str:
    shown = ", ".join(f"{v.name!r} {'×'.join(map(str, v.shape)) or 'scalar'}" for v in vars_[:12])
    return shown + (f" and {len(vars_) - 12} more" if len(vars_) > 12 else "") if vars_ else "nothing readable"


def _channels(var: Var, a: np.ndarray, orientation, label: str) -> np.ndarray:
    where = f"{label}: array {var.name!r}"
    if a.dtype.kind not in "fiu":
        raise DataError(f"{where} holds {a.dtype} values; time records are real numbers.")
    if a.ndim == 1:
        return np.asarray(a, dtype=float)[:, None]
    if a.ndim != 2:
        raise DataError(f"{where} has shape {a.shape}; give samples × channels (2-D), one record per file.")
    rows = orientation == "rows" if orientation else a.shape[0] < a.shape[1]
    return np.ascontiguousarray(a.T if rows else a, dtype=float)


def records_from_vars(vars_: list[Var], label: str, fmt: str, dt=None, variable=None,
                      orientation=None) -> Records:
    """Records ("time") from the arrays of a file; module docstring for the choices made."""
    if orientation is not None and orientation not in ORIENTATIONS:
        raise DataError(f"`orientation` must be 'rows' (one channel per row) or 'columns', got {orientation!r}.")
    chosen = _pick(vars_, variable, label)
    blocks = [_channels(v, v.read(), orientation, label) for v in chosen]
    n = {len(b) for b in blocks}
    if len(n) > 1:
        raise DataError(f"{label}: arrays {[v.name for v in chosen]} hold {[len(b) for b in blocks]} samples; "
                        "channels read side by side must be equally long.")
    if len(blocks) > 1:  # one copy into column-major storage: each channel is one contiguous column
        y = np.empty((len(blocks[0]), sum(b.shape[1] for b in blocks)), order="F")
        c = 0
        for b in blocks:
            y[:, c:c + b.shape[1]] = b
            c += b.shape[1]
    else:
        y = blocks[0]
    bad = ~np.isfinite(y) if not np.isfinite(np.add.reduce(y, axis=None)) else None  # one pass when all is well
    if bad is not None and bad.any():
        k, c = np.argwhere(bad)[0]
        raise DataError(f"{label}: {counted(bad.sum(), 'NaN or infinite value')}, the first at sample {k}, channel "
                        f"{c + 1}. Remove or interpolate them, then load again.")
    names, units, points = [], [], []
    for v, b in zip(chosen, blocks):
        given = [str(x) for x in np.atleast_1d(v.attrs.get("channels", []))]
        names += given if len(given) == b.shape[1] else (
            [v.name.lstrip("/")] if b.shape[1] == 1 else [f"{v.name.lstrip('/')}:{i + 1}" for i in range(b.shape[1])])  # file:channel
        unit = [str(x) for x in np.atleast_1d(v.attrs.get("units", ""))]
        units += unit if len(unit) == b.shape[1] else [unit[0]] * b.shape[1]
        where = [str(x).strip() for x in np.atleast_1d(v.attrs.get("points", []))]  # era.core.points labels (HDF5)
        points += where if len(where) == b.shape[1] else [""] * b.shape[1]
    lead = _time_channel(y, vars_, label)
    if lead is not None:  # a time axis stored as the first channel (np.vstack([t, force, acc]) and the like)
        step, start = lead
        how = f"{sampling(step)} from the first channel, a time axis"
        y, names, units, points = y[:, 1:], names[1:], units[1:], points[1:]
    else:
        step, start, how = _sampling(vars_, chosen, len(y), label, dt)
    force = force_channels(names, units)
    if lead is not None and not force.any():  # time, force, response rows (a hammer test's np.vstack)
        pulse = hammer_channel(y)
        if pulse is not None:
            force[pulse] = True
            how += (f"; {names[pulse]!r} proposed as the force (a short pulse: 99 % of its energy within "
                    f"{max(len(y) // 100, 1)} samples, the others ring on)")
    return Records(domain="time", values=[y], step=step, start=start, outputs=tuple(names),
                   output_units=tuple(units) if any(units) else (), force=force,
                   points={"channel_points": tuple(points)} if any(points) else None,
                   described=[f"{label}: {fmt}, {', '.join(v.name for v in chosen)} as "
                              f"{counted(y.shape[1], 'channel')} × {len(y)} samples, {how}"])


def even_step(t, resolution, where):
    """era.io.timebase.even_step; a jittered clock refused without the resample option (arrays take none)."""
    try:
        return _even_step_any(t, resolution, where)
    except UnevenClock as clock:
        raise DataError(str(clock).replace("Resample onto an even grid at that rate, or load an evenly sampled "
                                           "record.", "Resample the record onto an even grid, or save it as CSV "
                                           "with its time column: the import step can resample that.")) from None


def _time_channel(y: np.ndarray, vars_: list[Var], label: str) -> tuple[float, float] | None:
    """(Δt, start) when the first of several channels increases at every sample (a time axis: checked even, else
    DataError naming the step), and no variable is named as the time; else None."""
    if y.shape[1] < 2 or len(y) < 3 or any(v.key in TIME_NAMES for v in vars_):
        return None
    t = y[:, 0]
    if not np.all(np.diff(t) > 0):
        return None
    return even_step(t, binary_resolution(t), f"{label}: first channel (time)"), float(t[0])


def _sampling(vars_: list[Var], chosen: list[Var], n: int, label: str, dt) -> tuple[float, float, str]:
    """(Δt, start, how it was found): a time vector, then dt, then fs (variables, then the data's attributes)."""
    found = []
    for v in vars_:
        if v.key in TIME_NAMES and len(v.shape) <= 2 and max(v.shape, default=0) == n and v.kind in "fiu":
            stored = np.asarray(v.read()).reshape(-1)
            t = stored.astype(float)
            step = even_step(t, binary_resolution(stored), f"{label}: time vector {v.name!r}")
            found.append(("time vector", repr(v.name), step, float(t[0])))
        elif v.key in DT_NAMES and int(np.prod(v.shape)) == 1:
            found.append(("dt", repr(v.name), _scalar(v.read(), label, v.name), 0.0))
        elif v.key in FS_NAMES and int(np.prod(v.shape)) == 1:
            found.append(("fs", repr(v.name), 1 / _scalar(v.read(), label, v.name), 0.0))
    for v in chosen:
        for key, value in v.attrs.items():
            if key.lower() in DT_NAMES:
                found.append(("dt", f"attribute {key!r}", _scalar(value, label, key), 0.0))
            elif key.lower() in FS_NAMES:
                found.append(("fs", f"attribute {key!r}", 1 / _scalar(value, label, key), 0.0))
    if found:
        kind, name, step, start = found[0]
        for other in found[1:]:
            if abs(other[2] - step) > 1e-6 * step:
                raise DataError(f"{label}: {kind} {name} gives a sampling interval of {step:.9g} s but {other[0]} "
                                f"{other[1]} {other[2]:.9g} s; the file contradicts itself. Remove the wrong one.")
        return step, start, f"{sampling(step)} from {kind} {name}"
    if dt is not None:
        return float(dt), 0.0, f"{sampling(float(dt))} given"
    raise DataError(f"no sampling interval in {label}: give the sample rate (dt=...), or store it in the file as "
                    "fs (Hz), dt (s) or a time vector t.", option="dt")
