"""One rule everywhere (issue 25): the analysis opens at era's choice of modes (era.choose_modes), the stabilization
answer carries the verdict on every cluster, a report made without naming modes holds the chosen ones, and an FRF
dataset's band (which the choice looks in) survives the store."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

import era
from era.choice.choose import REASONS
from era.examples.synthetic import modal_response
from era.core.suggest import hankel_size

from apiclient import client, npz_bytes, upload

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "io"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
import uff_files as U  # noqa: E402
from chain_sim import continuous_chain  # noqa: E402

#: Four modes of three sensors, one input, Δτ = 0.01 s (Nyquist 50 Hz), 30 dB of noise.
TRUE_HZ = np.array([3.0, 7.5, 12.0, 18.0])


def noisy_four_modes(seed: int = 1) -> era.ResponseData:
    data, truth = modal_response(TRUE_HZ, [0.01, 0.015, 0.01, 0.02], 3, 1, 1000, 0.01, snr_db=30, seed=seed)
    np.testing.assert_allclose(truth.frequency_hz, TRUE_HZ)
    return data


def identify_defaults(c, blob: bytes, name: str = "four.npz") -> tuple[dict, dict]:
    ds = upload(c, blob, name).json()
    r = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": ds["defaults"]["rows"],
                                      "cols": ds["defaults"]["cols"]})
    assert r.status_code == 200, r.text
    return ds, r.json()


def test_the_stabilization_answer_carries_every_clusters_verdict_and_the_chosen_modes(tmp_path):
    with client(tmp_path) as c:
        ds, a = identify_defaults(c, npz_bytes(noisy_four_modes()))
        stab = c.get(f"/api/analyses/{a['id']}/stabilization").json()
        order, chosen = a["suggested_order"], a["chosen_indices"]
        assert order == stab["chosen_order"] and order in stab["orders"] and chosen == stab["chosen_indices"]
        assert stab["band_hz"] == [0.0, ds["nyquist_hz"]]  # time data: the whole band

        # every cluster: chosen, or a reason code and the reason in words; twins name their mode
        clusters = stab["modes"]
        assert clusters and all(mo["code"] in ("chosen",) + REASONS for mo in clusters)
        for mo in clusters:
            assert mo["chosen"] == (mo["code"] == "chosen") and (mo["reason"] == "") == mo["chosen"]
            assert (mo["mode"] is not None) == (mo["chosen"] or mo["code"] == "twin")
            assert [stab["order"][i] for i in mo["pole_indices"]] == mo["orders"]
        picked = sorted((mo for mo in clusters if mo["chosen"]), key=lambda mo: mo["mode"])
        assert [mo["mode"] for mo in picked] == list(range(4))
        np.testing.assert_allclose([mo["frequency_hz"] for mo in picked], TRUE_HZ, rtol=2e-3)
        # the same verdicts in the list of everything era judged (here every candidate is a cluster)
        cands = stab["candidates"]
        assert sorted(cand["cluster"] for cand in cands) == list(range(len(clusters)))
        for cand in cands:
            mo = clusters[cand["cluster"]]
            assert (cand["chosen"], cand["code"], cand["reason"], cand["mode"]) == \
                (mo["chosen"], mo["code"], mo["reason"], mo["mode"])
            assert cand["pole_indices"] == mo["pole_indices"]
        assert all(cand["evidence"] for cand in cands if cand["chosen"])

        # the default ticks: each known mode once, at the chosen order (GET /modes of that order)
        m = c.get(f"/api/analyses/{a['id']}/modes", params={"order": order, "fit": False}).json()
        np.testing.assert_allclose(np.array(m["frequency_hz"])[chosen], TRUE_HZ, rtol=2e-3)
        assert len(set(chosen)) == 4 and chosen == sorted(chosen, key=lambda k: m["frequency_hz"][k])
        # the analysis reopened (GET) says the same
        again = c.get(f"/api/analyses/{a['id']}").json()
        assert (again["suggested_order"], again["chosen_indices"]) == (order, chosen)


def test_a_report_made_without_naming_modes_holds_the_chosen_modes_and_so_do_its_exports(tmp_path):
    with client(tmp_path) as c:
        _, a = identify_defaults(c, npz_bytes(noisy_four_modes(seed=2)))
        made = c.post("/api/reports", json={"analysis_id": a["id"]})
        assert made.status_code == 200, made.text
        report = c.get(f"/api/reports/{made.json()['token']}").json()
        assert report["order"] == a["suggested_order"] and report["kept"] == a["chosen_indices"]
        assert report["analysis"]["chosen_indices"] == a["chosen_indices"]
        assert sum(mo["chosen"] for mo in report["stabilization"]["modes"]) == 4  # the verdicts are frozen too
        rows = c.get(f"/api/reports/{made.json()['token']}/modes.csv").text.splitlines()[1:]
        kept_hz = sorted(float(r.split(",")[2]) for r in rows if r.split(",")[1] == "1")
        np.testing.assert_allclose(kept_hz, TRUE_HZ, rtol=2e-3)
        uff = c.get(f"/api/reports/{made.json()['token']}/modes.uff")
        assert uff.status_code == 200 and len(uff.content) > 0
        # at another order the choice names no modes: the request must
        other = c.post("/api/reports", json={"analysis_id": a["id"], "order": a["suggested_order"] + 2})
        assert other.status_code == 422 and "Name the modes" in other.json()["error"]


def test_noise_free_data_of_exact_rank_open_at_that_rank_with_every_mode_chosen(tmp_path):
    """The paper's Case I: H(0) of exact rank 10 has no cluster stable below order 10; era takes the exact
    realization's five modes, which are candidates of no cluster."""
    with client(tmp_path) as c:
        ds = c.post("/api/examples/case1").json()
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": 90, "cols": 90}).json()
        stab = c.get(f"/api/analyses/{a['id']}/stabilization").json()
    assert a["suggested_order"] == a["noise_floor_order"] == stab["chosen_order"] == 10
    assert a["chosen_indices"] == [0, 1, 2, 3, 4]
    picked = [cand for cand in stab["candidates"] if cand["chosen"]]
    assert [cand["mode"] for cand in picked] == [0, 1, 2, 3, 4] and all(cand["orders"] == [10] for cand in picked)
    np.testing.assert_allclose([cand["frequency_hz"] for cand in picked], np.arange(1, 6) / (2 * np.pi), rtol=1e-8)


