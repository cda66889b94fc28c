"""Analyses: identification, modes of any order, stabilization, reconstruction, limits, restarts."""

from __future__ import annotations

import numpy as np
import pytest

import era

from apiclient import analysis, case1_frequencies_hz, case1_npz, client, upload


def test_case_1_identifies_five_modes_at_order_10(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        assert a["suggested_order"] == 10 and a["max_order"] == 10  # rank 10 of noise-free data (eqs. 38-39)
        assert a["hankel_shape"] == [90, 90] and len(a["id"]) >= 22
        d = np.array(a["singular_values"])
        assert d[9] / d[0] > 1e-6 and d[10] / d[0] < 1e-12
        m = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 10}).json()
        assert m["n_modes"] == 5
        np.testing.assert_allclose(m["frequency_hz"], case1_frequencies_hz(), rtol=1e-8)
        np.testing.assert_allclose(m["damping_ratio"], 0.01 / np.hypot(0.01, 1), rtol=1e-6)  # ζ = 0.01 j / |s_j|
        assert min(m["emac"]) > 0.999 and min(m["mpc"]) > 0.999
        assert m["fit_percent"][0][0] > 99.99
        assert len(m["shapes_re"]) == 5 and len(m["shapes_re"][0]) == 1
        quick = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 10, "fit": False}).json()
        assert quick["fit_percent"] is None and quick["frequency_hz"] == m["frequency_hz"]


def test_lower_order_is_realized_from_the_same_svd(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        m4 = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 4}).json()
        assert m4["order"] == 4 and m4["n_modes"] == 2
        assert m4["fit_percent"][0][0] < 99  # two modes cannot reproduce five


@pytest.mark.parametrize("order, status, words", [(0, 422, "order"), (11, 422, "Order 11"), ("x", 422, "order")])
def test_bad_orders(tmp_path, order, status, words):
    with client(tmp_path) as c:
        _, a = analysis(c)
        r = c.get(f"/api/analyses/{a['id']}/modes", params={"order": order})
    assert r.status_code == status and words in r.json()["error"]


def test_order_is_required(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        assert c.get(f"/api/analyses/{a['id']}/modes").status_code == 422


@pytest.mark.parametrize("body, words", [
    ({"rows": 0, "cols": 90}, "rows"),
    ({"rows": 150, "cols": 90}, "samples"),                       # rows + cols > N
    ({"rows": 5, "cols": 5, "row_shifts": [2, 1, 3, 4]}, "increasing"),
    ({"rows": 5, "cols": 5, "col_shifts": [1, 2]}, "col_shifts"),
    ({"rows": 10, "cols": 10, "max_order": 50}, "max_order"),     # above min(r p, s m) = 10
    ({"cols": 10}, "rows"),
])
def test_bad_hankel_parameters_are_422_with_what_to_change(tmp_path, body, words):
    with client(tmp_path) as c:
        ds = upload(c, case1_npz()).json()
        r = c.post("/api/analyses", json=dict(dataset_id=ds["id"], **body))
    assert r.status_code == 422
    assert words in r.json()["error"]


def test_hankel_above_the_server_limit_says_what_fits(tmp_path):
    with client(tmp_path, max_hankel_elements=1000) as c:
        ds = upload(c, case1_npz()).json()
        r = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 90, "cols": 90})
        assert r.status_code == 422
        msg = r.json()["error"]
        assert "8,100 elements" in msg and "1,000" in msg and "fits" in msg
        # the suggestion really fits
        import re
        rows, cols = map(int, re.search(r"rows = (\d+), cols = (\d+) fits", msg).groups())
        assert rows * cols <= 1000
        assert c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": rows, "cols": cols}).status_code == 200


def test_hankel_limit_below_one_block(tmp_path):
    import era.examples.paper_cases
    from apiclient import npz_bytes
    with client(tmp_path, max_hankel_elements=3) as c:  # Case II MIMO: one block is 2 × 2 = 4 elements
        ds = upload(c, npz_bytes(era.examples.paper_cases.case_2(100))).json()
        r = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 5, "cols": 5})
        assert r.status_code == 422 and "Even rows = cols = 1" in r.json()["error"]


