"""Tracking rules on hand-made records: crossing, vanishing, reappearing, new modes, one pairing per mode."""

from __future__ import annotations

import numpy as np
import pytest

import era
from era.campaign import RecordModes, run_campaign, time_from_name, track_modes
from era.campaign.simulated import ambient_record, monitoring_truth, record_csv
from era.examples.synthetic import modal_response

SHAPES = np.linalg.qr(np.random.default_rng(3).standard_normal((6, 5)))[0]  # five orthonormal shapes at 6 sensors


def record(index, freqs, which, *, p=6, noise=0.0):
    """RecordModes holding the modes ``which`` (columns of SHAPES) at frequencies ``freqs``."""
    rng = np.random.default_rng(index)
    shapes = SHAPES[:p, which].astype(complex) + noise * rng.standard_normal((p, len(which)))
    order = np.argsort(freqs)
    k = len(freqs)
    return RecordModes(index=index, name=f"record {index}", time=None, frequency_hz=np.asarray(freqs, float)[order],
                       frequency_std_hz=np.zeros(k), damping_ratio=np.full(k, 0.01), damping_std=np.zeros(k),
                       emac=np.ones(k), mpc=np.ones(k),
                       n_orders=np.full(k, 30), shapes=shapes[:, order], outputs=tuple(f"a{i}" for i in range(p)),
                       kind="ambient", rows=100, cols=100, n_samples=2048)


def frequencies(trk, mode):
    out = []
    for pos, rec in enumerate(trk.records):
        i = trk.assignment[pos, mode]
        out.append(rec.frequency_hz[i] if i >= 0 else np.nan)
    return np.array(out)


def test_two_crossing_modes_keep_their_identities_because_the_shape_decides():
    recs = [record(r, [4.0 - 0.02 * r, 3.9 + 0.02 * r], [0, 1], noise=0.05) for r in range(10)]  # cross at r = 2.5
    trk = track_modes(recs)
    rising, falling = (0, 1) if trk.modes[0].reference_frequency_hz < 3.95 else (1, 0)
    np.testing.assert_allclose(frequencies(trk, rising), 3.9 + 0.02 * np.arange(10))
    np.testing.assert_allclose(frequencies(trk, falling), 4.0 - 0.02 * np.arange(10))


@pytest.mark.parametrize("freq_scale", [0.01, 0.001])
def test_modes_that_swap_frequencies_between_records_keep_their_identities(freq_scale):
    """Each record's modes sit exactly where the other mode was in the record before: the frequency term favours
    the swap, the shapes (MAC 0.85-0.97 with their own, noise 0.1) do not. Even when a frequency error weighs ten
    times more (freq_scale 0.001, a swap then saves the largest frequency cost), no mode is lost or swapped."""
    rising, falling = [3.90, 3.95, 4.00, 4.05], [4.05, 4.00, 3.95, 3.90]
    recs = [record(r, [rising[r], falling[r]], [0, 1], noise=0.1) for r in range(4)]
    trk = track_modes(recs, freq_scale=freq_scale)
    assert len(trk.modes) == 2
    up, down = (0, 1) if trk.modes[0].reference_frequency_hz < 4.0 else (1, 0)
    np.testing.assert_array_equal(frequencies(trk, up), rising)
    np.testing.assert_array_equal(frequencies(trk, down), falling)
    assert np.nanmin(trk.mac_to_reference) >= 0.8


def test_a_mode_that_vanishes_is_missing_then_found_again():
    recs = [record(r, [2.0, 5.0] if r not in (3, 4, 5) else [2.0], [0, 1] if r not in (3, 4, 5) else [0])
            for r in range(9)]
    trk = track_modes(recs)
    f = frequencies(trk, 1)
    assert np.isnan(f[3:6]).all() and np.all(f[[0, 1, 2, 6, 7, 8]] == 5.0)
    assert trk.modes[1].n_found == 6 and len(trk.modes) == 2


def test_a_new_mode_that_persists_is_reported_and_a_one_off_is_not():
    recs = [record(0, [2.0], [0])] + [record(r, [2.0, 7.0], [0, 2]) for r in (1, 2, 3, 4)]
    recs += [record(5, [2.0, 3.3], [0, 3]), record(6, [2.0], [0])]  # 3.3 Hz once: noise
    trk = track_modes(recs)
    assert [m.origin for m in trk.modes] == ["reference", "new"]
    new = trk.modes[1]
    assert new.first_record == 1 and new.n_found == 4 and new.reference_frequency_hz == 7.0
    np.testing.assert_array_equal(frequencies(trk, 1)[1:5], 7.0)  # found from its first record on, not only from
    assert np.isnan(frequencies(trk, 1)[[0, 5, 6]]).all()         # the record that confirmed it


