"""UFF in: 58/58b function records into outputs × references, 15/82 into a Geometry, 55 modes both ways."""

import sys
from pathlib import Path

import numpy as np
import pytest

import era
import uff_files as U

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import chain, continuous_chain, simulate  # noqa: E402
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "data"
SHARED = SHARED_DATASETS


def chain_accelerance(f):
    a, b, f_modes, _ = continuous_chain()
    w = 2j * np.pi * f
    return np.stack([np.linalg.solve(x * np.eye(6) - a, b)[:3] * x ** 2 for x in w]), f_modes


GEOMETRY_SETS = [U.nodes15([1, 2, 3, 9], [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]), U.trace82([1, 2, 3, 9])]


@pytest.fixture(scope="module")
def frf_file(tmp_path_factory):
    """A roving-accelerometer test: responses at nodes 1, 2, 3 (+Z), reference hammer at node 3 (+Z)."""
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    h, f_modes = chain_accelerance(f)
    sets = list(GEOMETRY_SETS) + [U.record58(h[:, i, 2], 0.0, 0.01, (i + 1, 3), (3, 3), func_type=4,
                                             denominator=U.FORCE, den_unit="N") for i in range(3)]
    path = tmp_path_factory.mktemp("uff") / "chain_frf.uff"
    U.write(path, sets)
    return path, f_modes


def test_frf_records_become_markov_parameters_with_geometry_and_units(frf_file):
    path, f_modes = frf_file
    ds = era.load(path)
    assert ds.source["format"] == "uff" and ds.source["kind"] == "frf"
    assert ds.data.markov.shape == (4999, 3, 1) and ds.data.dt == pytest.approx(0.01)
    assert ds.data.outputs == ("1+Z", "2+Z", "3+Z") and ds.data.inputs == ("ref 3+Z",)
    assert ds.data.output_units == ("m/s^2/N",) * 3 and ds.data.input_units == ("N",)
    assert "accelerance" in ds.source["records"][0]
    g = ds.geometry
    assert g.node_ids.tolist() == [1, 2, 3, 9] and g.edges.tolist() == [[0, 1], [1, 2], [2, 3]]
    assert g.channel_nodes.tolist() == [0, 1, 2] and np.allclose(g.channel_directions, [[0, 0, 1]] * 3)
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=2e-3)


def test_an_upload_is_read_from_bytes_with_its_original_name(frf_file):
    path, _ = frf_file
    with open(path, "rb") as fh:
        ds = era.load(fh, name="my test.uff", band_hz=(2.0, 40.0))
    assert ds.source["file"] == "my test.uff"
    assert ds.data.dt == pytest.approx(1 / 80)
    assert any("band 2-40 Hz" in c for c in ds.source["conversions"])


def test_binary_58b_shaker_records_with_a_force_channel_go_through_okid(tmp_path):
    ad, bd, cd, dd, f_modes, _ = chain(0.005)
    force = np.random.default_rng(0).standard_normal((4000, 1))
    acc = simulate(ad, bd[:, 2:], cd, dd[:, 2:], force)
    sets = [U.record58(force[:, 0], 0.0, 0.005, (3, 3), ordinate=U.FORCE, unit="N", binary=1)]
    sets += [U.record58(acc[:, i], 0.0, 0.005, (i + 1, 3), binary=1) for i in range(3)]
    U.write(tmp_path / "shaker.uff", sets)
    ds = era.load(tmp_path / "shaker.uff", n_observer=10)
    assert ds.source["kind"] == "io"
    assert ds.data.inputs == ("3+Z",) and ds.data.input_units == ("N",) and ds.data.outputs == ("1+Z", "2+Z", "3+Z (2)")
    model = era.identify(ds.data, rows=20, cols=20).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-6)


def test_impulse_responses_with_pretrigger_start_at_the_sample_after_time_zero(tmp_path):
    ad, bd, cd, dd, _, _ = chain(0.01)
    exact = np.stack([cd @ np.linalg.matrix_power(ad, k) @ bd[:, :1] for k in range(300)])  # Y_1.. = C A^k B
    pulse = np.concatenate([np.zeros((20, 3, 1)), dd[None, :, :1], exact])  # 20 pre-trigger samples, Y_0 = D
    sets = [U.record58(pulse[:, i, 0], -0.2, 0.01, (i + 1, 3), (1, 3), denominator=U.FORCE, den_unit="N")
            for i in range(3)]
    U.write(tmp_path / "irf.uff", sets)
    ds = era.load(tmp_path / "irf.uff")
    assert ds.source["kind"] == "pulse"
    np.testing.assert_allclose(ds.data.markov, exact, rtol=1e-9, atol=1e-11 * np.abs(exact).max())


