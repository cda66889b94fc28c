"""The truth generator: a simulated grid test that is not the nominal model and that ERA identifies well."""

import numpy as np
import pytest

import era
from era.errors import EraError
from era.examples.grid import SENSORS_FT, nasa_grid
from era.examples.grid_simulation import EFFECTS, LOOSE_JOINT_LIMIT_PCT, loose_joint_signature_pct, simulate_grid_test


def matched_errors(f_identified, f_true):
    """Relative error of the identified frequency nearest to each true one."""
    f_identified = np.asarray(f_identified)
    return np.array([np.min(np.abs(f_identified / f - 1)) for f in f_true])


def test_records_have_the_test_layout_and_repeat_per_seed():
    data, truth = simulate_grid_test(seed=3, duration_s=30.0)
    assert data.markov.shape == (960, 9, 6) and data.dt == pytest.approx(1 / 32)
    assert data.outputs == tuple(f"w({x:g},{y:g}) ft" for x, y in SENSORS_FT)     # model.sensors order
    assert data.inputs[0] == "impulse at (10,0) ft"
    again, truth2 = simulate_grid_test(seed=3, duration_s=30.0)
    np.testing.assert_array_equal(data.markov, again.markov)
    np.testing.assert_array_equal(truth["frequency_hz"], truth2["frequency_hz"])
    other, _ = simulate_grid_test(seed=4, duration_s=30.0)
    assert not np.allclose(data.markov, other.markov)
    assert truth["shapes"].shape == (9, truth["frequency_hz"].size) and truth["node_shapes"].shape[0] == 88
    assert np.all(truth["frequency_hz"] < 0.85 * 16) and truth["frequency_hz"].size >= 10
    assert np.all((truth["damping_ratio"] >= 0.003) & (truth["damping_ratio"] <= 0.01))


def test_the_truth_is_not_the_nominal_model():
    f_nominal = nasa_grid().modes(10)[0]
    errors = []
    for seed in range(3):
        _, truth = simulate_grid_test(seed=seed)
        assert truth["effect"]["name"] == "none" and truth["nominal_params"] == {}
        assert truth["model"].params["elements_per_bar"] >= 2
        assert 0.005 < abs(truth["stiffness_factor"] - 1) < 0.015
        assert 0.0 < np.std(truth["gains"]) < 0.05
        errors.append(truth["frequency_hz"][:10] / f_nominal - 1)
    errors = np.abs(errors)
    assert errors.max() < 0.015                # close: no effect hidden ...
    assert errors[:, 3:].max() > 1e-3          # ... but never identical (scatter, E error, mesh)


@pytest.mark.parametrize("effect, lower", [
    ({"name": "joint_flexibility", "joint_stiffness": 300.0}, slice(3, 10)),
    ({"name": "torsion_stiffness", "torsion_factor": 0.9}, slice(3, 10)),
    ({"name": "cable_length", "cable_length_m": 0.6}, slice(0, 3)),
    ({"name": "distributed_mass", "distributed_mass_kg": 2.0}, slice(3, 10)),
    ({"name": "point_mass", "point_mass_kg": 1.5, "point_mass_at": (10, 0)}, slice(3, 10)),
    ({"name": "loose_joint", "loose_joint_stiffness": 2.0, "loose_joint_at": (0, 3)}, slice(3, 10)),
    ({"name": "damaged_bar", "bar": ("y", 5.0), "ei_factor": 0.5}, slice(3, 10)),
    ({"name": "ground_spring", "at": (10, 0), "stiffness_n_per_m": 100.0}, slice(0, 0)),
])
def test_each_hidden_effect_shifts_the_truth_the_physical_way(effect, lower):
    _, clean = simulate_grid_test(None, seed=7)               # same seed: same scatter, same E error
    _, truth = simulate_grid_test(effect, seed=7)
    ratio = truth["frequency_hz"][:10] / clean["frequency_hz"][:10]
    if effect["name"] == "ground_spring":       # a spring only stiffens
        assert np.all(ratio >= 1 - 1e-9) and ratio.max() > 1.01
    else:
        assert np.all(ratio[lower] <= 1 + 1e-9) and ratio[lower].min() < 0.998
    assert truth["effect"]["name"] == effect["name"]
    assert truth["effect"]["in_library"] == (effect["name"] in EFFECTS)
    assert isinstance(truth["effect"]["description"], str)
    for key, value in effect.items():
        if key not in ("name", "bar", "at"):
            assert truth["effect"]["parameters"][key] == value


