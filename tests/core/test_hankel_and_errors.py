"""Eq. 16 with arbitrary shifts, and the errors a user gets for bad input."""

import numpy as np
import pytest

import era
from era.core.hankel import block_hankel, shifts
from era.examples.paper_cases import case_1, case_1_eigenvalues, case_2


def test_block_hankel_follows_eq_16_with_arbitrary_shifts():
    y = np.random.default_rng(0).standard_normal((40, 2, 3))
    js, ts = np.array([0, 2, 7]), np.array([0, 1, 5, 6])
    h1 = block_hankel(y, js, ts, k=1)
    assert h1.shape == (3 * 2, 4 * 3) and h1.flags.c_contiguous
    for i, j in enumerate(js):
        for c, t in enumerate(ts):
            np.testing.assert_array_equal(h1[2 * i:2 * i + 2, 3 * c:3 * c + 3], y[1 + j + t])


def test_sparse_shifts_identify_case_1_exactly_with_a_smaller_hankel():
    row = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 20, 40, 60]
    col = [2, 4, 6, 8, 10, 12, 14, 16, 18, 30, 50, 70, 90]
    ident = era.identify(case_1(), rows=15, cols=14, row_shifts=row, col_shifts=col)
    assert ident.order() == 10
    model = ident.realize(10)
    np.testing.assert_allclose(np.sort_complex(model.eigenvalues), np.sort_complex(case_1_eigenvalues()), rtol=1e-6)
    np.testing.assert_allclose(model.emac, 1.0, atol=1e-6)  # the ideal history uses these t_i


def test_default_shifts_are_consecutive():
    np.testing.assert_array_equal(shifts(4, None, "row_shifts"), [0, 1, 2, 3])
    np.testing.assert_array_equal(shifts(3, [2, 5], "row_shifts"), [0, 2, 5])


@pytest.mark.parametrize("kwargs, message", [
    (dict(rows=90, cols=90, row_shifts=[1, 2]), "89 are needed"),
    (dict(rows=3, cols=3, row_shifts=[2, 2]), "strictly increasing"),
    (dict(rows=3, cols=3, col_shifts=[1, 0.5]), "integers"),
    (dict(rows=0, cols=3), "`rows` must be a positive integer"),
    (dict(rows=3, cols=2.5), "`cols` must be a positive integer"),
    (dict(rows=150, cols=90), r"need 240 samples .* the data have 200.*rows \+ cols may be at most 200"),
])
def test_bad_hankel_parameters_are_refused_with_a_clear_message(kwargs, message):
    with pytest.raises(era.HankelError, match=message):
        era.identify(case_1(), **kwargs)


def test_too_large_a_hankel_is_refused_with_what_fits(monkeypatch):
    monkeypatch.setattr(era.core.hankel, "MAX_HANKEL_ELEMENTS", 1000)
    with pytest.raises(era.HankelError, match="90 × 90 .* below it"):
        era.identify(case_1(), rows=90, cols=90)


def test_order_errors_name_the_rank():
    ident = era.identify(case_1(), rows=90, cols=90)
    with pytest.raises(era.OrderError, match="numerical rank of H\\(0\\), 10"):
        ident.realize(12)
    with pytest.raises(era.OrderError, match="at least 1"):
        ident.realize(0)
    with pytest.raises(era.OrderError, match="positive integer"):
        ident.realize(2.5)
    with pytest.raises(era.EraError, match="'ERA', 'A1' or 'A2'"):
        ident.realize(4, method="A3")


@pytest.mark.parametrize("markov, dt, message", [
    (np.array([1.0, np.nan, 2.0]), 0.1, "1 NaN or infinite value, the first at sample 1"),
    (np.ones((5, 2, 2)) * np.inf, 0.1, "20 NaN"),
    (np.ones((5, 2, 2, 2)), 0.1, "4 dimensions"),
    (np.ones((0, 2, 2)), 0.1, "every axis"),
    (np.ones(5) * 1j, 0.1, "complex"),
    (np.ones(5), 0.0, "positive, finite"),
    (np.ones(5), "fast", "number of seconds"),
    (np.array(["a", "b"]), 0.1, "numeric"),
])
def test_bad_data_is_refused_with_a_clear_message(markov, dt, message):
    with pytest.raises(era.DataError, match=message):
        era.ResponseData(markov, dt)


def test_labels_must_match_the_channels_and_errors_are_value_errors():
    with pytest.raises(era.DataError, match="3 output labels were given for 2 outputs"):
        era.ResponseData(np.ones((10, 2, 1)), 0.1, outputs=["a", "b", "c"])
    assert issubclass(era.EraError, ValueError)
    with pytest.raises(era.EraError, match="era.ResponseData"):
        era.identify(np.ones((10, 1, 1)), rows=2, cols=2)


def test_response_data_is_an_immutable_copy():
    y = np.ones((10, 2, 1))
    data = era.ResponseData(y, 0.1)
    y[0] = 5
    assert data.markov[0, 0, 0] == 1
    with pytest.raises(ValueError):
        data.markov[0, 0, 0] = 3
    assert (data.n_samples, data.n_outputs, data.n_inputs) == (10, 2, 1)
    assert data.outputs == ("y1", "y2") and data.inputs == ("u1",)
    assert case_2().outputs == ("sensor 1", "sensor 2")
