"""Campaigns: the issue's full case and the throughput against the number of workers.

Run: python3 -m pytest tests/bench/bench_campaign.py -s

The full case: 48 hourly ambient records of 30 min (20 Hz, six sensors, five modes; era.campaign.simulated) over two
days, every frequency following the temperature curve (±2 %, mode 4 ±1 % the other way, so modes 3 and 4 cross
four times), mode 2 3 % lower from record 30, plus a record cut off half-way (49 files). Reported: each mode's
rms and largest error against the truth, the share of cells within 0.3 %, the step of every mode with the
temperature effect removed, the failures.

Throughput: 16 of those records on 1, 2 and 4 local workers, as local processes (the default, client=None) and on a
distributed.LocalCluster (one thread per worker, created before the clock starts, as a standing cluster would
be), in records per serial record time: 1.0 is one record after the other in one process, and n workers can at
most reach n (minus the spread of the last tasks). BLAS is pinned to one thread (tests/bench/conftest.py).

Measured on the shared 2-core machine (load average ~3 from other jobs), 0.82 s per record serial:
1 worker 1.09 (processes) / 0.93 (LocalCluster), 2 workers 1.64 / 1.63, 4 workers 1.04 / 0.96 (four processes
on two cores only compete). What a larger cluster should give: records are independent, a task's answer is a few
kB and its input one file (2.2 MB here), so the rate grows with the cores until the files' storage or the
scheduler (~1 ms per task) limits it: about 14-15 on 16 cores, and on several machines about the total cores,
as long as the shared file system delivers ~2.5 MB per record per core-second.
"""

from __future__ import annotations

import os
import time

import numpy as np
import pytest

from era.campaign import run_campaign
from era.campaign.simulated import SENSITIVITY, monitoring_truth, write_campaign
from era.core.indicators import mac

N_RECORDS, DAMAGE_FROM, DURATION_S = 48, 30, 1800.0


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    truth = monitoring_truth(N_RECORDS, damage_from=DAMAGE_FROM, duration_s=DURATION_S)
    folder = tmp_path_factory.mktemp("campaign48")
    paths = write_campaign(folder, truth, seed=2)
    whole = open(paths[5], "rb").read()
    corrupt = folder / "rec_2026-03-02T05-30.csv"
    corrupt.write_bytes(whole[: len(whole) // 2])
    return truth, paths, corrupt


def test_the_full_48_record_campaign(campaign):
    truth, paths, corrupt = campaign
    t0 = time.perf_counter()
    result = run_campaign(paths + [corrupt], kind="ambient", workers=2)
    wall = time.perf_counter() - t0
    assert [f.name for f in result.failed] == [corrupt.name]
    t = result.table
    shapes = np.stack([m.shape for m in result.modes], axis=1)
    best = np.argmax(mac(truth.shapes.astype(complex), shapes), axis=1)
    assert len(set(best)) == 5
    temp = 1 + np.array(SENSITIVITY)[None, :] * truth.temperature[:, None]
    print(f"\n48 records + 1 corrupt on 2 local processes: {wall:.1f} s; tracked modes "
          f"{[(m.mode, round(m.reference_frequency_hz, 3), m.origin, m.n_found) for m in result.modes]}")
    cells = []
    for j, mode in enumerate(best):
        f = t[t["mode"] == mode].sort_values("time")["frequency_hz"].to_numpy()
        err = 100 * (f / truth.frequency_hz[:, j] - 1)
        found = ~np.isnan(err)
        normalised = f / temp[:, j]
        step = 100 * (np.nanmean(normalised[DAMAGE_FROM:]) / np.nanmean(normalised[:DAMAGE_FROM]) - 1)
        rms, worst = np.sqrt(np.mean(err[found] ** 2)), np.abs(err[found]).max()
        print(f"  mode {j + 1} ({truth.frequency_hz[0, j]:.2f} Hz) -> tracked {mode}: found {found.sum()}/48, "
              f"rms {rms:.3f} %, max {worst:.3f} %, step {step:+.2f} %")
        assert rms <= 0.2 and worst <= 1.0
        assert (-3.3 <= step <= -2.7) if j == truth.damaged_mode else abs(step) <= 0.3
        cells.extend(np.abs(err[found]))
    cells = np.array(cells)
    print(f"  cells within 0.3 %: {100 * np.mean(cells <= 0.3):.1f} % of {cells.size}; largest {cells.max():.3f} %")
    assert np.mean(cells <= 0.3) >= 0.9


def _records_per_serial_time(run, n, serial_s) -> float:
    t0 = time.perf_counter()
    result = run()
    wall = time.perf_counter() - t0
    assert len(result.records) == n and not result.failed
    return n * serial_s / wall


def test_throughput_against_workers(campaign):
    import distributed
    _, paths, _ = campaign
    paths = paths[:16]
    t0 = time.perf_counter()
    run_campaign(paths[:4], kind="ambient", workers=0)
    serial = (time.perf_counter() - t0) / 4
    print(f"\none record, serial, in this process: {serial:.2f} s (cores here: {os.cpu_count()})")
    print("  workers | local processes | LocalCluster   (records per serial record time, 16 records)")
    rates = {}
    for n in (1, 2, 4):
        local = _records_per_serial_time(lambda: run_campaign(paths, kind="ambient", workers=n), 16, serial)
        with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                                      silence_logs=40) as cluster, distributed.Client(cluster) as client:
            client.wait_for_workers(n)
            dask = _records_per_serial_time(lambda: run_campaign(paths, kind="ambient", client=client), 16, serial)
        rates[n] = (local, dask)
        print(f"  {n:7d} | {local:15.2f} | {dask:12.2f}")
    assert rates[2][0] > 1.2 * rates[1][0] and rates[2][1] > 1.2 * rates[1][1]  # two cores do help
