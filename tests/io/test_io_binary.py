"""Binary arrays in: .npy, MATLAB v5 (scipy.io) and v7.3 (HDF5), plain HDF5 and NI TDMS, each written here by the
library that writes it in the field; the data and the sampling found by name, ambiguity named with the way to
choose; lying, cut and hostile files refused before anything is allocated."""

import io
import struct
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.io
from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

import era

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import hammer_decay  # noqa: E402

DT = 0.01


def decay(n=1500, hit=2):
    return hammer_decay(n, hit, DT)


def modes_of(ds, f_modes):
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)


def npy_bytes(a):
    buf = io.BytesIO()
    np.save(buf, a)
    return buf.getvalue()


def test_npy_needs_dt_and_reads_either_orientation():
    y, f_modes = decay()
    with pytest.raises(era.DataError, match=r"^no sampling interval in acc.npy: give the sample rate \(dt=\.\.\.\)"):
        era.load(npy_bytes(y), name="acc.npy")
    ds = era.load(npy_bytes(y.T), name="acc.npy", dt=DT)  # 3 × N: channels in rows, from the shape
    assert ds.source["format"] == "npy" and ds.data.outputs == ("acc:1", "acc:2", "acc:3")
    modes_of(ds, f_modes)
    with pytest.raises(era.DataError, match="Record 1 has 3 samples"):
        era.load(npy_bytes(y.T), name="acc.npy", dt=DT, orientation="columns")


def test_mat_v5_finds_fs_or_a_time_vector_and_names_the_ambiguity():
    y, f_modes = decay()
    buf = io.BytesIO()
    scipy.io.savemat(buf, {"acc": y, "fs": 1 / DT, "hammer": np.zeros(len(y)), "info": "beam test"})
    raw = buf.getvalue()
    with pytest.raises(era.DataError, match=r"test.mat: several arrays could be the data: 'acc' 1500×3, 'hammer' "
                                            r"1500; choose with variable='acc'"):
        era.load(raw, name="test.mat")
    ds = era.load(raw, name="test.mat", variable="acc")
    assert ds.source["format"] == "mat" and ds.data.dt == pytest.approx(DT)
    assert "Δt = 0.01 s (100 Hz) from fs 'fs'" in ds.source["records"][0]
    modes_of(ds, f_modes)
    buf = io.BytesIO()
    scipy.io.savemat(buf, {"y": y.T, "t": np.arange(len(y)) * DT}, do_compression=True)
    ds = era.load(buf.getvalue(), name="compressed.mat")
    assert "from time vector 't'" in ds.source["records"][0]
    modes_of(ds, f_modes)
    buf = io.BytesIO()
    scipy.io.savemat(buf, {"y": y, "t": np.arange(len(y)) * DT, "fs": 50.0})
    with pytest.raises(era.DataError, match=r"liar.mat: time vector 't' gives a sampling interval of 0.01 s but fs "
                                            r"'fs' 0.02 s"):
        era.load(buf.getvalue(), name="liar.mat")
    with pytest.raises(era.DataError, match=r"test.mat: no array named 'acc2'; the file holds 'acc' 1500×3"):
        era.load(raw, name="test.mat", variable="acc2")


