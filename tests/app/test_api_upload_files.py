"""Real test data in through the API: several files as one dataset, and the options a file cannot say itself
(the sample rate, channels in rows), with errors that name the file and the fix and leave nothing stored."""

from __future__ import annotations


import numpy as np
import pytest

from apiclient import client
from shared_data import SHARED_DATASETS, require_shared

CARINI = SHARED_DATASETS / "carini_ambient_3ch" / "yk.txt"


def _decay_csv(seed: int) -> bytes:
    """A 2-channel free decay at 100 Hz (modes 3 and 7.5 Hz) with a time column."""
    t = np.arange(600) / 100.0
    rng = np.random.default_rng(seed)
    a, b = rng.uniform(0.5, 1.5, 2)
    y1 = a * np.exp(-0.2 * t) * np.cos(2 * np.pi * 3.0 * t) + b * np.exp(-0.4 * t) * np.cos(2 * np.pi * 7.5 * t)
    y2 = b * np.exp(-0.2 * t) * np.cos(2 * np.pi * 3.0 * t) - a * np.exp(-0.4 * t) * np.cos(2 * np.pi * 7.5 * t)
    lines = ["time [s],a1 [m/s^2],a2 [m/s^2]"] + [f"{ti:.2f},{u:.9e},{v:.9e}" for ti, u, v in zip(t, y1, y2)]
    return ("\n".join(lines) + "\n").encode()


def test_several_csv_files_are_one_dataset_of_several_records(tmp_path):
    with client(tmp_path) as c:
        parts = [("file", (f"hit{k}.csv", _decay_csv(k), "text/csv")) for k in range(3)]
        r = c.post("/api/datasets", files=parts, data={"kind": "decay"})
        assert r.status_code == 200, r.text
        ds = r.json()
        assert ds["n_inputs"] == 3 and ds["n_outputs"] == 2 and ds["dt"] == pytest.approx(0.01)
        assert ds["source"]["file"] == ["hit0.csv", "hit1.csv", "hit2.csv"] and ds["name"] == "hit0.csv + 2 more"


def test_headerless_rows_need_the_sample_rate_and_nothing_is_stored_until_given(tmp_path):
    blob = require_shared(CARINI).read_bytes()
    with client(tmp_path) as c:
        refused = c.post("/api/datasets", files={"file": ("yk.txt", blob)}, data={"kind": "ambient"})
        assert refused.status_code == 422
        assert "no sampling interval in yk.txt" in refused.json()["error"] and "dt" in refused.json()["error"]
        assert c.get("/api/health").json()["usage"]["rows"]["datasets"] == 0
        ok = c.post("/api/datasets", files={"file": ("yk.txt", blob)},
                    data={"kind": "ambient", "dt": str(1 / 25), "orientation": "rows"})
        assert ok.status_code == 200, ok.text
        ds = ok.json()
        assert ds["n_outputs"] == 3 and ds["dt"] == pytest.approx(0.04)
        assert ds["source"]["options"] == {"dt": pytest.approx(0.04), "orientation": "rows", "kind": "ambient"}
        assert c.get(f"/api/datasets/{ds['id']}").json()["source"]["options"]["orientation"] == "rows"


def test_bad_options_are_refused_clearly(tmp_path):
    with client(tmp_path) as c:
        r = c.post("/api/datasets", files={"file": ("a.csv", _decay_csv(0))}, data={"dt": "-1"})
        assert r.status_code == 422 and "dt" in r.json()["error"]
        r = c.post("/api/datasets", files={"file": ("a.csv", _decay_csv(0))}, data={"kind": "modal"})
        assert r.status_code == 422 and "`kind` must be one of" in r.json()["error"]
