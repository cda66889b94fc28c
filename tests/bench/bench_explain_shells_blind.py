"""era.explain's confusion matrix on plates and shells against blind truths solved by CalculiX (never by era.fem).

Run: nice python3 tests/bench/bench_explain_shells_blind.py 36          (cases 0..35: every effect 3 times on both)
 or: nice python3 tests/bench/bench_explain_shells_blind.py 12 0.5      (12 cases, model-form scatter × 0.5)
 or: nice python3 tests/bench/bench_explain_shells_blind.py 5,17        (these cases only; one case: "4,")
 or: python3 -m pytest -s tests/bench/bench_explain_shells_blind.py     (the first 12; fails on a confident wrong)

The truths: tests/discrepancy/shell_truth.py (a plate on elastic edge supports with three PSHELL regions and a
stiffened panel with shell webs, each a Nastran deck; the truth solved by ``ccx`` with thickness and E ±2 % per
region, boundary springs ±10 %, one hidden effect or none, measurement noise), scored as the frames' matrix
(tests/bench/bench_explain_opensees.py), by tests/discrepancy/confusion.py: named right / set contains truth /
confident wrong / honest. A MAT1's E named where that material belongs to one PSHELL is scored as that part's
stiffness (the same matrices: shell_truth.equivalent).

One case takes 10-45 s (explain on a deck of about 2,000 DOFs; ccx 2-3 s) on a shared 2-core machine.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from types import SimpleNamespace

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(os.path.dirname(HERE), "discrepancy")]

import era  # noqa: E402
from confusion import matrix, table  # noqa: E402
from shell_truth import equivalent, make_case  # noqa: E402


def explain_in_truth_terms(case):
    """era.explain on the nominal deck, each named effect restated in the truth's terms (shell_truth.equivalent):
    when one of its places stands for the hidden (kind, place), the effect is that kind with that place first
    and its other places after it; else as named."""
    r = era.explain(case.data, case.frame)
    hidden = {(kind, str(place)) for kind, place, _ in case.truth["effects"]}
    effects = []
    for e in r.effects:
        pairs = equivalent(e, case.frame)
        hit = next((pair for pair in pairs if pair in hidden), None)
        name = hit[0] if hit else e.name
        places = ([hit[1]] if hit else []) + [p for pair in pairs if pair != hit for p in pair[1:]]
        effects.append(SimpleNamespace(name=name, places=[(p, 1.0) for p in places], location=places[0]))
    return SimpleNamespace(verdict=r.verdict, effects=tuple(effects))


def run(indices, scatter: float = 1.0) -> dict:
    """The matrix (confusion.matrix's result) of the blind cases ``indices``."""
    with tempfile.TemporaryDirectory() as folder:
        t = time.perf_counter()
        truths = [make_case(i, folder, scatter) for i in indices]
        print(f"{len(truths)} CalculiX truths built in {time.perf_counter() - t:.1f} s", flush=True)
        result = matrix(truths, explain_in_truth_terms)
    print()
    print(table(result, f"CalculiX truths on plates and shells (model-form scale {scatter}), "
                        f"{len(truths)} cases"))
    return result


def test_no_confident_wrong_on_the_first_twelve_cases():
    result = run(range(12))
    assert result["total"]["confident wrong"] == 0 and result["total"]["failed"] == 0


if __name__ == "__main__":
    arg = sys.argv[1] if len(sys.argv) > 1 else "36"
    chosen = [int(x) for x in arg.split(",") if x] if "," in arg else range(int(arg))
    run(chosen, float(sys.argv[2]) if len(sys.argv) > 2 else 1.0)