def matlab_v73(path, variables: dict, struct: dict | None = None):
    """A MATLAB 7.3 file as MATLAB writes it: a 512-byte user block with the text header, column-major HDF5
    datasets with a MATLAB_class attribute; ``struct`` fields go into a group."""
    with h5py.File(path, "w", userblock_size=512) as f:
        for name, value in variables.items():
            f[name] = np.atleast_2d(np.asarray(value, dtype=float)).T  # MATLAB's column-major order
            f[name].attrs["MATLAB_class"] = np.bytes_("double")
        if struct:
            g = f.create_group("data")
            g.attrs["MATLAB_class"] = np.bytes_("struct")
            for name, value in struct.items():
                g[name] = np.atleast_2d(np.asarray(value, dtype=float)).T
                g[name].attrs["MATLAB_class"] = np.bytes_("double")
    with open(path, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Nov 23 19:00:00 2026 HDF5 schema 1.00 .")


def test_mat_v73_through_h5py_with_a_struct(tmp_path):
    y, f_modes = decay()
    matlab_v73(tmp_path / "v73.mat", {}, struct={"acc": y, "fs": [[1 / DT]]})
    ds = era.load(tmp_path / "v73.mat")
    assert ds.source["format"] == "mat" and "MATLAB .mat (v7.3)" in ds.source["records"][0]
    assert ds.data.outputs == ("data/acc:1", "data/acc:2", "data/acc:3")
    modes_of(ds, f_modes)


def test_plain_hdf5_in_the_documented_layout(tmp_path):
    y, f_modes = decay()
    with h5py.File(tmp_path / "run.h5", "w") as f:
        f.attrs["fs"] = 1 / DT
        d = f.create_dataset("acc", data=y, compression="gzip")
        d.attrs["units"] = "m/s^2"
        d.attrs["channels"] = np.array([b"a1", b"a2", b"a3"])
    ds = era.load(tmp_path / "run.h5")
    assert ds.source["format"] == "hdf5" and ds.data.outputs == ("a1", "a2", "a3")
    assert ds.data.output_units == ("m/s^2",) * 3 and "from fs attribute 'fs'" in ds.source["records"][0]
    modes_of(ds, f_modes)
    with h5py.File(tmp_path / "split.h5", "w") as f:  # one 1-D dataset per channel and a time vector
        g = f.create_group("test 1")
        for i in range(3):
            g[f"ch{i}"] = y[:, i]
        g["time"] = np.arange(len(y)) * DT
    ds = era.load((tmp_path / "split.h5").read_bytes(), name="upload")  # no extension: the magic bytes say HDF5
    assert ds.data.outputs == ("test 1/ch0", "test 1/ch1", "test 1/ch2")
    modes_of(ds, f_modes)


def tdms_bytes(groups: dict, increment=DT):
    buf = io.BytesIO()
    with TdmsWriter(buf) as w:
        objects = [RootObject(properties={"title": "hammer test"})]
        for group, channels in groups.items():
            objects.append(GroupObject(group))
            objects += [ChannelObject(group, name, data, properties={"wf_increment": increment, "unit_string": "g"})
                        for name, data in channels.items()]
        w.write_segment(objects)
    return buf.getvalue()


def test_tdms_groups_are_records_or_chosen(tmp_path):
    (y1, f_modes), (y2, _) = decay(hit=2), decay(hit=0)
    raw = tdms_bytes({"Hit 1": {f"a{i}": y1[:, i] for i in range(3)}, "Hit 2": {f"a{i}": y2[:, i] for i in range(3)}})
    ds = era.load(raw, name="hits.tdms")
    assert ds.source["format"] == "tdms" and ds.data.markov.shape[2] == 2
    assert ds.data.output_units == ("g",) * 3 and "wf_increment" in ds.source["records"][0]
    modes_of(ds, f_modes)
    mixed = tdms_bytes({"Hit 1": {f"a{i}": y1[:, i] for i in range(3)}, "Setup": {"temperature": np.ones(20)}})
    with pytest.raises(era.DataError, match=r"mixed.tdms: groups with different channels .* choose one with "
                                            r"group='Hit 1'"):
        era.load(mixed, name="mixed.tdms")
    ds = era.load(mixed, name="mixed.tdms", group="Hit 1")
    assert ds.data.markov.shape[2] == 1
    with pytest.raises(era.DataError, match="`group` applies to TDMS files, not to MAT"):
        era.load(b"MATLAB 5.0 MAT-file" + bytes(200), name="x.mat", group="Hit 1")


def test_hostile_binary_files_are_refused_before_allocating(tmp_path):
    y, _ = decay(300)
    # .npy: a header promising 10^12 doubles (8 TB) over 2.4 kB
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (10 ** 12,)})
    with pytest.raises(era.DataError, match=r"huge.npy: array: the header promises shape \(1000000000000,\)"):
        era.load(b"\x93NUMPY" + header.getvalue()[6:] + y.tobytes(), name="huge.npy", dt=DT)
    good = npy_bytes(y)
    with pytest.raises(era.DataError, match="cut.npy: array: the header promises shape"):
        era.load(good[:-100], name="cut.npy", dt=DT)
    with pytest.raises(era.DataError, match="objects.npy: the array holds Python objects"):
        buf = io.BytesIO()
        np.save(buf, np.array([{"a": 1}], dtype=object), allow_pickle=True)
        era.load(buf.getvalue(), name="objects.npy", dt=DT)
    # HDF5: a chunked dataset of 10^12 values of which nothing was ever written
    with h5py.File(tmp_path / "empty.h5", "w") as f:
        f.create_dataset("acc", shape=(10 ** 12,), dtype="f8", chunks=(1024,))
        f.attrs["fs"] = 100.0
    with pytest.raises(era.DataError, match=r"empty.h5: dataset 'acc': the header promises shape \(1000000000000,\)"):
        era.load(tmp_path / "empty.h5")
    with h5py.File(tmp_path / "external.h5", "w") as f:  # raw data in another file of the server
        f.create_dataset("acc", shape=(1000,), dtype="f8", external=[("/etc/hostname", 0, 8000)])
        f.attrs["fs"] = 100.0
    with pytest.raises(era.DataError, match="external.h5: dataset 'acc' refers to data in other files"):
        era.load(tmp_path / "external.h5")
    with h5py.File(tmp_path / "types.h5", "w") as f:  # wrong types: a rate in words, names where numbers belong
        f["acc"] = y
        f.attrs["fs"] = "fast"
        f["labels"] = np.array([b"a", b"b"])
    with pytest.raises(era.DataError, match=r"types.h5: `fs` must be one number"):
        era.load(tmp_path / "types.h5")
    with h5py.File(tmp_path / "words.h5", "w") as f:
        f["labels"] = np.array([b"a"] * 50)
    with pytest.raises(era.DataError, match=r"words.h5: no numeric array of at least 8 samples; the file holds "
                                            r"'labels' 50"):
        era.load(tmp_path / "words.h5", dt=0.01)
    with h5py.File(tmp_path / "ok.h5", "w") as f:
        f["acc"] = y
        f.attrs["fs"] = 100.0
    raw = (tmp_path / "ok.h5").read_bytes()
    with pytest.raises(era.DataError, match="cut.h5"):
        era.load(raw[: len(raw) // 2], name="cut.h5")
    # MAT: a matrix header claiming 10^5 × 10^5 doubles (80 GB) over a few kB, refused before loadmat reads it
    buf = io.BytesIO()
    scipy.io.savemat(buf, {"acc": y, "fs": 100.0})
    liar = buf.getvalue().replace(struct.pack("<ii", *y.shape), struct.pack("<ii", 100_000, 100_000), 1)
    with pytest.raises(era.DataError, match=r"liar.mat: variable 'acc': the header promises shape \(100000, 100000\)"):
        era.load(liar, name="liar.mat")
    # MAT: cut, garbage after the header
    buf = io.BytesIO()
    scipy.io.savemat(buf, {"acc": y, "fs": 100.0}, do_compression=True)
    raw = buf.getvalue()
    for name, blob in (("cut.mat", raw[: len(raw) // 2]), ("junk.mat", raw[:128] + bytes(range(256)) * 8)):
        with pytest.raises(era.DataError, match=name):
            era.load(blob, name=name)
    # TDMS: cut in the data, garbage after the lead-in tag
    raw = tdms_bytes({"Run": {"a": y[:, 0]}})
    for name, blob in (("cut.tdms", raw[: len(raw) - 1000]), ("junk.tdms", b"TDSm" + bytes(range(256)) * 4)):
        with pytest.raises(era.DataError, match=name):
            era.load(blob, name=name)
