"""What the readers write for a person (the import step's sentence, the dataset's source, the report): counts in
words that agree with them ("1 channel", "2 channels", never "channel(s)"), lists as a sentence lists them (never a
Python list), and a preview of a file without a sampling interval says so instead of the stand-in step it is
drawn with."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

import era
from era.io.preview import preview
from era.markov import markov_from_decay

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402


def test_the_usc_cantilever_is_described_once_in_words():
    lvm = require_shared(SHARED_DATASETS / "usc_cantilever_free_decay" / "timeseries_data.lvm")
    pv = preview(lvm)
    assert pv.described == ["timeseries_data.lvm: LabVIEW LVM, 1 record of 81920 samples × 1 channel, "
                            "Δt = 0.000605469 s (1651.61 Hz, from the X_Value column)"]
    ds = era.load(lvm)
    conversion = ds.source["conversions"][-1]
    assert re.fullmatch(r"free decay from sample \d+ \(t = [0-9.]+ s\), \d+ samples", conversion), conversion


def test_a_decay_of_two_inputs_names_both_start_samples_in_words():
    t = np.arange(400) * 0.01
    y = np.stack([np.exp(-0.5 * t) * np.cos(2 * np.pi * 3 * t)] * 2, axis=1)[:, None, :]  # (N, 1, 2)
    data = markov_from_decay(y, 0.01, start=[10, 12])
    assert data.meta["conversions"] == ["free decay from samples 10 and 12 (t = 0.1, 0.12 s), 388 samples"]
    try:
        markov_from_decay(y, 0.01, start=[10, 999])
    except era.DataError as exc:
        assert str(exc) == "Start sample 999 lies outside the record of 400 samples."
    else:
        raise AssertionError("a start outside the record was accepted")


def test_a_file_without_a_sampling_interval_is_not_described_with_the_stand_in_step(tmp_path):
    rows = np.random.default_rng(0).standard_normal((3, 600))
    path = tmp_path / "bare.txt"
    path.write_text("\n".join(" ".join(f"{v:.6f}" for v in r) for r in rows))
    pv = preview(path)
    assert pv.step is None and pv.problem_option == "dt"
    assert pv.described == ["bare.txt: headerless text, 3 channels in rows (from the shape) × 600 samples, no "
                            "sampling interval in the file, blank-separated"], pv.described
