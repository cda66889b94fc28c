"""Starting points for the person (Hankel size, order) and the CMIF drawn under the stabilization diagram."""

import numpy as np
import pytest

import era
import era.examples.paper_cases
from era.core.spectrum import cmif
from era.core.suggest import hankel_size, order_from_singular_values


def test_case_1_gets_the_papers_hankel_size():
    c = hankel_size(200, 1, 1)
    assert (c.rows, c.cols) == (90, 90)


def test_hankel_size_respects_samples_and_the_element_limit():
    c = hankel_size(1280, 9, 6, max_side=800, max_elements=200_000)
    assert c.rows + c.cols <= 1280
    assert c.rows * 9 * c.cols * 6 <= 200_000
    assert c.max_order <= min(c.rows * 9, c.cols * 6)
    with pytest.raises(era.DataError):
        hankel_size(2, 1, 1)


def test_order_from_singular_values_finds_the_rank_of_noise_free_data():
    data = era.examples.paper_cases.case_1()
    ident = era.identify(data, 90, 90)
    assert order_from_singular_values(ident.singular_values, ident.max_order) == 10


def test_order_from_singular_values_with_noise_counts_values_above_the_floor():
    d = np.concatenate([[100, 90, 50, 45, 20, 19], 0.1 * np.linspace(1, 0.5, 60)])
    assert order_from_singular_values(d) == 6
    assert order_from_singular_values(d, max_order=4) == 4
    assert order_from_singular_values(np.zeros(5)) == 1


def test_cmif_peaks_at_the_repeated_pair_with_two_curves():
    data = era.examples.paper_cases.case_2(400, mimo=True)
    f, values = cmif(data)
    assert values.shape == (2, f.size) and f[-1] == pytest.approx(10.0)
    # the second curve peaks at the repeated root too (two independent copies of the pair), far above its floor
    assert abs(f[np.argmax(values[1])] - 1 / (2 * np.pi)) < 2 * (f[1] - f[0])
    assert values[1].max() > 100 * np.median(values[1])
    assert np.all(values[0] >= values[1])
