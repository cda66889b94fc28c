"""Several ambient records of one test uploaded as one dataset: σ comes from the records' scatter, and the modes
payload, the report and its UFF 55 export say so; one record: from its residuals."""

from __future__ import annotations

import csv
import io

import numpy as np
import pyuff
from scipy.signal import lfilter

from era.io.uff_write import read_uncertainty_lines

from apiclient import client

DT = 0.02
F_HZ, ZETA = (1.5, 4.0), (0.02, 0.02)


def _ambient_csv(seed: int, n: int = 3000) -> bytes:
    """Two channels of a 2-mode structure under white noise (50 Hz), with a time column."""
    rng = np.random.default_rng(seed)
    modes = []
    for f, z in zip(F_HZ, ZETA):
        r = np.exp(-z * 2 * np.pi * f * DT)
        modes.append(lfilter([1.0], [1.0, -2 * r * np.cos(2 * np.pi * f * DT * np.sqrt(1 - z**2)), r**2],
                             rng.standard_normal(n)))
    y1, y2 = modes[0] + 0.5 * modes[1], 0.8 * modes[0] - modes[1]
    t = np.arange(n) * DT
    lines = ["time [s],a1 [m/s^2],a2 [m/s^2]"] + [f"{ti:.2f},{u:.9e},{v:.9e}" for ti, u, v in zip(t, y1, y2)]
    return ("\n".join(lines) + "\n").encode()


def _modes(c, files):
    parts = [("file", (f"rec{k}.csv", blob, "text/csv")) for k, blob in enumerate(files)]
    r = c.post("/api/datasets", files=parts, data={"kind": "ambient"})
    assert r.status_code == 200, r.text
    a = c.post("/api/analyses", json={"dataset_id": r.json()["id"], "rows": 30, "cols": 30}).json()
    return a, c.get(f"/api/analyses/{a['id']}/modes", params={"order": 8, "fit": False}).json()


def test_six_records_give_sigma_from_their_scatter_and_the_uff_export_says_so(tmp_path):
    files = [_ambient_csv(k) for k in range(6)]
    with client(tmp_path) as c:
        a, m = _modes(c, files)
        assert m["uncertainty_source"] == "σ from 6 records"
        f = np.array(m["frequency_hz"])
        kept = [int(np.argmin(abs(f - x))) for x in F_HZ]
        assert np.all(np.array(m["frequency_std_hz"])[kept] > 0)
        _, single = _modes(c, files[:1])
        assert single["uncertainty_source"].endswith("segments of the record")  # one record: its segments' scatter
        r = c.post("/api/reports", json={"analysis_id": a["id"], "order": 8, "modes": kept})
        assert r.status_code == 200, r.text
        token = r.json()["token"]
        report = c.get(f"/api/reports/{token}").json()
        assert report["modes"]["uncertainty_source"] == "σ from 6 records"
        assert report["stabilization"]["uncertainty_source"] == "σ from 6 records"
        stab = c.get(f"/api/analyses/{a['id']}/stabilization").json()
        assert stab["uncertainty_source"] == "σ from 6 records"
        rows = list(csv.DictReader(io.StringIO(c.get(f"/api/reports/{token}/modes.csv").text)))
        assert {r["std_source"] for r in rows} == {"σ from 6 records"}
        uff = c.get(f"/api/reports/{token}/modes.uff")
        assert uff.status_code == 200
    path = tmp_path / "modes.uff"
    path.write_bytes(uff.content)
    sets = [s for s in pyuff.UFF(str(path)).read_sets() if s["type"] == 55]
    assert len(sets) == len(kept)
    for s, k in zip(sets, kept):
        back = read_uncertainty_lines(s["id3"], s["id4"])
        assert back["source"] == "sigma from 6 records"
        np.testing.assert_allclose(back["frequency_std_hz"], m["frequency_std_hz"][k], rtol=1e-3)
        np.testing.assert_allclose(back["shape_scatter"], report["modes"]["shape_scatter"][k], rtol=1e-3)
