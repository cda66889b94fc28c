"""era.explain's confusion matrix on blind simulated tests: single effects, pairs, damage, out-of-library effects.

Run: nice python3 tests/bench/bench_explain_matrix.py 0,1,2,3,4,5    (every group, these seeds; ~15 min as two
     processes, 0,1,2 and 3,4,5, on a shared 2-core machine)
 or: nice python3 tests/bench/bench_explain_matrix.py 0,1 pairs      (one group: single, pairs, damage, outside)
 or: python3 -m pytest -s tests/bench/bench_explain_matrix.py        (seeds 0, 1; fails on a confident wrong name)
 or: python3 -m pytest -s tests/bench/bench_explain_matrix.py -k time (one two-effect case: where the time goes)

Each case is classed by what explain() names against what the truth hides (era.examples.grid_simulation):
  right     the named set is the hidden set (located effects at their place: the joint, the member);
  part      only some of the hidden effects are named, nothing wrong (verdict "explained" on a subset);
  near      the right names, but a place left uncertain: the best place is a neighbour, and the report lists
            the true place among its set of places ("one of these", NamedEffect.places) or the others still in
            contention (with its probability);
  wrong     some named effect is not hidden, or sits at a wrong place the report does not qualify: a confident
            wrong name;
  honest    nothing named: "unexplained", "ambiguous" or "no_significant_discrepancy" (right for "none").
For "none" the right answer is "no_significant_discrepancy"; for out-of-library truths (a ground spring, a whole
damaged bar) nothing may be named. Each row also prints the adequacy test of the model with the named set (or of
the best the library could do): frequency χ² over the modes, its tail probability, the largest |Δf|/σ.
"""

from __future__ import annotations

import os
import sys
import time

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import era  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from timing import median_time  # noqa: E402
from era.examples.grid import nasa_grid  # noqa: E402
from era.examples.grid_simulation import EFFECTS, simulate_grid_test  # noqa: E402

GROUPS = {
    "single": (None,) + EFFECTS,
    "pairs": (("point_mass", "cable_length"), ("torsion_stiffness", "joint_flexibility"),
              ("distributed_mass", "loose_joint"), ("member_stiffness", "torsion_stiffness"),
              ("point_mass", "member_stiffness")),
    "damage": ({"name": "member_stiffness", "member_factor": 0.1}, {"name": "damaged_bar", "ei_factor": 0.15}),
    "outside": ("ground_spring", "damaged_bar"),
}
_LOC = {"point_mass": "point_mass_at", "loose_joint": "loose_joint_at", "member_stiffness": "member_at"}


def _key(name, location):
    if location is None:
        return name, None
    loc = tuple(tuple(float(x) for x in v) if isinstance(v, tuple) else float(v) for v in location)
    if name == "member_stiffness":      # a member either way round
        loc = tuple(sorted(loc))
    return name, loc


def classify(result, truth) -> str:
    hidden = {_key(e["name"], e["location"]) for e in truth["effects"] if e["in_library"] and e["name"] != "none"}
    named = {_key(e.name, e.location) for e in result.effects}
    if not named:
        return "honest"
    if any(not e["in_library"] for e in truth["effects"]):
        return "wrong"
    if named <= hidden:
        return "right" if named == hidden else "part"
    # a wrong place: "near" when the report names the true place among the others in contention
    for e in result.effects:
        if _key(e.name, e.location) not in hidden:
            alts = {_key(e.name, loc) for loc, _ in tuple(e.places) + tuple(e.other_locations)}
            if not (alts & hidden) or e.name not in {n for n, _ in hidden}:
                return "wrong"
    return "near"


def run_case(effect, seed):
    data, truth = simulate_grid_test(effect, seed=seed)
    t = time.perf_counter()
    r = era.explain(data, nasa_grid(**truth["nominal_params"]))
    seconds = time.perf_counter() - t
    # the named set's step, or the last step's best: the best the library could do
    best = r.rankings[len(r.effects) - 1][0] if r.effects else r.rankings[-1][0]
    return dict(truth=truth, result=r, seconds=seconds, outcome=classify(r, truth), test=best.test,
                solves=sum(x.n_solves for rk in r.rankings for x in rk))


def _label(effect) -> str:
    items = effect if isinstance(effect, tuple) else (effect,)
    return "+".join("none" if e is None else (e if isinstance(e, str) else e["name"]) for e in items)


