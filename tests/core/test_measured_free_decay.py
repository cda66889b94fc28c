"""A real measured free decay: the USC steel cantilever (CC BY-SA 4.0, read from ../shared, not copied).

Published natural frequencies (upstream README): 6.62, 41.4 and 117.5 Hz, read off an FFT.
"""

import numpy as np
import scipy.signal

import era


def _free_decay(folder):
    path = folder / "usc_cantilever_free_decay" / "timeseries_data.lvm"
    acc = np.loadtxt(path, skiprows=23, usecols=1)  # LabVIEW LVM: 23 header lines, then time, acceleration (g)
    dt = 0.000605
    # anti-aliased decimation by 4 (Nyquist 207 Hz > 117.5 Hz), then the decay from just after the impact
    y = scipy.signal.decimate(acc, 4, ftype="fir", zero_phase=True)
    start = int(np.argmax(np.abs(y))) + 5
    return era.ResponseData(y[start:start + 3000], 4 * dt, outputs=("tip acceleration",), output_units=("g",))


def test_cantilever_modes_match_the_published_frequencies(shared_datasets):
    data = _free_decay(shared_datasets)
    ident = era.identify(data, rows=150, cols=1300)
    stab = era.stabilization(ident, orders=range(2, 61, 2))
    persistent = [m for m in stab.modes if len(m.orders) >= 15 and m.emac > 0.99]
    for published, tol in ((6.62, 0.003), (41.4, 0.003), (117.5, 0.006)):
        best = min(persistent, key=lambda m: abs(m.frequency_hz - published))
        assert abs(best.frequency_hz - published) / published < tol, (published, best.frequency_hz)
        assert 0 < best.damping_ratio < 0.01  # a lightly damped steel beam
        assert best.frequency_std_hz < 1e-3 * published  # stable across orders