def test_no_record_mode_is_used_twice_and_a_far_mode_is_not_forced():
    recs = [record(0, [2.0, 5.0], [0, 1]), record(1, [2.01, 2.02], [0, 0]), record(2, [2.0, 5.6], [0, 1])]
    trk = track_modes(recs)
    assert trk.assignment[1, 0] >= 0 and trk.assignment[1, 1] == -1  # 2.02 Hz has mode 0's shape: not mode 1
    assert trk.assignment[2, 1] == -1  # 12 % away: beyond the 5 % gate, missing rather than wrong


def test_a_reference_model_and_records_with_other_sensors():
    data, truth = modal_response([1.5, 4.0], [0.01, 0.02], 6, 1, 400, 0.02, shapes=SHAPES[:, :2], seed=2)
    model = era.identify(data, 150, 150).model(4)
    recs = [record(0, [1.5, 4.0], [0, 1]), record(1, [1.5], [0], p=5), record(2, [4.02, 1.49], [1, 0])]
    trk = track_modes(recs, model)
    np.testing.assert_allclose([m.reference_frequency_hz for m in trk.modes], [1.5, 4.0], rtol=1e-3)
    assert [r.name for r in trk.refused] == ["record 1"] and "channels" in trk.refused[0].reason
    np.testing.assert_allclose(frequencies(trk, 1), [4.0, 4.02])
    with pytest.raises(era.DataError, match="no decaying modes"):
        track_modes(recs, (np.zeros(0), np.zeros(0), np.zeros((6, 0))))


@pytest.mark.parametrize("name, expected", [
    ("rec_2026-03-02T05-00.csv", "2026-03-02T05:00:00"), ("bridge_20260302_051530.uff", "2026-03-02T05:15:30"),
    ("2026-03-02 05:00:00.csv", "2026-03-02T05:00:00"), ("run7.csv", None)])
def test_times_are_read_from_file_names(name, expected):
    t = time_from_name(name)
    assert (t is None and expected is None) or t == np.datetime64(expected)


def test_a_bad_file_is_a_failure_with_its_reason_and_bad_arguments_are_refused(tmp_path):
    good = tmp_path / "a.csv"  # 5 min of the simulated monitored structure (a pure sine is no mode: not chosen)
    truth = monitoring_truth(1, duration_s=300.0)
    good.write_bytes(record_csv(ambient_record(truth.frequency_hz[0], truth.damping_ratio, truth.shapes, dt=truth.dt,
                                               duration_s=truth.duration_s), truth.dt))
    result = run_campaign([good, b"\x00\x01 not a record"], kind="ambient", workers=0, times=[0.0, 1.0])
    assert [f.name for f in result.failed] == ["record 1"] and "binary" in result.failed[0].reason
    assert list(result.table["time"].unique()) == [0.0]
    with pytest.raises(era.EraError, match="one per record"):
        run_campaign([good], times=[1, 2])
    with pytest.raises(era.EraError, match="orders"):
        run_campaign([good], orders=[0, 2])
    with pytest.raises(era.EraError, match="No records"):
        run_campaign([])


