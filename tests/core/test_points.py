"""The mode shape at every measured or struck point (issue 26, era.core.points): a simulated roving-hammer test whose
residues are made from known shapes at known hit points gives back those shapes at the hit points, scaled onto the
sensors' through the driving point; with one sensor off the hit points, the hit points' shapes alone."""

import numpy as np
import pytest

import era
from era.examples.synthetic import modal_response
from era.core.points import point_geometry, point_shapes

F_HZ = np.array([5.0, 12.0, 21.0])
ZETA = np.array([0.02, 0.015, 0.01])
DT = 0.01


def _mac(a, b):
    return abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)


def roving_hammer(psi, outputs, inputs, modal_constant, signs_out=None, signs_in=None, n_samples=400):
    """Pulse responses Y(k) = Σ_j 2 Re(z_j^k ψ_i ψ_k / a_j) of sensors at ``outputs`` for hits at ``inputs``
    (rows of ψ; reciprocity: the same ψ on both sides), each channel read with its sign."""
    so = np.ones(len(outputs)) if signs_out is None else np.asarray(signs_out)
    si = np.ones(len(inputs)) if signs_in is None else np.asarray(signs_in)
    s = -ZETA * 2 * np.pi * F_HZ / np.sqrt(1 - ZETA ** 2) + 2j * np.pi * F_HZ
    zk = np.exp(np.outer(np.arange(n_samples) * DT, s))
    y = 2 * np.einsum("kj,pj,mj,j->kpm", zk, psi[outputs] * so[:, None], psi[inputs] * si[:, None],
                      1 / modal_constant).real
    labels = [f"{k + 1}Z" for k in range(len(psi))]
    meta = {"output_points": tuple(labels[i] for i in outputs), "output_signs": tuple(so),
            "input_points": tuple(labels[i] for i in inputs), "input_signs": tuple(si)}
    return era.ResponseData(markov=y, dt=DT, meta=meta)


def _truth_at(model, psi):
    return psi[[int(p[:-1]) - 1 for p in model.points]]


def test_a_roving_hammer_with_a_driving_point_gives_the_shape_at_every_point():
    # complex (non-proportionally damped) modes: the amplitudes are ψ, not its conjugate, times a constant
    _, truth = modal_response(F_HZ, ZETA, 8, 1, 10, DT, seed=3)  # known real shapes, 8 points
    rng = np.random.default_rng(1)
    psi = truth.shapes + 0.3j * rng.standard_normal(truth.shapes.shape)
    data = roving_hammer(psi, outputs=[0, 3], inputs=[1, 2, 3, 4, 5, 6, 7],
                         modal_constant=np.array([1 + .5j, 2 - 1j, .7]),
                         signs_out=[1, -1], signs_in=[1, 1, -1, 1, 1, 1, 1])
    model = era.identify(data, rows=40, cols=40).model(6)
    assert sorted(model.points) == [f"{k}Z" for k in range(1, 9)] and model.point_shapes.shape == (8, 3)
    want = _truth_at(model, psi)
    for j in range(3):
        v = model.point_shapes[:, j]
        assert np.max(np.abs(v)) == pytest.approx(1.0)
        # the scale between the sensors' and the hammer's sides is right: the shapes agree component by component
        np.testing.assert_allclose(v / v[0], want[:, j] / want[0, j], atol=1e-9)
    kept = model.select([0, 2])  # select keeps the points' shapes in step
    np.testing.assert_allclose(kept.point_shapes, model.point_shapes[:, [0, 2]])


def test_one_sensor_off_the_hit_points_gives_the_hit_points_shape():
    _, truth = modal_response(F_HZ, ZETA, 7, 1, 10, DT, seed=4)
    data = roving_hammer(truth.shapes, outputs=[6], inputs=[0, 1, 2, 3, 4, 5], modal_constant=np.ones(3) * 2j)
    model = era.identify(data, rows=40, cols=40).model(6)
    assert model.points == tuple(f"{k}Z" for k in range(1, 7))  # the sensor's own value cannot be separated
    for j in range(3):
        assert _mac(model.point_shapes[:, j], truth.shapes[:6, j]) > 1 - 1e-12


def test_without_input_points_the_points_are_the_sensors():
    data, _ = modal_response(F_HZ, ZETA, 3, 2, 300, DT, seed=0)
    model = era.identify(data, rows=30, cols=30).model(6)
    assert model.points == data.outputs and model.point_shapes is model.shapes


def test_a_sensor_measured_twice_is_one_point_and_a_geometry_places_each_point():
    shapes = np.array([[1.0, 0.5], [1.0, 0.5], [0.2, 1.0]])
    pts, vals = point_shapes(shapes, np.ones((2, 1)), ["1X", "1X", "2Y"], [""])
    assert pts == ("1X", "2Y") and vals.shape == (2, 2)
    geo = era.Geometry([1, 2], [[0, 0, 0], [1, 0, 0]], [[0, 1]], [0, 1], [[1, 0, 0], [0, 1, 0]])
    placed = point_geometry(geo, ["2Y", "1X", "9Z", "E x"])
    assert placed.channel_nodes.tolist() == [1, 0, -1, -1]
    np.testing.assert_allclose(placed.channel_directions[:2], [[0, 1, 0], [1, 0, 0]])


def test_the_uff_55_export_writes_the_point_shapes_at_their_nodes(tmp_path):
    _, truth = modal_response(F_HZ, ZETA, 6, 1, 10, DT, seed=5)
    data = roving_hammer(truth.shapes, outputs=[2], inputs=[0, 1, 2, 3, 4, 5], modal_constant=np.ones(3))
    model = era.identify(data, rows=40, cols=40).model(6)
    geo = era.Geometry(np.arange(1, 7), np.column_stack([np.arange(6.0), np.zeros(6), np.zeros(6)]),
                       [[k, k + 1] for k in range(5)], [2], [[0, 0, 1]])  # the sensor at node 3 along z
    era.save_modes_uff(tmp_path / "modes.uff", model, geo)
    back = era.read_modes_uff(str(tmp_path / "modes.uff"))
    assert back.node_ids.tolist() == [1, 2, 3, 4, 5, 6]
    at = [model.points.index(f"{k}Z") for k in range(1, 7)]
    np.testing.assert_allclose(back.shapes[:, 2, :], model.point_shapes[at], atol=1e-5)
    np.testing.assert_allclose(back.shapes[:, :2, :], 0, atol=1e-12)


def test_a_simulated_tests_input_locations_name_the_struck_points_as_its_sensors():
    _, truth = modal_response(F_HZ, ZETA, 4, 1, 10, DT, seed=6)
    data = roving_hammer(truth.shapes, outputs=[0, 1, 2, 3], inputs=[1, 3], modal_constant=np.ones(3))
    frame = era.ResponseData(markov=data.markov, dt=DT, outputs=("A x", "B x", "C x", "D x"),
                             meta={"input_locations": (("B", "x"), ("D", "x"))})
    model = era.identify(frame, rows=40, cols=40).model(6)
    assert model.points == frame.outputs  # every struck point is measured: the sensors' shapes
    np.testing.assert_allclose(model.point_shapes, model.shapes, atol=1e-12)
