"""A simulated monitored structure, written once per session as CSV files, and its campaign run two ways.

16 ambient records of 30 min (20 Hz, six sensors, five modes), one every 3 h over two days: the temperature
curve swings every frequency by ±2 % (mode 4 the other way, ±1 %, so modes 3 and 4 cross twice a day), and mode 2
drops 3 % from record 10 (hour 30). The issue's 48 hourly records are in tests/bench/bench_campaign.py; 16 keep
these tests within a minute on two shared cores while covering two temperature cycles, four crossings and six
damaged records. A 17th file, cut off in the middle of a line, is the corrupt record.
"""

from __future__ import annotations

import multiprocessing
import os
import signal

import pytest

from era.campaign import run_campaign
from era.campaign.simulated import monitoring_truth, write_campaign

N_RECORDS, HOURS_BETWEEN, DAMAGE_FROM, DURATION_S = 16, 3.0, 10, 1800.0
CORRUPT = "rec_2026-03-03T10-30.csv"


@pytest.fixture(scope="session")
def truth():
    return monitoring_truth(N_RECORDS, hours_between=HOURS_BETWEEN, damage_from=DAMAGE_FROM, duration_s=DURATION_S)


@pytest.fixture(scope="session")
def campaign_dir(tmp_path_factory, truth):
    folder = tmp_path_factory.mktemp("campaign")
    paths = write_campaign(folder / "records", truth, seed=1)
    with open(paths[3], "rb") as fh:
        whole = fh.read()
    with open(folder / "records" / CORRUPT, "wb") as fh:  # a transfer that stopped half-way through a line
        fh.write(whole[: len(whole) // 2])
    return folder


def kill_once(kill):
    """A progress callback that records its calls and, at the second record done, kills a worker once."""
    calls = []

    def progress(done, total):
        calls.append((done, total))
        if len(calls) == 2:
            kill()
    return progress, calls


@pytest.fixture(scope="session")
def on_processes(campaign_dir):
    """The campaign on two local processes, every record cached in campaign_dir/cache; one worker process is
    killed mid-campaign (SIGKILL, as the out-of-memory killer would): its records are run again."""
    def kill():
        busy = [p for p in multiprocessing.active_children() if p.is_alive()]
        os.kill(busy[0].pid, signal.SIGKILL)

    progress, calls = kill_once(kill)
    result = run_campaign(campaign_dir / "records", kind="ambient", workers=2, cache_dir=campaign_dir / "cache",
                          progress=progress)
    return result, calls


@pytest.fixture(scope="session")
def on_cluster(campaign_dir):
    """The same campaign on a distributed.LocalCluster of two single-threaded worker processes, one of which is
    lost mid-campaign (its process is killed; the nanny starts a new one and the scheduler runs its tasks again)."""
    import distributed
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=40) as cluster, distributed.Client(cluster) as client:
        def kill():
            busy = [w for w, keys in client.processing().items() if keys]
            pid = client.run(os.getpid, workers=busy[:1])[busy[0]]
            os.kill(pid, signal.SIGKILL)

        progress, calls = kill_once(kill)
        paths = sorted(os.path.join(campaign_dir / "records", n) for n in os.listdir(campaign_dir / "records"))
        return run_campaign(paths, kind="ambient", client=client, progress=progress), calls
