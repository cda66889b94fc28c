"""era.load(max_bytes=): what compressed files inflate to is measured before it is inflated (the size the file
declares) and while it is (in bounded chunks), over all the files of one load; nothing changes without it."""

import io
import zipfile
import zlib

import h5py
import numpy as np
import pytest
import scipy.io

import era
from era.io.inflate import Budget

MB = 1 << 20


def npz(markov: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.savez_compressed(buf, markov=markov, dt=np.array(0.01))
    return buf.getvalue()


def h5(n: int, seed: int) -> bytes:
    buf = io.BytesIO()
    with h5py.File(buf, "w") as f:
        f.create_dataset("acc", data=np.random.default_rng(seed).normal(size=n), compression="gzip")
        f.attrs["fs"] = 100.0
    return buf.getvalue()


def test_an_npz_member_declaring_more_than_the_limit_is_refused_naming_it():
    blob = npz(np.zeros((400_000, 2, 2)))  # 12.2 MB of zeros, a few kB on the wire
    assert len(blob) < 100_000
    with pytest.raises(era.TooLargeError, match=r"markov.npy' inflates to 12.2 MB .* limit of 4.0 MB"):
        era.load(blob, name="zeros.npz", max_bytes=4 * MB)
    assert era.load(blob, name="zeros.npz").data.markov.shape == (400_000, 2, 2)  # the library's default: no limit


def test_a_compressed_matlab_v5_variable_is_measured_as_it_inflates():
    buf = io.BytesIO()
    scipy.io.savemat(buf, {"acc": np.zeros(2_000_000), "fs": 100.0}, do_compression=True)
    with pytest.raises(era.TooLargeError, match=r"compressed variables inflate to more than 4.0 MB"):
        era.load(buf.getvalue(), name="zeros.mat", max_bytes=4 * MB)
    assert era.load(buf.getvalue(), name="zeros.mat", max_bytes=32 * MB, kind="decay") is not None


def test_the_files_of_one_load_share_the_limit():
    files = [h5(100_000, 1), h5(100_000, 2)]  # 0.8 MB uncompressed each
    ds = era.load([io.BytesIO(b) for b in files], max_bytes=int(1.7 * MB), kind="decay")
    assert ds.data.markov.shape[0] > 0
    with pytest.raises(era.TooLargeError, match="already read"):
        era.load([io.BytesIO(b) for b in files], max_bytes=int(1.2 * MB), kind="decay")


def test_the_budget_reads_in_bounded_chunks_and_stops_at_the_limit():
    raw = io.BytesIO()
    with zipfile.ZipFile(raw, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("a", bytes(3 * MB))
    with zipfile.ZipFile(raw) as zf, zf.open("a") as fh:
        assert len(Budget(4 * MB).read(fh, 3 * MB, "a")) == 3 * MB
        with pytest.raises(era.TooLargeError):
            Budget(2 * MB).read(fh, 3 * MB, "a")  # claimed before a byte is inflated
    with pytest.raises(era.TooLargeError, match="more than 1.0 MB"):
        Budget(MB).inflate_size(zlib.compress(bytes(64 * MB)), "zeros")
    assert Budget(None).inflate_size(zlib.compress(bytes(3 * MB)), "zeros") == 3 * MB
