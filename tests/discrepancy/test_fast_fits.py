"""The cheap paths of explain on the grid (issue 13's speed): Rayleigh-Ritz with attachment modes for a fit's
trials, self-weight by superposition, solves shared by parameter set, and fits that end on a full solve.

Each cheap path is checked against the full solve it replaces."""

import numpy as np
import pytest

from era.discrepancy import grid_effects, modes_from_arrays
from era.discrepancy.fitting import ErrorLevels, fit_effect, mode_residuals, profile_interval
from era.discrepancy.effects import nuisance
from era.examples.grid import GridModel, nasa_grid

MEMBER = ((3.0, 0.0), (4.0, 0.0))


def _mac(a, b):
    return (np.sum(a * b, axis=0) ** 2) / (np.sum(a * a, axis=0) * np.sum(b * b, axis=0))


@pytest.mark.parametrize("change, tol", [
    (dict(member_at=MEMBER, member_factor=0.3), 2e-3),
    (dict(point_mass_kg=2.0, point_mass_at=(6.0, 4.0)), 2e-3),
    # a rigid joint turned into a near-hinge: the release spreads beyond the joint, the loosest approximation
    (dict(loose_joint_at=(0.0, 3.0), loose_joint_stiffness=20.0), 1e-2),
    (dict(cable_length_m=0.6, stiffness_factor=0.98), 2e-3),
])
def test_ritz_with_attachment_modes_matches_the_solve_and_beats_the_modes_alone(change, tol):
    ref = nasa_grid()
    model = ref.with_params(**change)
    f, s = model.node_modes(12)
    fr, sr = model.ritz(ref, 30).node_modes(12)
    fb, sb = model.ritz(ref, 30, attach=False).node_modes(12)
    err, err_bare = np.abs(fr / f - 1), np.abs(fb / f - 1)
    assert np.all(fr >= f * (1 - 1e-9))                         # Rayleigh-Ritz: upper bounds
    assert err.max() < tol and _mac(sr, s).min() > 0.99
    assert err.max() <= err_bare.max() + 1e-12                  # the attachments only add to the span


def test_ritz_declines_when_every_joint_spring_moves_far():
    ref = nasa_grid(joint_stiffness=1000.0)
    assert ref.with_params(joint_stiffness=50.0).ritz(ref, 30) is None
    near = ref.with_params(joint_stiffness=1010.0).ritz(ref, 30)
    f = ref.with_params(joint_stiffness=1010.0).modes(12)[0]
    assert near is not None and np.abs(near.modes(12)[0] / f - 1).max() < 1e-4


def test_self_weight_by_superposition_equals_a_direct_solve():
    family = nasa_grid(distributed_mass_kg=0.5, member_at=MEMBER, member_factor=0.4)
    for kw in (dict(point_mass_kg=1.3, point_mass_at=(4.0, 5.0)), dict(point_mass_kg=2.3, point_mass_at=(4.0, 5.0)),
               dict(distributed_mass_kg=2.0), dict(point_mass_kg=0.7, point_mass_at=(9.0, 1.0))):
        shared = family.with_params(**kw)
        alone = GridModel(shared.params)                # its own cache: a direct solve
        for a, b in zip(shared._system[4], alone._system[4]):
            np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-9 * np.abs(b).max())
    # 4 sets of weights on one structure: the first solved directly, then bare, spread and two joints
    assert family.cache.counts()["statics"] <= 5


def test_models_of_one_family_share_their_solves():
    a = nasa_grid()
    b = a.with_params(torsion_factor=0.9)
    f1 = b.modes(12)[0]
    c = a.with_params(torsion_factor=0.9)           # the same parameters: served from the cache
    np.testing.assert_array_equal(c.modes(12)[0], f1)
    assert a.cache.counts()["solves"] == 1 and a.cache.counts()["hits"] >= 1
    assert nasa_grid().cache is not a.cache         # another nominal: another family


@pytest.mark.parametrize("truth, name, where", [
    (dict(point_mass_kg=1.5, point_mass_at=(7.0, 2.0), stiffness_factor=1.01), "point_mass", (7.0, 2.0)),
    (dict(member_at=MEMBER, member_factor=0.25), "member_stiffness", MEMBER),
    (dict(torsion_factor=0.85), "torsion_stiffness", None),
])
def test_a_fit_by_ritz_trials_ends_where_the_solved_fit_ends(truth, name, where):
    nominal = nasa_grid()
    f, s = nominal.with_params(**truth).modes(12)
    fm = modes_from_arrays(f * (1 + 0.002 * np.sin(np.arange(12))), s)
    w = ErrorLevels().weights(fm)
    spec = next(e for e in grid_effects(nominal) if e.name == name)
    u0 = None if where is None else np.array([0.0] + [p.prior_mean for p in spec.params])
    kw = dict(location=where, u0=u0)
    solved = fit_effect(nominal, spec, nuisance(nominal), fm, w, 18, **kw)
    before = nominal.cache.counts()["solves"]
    quick = fit_effect(nominal, spec, nuisance(nominal), fm, w, 18, ritz_modes=30, **kw)
    assert nominal.cache.counts()["solves"] - before <= 6 < solved.n_evals
    post = np.array([solved.uncertainty[p.name] / (solved.parameters[p.name] if p.log else 1) for p in solved.params])
    assert np.all(np.abs(quick.u - solved.u) <= 0.2 * post)      # within a fifth of the posterior σ
    assert quick.log_evidence == pytest.approx(solved.log_evidence, abs=0.1)
    # what is reported comes from a full solve at the final parameters
    r, _ = mode_residuals(nominal.with_params(**{p.name: p.value(x) for p, x in zip(quick.params, quick.u)},
                                              **({} if where is None else {spec.location_keyword: where})),
                          fm, w, 18)
    assert quick.chi2 == pytest.approx(float(r @ r), rel=1e-9)
    iv_solved = profile_interval(nominal, solved, fm, w, 18)
    iv_quick = profile_interval(nominal, quick, fm, w, 18, ritz_modes=30)
    for a, b in zip(iv_solved, iv_quick):
        assert (a is None) == (b is None) and (a is None or b == pytest.approx(a, rel=0.02))


@pytest.mark.parametrize("kw", [{}, dict(loose_joint_at=(3.0, 4.0), loose_joint_stiffness=20.0),
                                dict(joint_stiffness=500.0, gravity=False),
                                dict(point_mass_kg=1.0, point_mass_at=(2.0, 3.0), member_at=MEMBER, member_factor=0.3)])
def test_the_grid_assembles_what_fem_assembles(kw):
    from era import fem
    model = nasa_grid(**kw)
    frame, system, _, _, (axial, _) = model._system
    ref = fem.assemble_out_of_plane(frame, axial if model.params["gravity"] else None)
    assert np.array_equal(ref.dofs, system.dofs)
    for a, b in ((system.K, ref.K), (system.M, ref.M)):
        assert abs(a - b).max() <= 1e-14 * abs(b).max()
