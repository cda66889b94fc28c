"""The import step in a real browser, with real files: drop the USC cantilever's LabVIEW file and see its modes;
drop the Carini rows file, read the refusal next to the sample rate, say 25 Hz and channels in rows, see its modes
near 2.31 / 4.96 / 7.37 Hz; drop three UFF files of a roving-hammer test at once and see one dataset of three
references. The choices are in the summary and in the report.

Same server and browser setup as the other browser tests (app_server.py, conftest.py) (Debian's Chromium, never downloaded).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from app_server import open_page

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "io"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
import uff_files as U  # noqa: E402
from chain_sim import continuous_chain  # noqa: E402
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

pytestmark = pytest.mark.e2e

CARINI = SHARED_DATASETS / "carini_ambient_3ch" / "yk.txt"
USC = SHARED_DATASETS / "usc_cantilever_free_decay" / "timeseries_data.lvm"


def chosen_modes(page) -> list[float]:
    """Frequencies (Hz) of the modes era chose (era.choose_modes): the green lines of the stabilization diagram."""
    page.wait_for_function("(document.getElementById('stab-plot').layout?.shapes || []).length > 0", timeout=120000)
    return page.evaluate("document.getElementById('stab-plot').layout.shapes.map(s => s.x0)")


def near(found: list[float], targets, rtol: float) -> list[float]:
    """The found frequency closest to each target, asserting it is within rtol."""
    out = []
    for f in targets:
        best = min(found, key=lambda x: abs(x - f))
        assert abs(best - f) <= rtol * f, (f, sorted(found))
        out.append(best)
    return out


def test_drop_the_lvm_and_see_its_modes(tmp_path, browser, shots, server):
    lvm = require_shared(USC)
    page, errors = open_page(server, browser, 1100)
    page.set_input_files("#file", str(lvm))
    page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr")
    cells = page.eval_on_selector_all("#import-channels tbody tr td", "tds => tds.map(td => td.textContent)")
    assert cells[1:3] == ["Acceleration", "g"]  # the channel and its unit, as LabVIEW wrote them
    assert page.input_value("#import-rate") == "1651.61"  # the file's 1 / 0.00060546875 s, to 6 digits
    assert page.is_disabled("#import-rate")  # read from the file: nothing to say
    assert "LabVIEW LVM, 1 record of 81920 samples × 1 channel" in page.text_content("#import-read")
    page.wait_for_function("document.getElementById('import-plot').data?.length === 1")
    page.screenshot(path=str(shots / "import-1-lvm.png"), full_page=True)
    assert page.locator("#summary").is_hidden()  # nothing identified before the person says so
    page.click("#import-use")
    page.wait_for_selector("#summary:not([hidden])")
    page.wait_for_selector("#modes-table tbody tr", timeout=120000)
    near(chosen_modes(page), [6.614, 41.36, 116.85], 0.005)  # the published frequencies
    assert page.locator("#import").is_hidden() and not errors, errors


def test_the_rows_file_asks_for_its_sample_rate_next_to_the_control(tmp_path, browser, shots, server):
    yk = require_shared(CARINI)
    page, errors = open_page(server, browser, 1100)
    page.set_input_files("#file", str(yk))
    page.wait_for_selector("#import-error-dt:not([hidden])")
    assert "no sampling interval in yk.txt: give the sample rate" in page.text_content("#import-error-dt")
    assert page.is_disabled("#import-use")
    assert page.eval_on_selector("#field-rate", "l => l.classList.contains('problem')")
    assert page.locator("#import-channels tbody tr").count() == 3  # read anyway, against the sample number
    page.fill("#import-rate", "25")
    page.select_option("#import-orientation", "rows")
    page.wait_for_function("!document.getElementById('import-use').disabled")
    assert page.locator("#import-error-dt").is_hidden()
    assert "Δt = 0.04 s (25 Hz) given" in page.text_content("#import-read")
    assert "ambient" in page.text_content("#import-read")  # what "detected" will read it as
    page.screenshot(path=str(shots / "import-2-rows.png"), full_page=True)
    page.click("#import-use")
    page.wait_for_selector("#summary:not([hidden])")
    summary = page.text_content("#summary")
    assert "sample rate 25 Hz (Δt 0.04 s); channels in rows" in summary  # the choices, kept with the dataset
    page.wait_for_selector("#modes-table tbody tr", timeout=120000)
    near(chosen_modes(page), [2.31, 4.96, 7.37], 0.01)
    page.click("#create-report")
    page.wait_for_selector("#report-link-box:not([hidden])", timeout=120000)
    report = browser.new_page()
    report.goto(server.base + page.get_attribute("#report-link", "href"))
    report.wait_for_selector("body[data-ready='1']", timeout=60000)
    assert "sample rate 25 Hz (Δt 0.04 s); channels in rows" in report.text_content("#report-meta")
    assert not errors, errors


def test_three_uff_files_of_a_roving_hammer_test_dropped_at_once(tmp_path, browser, shots, server):
    a, b, f_modes, _ = continuous_chain()
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    w = 2j * np.pi * f
    h = np.stack([np.linalg.solve(x * np.eye(6) - a, b)[:3] * x ** 2 for x in w])
    nodes = U.nodes15([1, 2, 3], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
    paths = []
    for hit in (1, 2, 3):
        paths.append(tmp_path / f"hit{hit}.uff")
        U.write(paths[-1], [nodes, U.record58(h[:, 0, hit - 1], 0.0, 0.01, (1, 3), (hit, 3), func_type=4,
                                              denominator=U.FORCE, den_unit="N")])
    page, errors = open_page(server, browser, 1100)
    page.set_input_files("#file", [str(p) for p in paths])
    page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr")
    assert "3 files: hit1.uff, hit2.uff, hit3.uff" in page.text_content("#import-files")
    read = page.text_content("#import-read")
    assert "as 1 output × 3 references" in read and "geometry of 3 nodes" in read and "(s)" not in read
    row = page.eval_on_selector_all("#import-channels tbody tr td", "tds => tds.map(td => td.textContent)")
    assert row[3:5] == ["1", "+Z"]  # node and direction from the files
    assert page.is_disabled("#import-start")  # FRFs have no pre-trigger, but a sign convention
    assert page.is_visible("#field-frf-sign") and page.input_value("#import-frf-sign") == "auto"
    page.click("#import-use")
    page.wait_for_selector("#summary:not([hidden])")
    assert page.locator("#records-input option").count() == 3  # one dataset, three references
    page.wait_for_selector("#modes-table tbody tr", timeout=120000)
    near(chosen_modes(page), list(f_modes), 0.005)
    page.screenshot(path=str(shots / "import-3-roving.png"), full_page=True)
    assert not errors, errors


def test_a_shaker_test_whose_force_channel_is_in_volts_is_named_by_its_role(tmp_path, browser, shots, server):
    from chain_sim import chain, simulate

    ad, bd, cd, dd, f_modes, _ = chain(0.01)
    u = np.random.default_rng(3).standard_normal((3000, 3)) * np.array([0.0, 0.0, 1.0])
    y = simulate(ad, bd, cd, dd, u)
    table = np.column_stack([np.arange(3000) * 0.01, u[:, 2], y])
    path = tmp_path / "shaker.csv"
    np.savetxt(path, table, delimiter=",", header="time [s],drive [V],a1 [V],a2 [V],a3 [V]", comments="", fmt="%.10g")
    page, errors = open_page(server, browser, 1100)
    page.set_input_files("#file", str(path))
    page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr")
    page.select_option("#kind", "io")
    page.wait_for_function("!document.getElementById('import-use').disabled")
    page.click("#import-use")  # nothing says which channel is the force: refused under the channel table
    page.wait_for_selector("#import-error-channels:not([hidden])")
    said = page.text_content("#import-error-channels")  # in the page's words, not era.load's parameters
    assert "Mark it “force” among the channels' roles" in said and "forces=" not in said
    page.select_option("#import-channels select[data-channel='0']", "force")
    page.wait_for_function("!document.getElementById('import-use').disabled")
    page.click("#import-use")
    page.wait_for_selector("#summary:not([hidden])")
    assert page.locator("#records-input option").all_text_contents() == ["drive"]
    assert "force channels: drive" in page.text_content("#summary")
    page.wait_for_selector("#modes-table tbody tr", timeout=120000)
    near(chosen_modes(page), list(f_modes), 0.01)
    assert not errors, errors


PHONE = Path(__file__).resolve().parents[1] / "data" / "cessipy_smartphone_slab.csv"


def test_a_phone_csv_is_read_and_resampled_when_the_person_ticks_the_box(tmp_path, browser, shots, server):
    """The CESSIPy phone record: every row ends in a comma (read as it is), its stamps jitter about 425 Hz. The
    refusal sits under the resample box, in the page's words; ticked, Δt reads to 6 digits with its rate, and the
    summary says what was done to the records."""
    page, errors = open_page(server, browser, 1100)
    assert page.locator("#field-resample").is_hidden()
    page.set_input_files("#file", str(PHONE))
    page.wait_for_selector("#import-error-resample:not([hidden])")
    said = page.text_content("#import-error-resample")
    assert "No sample is missing or repeated" in said and "425.077 Hz" in said and "resample=" not in said
    assert page.is_disabled("#import-use") and page.is_visible("#field-resample")
    cells = page.eval_on_selector_all("#import-channels tbody tr td", "tds => tds.map(td => td.textContent)")
    assert cells[1:3] == ["X-Axis", "m/s2"]  # the file's own labels and units
    page.screenshot(path=str(shots / "import-phone-refused.png"), full_page=True)
    page.check("#import-resample")
    page.wait_for_function("!document.getElementById('import-use').disabled")
    read = page.text_content("#import-read")
    assert "Δt = 0.00235252 s (425.077 Hz)" in read and "resampled onto an even grid" in read
    page.click("#import-use")
    page.wait_for_selector("#summary:not([hidden])")
    summary = page.text_content("#summary")
    assert "time stamps resampled onto an even grid at the mean rate" in summary
    assert "0.00235252 s (425.077 Hz)" in summary and "resampled onto an even grid at the mean rate 425.077 Hz" \
        in summary
    page.screenshot(path=str(shots / "import-phone-dataset.png"), full_page=True)
    page.wait_for_selector("#modes-table tbody tr", timeout=120000)
    page.click("#create-report")
    page.wait_for_selector("#report-link-box:not([hidden])", timeout=120000)
    report = browser.new_page()
    report.goto(server.base + page.get_attribute("#report-link", "href"))
    report.wait_for_selector("body[data-ready='1']", timeout=60000)
    meta = report.text_content("#report-meta")  # frozen into the report: what was done, and that it was asked
    assert "resampled onto an even grid at the mean rate 425.077 Hz" in meta
    assert "time stamps resampled onto an even grid at the mean rate" in meta and "(425.077 Hz)" in meta
    assert not errors, errors


def test_the_usc_cantilever_saved_as_csv_with_7_significant_digits_is_read_as_even(tmp_path, browser, shots, server):
    """The USC record as a spreadsheet saves it (`time_s,tip_acc_g`, times in single precision, 7 significant
    digits): even within the printed digits, Δt read to 6 digits with its rate, and its three modes found."""
    import era

    rec = era.io.read(require_shared(USC)).records
    y = rec.values[0][:, 0]
    t = (rec.step * np.arange(len(y))).astype(np.float32).astype(float)
    path = tmp_path / "usc_cantilever.csv"
    path.write_text("time_s,tip_acc_g\n" + "\n".join(f"{a:.7g},{b:.7g}" for a, b in zip(t, y)) + "\n")
    page, errors = open_page(server, browser, 1100)
    page.set_input_files("#file", str(path))
    page.wait_for_function("!document.getElementById('import-use').disabled")
    assert "Δt = 0.000605469 s (1651.61 Hz)" in page.text_content("#import-read")
    assert page.locator("#field-resample").is_hidden()  # an even record: nothing to resample
    page.wait_for_function("document.getElementById('import-plot').data?.length === 1")
    page.screenshot(path=str(shots / "import-usc-csv.png"), full_page=True)
    page.click("#import-use")
    page.wait_for_selector("#modes-table tbody tr", timeout=120000)
    near(chosen_modes(page), [6.614, 41.36, 116.85], 0.005)
    assert "0.000605469 s (1651.61 Hz)" in page.text_content("#summary")
    page.screenshot(path=str(shots / "usc-csv-table.png"), full_page=True)
    assert not errors, errors


LADISK = SHARED_DATASETS / "ladisk_pyfrf_impact"


def test_the_ladisk_hammer_records_propose_their_force_channel(tmp_path, browser, shots, server):
    """Five .npy files of rows [time, force, acceleration]: the step proposes the pulse channel as the force and the
    records as input and output, without the person finding either."""
    paths = [str(require_shared(LADISK / f"measurements_{k}.npy")) for k in range(1, 6)]
    page, errors = open_page(server, browser, 1100)
    page.set_input_files("#file", paths)
    page.wait_for_selector("#import:not([hidden]) #import-channels tbody tr")
    roles = page.eval_on_selector_all("#import-channels select", "ss => ss.map(s => s.value)")
    names = page.eval_on_selector_all("#import-channels tbody tr td:nth-child(2)", "tds => tds.map(t => t.textContent)")
    assert roles == ["force", "response"] and names == ["measurements_1:2", "measurements_1:3"]
    read = page.text_content("#import-read")
    assert "read as “input and output time histories”" in read and "Δt = 0.0000390625 s (25600 Hz)" in read
    page.screenshot(path=str(shots / "import-ladisk.png"), full_page=True)
    assert not errors, errors