def test_real_testlab_and_artemis_geometry_files():
    ds = era.load(DATA / "testlab_geometry_15_82.uff")
    assert ds.data is None and ds.modes is None
    g = ds.geometry
    assert g.n_nodes == 36
    # trace lines 'Massif' (7 segments), 'Stator' (16), 'Dalle' (7) from their node sequences, 0 = pen up
    assert g.edges.shape == (30, 2)
    pairs = {tuple(sorted(g.node_ids[e].tolist())) for e in g.edges}
    assert {(2, 5), (7, 19), (32, 33)} <= pairs and (18, 30) in pairs and (0, 30) not in pairs
    art = era.load(DATA / "artemis_geometry_RPBC.uff").geometry
    assert art.n_nodes == 74
    extent = art.coordinates.max(axis=0) - art.coordinates.min(axis=0)
    np.testing.assert_allclose(extent, [9.856, 3.84, 2.04], atol=1e-9)  # x -4.24..5.616, y 0..3.84, z 0..2.04 m


def test_real_58b_operational_records_are_read_as_ambient_response():
    ds = era.load(DATA / "mpstd_first_8192.uff", n_lags=512)
    assert ds.source["kind"] == "ambient"
    assert ds.data.dt == pytest.approx(1 / 3200)
    assert ds.data.outputs == ("1+Z", "2+Z", "3+Z", "1+Z (2)") and ds.data.output_units == ("m/s2",) * 4
    assert ds.data.markov.shape == (512, 4, 4)
    assert "4 channels × 1 record of 8192 samples, Δt = 0.0003125 s (3200 Hz)" in ds.source["records"][0]


def test_full_mpstd_file_from_shared():
    path = SHARED / "pyuff_samples" / "MPSTD_Set001_2024_10_08.uff"
    require_shared(path)
    ds = era.load(path, references=[0], n_lags=1024)
    assert ds.data.markov.shape == (1024, 4, 1)
    assert "4 channels × 1 record of 222400 samples" in ds.source["records"][0]
    assert ds.data.dt == pytest.approx(1 / 3200)
    assert np.all(ds.data.meta["zero_lag"][:, 0] != 0)


def test_modes_written_as_uff55_read_back_with_their_geometry(tmp_path, frf_file):
    path, f_modes = frf_file
    ds = era.load(path)
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    out = tmp_path / "modes.uff"
    era.save_modes_uff(out, model, ds.geometry)
    modes = era.read_modes_uff(out)
    np.testing.assert_allclose(modes.frequency_hz, model.natural_frequency_hz, rtol=1e-5)
    np.testing.assert_allclose(modes.damping_ratio, model.damping_ratio, rtol=1e-4)
    # channel i measures node i+1 in +Z: the shape's z column at those nodes is the identified shape
    np.testing.assert_allclose(modes.shapes[:3, 2, :], model.shapes, rtol=1e-4, atol=1e-6)
    assert np.all(modes.shapes[3] == 0) and np.all(modes.shapes[:, :2] == 0)
    back = era.load(out)
    assert back.data is None and back.geometry.edges.tolist() == [[0, 1], [1, 2], [2, 3]]
    assert back.modes.node_ids.tolist() == [1, 2, 3, 9]


def test_universal_2411_nodes_and_content_sniffing_without_a_file_name(tmp_path):
    import pyuff
    nodes = pyuff.prepare_2411(node_nums=np.array([10, 20]), def_cs=np.array([1, 1]), disp_cs=np.array([1, 1]),
                               color=np.array([1, 1]), x=np.array([0.0, 0.5]), y=np.zeros(2), z=np.zeros(2))
    t = np.arange(2000) * 0.01
    decay = np.exp(-0.3 * t) * np.sin(2 * np.pi * 4 * t)
    sets = [nodes, U.record58(decay, 0.0, 0.01, (20, -2), name="tip -Y")]
    U.write(tmp_path / "model.unv", sets)
    ds = era.load((tmp_path / "model.unv").read_bytes(), name="upload")  # no extension: sniffed from '    -1'
    assert ds.source["format"] == "uff" and ds.source["kind"] == "decay"
    assert ds.data.outputs == ("tip -Y",)
    assert ds.geometry.node_ids.tolist() == [10, 20] and ds.geometry.channel_nodes.tolist() == [1]
    np.testing.assert_array_equal(ds.geometry.channel_directions, [[0, -1, 0]])
    model = era.identify(ds.data, rows=20, cols=20).realize(order=2)
    assert model.frequency_hz[0] == pytest.approx(4.0, rel=1e-6)  # damped frequency of the record
    assert model.damping_ratio[0] == pytest.approx(0.3 / np.hypot(0.3, 2 * np.pi * 4), rel=1e-5)


