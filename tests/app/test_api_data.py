"""Datasets and examples: uploads (good, malformed, empty, oversized), summaries, records, spectra, examples."""

from __future__ import annotations

import numpy as np
import pytest

import era
import era.examples.paper_cases
from apiclient import case1_npz, client, npz_bytes, upload

REPO = __import__("pathlib").Path(__file__).resolve().parents[2]


def test_upload_npz_returns_the_summary_with_defaults_and_limits(tmp_path):
    with client(tmp_path) as c:
        r = upload(c, case1_npz())
        assert r.status_code == 200, r.text
        ds = r.json()
        assert ds["n_samples"] == 200 and ds["dt"] == 0.05
        assert ds["outputs"] == ["sensor 1"] and ds["inputs"] == ["IC 1"]
        assert ds["defaults"] == {"rows": 90, "cols": 90, "max_order": 90}  # the paper's Case I choice
        assert ds["limits"]["rows_plus_cols_max"] == 200
        assert len(ds["id"]) >= 22 and len(ds["sha256"]) == 64
        assert c.get(f"/api/datasets/{ds['id']}").json() == ds


def test_dataset_ids_are_random_and_not_sequential(tmp_path):
    with client(tmp_path) as c:
        ids = {upload(c, case1_npz()).json()["id"] for _ in range(3)}
    assert len(ids) == 3 and all(len(i) >= 22 for i in ids)  # 18 random bytes, URL-safe


def test_labels_are_stored_verbatim_as_text(tmp_path):
    evil = "<img src=x onerror=alert(1)>"
    data = era.ResponseData(era.examples.paper_cases.case_1(50).markov, 0.05, outputs=(evil,), inputs=("hammer & <b>",))
    with client(tmp_path) as c:
        ds = upload(c, npz_bytes(data), name="<script>.npz").json()
        assert ds["outputs"] == [evil] and ds["inputs"] == ["hammer & <b>"]
        assert ds["name"] == "<script>.npz"


@pytest.mark.parametrize("blob, name, words", [
    (b"this is not an archive", "data.npz", "data.npz"),
    (b"PK\x03\x04broken zip", "broken.npz", "npz"),
    (b"time,a\n0,1\n0.1,nan\n", "bad.csv", "nan"),
])
def test_malformed_files_get_422_with_the_loaders_message(tmp_path, blob, name, words):
    with client(tmp_path) as c:
        r = upload(c, blob, name)
    assert r.status_code == 422
    msg = r.json()["error"]
    assert words.lower() in msg.lower() and "Traceback" not in msg


def test_npz_without_markov_names_what_is_missing(tmp_path):
    import io
    buf = io.BytesIO()
    np.savez(buf, dt=np.array(0.1), y=np.zeros(10))
    with client(tmp_path) as c:
        r = upload(c, buf.getvalue(), "nomarkov.npz")
    assert r.status_code == 422 and "markov" in r.json()["error"]


def test_nan_in_the_data_is_a_422(tmp_path):
    y = era.examples.paper_cases.case_1(50).markov.copy()
    import io
    buf = io.BytesIO()
    y[7, 0, 0] = np.nan
    np.savez(buf, markov=y, dt=np.array(0.05))
    with client(tmp_path) as c:
        r = upload(c, buf.getvalue(), "nan.npz")
    assert r.status_code == 422 and "NaN" in r.json()["error"]


def test_empty_file_and_missing_field_are_422(tmp_path):
    with client(tmp_path) as c:
        assert upload(c, b"", "empty.npz").status_code == 422
        r = c.post("/api/datasets", data={"other": "x"})
        assert r.status_code == 422 and "file" in r.json()["error"]


def test_geometry_only_file_is_refused_with_a_reason(tmp_path):
    path = REPO / "tests" / "data" / "testlab_geometry_15_82.uff"
    with client(tmp_path) as c:
        r = upload(c, path.read_bytes(), path.name)
    assert r.status_code == 422 and "no response records" in r.json()["error"]


