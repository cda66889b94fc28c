"""A monitored structure over two days: the campaign table follows the simulated truth.

What 30-min records allow: the Fourier resolution 1/T = 0.56 mHz (0.04 % at 1.25 Hz) is not the limit; the random
error of a mode identified from ambient response is, about σ_f/f ≈ sqrt(ζ / (2π f T)) (0.05-0.08 % here, NExT-ERA
lands within about twice that). So the table is asked to be within 0.3 % in at least 90 % of the cells, never more
than 1 % off (a wrong pairing would be 1.5-60 % off), and within 0.2 % rms per mode. Where the crossing modes 3
and 4 are closer than their half-power bandwidth (2ζ ≈ 2 %), the record cannot always separate them: a cell may
be missing there, but it is never given to the wrong mode.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from era.core.indicators import mac

# the layout of the simulated campaign (tests/campaign/conftest.py)
N_RECORDS, DAMAGE_FROM, CORRUPT = 16, 10, "rec_2026-03-03T10-30.csv"


def truth_columns(result, truth) -> dict:
    """truth mode j → the tracked mode whose reference shape is closest to it."""
    shapes = np.stack([m.shape for m in result.modes], axis=1)
    m = mac(truth.shapes.astype(complex), shapes)
    return {j: int(np.argmax(m[j])) for j in range(truth.shapes.shape[1])}


def tracked(result, mode) -> np.ndarray:
    """(records,) the mode's frequency in each analysed record, in time order (NaN where missing)."""
    t = result.table
    return t[t["mode"] == mode].sort_values("time")["frequency_hz"].to_numpy()


def test_every_record_but_the_corrupt_one_is_analysed(on_processes, campaign_dir):
    result, calls = on_processes
    assert [f.name for f in result.failed] == [CORRUPT]
    assert "line" in result.failed[0].reason  # the loader's message names where the file breaks
    assert result.table["record"].nunique() == N_RECORDS
    assert len(result.table) == N_RECORDS * len(result.modes)
    assert calls[-1] == (N_RECORDS + 1, N_RECORDS + 1) and len(calls) == N_RECORDS + 1
    assert result.table["time"].is_monotonic_increasing  # times from the file names


def test_the_table_follows_the_truth_within_0_3_percent(on_processes, truth):
    result, _ = on_processes
    cols = truth_columns(result, truth)
    assert len(set(cols.values())) == 5  # five distinct tracked modes for the five true ones
    errors = []
    for j, mode in cols.items():
        err = 100 * (tracked(result, mode) / truth.frequency_hz[:, j] - 1)  # the truth is in time order too
        found = ~np.isnan(err)
        assert found.sum() >= (N_RECORDS - 4 if j in (2, 3) else N_RECORDS - 1), (j, err)
        assert np.sqrt(np.mean(err[found] ** 2)) <= 0.2, (j, err)
        errors.extend(err[found])
    errors = np.abs(errors)
    assert errors.max() <= 1.0
    assert np.mean(errors <= 0.3) >= 0.9, np.sort(errors)[-8:]


def test_the_damage_step_shows_in_mode_2_only(on_processes, truth):
    result, _ = on_processes
    cols = truth_columns(result, truth)
    temp = 1 + np.array([-0.02, -0.02, -0.02, 0.01, -0.02])[None, :] * truth.temperature[:, None]
    for j, mode in cols.items():
        f = tracked(result, mode)
        normalised = f / temp[:, j]  # the temperature effect removed, as a monitoring engineer would
        before, after = np.nanmean(normalised[:DAMAGE_FROM]), np.nanmean(normalised[DAMAGE_FROM:])
        change = 100 * (after / before - 1)
        if j == truth.damaged_mode:
            assert -3.3 <= change <= -2.7, change
        else:
            assert abs(change) <= 0.3, (j, change)


def test_two_crossing_modes_keep_their_identities(on_processes, truth):
    result, _ = on_processes
    cols = truth_columns(result, truth)
    f3, f4 = tracked(result, cols[2]), tracked(result, cols[3])
    t3, t4 = truth.frequency_hz[:, 2], truth.frequency_hz[:, 3]
    assert (t3 > t4).any() and (t3 < t4).any()  # they do cross
    apart = np.abs(t3 - t4) > 0.005 * t3  # where the truth tells them apart
    for mine, own, other in ((f3, t3, t4), (f4, t4, t3)):
        ok = apart & ~np.isnan(mine)
        assert ok.sum() >= 10
        assert np.all(np.abs(mine[ok] - own[ok]) < np.abs(mine[ok] - other[ok]))
    t = result.table
    crossing = t[t["mode"].isin([cols[2], cols[3]]) & t["found"]]
    # a record mode of mixed shape at the crossing is taken by the tracked mode it resembles most (MAC ≥ 0.5,
    # found_by "crossing"); every other cell passed the 0.8 gate
    assert crossing[crossing["found_by"] != "crossing"]["mac_to_reference"].min() >= 0.8
    assert crossing["mac_to_reference"].min() >= 0.5


def test_local_cluster_and_local_processes_give_the_same_table(on_processes, on_cluster):
    """Both runs lost a worker mid-campaign; neither lost a record."""
    result, _ = on_processes
    cluster, calls = on_cluster
    pd.testing.assert_frame_equal(result.table, cluster.table)
    assert [f.name for f in cluster.failed] == [CORRUPT]
    assert calls[-1] == (N_RECORDS + 1, N_RECORDS + 1) and len(calls) == N_RECORDS + 1


def test_a_second_run_resumes_from_the_cache(on_processes, campaign_dir):
    from era.campaign import run_campaign

    result, _ = on_processes
    calls = []
    again = run_campaign(campaign_dir / "records", kind="ambient", workers=0, cache_dir=campaign_dir / "cache",
                         progress=lambda done, total: calls.append((done, total)))
    # 16 answers come from the cache at once; only the corrupt file (failures are not stored) is read again
    assert calls == [(N_RECORDS, N_RECORDS + 1), (N_RECORDS + 1, N_RECORDS + 1)]
    pd.testing.assert_frame_equal(result.table, again.table)
    assert len(list((campaign_dir / "cache").glob("*.json"))) == N_RECORDS
    assert not list((campaign_dir / "cache").glob("*.part"))


def test_the_command_line_writes_the_table(on_processes, campaign_dir, tmp_path):
    import subprocess
    import sys

    result, _ = on_processes
    out = tmp_path / "table.csv"
    run = subprocess.run([sys.executable, "-m", "era", "campaign", str(campaign_dir / "records"), "--out", str(out),
                          "--kind", "ambient", "--workers", "0", "--cache-dir", str(campaign_dir / "cache"),
                          "--quiet"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert f"failed: {CORRUPT}" in run.stderr
    table = pd.read_csv(out)
    assert list(table.columns) == list(result.table.columns)
    np.testing.assert_allclose(table["frequency_hz"], result.table["frequency_hz"], rtol=1e-12)


def test_damping_is_unbiased_within_its_known_scatter(on_processes, truth):
    """Ambient damping estimates scatter ten times more than frequencies (here 9-18 % rms per mode); their median
    stays within 10 % of the truth."""
    result, _ = on_processes
    t = result.table
    for j, mode in truth_columns(result, truth).items():
        zeta = t[t["mode"] == mode].sort_values("time")["damping_ratio"].to_numpy()
        err = zeta / truth.damping_ratio[j] - 1
        assert abs(np.nanmedian(err)) <= 0.10 and np.sqrt(np.nanmean(err ** 2)) <= 0.25, (j, err)
