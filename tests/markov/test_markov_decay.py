"""Free decays and impulse responses: the pulse response starts after the impact / at t = 0."""

import numpy as np
import pytest

import era


def test_decay_starts_after_the_impact_peak_and_keeps_the_modes():
    dt = 0.01
    t = np.arange(3000) * dt
    decay = np.exp(-0.05 * 2 * np.pi * 3 * t) * np.sin(2 * np.pi * 3 * t + 0.3)
    record = np.concatenate([np.zeros(200), [0.3, 2.5], decay])  # pre-trigger, impact, free decay
    data = era.markov_from_decay(record, dt)
    assert data.meta["start_samples"] == [202]
    assert data.markov.shape == (3000, 1, 1)
    model = era.identify(data, rows=20, cols=20).realize(order=2)
    assert model.frequency_hz[0] == pytest.approx(3.0, rel=1e-9)
    assert model.damping_ratio[0] == pytest.approx(0.05 / np.sqrt(1 + 0.05 ** 2), rel=1e-6)  # σ/|s|, σ = 0.05 ω_d


def test_columns_triggered_at_different_samples_are_aligned():
    y = np.zeros((500, 1, 2))
    y[10:, 0, 0] = 0.9 ** np.arange(490)
    y[30:, 0, 1] = 0.8 ** np.arange(470)
    data = era.markov_from_decay(y, 0.1, start=[10, 30])
    assert data.markov.shape == (470, 1, 2)
    assert data.markov[3, 0, 0] == pytest.approx(0.9 ** 3) and data.markov[3, 0, 1] == pytest.approx(0.8 ** 3)
    with pytest.raises(era.DataError, match="too few"):
        era.markov_from_decay(y, 0.1, start=498)
