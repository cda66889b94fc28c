"""A simulated monitored structure: hourly records whose modes drift with temperature, one of which drops after
damage, two of which cross. For tests, benchmarks and demos of campaigns (the truth is returned).

The structure has five modes seen by six sensors. An ambient record (:func:`write_campaign`, CSV) is the response
of the modes to independent white noise (exact discrete second-order filters, one per mode), plus white
measurement noise, so NExT's correlations are sums of the modes' free decays. A pulse-response record
(:func:`write_pulse_campaign`, NPZ) is what hammer or shaker tests at two sensors give: the normal modes' impulse
responses, plus white noise. Frequencies are held constant within a record (a record of minutes against a
temperature that changes over hours).
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter, lfiltic

from ..core.data import ResponseData
from ..io import save_npz

#: Nominal damped frequencies (Hz) of the five modes at the mean temperature.
NOMINAL_HZ = (1.25, 2.41, 3.90, 3.90, 6.15)
#: Relative frequency change per unit of the temperature curve (which swings over [-1, 1]): -0.02 is 2 % lower
#: when warmest. Mode 3 softens and mode 4 stiffens (a bearing that locks when warm), so they cross at T = 0.
SENSITIVITY = (-0.02, -0.02, -0.02, 0.01, -0.02)
DAMPING = (0.010, 0.010, 0.009, 0.011, 0.008)
#: Modal force level: lower modes of a real structure respond more; all stay well above the noise.
AMPLITUDE = (3.0, 2.0, 1.2, 1.2, 1.0)


@dataclass(frozen=True)
class MonitoringTruth:
    """What the records were made from.

    time_h : (n_records,) hours since the first record; temperature : (n_records,) the curve in [-1, 1];
    frequency_hz : (n_records, 5) the damped frequencies of each record; damping_ratio : (5,);
    shapes : (6, 5) real, unit-norm columns; damaged_mode : index of the mode that drops;
    damage_from : first damaged record (0-based); damage_drop : relative drop (0.03 = 3 %);
    dt : sampling interval in s; duration_s : record length in s;
    amplitude : (k,) modal force level of each mode, or None for AMPLITUDE;
    present : (n_records, k) bool, the modes each record holds (a mode that appears mid-way), or None for all;
    second_half_hz : (n_records, k) damped frequencies from each record's middle on (a change within one record,
        which splits the mode into twins: the same shape at two close frequencies), NaN where unchanged; or None.
    k may exceed five (era.campaign.scenarios adds a local mode).
    """

    time_h: np.ndarray
    temperature: np.ndarray
    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    damaged_mode: int
    damage_from: int
    damage_drop: float
    dt: float
    duration_s: float
    amplitude: np.ndarray | None = None
    present: np.ndarray | None = None
    second_half_hz: np.ndarray | None = None

    def record_modes(self, r: int) -> dict:
        """The keywords of :func:`ambient_record` for record r: the modes it holds, their frequencies (and those of
        its second half), damping, shapes and force levels."""
        k = self.frequency_hz.shape[1]
        keep = np.ones(k, bool) if self.present is None else np.asarray(self.present[r], bool)
        amp = np.array([AMPLITUDE[j % len(AMPLITUDE)] for j in range(k)]) if self.amplitude is None else \
            np.asarray(self.amplitude, float)
        half = None if self.second_half_hz is None else np.asarray(self.second_half_hz[r], float)[keep]
        return dict(frequency_hz=self.frequency_hz[r, keep], damping_ratio=self.damping_ratio[keep],
                    shapes=self.shapes[:, keep], amplitude=amp[keep],
                    second_half_hz=None if half is None or np.isnan(half).all() else half)


def monitoring_truth(n_records: int = 48, *, hours_between: float = 1.0, damage_from: int = 30,
                     damaged_mode: int = 1, damage_drop: float = 0.03, dt: float = 0.05,
                     duration_s: float = 600.0) -> MonitoringTruth:
    """The modes of every record: a daily temperature cycle (peak at 15:00, records from midnight) scales each
    frequency by 1 + SENSITIVITY·T, and ``damaged_mode`` drops by ``damage_drop`` from record ``damage_from``."""
    t = np.arange(n_records) * float(hours_between)
    temperature = np.sin(2 * np.pi * (t - 9.0) / 24.0)
    f = np.array(NOMINAL_HZ)[None, :] * (1 + np.array(SENSITIVITY)[None, :] * temperature[:, None])
    f[damage_from:, damaged_mode] *= 1 - damage_drop
    x = np.linspace(0, 1, 6)
    shapes = np.stack([np.sin(np.pi * x * (k + 0.5) + 0.3 * k) + 0.2 * np.cos(3 * k * x) for k in range(5)], axis=1)
    shapes[:, 3] = np.cos(2.5 * np.pi * x) * np.linspace(1, -0.5, 6)  # the crossing partner: a different shape
    shapes /= np.linalg.norm(shapes, axis=0, keepdims=True)
    return MonitoringTruth(time_h=t, temperature=temperature, frequency_hz=f, damping_ratio=np.array(DAMPING),
                           shapes=shapes, damaged_mode=int(damaged_mode), damage_from=int(damage_from),
                           damage_drop=float(damage_drop), dt=float(dt), duration_s=float(duration_s))


def _resonator(frequency_hz, damping_ratio, dt: float) -> list:
    """The denominator [1, a1, a2] of the discrete resonator whose poles are the mode's, exp(λ dt)."""
    wd = 2 * np.pi * float(frequency_hz)
    wn = wd / np.sqrt(1 - damping_ratio**2)
    z = np.exp((-damping_ratio * wn + 1j * wd) * dt)
    return [1.0, -2 * z.real, abs(z) ** 2]


