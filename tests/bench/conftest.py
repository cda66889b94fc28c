"""Benchmarks pin BLAS to one thread so ratios are repeatable on a shared 2-core machine."""

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
try:  # numpy may already be imported by the time this runs: limit the loaded BLAS too
    from threadpoolctl import threadpool_limits  # noqa: F401

    threadpool_limits(1)
except ImportError:
    pass
