"""The USC steel cantilever (real data, CC BY-SA 4.0, read from ../shared, never copied): 759 × 50.66 × 5.14 mm,
clamped, one accelerometer near the tip; published 6.62 / 41.4 / 117.5 Hz. The nominal era.Frame model is ~9-10 %
high; with one sensor and three modes explain cannot say why, and says so (ambiguous, with the ranking)."""


import numpy as np
import pytest
import scipy.signal

import era
from era.discrepancy import measured_modes
from era.examples.frames import cantilever
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

USC = SHARED_DATASETS / "usc_cantilever_free_decay" / "timeseries_data.lvm"


@pytest.fixture(scope="module")
def usc_modes():
    require_shared(USC)
    acc = np.loadtxt(USC, skiprows=23, usecols=1)      # LabVIEW LVM: 23 header lines, then time, acceleration (g)
    y = scipy.signal.decimate(acc, 4, ftype="fir", zero_phase=True)     # Nyquist 207 Hz > 117.5 Hz
    start = int(np.argmax(np.abs(y))) + 5                                # the decay just after the impact
    data = era.ResponseData(y[start:start + 3000], 4 * 0.000605, outputs=("tip",), output_units=("g",))
    m = measured_modes(era.identify(data, rows=150, cols=1300), range(2, 61, 2))
    # the bending modes below 150 Hz: stable over ≥ 15 orders with γ > 0.99 (one sensor: μ = 1 always, and
    # short-lived tracks of noise pair with anything, as MAC is 1 for any two one-sensor shapes)
    return m.take(np.flatnonzero((m.n_orders >= 15) & (m.emac > 0.99) & (m.frequency_hz < 150)))


def model():
    """The strip along x, clamped at node 0, eight members, the accelerometer along z at the tip (node 8)."""
    return cantilever(n_members=8, sensors=[("8", "z")])


def test_the_nominal_strip_is_ten_percent_stiff_and_explain_cannot_say_why_from_one_sensor(usc_modes):
    np.testing.assert_allclose(usc_modes.frequency_hz, [6.62, 41.4, 117.5], rtol=0.006)
    np.testing.assert_allclose(model().modes(4)[0][[0, 1, 3]], [7.28, 45.6, 127.7], rtol=0.002)
    r = era.explain(usc_modes, model())
    assert r.before.max_abs_freq_error_pct == pytest.approx(10.1, abs=0.3)
    assert r.verdict == "ambiguous" and r.effect is None
    # four candidates fit the three frequencies within their errors (the members known to ±2 %): spread mass, a
    # mass near mid-span, the whole strip softer (≡ thinner), a flexible clamp; none takes 90 %
    fits = {c.name: c for c in r.ranking if c.adequate}
    assert set(fits) == {"point_mass", "distributed_mass", "member_stiffness", "support_flexibility"}
    assert max(c.probability for c in r.ranking) < 0.9
    assert fits["member_stiffness"].location == ("*",)
    assert fits["member_stiffness"].parameters["member_factor"] == pytest.approx(0.83, abs=0.01)
    assert fits["distributed_mass"].parameters["distributed_mass_kg"] == pytest.approx(0.31, abs=0.02)


def test_with_the_members_taken_as_exact_one_sensor_still_names_nothing(usc_modes):
    """Without the members' scatter and the model-form allowance the 0.15 % floor leaves only a point mass placed
    freely fitting the three frequencies: three numbers for three unknowns (mass, place, stiffness factor), so no
    name."""
    r = era.explain(usc_modes, model(), errors=era.discrepancy.ErrorLevels(member_scatter=0.0, model_form=0.0,
                                                                           model_form_shape=0.0))
    assert r.verdict == "ambiguous" and r.effect is None
    assert "3 numbers (3 modes at 1 sensor)" in r.message and r.ranking[0].name == "point_mass"