def test_normal_modes_of_a_finite_element_program_and_spectra_that_are_not_used(tmp_path):
    import pyuff
    shape = np.array([0.5, 1.0, -0.25])
    fe = [pyuff.prepare_55(model_type=1, id1="FE mode 1", id2="NONE", id3="NONE", id4="NONE", id5="NONE",
                           analysis_type=2, data_ch=2, spec_data_type=8, data_type=2, n_data_per_node=3,
                           r1=np.zeros(3), r2=np.zeros(3), r3=shape * k, node_nums=[1, 2, 3], load_case=1,
                           mode_n=k, modal_m=1.0, freq=10.0 * k, modal_damp_vis=0.01, modal_damp_his=0.0)
          for k in (1, 2)]
    U.write(tmp_path / "fe.uff", fe)
    modes = era.read_modes_uff(tmp_path / "fe.uff")
    assert modes.names == ("FE mode 1", "FE mode 1") and modes.node_ids.tolist() == [1, 2, 3]
    np.testing.assert_allclose(modes.frequency_hz, [10.0, 20.0])
    np.testing.assert_allclose(modes.damping_ratio, [0.01, 0.01])
    np.testing.assert_allclose(modes.shapes[:, 2, 1].real, 2 * shape, rtol=1e-6)
    with pytest.raises(era.DataError, match="no UFF 55 mode shapes"):
        era.read_modes_uff(DATA / "testlab_geometry_15_82.uff")
    # an FRF export with a coherence record alongside: the coherence is noted and left out
    f = np.arange(0, 20.0, 0.05)
    frf = U.record58(1 / (1 - (f / 5) ** 2 + 0.02j * f / 5), 0.0, 0.05, (1, 3), (1, 3), func_type=4,
                     denominator=U.FORCE, den_unit="N")
    coherence = dict(U.record58(np.ones(f.size), 0.0, 0.05, (1, 3), (1, 3), func_type=6), abscissa_spec_data_type=18)
    U.write(tmp_path / "with_coherence.uff", [frf, coherence])
    ds = era.load(tmp_path / "with_coherence.uff")
    assert ds.data.markov.shape == (398, 1, 1)
    assert "1 other UFF 58 record (spectra, coherence, ...) not used" in ds.source["records"]


def test_uff55_id_lines_carry_sigma_and_the_shape_scatter_and_read_back(tmp_path):
    """ID line 3: std of f and ζ; line 4: expected 1 - MAC and where σ came from (era.io.uff_write)."""
    from era.examples.synthetic import modal_response
    import pyuff

    from era.io.uff_write import read_uncertainty_lines

    data, _ = modal_response([2.0, 3.3], [0.02, 0.03], 3, 2, 300, 0.05, snr_db=30, seed=4)
    ident = era.identify(data, 20, 40)
    model = ident.model(4)
    scatter = ident.shape_scatter(4)
    out = tmp_path / "modes.uff"
    era.save_modes_uff(out, model, shape_scatter=scatter)
    sets = [s for s in pyuff.UFF(str(out)).read_sets() if s["type"] == 55]
    assert len(sets) == model.n_modes == 2
    for k, s in enumerate(sets):
        back = read_uncertainty_lines(s["id3"], s["id4"])
        np.testing.assert_allclose(back["frequency_std_hz"], model.frequency_std_hz[k], rtol=1e-3)
        np.testing.assert_allclose(back["damping_std"], model.damping_std[k], rtol=1e-3)
        np.testing.assert_allclose(back["shape_scatter"], scatter[k], rtol=1e-3)
        assert back["source"] == "sigma from one record's residuals"
    era.save_modes_uff(out, ident.model(4, uncertainty=False))  # nothing known: the lines stay NONE
    plain = [s for s in pyuff.UFF(str(out)).read_sets() if s["type"] == 55]
    assert all(read_uncertainty_lines(s["id3"], s["id4"]) == {"frequency_std_hz": None, "damping_std": None,
                                                              "shape_scatter": None, "source": ""} for s in plain)