def test_records_of_pure_noise_open_at_a_diagram_order_with_nothing_chosen_and_every_reason_given(tmp_path):
    noise = era.ResponseData(markov=np.random.default_rng(0).standard_normal((400, 2, 1)), dt=0.01)
    with client(tmp_path) as c:
        _, a = identify_defaults(c, npz_bytes(noise), "noise.npz")
        stab = c.get(f"/api/analyses/{a['id']}/stabilization").json()
        refused = c.post("/api/reports", json={"analysis_id": a["id"]})
    assert a["chosen_indices"] == [] == stab["chosen_indices"] and a["suggested_order"] in stab["orders"]
    # the diagram order nearest the singular values' (the lower of two)
    nearest = min(stab["orders"], key=lambda o: (abs(o - a["noise_floor_order"]), o))
    assert a["suggested_order"] == stab["chosen_order"] == nearest
    assert stab["candidates"] and all(not cand["chosen"] and cand["reason"] for cand in stab["candidates"])
    assert refused.status_code == 422 and "no mode" in refused.json()["error"]


def test_the_hankel_size_and_orders_are_eras_defaults_with_the_server_settings_as_caps(tmp_path):
    data = noisy_four_modes()
    n, p, m = data.markov.shape
    era_default = hankel_size(n, p, m, max_side=era.choice.analysis.DEFAULT_MAX_SIDE,
                              max_elements=era.choice.analysis.DEFAULT_MAX_ELEMENTS,
                              max_order=era.choice.analysis.DEFAULT_MAX_ORDER)
    with client(tmp_path / "a") as c:
        ds, a = identify_defaults(c, npz_bytes(data))
        stab = c.get(f"/api/analyses/{a['id']}/stabilization").json()
    assert ds["defaults"] == {"rows": era_default.rows, "cols": era_default.cols, "max_order": era_default.max_order}
    assert stab["orders"] == list(era.choice.analysis.diagram_orders(a["max_order"]))
    with client(tmp_path / "b", max_hankel_elements=20_000, max_order=60, max_stabilization_order=40) as c:
        ds, a = identify_defaults(c, npz_bytes(data))
        stab = c.get(f"/api/analyses/{a['id']}/stabilization").json()
    assert ds["defaults"]["rows"] * p * ds["defaults"]["cols"] * m <= 20_000 and ds["defaults"]["max_order"] <= 60
    assert stab["orders"][-1] == 40 and a["suggested_order"] <= 40