def ambient_record(frequency_hz, damping_ratio, shapes, *, dt: float, duration_s: float, snr_db: float = 20.0,
                   seed: int = 0, amplitude=None, second_half_hz=None) -> np.ndarray:
    """(N, p) ambient accelerations: each mode a discrete resonator driven by its own white noise.

    frequency_hz : (k,) damped; damping_ratio : (k,); shapes : (p, k); N = round(duration_s / dt).
    amplitude : (k,) modal force levels (None: AMPLITUDE); second_half_hz : (k,) damped frequencies from sample
    N // 2 on (the resonator goes on from its state; NaN: unchanged), or None.
    White noise of rms(y_i)·10^(-snr_db/20) is added to each channel i.
    """
    rng = np.random.default_rng(seed)
    n = int(round(duration_s / dt))
    f, zeta = np.asarray(frequency_hz, float), np.asarray(damping_ratio, float)
    amp = [AMPLITUDE[j % len(AMPLITUDE)] for j in range(f.size)] if amplitude is None else list(amplitude)
    q = np.empty((n, f.size))
    for j in range(f.size):
        x = rng.standard_normal(n)
        den = _resonator(f[j], zeta[j], dt)
        if second_half_hz is None or not np.isfinite(second_half_hz[j]):
            q[:, j] = amp[j] * lfilter([0.0, 1.0], den, x)
            continue
        h = n // 2  # the second half goes on from the first half's last outputs and input
        first = lfilter([0.0, 1.0], den, x[:h])
        after = _resonator(second_half_hz[j], zeta[j], dt)
        zi = lfiltic([0.0, 1.0], after, y=first[::-1][:2], x=x[:h][::-1][:2])
        q[:, j] = amp[j] * np.concatenate([first, lfilter([0.0, 1.0], after, x[h:], zi=zi)[0]])
    y = q @ np.asarray(shapes, float).T
    rms = np.sqrt(np.mean(y**2, axis=0, keepdims=True))
    return y + rng.standard_normal(y.shape) * rms * 10 ** (-snr_db / 20)


def record_csv(y: np.ndarray, dt: float) -> bytes:
    """The CSV that era.load reads as ambient time records: a time column, one column per sensor in m/s²."""
    t = np.arange(len(y)) * dt
    head = "time," + ",".join(f"a{i + 1} [m/s^2]" for i in range(y.shape[1]))
    body = "\n".join(f"{a:.4f}," + ",".join(f"{v:.6g}" for v in row) for a, row in zip(t, y))
    return (head + "\n" + body + "\n").encode()


