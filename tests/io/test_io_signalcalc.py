"""DataPhysics SignalCalc ASCII FRF exports: the real ModeLAB roving-hammer beam (GPL, read from ../shared, never
copied) reaches its published modes; files written here in the same layout cover magnitude/phase, channel pairs
assembled into a matrix, and malformed exports."""


import numpy as np
import pytest

import era
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

MODELAB = SHARED_DATASETS / "modelab_beam_frf" / "SignalCalc"
PUBLISHED_HZ = [111.99, 306.86, 596.37, 974.14]  # the repository's modeshapes.png


def test_the_modelab_beam_in_nine_files_gives_the_published_modes():
    require_shared(MODELAB)
    paths = [MODELAB / f"ASCII0000{k}" / f"Hxysv0000{k}.txt" for k in range(1, 10)]
    one = era.load(paths[0], band_hz=(65.0, 1000.0))
    assert one.source["format"] == "signalcalc" and one.data.markov.shape[1:] == (1, 1)
    ds = era.load(paths, band_hz=(65.0, 1000.0), n_samples=3000)  # setup.csv: fMin 65 Hz, fMax 1000 Hz
    assert ds.source["kind"] == "frf" and ds.data.markov.shape == (3000, 1, 9) and ds.data.dt == pytest.approx(5e-4)
    assert ds.data.inputs[0] == "Hxysv00001:0-Z" and ds.data.output_units == ("m/s²/N",)
    assert "the files are the references" in ds.source["records"][0]
    assert "m/s²/N (accelerance)" in ds.source["records"][0]
    model = era.identify(ds.data, rows=300, cols=60).realize(order=20)
    strongest = np.argsort(model.contribution)[-4:]
    np.testing.assert_allclose(np.sort(model.frequency_hz[strongest]), PUBLISHED_HZ, rtol=5e-4)
    assert np.all(model.emac[strongest] > 0.99) and np.all(model.damping_ratio[strongest] < 0.01)


F = np.arange(0, 50.0 + 1e-9, 0.0625)


def export(h, pair="1-Z:2-Z", columns=("Real", "Imaginary"), unit="(m/s²)(N)", f=F):
    """A SignalCalc-style ASCII export of one FRF (cp1252, CR LF), written from scratch here."""
    head = ["Units: Ratio", f"Ref Chan:Resp Chan\t{pair}", "Channel Name\t : ", "Channel Comment\t : ", "",
            f"Frequency\t {columns[0]}\t {columns[1]}", "", "Units:", f"Hz\t{unit}\t "]
    a, b = (h.real, h.imag) if columns[0] == "Real" else (np.abs(h), np.degrees(np.angle(h)))
    rows = [f"{fi:.13e}\t{x:16.7g}\t{y:16.7g}" for fi, x, y in zip(f, a, b)]
    return ("\r\n".join(head + rows) + "\r\n").encode("cp1252")


def sdof(fn, zeta=0.02):
    w = 2j * np.pi * F
    wn = 2 * np.pi * fn
    return w ** 2 / (wn ** 2 + 2 * zeta * wn * w + w ** 2)


def test_magnitude_phase_and_channel_pairs_assembled_into_a_matrix():
    h1, h2 = sdof(12.0) + sdof(31.0), 0.5 * sdof(12.0) - sdof(31.0)
    ds = era.load([export(h1, "1-Z:2-Z"), export(h2, "1-Z:3-Z", columns=("Magnitude", "Phase"))],
                  band_hz=(2.0, 50.0), n_samples=400)
    assert ds.data.outputs == ("resp 2-Z", "resp 3-Z") and ds.data.inputs == ("ref 1-Z",)
    model = era.identify(ds.data, rows=40, cols=40).realize(order=4)
    np.testing.assert_allclose(np.sort(model.natural_frequency_hz), [12.0, 31.0], rtol=2e-3)