@pytest.fixture()
def frf_files(tmp_path) -> tuple[list[Path], np.ndarray]:
    """Three UFF 58 FRF files of a roving-hammer test of a 3-mass chain (0-50 Hz), one per hit."""
    a, b, f_modes, _ = continuous_chain()
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    h = np.stack([np.linalg.solve(x * np.eye(6) - a, b)[:3] * x ** 2 for x in 2j * np.pi * f])
    nodes = U.nodes15([1, 2, 3], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
    paths = []
    for hit in (1, 2, 3):
        paths.append(tmp_path / f"hit{hit}.uff")
        U.write(paths[-1], [nodes, U.record58(h[:, 0, hit - 1], 0.0, 0.01, (1, 3), (hit, 3), func_type=4,
                                              denominator=U.FORCE, den_unit="N")])
    return paths, f_modes


def test_an_frf_datasets_band_bounds_the_choice_and_survives_a_restart(tmp_path, frf_files):
    paths, f_modes = frf_files
    parts = [("file", (p.name, p.read_bytes(), "application/octet-stream")) for p in paths]
    with client(tmp_path) as c:
        ds = c.post("/api/datasets", files=parts, data={"band_hz": "2,40"}).json()
        assert ds["band_hz"] == [2.0, 40.0] and ds["source"]["options"]["band_hz"] == [2.0, 40.0]
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": ds["defaults"]["rows"],
                                          "cols": ds["defaults"]["cols"]}).json()
        stab = c.get(f"/api/analyses/{a['id']}/stabilization").json()
        assert stab["band_hz"] == [2.0, 40.0]
        picked = sorted(cand["frequency_hz"] for cand in stab["candidates"] if cand["chosen"])
        np.testing.assert_allclose(picked, f_modes, rtol=5e-3)
        bad = c.post("/api/datasets", files=parts, data={"band_hz": "2 to 40"})
        assert bad.status_code == 422 and bad.json()["option"] == "band_hz"
    with client(tmp_path) as c:  # a new process: the dataset is read back from its NPZ, which has no band
        again = c.get(f"/api/analyses/{a['id']}/stabilization").json()
        assert again["band_hz"] == [2.0, 40.0] and again["chosen_indices"] == stab["chosen_indices"]
        assert c.get(f"/api/datasets/{ds['id']}").json()["band_hz"] == [2.0, 40.0]


def test_a_report_frozen_before_the_choice_still_opens(tmp_path):
    """Reports are kept for good: one stored without the choice's fields reads and downloads as before."""
    with client(tmp_path) as c:
        _, a = identify_defaults(c, npz_bytes(noisy_four_modes()))
        token = c.post("/api/reports", json={"analysis_id": a["id"]}).json()["token"]
        path = tmp_path / "reports" / token / "report.json"
        old = json.loads(path.read_text())
        for key in ("chosen_indices", "noise_floor_order"):
            del old["analysis"][key]
        for key in ("candidates", "chosen_order", "chosen_indices", "band_hz"):
            del old["stabilization"][key]
        for mo in old["stabilization"]["modes"]:
            for key in ("pole_indices", "chosen", "code", "reason", "mode"):
                del mo[key]
        path.write_text(json.dumps(old))
        r = c.get(f"/api/reports/{token}")
        assert r.status_code == 200, r.text
        assert r.json()["analysis"]["chosen_indices"] is None and r.json()["stabilization"]["candidates"] is None
        assert c.get(f"/api/reports/{token}/report.html").status_code == 200
