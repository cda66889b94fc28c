"""FRFs in the other sign convention (e^(-iωt), conjugated) are recognised by their impulse responses running
backwards in time, or declared with frf_sign."""

import numpy as np
import pytest

import era
import uff_files as U
from test_io_uff import chain_accelerance


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    h, f_modes = chain_accelerance(f)
    folder = tmp_path_factory.mktemp("sign")
    for name, values in (("plus.uff", h), ("minus.uff", h.conj())):
        U.write(folder / name, [U.record58(values[:, i, 2], 0.0, 0.01, (i + 1, 3), (3, 3), func_type=4,
                                           denominator=U.FORCE, den_unit="N") for i in range(3)])
    return folder, f_modes


def test_conjugated_frfs_are_detected_and_give_the_same_markov_parameters(both):
    folder, f_modes = both
    plus, minus = era.load(folder / "plus.uff"), era.load(folder / "minus.uff")
    assert not any("conjugated" in c for c in plus.source["conversions"])
    assert "FRFs conjugated: their impulse responses ran backwards in time" in minus.source["conversions"][0]
    np.testing.assert_allclose(minus.data.markov, plus.data.markov, atol=1e-12 * np.abs(plus.data.markov).max())
    model = era.identify(minus.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=2e-3)


def test_the_convention_can_be_declared(both):
    folder, _ = both
    plus = era.load(folder / "plus.uff")
    declared = era.load(folder / "minus.uff", frf_sign="-")
    assert declared.source["conversions"][0] == "FRFs conjugated: the e^(-iωt) sign convention was given (frf_sign='-')"
    np.testing.assert_allclose(declared.data.markov, plus.data.markov, atol=1e-12 * np.abs(plus.data.markov).max())
    kept = era.load(folder / "minus.uff", frf_sign="+")  # taken at its word: the pulse responses come out reversed
    assert not np.allclose(kept.data.markov, plus.data.markov)
    with pytest.raises(era.DataError, match="`frf_sign` must be 'auto', '\\+'"):
        era.load(folder / "plus.uff", frf_sign="negative")
