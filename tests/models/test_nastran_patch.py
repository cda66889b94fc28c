"""The fix back out: a bulk-data patch (CONM2, CELAS1 + PELAS, changed PSHELL/MAT1/PBAR/PBEAM/PROD) that the deck
INCLUDEs; the patched deck read again is the model with the effect, matrix for matrix."""

from __future__ import annotations

import numpy as np
import pytest
from nastran_decks import deck_text, every_card

from era.errors import DataError
from era.models.nastran import deck_model, read_bdf, read_deck
from era.models.nastran.patch import PATCH_FILE, deck_patch, deck_patch_for, write_patched_deck

FACTORS = {"PSHELL 1 T": 0.9, "MAT1 2 E": 1.2, "PBARL 2 I": 0.7, "PBEAM 4 J": 1.3, "PROD 5 A": 0.5}


def _deck(tmp_path, extra=(), style="small"):
    folder = tmp_path / "deck"
    folder.mkdir()
    (folder / "model.bdf").write_text(deck_text(list(every_card()) + list(extra), style, "SOL 103\nCEND\nSPC=1"))
    return read_deck(folder / "model.bdf")


def _close(a, b):
    return abs(a - b).max() <= 1e-8 * abs(b).max()


def test_the_patched_deck_is_the_model_with_the_effects(tmp_path):
    deck = _deck(tmp_path)
    patch = deck_patch(deck, masses=[(122, 0.05, (1e-4, 2e-4, 3e-4))], springs=[(103, "z", 1e4), (120, 4, 50.0)],
                       factors=FACTORS, title="a point mass, two springs and five properties")
    assert {r[3] for r in patch.replaces} == {"PSHELL", "MAT1", "PBARL", "PBEAM", "PROD"}
    main = write_patched_deck(deck, patch, tmp_path / "patched")
    assert f"INCLUDE '{PATCH_FILE}'" in main.read_text()
    got = read_bdf(main)
    want = deck_model(deck, FACTORS)
    assert got.dofs == want.dofs
    k, m = want.stiffness.tolil(), want.mass.tolil()
    k[want.index(103, "z"), want.index(103, "z")] += 1e4
    k[want.index(120, "rx"), want.index(120, "rx")] += 50.0
    for d, v in zip(("x", "y", "z", "rx", "ry", "rz"), (0.05, 0.05, 0.05, 1e-4, 2e-4, 3e-4)):
        m[want.index(122, d), want.index(122, d)] += v
    assert _close(got.stiffness, k.tocsr()) and _close(got.mass, m.tocsr())
    assert not _close(want.stiffness, deck_model(deck).stiffness)             # the factors did change it


def test_new_ids_do_not_collide_and_wtmass_is_divided_out(tmp_path):
    deck = _deck(tmp_path, extra=[("PARAM", ["WTMASS", 0.5])])
    patch = deck_patch(deck, masses=[(122, 0.05)], springs=[(103, "z", 1e4)])
    main = write_patched_deck(deck, patch, tmp_path / "patched")
    again = read_deck(main)
    assert set(again.masses) - set(deck.masses) == {deck.max_ids["element"] + 1}
    assert set(again.springs) - set(deck.springs) == {deck.max_ids["element"] + 2}
    added = again.masses[deck.max_ids["element"] + 1]
    assert added.mass == pytest.approx(0.1)                  # × WTMASS 0.5 = 0.05 in the model
    got, nominal = read_bdf(main), deck_model(deck)
    dm = (got.mass - nominal.mass).toarray()
    assert dm[got.index(122, "z"), got.index(122, "z")] == pytest.approx(0.05)


def test_the_patch_itself_is_large_field_bulk_data(tmp_path):
    deck = _deck(tmp_path)
    text = deck_patch(deck, factors={"MAT1 1 E": 0.95}).text
    assert text.splitlines()[1].startswith("$ replaces MAT1 1 (model.bdf, line")
    card = [line for line in text.splitlines() if line.startswith("MAT1*")][0]
    assert float(card[24:40]) == pytest.approx(0.95 * 7e10)


