"""Bad files get an era.DataError that names the file, record or line and says what is wrong. Every case writes a
real malformed file."""

import io
import zipfile

import numpy as np
import pytest

import era
import uff_files as U


def frf_sets(n=2001, df=0.05, lengths=None, steps=None):
    f = np.arange(n) * df
    h = 1 / (1 - (f / 20) ** 2 + 0.02j * f / 20)
    sets = []
    for i in range(2):
        m = lengths[i] if lengths else n
        d = steps[i] if steps else df
        sets.append(U.record58(h[:m], 0.0, d, (i + 1, 3), (1, 3), func_type=4, denominator=U.FORCE, den_unit="N"))
    return sets


@pytest.fixture
def good_uff(tmp_path):
    path = tmp_path / "good.uff"
    U.write(path, frf_sets())
    assert era.load(path).data.markov.shape == (1999, 2, 1)
    return path


def test_empty_and_blank_files(tmp_path):
    (tmp_path / "empty.uff").write_bytes(b"")
    (tmp_path / "blank.csv").write_text("\n  \n")
    for name in ("empty.uff", "blank.csv"):
        with pytest.raises(era.DataError, match=f"{name}: the file is empty"):
            era.load(tmp_path / name)


def test_binary_garbage(tmp_path):
    junk = np.random.default_rng(0).integers(0, 256, 5000, dtype=np.uint8).tobytes()
    (tmp_path / "junk.bin").write_bytes(junk)
    with pytest.raises(era.DataError, match="junk.bin: binary content"):
        era.load(tmp_path / "junk.bin")
    (tmp_path / "junk.uff").write_bytes(junk.replace(b"    -1", b"xxxxxx"))
    with pytest.raises(era.DataError, match="junk.uff: no UFF data sets"):
        era.load(tmp_path / "junk.uff")
    with pytest.raises(era.DataError, match="not a readable .npz"):
        era.load(b"PK\x03\x04" + junk, name="junk.npz")


def test_truncated_uff(good_uff, tmp_path):
    raw = good_uff.read_bytes()
    (tmp_path / "cut.uff").write_bytes(raw[: int(len(raw) * 0.7)])
    with pytest.raises(era.DataError, match="cut.uff: the file does not end .* cut short"):
        era.load(tmp_path / "cut.uff")


def test_corrupt_values_in_a_uff_record_name_the_set_and_line(good_uff, tmp_path):
    lines = good_uff.read_text().splitlines(True)
    second = [k for k, ln in enumerate(lines) if ln.rstrip() == "    58"][1]  # the second 58 record's type line
    lines[second + 20] = "   garbage!" + lines[second + 20][11:]
    (tmp_path / "corrupt.uff").write_text("".join(lines))
    with pytest.raises(era.DataError,
                       match=rf"corrupt.uff: data set #2 \(UFF 58\) starting at line {second} is corrupt"):
        era.load(tmp_path / "corrupt.uff")


def test_header_promising_more_values_than_the_record_holds(good_uff, tmp_path):
    text = good_uff.read_text()
    # record 7 field 2 (10 columns): the number of values, 2001 -> 999999999
    patched = text.replace("         6      2001", "         6 999999999", 1)
    assert patched != text
    (tmp_path / "liar.uff").write_text(patched)
    with pytest.raises(era.DataError, match=r"data set #1 \(UFF 58, line 1\): the header promises 999999999 values "
                                            r"but the record holds 2001"):
        era.load(tmp_path / "liar.uff")


def test_nan_in_a_uff_record(good_uff, tmp_path):
    lines = good_uff.read_text().splitlines(True)
    lines[30] = f"{'NaN':>20}" + lines[30][20:]
    (tmp_path / "nan.uff").write_text("".join(lines))
    with pytest.raises(era.DataError, match=r"nan.uff: data set #1 \(UFF 58, line 1\): 1 NaN or infinite"):
        era.load(tmp_path / "nan.uff")


def test_records_of_different_lengths_or_steps(tmp_path):
    U.write(tmp_path / "len.uff", frf_sets(lengths=[2001, 1500]))
    with pytest.raises(era.DataError, match=r"data set #2 .*1500 samples, but data set #1 has 2001"):
        era.load(tmp_path / "len.uff")
    U.write(tmp_path / "step.uff", frf_sets(steps=[0.05, 0.1]))
    with pytest.raises(era.DataError, match=r"data set #2 .*sampling step 0.1 .* data set #1 has step 0.05"):
        era.load(tmp_path / "step.uff")