def matrix(seeds=(0, 1), groups=tuple(GROUPS)):
    rows = []
    for group in groups:
        for effect in GROUPS[group]:
            for seed in seeds:
                c = run_case(effect, seed)
                c.update(group=group, label=_label(effect), seed=seed)
                rows.append(c)
                r, t = c["result"], c["test"]
                named = ", ".join(f"{e.name}{'' if e.location is None else ' ' + str(e.location)}"
                                  for e in r.effects) or "-"
                hidden = ", ".join(f"{e['name']}{'' if e['location'] is None else ' ' + str(e['location'])}"
                                   for e in c["truth"]["effects"])
                print(f"{group:7s} {c['label']:38s} s{seed} {c['outcome']:6s} {r.verdict:26s} named [{named}] "
                      f"hidden [{hidden}] before {r.before.max_abs_freq_error_pct:5.2f}% after "
                      f"{r.after.max_abs_freq_error_pct:5.2f}% | best set chi2_f {t.chi2_freq:7.1f}/{r.fit_modes.size} "
                      f"p_f {t.p_freq:.1e} p_s {t.p_shape:.1e} max {t.max_freq_sigma:4.1f}σ | {c['seconds']:5.1f} s "
                      f"{c['solves']} solves", flush=True)
    print("\nconfusion (right / near / part / wrong / honest), by group:")
    for group in groups:
        sel = [c for c in rows if c["group"] == group]
        counts = {k: sum(c["outcome"] == k for c in sel) for k in ("right", "near", "part", "wrong", "honest")}
        print(f"  {group:8s} " + " / ".join(f"{counts[k]:3d}" for k in counts) + f"   ({len(sel)} cases)")
    return rows


def test_one_two_effect_case_time():
    """One blind case with two hidden effects (the search runs two steps): the issue asks for < 10 s on 2 cores.
    Prints where the time goes, the machine-independent counts (full solves, Rayleigh-Ritz evaluations,
    self-weight solves), the wall-clock and the CPU seconds of this (single-threaded) process, and the CPU time
    as a multiple of one grid solve's CPU time in the same process: on a shared machine the wall clock waits
    for the others, the CPU seconds are what an idle 2-core machine would take (explain uses one core), and the
    ratio travels between machines. Fails above 800 solves' worth (1319 before the Ritz fits, 13.6 s) or 30 s."""
    model = nasa_grid()
    k = iter(range(1, 100))

    def one_solve():
        return median_time(lambda: model.with_params(stiffness_factor=1.0 + 1e-4 * next(k)).modes(16), 9,
                           time.process_time)

    ref = one_solve()
    data, truth = simulate_grid_test(("point_mass", "cable_length"), seed=0)
    nominal = nasa_grid(**truth["nominal_params"])
    t, c = time.perf_counter(), time.process_time()
    r = era.explain(data, nominal)
    seconds, cpu = time.perf_counter() - t, time.process_time() - c
    ref = min(ref, one_solve())
    counts = nominal.cache.counts()
    print(f"\none grid solve (build + modes(16)) here: {1e3 * ref:.1f} ms CPU; the case took {cpu / ref:.0f} × that")
    print(f"two-effect case (point_mass + cable_length, seed 0): {seconds:.1f} s wall, {cpu:.1f} s CPU; "
          f"{counts['solves']} solves, {counts['ritz']} Rayleigh-Ritz, {counts['statics']} self-weight solves, "
          f"{counts['hits']} cache hits; ERA {r.timing_s['era_s']:.2f} s, search {r.timing_s['ranking_s']:.1f} s, "
          f"report {r.timing_s['report_s']:.2f} s (wall); named {[e.name for e in r.effects]}")
    for k, ranking in enumerate(r.rankings):
        for x in ranking:
            print(f"   step {k + 1} {x.name:20s} {x.seconds:5.2f} s  {x.n_solves:4d} evaluations")
    assert classify(r, truth) == "right"
    assert cpu / ref < 800 and seconds < 30.0


def test_no_confident_wrong_name():
    rows = matrix((0, 1))
    wrong = [(c["label"], c["seed"]) for c in rows if c["outcome"] == "wrong"]
    assert not wrong, f"confident wrong names: {wrong}"


if __name__ == "__main__":
    seeds = tuple(int(s) for s in sys.argv[1].split(",")) if len(sys.argv) > 1 else (0, 1)
    matrix(seeds, tuple(sys.argv[2].split(",")) if len(sys.argv) > 2 else tuple(GROUPS))