def write_campaign(folder, truth: MonitoringTruth, *, snr_db: float = 20.0, seed: int = 0,
                   start: str = "2026-03-02") -> list[str]:
    """One CSV file per record in ``folder``, named with its date and hour (``rec_2026-03-02T05-00.csv``) so the
    campaign reads its time from the name. Returns the paths in time order."""
    os.makedirs(folder, exist_ok=True)
    base = np.datetime64(f"{start}T00:00")
    paths = []
    for r, hours in enumerate(truth.time_h):
        stamp = str(base + np.timedelta64(int(round(hours * 60)), "m")).replace(":", "-")
        y = ambient_record(**truth.record_modes(r), dt=truth.dt, duration_s=truth.duration_s, snr_db=snr_db,
                           seed=seed * 100003 + r)
        path = os.path.join(folder, f"rec_{stamp}.csv")
        with open(path + ".part", "wb") as fh:
            fh.write(record_csv(y, truth.dt))
        os.replace(path + ".part", path)
        paths.append(path)
    return paths


#: The sensors where the pulse-response records' two inputs act (the first and fifth: each mode moves at one).
PULSE_INPUTS = (0, 4)


def pulse_record(frequency_hz, damping_ratio, shapes, *, dt: float, n_samples: int, inputs=PULSE_INPUTS,
                 snr_db: float = 30.0, seed: int = 0) -> np.ndarray:
    """(N, p, m) pulse responses of unit-mass normal modes to unit impulses at the sensors ``inputs``, with noise.

    Y[k]_il = Σ_j φ_ij φ_lj e^(-ζ_j ω_j t_k) sin(ω_dj t_k) / ω_dj · dt, t_k = k dt (the impulse response of each
    mode, ω_j = ω_dj / sqrt(1 - ζ_j²)), l over ``inputs``; frequency_hz : (k,) damped, damping_ratio : (k,),
    shapes : (p, k). White noise of rms(Y_i)·10^(-snr_db/20) is added to each output channel i.
    """
    rng = np.random.default_rng(seed)
    f, zeta = np.asarray(frequency_hz, float), np.asarray(damping_ratio, float)
    phi = np.asarray(shapes, float)
    wd = 2 * np.pi * f
    wn = wd / np.sqrt(1 - zeta**2)
    t = np.arange(int(n_samples))[:, None] * dt
    decay = np.exp(-zeta * wn * t) * np.sin(wd * t) / wd * dt  # (N, k)
    y = np.einsum("nk,pk,mk->npm", decay, phi, phi[list(inputs)])
    rms = np.sqrt(np.mean(y**2, axis=(0, 2), keepdims=True))
    return y + rng.standard_normal(y.shape) * rms * 10 ** (-snr_db / 20)


def write_pulse_campaign(folder, truth: MonitoringTruth, *, n_samples: int = 1500, snr_db: float = 30.0,
                         seed: int = 0, start: str = "2026-03-02") -> list[str]:
    """One NPZ file of pulse responses (:func:`pulse_record` at ``truth.dt``, era.save_npz) per record in ``folder``,
    named with its date and hour (``rec_2026-03-02T05-00.npz``). Returns the paths in time order."""
    os.makedirs(folder, exist_ok=True)
    base = np.datetime64(f"{start}T00:00")
    outputs = [f"a{i + 1}" for i in range(truth.shapes.shape[0])]
    paths = []
    for r, hours in enumerate(truth.time_h):
        stamp = str(base + np.timedelta64(int(round(hours * 60)), "m")).replace(":", "-")
        y = pulse_record(truth.frequency_hz[r], truth.damping_ratio, truth.shapes, dt=truth.dt, n_samples=n_samples,
                         snr_db=snr_db, seed=seed * 100003 + r)
        data = ResponseData(markov=y, dt=truth.dt, outputs=outputs, inputs=[f"hit {outputs[i]}" for i in PULSE_INPUTS])
        path = os.path.join(folder, f"rec_{stamp}.npz")
        save_npz(path + ".part", data, name=f"record {r}")
        os.replace(path + ".part", path)
        paths.append(path)
    return paths
