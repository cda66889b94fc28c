"""Sparse assembly of batched element matrices: the planar frames' 6-DOF bars (era/fem/frame.py) and the 3-D
frames' 12-DOF beams (era/fem/space.py, era/fem/reduced.py) alike."""

from __future__ import annotations

import numpy as np
import scipy.sparse


def scatter(element_mats: np.ndarray, element_dofs: np.ndarray, n_dof: int,
            extra: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None) -> scipy.sparse.csc_matrix:
    """The (n_dof, n_dof) sum of (e, d, d) element matrices at their DOFs (e, d), plus optional (rows, cols,
    values) triplets (e.g. springs to ground on the diagonal); repeated entries add up."""
    d = element_dofs.shape[1]
    rows = np.repeat(element_dofs, d, axis=1).ravel()
    cols = np.tile(element_dofs, (1, d)).ravel()
    vals = element_mats.reshape(-1)
    if extra is not None:
        rows, cols, vals = (np.concatenate([a, np.asarray(b).ravel()]) for a, b in zip((rows, cols, vals), extra))
    return scipy.sparse.csc_matrix((vals, (rows, cols)), shape=(n_dof, n_dof))


def diagonal(values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The (rows, cols, values) triplets of a diagonal ``values`` (n,), for :func:`scatter`'s ``extra``."""
    n = np.arange(len(values))
    return n, n, np.asarray(values)
