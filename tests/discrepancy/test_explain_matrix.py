"""explain() on an FE model given as matrices: a cantilever plate of bricks whose stiffness and mass CalculiX
wrote (``*FREQUENCY, SOLVER=MATRIXSTORAGE``), tested against truths CalculiX solved itself (a run of ``ccx``
with a MASS or SPRING2 element hidden in the deck, E 2 % high on the root half and 1 % low on the tip half, 0.2 %
frequency noise, 1 % sensor gains and shape noise). It names the hidden mass and the hidden spring to ground, their
places and sizes, as it does on an era.Frame; the patch it writes brings the matrices to the truth."""

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

import ccx_plate
import era
from era.discrepancy import modes_from_arrays
from era.discrepancy.effects_matrix import matrix_effects
from era.examples.synthetic import modal_response

N_MODES = 7
SENSORS = [(str(ccx_plate.node(i, j, 1)), "z") for i in range(2, ccx_plate.NX + 1, 2)
           for j in range(0, ccx_plate.NY + 1, 2)]
FORM = (1.02, 0.99)     # E of the root and tip halves in the truth


@pytest.fixture(scope="module")
def plate(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plate")
    return folder, era.load_model(ccx_plate.matrices(folder)).with_sensors(SENSORS)


def measured(folder, job, seed, **hidden):
    """The truth's lowest modes (ccx) with noise, as a test would measure them at SENSORS."""
    f, s = ccx_plate.modes(folder, job, N_MODES, SENSORS, e_scale=FORM, **hidden)
    rng = np.random.default_rng(seed)
    f = f * (1 + 0.002 * rng.standard_normal(f.size))
    s = s * (1 + 0.01 * rng.standard_normal((s.shape[0], 1)))
    s = s / np.linalg.norm(s, axis=0) + 0.01 * rng.standard_normal(s.shape)
    return modes_from_arrays(f, s, 0.002 * f), f


def _in_interval(value, interval):
    low, high = interval
    return (low is None or low <= value) and (high is None or value <= high)


def test_a_hidden_point_mass_is_named_at_its_node_with_its_size(plate, tmp_path):
    folder, model = plate
    at, kg = str(ccx_plate.node(6, 3, 1)), 0.8
    data, truth_f = measured(folder, "mass", 1, mass=(at, kg))
    r = era.explain(data, model)
    assert r.verdict == "explained" and r.effect.name == "point_mass"
    assert at in [p for p, _ in r.effect.places] and r.effect.location == at
    assert _in_interval(kg, r.effect.size_interval)
    assert r.before.max_abs_freq_error_pct > 2.0 and r.after.max_abs_freq_error_pct < 1.0
    # the fix back out: the changed M, loaded back with the model's own K, has the truth's frequencies
    era.save_model(model, tmp_path / "updated")
    era.save_patch(model, r.updated_model.params, tmp_path / "updated", stiffness_factor=True)
    fixed = era.load_model(tmp_path / "updated")
    np.testing.assert_allclose(fixed.modes(N_MODES)[0], truth_f, rtol=0.015)


def test_a_hidden_spring_to_ground_is_named_with_the_places_the_data_cannot_tell_apart(plate):
    """A spring under the tip corner (about four times the stiffness a point load meets there). With E 2 % off
    one way at the root and 1 % the other at the tip, a spring anywhere along the free edge fits about as well,
    a stiffer one nearer the root: explain names the effect and a set of places on that edge holding the truth,
    and does not pretend to know which (nor the size, which trades with the place)."""
    folder, model = plate
    at, k = ccx_plate.node(ccx_plate.NX, ccx_plate.NY, 1), 2e5
    data, _ = measured(folder, "spring", 2, spring=(at, "z", k))
    r = era.explain(data, model)
    assert r.verdict == "explained" and r.effect.name == "ground_spring_z"
    # the top and bottom nodes of the corner are one place for bending modes: both in the credible set
    places = [p for p, _ in r.effect.places]
    assert f"{at}:z" in places and f"{ccx_plate.node(ccx_plate.NX, ccx_plate.NY, 0)}:z" in places
    assert all(p.endswith(":z") for p in places) and len(places) < 12
    assert "at one of these DOFs: node" in r.effect.description and " in z " in r.effect.description
    assert r.after.max_abs_freq_error_pct < 1.5 and r.before.max_abs_freq_error_pct > 5


def test_the_plate_as_modelled_raises_no_alarm_and_its_points_come_from_the_channel_labels(plate):
    """Pulse responses of the truth's modes (ERA identifies them) whose channels are labelled "117z": the model
    has no sensors of its own, and explain reads them from the labels."""
    folder, model = plate
    f, s = ccx_plate.modes(folder, "none", N_MODES, SENSORS, e_scale=FORM)
    data, _ = modal_response(f, 0.01, len(SENSORS), 1, 1500, 1 / 5000, snr_db=50, seed=3, shapes=s)
    data = dataclasses.replace(data, outputs=tuple(f"{n}{d}" for n, d in SENSORS))
    bare = model.with_sensors(())
    r = era.explain(data, bare)
    assert r.nominal_model.sensors == tuple(SENSORS)
    assert r.verdict != "explained" and r.effect is None
    with pytest.raises(era.DataError, match="output labels do not all name a node and direction"):
        era.explain(dataclasses.replace(data, outputs=("A1",) * len(SENSORS)), bare)


def test_struck_points_on_free_dofs_join_the_sensors_and_the_others_are_said(plate):
    """A roving-hammer test: ten accelerometers, the other ten points struck (their shapes scaled through a
    driving point). The struck points that name a free DOF of the matrices are compared as sensors; a point
    on the clamped edge (no DOF in the matrices) and a label that names no node are left out, in words."""
    folder, model = plate
    at, kg = str(ccx_plate.node(6, 3, 1)), 0.8
    f, s = ccx_plate.modes(folder, "mass", N_MODES, SENSORS, e_scale=FORM, mass=(at, kg))
    rng = np.random.default_rng(4)
    s = s / np.linalg.norm(s, axis=0) + 0.005 * rng.standard_normal(s.shape)
    clamped = f"{ccx_plate.node(0, 3, 1)}z"
    struck_shapes = np.vstack([s, np.zeros((2, s.shape[1]))])      # the two points that map nowhere
    data = dataclasses.replace(modes_from_arrays(f, s[:10], 0.002 * f),
                               struck_points=tuple(f"{n}{d}" for n, d in SENSORS[10:]) + (clamped, "A7z"),
                               struck_shapes=struck_shapes, struck_shape_std=np.full(f.size, 0.005))
    r = era.explain(data, model.with_sensors(SENSORS[:10]))
    assert r.nominal_model.sensors == tuple(SENSORS)
    assert f"2 struck points ({clamped}, A7z) name no node and direction of the model" in r.message
    assert r.verdict == "explained" and r.effect.name == "point_mass" and r.effect.location == at


def test_on_a_mesh_larger_than_the_screen_the_mass_is_named_at_its_own_node(tmp_path):
    """A cantilever plate of 30 × 20 era.fem shells (630 nodes that move, more than the 400 the first screening
    spreads over it) with 10 % of its mass hidden at a node that screening leaves out, 2.8 cm from every node it
    keeps. The truth is CalculiX's (S8R shells, a MASS element, E 2 % high on the root half and 1 % low on the
    tip half), the noise as above: the second screening, around the best places, finds the node itself."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "fem"))
    from calculix import displacements, frequencies, frequency_inp, node_ids, run
    from plates import grid

    from era.fem import FEMesh, ShellProperty, assemble

    nodes, shells = grid(30, 20, 0.6, 0.4)
    fixed = tuple((n, d) for n, x in nodes.items() if x[0] == 0.0 for d in ("x", "y", "z", "rx", "ry", "rz"))
    steel = ShellProperty(0.004, 210e9, 0.3, 7850.0)
    a = assemble(FEMesh(nodes, shells, shell_properties={"plate": steel}, fixed=fixed))
    sensors = [(f"{i}_{j}", "z") for i in range(5, 31, 5) for j in range(0, 21, 5)]
    model = era.MatrixModel(a.stiffness, a.mass, a.dofs, coordinates=nodes, sensors=sensors)
    at, kg = "19_8", 0.1 * model.total_mass()
    screened = matrix_effects(model)[1]
    assert screened.name == "point_mass" and 400 <= len(screened.locations) < 630 and at not in screened.locations
    halves = tuple(("root" if nodes[c[0]][0] < 0.3 - 1e-9 else "tip", c) for _, c in shells)
    truth = FEMesh(nodes, halves, shell_properties={"root": dataclasses.replace(steel, e=210e9 * FORM[0]),
                                                    "tip": dataclasses.replace(steel, e=210e9 * FORM[1])},
                   masses=((at, kg, (0.0, 0.0, 0.0)),), fixed=fixed)
    dat = run(frequency_inp(truth, N_MODES, printed=tuple(n for n, _ in sensors)), tmp_path)
    ids = node_ids(truth)
    f, s = frequencies(dat), displacements(dat, [(ids[n], d) for n, d in sensors])
    rng = np.random.default_rng(5)
    f = f * (1 + 0.002 * rng.standard_normal(f.size))
    s = s / np.linalg.norm(s, axis=0) + 0.01 * rng.standard_normal(s.shape)
    r = era.explain(modes_from_arrays(f, s, 0.002 * f), model)
    assert r.verdict == "explained" and r.effect.name == "point_mass" and r.effect.location == at
    assert _in_interval(kg, r.effect.size_interval)
    assert "then every node within 0.0283 m of the best of them" in r.effect.description


def test_the_thinned_places_and_the_nodes_near_each_cover_the_whole_mesh():
    """spread: without coordinates every k-th node, the k − 1 on each side near it; with the coordinates of a
    plate of bricks (two layers 1 cm apart), cells over its plane only (the thickness is thinner than a cell),
    both layers' nodes near the kept ones, and every node near at least one kept node."""
    import scipy.sparse

    from era.discrepancy.effects_matrix import spread

    def model(nodes, coordinates=None):
        n = len(nodes)
        k = scipy.sparse.diags([2.0] * n) - scipy.sparse.diags([1.0] * (n - 1), 1) - scipy.sparse.diags(
            [1.0] * (n - 1), -1)
        m = era.MatrixModel(k, scipy.sparse.identity(n), [(x, "z") for x in nodes], coordinates=coordinates)
        return era.discrepancy.MatrixExplainModel.of(m, [(nodes[0], "z"), (nodes[-1], "z")])

    chain = tuple(str(i) for i in range(900))
    places = spread(model(chain), chain)
    assert places.nodes == chain[::3] and places.nearby["3"] == ("4", "2", "5", "1")
    assert "one node in 3 of 900, in the model's order" in places.words
    xyz = {f"{i}_{j}_{k}": (0.02 * i, 0.02 * j, 0.01 * k) for k in (0, 1) for j in range(21) for i in range(31)}
    bricks = tuple(xyz)
    places = spread(model(bricks, xyz), bricks)
    assert 350 <= len(places.nodes) <= 450
    near = set(places.nodes) | {n for v in places.nearby.values() for n in v}
    assert near == set(bricks)
    assert "one per cell of 0.0" in places.words and " m, then every node within " in places.words
