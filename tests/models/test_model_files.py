"""era.load_model: Matrix Market folders and zips (with and without the dofs.csv header), CalculiX's matrix
storage written by a real ``ccx`` run (its frequencies compared with those ccx itself prints), and the limits that
refuse a zip bomb or a file too large."""

import io
import zipfile

import numpy as np
import pytest
import scipy.io
import scipy.sparse

import ccx_plate
import era
from era.errors import DataError, TooLargeError


def _model():
    K = scipy.sparse.diags([[2e4, 2e4, 1e4], [-1e4, -1e4], [-1e4, -1e4]], [0, 1, -1])
    return era.MatrixModel(K, np.diag([1.0, 1.0, 0.5]), [("1", "x"), ("2", "x"), ("3", "x")],
                           coordinates={"1": (1, 0, 0), "2": (2, 0, 0), "3": (3, 0, 0), "0": (0, 0, 0)},
                           parts={"lower": scipy.sparse.diags([[2e4, 1e4, 0], [-1e4, 0], [-1e4, 0]], [0, 1, -1])},
                           part_masses={"top": np.diag([0, 0, 0.5])}, units="N-mm-t")


@pytest.mark.parametrize("name", ["folder", "model.zip"])
def test_a_model_round_trips_through_a_folder_and_a_zip(tmp_path, name):
    model = _model()
    back = era.load_model(era.save_model(model, tmp_path / name))
    assert back.dofs == model.dofs and back.coordinates == model.coordinates and back.units == model.units
    assert abs(back.stiffness - model.stiffness).max() == 0 and abs(back.mass - model.mass).max() == 0
    assert abs(back.parts["lower"] - model.parts["lower"]).max() == 0 and set(back.part_masses) == {"top"}
    np.testing.assert_allclose(back.modes(3)[0], model.modes(3)[0], rtol=1e-12)


def test_dofs_without_a_header_a_zip_with_one_top_folder_and_numbered_directions(tmp_path):
    buf = io.BytesIO()
    scipy.io.mmwrite(buf, scipy.sparse.coo_matrix(np.array([[2.0, -1.0], [-1.0, 1.0]])))
    k = buf.getvalue()
    with zipfile.ZipFile(tmp_path / "m.zip", "w") as zf:
        zf.writestr("exported/K.mtx", k)
        zf.writestr("exported/m.mtx", b"%%MatrixMarket matrix array real general\n2 2\n1\n0\n0\n1\n")
        zf.writestr("exported/dofs.csv", "10; 3\n11; 3\n")
    model = era.load_model(tmp_path / "m.zip")
    assert model.dofs == (("10", "z"), ("11", "z"))
    np.testing.assert_allclose(model.modes(2)[0] * 2 * np.pi, np.sqrt([(3 - 5**0.5) / 2, (3 + 5**0.5) / 2]))


def test_missing_and_malformed_files_say_which_file_and_what_to_do(tmp_path):
    folder = era.save_model(_model(), tmp_path / "m")
    (folder / "M.mtx").unlink()
    with pytest.raises(DataError, match="has no M.mtx"):
        era.load_model(folder)
    era.save_model(_model(), folder)
    (folder / "dofs.csv").write_text("node,direction\n1,x\n2\n")
    with pytest.raises(DataError, match="dofs.csv line 3"):
        era.load_model(folder)
    (folder / "dofs.csv").write_text("1,x\n2,x\n3,x\n")
    (folder / "K.mtx").write_text("not a matrix\n")
    with pytest.raises(DataError, match="K.mtx in m is not a Matrix Market file"):
        era.load_model(folder)
    with pytest.raises(DataError, match="not a file without a suffix|does not exist"):
        era.load_model(tmp_path / "nothing")


def test_a_zip_bomb_and_an_oversized_model_are_refused_before_they_are_read(tmp_path):
    with zipfile.ZipFile(tmp_path / "bomb.zip", "w", compression=zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("K.mtx", b"%%MatrixMarket matrix coordinate real general\n" + b" " * (64 << 20))
        zf.writestr("M.mtx", b"")
        zf.writestr("dofs.csv", b"1,x\n")
    assert (tmp_path / "bomb.zip").stat().st_size < 1 << 20
    with pytest.raises(TooLargeError, match="above the limit of 16.0 MB"):
        era.load_model(tmp_path / "bomb.zip", max_bytes=16 << 20)
    with zipfile.ZipFile(tmp_path / "huge.zip", "w") as zf:
        zf.writestr("K.mtx", b"%%MatrixMarket matrix array real general\n100000 100000\n1\n")
        zf.writestr("M.mtx", b"")
        zf.writestr("dofs.csv", b"1,x\n")
    with pytest.raises(TooLargeError, match="dense 100,000 × 100,000"):
        era.load_model(tmp_path / "huge.zip")


@pytest.fixture(scope="module")
def ccx_job(tmp_path_factory):
    """The plate's matrices written by ccx (MATRIXSTORAGE) and the frequencies ccx itself prints for it."""
    folder = tmp_path_factory.mktemp("ccx")
    sti = ccx_plate.matrices(folder)
    dat = ccx_plate.run(folder, "solved", ccx_plate.plate_deck("*FREQUENCY\n8"))
    return sti, ccx_plate.frequencies(dat)


def test_calculix_matrix_storage_gives_the_frequencies_ccx_prints(ccx_job, tmp_path):
    sti, printed = ccx_job
    model = era.load_model(sti)                   # named by its .sti; .mas and .dof beside it
    assert model.n_dofs == 3 * (ccx_plate.NX * (ccx_plate.NY + 1) * 2)     # the clamped edge's nodes are out
    assert model.coordinates is not None and model.dofs[0][1] == "x"
    np.testing.assert_allclose(model.modes(8)[0], printed, rtol=2e-6)       # ccx prints 7 digits
    with zipfile.ZipFile(tmp_path / "ccx.zip", "w") as zf:                 # the three files zipped, nothing else
        for ext in (".sti", ".mas", ".dof"):
            zf.write(sti.with_suffix(ext), "plate" + ext)
    zipped = era.load_model(tmp_path / "ccx.zip")
    assert zipped.coordinates is None
    np.testing.assert_allclose(zipped.modes(3)[0], printed[:3], rtol=2e-6)
    (tmp_path / "two").mkdir()
    with pytest.raises(DataError, match="no plate.mas"):
        (tmp_path / "two" / "plate.sti").write_bytes(sti.read_bytes())
        era.load_model(tmp_path / "two")


def test_calculix_beams_expanded_into_bricks_are_refused_with_the_reason(tmp_path):
    deck = ("*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 2, 0, 0\n*ELEMENT, TYPE=B31, ELSET=EB\n1, 1, 2\n2, 2, 3\n"
            "*MATERIAL, NAME=S\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7800.\n*BEAM SECTION, ELSET=EB, MATERIAL=S, "
            "SECTION=RECT\n0.1, 0.05\n0., 0., 1.\n*BOUNDARY\n1, 1, 6\n*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n2\n"
            "*END STEP\n")
    ccx_plate.run(tmp_path, "beam", deck)
    with pytest.raises(DataError, match="expands them into bricks|expands into bricks|which it expands"):
        era.load_model(tmp_path / "beam.dof")
