"""Effects on a deck: explain names a property off by a factor (the deck re-assembled with the changed card)
among the matrix model's effects; the keywords change what they say."""

from __future__ import annotations

import numpy as np
import pytest
from nastran_decks import deck_text, every_card

from era.discrepancy import explain, modes_from_arrays
from era.discrepancy.deck_model import DeckExplainModel
from era.discrepancy.effects import place
from era.discrepancy.effects_deck import deck_effects
from era.errors import DataError
from era.models.nastran import deck_model, read_bdf
from era.models.nastran.mesh import property_keys

SENSORS = [(g, "z") for g in (100, 101, 102, 103, 110, 113, 120, 122, 123)]


@pytest.fixture(scope="module")
def nominal(tmp_path_factory):
    path = tmp_path_factory.mktemp("deck") / "model.bdf"
    path.write_text(deck_text(every_card(), "small", "CEND\nSPC = 1"))
    return DeckExplainModel.of(read_bdf(path), SENSORS)


def test_keywords_change_the_model_as_named(nominal):
    f0 = nominal.modes(4)[0]
    assert property_keys(nominal.deck) == ("PSHELL 1 T", "MAT1 1 E", "MAT1 2 E", "PBARL 2 I",
                                                      "PBEAM 4 I", "PROD 5 A")
    thin = nominal.with_params(property_at="property:PSHELL 1 T", property_factor=0.8)
    want = deck_model(nominal.deck, {"PSHELL 1 T": 0.8}).modes(4)[0]
    assert thin.exact.modes(4)[0] == pytest.approx(want, rel=2e-4)     # the cubic in t (variation.py)
    heavy = nominal.with_params(point_mass_at="122", point_mass=0.5)
    assert np.all(heavy.exact.modes(4)[0] <= f0 * (1 + 1e-9))
    both = thin.with_params(point_mass_at="122", point_mass=0.5)
    assert np.all(both.exact.modes(4)[0] < want)
    soft = nominal.with_params(part_at="part:PSHELL 1", part_factor=0.5)
    assert np.all(soft.exact.modes(4)[0] < f0)
    with pytest.raises(DataError, match="unknown parameters"):
        nominal.with_params(thickness=2)
    with pytest.raises(DataError, match="not a property of the deck"):
        nominal.with_params(property_at="property:PSHELL 9 T", property_factor=0.5).modes(2)
    assert place("property:PSHELL 1 T") == "in T of PSHELL 1"


def test_explain_names_the_thinner_plate(nominal):
    truth = nominal.with_params(property_at="property:PSHELL 1 T", property_factor=0.85, stiffness_factor=1.005)
    f, s = truth.exact.modes(6)
    library = deck_effects(nominal)
    # MAT1 1, which PSHELL 1 alone uses, is that part's stiffness: no second candidate (effects_deck)
    assert library[-1].name == "property_factor" and len(library[-1].locations) == 5
    assert "property:MAT1 1 E" not in library[-1].locations and "property:MAT1 2 E" in library[-1].locations
    # the whole library costs a minute on 2 busy cores: the nominal, a point mass, a part and the properties
    kept = tuple(e for e in library if e.name in ("none", "point_mass", "part_stiffness", "property_factor"))
    r = explain(modes_from_arrays(f, s), nominal, effects=kept, extra_model_modes=3)
    assert r.verdict == "explained" and r.effect.name == "property_factor"
    assert r.effect.location == "property:PSHELL 1 T"
    assert r.effect.parameters["property_factor"] == pytest.approx(0.85, rel=0.01)
    assert "in T of PSHELL 1" in r.effect.description


def test_explain_takes_a_deck_model_as_a_deck(nominal):
    from era.discrepancy.explain import _nominal
    model = nominal.deck_model.with_sensors(SENSORS)
    assert type(model).__name__ == "NastranModel" and model.deck is nominal.deck
    wrapped = _nominal(model, None)
    assert isinstance(wrapped, DeckExplainModel)
    assert [e.name for e in deck_effects(wrapped)][-1] == "property_factor"
