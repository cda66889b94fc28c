"""The choice of modes on every record of the choice benchmark with one and two BLAS threads: the same modes, the
same order, the same verdict on every cluster (tests/core/test_choice_blas.py runs a few of them in CI).

Run: python3 -m pytest tests/bench/bench_choice_blas.py -s
"""

import sys
from pathlib import Path

from threadpoolctl import threadpool_limits

from tests.bench.bench_choice import cases

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "core"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from test_choice_blas import chain_frf_data, decisions  # noqa: E402


def test_every_benchmark_record_is_chosen_alike_with_one_and_two_blas_threads():
    records = [("chain FRFs 2-40 Hz", chain_frf_data()[0], (2.0, 40.0))]
    records += [(name, data, None) for name, data, _, _ in cases()]
    differ = []
    for name, data, band in records:
        with threadpool_limits(1):
            one = decisions(data, band)
        with threadpool_limits(2):
            two = decisions(data, band)
        print(f"{name:42s} {'same' if one == two else 'DIFFERENT'}: {len(one['chosen'])} modes at order "
              f"{one['order']}")
        if one != two:
            differ.append((name, one, two))
    assert not differ, differ
