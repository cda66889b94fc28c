"""Hard monitoring campaigns for tests and benchmarks: the simulated structure of era.campaign.simulated with a weak
mode, a local mode that appears after the damage, and records in which a mode changes half-way (twins).

Each builder returns an era.campaign.simulated.MonitoringTruth that :func:`era.campaign.simulated.write_campaign`
turns into CSV records; the truth says which modes each record holds (``present``), so the share of those records
in which a campaign found each mode can be counted against it.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .simulated import AMPLITUDE, MonitoringTruth, monitoring_truth

#: The local mode that appears with the damage (a loosened part): frequency at the mean temperature (Hz), its
#: relative change per unit of the temperature curve, damping, and its modal force level.
LOCAL_HZ, LOCAL_SENSITIVITY, LOCAL_DAMPING, LOCAL_AMPLITUDE = 5.0, -0.01, 0.012, 1.0
#: How much a mode's frequency moves half-way through a twin record (relative): 4.427 → 4.387 Hz is 0.9 %.
TWIN_SHIFT = -0.009


def local_shape(p: int = 6) -> np.ndarray:
    """(p,) unit-norm shape of the local mode: the last sensors move, the others hardly (MAC < 0.5 with every
    mode of the simulated structure)."""
    x = np.linspace(0, 1, p)
    s = np.where(x > 0.6, np.sin(np.pi * (x - 0.6) / 0.4 * 1.5), 0.05 * x)
    return s / np.linalg.norm(s)


def campaign_truth(n_records: int = 48, *, hours_between: float = 1.0, damage_from: int = 30,
                   damaged_mode: int = 1, damage_drop: float = 0.03, weak_mode: int | None = None,
                   weak_factor: float = 10.0, local_from: int | None = None, twin_mode: int = 1,
                   twin_records=(), dt: float = 0.05, duration_s: float = 600.0) -> MonitoringTruth:
    """The monitored structure (temperature drift, modes 3 and 4 crossing, ``damaged_mode`` dropping by
    ``damage_drop`` from record ``damage_from``) with, as asked:

    weak_mode : a mode whose modal force is ``weak_factor`` times smaller (its response that much weaker);
    local_from : the first record of a sixth, local mode (:func:`local_shape`, LOCAL_HZ drifting with the
        temperature); None: no local mode;
    twin_records : records in which ``twin_mode`` moves by TWIN_SHIFT half-way through (its damped frequency in
        the second half), so the record holds it twice, the same shape at two frequencies 0.9 % apart.

    Returns a MonitoringTruth whose ``present`` says which records hold each mode.
    """
    base = monitoring_truth(n_records, hours_between=hours_between, damage_from=damage_from,
                            damaged_mode=damaged_mode, damage_drop=damage_drop, dt=dt, duration_s=duration_s)
    f, zeta, shapes = base.frequency_hz, base.damping_ratio, base.shapes
    amp = np.array(AMPLITUDE, float)
    present = np.ones(f.shape, bool)
    if local_from is not None:
        f = np.column_stack([f, LOCAL_HZ * (1 + LOCAL_SENSITIVITY * base.temperature)])
        zeta = np.append(zeta, LOCAL_DAMPING)
        shapes = np.column_stack([shapes, local_shape(shapes.shape[0])])
        amp = np.append(amp, LOCAL_AMPLITUDE)
        present = np.column_stack([present, np.arange(n_records) >= int(local_from)])
    if weak_mode is not None:
        amp[int(weak_mode)] /= float(weak_factor)
    half = np.full(f.shape, np.nan)
    for r in twin_records:
        half[int(r), int(twin_mode)] = f[int(r), int(twin_mode)] * (1 + TWIN_SHIFT)
    return replace(base, frequency_hz=f, damping_ratio=zeta, shapes=shapes, amplitude=amp, present=present,
                   second_half_hz=half if len(tuple(twin_records)) else None)
