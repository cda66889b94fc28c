"""The timer every benchmark uses: the median of repeated wall-clock runs."""

import time

import numpy as np


def median_time(fn, repeat: int = 3) -> float:
    """Median wall-clock seconds of ``repeat`` calls of ``fn()``."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return float(np.median(times))
