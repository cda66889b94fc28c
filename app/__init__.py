"""The ERA web app (FastAPI): ``app.main:app``.

BLAS runs one thread per call here: the app already runs several computations at once on its own pools, and
multi-threaded OpenBLAS under that load oversubscribes the cores (the grid's stabilization diagram took 34 s
instead of 1.6 s on the 2-core reference machine). Set before numpy is imported; an explicit setting wins.
"""

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
