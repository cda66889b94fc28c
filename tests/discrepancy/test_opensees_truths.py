"""Issue 27: explain judged on structures solved by independent code. The OpenSees truths (opensees_truth.py) solve
the same nominal structures as era/fem differently (elements, mass, joints, supports, cables), and a handful of
blind cases through era.explain give no confident wrong name (confusion.py's classes)."""

from types import SimpleNamespace

import numpy as np
import pytest

from confusion import matrix, score
from opensees_truth import FAMILIES, N_MODES, N_SUB, ModelForm, make_case, measure, solve


def _paired_errors(frame, frequency_hz, shapes):
    """Relative frequency error (k,) of each measured mode against its best-MAC era/fem mode, and (k,) the MAC
    with the span of that mode and its era neighbours within 3 % (a nearly repeated pair mixes its shapes)."""
    f_era, s_era = frame.modes(20)
    norm = np.linalg.norm(s_era, axis=0)
    f_era, unit = f_era[norm > 1e-9 * norm.max()], s_era[:, norm > 1e-9 * norm.max()] / norm[norm > 1e-9 * norm.max()]
    mac = (shapes.T @ unit) ** 2 / np.sum(shapes**2, 0)[:, None]
    best = np.argmax(mac, axis=1)
    span = []
    for k, j in enumerate(best):
        q, _ = np.linalg.qr(unit[:, np.abs(f_era / f_era[j] - 1.0) < 0.03])
        v = shapes[:, k] / np.linalg.norm(shapes[:, k])
        span.append(float(np.sum((q.T @ v) ** 2)))
    return frequency_hz / f_era[best] - 1.0, np.array(span)


@pytest.mark.parametrize("family", tuple(FAMILIES))
def test_opensees_and_era_fem_solve_the_same_nominal_structure_within_the_model_form_scatter(family):
    frame = FAMILIES[family]()
    f, u = solve(frame, ModelForm.draw(frame, None, N_SUB[family], scale=0.0), n_modes=N_MODES[family] + 8)
    exact, _ = measure(frame, f, u, np.random.default_rng(0), N_MODES[family], 0.0, 0.0, 0.0)
    err, mac = _paired_errors(frame, exact.frequency_hz, exact.shapes)
    # only the formulation differs: the lowest sensed modes within 2.5 %, shapes alike, and not identical
    assert exact.n_modes == N_MODES[family] and np.all(mac > 0.95)
    assert np.max(np.abs(err)) < 0.025 and np.max(np.abs(err)) > 1e-4
    # with the model-form scatter drawn for seed 0 (and 0.2 % identification noise): within 5 %
    case = make_case(family, "none", 0)
    err, mac = _paired_errors(frame, case.data.frequency_hz, case.data.shapes)
    assert case.truth == {"effects": []} and np.all(mac > 0.9) and np.max(np.abs(err)) < 0.05


def test_a_hidden_point_mass_lowers_the_truths_frequencies_and_a_spring_to_ground_raises_them():
    none, mass, spring = (make_case("portal", label, 0) for label in ("none", "point_mass", "ground_spring (outside)"))
    assert np.all(mass.frequency_hz < none.frequency_hz) and spring.frequency_hz[0] > 1.02 * none.frequency_hz[0]
    assert mass.truth["effects"][0][:2] == ("point_mass", mass.era_params["point_mass_at"])
    assert spring.truth["effects"][0][0] == "outside" and spring.era_params is None


def test_the_scorer_reads_single_places_sets_of_places_and_refusals():
    case = SimpleNamespace(truth={"effects": [("point_mass", "E", 30.0), ("member_stiffness", ("C", "G"), 0.6)]})
    named = lambda *effects: SimpleNamespace(effects=effects)     # noqa: E731
    mass = SimpleNamespace(name="point_mass", location="E", other_locations=())
    member_set = SimpleNamespace(name="member_stiffness", location=("B", "C"), other_locations=((("G", "C"), 0.3),))
    assert score(named(mass), case) == "named right"
    assert score(named(mass, member_set), case) == "set contains truth"
    assert score(named(SimpleNamespace(name="point_mass", location="B", other_locations=())), case) == \
        "confident wrong"
    assert score(named(mass, SimpleNamespace(name="support_flexibility", location="A", other_locations=())),
                 case) == "confident wrong"
    assert score(named(mass, SimpleNamespace(name="point_mass", location="E", other_locations=())), case) == \
        "confident wrong"      # the same true effect cannot be named twice
    places = SimpleNamespace(name="point_mass", location="B", other_locations=(), places=[("B", 0.6), ("E", 0.4)])
    assert score(named(places), case) == "set contains truth"
    first = SimpleNamespace(name="point_mass", location="E", other_locations=(("B", 0.2),))
    assert score(named(first), case) == "set contains truth"      # right first, but not a single name
    assert score(None, case) == score(named(), case) == "honest"
    outside = SimpleNamespace(truth={"effects": [("outside", "E", "tuned_mass")]})
    assert score(named(mass), outside) == "confident wrong" and score(named(), outside) == "honest"


# a handful of blind cases: nothing hidden (portal), the footbridge (a point mass and a softened member), a
# crack in a grid bar, a tuned mass outside the library, and two that today's explain names wrongly: a softened
# footbridge chord, a semi-rigid portal joint
SMALL = (("portal", "none", 0), ("footbridge", "two", 0), ("grid", "damage", 0),
         ("footbridge", "tuned_mass (outside)", 0), ("footbridge", "member_stiffness", 2),
         ("portal", "joint_flexibility", 0))


@pytest.fixture(scope="module")
def small_matrix():
    return matrix([make_case(*c) for c in SMALL], verbose=False)


def test_every_blind_case_ends_in_an_explanation_or_a_refusal_in_words(small_matrix):
    assert small_matrix["total"]["failed"] == 0, [r["verdict"] for r in small_matrix["rows"]]
    assert sum(small_matrix["total"].values()) == len(SMALL)


def test_no_confident_wrong_name_on_the_blind_cases(small_matrix):
    wrong = [r["name"] for r in small_matrix["rows"] if r["outcome"] == "confident wrong"]
    assert not wrong, wrong
