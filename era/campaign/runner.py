"""run_campaign: every record analysed as a task (on a Dask cluster or on local processes), then the modes tracked.

Where the tasks run:

- ``client`` given (a ``dask.distributed.Client``): one task per record with ``client.map``, answers collected
  with ``as_completed``. A worker lost mid-campaign costs only a re-run of its records: the scheduler runs them
  again elsewhere (up to its ``distributed.scheduler.allowed-failures`` lost workers per task, then the record is
  in ``failed``), and ``retries=`` re-runs a task that raised on the worker outside the record's own analysis
  (e.g. a source that could not be unpickled there). Paths must be readable by the workers (a shared file
  system); bytes travel with the task.
- ``client=None``: a ``concurrent.futures.ProcessPoolExecutor`` (spawned processes, ``workers`` of them, default
  one per core). Chosen over a ``distributed.LocalCluster`` for the default because it starts in a fraction of
  a second, opens no ports and no dashboard, and needs only the standard library; the task is the same, so
  ``Client(LocalCluster(...))`` gives the same table when a dashboard is wanted. A worker process that dies
  (killed, out of memory) breaks the pool: the pool is rebuilt and the records it held are run again, up to
  ``retries`` times. As with any spawned process, a script that calls run_campaign needs the
  ``if __name__ == "__main__":`` guard.
- ``workers=0``: in this process, one record after the other (debugging, timing).

Every task catches its own errors (:func:`era.campaign.record.analyse_record`), so a bad file is a line in
``failed`` and never stops the campaign.
"""

from __future__ import annotations

import inspect
import multiprocessing
import os
import uuid
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import replace

import numpy as np

from ..errors import EraError
from . import cache
from .record import CampaignSettings, RecordFailure, RecordModes, analyse_record, record_name
from .result import CampaignResult, build_table, require_pandas
from .tracking import track_modes


def _sources(sources) -> list:
    """A flat list of records: a folder stands for its files (sorted by name), a single path or bytes for itself."""
    if isinstance(sources, (str, os.PathLike, bytes, bytearray)):
        sources = [sources]
    out = []
    for s in sources:
        if isinstance(s, (str, os.PathLike)) and os.path.isdir(s):
            names = sorted(n for n in os.listdir(s) if not n.startswith(".") and os.path.isfile(os.path.join(s, n)))
            out.extend(os.path.join(os.fspath(s), n) for n in names)
        else:
            out.append(s)
    if not out:
        raise EraError("No records given: pass a list of file paths (or bytes), or a folder holding the records.")
    return out


def _as_time(value):
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        return float(value)
    try:
        return np.datetime64(value, "s")
    except (TypeError, ValueError):
        raise EraError(f"A record time must be a date-time (datetime, numpy.datetime64, ISO text) or a number, got "
                       f"{value!r}.") from None


def _settings(kind, dt, rows, cols, orders, load_options) -> CampaignSettings:
    try:
        orders = tuple(sorted({int(n) for n in orders}))
    except (TypeError, ValueError):
        raise EraError(f"`orders` must be model orders (positive integers), e.g. range(2, 81, 2), got {orders!r}.") \
            from None
    if not orders or orders[0] < 1:
        raise EraError("`orders` must hold positive integers (model orders), e.g. range(2, 81, 2).")
    for name, v in (("rows", rows), ("cols", cols)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1):
            raise EraError(f"`{name}` must be a positive integer or None (the suggested Hankel size), got {v!r}.")
    return CampaignSettings(kind=str(kind), dt=None if dt is None else float(dt),
                            rows=None if rows is None else int(rows), cols=None if cols is None else int(cols),
                            orders=orders, load_options=tuple(sorted((load_options or {}).items())))


