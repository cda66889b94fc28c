"""UFF coordinate systems (18, 2420): node coordinates and measurement directions given in local systems come out
global, as Simcenter Testlab writes them (one displacement system per node); UFF 164 unit factors with the records'
unit exponents give SI values."""

from pathlib import Path

import numpy as np
import pytest

import era
import uff_files as U

DATA = Path(__file__).resolve().parents[1] / "data"
ROT_Z90 = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # local x = global Y, local y = global -X


def nodes(ids, xyz, def_cs, disp_cs):
    d = U.nodes15(ids, xyz)
    d.update(def_cs=np.asarray(def_cs), disp_cs=np.asarray(disp_cs))
    return d


def cs18(labels, origins, x_points, xz_points, refs=None, kinds=None):
    n = len(labels)
    return {"type": 18, "cs_num": list(labels), "cs_type": kinds or [0] * n, "ref_cs_num": refs or [0] * n,
            "color": [8] * n, "method": [1] * n, "cs_name": [f"SYS{k}" for k in labels],
            "ref_o": np.asarray(origins, float), "x_point": np.asarray(x_points, float),
            "xz_point": np.asarray(xz_points, float)}


def cs2420(labels, matrices, kinds=None):
    n = len(labels)
    return {"type": 2420, "Part_UID": 1, "Part_Name": "part", "CS_sys_labels": list(labels),
            "CS_types": kinds or [0] * n, "CS_colors": [8] * n, "CS_names": [f"CS{k}" for k in labels],
            "CS_matrices": [np.asarray(m, float) for m in matrices]}


def decay(n=400):
    t = np.arange(n) * 0.01
    return np.exp(-0.3 * t) * np.sin(2 * np.pi * 4 * t)


def test_local_systems_give_global_coordinates_and_directions(tmp_path):
    sets = [
        cs2420([5], [np.vstack([ROT_Z90, [1.0, 0.0, 0.0]])]),  # rotated 90° about Z, origin at x = 1
        cs18([7, 8], origins=[[0, 0, 0], [0, 0, 0]], x_points=[[-1, 0, 0], [1, 0, 0]],
             xz_points=[[-1, 0, -1], [1, 0, 1]], kinds=[0, 1]),  # 7: x = -X, z = -Z (Testlab's skew); 8: cylinder
        nodes([1, 2, 3], [[0.5, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 90.0, 0.3]], def_cs=[0, 5, 8], disp_cs=[7, 5, 8]),
        U.record58(decay(), 0.0, 0.01, (1, 3)), U.record58(decay(), 0.0, 0.01, (2, 1)),
        U.record58(decay(), 0.0, 0.01, (3, 1)), U.record58(decay(), 0.0, 0.01, (3, -2)),
    ]
    U.write(tmp_path / "local.uff", sets)
    g = era.load(tmp_path / "local.uff", kind="decay").geometry
    # node 2: (2, 0, 0) in system 5 = origin + 2 × (local x = global Y); node 3: r = 2, θ = 90°, z = 0.3
    np.testing.assert_allclose(g.coordinates, [[0.5, 0, 0], [1, 2, 0], [0, 2, 0.3]], atol=1e-12)
    # +Z of node 1 is -Z; +X of node 2 is +Y; at node 3 (θ = 90°) +r is +Y and -θ is +X
    np.testing.assert_allclose(g.channel_directions, [[0, 0, -1], [0, 1, 0], [0, 1, 0], [1, 0, 0]], atol=1e-12)
    ds = era.load(tmp_path / "local.uff", kind="decay")
    assert any("turned into global X/Y/Z" in r for r in ds.source["records"])


def test_the_testlab_file_keeps_its_global_coordinates_with_36_node_systems():
    ds = era.load(DATA / "testlab_geometry_15_82.uff")  # def_cs 0, one displacement system per node (UFF 18)
    assert ds.geometry.n_nodes == 36


