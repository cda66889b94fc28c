"""identify_modes balances the inputs before era.analyse: the kept records (σ from their scatter) are balanced
alike."""

import numpy as np

import era
from era.discrepancy import measured


def test_balanced_inputs_scale_the_records_like_their_mean(monkeypatch):
    rng = np.random.default_rng(3)
    records = rng.standard_normal((5, 200, 3, 2)) * np.array([1.0, 1e3])     # second input 1000× stronger
    data = era.ResponseData(records.mean(axis=0), 0.01, records=records)
    seen = {}

    def capture(d, **kw):
        seen["data"] = d
        raise RuntimeError("captured")

    monkeypatch.setattr(measured, "analyse", capture)
    try:
        measured.identify_modes(data)
    except RuntimeError:
        pass
    d = seen["data"]
    w = measured.input_weights(data.markov)
    assert not np.allclose(w, 1.0)
    np.testing.assert_allclose(d.records.mean(axis=0), d.markov, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(d.records, records * w, rtol=1e-12)