def test_malformed_exports_name_the_file_and_line():
    h = sdof(12.0)
    good = export(h).decode("cp1252").split("\r\n")
    cases = {
        "cut.txt": ("\r\n".join(good[:300] + [good[300][:20]]), r"cut.txt, line 301: \d values where a frequency line"),
        "word.txt": ("\r\n".join(good[:100] + ["1.0\tabc\t2"] + good[101:]), r"word.txt, line 101: 'abc' is not"),
        "gap.txt": ("\r\n".join(good[:200] + good[201:]), r"gap.txt, frequency column, line 201: the line spacing is 0.125 Hz"),
        "nan.txt": ("\r\n".join(good[:50] + [good[50].split("\t")[0] + "\tnan\t0"] + good[51:]), r"nan.txt: 1 NaN"),
        "cols.txt": ("\r\n".join(g.replace("Imaginary", "Coherence") for g in good), r"cols.txt: columns .*Real, "
                                                                                      r"Imaginary"),
    }
    for name, (text, message) in cases.items():
        with pytest.raises(era.DataError, match=message):
            era.load(text.encode("cp1252"), name=name)
    with pytest.raises(era.DataError, match=r"b.txt: 401 frequency lines but a.txt has 801"):
        era.load([_named(export(h), "a.txt"), _named(export(h[:401], f=F[:401]), "b.txt")])
    with pytest.raises(era.DataError, match=r"b.txt: unit \(g\)/\(N\) but a.txt has \(m/s²\)/\(N\)"):
        era.load([_named(export(h), "a.txt"), _named(export(h, unit="(g)(N)"), "b.txt")])


def _named(raw, name):
    import io

    buf = io.BytesIO(raw)
    buf.name = name
    return buf


def _free_free_beam(z_m, beta_l, length_m=1.3):
    """Euler-Bernoulli free-free bending shape with β L = ``beta_l`` at ``z_m`` along a beam of ``length_m``."""
    b = beta_l / length_m
    sigma = (np.cosh(beta_l) - np.cos(beta_l)) / (np.sinh(beta_l) - np.sin(beta_l))
    return np.cosh(b * z_m) + np.cos(b * z_m) - sigma * (np.sinh(b * z_m) + np.sin(b * z_m))


def test_the_modelab_setup_places_the_nine_hits_and_the_point_shapes_are_the_beams_bending_shapes():
    """Issue 26: with setup.csv the hammer points and the accelerometer are placed; by reciprocity the input-side
    shapes are the mode shapes at the nine hit points (scaled through the driving point z = 0.5 m), each with
    MAC ≥ 0.95 against the free-free beam's (0-1.3 m, β L = 4.7300, 7.8532, 10.9956, 14.1372)."""
    require_shared(MODELAB)
    paths = [MODELAB / f"ASCII0000{k}" / f"Hxysv0000{k}.txt" for k in range(1, 10)] + [MODELAB / "setup.csv"]
    ds = era.load(paths, band_hz=(65.0, 1000.0))
    meta = ds.data.meta
    assert meta["input_points"] == tuple(f"{k}X" for k in range(1, 10)) and meta["input_signs"] == (1.0,) * 9
    assert meta["output_points"] == ("4X",) and meta["output_signs"] == (-1.0,)  # z = 0.5 m, along -x
    assert meta["proposed_band_hz"] == (65.0, 1000.0)
    geo = ds.geometry
    np.testing.assert_allclose(geo.coordinates[:, 2], [0.1, 0.25, 0.375, 0.5, 0.65, 0.8, 0.925, 1.05, 1.2])
    assert geo.edges.tolist() == [[k, k + 1] for k in range(8)] and geo.channel_nodes.tolist() == [3]
    model = era.analyse(ds.data).model
    np.testing.assert_allclose(model.frequency_hz, PUBLISHED_HZ, rtol=5e-4)
    assert model.points == tuple(f"{k}X" for k in range(1, 10)) and model.point_shapes.shape == (9, 4)
    z = geo.coordinates[[int(p[:-1]) - 1 for p in model.points], 2]
    for j, beta_l in enumerate([4.7300, 7.8532, 10.9956, 14.1372]):
        mac = era.mac(model.point_shapes[:, j:j + 1], _free_free_beam(z, beta_l)[:, None].astype(complex))[0, 0]
        assert mac >= 0.95, (j, mac)


def test_a_setup_that_does_not_fit_the_files_is_refused_with_what_to_fix(tmp_path):
    require_shared(MODELAB)
    paths = [MODELAB / f"ASCII0000{k}" / f"Hxysv0000{k}.txt" for k in range(1, 4)] + [MODELAB / "setup.csv"]
    with pytest.raises(era.DataError, match="9 hammer points .* 3 reference"):
        era.load(paths)
    bad = tmp_path / "setup.csv"
    bad.write_text((MODELAB / "setup.csv").read_text().replace("zHammer,0.1", "zHammer,near"))
    with pytest.raises(era.DataError, match="'near' in row 'zHammer' is not a number"):
        era.load(paths[:3] + [bad])
