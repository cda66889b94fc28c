"""The analyses behind the API: ERA calls, the in-memory caches, and the JSON each route returns.

One SVD per analysis (era.identify); every order after that is a cheap ``ident.realize(order)`` (eq. 34 from
the leading block), cached per (analysis, order) for the order slider. An identification evicted from the
cache, or lost in a restart, is recomputed from the stored dataset and the stored parameters.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from dataclasses import replace

import numpy as np

import era
from era.spectrum import cmif
from era.suggest import hankel_size, order_from_singular_values

from .config import Settings
from .store import Store


class NotFound(LookupError):
    """An unknown dataset, analysis or report id (404)."""


class LRU:
    """A small thread-safe least-recently-used cache."""

    def __init__(self, size: int):
        self.size = max(1, int(size))
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
            self._items[key] = value
            self._items.move_to_end(key)
            while len(self._items) > self.size:
                self._items.popitem(last=False)
        return value


# ---- JSON helpers -------------------------------------------------------------------------------------
def floats(values) -> list:
    """A float array as a JSON list: NaN and ±inf (not valid JSON) become null."""
    a = np.asarray(values, dtype=float)
    out = a.tolist()
    if not np.isfinite(a).all():
        return _nulls(out)
    return out


def _nulls(x):
    if isinstance(x, list):
        return [_nulls(v) for v in x]
    return x if math.isfinite(x) else None


def decimate(n_samples: int, max_points: int) -> slice:
    return slice(None, None, max(1, math.ceil(n_samples / max_points)))


def fit_percent(error) -> list:
    """Fit 100 (1 - e) in percent from the normalised RMS error e (p, m); can be negative for a bad model."""
    return floats(100.0 * (1.0 - np.asarray(error, dtype=float)))


# ---- datasets -------------------------------------------------------------------------------------------
def dataset_summary(data: era.ResponseData, geometry: era.Geometry | None, name: str, settings: Settings,
                    source: dict | None = None) -> dict:
    """What the API says about a dataset, with the default Hankel size and the limits that apply to it."""
    n, p, m = data.markov.shape
    choice = hankel_size(n, p, m, max_elements=settings.max_hankel_elements, max_order=min(200, settings.max_order))
    return {
        "name": name,
        "outputs": list(data.outputs), "inputs": list(data.inputs),
        "output_units": list(data.output_units) if data.output_units else None,
        "input_units": list(data.input_units) if data.input_units else None,
        "dt": data.dt, "n_samples": n, "n_outputs": p, "n_inputs": m,
        "duration_s": n * data.dt, "nyquist_hz": 0.5 / data.dt,
        "geometry": None if geometry is None else {"n_nodes": int(geometry.n_nodes), "units": geometry.units,
                                                   "n_edges": int(len(geometry.edges))},
        "source": source or {},
        "defaults": {"rows": choice.rows, "cols": choice.cols, "max_order": choice.max_order},
        "limits": {"rows_plus_cols_max": n, "max_hankel_elements": settings.max_hankel_elements,
                   "max_order": settings.max_order,
                   "note": (f"With consecutive shifts rows + cols ≤ {n} (N samples); rows·{p} × cols·{m} ≤ "
                            f"{settings.max_hankel_elements:,} elements; max order ≤ min(rows·{p}, cols·{m}, "
                            f"{settings.max_order}).")},
    }


def records_json(data: era.ResponseData, settings: Settings, input_index: int = 0) -> dict:
    sl = decimate(data.n_samples, settings.max_plot_points)
    return {"time_s": floats(data.time_s[sl]), "input": data.inputs[input_index],
            "outputs": list(data.outputs), "series": [floats(data.markov[sl, i, input_index])
                                                      for i in range(data.n_outputs)]}


def spectrum_json(data: era.ResponseData, settings: Settings) -> dict:
    f, values = cmif(data)
    sl = decimate(f.size, settings.max_plot_points)
    return {"frequency_hz": floats(f[sl]), "values": [floats(v[sl]) for v in values]}


# ---- analyses ---------------------------------------------------------------------------------------------
def check_hankel(params: dict, n_samples: int, p: int, m: int, settings: Settings) -> None:
    """Raise era.HankelError when H(0) would break this server's memory/time limit, saying what fits."""
    rows, cols = params["rows"], params["cols"]
    elements = rows * p * cols * m
    limit = settings.max_hankel_elements
    if elements > limit:
        what = (f"H(0) would be {rows * p} × {cols * m} = {elements:,} elements (rows·p × cols·m with p = {p} "
                f"outputs, m = {m} inputs), above this server's limit of {limit:,} (ERA_MAX_HANKEL_ELEMENTS).")
        if p * m > limit:
            raise era.HankelError(f"{what} Even rows = cols = 1 is too large: raise the limit or use fewer channels.")
        fit_rows = max(1, min(math.isqrt(limit // (p * m)), rows))
        fit_cols = max(1, min(cols, limit // (p * m * fit_rows)))
        raise era.HankelError(f"{what} For example rows = {fit_rows}, cols = {fit_cols} fits.")
    max_order = params.get("max_order")
    cap = min(rows * p, cols * m, settings.max_order)
    if max_order is not None and max_order > cap:
        raise era.OrderError(
            f"max_order = {max_order} is above what this Hankel size and server allow: min(rows·p = {rows * p}, "
            f"cols·m = {cols * m}, server limit {settings.max_order}) = {cap}. Choose max_order ≤ {cap}.")


class Engine:
    """Datasets, identifications and models, cached; every method is blocking (call it through app.jobs)."""

    def __init__(self, store: Store, settings: Settings):
        self.store = store
        self.settings = settings
        self._datasets = LRU(16)
        self._idents = LRU(settings.cache_identifications)
        self._models = LRU(settings.cache_models)
        self._stabs = LRU(settings.cache_identifications)
        self._inflight: dict = {}
        self._inflight_lock = threading.Lock()

    # datasets
    def dataset(self, dataset_id: str) -> tuple[era.ResponseData, era.Geometry | None, str]:
        hit = self._datasets.get(dataset_id)
        if hit is not None:
            return hit
        loaded = self.store.load_dataset(dataset_id)
        if loaded is None:
            raise NotFound(f"No dataset with id {dataset_id!r}: upload the file again or pick an example.")
        return self._datasets.put(dataset_id, loaded)

    def add_dataset(self, data, geometry, name: str, source: dict | None = None,
                    rows: int | None = None, cols: int | None = None) -> dict:
        """Store a dataset; ``rows``/``cols`` override the default Hankel size (e.g. the paper's choice)."""
        summary = dataset_summary(data, geometry, name, self.settings, source)
        if rows and cols:
            cap = min(rows * data.n_outputs, cols * data.n_inputs, 200, self.settings.max_order)
            summary["defaults"] = {"rows": rows, "cols": cols, "max_order": cap}
        dataset_id = self.store.add_dataset(data, geometry, name, summary)
        self._datasets.put(dataset_id, (data, geometry, name))
        return self.store.dataset_summary(dataset_id)

    def summary(self, dataset_id: str) -> dict:
        s = self.store.dataset_summary(dataset_id)
        if s is None:
            raise NotFound(f"No dataset with id {dataset_id!r}: upload the file again or pick an example.")
        return s

    # identifications
    def _identify(self, data: era.ResponseData, params: dict) -> era.Identification:
        n, p, m = data.markov.shape
        check_hankel(params, n, p, m, self.settings)
        max_order = params.get("max_order") or min(params["rows"] * p, params["cols"] * m, self.settings.max_order)
        ident = era.identify(data, params["rows"], params["cols"], params.get("row_shifts"),
                             params.get("col_shifts"), max_order=max_order)
        if ident.max_order == 0:
            raise era.DataError("H(0) has rank 0: the records are zero (or round-off) throughout, so there is "
                                "nothing to identify. Check the file's channels and scaling.")
        return ident

    def new_analysis(self, dataset_id: str, params: dict) -> tuple[str, era.Identification]:
        data, _, _ = self.dataset(dataset_id)
        ident = self._identify(data, params)
        analysis_id = self.store.add_analysis(dataset_id, params)
        return analysis_id, self._idents.put(analysis_id, ident)

    def analysis(self, analysis_id: str) -> tuple[str, dict]:
        row = self.store.analysis(analysis_id)
        if row is None:
            raise NotFound(f"No analysis with id {analysis_id!r}: run the identification again.")
        return row

    def identification(self, analysis_id: str) -> era.Identification:
        """The cached Identification, or recomputed from the stored dataset (once, even if asked twice)."""
        hit = self._idents.get(analysis_id)
        if hit is not None:
            return hit
        dataset_id, params = self.analysis(analysis_id)
        return self._once(self._idents, analysis_id,
                          lambda: self._identify(self.dataset(dataset_id)[0], params))

    def _once(self, cache: LRU, key, compute):
        """cache[key], computed by one thread while others asking for the same key wait for it."""
        with self._inflight_lock:
            lock = self._inflight.setdefault(key, threading.Lock())
        try:
            with lock:
                hit = cache.get(key)
                if hit is None:
                    hit = cache.put(key, compute())
                return hit
        finally:
            with self._inflight_lock:
                self._inflight.pop(key, None)

    def is_cached(self, analysis_id: str) -> bool:
        return self._idents.get(analysis_id) is not None

    def model(self, analysis_id: str, order: int) -> era.ModalModel:
        key = (analysis_id, int(order))
        hit = self._models.get(key)
        if hit is None:  # the modes and the reconstruction of a slider step ask at the same time: realize once
            hit = self._once(self._models, key, lambda: self.identification(analysis_id).realize(int(order)))
        return hit

    def stabilization(self, analysis_id: str):
        hit = self._stabs.get(analysis_id)
        if hit is None:
            ident = self.identification(analysis_id)
            top = min(ident.max_order, self.settings.max_stabilization_order)
            orders = range(2, top + 1, 2) if top >= 2 else range(1, top + 1)
            hit = self._stabs.put(analysis_id, era.stabilization(ident, orders))
        return hit


# ---- JSON of results ---------------------------------------------------------------------------------
def analysis_json(analysis_id: str, dataset_id: str, params: dict, ident: era.Identification) -> dict:
    d = ident.singular_values
    return {
        "id": analysis_id, "dataset_id": dataset_id, "rows": ident.rows, "cols": ident.cols,
        "row_shifts": ident.row_shifts[1:].tolist(), "col_shifts": ident.col_shifts[1:].tolist(),
        "max_order": ident.max_order, "requested_max_order": params.get("max_order"),
        "hankel_shape": [int(ident.P.shape[0]), int(ident.Q.shape[0])], "svd_method": ident.svd_method,
        "singular_values": floats(d[: min(d.size, max(2 * ident.max_order, 50), 2000)]),
        "suggested_order": order_from_singular_values(d, ident.max_order),
    }


def modes_json(model: era.ModalModel, data: era.ResponseData, with_fit: bool = True) -> dict:
    """The modes of one order; with_fit adds the fit of all modes to every channel (one full reconstruction)."""
    contrib = np.asarray(model.contribution, dtype=float)
    top = np.max(contrib[np.isfinite(contrib)]) if np.isfinite(contrib).any() and contrib.size else 1.0
    rel = contrib / top if top > 0 else np.zeros_like(contrib)
    error = model.fit_error(data) if with_fit else None
    return {
        "order": model.order, "n_modes": model.n_modes, "outputs": list(data.outputs), "inputs": list(data.inputs),
        "frequency_hz": floats(model.frequency_hz), "natural_frequency_hz": floats(model.natural_frequency_hz),
        "eigenvalue_re": floats(model.eigenvalues.real), "eigenvalue_im": floats(model.eigenvalues.imag),
        "damping_ratio": floats(model.damping_ratio), "emac": floats(model.emac), "mpc": floats(model.mpc),
        "emac_mpc": floats(model.emac * model.mpc), "contribution": floats(contrib),
        "contribution_relative": floats(rel), "is_pair": model.is_pair.tolist(),
        "shapes_re": [floats(c) for c in model.shapes.real.T], "shapes_im": [floats(c) for c in model.shapes.imag.T],
        "fit_percent": None if error is None else fit_percent(error),
        "fit_percent_overall": None if error is None else float(np.nanmean(100 * (1 - np.minimum(error, 1e6)))),
    }


def parse_modes(modes: str | list | None, n_modes: int) -> np.ndarray | None:
    """Kept mode indices from "0,2,5" or a list; None keeps all. Raises era.EraError for bad ones."""
    if modes is None:
        return None
    if isinstance(modes, str):
        items = [x.strip() for x in modes.split(",") if x.strip()]
        try:
            idx = [int(x) for x in items]
        except ValueError:
            raise era.EraError(f"`modes` must be comma-separated mode numbers like 0,2,5; got {modes!r}.") from None
    else:
        idx = [int(x) for x in modes]
    bad = [i for i in idx if not 0 <= i < n_modes]
    if bad:
        raise era.EraError(f"Mode {bad[0]} does not exist: this order has {n_modes} modes (0..{n_modes - 1}).")
    return np.array(sorted(set(idx)), dtype=int)


def kept_by_thresholds(model: era.ModalModel, min_emac: float = 0.0, min_mpc: float = 0.0,
                       min_contribution: float = 0.0, physical_only: bool = False) -> np.ndarray:
    """Indices of the modes with γ ≥ min_emac, μ ≥ min_mpc, contribution ≥ min_contribution × the largest
    (as ModalModel.select), and if physical_only, complex pairs that decay (0 < ζ < 1): real poles and growing
    (negative damping) poles are computational. The automatic keep/reject of the modes table."""
    for value, name in ((min_emac, "min_emac"), (min_mpc, "min_mpc"), (min_contribution, "min_contribution")):
        if not 0.0 <= value <= 1.0:
            raise era.EraError(f"`{name}` is a fraction in [0, 1], got {value!r}.")
    contrib = np.asarray(model.contribution, dtype=float)
    top = np.max(contrib[np.isfinite(contrib)]) if np.isfinite(contrib).any() else 0.0
    keep = (model.emac >= min_emac) & (model.mpc >= min_mpc) & (contrib >= min_contribution * top)
    if physical_only:
        zeta = model.damping_ratio
        keep &= model.is_pair & (zeta > 0) & (zeta < 1)
    return np.flatnonzero(keep)


def reconstruction_json(model: era.ModalModel, data: era.ResponseData, kept: np.ndarray | None, output: int,
                        input_: int, settings: Settings) -> dict:
    p, m = data.n_outputs, data.n_inputs
    if not 0 <= output < p:
        raise era.EraError(f"`output` must be 0..{p - 1} (this dataset has {p} outputs), got {output}.")
    if not 0 <= input_ < m:
        raise era.EraError(f"`input` must be 0..{m - 1} (this dataset has {m} inputs), got {input_}.")
    reduced = model if kept is None else model.select(kept)
    # Only the one channel is drawn: reconstruct (eq. 35, summed in modal form) with that sensor's shape row
    # and that input's amplitudes, p·m times less work than every channel (what keeps the slider fast).
    channel = replace(reduced, shapes=reduced.shapes[output:output + 1], amplitudes=reduced.amplitudes[:, input_:input_ + 1])
    measured = data.markov[:, output:output + 1, input_:input_ + 1]
    rebuilt = channel.reconstruct(data.n_samples)[:, 0, 0]
    error = channel.fit_error(measured)[0, 0]
    sl = decimate(data.n_samples, settings.max_plot_points)
    return {
        "output": data.outputs[output], "input": data.inputs[input_],
        "kept": list(range(model.n_modes)) if kept is None else kept.tolist(),
        "time_s": floats(data.time_s[sl]), "measured": floats(measured[sl, 0, 0]),
        "reconstructed": floats(rebuilt[sl]), "fit_percent": fit_percent(error),
    }


def stabilization_json(stab, ident: era.Identification) -> dict:
    order = np.asarray(stab.order, dtype=int)
    # position of each pole among the modes of its order (realize(n) sorts modes the same way)
    first = {}
    mode_index = np.empty(order.size, dtype=int)
    for i, n in enumerate(order.tolist()):
        first.setdefault(n, i)
        mode_index[i] = i - first[n]
    return {
        "orders": np.asarray(stab.orders).tolist(), "order": order.tolist(), "mode_index": mode_index.tolist(),
        "frequency_hz": floats(stab.frequency_hz), "damping_ratio": floats(stab.damping_ratio),
        "emac": floats(stab.emac), "mpc": floats(stab.mpc), "contribution": floats(stab.contribution),
        "stable_frequency": np.asarray(stab.stable_frequency).tolist(),
        "stable_damping": np.asarray(stab.stable_damping).tolist(),
        "stable_shape": np.asarray(stab.stable_shape).tolist(), "stable": np.asarray(stab.stable).tolist(),
        "modes": [{"frequency_hz": mo.frequency_hz, "frequency_std_hz": mo.frequency_std_hz,
                   "damping_ratio": mo.damping_ratio, "damping_std": mo.damping_std, "emac": mo.emac,
                   "mpc": mo.mpc, "orders": list(mo.orders)} for mo in stab.modes],
        "nyquist_hz": 0.5 / ident.dt,
    }
