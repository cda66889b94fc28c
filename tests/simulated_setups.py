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
