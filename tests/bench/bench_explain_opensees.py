"""era.explain's confusion matrix against truths solved by independent code (OpenSees), beside the same cases
against the team's own FE generator.

Run: nice python3 tests/bench/bench_explain_opensees.py 0,1,2                 (every family, these seeds)
 or: nice python3 tests/bench/bench_explain_opensees.py 0 portal,footbridge   (some families)
 or: nice python3 tests/bench/bench_explain_opensees.py 0 grid 0.5            (model-form scatter × 0.5)
 or: python3 -m pytest -s tests/bench/bench_explain_opensees.py               (seed 0; fails on an exception)

The truths: tests/discrepancy/opensees_truth.py (the NASA grid as an era.Frame on its cables, a truss footbridge,
a portal; each effect of the frame library, a point mass with a softened member, a crack, a tuned mass and a
spring to ground that the library cannot name, and none), scored by tests/discrepancy/confusion.py: named right /
set contains truth / confident wrong / honest.

Beside it, the same cases with the truth made by the team's own generator, era.examples.frame_simulation (the one
tests/bench/bench_explain_frame.py uses: era/fem itself with 2 % member scatter and twice the mesh), with the same
effects (FrameModel parameters; a crack as the member factor of equal bending compliance) and the same noise; the
effects outside the library have no such counterpart and are left out of that column. The grid example's own
model (nasa_grid(), not an era.Frame) has its own matrix, tests/bench/bench_explain_matrix.py, with its own classes;
`python3 tests/bench/bench_explain_opensees.py 0,1 grid-model` runs it from here (by import).
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(os.path.dirname(HERE), "discrepancy")]

from era.examples.frame_simulation import simulate_frame_test  # noqa: E402
from confusion import matrix, table  # noqa: E402
from opensees_truth import FAMILIES, N_MODES, cases  # noqa: E402


def era_fe_twin(case):
    """The same case with its measured modes from era's own generator (same effects, same noise levels), or None
    when the effects are outside the library."""
    if case.era_params is None:
        return None
    measured, _ = simulate_frame_test(case.frame, case.label, dict(case.era_params), seed=case.seed,
                                      n_modes=N_MODES[case.family], freq_noise=0.002, shape_noise=0.01,
                                      gain_std=0.01)
    return dataclasses.replace(case, data=measured)


def run(seeds=(0,), families=tuple(FAMILIES), scale: float = 1.0) -> tuple[dict, dict]:
    """Both matrices (confusion.matrix results): against the OpenSees truths and against era's own generator."""
    t = time.perf_counter()
    truths = cases(families, seeds, scale=scale)
    print(f"{len(truths)} OpenSees truths built in {time.perf_counter() - t:.1f} s", flush=True)
    print("\n== against the OpenSees truths")
    by_opensees = matrix(truths)
    print("\n== the same cases, truth from era's own generator (era.examples.frame_simulation)")
    by_era = matrix([c for c in map(era_fe_twin, truths) if c is not None])
    print()
    print(table(by_opensees, f"OpenSees truths (model-form scale {scale}), seeds {tuple(seeds)}"))
    print()
    print(table(by_era, "era's own FE generator, same cases (outside effects not expressible)"))
    return by_opensees, by_era


def test_the_matrix_runs_seed_0_without_an_exception():
    by_opensees, by_era = run((0,))
    assert by_opensees["total"]["failed"] == 0 and by_era["total"]["failed"] == 0


if __name__ == "__main__":
    seeds = tuple(int(s) for s in sys.argv[1].split(",")) if len(sys.argv) > 1 else (0,)
    families = tuple(sys.argv[2].split(",")) if len(sys.argv) > 2 else tuple(FAMILIES)
    if families == ("grid-model",):
        import bench_explain_matrix
        bench_explain_matrix.matrix(seeds, tuple(bench_explain_matrix.GROUPS))
    else:
        run(seeds, families, float(sys.argv[3]) if len(sys.argv) > 3 else 1.0)