def test_upload_above_the_limit_is_413_before_parsing(tmp_path):
    with client(tmp_path, max_upload_bytes=2000) as c:
        r = upload(c, b"x" * 5000, "big.npz")
        assert r.status_code == 413 and "limit" in r.json()["error"]
        # without Content-Length (chunked): counted as it arrives
        r = c.post("/api/datasets", content=(b"y" * 1000 for _ in range(5)),
                   headers={"content-type": "multipart/form-data; boundary=zz"})
        assert r.status_code == 413
        assert upload(c, b"small but not npz", "s.npz").status_code == 422  # under the limit: parsed


def test_records_and_spectrum(tmp_path):
    with client(tmp_path, max_plot_points=64) as c:
        ds = upload(c, case1_npz()).json()
        rec = c.get(f"/api/datasets/{ds['id']}/records").json()
        assert rec["outputs"] == ["sensor 1"] and len(rec["series"]) == 1
        assert len(rec["time_s"]) == len(rec["series"][0]) <= 64  # decimated for the browser
        assert c.get(f"/api/datasets/{ds['id']}/records?input=1").status_code == 422
        spec = c.get(f"/api/datasets/{ds['id']}/spectrum").json()
        f = np.array(spec["frequency_hz"])
        peak = f[int(np.argmax(spec["values"][0]))]
        assert abs(peak - 5 / (2 * np.pi)) < 0.06  # the strongest of the five modes (eq. 58)


def test_unknown_dataset_is_404_everywhere(tmp_path):
    with client(tmp_path) as c:
        for path in ("/api/datasets/nope", "/api/datasets/nope/records", "/api/datasets/nope/spectrum"):
            r = c.get(path)
            assert r.status_code == 404 and "No dataset" in r.json()["error"]


def test_examples_list_and_load(tmp_path):
    with client(tmp_path) as c:
        names = [e["name"] for e in c.get("/api/examples").json()]
        assert {"case1", "case2"} <= set(names)
        ds = c.post("/api/examples/case2").json()
        assert ds["n_outputs"] == 2 and ds["n_inputs"] == 2
        assert ds["defaults"]["rows"] == 45 and ds["defaults"]["cols"] == 45  # the paper's choice
        r = c.post("/api/examples/case9")
        assert r.status_code == 404 and "case1" in r.json()["error"]


def test_grid_example_has_nine_sensors_and_the_geometry(tmp_path):
    with client(tmp_path) as c:
        ds = c.post("/api/examples/grid").json()
    assert ds["n_outputs"] == 9 and ds["geometry"]["n_nodes"] == 88


def test_upload_uff_ambient_records_become_correlation_functions(tmp_path):
    path = REPO / "tests" / "data" / "mpstd_first_8192.uff"
    with client(tmp_path) as c:
        r = upload(c, path.read_bytes(), path.name)
        assert r.status_code == 200, r.text
        ds = r.json()
        assert (ds["n_outputs"], ds["n_inputs"]) == (4, 4) and ds["dt"] == pytest.approx(1 / 3200)
        assert ds["source"]["format"] == "uff" and "NExT" in " ".join(ds["source"]["conversions"])
        assert ds["output_units"] == ["m/s2"] * 4
        # NExT keeps about four periods of the lowest resonance (era.markov.next.default_lags): 71 lags here
        assert 40 <= ds["n_samples"] <= 2048
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 30, "cols": 30, "max_order": 60})
        assert a.status_code == 200, a.text


def test_upload_csv_of_a_free_decay(tmp_path):
    data = era.examples.paper_cases.case_1(200)
    lines = ["time,sensor 1"] + [f"{k * 0.05:.2f},{v:.12g}" for k, v in enumerate(data.markov[:, 0, 0])]
    with client(tmp_path) as c:
        blob = "\n".join(lines).encode()
        r = c.post("/api/datasets", files={"file": ("decay.csv", blob, "text/csv")}, data={"kind": "decay"})
        assert r.status_code == 200, r.text
        ds = r.json()
        assert ds["n_samples"] >= 190 and ds["dt"] == pytest.approx(0.05)
        assert ds["source"]["format"] == "csv" and ds["source"]["kind"] == "decay"
        r = c.post("/api/datasets", files={"file": ("decay.csv", blob, "text/csv")}, data={"kind": "guess"})
        assert r.status_code == 422 and "kind" in r.json()["error"]
