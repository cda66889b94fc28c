"""One record of a campaign, analysed the way the app analyses a dataset: the task every worker runs.

era.load → Markov parameters by the record's kind (NExT for ambient records) → era.identify with the Hankel size of
era.suggest.hankel_size → era.stabilization over the campaign's orders → the stable modes that pass the app's keep
rule (coherent: mean γ·μ ≥ era.stabilization.COHERENT_MIN; a decaying complex pair, era.keep_mask with
physical_only). What goes back to the caller is a few numbers per mode (:class:`RecordModes`), never a Hankel
matrix, so a task's answer is a few kB whatever the record's length.
"""

from __future__ import annotations

import os
import re
import traceback
from dataclasses import dataclass, field

import numpy as np

from ..errors import EraError
from ..indicators import mac
from ..io import load
from ..realization import identify
from ..selection import keep_mask
from ..stabilization import stabilization
from ..suggest import hankel_size


@dataclass(frozen=True)
class Settings:
    """How every record of a campaign is analysed (the same for all, so the modes compare).

    kind : era.load's conversion ("auto", "ambient", "decay", "pulse", "frf", "io").
    dt : sampling interval in s for CSV files without a time column, or None.
    rows, cols : Hankel block rows and columns; None: era.suggest.hankel_size of each record.
    orders : model orders of the stabilization diagram (tuple of int).
    min_stable_fraction : a mode must be stable in at least this fraction of the computed orders. The app's
        diagram asks for 3 orders because a person looks at it; a campaign has nobody to reject short-lived
        noise poles, and a physical mode of an ambient record stays stable over most orders (0 keeps every
        mode the app would mark coherent).
    load_options : extra keywords for era.load (e.g. references=[0, 1], n_lags=1024), as sorted (name, value)
        pairs so the settings stay hashable.
    """

    kind: str = "auto"
    dt: float | None = None
    rows: int | None = None
    cols: int | None = None
    orders: tuple = tuple(range(2, 81, 2))
    min_stable_fraction: float = 0.5
    load_options: tuple = field(default_factory=tuple)

    def fingerprint(self) -> str:
        """A text that changes whenever a setting that changes the result changes (for the cache)."""
        return repr((self.kind, self.dt, self.rows, self.cols, self.orders, self.min_stable_fraction,
                     self.load_options))


@dataclass(frozen=True, eq=False)
class RecordModes:
    """The modes one record gave, sorted by frequency (k modes, p outputs).

    index : position of the record in the campaign's sources; name : its file name (or "record i");
    time : numpy.datetime64 (s) read from the file name, or None;
    frequency_hz, frequency_std_hz, damping_ratio, emac, mpc : (k,) means over the orders where each mode is
    stable (the std is the spread across orders); n_orders : (k,) how many orders;
    shapes : (p, k) complex, the shape at the highest of those orders; outputs : the p channel names;
    kind : the conversion era.load used; rows, cols : the Hankel size; n_samples : Markov parameters used.
    """

    index: int
    name: str
    time: object
    frequency_hz: np.ndarray
    frequency_std_hz: np.ndarray
    damping_ratio: np.ndarray
    emac: np.ndarray
    mpc: np.ndarray
    n_orders: np.ndarray
    shapes: np.ndarray
    outputs: tuple
    kind: str
    rows: int
    cols: int
    n_samples: int

    @property
    def n_modes(self) -> int:
        return int(self.frequency_hz.size)


@dataclass(frozen=True)
class RecordFailure:
    """A record that could not be analysed: its position, name and the reason (a sentence for a person)."""

    index: int
    name: str
    reason: str


_STAMP = re.compile(r"(\d{4})-?(\d{2})-?(\d{2})[T_ -]?(\d{2})[-:h.]?(\d{2})(?:[-:m.]?(\d{2}))?")


def time_from_name(name: str):
    """The date and time in a file name (``2026-03-02T05-00``, ``20260302_050000``, ``2026-03-02 05:00:00``) as
    numpy.datetime64 in seconds, or None when the name holds none."""
    m = _STAMP.search(os.path.basename(str(name)))
    if not m:
        return None
    y, mo, d, h, mi, s = (int(g) if g else 0 for g in m.groups())
    try:
        return np.datetime64(f"{y:04d}-{mo:02d}-{d:02d}T{h:02d}:{mi:02d}:{s:02d}", "s")
    except ValueError:
        return None


def record_name(source, index: int) -> str:
    """A label for messages and the table: the file name of a path, ``record i`` for bytes."""
    if isinstance(source, (str, os.PathLike)):
        return os.path.basename(os.fspath(source))
    return f"record {index}"