def test_the_command_line_says_what_failed(tmp_path):
    import subprocess
    import sys

    run = subprocess.run([sys.executable, "-m", "era", "campaign", str(tmp_path / "missing.csv"), "--out",
                          str(tmp_path / "t.csv"), "--workers", "0"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 1 and "failed: missing.csv" in run.stderr and "no such file" in run.stderr
    helped = subprocess.run([sys.executable, "-m", "era", "campaign", "--help"], capture_output=True, text=True)
    assert helped.returncode == 0 and "--scheduler" in helped.stdout and "--cache-dir" in helped.stdout


def test_an_interrupted_campaign_resumes_from_its_cache(tmp_path):
    """A progress callback that raises stands for Ctrl-C: what finished is kept, the rest is not waited for."""
    t = np.arange(3000) * 0.05
    rng = np.random.default_rng(1)
    paths = []
    for r in range(3):
        y = np.sin(2 * np.pi * (1.3 + 0.01 * r) * t)[:, None] * [1, -0.5] + 0.1 * rng.standard_normal((3000, 2))
        paths.append(tmp_path / f"r{r}.csv")
        paths[-1].write_text("time,a1,a2\n" + "\n".join(f"{a:.2f},{b:.5f},{c:.5f}" for a, (b, c) in zip(t, y)))

    def stop(done, total):
        if done == 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_campaign(paths, kind="ambient", workers=0, cache_dir=tmp_path / "cache", progress=stop)
    assert len(list((tmp_path / "cache").glob("*.json"))) == 1
    calls = []
    result = run_campaign(paths, kind="ambient", workers=0, cache_dir=tmp_path / "cache",
                          progress=lambda done, total: calls.append(done))
    assert calls == [1, 2, 3] and len(result.records) == 3


def test_a_twin_in_one_record_never_becomes_a_mode_nor_takes_the_modes_records():
    """Record 4 shows mode 1 twice (4.427 and 4.387 Hz, the same shape, as in a noisy record): mode 1 takes one,
    the other is a twin, not a candidate. Three such records in a row still make no new mode, and mode 1 keeps
    every record (identification rate 1)."""
    recs = [record(r, [2.0, 4.43], [0, 1], noise=0.02) for r in range(12)]
    for r in (4, 7, 8, 9):
        recs[r] = record(r, [2.0, 4.427, 4.387], [0, 1, 1], noise=0.02)
    trk = track_modes(recs)
    assert len(trk.modes) == 2
    assert np.all(trk.assignment >= 0)
    assert [m.identification_rate for m in trk.modes] == [1.0, 1.0]


def test_a_mode_appearing_mid_way_has_its_own_identity_and_rate_from_its_first_record():
    """A local mode (another shape) appears in record 5 and stays, missed once (record 9): it is new from record 5,
    found in 6 of the 7 records that hold it; the reference modes are found in all 12, crossing meanwhile."""
    recs = []
    for r in range(12):
        freqs, which = [2.0, 4.0 - 0.05 * r, 3.6 + 0.05 * r], [0, 1, 2]  # modes 1 and 2 cross at r = 4
        if r >= 5 and r != 9:
            freqs, which = freqs + [5.5], which + [3]
        recs.append(record(r, freqs, which, noise=0.05))
    trk = track_modes(recs)
    assert [m.origin for m in trk.modes] == ["reference"] * 3 + ["new"]
    new = trk.modes[3]
    assert new.first_record == 5 and (new.n_found, new.n_held) == (6, 7)
    assert new.identification_rate == pytest.approx(6 / 7)
    f = frequencies(trk, 3)
    assert np.all(f[[5, 6, 7, 8, 10, 11]] == 5.5) and np.isnan(f[[0, 1, 2, 3, 4, 9]]).all()
    falling, rising = (1, 2) if trk.modes[1].reference_frequency_hz > 3.8 else (2, 1)
    np.testing.assert_allclose(frequencies(trk, falling), 4.0 - 0.05 * np.arange(12))
    np.testing.assert_allclose(frequencies(trk, rising), 3.6 + 0.05 * np.arange(12))
    assert [m.identification_rate for m in trk.modes[:3]] == [1.0, 1.0, 1.0]


def test_a_weak_mode_missed_in_some_records_stays_one_mode_with_its_rate():
    """A weak mode whose shape is noisy (MAC ≈ 0.85-0.95) and that two records miss: one tracked mode, rate 10/12,
    never a second identity."""
    recs = [record(r, [2.0, 3.1] if r not in (3, 8) else [2.0], [0, 2] if r not in (3, 8) else [0], noise=0.12)
            for r in range(12)]
    trk = track_modes(recs)
    assert len(trk.modes) == 2 and trk.modes[1].n_found == 10 and trk.modes[1].n_held == 12
    assert trk.modes[1].identification_rate == pytest.approx(10 / 12)


def test_a_mode_the_choice_left_out_is_found_among_the_records_spares_and_a_spare_never_starts_a_mode():
    """Record 3's choice left mode 1 out (a crossing, a weak mode): its diagram still holds it as a spare cluster
    (RecordModes.spares), which the tracked mode takes by shape and frequency (rate 1, record_mode n_modes + 0);
    a spare of another shape in every record is never a new mode."""
    from dataclasses import replace

    other = SHAPES[:, 4].astype(complex)
    recs = []
    for r in range(8):
        rec = record(r, [2.0, 4.0] if r != 3 else [2.0], [0, 1] if r != 3 else [0], noise=0.02)
        spares = [(7.5, 0.01, 0.001, 0.001, 1.0, 1.0, 5, other)]
        if r == 3:
            spares.insert(0, (4.01, 0.012, 0.002, 0.002, 0.9, 0.9, 4, SHAPES[:, 1].astype(complex)))
        recs.append(replace(rec, spares=tuple(spares)))
    trk = track_modes(recs)
    assert len(trk.modes) == 2 and trk.assignment[3, 1] == 1  # n_modes (1) + spare 0
    assert trk.modes[1].identification_rate == 1.0 and trk.mac_to_reference[3, 1] > 0.99
    np.testing.assert_allclose(frequencies_with_spares(trk, 1)[2:5], [4.0, 4.01, 4.0])


def frequencies_with_spares(trk, mode):
    from era.campaign.record import mode_value

    return np.array([mode_value(rec, "frequency_hz", i) if (i := trk.assignment[pos, mode]) >= 0 else np.nan
                     for pos, rec in enumerate(trk.records)])


def poles_of(freqs, shapes, orders):
    """DiagramPoles holding each (frequency, shape) at every order of ``orders``, of no cluster."""
    from era.campaign.record import DiagramPoles

    f = np.repeat(np.asarray(freqs, float), len(orders))
    o = np.tile(np.asarray(orders), len(freqs))
    s = np.repeat(np.asarray(shapes, complex), len(orders), axis=1)
    return DiagramPoles(order=o, frequency_hz=f, damping_ratio=np.full(f.size, 0.01), emac=np.ones(f.size),
                        mpc=np.ones(f.size), cluster=np.full(f.size, -1), shapes=s)


def test_a_mode_the_records_clusters_miss_is_looked_up_in_its_diagram_with_the_tracked_frequency_and_shape():
    """Record 4's clusters hold no mode 1 (its choice left it out, no spare either) but its diagram's poles hold it at
    three orders: the campaign finds it there (found_by "diagram", σ NaN, the record's evidence says so). A pole at
    one order only, or of another shape, is not enough."""
    from dataclasses import replace

    recs = [record(r, [2.0, 4.0], [0, 1], noise=0.02) for r in range(8)]
    recs[4] = replace(record(4, [2.0], [0]), poles=poles_of([4.01, 4.05], SHAPES[:, [1, 3]], [20, 22, 24]))
    recs[6] = replace(record(6, [2.0], [0]), poles=poles_of([4.0], SHAPES[:, [1]], [30]))  # one order only
    trk = track_modes(recs)
    assert len(trk.modes) == 2 and trk.assignment[4, 1] == 1 and trk.found_by[4, 1] == "diagram"
    assert trk.assignment[6, 1] == -1 and trk.found_by[6, 1] == ""
    rec4 = trk.records[4]
    assert rec4.spares[0][0] == pytest.approx(4.01) and np.isnan(rec4.spares[0][2])
    assert rec4.rejected[-1][1] == "prior" and "found by the campaign" in rec4.rejected[-1][2]
    assert trk.modes[1].n_found == 7 and trk.modes[1].n_held == 8


def test_a_weak_mode_the_first_records_left_out_is_a_reference_mode_found_from_the_first_record():
    """Mode 1 is only a spare (a cluster the choice called noise) in records 0, 2 and 3: once records 1, 4 and 5
    confirm it, the campaign fills records 0-3 from their spares: one identity, a reference mode, rate 1."""
    from dataclasses import replace

    recs = []
    for r in range(10):
        if r in (0, 2, 3):
            rec = record(r, [2.0, 6.0], [0, 2], noise=0.02)
            rec = replace(rec, spares=((4.0 + 0.001 * r, 0.01, 0.001, 0.001, 1.0, 1.0, 20,
                                        SHAPES[:, 1].astype(complex)),))
        else:
            rec = record(r, [2.0, 4.0 + 0.001 * r, 6.0], [0, 1, 2], noise=0.02)
        recs.append(rec)
    trk = track_modes(recs)
    assert [m.origin for m in trk.modes] == ["reference"] * 3
    weak = next(m for m in trk.modes if abs(m.reference_frequency_hz - 4.0) < 0.01)
    assert (weak.first_record, weak.n_found, weak.n_held) == (0, 10, 10)
    assert list(trk.found_by[[0, 2, 3], weak.mode]) == ["cluster"] * 3


def test_a_local_mode_appearing_mid_way_starts_at_its_first_record_even_with_look_alikes_before():
    """A local mode appears in record 6 (seen as a spare there, chosen from record 7 on); before it, the records'
    diagrams hold only other shapes near its frequency: its identity starts at record 6, no earlier."""
    from dataclasses import replace

    recs = []
    for r in range(12):
        rec = record(r, [2.0, 4.0] + ([5.5] if r >= 7 else []), [0, 1] + ([3] if r >= 7 else []), noise=0.02)
        if r == 6:
            rec = replace(rec, spares=((5.49, 0.01, 0.001, 0.001, 1.0, 1.0, 12, SHAPES[:, 3].astype(complex)),))
        else:
            rec = replace(rec, poles=poles_of([5.5], SHAPES[:, [4]], [10, 12, 14]))
        recs.append(rec)
    trk = track_modes(recs)
    assert [m.origin for m in trk.modes] == ["reference", "reference", "new"]
    assert (trk.modes[2].first_record, trk.modes[2].n_found, trk.modes[2].n_held) == (6, 6, 6)
    assert trk.found_by[6, 2] == "cluster"
