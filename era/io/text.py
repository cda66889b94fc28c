"""Headerless text: a bare matrix of numbers, one channel per column or one channel per row.

Acquisition scripts often save ``np.savetxt(y)`` or MATLAB's ``save -ascii``: no names, no units, no time. The
orientation is taken from the shape (records are far longer than they are wide: a matrix with fewer rows than
columns holds its channels in rows) unless the caller says ``orientation="rows"`` or ``"columns"``. A first column
(or row) that increases at every sample is a time axis and must be even (era.io.timebase); without one the caller
gives the sampling interval ``dt``.
"""

from __future__ import annotations


import numpy as np

from ..errors import DataError
from ..words import counted, sampling
from .records import Records, hammer_channel
from .timebase import UnevenClock, even_step_printed, resample as resample_onto

ORIENTATIONS = ("rows", "columns")


def read_headerless(numbered: list[tuple[int, str]], split, body: str, delim: str | None, label: str,
                    dt: float | None, orientation: str | None, notes: str, resample: bool = False) -> Records:
    """Records ("time") from the data lines of a text file without a header.

    numbered : (line number, text) of every data line; split : line -> cells; body : the data lines joined, decimal
    commas already turned into points; delim : the delimiter (None: blanks); notes : what the caller found (for
    ``described``); resample : True to put a time axis that scatters about a steady rate onto an even grid.
    """
    if orientation is not None and orientation not in ORIENTATIONS:
        raise DataError(f"`orientation` must be 'rows' (one channel per row) or 'columns' (one channel per column), "
                        f"got {orientation!r}.")
    try:
        table = np.loadtxt(body.splitlines(), delimiter=delim, ndmin=2, dtype=float, comments=None)
    except ValueError as exc:
        raise DataError(_first_bad(numbered, split, label) or f"{label}: not a matrix of numbers ({exc}).") from None
    n_rows, n_cols = table.shape
    chosen = orientation or ("rows" if n_rows < n_cols else "columns")
    bad = ~np.isfinite(table)
    if bad.any():
        r, c = np.argwhere(bad)[0]
        raise DataError(f"{label}, line {numbered[r][0]}, value {c + 1}: NaN or infinite ({int(bad.sum())} in all). "
                        "Remove or interpolate them, then load again.")
    y = table.T if chosen == "rows" else table
    t = y[:, 0]
    time = len(t) > 2 and y.shape[1] > 1 and bool(np.all(np.diff(t) > 0))
    if time:
        if chosen == "columns":
            lines = np.array([k for k, _ in numbered])
            sample = [split(ln)[0] for _, ln in numbered[:200] + numbered[-200:]]
            first = lambda: [split(ln)[0] for _, ln in numbered]  # noqa: E731
            where = f"{label}, column 1 (time)"
        else:
            lines = None
            cells = split(numbered[0][1])
            sample, first = cells[:200] + cells[-200:], lambda: cells  # noqa: E731
            where = f"{label}, line {numbered[0][0]} (time)"
        conversions = []
        try:
            step = even_step_printed(t, sample, first, where, lines)
            y = y[:, 1:]
        except UnevenClock as clock:
            if not resample:
                raise
            step = clock.step
            y, done = resample_onto(t, y[:, 1:], clock.step)
            conversions.append(f"{label}: {done}")
        start = float(t[0])
        found = f"time in the first {chosen[:-1]}, {sampling(step)}"
    elif dt is None:
        raise DataError(f"no sampling interval in {label}: give the sample rate (dt=...). The file is a bare matrix "
                        f"({n_rows} lines × {n_cols} values, read as {counted(y.shape[1], 'channel')} in {chosen}; "
                        f"say orientation='rows' or 'columns' if that is wrong).", option="dt")
    else:
        step, start, found, conversions = float(dt), 0.0, f"{sampling(float(dt))} given", []
    names = tuple(f"ch{i + 1}" for i in range(y.shape[1]))
    force = np.zeros(len(names), bool)
    pulse = hammer_channel(y) if time else None
    if pulse is not None:  # time, force, response columns without names: the short pulse is the hammer
        force[pulse] = True
        found += (f"; {names[pulse]} proposed as the force (a short pulse: 99 % of its energy within "
                  f"{max(len(y) // 100, 1)} samples, the others ring on)")
    how = "as given" if orientation else "from the shape"
    return Records(domain="time", values=[np.ascontiguousarray(y)], step=step, start=start, outputs=names,
                   output_units=(), force=force, conversions=conversions,
                   described=[f"{label}: headerless text, {counted(y.shape[1], 'channel')} in {chosen} ({how}) × "
                              f"{len(y)} samples, {found}{notes}"])


def _first_bad(numbered, split, label) -> str | None:
    """The message for the first line that breaks the matrix (only called after loadtxt failed)."""
    width = len(split(numbered[0][1]))
    for k, ln in numbered:
        cells = split(ln)
        if len(cells) != width:
            return (f"{label}, line {k}: {len(cells)} values where line {numbered[0][0]} has {width}; every line of "
                    "a matrix must hold the same number of values (a cut-off line?).")
        for c, cell in enumerate(cells):
            try:
                float(cell)
            except ValueError:
                return f"{label}, line {k}, value {c + 1}: {cell!r} is not a number."
    return None