def test_undefined_or_spherical_systems_name_the_node(tmp_path):
    U.write(tmp_path / "missing.uff", [nodes([1, 2], [[0, 0, 0], [1, 0, 0]], [0, 0], [0, 9]),
                                       U.record58(decay(), 0.0, 0.01, (2, 3))])
    with pytest.raises(era.DataError, match=r"missing.uff: node 2 gives its measurement directions in coordinate "
                                            r"system 9, which no data set 18 or 2420"):
        era.load(tmp_path / "missing.uff")
    U.write(tmp_path / "sphere.uff", [cs2420([4], [np.vstack([np.eye(3), np.zeros(3)])], kinds=[2]),
                                      nodes([1], [[1, 0, 0]], [4], [0]), U.record58(decay(), 0.0, 0.01, (1, 3))])
    with pytest.raises(era.DataError, match=r"sphere.uff: node 1 uses spherical coordinate system 4"):
        era.load(tmp_path / "sphere.uff")
    U.write(tmp_path / "flat.uff", [cs18([3], [[0, 0, 0]], [[1, 0, 0]], [[2, 0, 0]]), nodes([1], [[0, 0, 0]], [3], [0]),
                                    U.record58(decay(), 0.0, 0.01, (1, 3))])
    with pytest.raises(era.DataError, match=r"flat.uff: data set #1 \(UFF 18, line \d+\), system 3: its defining "
                                            r"points coincide or lie on one line"):
        era.load(tmp_path / "flat.uff")


def test_unit_exponents_with_the_files_unit_factors_give_si_values(tmp_path):
    """A file in mm (UFF 164 length factor 1000): accelerance in mm/s²/N and node coordinates in mm come out in SI."""
    import pyuff

    f = np.arange(0, 20.0, 0.05)
    h = (f / 5) ** 2 / (1 - (f / 5) ** 2 + 0.02j * f / 5)

    def frf(scale, unit):
        rec = U.record58(h * scale, 0.0, 0.05, (1, 3), (1, 3), func_type=4, denominator=U.FORCE, den_unit="N",
                         unit=unit)
        rec.update(ordinate_len_unit_exp=1, orddenom_force_unit_exp=1)  # (length / s²) / force
        return rec

    units_mm = pyuff.prepare_164(units_code=5, units_description="mm", temp_mode=1, length=1000.0, force=1.0,
                                 temp=1.0, temp_offset=273.15)
    U.write(tmp_path / "si.uff", [U.nodes15([1], [[0.5, 0, 0]]), frf(1.0, "m/s^2")])
    U.write(tmp_path / "mm.uff", [units_mm, U.nodes15([1], [[500.0, 0, 0]]), frf(1000.0, "mm/s^2")])
    si, mm = era.load(tmp_path / "si.uff"), era.load(tmp_path / "mm.uff")
    np.testing.assert_allclose(mm.data.markov, si.data.markov, rtol=1e-5, atol=1e-9 * np.abs(si.data.markov).max())
    assert mm.data.output_units == ("m/s^2/N",) and "converted to SI" in " ".join(mm.source["records"])
    np.testing.assert_allclose(mm.geometry.coordinates, [[0.5, 0, 0]])


def test_finite_element_modes_in_mm_and_local_systems_come_out_in_m_along_global_axes(tmp_path):
    """UFF 55 shapes written in mm (UFF 164) at a node whose displacement system is turned 90° about Z (UFF 2420):
    era.read_modes_uff gives them in m along global X/Y/Z, as the test's channels are."""
    import pyuff

    units_mm = pyuff.prepare_164(units_code=5, units_description="mm", temp_mode=1, length=1000.0, force=1.0,
                                 temp=1.0, temp_offset=273.15)
    local = np.array([[2.0, 0.0, 1.0], [0.0, 0.0, 3.0]])  # mm, at nodes 1 and 2, in their own systems
    mode = pyuff.prepare_55(id1="FE mode 1", id2="NONE", id3="NONE", id4="NONE", id5="NONE", model_type=1,
                            analysis_type=2, data_ch=2, spec_data_type=8, data_type=2, n_data_per_node=3,
                            r1=local[:, 0], r2=local[:, 1], r3=local[:, 2], node_nums=[1, 2], load_case=1,
                            mode_n=1, freq=12.5, modal_m=1.0, modal_damp_vis=0.0, modal_damp_his=0.0)
    sets = [units_mm, cs2420([5], [np.vstack([ROT_Z90, [0.0, 0.0, 0.0]])]),
            nodes([1, 2], [[0.0, 0.0, 0.0], [1000.0, 0.0, 0.0]], def_cs=[0, 0], disp_cs=[5, 0]), mode]
    U.write(tmp_path / "fe.uff", sets)
    fe = era.read_modes_uff(tmp_path / "fe.uff")
    assert fe.frequency_hz.tolist() == [12.5] and fe.node_ids.tolist() == [1, 2]
    # node 1: local x (2 mm) is global +Y, local z (1 mm) is +Z; node 2 is in the global system already
    np.testing.assert_allclose(fe.shapes[:, :, 0].real, [[0.0, 0.002, 0.001], [0.0, 0.0, 0.003]], atol=1e-15)
