"""Issue 26: UFF 58 reference node and direction place the inputs. A roving-hammer test of a 3-mass chain (one
accelerometer on mass 1, the hammer on masses 1, 2, 3, one hit from the -Z side) gives the shape at the three
masses, the chain's own mode shapes, with the hit's direction undone."""

import sys
from pathlib import Path

import numpy as np

import era

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
import uff_files as U  # noqa: E402
from chain_sim import continuous_chain  # noqa: E402


def test_uff_references_place_the_hammer_and_the_point_shapes_are_the_chains_modes(tmp_path):
    a, b, f_modes, _ = continuous_chain()
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    h = np.stack([np.linalg.solve(x * np.eye(6) - a, b)[:3] * x ** 2 for x in 2j * np.pi * f])  # accelerance
    nodes = U.nodes15([1, 2, 3], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
    paths = []
    for hit, sense in ((1, 3), (2, -3), (3, 3)):  # the hit on mass 2 from the other side: its FRF changes sign
        paths.append(tmp_path / f"hit{hit}.uff")
        U.write(paths[-1], [nodes, U.record58(np.sign(sense) * h[:, 0, hit - 1], 0.0, 0.01, (1, 3), (hit, sense),
                                              func_type=4, denominator=U.FORCE, den_unit="N")])
    ds = era.load(paths, band_hz=(2, 40))
    assert ds.data.meta["input_points"] == ("1Z", "2Z", "3Z") and ds.data.meta["input_signs"] == (1.0, -1.0, 1.0)
    assert ds.data.meta["output_points"] == ("1Z",)
    model = era.analyse(ds.data).model
    np.testing.assert_allclose(model.frequency_hz, f_modes, rtol=2e-3)
    assert model.points == ("1Z", "2Z", "3Z")
    k = 1e4 * np.array([[2, -1, 0], [-1, 2, -1], [0, -1, 1.0]])
    truth = np.linalg.eigh(k)[1]  # unit masses: the stiffness matrix's eigenvectors, ascending frequency
    for j in range(3):
        assert era.mac(model.point_shapes[:, j:j + 1], truth[:, j:j + 1].astype(complex))[0, 0] > 0.999
    # through the stored format the points survive (the web app keeps its datasets as NPZ)
    back = era.load(era.io.npz_bytes(ds.data, ds.geometry), name="chain.npz")
    assert back.data.meta["input_signs"] == (1.0, -1.0, 1.0)
    placed = era.core.points.point_geometry(back.geometry, model.points)
    assert placed.channel_nodes.tolist() == [0, 1, 2]
