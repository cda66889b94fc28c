"""The timer every benchmark uses: the median of repeated wall-clock runs."""

import time

import numpy as np


def median_time(fn, repeat: int = 3, clock=time.perf_counter) -> float:
    """Median seconds of ``repeat`` calls of ``fn()``: wall-clock, or CPU with ``clock=time.process_time``."""
    times = []
    for _ in range(repeat):
        t = clock()
        fn()
        times.append(clock() - t)
    return float(np.median(times))
