"""Loading a ~100 MB UFF file: era.load's time against pyuff's own parse of the same file, in the same process.

Run: python3 -m pytest tests/bench/bench_load.py -s
The files are written with pyuff into a temporary folder (a minute or so: pyuff writes 58b one value at a time).
Reported, for era.io.uff.read_uff (pyuff + our checks and assembly into outputs × references) and for era.load
(all that + the conversion to Markov parameters): the total time and, within the same call, the time spent
inside pyuff (UFF() and read_sets); the ratio total / pyuff is our overhead. Times are CPU seconds of this process
(time.process_time, BLAS pinned to one thread): wall time on the shared 2-core machine swings 3x with other jobs.
"""

import time

import numpy as np
import pytest
import pyuff

import era
import era.io.hdf5
import era.io.lvm
import era.io.mat
import era.io.npy
import era.io.signalcalc
import era.io.tdms
from era.io.uff import read_uff

ROUNDS = 3


def _write(path, sets):
    path.unlink(missing_ok=True)
    pyuff.UFF(str(path)).write_sets(sets, mode="add")  # "add" to a new file: "overwrite" breaks 58b headers


def _record(data, dx, rsp, ref, func_type, binary):
    return {"type": 58, "binary": binary, "func_type": func_type, "rsp_node": rsp, "rsp_dir": 3, "ref_node": ref,
            "ref_dir": 3, "data": data, "x": dx * np.arange(len(data)), "abscissa_spacing": 1,
            "abscissa_spec_data_type": 18 if func_type == 4 else 17, "ordinate_spec_data_type": 12,
            "ordinate_axis_units_lab": "m/s^2", "orddenom_spec_data_type": 13 if func_type == 4 else 0,
            "orddenom_axis_units_lab": "N" if func_type == 4 else "NONE"}


def ambient_58b(path):
    """8 channels × 1.6 M samples of noise-driven response, UFF 58b binary doubles: 102 MB."""
    rng = np.random.default_rng(0)
    n, dt = 1_600_000, 1 / 2048
    t = np.arange(n) * dt
    base = np.sin(2 * np.pi * 12.3 * t) + 0.5 * np.sin(2 * np.pi * 31.7 * t)
    _write(path, [_record(base * (k + 1) + rng.standard_normal(n), dt, k + 1, 0, 1, 1) for k in range(8)])
    return {"kind": "ambient", "references": [0, 1], "n_lags": 1024}


def frf_ascii(path):
    """1 accelerometer × 48 hammer points × 50 001 lines of complex accelerance, UFF 58 ASCII: 98 MB."""
    f = np.arange(50_001) * 0.02
    sets = []
    for k in range(48):
        w = f / (50 + 10 * k)
        sets.append(_record(w ** 2 / (1 - w ** 2 + 0.01j * w), 0.02, 1, k + 1, 4, 0))
    _write(path, sets)
    return {"kind": "frf", "band_hz": (5.0, 1000.0)}


class PyuffClock:
    """Adds up the time spent inside pyuff (UFF() with its file scan, read_sets) while era reads a file, so the
    ratio total / pyuff comes from the same call and is not blurred by load on a shared machine."""

    def __init__(self, monkeypatch):
        self.seconds = 0.0
        for name in ("__init__", "read_sets"):
            original = getattr(pyuff.UFF, name)
            monkeypatch.setattr(pyuff.UFF, name, self._timed(original))

    def _timed(self, fn):
        def wrapper(*args, **kwargs):
            t0 = time.process_time()
            try:
                return fn(*args, **kwargs)
            finally:
                self.seconds += time.process_time() - t0
        return wrapper


@pytest.mark.parametrize("make", [ambient_58b, frf_ascii], ids=["58b binary time records", "58 ASCII FRFs"])
def test_loading_a_100_mb_uff_is_dominated_by_pyuff_parsing(tmp_path, make, monkeypatch):
    path = tmp_path / "big.uff"
    options = make(path)
    size_mb = path.stat().st_size / 1e6
    path.read_bytes()  # warm the page cache so no timing below pays for the disk
    clock = PyuffClock(monkeypatch)
    rows = []
    for _ in range(ROUNDS):
        for what, fn in (("read_uff", lambda: read_uff(str(path), path.name)),
                         ("era.load", lambda: era.load(path, **options))):
            clock.seconds = 0.0
            t0 = time.process_time()
            fn()
            total = time.process_time() - t0
            rows.append((what, total, clock.seconds))
    ds = era.load(path, **options)
    best = {w: min((r for r in rows if r[0] == w), key=lambda r: r[1] / r[2]) for w in ("read_uff", "era.load")}
    (_, t_read, p_read), (_, t_load, p_load) = best["read_uff"], best["era.load"]
    print(f"\n[{make.__name__}] {size_mb:.0f} MB, markov {ds.data.markov.shape}: "
          f"read_uff {t_read:.2f} s of which pyuff {p_read:.2f} s -> {t_read / p_read:.3f}x pyuff | "
          f"era.load with the {options['kind']} conversion {t_load:.2f} s of which pyuff {p_load:.2f} s -> "
          f"{t_load / p_load:.3f}x pyuff")
    assert t_read / p_read < 1.25, "our checks and assembly must stay a small fraction of pyuff's parse"
    assert t_load / p_load < 1.5, "the conversion must not outweigh the parse"


# --- every other format: era's reader against the library (or numpy parse) that reads the same bytes ----------------
# A file of each format is written here; for text formats the reference is numpy's own parse of the same data block
# (np.loadtxt), for binary ones the library's read of the arrays (np.load, scipy.io.loadmat, h5py, npTDMS). era's
# reader is given what era.load gives it: the path for .npy/HDF5/TDMS, the bytes for text and MAT (scipy reads
# MAT from memory so that a lying size field cannot make it reserve memory). The ratio is era's reader / the
# reference, the best of ROUNDS in CPU seconds.