@pytest.mark.parametrize("kwargs, match", [({"masses": [(999, 1.0)]}, "grid 999 is not in the deck"),
                                           ({"factors": {"PSHELL 1 E": 2.0}}, "not a property change"),
                                           ({"springs": [(100, "w", 1.0)]}, "unknown direction")])
def test_a_patch_of_something_not_in_the_deck_is_refused(tmp_path, kwargs, match):
    with pytest.raises(DataError, match=match):
        deck_patch(_deck(tmp_path), **kwargs)


def test_factors_change_what_they_name(tmp_path):
    deck = _deck(tmp_path)
    nominal = deck_model(deck)
    heavier = deck_model(deck, {"MAT1 1 RHO": 2.0})
    plate = nominal.part_masses["PSHELL 1"]
    assert _close(heavier.part_masses["PSHELL 1"], 2 * plate)
    stiffer = deck_model(deck, {"MAT1 1 E": 1.5})
    assert _close(stiffer.parts["PSHELL 1"], 1.5 * nominal.parts["PSHELL 1"])
    assert np.all(stiffer.modes(3)[0] > nominal.modes(3)[0])
    with pytest.raises(DataError, match="not a property of the deck"):
        deck_model(deck, {"PSHELL 9 T": 0.5})


@pytest.mark.parametrize("part", ["PSHELL 1", "PBARL 2", "PROD 5"])
def test_a_part_stiffer_and_lighter_is_a_new_mat1_under_its_property(tmp_path, part):
    deck = _deck(tmp_path)
    nominal = deck_model(deck)
    params = {"part_at": f"part:{part}", "part_factor": 1.25, "part_mass_at": f"part:{part}",
              "part_mass_factor": 0.8, "stiffness_factor": 1.01, "point_mass_at": "122", "point_mass": 0.05}
    patch = deck_patch_for(deck, params, title="explain's updated model")
    assert f"MAT1*   {deck.max_ids['material'] + 1:>16}" in patch.text
    got = read_bdf(write_patched_deck(deck, patch, tmp_path / "patched"))
    k = nominal.stiffness + 0.25 * nominal.parts[part]
    m = (nominal.mass - 0.2 * nominal.part_masses[part]).tolil()
    for d in ("x", "y", "z"):
        m[nominal.index(122, d), nominal.index(122, d)] += 0.05
    assert _close(got.stiffness, k) and _close(got.mass, m.tocsr())


def test_explains_parameters_become_the_patch(tmp_path):
    deck = _deck(tmp_path)
    params = {"property_at": "property:PSHELL 1 T", "property_factor": 0.9, "spring_at": "103:z",
              "spring_stiffness": 1e4, "stiffness_factor": 0.98}
    patch = deck_patch_for(deck, params)
    got = read_bdf(write_patched_deck(deck, patch, tmp_path / "patched"))
    want = deck_model(deck, {"PSHELL 1 T": 0.9}).stiffness.tolil()
    want[got.index(103, "z"), got.index(103, "z")] += 1e4
    assert _close(got.stiffness, want.tocsr())
    with pytest.raises(DataError, match="PARAM WTMASS"):
        deck_patch_for(deck, {"distributed_mass": 0.3})
    with pytest.raises(DataError, match="changed twice"):
        deck_patch_for(deck, {"property_at": "property:PSHELL 1 T", "property_factor": 0.9,
                              "part_at": "part:PSHELL 1", "part_factor": 1.1})


def test_save_patch_of_a_deck_model_writes_bulk_data_and_matrices(tmp_path):
    from era.models.patch import patch_files
    deck = _deck(tmp_path)
    model = deck_model(deck)
    params = {"property_at": "property:PSHELL 1 T", "property_factor": 0.9, "point_mass_at": "122",
              "point_mass": 0.05, "stiffness_factor": 1.0}
    files = patch_files(model, params)
    assert {"K.mtx", "M.mtx", "era_patch.bdf", "dofs.csv", "README.txt"} <= set(files)
    text = files["era_patch.bdf"].decode()
    assert "CONM2*" in text and "PSHELL*" in text and "$ replaces PSHELL 1" in text
    assert b"era_patch.bdf" in files["README.txt"]
