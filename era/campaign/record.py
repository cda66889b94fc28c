"""One record of a campaign, analysed the way the app analyses a dataset: the task every worker runs.

era.load → Markov parameters by the record's kind (NExT for ambient records) → era.analyse (one SVD, the
stabilization diagram over the campaign's orders with the data's uncertainty, and THE choice of the structure's
modes, era.choose_modes) with the campaign's Hankel size. A record's modes are the chosen model's: frequencies,
damping, γ, μ and shapes at the one order era.choose_modes reads them at, with their standard deviations from the
data. What goes back to the caller is a few numbers per mode (:class:`RecordModes`), never a Hankel matrix, so a
task's answer is a few kB whatever the record's length.
"""

from __future__ import annotations

import os
import re
import traceback
from dataclasses import dataclass, field

import numpy as np

from ..choice.analysis import AnalysisResult, analyse
from ..errors import EraError
from ..io import load
from ..core.suggest import hankel_size


@dataclass(frozen=True)
class CampaignSettings:
    """How every record of a campaign is analysed (the same for all, so the modes compare).

    kind : era.load's conversion ("auto", "ambient", "decay", "pulse", "frf", "io").
    dt : sampling interval in s for CSV files without a time column, or None.
    rows, cols : Hankel block rows and columns; None: era.core.suggest.hankel_size of each record.
    orders : model orders of the stabilization diagram (tuple of int); orders above what the Hankel size allows
        are left out.
    load_options : extra keywords for era.load (e.g. references=[0, 1], n_lags=1024), as sorted (name, value)
        pairs so the settings stay hashable.

    Which of the diagram's modes a record keeps is not a setting: it is era.choose_modes, the rule the app and
    explain use.
    """

    kind: str = "auto"
    dt: float | None = None
    rows: int | None = None
    cols: int | None = None
    orders: tuple = tuple(range(2, 81, 2))
    load_options: tuple = field(default_factory=tuple)

    def fingerprint(self) -> str:
        """A text that changes whenever a setting that changes the result changes (for the cache), the thresholds
        of era.choose_modes included: a cache made under other thresholds is not mixed into a new table."""
        return repr((self.kind, self.dt, self.rows, self.cols, self.orders, self.load_options, _rule_constants()))


def _rule_constants() -> tuple:
    from .. import __version__
    from ..choice import choose as choice, evidence
    return (__version__,) + tuple((k, getattr(m, k)) for m in (choice, evidence) for k in sorted(vars(m))
                                  if k.isupper())


@dataclass(frozen=True, eq=False)
class RecordModes:
    """The modes one record gave: those era.choose_modes chose, sorted by frequency (k modes, p outputs).

    index : position of the record in the campaign's sources; name : its file name (or "record i");
    time : numpy.datetime64 (s) read from the file name, or None;
    frequency_hz, damping_ratio, emac, mpc : (k,) the chosen model's (ModalModel at ``order``: Hz, fraction, γ, μ);
    frequency_std_hz, damping_std : (k,) their standard deviations from the data at that order (era.core.uncertainty;
        NaN where not computed);
    n_orders : (k,) at how many of the diagram's orders the mode is a stable pole (its track and its split
        twins);
    shapes : (p, k) complex, the chosen model's shapes; outputs : the p channel names;
    order : the diagram order the modes are read at (ModeChoice.order);
    rejected : ((frequency_hz, code, reason), ...) the diagram's other clusters and why each is not a mode
        (era.Candidate's code and reason), by frequency;
    kind : the conversion era.load used; rows, cols : the Hankel size; n_samples : Markov parameters used;
    spares : the diagram's other clusters (those in ``rejected``) as (frequency_hz, damping_ratio,
        frequency_std_hz, damping_std, emac, mpc, n_orders, shape (p,) complex), by frequency: a tracked mode
        the choice left out of this record is looked for among them (era.campaign.track_modes); index
        ``n_modes + k`` is spare k (:func:`mode_value`, :func:`mode_shape`);
    poles : the diagram's poles that are stable in frequency (a partner at the previous order), the material a
        tracked mode the record's clusters miss is looked up in (era.campaign.lookup), as :class:`DiagramPoles`
        or None.
    """

    index: int
    name: str
    time: object
    frequency_hz: np.ndarray
    frequency_std_hz: np.ndarray
    damping_ratio: np.ndarray
    damping_std: np.ndarray
    emac: np.ndarray
    mpc: np.ndarray
    n_orders: np.ndarray
    shapes: np.ndarray
    outputs: tuple
    kind: str
    rows: int
    cols: int
    n_samples: int
    order: int = 0
    rejected: tuple = ()
    spares: tuple = ()
    poles: object = None

    @property
    def n_modes(self) -> int:
        return int(self.frequency_hz.size)


