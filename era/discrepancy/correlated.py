"""Correlated prediction errors: a few shared causes (each part's stiffness a few per cent off) move many residuals
together, so their covariance is not diagonal. For normalised residuals r (n_r,) with covariance I + G Gᵀ, G (n_r, q)
the residuals' change per 1σ of each cause, the whitened residuals are

    r' = (I + G Gᵀ)^{-1/2} r = r − U diag(1 − 1/√(1 + s²)) Uᵀ r,      G = U diag(s) Vᵀ (thin SVD),

so r'ᵀr' = rᵀ (I + G Gᵀ)⁻¹ r: the misfit with the causes marginalised (linearised, Gaussian priors). Its
log-determinant is the same for every candidate fitted to the same data, so the evidence needs nothing else.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class CorrelatedErrors:
    """The whitening of :func:`correlated_errors`: basis (n_r, q') orthonormal columns, shrink (q',) in [0, 1)."""

    basis: np.ndarray
    shrink: np.ndarray

    def whiten(self, r: np.ndarray) -> np.ndarray:
        """(n_r,) residuals normalised by their own levels → whitened against the shared causes as well."""
        return r - self.basis @ (self.shrink * (self.basis.T @ r))


def correlated_errors(g: np.ndarray) -> CorrelatedErrors | None:
    """The whitening for normalised residuals whose shared causes move them by the columns of ``g`` (n_r, q) per 1σ
    of each cause; None when they do not move them (every column zero or not finite)."""
    g = np.where(np.isfinite(g), g, 0.0)
    u, s, _ = np.linalg.svd(g, full_matrices=False)
    keep = s > 1e-9 * max(float(s.max(initial=0.0)), 1e-300)
    if not keep.any():
        return None
    return CorrelatedErrors(u[:, keep], 1.0 - 1.0 / np.sqrt(1.0 + s[keep] ** 2))
