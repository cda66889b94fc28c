"""FRF -> Markov parameters by inverse FFT: a known chain, the FRF types and band limits, and the real ModeLAB
roving-hammer beam (GPL data read from ../shared, never copied)."""

from pathlib import Path

import numpy as np
import pytest

import era
from chain_sim import continuous_chain
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

SHARED = SHARED_DATASETS
MODELAB = SHARED / "modelab_beam_frf" / "SignalCalc"


def chain_frf(f_hz, quantity="acceleration"):
    """Exact FRF (K, 3, 3) of the chain, force in, ``quantity`` out, and the modes (f_hz, zeta)."""
    a, b, f_modes, zeta = continuous_chain()
    w = 2j * np.pi * np.asarray(f_hz)
    disp = np.stack([np.linalg.solve(x * np.eye(6) - a, b)[:3] for x in w])  # displacement / force
    power = {"displacement": 0, "velocity": 1, "acceleration": 2}[quantity]
    return disp * (w ** power)[:, None, None], f_modes, zeta


def modes_near(model, targets, rel):
    """For each target frequency the identified damped frequency closest to it (must exist within rel)."""
    f = model.frequency_hz
    found = [f[np.argmin(np.abs(f - t))] for t in targets]
    np.testing.assert_allclose(found, targets, rtol=rel)
    return np.array(found)


def test_accelerance_of_a_known_chain_gives_its_three_modes():
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    h, f_modes, zeta = chain_frf(f)
    data = era.markov_from_frf(f, h, n_samples=1500)
    assert data.dt == pytest.approx(0.01)
    assert data.markov.shape == (1500, 3, 3)
    model = era.identify(data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=2e-3)
    np.testing.assert_allclose(model.damping_ratio[np.argsort(model.frequency_hz)], zeta, rtol=0.1)


def test_frf_types_convert_into_each_other():
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    acc, _, _ = chain_frf(f, "acceleration")
    disp, _, _ = chain_frf(f, "displacement")
    band = (3.0, 50.0)
    from_acc = era.markov_from_frf(f, acc, frf_type="accelerance", to="displacement", band_hz=band, n_samples=800,
                                   output_units=["m/s^2/N"] * 3)
    assert from_acc.output_units == ("(m/s^2/N)·s^2",) * 3
    from_disp = era.markov_from_frf(f, disp, band_hz=band, n_samples=800)
    scale = np.abs(from_disp.markov).max()
    assert np.abs(from_acc.markov - from_disp.markov).max() < 1e-9 * scale
    assert any("converted to displacement" in c for c in from_acc.meta["conversions"])


def test_band_limits_keep_only_the_modes_inside_the_band():
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    h, f_modes, _ = chain_frf(f)
    data = era.markov_from_frf(f, h, band_hz=(12.0, 40.0), n_samples=1200)
    assert data.dt == pytest.approx(1 / 80)  # Nyquist moved to the band's top
    model = era.identify(data, rows=40, cols=40).realize(order=12)
    strong = model.frequency_hz[model.contribution > 0.05 * model.contribution.max()]
    modes_near(model, f_modes[1:], 3e-3)
    assert not np.any(np.abs(strong - f_modes[0]) < 1.0), "the 7 Hz mode lies below the band and must be gone"


def test_frf_not_starting_at_zero_is_zero_filled_and_uneven_lines_are_refused():
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    h, f_modes, _ = chain_frf(f)
    data = era.markov_from_frf(f[100:], h[100:], band_hz=(2.0, 50.0), n_samples=1500)
    assert "filled 100 missing lines" in data.meta["conversions"][0]
    modes_near(era.identify(data, rows=30, cols=30).realize(order=6), f_modes, 3e-3)
    bad = f.copy()
    bad[500] += 0.003
    with pytest.raises(era.DataError, match="not evenly spaced.*line 499"):
        era.markov_from_frf(bad, h)
    with pytest.raises(era.DataError, match="whole multiple"):
        era.markov_from_frf(f + 0.004, h)
    h_nan = h.copy()
    h_nan[7, 1, 2] = np.nan
    with pytest.raises(era.DataError, match="line 7, output 1, input 2"):
        era.markov_from_frf(f, h_nan)


def _read_signalcalc(path: Path) -> tuple[np.ndarray, np.ndarray]:
    a = np.loadtxt(path, skiprows=9, encoding="latin-1")
    return a[:, 0], a[:, 1] + 1j * a[:, 2]


@pytest.fixture(scope="module")
def modelab():
    require_shared(MODELAB)
    cols = [_read_signalcalc(MODELAB / f"ASCII0000{k}" / f"Hxysv0000{k}.txt") for k in range(1, 10)]
    f = cols[0][0]
    return f, np.stack([h for _, h in cols], axis=1)[:, None, :]  # (K, 1 accelerometer, 9 hammer points)


PUBLISHED_HZ = [111.99, 306.86, 596.37, 974.14]


@pytest.mark.parametrize("reciprocal", [False, True], ids=["p=1,m=9", "p=9,m=1 (reciprocity)"])
def test_modelab_roving_hammer_beam_gives_the_published_modes(modelab, reciprocal):
    f, h = modelab
    assert h.shape == (51201, 1, 9) and f[-1] == pytest.approx(1000.0)
    if reciprocal:
        h = h.transpose(0, 2, 1)
    # setup.csv of the test: analysis band fMin = 65 Hz .. fMax = 1000 Hz (below 65 Hz: rigid-body mass line, noise)
    data = era.markov_from_frf(f, h, frf_type="accelerance", band_hz=(65.0, 1000.0), n_samples=3000)
    assert data.dt == pytest.approx(5e-4)
    rows, cols = (300, 60) if not reciprocal else (60, 300)
    model = era.identify(data, rows=rows, cols=cols).realize(order=20)
    strongest = np.sort(model.frequency_hz[np.argsort(model.contribution)[-4:]])
    np.testing.assert_allclose(strongest, PUBLISHED_HZ, rtol=5e-3)
    assert np.all(model.emac[np.argsort(model.contribution)[-4:]] > 0.95)
    assert np.all(model.damping_ratio[np.argsort(model.contribution)[-4:]] < 0.01)
