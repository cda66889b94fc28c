"""A simulated multi-setup ambient test (issue 26) as the files a person would upload: a simply supported beam's four
modes at twelve points, recorded in four setups that share two reference sensors (P2, P5), one CSV file per setup
(a time column, then the channels P<i>). Used by tests/app/test_setups_api.py and tests/e2e/test_setups_e2e.py."""

from __future__ import annotations

import csv
import io
from functools import lru_cache

import numpy as np

from era.examples.synthetic import ambient_response

FREQUENCY_HZ = np.array([2.0, 5.5, 9.0, 14.0])
DAMPING = np.array([0.015, 0.01, 0.012, 0.01])
X = np.arange(1, 13) / 13  # a simply supported beam at twelve points: sin(j π x), none on a node of modes 1-4
TRUE_SHAPES = np.sin(np.pi * np.outer(X, np.arange(1, 5)))
REFERENCES = [1, 4]  # P2 and P5 stay put
ROVING = [[0, 2, 3], [5, 6, 7], [8, 9], [10, 11]]
LEVELS = [1.0, 2.5, 0.7, 1.8]
DT = 0.025


@lru_cache(maxsize=None)
def setup_file(k: int, modes: tuple = (0, 1, 2, 3), references_last: bool = False) -> tuple[str, bytes]:
    """Setup k's ambient record as a CSV file: a time column, then its channels P<i> (the references first, or
    last with ``references_last``)."""
    rows, modes = REFERENCES + ROVING[k], list(modes)
    y, _ = ambient_response(FREQUENCY_HZ[modes], DAMPING[modes], len(rows), 12_000, DT, snr_db=20, seed=10 + k,
                            shapes=TRUE_SHAPES[rows][:, modes])
    y = LEVELS[k] * y
    if references_last:
        rows, y = rows[2:] + rows[:2], np.column_stack([y[:, 2:], y[:, :2]])
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["time"] + [f"P{i + 1}" for i in rows])
    for i, row in enumerate(y):
        w.writerow([f"{i * DT:.4f}"] + [f"{v:.6g}" for v in row])
    return f"setup{k + 1}.csv", buf.getvalue().encode()


def truth_at(points) -> np.ndarray:
    """(points, 4) the true shapes at points named "P<i>"."""
    return TRUE_SHAPES[[int(q[1:]) - 1 for q in points]]


def beam_geometry(k: int):
    """The beam's twelve points as nodes 1-12 along x (m), joined in a line; setup k's channels on its points'
    nodes, moving along z."""
    import era

    rows = REFERENCES + ROVING[k]
    xyz = np.column_stack([1.3 * X, np.zeros(12), np.zeros(12)])
    edges = np.column_stack([np.arange(11), np.arange(1, 12)])
    return era.Geometry(np.arange(1, 13), xyz, edges, np.array(rows), np.tile([0.0, 0.0, 1.0], (len(rows), 1)))


@lru_cache(maxsize=None)
def setup_npz(k: int) -> tuple[str, bytes]:
    """Setup k as era's NPZ: its correlation functions (NExT with the two references, as the app would make them)
    and its geometry, as a file another program (or era.save_npz) would write."""
    import era
    from era.io.npz import npz_bytes

    rows = REFERENCES + ROVING[k]
    y, _ = ambient_response(FREQUENCY_HZ, DAMPING, len(rows), 12_000, DT, snr_db=20, seed=10 + k,
                            shapes=TRUE_SHAPES[rows])
    data = era.markov_from_ambient(LEVELS[k] * y, DT, references=[0, 1], names=[f"P{i + 1}" for i in rows])
    return f"setup{k + 1}.npz", npz_bytes(data, beam_geometry(k))


# ---- a tower in four setups, as the engineer of issue 36 met it -----------------------------------------------------
# A uniform shear cantilever (a tall building's sway, continuous): φ_j(h) = sin((2j - 1) π h / 2),
# f_j = (2j - 1) f_1, exact for the continuum. Twenty-two roving floors at h = i/22 and two reference sensors at
# h = 0.385 and 0.795, both near a node of the third mode (h = 0.4, 0.8: its reference components are 0.08 and 0.04
# of its largest), none on a roving floor. Setup 1 has 4 roving channels, setups 2-4 have 6; the references are the
# last two channels of every setup (ch5, ch6 in setup 1, ch7, ch8 in the others): the channel names say nothing.
TOWER_HEIGHTS = np.concatenate([np.arange(1, 23) / 22, [0.385, 0.795]])
TOWER_HZ = 0.9 * (2 * np.arange(1, 6) - 1)
TOWER_DAMPING = np.array([0.012, 0.01, 0.012, 0.01, 0.011])
TOWER_SHAPES = np.sin(np.outer(TOWER_HEIGHTS, (2 * np.arange(1, 6) - 1) * np.pi / 2))
TOWER_REFERENCES = [22, 23]
TOWER_ROVING = [list(range(0, 4)), list(range(4, 10)), list(range(10, 16)), list(range(16, 22))]
TOWER_LEVELS = [1.0, 2.0, 0.7, 1.5]


def tower_rows(k: int) -> list[int]:
    """Setup k's points (rows of TOWER_SHAPES) in its channel order: its roving floors, then the two references."""
    return TOWER_ROVING[k] + TOWER_REFERENCES


def tower_records(k: int, n_samples: int = 24_000, snr_db: float = 10.0, seed: int = 0) -> np.ndarray:
    """(n_samples, channels) setup k's ambient record at 40 Hz (600 s by default), 10 dB of sensor noise."""
    rows = tower_rows(k)
    y, _ = ambient_response(TOWER_HZ, TOWER_DAMPING, len(rows), n_samples, DT, snr_db=snr_db, seed=100 + k + 7 * seed,
                            shapes=TOWER_SHAPES[rows])
    return TOWER_LEVELS[k] * y


def tower_truth(points_rows) -> np.ndarray:
    """(points, 5) the true shapes at rows of TOWER_SHAPES."""
    return TOWER_SHAPES[list(points_rows)]


@lru_cache(maxsize=None)
def tower_file(k: int, n_samples: int = 24_000, seed: int = 0) -> tuple[str, bytes]:
    """Setup k as the file of issue 36: no time column (40 Hz to be typed), channels ch1..ch<n>."""
    y = tower_records(k, n_samples, seed=seed)
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow([f"ch{i + 1}" for i in range(y.shape[1])])
    for row in y:
        w.writerow([f"{v:.6g}" for v in row])
    return f"tower{k + 1}.csv", buf.getvalue().encode()


def tower_geometry_csv() -> str:
    """The test's points as the CSV an engineer types (point,x,y,z,direction, m), then the lines (from,to) up the
    tower through every point by height: setup k's channel c is point ``S<k>:ch<c>`` (a reference as setup 1
    names it, S1:ch5 and S1:ch6); every sensor along +x at the tower's axis."""
    names = {}
    for k in range(4):
        for c, row in enumerate(TOWER_ROVING[k]):
            names[row] = f"S{k + 1}:ch{c + 1}"
    names[TOWER_REFERENCES[0]], names[TOWER_REFERENCES[1]] = "S1:ch5", "S1:ch6"
    lines = ["point,x,y,z,direction"] + [f"{names[row]},0,0,{60 * TOWER_HEIGHTS[row]:.4f},x" for row in names]
    by_height = sorted(names, key=lambda row: TOWER_HEIGHTS[row])
    lines += ["from,to"] + [f"{names[a]},{names[b]}" for a, b in zip(by_height, by_height[1:])]
    return "\n".join(lines) + "\n"