def select_modes(stab, *, min_stable_fraction: float = 0.5, twin_mac: float = 0.9, twin_freq: float = 0.01) -> list:
    """The stable modes of a diagram a campaign keeps, as (StableMode, n_orders) sorted by frequency.

    Candidates are the Stabilization.modes that are coherent (StableMode.coherent, the app's mark) and decaying
    complex pairs (era.keep_mask with physical_only; a real pole has frequency 0). Noise often splits one physical
    mode into two tracks over the orders (two poles within ``twin_freq``, relative, with MAC ≥ ``twin_mac``):
    such twins count as one mode, the track stable over more orders, stable in the union of their orders. A mode
    is kept when that union covers ≥ ``min_stable_fraction`` of the diagram's orders.
    """
    modes = list(stab.modes)
    if not modes:
        return []
    f = np.array([m.frequency_hz for m in modes])
    keep = keep_mask([m.emac for m in modes], [m.mpc for m in modes], damping_ratio=[m.damping_ratio for m in modes],
                     is_pair=f > 0, physical_only=True) & np.array([m.coherent for m in modes])
    groups: list[tuple] = []  # (representative, set of orders)
    for m in sorted((m for m, k in zip(modes, keep) if k), key=lambda m: -len(m.orders)):
        for g, (rep, orders) in enumerate(groups):
            if (abs(rep.frequency_hz - m.frequency_hz) <= twin_freq * rep.frequency_hz
                    and mac(rep.shape[:, None], m.shape[:, None])[0, 0] >= twin_mac):
                groups[g] = (rep, orders | set(m.orders))
                break
        else:
            groups.append((m, set(m.orders)))
    need = min_stable_fraction * len(stab.orders)
    return sorted(((rep, len(o)) for rep, o in groups if len(o) >= need), key=lambda x: x[0].frequency_hz)


def modes_of(data, settings: Settings) -> tuple:
    """(kept StableModes, rows, cols) of one record's ResponseData: identify, stabilization, selection."""
    n, p, m = data.markov.shape
    choice = hankel_size(n, p, m)
    rows = settings.rows or choice.rows
    cols = settings.cols or choice.cols
    top = max(settings.orders)
    ident = identify(data, rows, cols, max_order=min(top, rows * p, cols * m))
    stab = stabilization(ident, settings.orders)
    return select_modes(stab, min_stable_fraction=settings.min_stable_fraction), rows, cols


def analyse_record(source, index: int, settings: Settings):
    """The campaign's task: one record in, :class:`RecordModes` or :class:`RecordFailure` out (never raises).

    source : a path or the bytes of a file era.load reads; index : its position among the campaign's sources.
    """
    name = record_name(source, index)
    try:
        _one_blas_thread()
        ds = load(source, name=name if isinstance(source, (bytes, bytearray)) else None, kind=settings.kind,
                  dt=settings.dt, **dict(settings.load_options))
        if ds.data is None:
            raise EraError(f"{name}: the file holds no response records (only geometry or modes).")
        modes, rows, cols = modes_of(ds.data, settings)
        p = ds.data.n_outputs
        shapes = np.stack([mo.shape for mo, _ in modes], axis=1) if modes else np.zeros((p, 0), complex)
        col = lambda attr: np.array([getattr(mo, attr) for mo, _ in modes], dtype=float)  # noqa: E731
        return RecordModes(
            index=index, name=name, time=time_from_name(name), frequency_hz=col("frequency_hz"),
            frequency_std_hz=col("frequency_std_hz"), damping_ratio=col("damping_ratio"), emac=col("emac"),
            mpc=col("mpc"), n_orders=np.array([n for _, n in modes], dtype=int), shapes=shapes,
            outputs=tuple(ds.data.outputs), kind=str(ds.source.get("kind")), rows=int(rows), cols=int(cols),
            n_samples=int(ds.data.n_samples))
    except EraError as exc:
        return RecordFailure(index, name, str(exc))
    except MemoryError:
        return RecordFailure(index, name, "out of memory on the worker: give fewer rows/cols or a worker with more "
                                          "memory.")
    except Exception as exc:  # a bad file must never stop a campaign; say where it broke
        where = traceback.extract_tb(exc.__traceback__)[-1]
        return RecordFailure(index, name, f"{type(exc).__name__}: {exc} (in {os.path.basename(where.filename)}, "
                                          f"line {where.lineno}); please report it with the file.")


_BLAS_LIMITED = []


def _one_blas_thread() -> None:
    """Workers run one record each, side by side: BLAS threads inside a task would only compete with them."""
    if _BLAS_LIMITED:
        return
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        return
    _BLAS_LIMITED.append(threadpool_limits(1))
