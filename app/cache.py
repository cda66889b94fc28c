"""What the app keeps in memory: datasets, identifications, realized models and stabilization diagrams with the
modes chosen from them.

One SVD per analysis (era.identify), with its diagram and era's choice of modes (app/choosing.py) computed in the
same worker call; every order after that is a cheap ``ident.model(order)`` (eq. 34 from the leading block),
cached per (analysis, order) for the order slider. Each result is computed once even when
several requests ask for it at the same time. An identification evicted from its LRU, or lost in a restart, is
recomputed from the stored dataset and the stored parameters. Every method may block (an SVD, a file read):
call them through app.jobs.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

import era

from . import choosing, compute, limits
from .config import Settings
from .errors import NotFound
from .store import Store

#: Loaded datasets kept in memory at most (and at most Settings.cache_dataset_bytes of them).
DATASETS_KEPT = 16
#: Staged uploads kept as read (a person previews, then makes the dataset): a few at once.
READS_KEPT = 4


@dataclass(frozen=True)
class CachedDataset:
    """A stored dataset as loaded: its id, the pulse responses, the geometry (or None) and its name."""

    id: str
    data: era.ResponseData
    geometry: era.Geometry | None
    name: str


@dataclass(frozen=True)
class Analysis:
    """A stored analysis, looked up once per request (routes/deps.py): its id, its dataset's id, the parameters
    it was identified with ({rows, cols, row_shifts, col_shifts, max_order}) and its dataset's data."""

    id: str
    dataset_id: str
    params: dict
    data: era.ResponseData
    geometry: era.Geometry | None
    name: str


def dataset_bytes(ds: CachedDataset) -> int:
    """The bytes a loaded dataset holds in memory (its pulse responses and records)."""
    records = ds.data.records
    return ds.data.markov.nbytes + (records.nbytes if records is not None else 0)


def identification_bytes(ident: era.Identification) -> int:
    """The bytes an identification holds: its P and Q and its own copy of the data (it comes back from a worker
    process pickled)."""
    data = ident.data
    records = data.records.nbytes if data.records is not None else 0
    return ident.P.nbytes + ident.Q.nbytes + data.markov.nbytes + records


def read_bytes(got) -> int:
    """The bytes uploaded files hold in memory once read (era.io.Read: their records' arrays)."""
    records = getattr(got, "records", None)
    return sum(np.asarray(v).nbytes for v in records.values) if records is not None else 0


class LRU:
    """A small thread-safe least-recently-used cache of at most ``size`` items and, when ``weigh`` (item -> bytes)
    is given, at most ``max_bytes`` in all (the newest item is kept even when it alone is larger)."""

    def __init__(self, size: int, max_bytes: int | None = None, weigh=None):
        self.size = max(1, int(size))
        self.max_bytes, self._weigh = max_bytes, weigh
        self.nbytes = 0
        self._items: OrderedDict = OrderedDict()
        self._lock = threading.Lock()

    def get(self, key):
        with self._lock:
            if key in self._items:
                self._items.move_to_end(key)
                return self._items[key]
            return None

    def put(self, key, value):
        with self._lock:
            if key in self._items:
                self.nbytes -= self._bytes(self._items[key])
            self._items[key] = value
            self._items.move_to_end(key)
            self.nbytes += self._bytes(value)
            while len(self._items) > self.size or (
                    self.max_bytes is not None and self.nbytes > self.max_bytes and len(self._items) > 1):
                self.nbytes -= self._bytes(self._items.popitem(last=False)[1])
        return value

    def _bytes(self, value) -> int:
        return self._weigh(value) if self._weigh is not None else 0


def _no_dataset(dataset_id: str) -> NotFound:
    return NotFound(f"No dataset with id {dataset_id!r}: upload the file again or pick an example.")


def _no_analysis(analysis_id: str) -> NotFound:
    return NotFound(f"No analysis with id {analysis_id!r}: run the identification again.")


