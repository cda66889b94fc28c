"""Issue 26: a roving-hammer test's struck points are sensors for explain's comparison too (era.core.points' labels in
data.meta["input_points"] that name a node and direction of the era.Frame become extra shape rows)."""

import dataclasses

import numpy as np

from era.core.correlation import mac
from era.core.data import ResponseData
from era.discrepancy import explain
from era.discrepancy.overlay import overlay
from era.discrepancy.weights import frame_point
from era.examples.frame_simulation import truth_model
from era.examples.frames import cantilever

MASS = {"point_mass_at": "2", "point_mass_kg": 0.15}


def roving(labels, struck=("4", "1", "2", "3"), seed=0, zeta=0.01, noise=0.005):
    """One accelerometer at the tip (4 z) of a cantilever with a hidden 0.15 kg at node 2, the hammer at
    ``struck`` nodes along z: displacement pulse responses (N, 1, m) from the truth's four lowest z-bending modes.
    Returns the nominal (one sensor), the data (input_points = ``labels``, none when None) and the truth's
    shapes at (tip, struck...) (1 + m, 4)."""
    nominal = cantilever(sensors=[("4", "z")])
    hammer = dataclasses.replace(nominal, sensors=[("4", "z")] + [(n, "z") for n in struck])
    truth, _ = truth_model(hammer, dict(MASS), rng=np.random.default_rng(seed))
    f, s = truth.modes(8)
    seen = np.flatnonzero(np.linalg.norm(s, axis=0) > 1e-6 * np.linalg.norm(s, axis=0).max())[:4]
    f, s = f[seen], s[:, seen]
    dt = 1.0 / (2.5 * f.max())
    w = 2 * np.pi * f
    t = np.arange(3000)[:, None] * dt
    h = np.exp(-zeta * w * t) * np.sin(w * np.sqrt(1 - zeta**2) * t) / (w * np.sqrt(1 - zeta**2))
    y = np.einsum("tn,pn,mn->tpm", h, s[:1], s[1:])
    y = y + noise * np.sqrt((y**2).mean(axis=0)) * np.random.default_rng(seed + 100).standard_normal(y.shape)
    data = ResponseData(markov=y, dt=dt, outputs=("4 z",), inputs=tuple(f"hammer {n}" for n in struck),
                        output_units=("m",), input_units=("N·s",) * len(struck),
                        meta={} if labels is None else {"input_points": tuple(labels)})
    return nominal, data, s


def test_frame_point_reads_era_points_labels():
    ids = ("0", "1", "E")
    assert frame_point("1Z", ids) == ("1", "z")
    assert frame_point("1 z", ids) == ("1", "z")
    assert frame_point("E -x", ids) == ("E", "-x")
    assert frame_point("9Z", ids) is None and frame_point("1RX", ids) is None and frame_point("", ids) is None


def test_overlay_of_an_explanation_with_struck_points_takes_the_outputs_rows():
    nominal, data, _ = roving(("4Z", "1 z", "2 z", "3Z"))
    ex = explain(data, nominal)
    out = overlay(ex, data)
    assert out["nominal"].shape == data.markov.shape
    assert np.all(out["fit_error_updated"] < 0.1)


def test_struck_points_become_shape_rows_and_the_mass_is_placed():
    nominal, data, truth = roving(("4Z", "1 z", "2 z", "3Z"))     # the tip ("4 z") is struck too: a driving point
    ex = explain(data, nominal)
    assert ex.nominal_model.sensors == (("4", "z"), ("1", "z"), ("2", "z"), ("3", "z"))
    assert ex.measured.shapes.shape == (4, ex.measured.n_modes)          # 1 sensor + 3 struck points
    # the struck shapes are the truth's (reciprocity, scaled through the tip)
    fit = ex.measured.shapes[:, ex.fit_modes]
    assert np.min(np.diag(mac(fit, truth[[0, 2, 3, 4], :fit.shape[1]]))) > 0.99
    # the MAC of the comparison is over the four rows
    model_shapes = ex.nominal_model.modes(ex.mac_before.shape[1])[1]
    assert model_shapes.shape[0] == 4
    np.testing.assert_allclose(ex.mac_before, mac(fit, model_shapes), atol=1e-9)
    assert ex.before.min_mac < 0.995       # the struck rows show the mass's shape change; one sensor cannot
    assert ex.verdict == "explained" and ex.effect.name == "point_mass" and ex.effect.location == "2"
    assert "struck point" not in ex.message


def test_without_input_points_one_sensor_as_before():
    nominal, data, _ = roving(None)
    ex = explain(data, nominal)
    assert ex.measured.struck_points is None
    assert ex.nominal_model.sensors == (("4", "z"),) and ex.measured.shapes.shape[0] == 1
    assert ex.before.min_mac > 0.9999      # a one-component shape: the MAC tells nothing
    assert "struck point" not in ex.message


def test_points_that_name_no_model_node_are_left_out_and_said():
    nominal, data, _ = roving(("4 z", "1 z", "2 z", "9Z"))
    ex = explain(data, nominal)
    assert ex.nominal_model.sensors == (("4", "z"), ("1", "z"), ("2", "z"))
    assert ex.measured.shapes.shape[0] == 3
    assert "1 struck point (9Z) names no node and direction of the model and is left out" in ex.message


def test_without_a_driving_point_the_struck_points_are_not_compared_and_said():
    nominal, data, _ = roving(("1 z", "2 z", "3 z"), struck=("1", "2", "3"))
    ex = explain(data, nominal)
    assert ex.nominal_model.sensors == (("4", "z"),) and ex.measured.shapes.shape[0] == 1
    assert "none of the struck points is also measured (a driving point)" in ex.message
