"""Several files as one dataset: a roving-hammer test exported as one UFF file per hit, shaker references in
separate files, time files as several initial conditions; files that do not belong together are named."""

import io
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.io
from nptdms import ChannelObject, GroupObject, TdmsWriter

import era
import uff_files as U

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import continuous_chain, hammer_decay  # noqa: E402

F = np.arange(0, 50.0 + 1e-9, 0.01)
NODES = U.nodes15([1, 2, 3], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])


def accelerance():
    a, b, f_modes, _ = continuous_chain()
    w = 2j * np.pi * F
    return np.stack([np.linalg.solve(x * np.eye(6) - a, b)[:3] * x ** 2 for x in w]), f_modes


def frf(h, rsp, ref, **kw):
    return U.record58(h, 0.0, kw.pop("df", 0.01), (rsp, 3), (ref, 3), func_type=4, denominator=U.FORCE,
                      den_unit="N", **kw)


@pytest.fixture(scope="module")
def roving(tmp_path_factory):
    """Accelerometer at node 1, the hammer at nodes 1, 2, 3: one file per hit, each with the geometry."""
    h, f_modes = accelerance()
    folder = tmp_path_factory.mktemp("roving")
    paths = []
    for hit in (1, 2, 3):
        paths.append(folder / f"hit{hit}.uff")
        U.write(paths[-1], [NODES, frf(h[:, 0, hit - 1], 1, hit)])
    return paths, h, f_modes


def test_a_roving_hammer_test_in_three_uff_files_is_one_dataset(roving):
    paths, _, f_modes = roving
    ds = era.load(list(reversed(paths)))  # the order of the files does not matter: the references are sorted out
    assert ds.source["kind"] == "frf" and ds.data.markov.shape[1:] == (1, 3)
    assert set(ds.data.inputs) == {"ref 1+Z", "ref 2+Z", "ref 3+Z"} and ds.data.outputs == ("1+Z",)
    assert ds.source["file"] == ["hit3.uff", "hit2.uff", "hit1.uff"]
    assert ds.source["records"][0] == "3 UFF files read as one test: hit3.uff, hit2.uff, hit1.uff"
    assert ds.geometry.node_ids.tolist() == [1, 2, 3] and ds.geometry.channel_nodes.tolist() == [0]
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=2e-3)
    uploads = era.load([io.BytesIO(p.read_bytes()) for p in paths])  # uploads: bytes without names
    np.testing.assert_allclose(uploads.data.markov, era.load(paths).data.markov)


def test_shaker_references_in_separate_files_become_columns(tmp_path):
    h, f_modes = accelerance()
    for ref in (1, 3):
        U.write(tmp_path / f"ref{ref}.uff", [frf(h[:, i, ref - 1], i + 1, ref) for i in range(3)])
    ds = era.load([tmp_path / "ref1.uff", tmp_path / "ref3.uff"])
    assert ds.data.markov.shape[1:] == (3, 2) and ds.data.inputs == ("ref 1+Z", "ref 3+Z")
    model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=2e-3)


def test_files_that_do_not_belong_together_are_named(tmp_path, roving):
    paths, h, _ = roving
    cases = {
        "step.uff": ([frf(h[:, 0, 1], 1, 2, df=0.02)], r"step.uff: data set #1 .*sampling step 0.02 .* but "
                                                         r"hit1.uff: data set #2 .* has step 0.01"),
        "short.uff": ([frf(h[:4000, 0, 1], 1, 2)], r"short.uff: data set #1 .*4000 samples, but hit1.uff: data set #2 "
                                                   r".* has 5001"),
        "units.uff": ([dict(frf(h[:, 0, 1], 1, 2), ordinate_axis_units_lab="g")],
                      r"units.uff: data set #1 .*units g/N but hit1.uff: data set #2 .* has m/s\^2/N"),
        "again.uff": ([frf(h[:, 0, 0], 1, 1)], r"again.uff: data set #1 .*a second record for response 1\+Z and "
                                               r"reference 1\+Z \(the first is hit1.uff: data set #2"),
        "moved.uff": ([U.nodes15([1, 2, 3], [[0, 0, 0], [1, 0, 0], [2.5, 0, 0]]), frf(h[:, 0, 1], 1, 2)],
                      r"moved.uff: node 3 at \[2.5, 0.0, 0.0\] but hit1.uff puts it at \[2.0, 0.0, 0.0\]"),
    }
    for name, (sets, message) in cases.items():
        U.write(tmp_path / name, sets)
        with pytest.raises(era.DataError, match=message):
            era.load([paths[0], tmp_path / name])
    (tmp_path / "run.csv").write_text("t,a\n" + "".join(f"{k * 0.01:.2f},{np.sin(k)}\n" for k in range(100)))
    with pytest.raises(era.DataError, match="run.csv is CSV but hit1.uff is UFF"):
        era.load([paths[0], tmp_path / "run.csv"])


def decays(hits, n=1500, dt=0.01):
    runs = [hammer_decay(n, hit, dt) for hit in hits]
    return [y for y, _ in runs], runs[0][1]


def test_uff_mat_tdms_and_csv_time_files_are_initial_conditions(tmp_path):
    (y1, y2), f_modes = decays((2, 0))
    for k, y in enumerate((y1, y2)):
        U.write(tmp_path / f"hit{k}.uff", [NODES] + [U.record58(y[:, i], 0.0, 0.01, (i + 1, 3)) for i in range(3)])
        scipy.io.savemat(tmp_path / f"hit{k}.mat", {"acc": y, "fs": 100.0})
        with TdmsWriter(str(tmp_path / f"hit{k}.tdms")) as w:
            w.write_segment([GroupObject("Run")] + [ChannelObject("Run", f"a{i}", y[:, i],
                                                                  properties={"wf_increment": 0.01})
                                                    for i in range(3)])
    for ext in ("uff", "mat", "tdms"):
        ds = era.load([tmp_path / f"hit0.{ext}", tmp_path / f"hit1.{ext}"], kind="decay")
        assert ds.data.markov.shape[2] == 2, ext
        model = era.identify(ds.data, rows=30, cols=30).realize(order=6)
        np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-5)
    assert era.load([tmp_path / "hit0.uff", tmp_path / "hit1.uff"]).geometry.channel_nodes.tolist() == [0, 1, 2]
    scipy.io.savemat(tmp_path / "short.mat", {"acc": y1[:1000], "fs": 100.0})
    with pytest.raises(era.DataError, match=r"short.mat: records of \[1000\] samples but hit0.mat has 1500"):
        era.load([tmp_path / "hit0.mat", tmp_path / "short.mat"])
    scipy.io.savemat(tmp_path / "slow.mat", {"acc": y1, "fs": 50.0})
    with pytest.raises(era.DataError, match=r"slow.mat: sampled every 0.02 s but hit0.mat every 0.01 s"):
        era.load([tmp_path / "hit0.mat", tmp_path / "slow.mat"])
    t = np.arange(len(y1)) * 0.01
    for name, unit in (("a.csv", "g"), ("b.csv", "m/s^2")):
        (tmp_path / name).write_text(f"time,a1 ({unit}),a2 ({unit}),a3 ({unit})\n" +
                                     "".join(f"{ti:.2f},{r[0]},{r[1]},{r[2]}\n" for ti, r in zip(t, y1)))
    with pytest.raises(era.DataError, match=r"b.csv: units \['m/s\^2', 'm/s\^2', 'm/s\^2'\] but a.csv has \['g'"):
        era.load([tmp_path / "a.csv", tmp_path / "b.csv"])
