"""The choice of modes is the data's, not the BLAS's: the same modes with one BLAS thread or two, on another
OpenBLAS kernel, and whatever ran before in the process.

The case that showed it: a roving-hammer test of a three-mass chain, noise-free FRFs cut to 2-40 Hz. Their H(0)'s
singular values fade smoothly from 1 to round-off (1e-13 of the largest) with no gap. The identification keeps the
values above max(shape)·ε·d_1, and how many lie that near the floor changes with the thread count (54 or 53); with
54, an even order, the choice took the "exact rank" path and read the realization at order 54, where a pole fitting
the band's cut (38.29 Hz) passed as a mode. Now exact rank needs the last value kept far above round-off
(era.choice.choose.EXACT_RANK_MARGIN): such a spectrum takes the diagram's path, and the chain's three modes are chosen
whatever the BLAS.
"""

from __future__ import annotations

import functools
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

import era
from era.choice.choose import exact_rank
from era.examples import paper_cases
from era.examples.synthetic import ambient_response, modal_response

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import continuous_chain  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def chain_frf_data() -> tuple[era.ResponseData, np.ndarray]:
    """The chain's accelerance FRFs (mass 1 out, a hammer on each mass), 0-50 Hz every 0.01 Hz, cut to 2-40 Hz,
    as pulse responses; and the chain's damped frequencies (Hz)."""
    a, b, f_modes, _ = continuous_chain()
    f = np.arange(0, 50.0 + 1e-9, 0.01)
    h = np.stack([np.linalg.solve(x * np.eye(6) - a, b)[:1] * x ** 2 for x in 2j * np.pi * f])
    return era.markov_from_frf(f, h, band_hz=(2.0, 40.0)), f_modes


@functools.lru_cache(maxsize=1)
def records() -> dict:
    """name -> (ResponseData, band_hz): records of the choice benchmark (tests/bench/bench_choice.py) of every kind,
    small enough for CI (the benchmark's whole list runs in tests/bench/bench_choice_blas.py)."""
    out = {"chain FRFs 2-40 Hz": (chain_frf_data()[0], (2.0, 40.0)),
           "paper Case II": (paper_cases.case_2(), None)}
    out["MIMO 4x2, 10 dB"] = (modal_response([3, 7.5, 12, 18.5, 26, 33], [0.01, 0.015, 0.01, 0.02, 0.012, 0.015],
                                             4, 2, 2000, 0.01, 10, 1)[0], None)
    out["one sensor, free decay"] = (modal_response([2.1, 9.3, 17.8, 31], [0.005, 0.008, 0.006, 0.01], 1, 1, 8000,
                                                    0.01, 30, 0)[0], None)
    shapes = np.linalg.qr(np.random.default_rng(5).standard_normal((6, 3)))[0]
    out["close pair 1 %"] = (modal_response([10, 10.1, 25], 0.01, 6, 2, 3000, 0.01, 30, 0, shapes=shapes)[0], None)
    y, _ = ambient_response([1.2, 3.1, 4.7, 6.6, 8.9], [0.01, 0.015, 0.01, 0.02, 0.015], 6, 60000, 0.02,
                            snr_db=10, seed=1)
    out["ambient 6 ch, 10 dB"] = (era.markov_from_ambient(y, 0.02, n_lags=500), None)
    return out


def decisions(data: era.ResponseData, band_hz) -> dict:
    """What the choice decided: the chosen frequencies (Hz, 4 significant digits), the order they are read at, and
    and every cluster's verdict code by frequency (band-edge and real poles left out: their
    count follows the order)."""
    a = era.analyse(data, band_hz=band_hz)
    return {"chosen": [float(f"{f:.4g}") for f in a.model.frequency_hz], "order": int(a.order),
            "codes": sorted((float(f"{c.frequency_hz:.3g}"), c.code) for c in a.choice.candidates()
                            if c.code not in ("band", "rigid"))}


def test_a_spectrum_fading_into_round_off_has_no_exact_rank_and_the_chain_keeps_its_three_modes():
    data, f_modes = chain_frf_data()
    for threads in (1, 2):
        with threadpool_limits(threads):
            a = era.analyse(data, band_hz=(2.0, 40.0))
        ident = a.identification
        assert not exact_rank(ident)  # however many values cleared the floor with this many threads
        np.testing.assert_allclose(a.model.frequency_hz, f_modes, rtol=1e-3)
    # the paper's noise-free cases do have an exact rank: their values drop from the last mode to round-off at once
    for case, rank in ((paper_cases.case_1(), 10), (paper_cases.case_2(), 10)):
        ident = era.analyse(case).identification
        assert ident.max_order == rank and exact_rank(ident)


@pytest.mark.parametrize("name", list(records()))
def test_the_choice_is_the_same_with_one_and_two_blas_threads(name):
    data, band = records()[name]
    with threadpool_limits(1):
        one = decisions(data, band)
    with threadpool_limits(2):
        two = decisions(data, band)
    assert one == two


KERNEL_SCRIPT = """
import json, sys
sys.path[:0] = [{tests!r}, {core!r}]
from test_choice_blas import records, decisions
print(json.dumps({{name: decisions(*rec) for name, rec in records().items()}}))
"""


def test_the_choice_is_the_same_on_another_openblas_kernel():
    """The same records in a process that runs OpenBLAS's generic kernel (OPENBLAS_CORETYPE=Prescott: other
    blocking, other summation order) and in this one."""
    if not any(pool.get("internal_api") == "openblas" for pool in threadpool_info()):  # in any order they loaded
        pytest.fail("numpy is expected to run on OpenBLAS here (its wheels ship it)")
    script = KERNEL_SCRIPT.format(tests=str(ROOT / "tests"), core=str(ROOT / "tests" / "core"))
    env = dict(os.environ, OPENBLAS_CORETYPE="Prescott", PYTHONPATH=str(ROOT))
    env.pop("OPENBLAS_L2_SIZE", None)
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=600,
                         cwd=ROOT)
    assert run.returncode == 0, run.stderr[-2000:]
    other = json.loads(run.stdout.strip().splitlines()[-1])
    here = {name: decisions(*rec) for name, rec in records().items()}
    for name in here:
        assert json.loads(json.dumps(here[name])) == other[name], name