def _best(fn) -> float:
    times = []
    for _ in range(ROUNDS):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return min(times)


def lvm_file(path):
    """8 channels × 400 000 samples at 2048 Hz, LabVIEW's tab-separated layout with one X column: ~45 MB."""
    n, dt = 400_000, 1 / 2048
    y = np.random.default_rng(1).standard_normal((n, 8))
    head = ("LabVIEW Measurement\t\nWriter_Version\t2\nReader_Version\t2\nSeparator\tTab\nDecimal_Separator\t.\n"
            "Multi_Headings\tYes\nX_Columns\tOne\nTime_Pref\tRelative\n***End_of_Header***\t\n\t\nChannels\t8\n"
            f"Samples{chr(9) * 1}{chr(9).join(['400000'] * 8)}\nY_Unit_Label\t{chr(9).join(['g'] * 8)}\n"
            f"X_Dimension\t{chr(9).join(['Time'] * 8)}\nX0\t{chr(9).join(['0.0'] * 8)}\n"
            f"Delta_X\t{chr(9).join([f'{dt:.6f}'] * 8)}\n***End_of_Header***\n"
            "X_Value\t" + "\t".join(f"ch{k}" for k in range(8)) + "\tComment\n")
    with open(path, "w") as fh:
        fh.write(head)
        np.savetxt(fh, np.column_stack([np.arange(n) * dt, y]), fmt="%.6f", delimiter="\t")
    skip = head.count("\n")
    return (lambda: era.io.lvm.read_lvm(path.read_bytes(), path.name),
            lambda: np.loadtxt(path, skiprows=skip, delimiter="\t"))


def text_file(path):
    """A bare matrix, 3 channels in rows × 1 000 000 samples (the Carini layout at a larger size): ~75 MB."""
    np.savetxt(path, np.random.default_rng(2).standard_normal((3, 1_000_000)), fmt="%.18e")
    return (lambda: era.load(path, dt=1 / 25, kind="ambient", n_lags=8).source,  # NExT of 8 lags: ~nothing
            lambda: np.loadtxt(path))


_BIG = (2_000_000, 8)  # samples × channels of the binary files: 128 MB of doubles


def _big():
    return np.random.default_rng(3).standard_normal(_BIG)


def npy_file(path):
    np.save(path, _big())
    return lambda: era.io.npy.read_npy(str(path), path.name, dt=1e-3), lambda: np.load(path)


def mat_file(path):
    import scipy.io
    scipy.io.savemat(path, {"acc": _big(), "fs": 1000.0})
    return (lambda: era.io.mat.read_mat(path.read_bytes(), path.name),
            lambda: scipy.io.loadmat(path, variable_names=["acc", "fs"]))


def hdf5_file(path):
    import h5py
    with h5py.File(path, "w") as f:
        f["acc"] = _big()
        f.attrs["fs"] = 1000.0

    def reference():
        with h5py.File(path, "r") as f:
            return f["acc"][()]
    return lambda: era.io.hdf5.read_hdf5(str(path), path.name), reference


def tdms_file(path):
    from nptdms import ChannelObject, GroupObject, TdmsFile, TdmsWriter
    y = _big()
    with TdmsWriter(str(path)) as w:
        w.write_segment([GroupObject("Run")] + [ChannelObject("Run", f"a{k}", y[:, k],
                                                              properties={"wf_increment": 1e-3})
                                               for k in range(y.shape[1])])
    return lambda: era.io.tdms.read_tdms(str(path), path.name), lambda: TdmsFile.read(str(path))


def signalcalc_file(path):
    """A SignalCalc-style FRF export of 1 000 001 lines (0-1000 Hz every mHz): ~48 MB."""
    f = np.arange(1_000_001) * 1e-3
    h = (f / 300) ** 2 / (1 - (f / 300) ** 2 + 0.02j * f / 300)
    head = ("Units: Ratio\r\nRef Chan:Resp Chan\t1-Z:2-Z\r\nChannel Name\t : \r\nChannel Comment\t : \r\n\r\n"
            "Frequency\t Real\t Imaginary\r\n\r\nUnits:\r\nHz\t(m/s2)(N)\t \r\n")
    with open(path, "w", newline="") as fh:
        fh.write(head)
        np.savetxt(fh, np.column_stack([f, h.real, h.imag]), fmt=["%.13e", "%16.7g", "%16.7g"], delimiter="\t",
                   newline="\r\n")
    return (lambda: era.io.signalcalc.read_signalcalc([path.read_bytes()], [path.name]),
            lambda: np.loadtxt(path, skiprows=9, delimiter="\t"))


@pytest.mark.parametrize("make", [lvm_file, text_file, npy_file, mat_file, hdf5_file, tdms_file, signalcalc_file],
                         ids=["LabVIEW LVM", "headerless text (rows)", "npy", "MATLAB v5", "HDF5", "TDMS",
                              "SignalCalc FRF"])
def test_each_format_reads_close_to_its_library(tmp_path, make):
    path = tmp_path / f"big.{make.__name__.split('_')[0]}"
    ours, reference = make(path)
    path.read_bytes()  # warm the page cache
    t_ours, t_ref = _best(ours), _best(reference)
    print(f"\n[{make.__name__}] {path.stat().st_size / 1e6:.0f} MB: era {t_ours:.2f} s, reference {t_ref:.2f} s -> "
          f"{t_ours / t_ref:.2f}x")
    assert t_ours / t_ref < 2.5, "checks and assembly must stay within the cost of the parse itself"