@dataclass(frozen=True, eq=False)
class DiagramPoles:
    """q poles of one record's stabilization diagram (those stable in frequency, positive frequency).

    order, frequency_hz, damping_ratio, emac, mpc : (q,) each pole's model order and values (Hz, fraction, γ, μ);
    cluster : (q,) the record's mode the pole belongs to: k < n_modes a chosen mode, n_modes + k spare k, -1 none;
    shapes : (p, q) complex.
    """

    order: np.ndarray
    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    emac: np.ndarray
    mpc: np.ndarray
    cluster: np.ndarray
    shapes: np.ndarray

    @property
    def size(self) -> int:
        return int(self.order.size)


#: The values of a spare mode, in the order RecordModes.spares holds them.
SPARE_FIELDS = ("frequency_hz", "damping_ratio", "frequency_std_hz", "damping_std", "emac", "mpc", "n_orders",
                "shape")


def mode_value(rec: RecordModes, name: str, i: int) -> float:
    """The value ``name`` (a RecordModes array: frequency_hz, damping_ratio, ...) of the record's mode i: a chosen
    mode for i < n_modes, else spare i - n_modes."""
    if i < rec.n_modes:
        return float(getattr(rec, name)[i])
    return float(rec.spares[i - rec.n_modes][SPARE_FIELDS.index(name)])


def mode_shape(rec: RecordModes, i: int) -> np.ndarray:
    """(p,) complex shape of the record's mode i (a chosen mode, or a spare for i ≥ n_modes)."""
    return rec.shapes[:, i] if i < rec.n_modes else np.asarray(rec.spares[i - rec.n_modes][-1], complex)


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


def modes_of(data, settings: CampaignSettings) -> tuple[AnalysisResult, int, int]:
    """(era.AnalysisResult, rows, cols) of one record's ResponseData: era.analyse with the campaign's Hankel size
    (era.core.suggest.hankel_size of the record where ``settings`` gives none) and orders."""
    n, p, m = data.markov.shape
    size = hankel_size(n, p, m)
    rows = settings.rows or size.rows
    cols = settings.cols or size.cols
    top = min(max(settings.orders), rows * p, cols * m)
    return analyse(data, rows=rows, cols=cols, max_order=top, orders=settings.orders), rows, cols


def record_modes(result: AnalysisResult, *, index: int, name: str, outputs, kind: str, rows: int, cols: int,
                 n_samples: int) -> RecordModes:
    """The :class:`RecordModes` of one record's era.analyse result: the chosen model's values."""
    model, choice = result.model, result.choice
    std = lambda v: np.full(model.n_modes, np.nan) if v is None else np.asarray(v, dtype=float)  # noqa: E731
    n_orders = [len(set(c.orders).union(*(t.orders for t in choice.rejected if t.code == "twin" and t.mode == k)))
                for k, c in enumerate(choice.chosen)]
    spare_clusters = [c for c in choice.rejected if np.isfinite(c.frequency_hz) and c.frequency_hz > 0]
    return RecordModes(
        index=index, name=name, time=time_from_name(name), frequency_hz=np.asarray(model.frequency_hz, float),
        frequency_std_hz=std(model.frequency_std_hz), damping_ratio=np.asarray(model.damping_ratio, float),
        damping_std=std(model.damping_std), emac=np.asarray(model.emac, float), mpc=np.asarray(model.mpc, float),
        n_orders=np.array(n_orders, dtype=int), shapes=np.asarray(model.shapes, complex), outputs=tuple(outputs),
        kind=str(kind), rows=int(rows), cols=int(cols), n_samples=int(n_samples), order=int(choice.order),
        rejected=tuple((float(c.frequency_hz), str(c.code), str(c.reason)) for c in choice.rejected),
        spares=tuple((float(c.frequency_hz), float(c.damping_ratio), float(c.frequency_std_hz), float(c.damping_std),
                      float(c.emac), float(c.mpc), len(c.orders), np.asarray(c.shape, complex))
                     for c in spare_clusters),
        poles=diagram_poles(result.stabilization, list(choice.chosen) + spare_clusters))


def diagram_poles(stab, clusters) -> DiagramPoles:
    """The :class:`DiagramPoles` of an era.Stabilization: its poles stable in frequency, each marked with the
    position of the cluster (era.choice Candidate, in ``clusters``: the chosen modes, then the spares) it belongs to."""
    owner = np.full(stab.frequency_hz.size, -1)
    for k, c in enumerate(clusters):
        owner[list(c.pole_indices)] = k
    keep = np.flatnonzero(np.asarray(stab.stable_frequency, bool) & (stab.frequency_hz > 0))
    return DiagramPoles(order=np.asarray(stab.order)[keep].astype(int), frequency_hz=stab.frequency_hz[keep],
                        damping_ratio=stab.damping_ratio[keep], emac=stab.emac[keep], mpc=stab.mpc[keep],
                        cluster=owner[keep], shapes=np.asarray(stab.shapes)[:, keep].astype(complex))


def analyse_record(source, index: int, settings: CampaignSettings):
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
        result, rows, cols = modes_of(ds.data, settings)
        return record_modes(result, index=index, name=name, outputs=ds.data.outputs, kind=ds.source.get("kind"),
                            rows=rows, cols=cols, n_samples=ds.data.n_samples)
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