def test_unknown_ids_are_404(tmp_path):
    with client(tmp_path) as c:
        r = c.post("/api/analyses", json={"dataset_id": "nope", "rows": 5, "cols": 5})
        assert r.status_code == 404
        for path in ("", "/modes?order=2", "/stabilization", "/reconstruction?order=2", "/step?order=2"):
            r = c.get(f"/api/analyses/nope{path}")
            assert r.status_code == 404 and "No analysis" in r.json()["error"], path


def test_stabilization_finds_the_five_modes(tmp_path):
    with client(tmp_path) as c:
        ds = upload(c, case1_npz()).json()
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 90, "cols": 90}).json()
        s = c.get(f"/api/analyses/{a['id']}/stabilization").json()
    assert s["orders"] == [2, 4, 6, 8, 10]
    n = len(s["order"])
    assert all(len(s[k]) == n for k in ("frequency_hz", "damping_ratio", "emac", "mpc", "stable", "mode_index"))
    top = [f for f, o in zip(s["frequency_hz"], s["order"]) if o == 10]
    np.testing.assert_allclose(top, case1_frequencies_hz(), rtol=1e-8)
    assert s["mode_index"][-5:] == [0, 1, 2, 3, 4]
    assert len(s["spectrum"]["frequency_hz"]) == len(s["spectrum"]["values"][0])
    assert s["nyquist_hz"] == pytest.approx(10.0)


def test_reconstruction_of_kept_modes(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        url = f"/api/analyses/{a['id']}/reconstruction"
        full = c.get(url, params={"order": 10}).json()
        assert full["fit_percent"] > 99.99 and full["kept"] == [0, 1, 2, 3, 4]
        assert len(full["measured"]) == len(full["reconstructed"]) == len(full["time_s"]) == 200
        part = c.get(url, params={"order": 10, "modes": "0,1"}).json()
        assert part["kept"] == [0, 1] and part["fit_percent"] < 90
        for bad in ({"modes": "a,b"}, {"modes": "7"}, {"output": 1}, {"input": 3}, {"min_emac": 2},
                    {"min_contribution": -0.1}):
            r = c.get(url, params={"order": 10, **bad})
            assert r.status_code == 422 and r.json()["error"], bad


def test_analysis_survives_a_restart_and_cache_eviction(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        before = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 10}).json()
    with client(tmp_path, cache_identifications=1) as c:  # a new process: nothing in memory
        after = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 10}).json()
        assert after["frequency_hz"] == pytest.approx(before["frequency_hz"], rel=1e-12)
        _, b = analysis(c)  # evicts nothing of value: recomputed on demand
        assert c.get(f"/api/analyses/{a['id']}").json()["suggested_order"] == 10
        assert c.get(f"/api/analyses/{b['id']}/modes", params={"order": 8}).json()["n_modes"] == 4


def test_custom_shifts_are_used(tmp_path):
    with client(tmp_path) as c:
        ds = upload(c, case1_npz()).json()
        shifts = list(range(2, 41, 2))  # every second sample
        r = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 21, "cols": 21, "row_shifts": shifts,
                                          "col_shifts": shifts})
        assert r.status_code == 200, r.text
        a = r.json()
        assert a["row_shifts"] == shifts and a["max_order"] == 10
        m = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 10}).json()
        np.testing.assert_allclose(m["frequency_hz"], case1_frequencies_hz(), rtol=1e-6)


def test_reconstruction_keeps_modes_by_thresholds(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        url = f"/api/analyses/{a['id']}/reconstruction"
        m = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 10}).json()
        rel = np.array(m["contribution_relative"])
        cut = float(np.sort(rel)[2])  # keeps the three strongest modes
        r = c.get(url, params={"order": 10, "min_contribution": cut, "min_emac": 0.9, "physical_only": True}).json()
        assert r["kept"] == sorted(np.flatnonzero(rel >= cut).tolist()) and len(r["kept"]) == 3
        # explicit modes win over thresholds
        r = c.get(url, params={"order": 10, "modes": "1", "min_emac": 0.9, "physical_only": True}).json()
        assert r["kept"] == [1]
        # realistic thresholds keep all five modes of noise-free data
        r = c.get(url, params={"order": 10, "min_emac": 0.9, "min_mpc": 0.9, "min_contribution": 0.01}).json()
        assert r["kept"] == [0, 1, 2, 3, 4]


