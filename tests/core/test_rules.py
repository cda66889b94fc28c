"""The rules the app and explain share, each owned once by era/: which modes are kept, one channel of a model,
a pole's place in the stabilization, the one path to a model of an order, the order cap."""

import re

import numpy as np
import pytest

import era
from era.discrepancy import measured_modes
from era.examples.paper_cases import case_2
from era.examples.synthetic import modal_response
from era.core.stabilization import COHERENT_MIN
from era.core.suggest import hankel_size, order_cap


@pytest.fixture(scope="module")
def ident():
    data, _ = modal_response([2.0, 5.5, 5.9, 11.0], [0.01, 0.02, 0.015, 0.005], n_outputs=5, n_inputs=2,
                             n_samples=600, dt=0.02, snr_db=30, seed=3)
    return era.identify(data, rows=40, cols=120)


def test_named_modes_and_thresholds_combine(ident):
    model = ident.model(30)
    by_threshold = era.kept_modes(model, min_emac=0.9, min_mpc=0.9)
    assert 4 <= by_threshold.size < model.n_modes  # the four physical modes, and the noise modes dropped
    named = [0, 1, int(by_threshold[-1])]
    both = era.kept_modes(model, named, min_emac=0.9, min_mpc=0.9)
    np.testing.assert_array_equal(both, np.intersect1d(named, by_threshold))
    np.testing.assert_array_equal(era.kept_modes(model, [-1, 0, 0]), [0, model.n_modes - 1])
    np.testing.assert_array_equal(era.kept_modes(model), np.arange(model.n_modes))
    reduced = model.select(named, min_emac=0.9, min_mpc=0.9)
    np.testing.assert_allclose(reduced.frequency_hz, model.frequency_hz[both])


def test_physical_only_keeps_decaying_pairs():
    z = np.array([0.9 * np.exp(0.3j), 1.05 * np.exp(0.5j), 0.5 + 0j, 0.95 * np.exp(1.0j)])
    # three pairs (one of them growing) and a real pole
    model = era.core.modal.build_model(_real_form(z), np.ones((7, 1)), np.ones((2, 7)), np.ones((7, 1)), 0.01,
                                  np.array([0]), np.array([0]))
    kept = era.kept_modes(model, physical_only=True)
    assert model.n_modes == 4 and kept.size == 2
    assert np.all(model.is_pair[kept]) and np.all(model.damping_ratio[kept] > 0)
    assert model.select(physical_only=True).n_modes == 2


def _real_form(z):
    """Real block-diagonal A with eigenvalues z (pairs for complex entries, 1 × 1 for real ones)."""
    blocks = []
    for zj in z:
        blocks.append(np.array([[zj.real, -zj.imag], [zj.imag, zj.real]]) if zj.imag else np.array([[zj.real]]))
    n = sum(b.shape[0] for b in blocks)
    A, k = np.zeros((n, n)), 0
    for b in blocks:
        A[k:k + b.shape[0], k:k + b.shape[0]] = b
        k += b.shape[0]
    return A


@pytest.mark.parametrize("bad", [{"min_emac": 1.5}, {"min_mpc": -0.1}, {"min_contribution": 2.0}])
def test_thresholds_outside_zero_one_are_refused(ident, bad):
    with pytest.raises(era.EraError, match="fraction in \\[0, 1\\]"):
        era.kept_modes(ident.model(10), **bad)


def test_bad_indices_are_refused(ident):
    model = ident.model(10)
    with pytest.raises(era.EraError, match="out of range"):
        era.kept_modes(model, [model.n_modes])
    with pytest.raises(era.EraError, match="mask needs"):
        era.kept_modes(model, np.ones(model.n_modes + 1, bool))


def test_the_one_channel_view_is_a_consistent_model_that_rebuilds_its_channel(ident):
    model = ident.model(16)
    full = model.reconstruct(ident.data.n_samples)
    for i, j in ((0, 0), (3, 1), (4, 1)):
        ch = model.channel(i, j)
        assert ch.C.shape == (1, ch.order) and ch.B.shape == (ch.order, 1) and ch.shapes.shape[0] == 1
        assert ch.outputs == (model.outputs[i],) and ch.inputs == (model.inputs[j],)
        np.testing.assert_allclose(ch.reconstruct(ident.data.n_samples)[:, 0, 0], full[:, i, j], atol=1e-12)
        # C A^k B of the view: the state-space and the modal sums are the same model
        np.testing.assert_allclose((ch.C @ np.linalg.matrix_power(ch.A, 5) @ ch.B)[0, 0], full[5, i, j], atol=1e-10)
    with pytest.raises(era.EraError, match="`output` must be 0..4"):
        model.channel(5, 0)


def test_a_pole_index_is_its_place_in_the_model_of_its_order(ident):
    stab = era.stabilization(ident, range(4, 41, 4))
    for order in stab.orders:
        model = ident.model(int(order))
        poles = np.flatnonzero(stab.order == order)
        np.testing.assert_array_equal(stab.mode_index[poles], np.arange(model.n_modes))
        np.testing.assert_array_equal(stab.frequency_hz[poles], model.frequency_hz[stab.mode_index[poles]])


def test_one_path_to_the_model_of_an_order(ident):
    a, b = ident.model(20), ident.realize(20)
    for name in ("z", "shapes", "amplitudes", "emac", "mpc", "contribution"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert a.outputs == ident.data.outputs and a.method == "ERA"


def test_suggested_modes_are_coherent_by_one_threshold(ident):
    stab = era.stabilization(ident, range(4, 41, 2))
    flags = [md.coherent for md in stab.modes]
    assert any(flags)
    for md, flag in zip(stab.modes, flags):
        assert flag == (md.emac * md.mpc >= COHERENT_MIN)


def test_the_order_cap():
    assert order_cap(90, 90, 1, 1) == 90 and order_cap(45, 45, 2, 2, 400) == 90 and order_cap(45, 45, 2, 2, 50) == 50
    choice = hankel_size(200, 2, 2, max_order=60)
    assert choice.max_order == order_cap(choice.rows, choice.cols, 2, 2, 60) == 60


def test_explain_reads_exactly_the_modes_kept_at_the_chosen_order():
    data = case_2(200, mimo=True)
    ident = era.identify(data, rows=45, cols=45)
    model = ident.model(10)
    kept = [1, 3]
    mm = measured_modes(ident, range(6, 11, 2), kept=(10, kept))
    np.testing.assert_array_equal(mm.frequency_hz, model.frequency_hz[kept])
    np.testing.assert_array_equal(mm.damping_ratio, model.damping_ratio[kept])
    assert np.all(mm.n_orders >= 1) and mm.shapes.shape == (2, 2)
    with pytest.raises(era.DataError, match="keep at least one mode"):
        measured_modes(ident, range(6, 11, 2), kept=(10, []))


def test_a_kept_pole_that_is_not_a_vibration_mode_is_refused_by_name(ident):
    model = ident.model(40)  # noise at order 40: real or growing computational poles
    odd = np.flatnonzero(~model.is_pair | (model.damping_ratio <= 0))
    assert odd.size
    with pytest.raises(era.DataError, match="not (a )?decaying vibration mode") as err:
        measured_modes(ident, range(30, 41, 2), kept=(40, np.arange(model.n_modes)))
    named = re.findall(r"\d+", str(err.value).split(" at order")[0])  # "Modes 3, 5 and 7", "Mode 3"
    assert {str(int(k)) for k in odd} <= set(named)