def run_campaign(sources, *, kind: str = "auto", dt: float | None = None, rows: int | None = None,
                 cols: int | None = None, orders=range(2, 81, 2), reference=None, client=None, progress=None,
                 times=None, cache_dir=None, workers: int | None = None, retries: int = 2,
                 load_options: dict | None = None, tracking: dict | None = None) -> CampaignResult:
    """Identify every record the same way and follow each mode through the records.

    Each record's modes are those era.analyse chooses (era.choose_modes, the app's rule) from its stabilization
    diagram over ``orders``, read at one order with their standard deviations from the data.

    Parameters
    ----------
    sources : paths or bytes of records era.load reads (one record each), or a folder of them (its files by name).
    kind, dt : era.load's conversion ("auto", "ambient" for NExT, "decay", "pulse", "frf", "io") and the sampling
        interval in s for CSV files without a time column.
    rows, cols : Hankel block rows and columns; None: era.core.suggest.hankel_size of each record.
    orders : model orders of each record's stabilization diagram (default 2, 4, … 80).
    reference : None (the modes of the first record that has any) or an era.ModalModel whose decaying modes are
        tracked (its outputs must be the records' sensors, in order).
    client : a dask.distributed.Client to run the records on, a scheduler's address ("tcp://host:8786", connected
        for this campaign only), or None for local processes (see the module).
    progress : callable(done, total) called in this process as records finish (cached ones count as done).
    times : one time per source (datetimes, ISO text or numbers), overriding the times read from file names;
        without either, a record's time is its position in ``sources``.
    cache_dir : folder where each analysed record's modes are stored (atomically) and found again by a later run
        with the same settings: an interrupted campaign resumes where it stopped.
    workers : local processes when client is None (default: one per core; 0: in this process).
    retries : times a record is run again when its task fails outside the analysis (Dask's ``retries=``) or its
        local worker process dies (a broken pool); Dask re-runs the tasks of a lost worker by itself.
    load_options : more keywords for era.load, e.g. {"references": [0, 1]} for NExT.
    tracking : keywords of era.campaign.track_modes (min_mac, max_freq_error, freq_scale, new_mode_records, …).

    Returns
    -------
    CampaignResult (its ``table`` is a pandas.DataFrame)

    Raises era.EraError for bad arguments (never for a bad record: those are in ``result.failed``).
    """
    srcs = _sources(sources)
    require_pandas()  # before any work: the table needs it
    try:
        inspect.signature(track_modes).bind_partial(None, **(tracking or {}))
    except TypeError:
        raise EraError(f"`tracking` takes keywords of era.campaign.track_modes (freq_scale, min_mac, max_freq_error, "
                       f"new_mode_records, new_mode_gap), got {sorted(tracking)}.") from None
    settings = _settings(kind, dt, rows, cols, orders, load_options)
    if times is not None:
        times = list(times)
        if len(times) != len(srcs):
            raise EraError(f"`times` holds {len(times)} values for {len(srcs)} records; give one per record.")
        times = [_as_time(t) for t in times]
    if client is None and workers is not None and (isinstance(workers, bool) or int(workers) < 0):
        raise EraError(f"`workers` must be 0 (this process) or a positive number of processes, got {workers!r}.")
    names = [record_name(s, i) for i, s in enumerate(srcs)]
    total = len(srcs)
    results: dict[int, object] = {}
    keys = [cache.record_key(s, settings.fingerprint()) for s in srcs] if cache_dir is not None else None
    if keys is not None:
        for i in range(total):
            hit = cache.load_entry(cache_dir, keys[i], i, names[i])
            if hit is not None:
                results[i] = hit
    todo = [i for i in range(total) if i not in results]
    if progress is not None and results:
        progress(len(results), total)
    own_client = run = None
    if todo and isinstance(client, str):  # a scheduler's address: connect for this campaign only
        own_client = client = _connect(client)
    try:
        if todo:
            run = _on_client(client, srcs, names, todo, settings, retries) if client is not None else \
                _on_processes(srcs, names, todo, settings, workers, retries)
            for res in run:
                results[res.index] = res
                if keys is not None and isinstance(res, RecordModes):
                    cache.store_entry(cache_dir, keys[res.index], res)
                if progress is not None:
                    progress(len(results), total)
    finally:
        if run is not None:
            run.close()  # now, not when the traceback is freed: cancels what has not started
        if own_client is not None:
            own_client.close()
    return _result(results, total, times, reference, settings, tracking or {})