def test_uneven_abscissa_in_uff(tmp_path):
    rec = U.record58(np.sin(np.arange(100.0)), 0.0, 0.01, (1, 3))
    rec["x"] = np.cumsum(np.r_[0, np.full(99, 0.01)])
    rec["x"][60:] += 0.004
    rec["abscissa_spacing"] = 0
    U.write(tmp_path / "uneven.uff", [rec])
    with pytest.raises(era.DataError, match=r"uneven.uff: data set #1 .*not evenly spaced \(step 0.014 after value 59"):
        era.load(tmp_path / "uneven.uff")


def test_incomplete_output_by_reference_matrix(tmp_path):
    sets = frf_sets()
    extra = dict(sets[0], ref_node=2)  # response 1 to reference 2 but no response 2 to reference 2
    U.write(tmp_path / "holes.uff", sets + [extra])
    with pytest.raises(era.DataError, match=r"no record for response 2\+Z and reference 2\+Z"):
        era.load(tmp_path / "holes.uff")


def test_csv_problems_name_the_line(tmp_path):
    good = ["time,a,b"] + [f"{k * 0.01:.2f},{np.sin(k):.5f},{np.cos(k):.5f}" for k in range(200)]
    cases = {
        "ragged.csv": (lambda L: L[:50] + ["0.49,1.0"] + L[51:], r"ragged.csv, line 51: 2 values where the file has 3"),
        "word.csv": (lambda L: L[:70] + ["0.69,abc,1.0"] + L[71:],
                     r"word.csv, line 71, column 2: 'abc' is not a number"),
        "nan.csv": (lambda L: L[:90] + ["0.89,nan,1.0"] + L[91:], r"nan.csv, line 91, column 2: NaN or infinite"),
        "inf.csv": (lambda L: L[:90] + ["0.89,1.0,-inf"] + L[91:], r"inf.csv, line 91, column 3: NaN or infinite"),
        "gap.csv": (lambda L: L[:120] + L[125:],
                    r"gap.csv, line 121: the time step is 0.06 s where the typical step is 0.01"),
        "short.csv": (lambda L: L[:6], r"5 samples; at least 8"),
    }
    for name, (edit, message) in cases.items():
        (tmp_path / name).write_text("\n".join(edit(good)) + "\n")
        with pytest.raises(era.DataError, match=message):
            era.load(tmp_path / name, kind="ambient")


def test_npz_problems(tmp_path):
    buf = io.BytesIO()
    np.savez(buf, markov=np.ones((100, 2, 1)), dt=np.array(0.1))
    raw = buf.getvalue()
    with pytest.raises(era.DataError, match="cut.npz: not a readable .npz"):
        era.load(raw[: len(raw) // 2], name="cut.npz")
    # a header promising 10^9 doubles (8 GB) over 800 bytes: refused before anything is allocated
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (10 ** 9,)})
    with zipfile.ZipFile(tmp_path / "liar.npz", "w") as zf:
        zf.writestr("markov.npy", header.getvalue() + np.ones(100).tobytes())
        zf.writestr("dt.npy", _npy(np.array(0.1)))
    with pytest.raises(era.DataError, match=r"liar.npz: array 'markov.npy': the header promises shape \(1000000000,\)"):
        era.load(tmp_path / "liar.npz")
    with zipfile.ZipFile(tmp_path / "pickle.npz", "w") as zf:
        zf.writestr("markov.npy", _npy(np.array([{"a": 1}], dtype=object)))
        zf.writestr("dt.npy", _npy(np.array(0.1)))
    with pytest.raises(era.DataError, match="Python objects"):
        era.load(tmp_path / "pickle.npz")
    buf = io.BytesIO()
    np.savez(buf, markov=np.ones((100, 2, 1)))
    with pytest.raises(era.DataError, match="no 'dt' array"):
        era.load(buf.getvalue(), name="nodt.npz")


def _npy(arr):
    b = io.BytesIO()
    np.save(b, arr, allow_pickle=True)
    return b.getvalue()
