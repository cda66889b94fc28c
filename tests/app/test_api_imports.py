"""The import step through the API: files are kept as they came and shown as read (channels, units, sampling, a
plot of each), re-read with the person's options, and become a dataset only when asked; refusals name the option
that fixes them; nothing is stored until then, and the choices stay with the dataset."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from pydantic import TypeAdapter

from app import schemas
from apiclient import client

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "io"))
import uff_files as U  # noqa: E402
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

CARINI = SHARED_DATASETS / "carini_ambient_3ch" / "yk.txt"


def valid(kind, value):
    TypeAdapter(kind).validate_python(value)
    return value


def test_a_rows_file_without_sample_rate_is_shown_then_imported_with_the_persons_choices(tmp_path):
    blob = require_shared(CARINI).read_bytes()
    with client(tmp_path) as c:
        first = c.post("/api/imports", files={"file": ("yk.txt", blob)})
        assert first.status_code == 200, first.text
        up = valid(schemas.Import, first.json())
        assert up["option"] == "dt" and "no sampling interval in yk.txt: give the sample rate" in up["error"]
        pv = up["preview"]  # shown anyway, against the sample number
        assert pv["dt"] is None and pv["x_label"] == "sample" and [ch["name"] for ch in pv["channels"]] == \
            ["ch1", "ch2", "ch3"]
        assert len(pv["traces"]) == 3 and len(pv["traces"][0]) == len(pv["x"]) <= 4000
        assert c.get("/api/health").json()["usage"]["rows"]["datasets"] == 0  # nothing stored yet

        again = valid(schemas.Import, c.post(f"/api/imports/{up['id']}/preview",
                                             json={"dt": 0.04, "orientation": "rows", "start_sample": 100,
                                                   "drop": [2]}).json())
        assert again["error"] is None and again["preview"]["sample_rate_hz"] == pytest.approx(25.0)
        assert [ch["dropped"] for ch in again["preview"]["channels"]] == [False, False, True]
        assert again["preview"]["start"] == pytest.approx(4.0) and again["preview"]["kind"] == "ambient"

        wrong = c.post(f"/api/imports/{up['id']}/dataset", json={"dt": 0.04, "orientation": "rows", "kind": "io"})
        assert wrong.status_code == 422 and wrong.json()["option"] == "forces"  # shown next to the channel roles
        assert c.get("/api/health").json()["usage"]["rows"]["datasets"] == 0

        made = c.post(f"/api/imports/{up['id']}/dataset", json={"dt": 0.04, "orientation": "rows", "kind": "ambient",
                                                                 "references": [0], "start_sample": 100})
        assert made.status_code == 200, made.text
        ds = valid(schemas.Dataset, made.json())
        assert ds["n_outputs"] == 3 and ds["n_inputs"] == 1 and ds["dt"] == pytest.approx(0.04)
        assert ds["source"]["options"] == {"dt": 0.04, "orientation": "rows", "references": [0], "start_sample": 100,
                                           "kind": "ambient"}
        assert ds["source"]["channels_read"] == ["ch1", "ch2", "ch3"]
        assert c.get(f"/api/datasets/{ds['id']}").json()["source"]["options"]["start_sample"] == 100
        gone = c.post(f"/api/imports/{up['id']}/preview", json={})  # the staged files went with the commit
        assert gone.status_code == 404 and "drop the files again" in gone.json()["error"]
        assert c.get("/api/health").json()["usage"]["bytes"]["imports"] == 0


def test_three_uff_files_of_a_roving_hammer_test_show_nodes_directions_and_references(tmp_path):
    f = np.arange(0, 50.0 + 1e-9, 0.05)
    h = 1.0 / (1 - (f / 12.0) ** 2 + 0.02j * f / 12.0)
    nodes = U.nodes15([1, 2, 3], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
    parts = []
    for hit in (1, 2, 3):
        path = tmp_path / f"hit{hit}.uff"
        U.write(path, [nodes, U.record58(h * hit, 0.0, 0.05, (1, 3), (hit, 3), func_type=4, denominator=U.FORCE,
                                         den_unit="N")])
        parts.append(("file", (path.name, path.read_bytes())))
    with client(tmp_path / "data") as c:
        up = valid(schemas.Import, c.post("/api/imports", files=parts).json())
        assert up["error"] is None and up["files"] == ["hit1.uff", "hit2.uff", "hit3.uff"]
        pv = up["preview"]
        assert pv["domain"] == "frequency" and pv["x_label"] == "frequency (Hz)" and pv["kind"] == "frf"
        assert pv["channels"][0]["node"] == 1 and pv["channels"][0]["direction"] == "+Z"
        assert len(pv["references"]) == 3 and pv["geometry_nodes"] == 3
        refused = c.post(f"/api/imports/{up['id']}/dataset", json={"start_sample": 5})
        assert refused.status_code == 422 and refused.json()["option"] == "start_sample"
        ds = c.post(f"/api/imports/{up['id']}/dataset", json={}).json()
        assert ds["n_inputs"] == 3 and ds["n_outputs"] == 1 and ds["geometry"]["n_nodes"] == 3


def test_bad_requests_are_refused_in_words(tmp_path):
    with client(tmp_path) as c:
        assert c.post("/api/imports/nope/dataset", json={}).status_code == 404
        empty = c.post("/api/imports", files={"file": ("a.csv", b"")})
        assert empty.status_code == 422 and "'a.csv' is empty" in empty.json()["error"]
        up = c.post("/api/imports", files={"file": ("a.csv", b"time,x\n0,1\n0.1,2\n0.2,3\n")}).json()
        odd = c.post(f"/api/imports/{up['id']}/preview", json={"dt": -1})
        assert odd.status_code == 422 and "dt" in odd.json()["error"]
        extra = c.post(f"/api/imports/{up['id']}/preview", json={"sample_rate": 25})
        assert extra.status_code == 422 and "sample_rate" in extra.json()["error"]
        assert up["error"] is None and up["preview"]["n_samples"] == [3]  # shown as read ...
        short = c.post(f"/api/imports/{up['id']}/dataset", json={})  # ... and refused in a sentence when used
        assert short.status_code == 422 and "samples" in short.json()["error"]
        assert c.get("/api/health").json()["usage"]["rows"]["datasets"] == 0


PHONE = Path(__file__).resolve().parents[1] / "data" / "cessipy_smartphone_slab.csv"


def test_a_phone_csv_with_a_jittered_clock_is_shown_and_resampled_only_when_the_person_ticks_it(tmp_path):
    """The CESSIPy phone record (every row ends in a comma, stamps jitter about 425 Hz): the refusal sits under
    the resample control with the records shown; ticked, the dataset is made and its source says what was done."""
    with client(tmp_path) as c:
        up = valid(schemas.Import, c.post("/api/imports", files={"file": (PHONE.name, PHONE.read_bytes())}).json())
        assert up["option"] == "resample" and "No sample is missing or repeated" in up["error"]
        assert "425.077 Hz" in up["error"] and "dt=" not in up["error"]
        pv = up["preview"]
        assert [ch["name"] for ch in pv["channels"]] == ["X-Axis", "Y- Axis", "Z-Axis"]
        assert pv["sample_rate_hz"] == pytest.approx(425.077, abs=1e-3) and len(pv["traces"]) == 3
        refused = c.post(f"/api/imports/{up['id']}/dataset", json={"kind": "ambient"})
        assert refused.status_code == 422 and refused.json()["option"] == "resample"
        ticked = valid(schemas.Import, c.post(f"/api/imports/{up['id']}/preview", json={"resample": True}).json())
        assert ticked["error"] is None and any("resampled onto an even grid" in d
                                               for d in ticked["preview"]["described"])
        made = c.post(f"/api/imports/{up['id']}/dataset", json={"kind": "ambient", "resample": True})
        assert made.status_code == 200, made.text
        src = made.json()["source"]
        assert src["options"] == {"kind": "ambient", "resample": True}
        assert src["conversions"][0].startswith(f"{PHONE.name}: resampled onto an even grid at the mean rate "
                                                "425.077 Hz")


def test_a_staged_upload_is_read_once_and_its_dataset_holds_the_files_numbers(tmp_path, monkeypatch):
    """Preview, then dataset with the same reading options: the files are read once (the preview's reading is
    converted); the free decays are the file's columns, as numpy wrote them. Another reading option reads again."""
    import era.io
    import era.io.preview

    t = np.arange(400) * 0.01
    y = np.stack([np.exp(-0.3 * t) * np.sin(2 * np.pi * 5 * t), np.exp(-0.5 * t) * np.cos(2 * np.pi * 8 * t)], 1)
    text = "time,a,b\n" + "\n".join(f"{a:.6f},{b:.17g},{c:.17g}" for a, (b, c) in zip(t, y))
    calls = []
    real = era.io.read

    def counted(*args, **kw):
        calls.append(kw)
        return real(*args, **kw)

    monkeypatch.setattr(era.io, "read", counted)
    monkeypatch.setattr(era.io.preview, "read", counted)
    with client(tmp_path) as c:
        up = c.post("/api/imports", files={"file": ("decay.csv", text.encode())}).json()
        assert up["error"] is None and len(calls) == 1
        made = c.post(f"/api/imports/{up['id']}/dataset", json={"kind": "decay"})
        assert made.status_code == 200, made.text
        assert len(calls) == 1  # converted from the preview's reading
        ds = made.json()
        assert ds["n_outputs"] == 2 and ds["dt"] == pytest.approx(0.01)
        markov = c.app.state.cache.dataset(ds["id"]).data.markov
        np.testing.assert_allclose(markov[:, :, 0], y[-len(markov):], rtol=1e-15, atol=1e-15)

        up2 = c.post("/api/imports", files={"file": ("decay.csv", text.encode())}).json()
        assert len(calls) == 2
        again = c.post(f"/api/imports/{up2['id']}/dataset", json={"kind": "decay", "dt": 0.02})  # another reading
        assert again.status_code == 200, again.text
        assert len(calls) == 3
