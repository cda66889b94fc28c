"""PreGER (era.merge_correlations, one identification of the stacked correlations) against PoSER
(era.merge_ambient_setups: each setup identified, shapes rescaled mode by mode) on the simulated tower of
tests/simulated_setups.py, short and long setups.

Run: python3 tests/bench/bench_setups_preger.py [seconds per setup, default 120] [seed, default 0]

Prints, for each method, the modes found, whether each is complete, and its MAC with the exact shear-cantilever
shape (the best over the five exact shapes, for poles that are no mode).
"""

import sys
import time

import numpy as np

import era
from tests.simulated_setups import DT, TOWER_REFERENCES, TOWER_ROVING, tower_records, tower_truth

REFERENCES = [[4, 5], [6, 7], [6, 7], [6, 7]]


def main(seconds: float, seed: int) -> None:
    records = [tower_records(k, int(seconds / DT), seed=seed) for k in range(4)]
    names = [[f"ch{i + 1}" for i in range(y.shape[1])] for y in records]
    truth = tower_truth(TOWER_REFERENCES + [i for rov in TOWER_ROVING for i in rov])
    t0 = time.perf_counter()
    only = [era.markov_from_ambient(y, DT, REFERENCES[k], names=names[k]) for k, y in enumerate(records)]
    pre = era.merge_correlations(only, REFERENCES)
    model = era.analyse(pre.data).model
    t1 = time.perf_counter()
    print(f"PreGER ({t1 - t0:.1f} s): scales {pre.scales.round(3)}, reference residual "
          f"{pre.reference_residual.round(3)}")
    for j in range(model.n_modes):
        print(f"  {model.frequency_hz[j]:7.3f} Hz  complete  MAC {np.max(era.mac(model.shapes[:, j], truth)):.4f}")
    choice = era.merge_ambient_setups(records, DT, REFERENCES, names=names)
    merged, result = choice.result.model, choice.result
    print(f"PoSER ({time.perf_counter() - t1:.1f} s): {choice.reason}")
    for j in range(merged.n_modes):
        mac = np.max(era.mac(np.nan_to_num(merged.point_shapes[:, j]), truth))
        print(f"  {merged.frequency_hz[j]:7.3f} Hz  {'complete' if result.complete[j] else 'partial '}  MAC {mac:.4f}")


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 120.0, int(sys.argv[2]) if len(sys.argv) > 2 else 0)