def test_a_slider_step_is_the_modes_and_the_reconstruction_in_one_answer(tmp_path):
    with client(tmp_path) as c:
        _, a = analysis(c)
        base = f"/api/analyses/{a['id']}"
        for params in ({"order": 10, "min_emac": 0.9, "min_mpc": 0.9, "min_contribution": 0.3, "physical_only": True},
                       {"order": 8, "modes": "0,3"}, {"order": 6}):
            both = c.get(f"{base}/step", params=params)
            assert both.status_code == 200, both.text
            both = both.json()
            modes = c.get(f"{base}/modes", params={"order": params["order"], "fit": False}).json()
            rec = c.get(f"{base}/reconstruction", params=params).json()
            for key in ("order", "n_modes", "frequency_hz", "damping_ratio", "emac", "mpc", "contribution_relative",
                        "shapes_re", "shapes_im", "is_pair"):
                assert both["modes"][key] == modes[key], key
            assert both["reconstruction"] == rec
        assert both["reconstruction"]["kept"] == [0, 1, 2] and both["modes"]["n_modes"] == 3
        rel = c.get(f"{base}/modes", params={"order": 10, "fit": False}).json()["contribution_relative"]
        cut = c.get(f"{base}/step", params={"order": 10, "min_contribution": sorted(rel)[2]}).json()
        assert cut["reconstruction"]["kept"] == sorted(np.argsort(rel)[2:].tolist())  # the weakest two rejected
        for bad in ({"modes": "7"}, {"output": 1}, {"min_emac": 2}, {"order": 0}):
            r = c.get(f"{base}/step", params={"order": 10, **bad})
            assert r.status_code == 422 and r.json()["error"], bad


def test_physical_only_rejects_growing_and_real_poles(tmp_path):
    from apiclient import npz_bytes
    dt, k = 0.05, np.arange(200)

    def pair(f_hz, zeta):
        w = 2 * np.pi * f_hz
        return np.exp((-zeta * w + 1j * w * np.sqrt(1 - zeta ** 2)) * dt * k).real

    y = pair(1.0, 0.02) + 0.5 * pair(2.0, -0.005) + 0.8 * 0.9 ** k  # decaying pair, growing pair, real pole
    with client(tmp_path) as c:
        ds = upload(c, npz_bytes(era.ResponseData(markov=y[:, None, None], dt=dt)), "three.npz").json()
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 90, "cols": 90}).json()
        url = f"/api/analyses/{a['id']}/reconstruction"
        m = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 5}).json()
        physical = c.get(url, params={"order": 5, "physical_only": True}).json()["kept"]
        every = c.get(url, params={"order": 5}).json()["kept"]
    assert m["is_pair"] == [False, True, True] and m["damping_ratio"][2] < 0
    assert physical == [1] and every == [0, 1, 2]


def test_one_channel_reconstruction_equals_the_full_one(tmp_path):
    import era.examples.paper_cases  # noqa: F401
    from app.payloads import reconstruction_json
    data = era.examples.paper_cases.case_2(200, mimo=True)
    model = era.identify(data, 45, 45).realize(10)
    kept = np.array([0, 2, 3])
    full = model.select(kept)
    rebuilt, error = full.reconstruct(200), full.fit_error(data)
    for o in range(2):
        for i in range(2):
            r = reconstruction_json(model, data, kept, o, i, max_points=4000)
            np.testing.assert_allclose(r["reconstructed"], rebuilt[:, o, i], atol=1e-12)
            assert r["fit_percent"] == pytest.approx(100 * (1 - error[o, i]), abs=1e-9)


def test_all_zero_records_are_a_422_not_an_empty_analysis(tmp_path):
    import io
    buf = io.BytesIO()
    np.savez(buf, markov=np.zeros((50, 2, 1)), dt=np.array(0.1))
    with client(tmp_path) as c:
        ds = upload(c, buf.getvalue(), "zeros.npz").json()
        r = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 10, "cols": 10})
    assert r.status_code == 422 and "rank 0" in r.json()["error"]