class Cache:
    """The app-wide cache service over the store (app.state.cache)."""

    def __init__(self, store: Store, settings: Settings):
        self.store = store
        self.settings = settings
        self._datasets = LRU(DATASETS_KEPT, settings.cache_dataset_bytes, dataset_bytes)
        self._idents = LRU(settings.cache_identifications, settings.cache_identification_bytes,
                           identification_bytes)
        self._models = LRU(settings.cache_models)
        self._diagrams = LRU(settings.cache_identifications)
        #: staged uploads as their preview read them (era.io.Read), by importing.read_key: the dataset made
        #: next from the same files with the same reading options converts them without reading them again
        self.reads = LRU(READS_KEPT, settings.cache_dataset_bytes // 4, read_bytes)
        self._inflight: dict = {}
        self._inflight_lock = threading.Lock()

    # ---- datasets -----------------------------------------------------------------------------------
    def dataset(self, dataset_id: str) -> CachedDataset:
        """The dataset with this id (NotFound otherwise), read from the store on a cache miss."""
        hit = self._datasets.get(dataset_id)
        if hit is not None:
            return hit
        loaded = self.store.load_dataset(dataset_id)
        if loaded is None:
            raise _no_dataset(dataset_id)
        return self._datasets.put(dataset_id, CachedDataset(dataset_id, *loaded))

    def cached_dataset(self, dataset_id: str) -> CachedDataset | None:
        """The dataset if it is in memory, else None (never reads a file: safe on the event loop)."""
        return self._datasets.get(dataset_id)

    def add_dataset(self, data: era.ResponseData, geometry: era.Geometry | None, name: str, summary: dict) -> dict:
        """Store a dataset with its summary (payloads.dataset_summary); returns the stored summary (with id)."""
        dataset_id = self.store.add_dataset(data, geometry, name, summary)
        self._datasets.put(dataset_id, CachedDataset(dataset_id, data, geometry, name))
        return self.summary(dataset_id)

    def summary(self, dataset_id: str) -> dict:
        """The stored summary of a dataset (schemas.Dataset); NotFound for an unknown id."""
        s = self.store.dataset_summary(dataset_id)
        if s is None:
            raise _no_dataset(dataset_id)
        return dict(s, has_model=self.store.has_model(dataset_id))

    # ---- analyses -----------------------------------------------------------------------------------
    def analysis_row(self, analysis_id: str) -> tuple[str, dict]:
        """(dataset_id, params) of a stored analysis (one quick SQL read); NotFound for an unknown id."""
        row = self.store.analysis(analysis_id)
        if row is None:
            raise _no_analysis(analysis_id)
        return row

    def analysis(self, analysis_id: str, row: tuple[str, dict] | None = None) -> Analysis:
        """The analysis record, with its dataset loaded (``row``: its stored row, if already read)."""
        dataset_id, params = row or self.analysis_row(analysis_id)
        ds = self.dataset(dataset_id)
        return Analysis(analysis_id, dataset_id, params, ds.data, ds.geometry, ds.name)

    def new_analysis(self, dataset: CachedDataset, params: dict) -> tuple[Analysis, era.Identification]:
        """Identify a dataset (one SVD, within the server's limits) with its diagram and chosen modes, then store
        the analysis and cache its results."""
        ident, diagram = self._compute(choosing.analyse_dataset, dataset.data, params, self.settings)
        analysis_id = self.store.add_analysis(dataset.id, params)
        a = Analysis(analysis_id, dataset.id, params, dataset.data, dataset.geometry, dataset.name)
        self._diagrams.put(analysis_id, diagram)
        return a, self._idents.put(analysis_id, ident)

    def is_identified(self, a: Analysis) -> bool:
        """The identification is in memory: asking for it, or for a model, will not take an SVD."""
        return self._idents.get(a.id) is not None

    def is_diagrammed(self, a: Analysis) -> bool:
        """The diagram and the choice are in memory: asking for them takes no computation."""
        return self._diagrams.get(a.id) is not None

    def identification(self, a: Analysis) -> era.Identification:
        """The cached Identification, or recomputed from the stored dataset (once, even if asked twice)."""
        hit = self._idents.get(a.id)
        if hit is not None:
            return hit
        return self._once(self._idents, a.id, lambda: self._compute(limits.identify_within_limits, a.data, a.params, self.settings))

    def model(self, a: Analysis, order: int) -> era.ModalModel:
        """The model of one order (era.OrderError above the identification's max_order)."""
        key = (a.id, int(order))
        hit = self._models.get(key)
        if hit is None:  # the modes and the reconstruction of a slider step ask at the same time: realize once
            hit = self._once(self._models, key, lambda: self.identification(a).model(int(order)))
        return hit

    def diagram(self, a: Analysis) -> choosing.Diagram:
        """The stabilization diagram (orders 2, 4, … up to min(max_order, the diagram's limit)) and the modes era
        chooses from it in the dataset's band; recomputed from the identification when not in memory."""
        hit = self._diagrams.get(a.id)
        if hit is None:
            band = choosing.band_of(a.data)
            hit = self._once(self._diagrams, a.id, lambda: self._compute(choosing.diagram, self.identification(a),
                                                                         band, self.settings))
        return hit

    def stabilization(self, a: Analysis) -> era.Stabilization:
        """The stabilization diagram alone (see :meth:`diagram`)."""
        return self.diagram(a).stabilization

    def _compute(self, fn, *args):
        """CPU-bound work in a worker process (app/compute.py): it holds neither this process's GIL nor its
        cores' priority against the slider."""
        return compute.run(fn, *args, workers=self.settings.heavy_workers)

    def _once(self, cache: LRU, key, make):
        """cache[key], computed by one thread while others asking for the same key wait for it. (The lock is
        per cache and key: the stabilization of an analysis may wait for its identification.)"""
        slot = (id(cache), key)
        with self._inflight_lock:
            lock = self._inflight.setdefault(slot, threading.Lock())
        try:
            with lock:
                hit = cache.get(key)
                if hit is None:
                    hit = cache.put(key, make())
                return hit
        finally:
            with self._inflight_lock:
                self._inflight.pop(slot, None)