def test_drawn_parameters_and_the_gravity_case():
    _, truth = simulate_grid_test("point_mass", seed=11)
    p = truth["effect"]["parameters"]
    assert 0.8 <= p["point_mass_kg"] <= 2.0 and truth["effect"]["location"] == p["point_mass_at"]
    # the mass is a patch, not a point: several mesh nodes carry it
    assert len(truth["model"].perturbation.point_masses) >= 3
    assert sum(m[2] for m in truth["model"].perturbation.point_masses) == pytest.approx(p["point_mass_kg"])
    for seed in (0, 1):   # a drawn loose joint sits where it moves some mode beyond the detection limit
        _, truth = simulate_grid_test("loose_joint", seed=seed)
        p = truth["effect"]["parameters"]
        assert 3.0 <= p["loose_joint_stiffness"] <= 30.0
        assert loose_joint_signature_pct(p["loose_joint_at"], p["loose_joint_stiffness"]) >= LOOSE_JOINT_LIMIT_PCT
    assert loose_joint_signature_pct((5.0, 3.0), 3.0) < 0.25 < 0.6 < loose_joint_signature_pct((0.0, 3.0), 3.0) < 1.0
    _, truth = simulate_grid_test("gravity_stiffening", seed=11)
    assert truth["nominal_params"] == {"gravity": False} and truth["model"].params["gravity"] is True
    f_model = nasa_grid(**truth["nominal_params"]).modes(10)[0]
    assert f_model[0] < 1e-3 < 0.3 < truth["frequency_hz"][0]
    with pytest.raises(EraError):
        simulate_grid_test("sagging_floor")
    with pytest.raises(EraError):
        simulate_grid_test({"name": "damaged_bar", "bar": ("x", 12.0)})
    with pytest.raises(EraError):
        simulate_grid_test({"name": "point_mass", "mass_kg": 1.0})          # the keyword is point_mass_kg


@pytest.mark.parametrize("effect, seed", [(None, 0), ({"name": "joint_flexibility"}, 5)])
def test_era_identifies_the_simulated_records(effect, seed):
    data, truth = simulate_grid_test(effect, seed=seed, duration_s=40.0, noise=0.03)
    ident = era.identify(data, rows=30, cols=500)
    model = ident.realize(40)
    err = matched_errors(model.frequency_hz, truth["frequency_hz"][:10])
    assert np.all(err < 0.005)
    # shapes too: the identified mode nearest each true one correlates with it (gains and noise aside)
    for k in range(10):
        i = np.argmin(np.abs(model.frequency_hz - truth["frequency_hz"][k]))
        assert era.mac(np.real(model.shapes[:, [i]] * np.exp(-1j * np.angle(model.shapes[np.argmax(np.abs(model.shapes[:, i])), i]))),
                       truth["shapes"][:, [k]])[0, 0] > 0.95


def test_dwell_excitation_gives_the_papers_eight_initial_conditions():
    data, truth = simulate_grid_test(seed=2, excitation="dwell", duration_s=30.0)
    assert data.markov.shape[2] == 8 and truth["inputs_ft"] == ((10.0, 0.0),) * 8
    model = era.identify(data, rows=30, cols=300).realize(40)
    assert np.all(matched_errors(model.frequency_hz, truth["frequency_hz"][:4]) < 0.005)
