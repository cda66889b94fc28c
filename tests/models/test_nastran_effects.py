"""Effects on a deck: explain names a property off by a factor (re-assembled from the changed card) among the
deck's properties, point masses, springs to ground and parts; the model's keywords change what they say."""

from __future__ import annotations

import numpy as np
import pytest
from nastran_decks import deck_text, every_card

from era.discrepancy import explain, modes_from_arrays
from era.discrepancy.effects_deck import deck_effects
from era.errors import DataError
from era.models.nastran import deck_model, read_bdf
from era.models.nastran.model import DeckModel, property_keys

SENSORS = [(g, "z") for g in (100, 101, 102, 103, 110, 113, 120, 122, 123)]


@pytest.fixture(scope="module")
def nominal(tmp_path_factory):
    path = tmp_path_factory.mktemp("deck") / "model.bdf"
    path.write_text(deck_text(every_card(), "small", "CEND\nSPC = 1"))
    return DeckModel.of(read_bdf(path), SENSORS)


def test_keywords_change_the_model_as_named(nominal):
    f0 = nominal.modes(4)[0]
    assert property_keys(nominal.deck) == ("PSHELL 1 T", "MAT1 1 E", "MAT1 2 E", "PBARL 2 I", "PBEAM 4 I",
                                           "PROD 5 A")
    thin = nominal.with_params(property_at="PSHELL 1 T", property_factor=0.8)
    assert thin.matrices().stiffness.shape == nominal.matrices().stiffness.shape
    want = deck_model(nominal.deck, {"PSHELL 1 T": 0.8}).modes(4)[0]
    assert thin.modes(4)[0] == pytest.approx(want, rel=1e-10)
    heavy = nominal.with_params(point_mass_at="122", point_mass_kg=0.5)
    assert np.all(heavy.modes(4)[0] <= f0 * (1 + 1e-12))
    held = nominal.with_params(spring_at="122 z", spring_stiffness=1e6)
    assert np.all(held.modes(4)[0] >= f0 * (1 - 1e-12))
    soft = nominal.with_params(part_at="PSHELL 1", part_factor=0.5)
    assert np.all(soft.modes(4)[0] < f0)
    with pytest.raises(DataError, match="unknown deck-model keywords"):
        nominal.with_params(thickness=2)


def test_explain_names_the_thinner_plate(nominal):
    truth = nominal.with_params(property_at="PSHELL 1 T", property_factor=0.85, stiffness_factor=1.005)
    f, s = truth.modes(6)
    library = [e for e in deck_effects(nominal, spring_places=("103 z", "123 z")) if e.name != "point_mass"]
    r = explain(modes_from_arrays(f, s), nominal, effects=tuple(library), extra_model_modes=3)
    assert r.verdict == "explained" and r.effect.name == "property_factor"
    assert r.effect.location == "PSHELL 1 T"
    assert r.effect.parameters["property_factor"] == pytest.approx(0.85, rel=0.01)
