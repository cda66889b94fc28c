"""explain() is not tied to the grid: any model with modes/params/with_params and its own effect library.

A fixed-free spring-mass chain of 8 masses, 4 sensors; candidates: a softer spring at one joint (located) and
a heavier tip. The measured modes come from a chain with a hidden soft spring.
"""

from dataclasses import dataclass, field

import numpy as np
import pytest
import scipy.linalg

from era.discrepancy import EffectSpec, Param, explain, modes_from_arrays

N = 8
SENSORS = (1, 3, 5, 7)


@dataclass(frozen=True)
class Chain:
    p: dict = field(default_factory=lambda: {"stiffness_factor": 1.0, "soft_at": None, "soft_factor": 1.0,
                                             "tip_mass_kg": 0.0})

    params = property(lambda self: dict(self.p))
    sensors = property(lambda self: np.array([(s, 0.0) for s in SENSORS]))
    joints_ft = property(lambda self: np.array([(j, 0.0) for j in range(N)]))

    def with_params(self, **changes):
        return Chain({**self.p, **changes})

    def node_modes(self, n):
        k = np.full(N, 1000.0 * self.p["stiffness_factor"])
        if self.p["soft_at"] is not None:
            k[int(self.p["soft_at"][0])] *= self.p["soft_factor"]
        K = np.diag(k + np.r_[k[1:], 0.0]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
        M = np.eye(N)
        M[-1, -1] += self.p["tip_mass_kg"]
        lam, phi = scipy.linalg.eigh(K, M, subset_by_index=[0, n - 1])
        return np.sqrt(lam) / (2 * np.pi), phi

    def modes(self, n):
        f, phi = self.node_modes(n)
        return f, phi[list(SENSORS)]


LIBRARY = (
    EffectSpec("none", summary="the chain is as drawn"),
    EffectSpec("soft_spring", (Param("soft_factor", True, np.log(0.5), 1.0),), location_keyword="soft_at",
               trial={"soft_factor": 0.5}, trial_power=-1.0, summary="one spring is softer"),
    EffectSpec("tip_mass", (Param("tip_mass_kg", True, np.log(0.3), 1.0, "kg"),), summary="the tip is heavier"),
)


def test_a_soft_spring_is_found_at_its_joint_in_a_spring_mass_chain():
    truth = Chain().with_params(soft_at=(5, 0.0), soft_factor=0.4, stiffness_factor=1.01)
    f, s = truth.modes(4)
    r = explain(modes_from_arrays(f, s), Chain(), effects=LIBRARY, extra_model_modes=3)
    assert r.verdict == "explained" and r.effect.name == "soft_spring"
    assert r.effect.location == (5.0, 0.0)
    assert r.effect.parameters["soft_factor"] == pytest.approx(0.4, rel=0.05)
    assert r.after.max_abs_freq_error_pct < 0.1 and r.after.min_mac > 0.999
    assert r.expanded_measured.shape == (N, 4)


def test_the_chain_as_drawn_raises_no_alarm():
    f, s = Chain().with_params(stiffness_factor=0.995).modes(4)
    r = explain(modes_from_arrays(f, s), Chain(), effects=LIBRARY, extra_model_modes=3)
    assert r.verdict == "no_significant_discrepancy" and r.effect is None


def test_two_candidates_the_data_cannot_tell_apart_give_ambiguous_not_a_name():
    """Two candidates that change the model identically (the same tip mass under two names): both fit, the
    posterior splits evenly between them, and neither is named."""
    twin = LIBRARY + (EffectSpec("tip_mass_twin", (Param("tip_mass_kg", True, np.log(0.3), 1.0, "kg"),),
                                 summary="the tip is heavier (second opinion)"),)
    truth = Chain().with_params(tip_mass_kg=0.5)
    f, s = truth.modes(4)
    r = explain(modes_from_arrays(f, s), Chain(), effects=twin, extra_model_modes=3)
    assert r.verdict == "ambiguous" and r.effect is None
    assert {r.ranking[0].name, r.ranking[1].name} == {"tip_mass", "tip_mass_twin"}
    assert r.ranking[0].probability == pytest.approx(0.5, abs=0.01)
    assert "equally well" in r.message
