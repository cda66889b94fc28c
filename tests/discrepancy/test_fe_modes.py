"""Test modes against another program's FE modes (UFF 55, issue 9 item 3): pairing, MAC, COMAC, the gap, and the
plain statement that nothing is named without a model era can change."""

import numpy as np
import pyuff
import pytest

import era
from era.discrepancy import modes_from_arrays
from era.discrepancy.fe_modes import NOT_UPDATABLE, compare_fe_modes
from era.examples.frames import cantilever


def _write_fe_modes(path, frame, n):
    """The frame's modes as a FE program exports them: UFF 55 normal modes (analysis type 2), x y z per node."""
    f, u = frame.node_modes(n)
    uff = pyuff.UFF(str(path))
    for k in range(n):
        uff.write_sets(pyuff.prepare_55(
            id1="FE", model_type=1, analysis_type=2, data_ch=2, spec_data_type=12, data_type=2, n_data_per_node=3,
            r1=u[:, 0, k], r2=u[:, 1, k], r3=u[:, 2, k], load_case=1, mode_n=k + 1, freq=f[k], modal_m=1.0,
            modal_damp_vis=0.0, modal_damp_his=0.0, node_nums=np.array([int(i) for i in frame.node_ids])),
            mode="add" if k else "overwrite")


def test_fe_modes_from_uff55_pair_with_the_test_and_name_nothing(tmp_path):
    fe_frame = cantilever()                                  # the FE program's model: nominal
    _write_fe_modes(tmp_path / "fe.unv", fe_frame, 8)
    fe = era.read_modes_uff(tmp_path / "fe.unv")
    truth = cantilever(masses={"4": 0.1})                    # the test: a 100 g tip mass the FE model lacks
    f, s = truth.modes(4)
    c = compare_fe_modes(modes_from_arrays(f, s), fe, truth.sensors)
    assert c.pairing.n_pairs == 4 and 0.9 < c.gap.min_mac < 1.0   # the tip mass bends the shapes too
    assert c.gap.max_abs_freq_error_pct == pytest.approx(np.max(np.abs(fe.frequency_hz[c.pairing.model_index]
                                                                        / f - 1)) * 100, rel=1e-6)
    assert c.gap.max_abs_freq_error_pct > 2 and c.comac.shape == (5,)
    assert NOT_UPDATABLE in c.message and c.table[0]["fe_mode"] == 1