def _result(results, total, times, reference, settings, tracking) -> CampaignResult:
    done = [results[i] for i in range(total)]
    if times is not None:
        done = [replace(r, time=times[r.index]) if isinstance(r, RecordModes) else r for r in done]
    good = [r for r in done if isinstance(r, RecordModes)]
    failed = [r for r in done if isinstance(r, RecordFailure)]
    if all(isinstance(r.time, np.datetime64) for r in good) or all(isinstance(r.time, float) for r in good):
        good.sort(key=lambda r: (r.time, r.index))  # time order; otherwise the order of the sources
    trk = track_modes(good, reference, **tracking)
    failed = sorted(failed + list(trk.refused), key=lambda f: f.index)
    return CampaignResult(table=build_table(trk), modes=trk.modes, failed=tuple(failed), records=trk.records,
                          settings=settings)


def _connect(address: str):
    try:
        from distributed import Client
    except ImportError:
        raise EraError("A Dask scheduler needs the distributed package: python3 -m pip install "
                       "'era-modal[campaign]'.") from None
    try:
        return Client(address, timeout=30)
    except (OSError, TimeoutError) as exc:
        raise EraError(f"No Dask scheduler answers at {address!r} ({exc}); start one (dask scheduler) or give "
                       "client=None to run on local processes.") from None


def _on_client(client, srcs, names, todo, settings, retries):
    """Yield each record's answer as it arrives from the Dask cluster."""
    try:
        from distributed import as_completed as dask_completed
    except ImportError:
        raise EraError("A Dask client needs the distributed package: python3 -m pip install 'era-modal[campaign]'.") \
            from None

    run = uuid.uuid4().hex[:12]
    keys = [f"era-campaign-{run}-record-{i}" for i in todo]
    futures = client.map(analyse_record, [srcs[i] for i in todo], todo, settings=settings, key=keys, pure=False,
                         retries=retries)
    index_of = {k: i for k, i in zip(keys, todo)}
    try:
        for fut in dask_completed(futures):
            i = index_of[fut.key]
            try:
                res = fut.result()
            except Exception as exc:  # the task itself never raises: the worker or the cluster failed
                res = RecordFailure(i, names[i], f"lost on the cluster ({type(exc).__name__}: {exc}); run the "
                                                 "campaign again with cache_dir= to resume.")
            fut.release()
            yield res
    finally:  # interrupted (Ctrl-C, a progress callback that raised): leave nothing running on the cluster
        client.cancel([f for f in futures if not f.done()])


def _on_processes(srcs, names, todo, settings, workers, retries):
    """Yield each record's answer as it finishes on local processes (or in this process for workers=0)."""
    if workers == 0:
        for i in todo:
            yield analyse_record(srcs[i], i, settings)
        return
    n = int(workers) if workers else (len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
                                      else os.cpu_count() or 1)
    attempts = dict.fromkeys(todo, 0)
    pending = list(todo)
    while pending:
        lost = []
        pool = ProcessPoolExecutor(max_workers=max(1, min(n, len(pending))),
                                   mp_context=multiprocessing.get_context("spawn"))
        try:
            futures = {pool.submit(analyse_record, srcs[i], i, settings): i for i in pending}
            for fut in as_completed(futures):
                i = futures[fut]
                try:
                    yield fut.result()
                except BrokenProcessPool:
                    lost.append(i)
                except Exception as exc:  # e.g. the source could not be sent to the process
                    yield RecordFailure(i, names[i], f"could not run ({type(exc).__name__}: {exc}).")
        finally:  # interrupted: drop the records not started instead of running them all first
            pool.shutdown(wait=True, cancel_futures=True)
        pending = []
        for i in sorted(lost):
            attempts[i] += 1
            if attempts[i] > retries:
                yield RecordFailure(i, names[i], f"its worker process died {attempts[i]} times (out of memory, or "
                                                 "killed); give it fewer rows/cols or more memory per worker.")
            else:
                pending.append(i)
