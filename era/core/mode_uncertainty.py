"""The uncertainty of an identification's modes, from era.core.uncertainty's first-order functionals: the covariance
of the poles, the standard deviations of frequency and damping, and the scatter of the shapes, from the residual
blocks of one record or the scatter of independent records.

Each function takes the identification (an era.Identification, ``ident``) and reads only its public attributes
and methods; the Identification's methods of the same names call these.
"""

from __future__ import annotations

import numpy as np

from .decomposition import ModalDecomposition, align_repeated, modal_sum
from ..errors import EraError
from .uncertainty import (
    MIN_RECORDS, PoleCovariance, block_sums, correlation_length, modal_std, pole_functionals, record_covariance,
    residual_covariance)


def mode_std(ident, order: int, raw: ModalDecomposition, modes, clusters=()) -> tuple[np.ndarray, np.ndarray]:
    """frequency_std_hz and damping_std (Hz, fraction) of some modes of the order-n decomposition ``raw`` (indices
    ``modes``), as era.Identification.model gives them: a member of a repeated cluster gets the cluster's largest."""
    idx = set(int(i) for i in modes)
    for c in clusters:
        if idx & set(int(i) for i in c):
            idx |= set(int(i) for i in c)
    idx = np.array(sorted(idx), dtype=int)
    f_std = np.full(raw.z.size, np.nan)
    d_std = np.full(raw.z.size, np.nan)
    if idx.size:
        cov = ident.pole_covariance(order, raw, idx).z_cov
        f_std[idx], d_std[idx] = modal_std(raw.z[idx], cov, ident.data.dt)
        for c in clusters:
            if np.isfinite(f_std[c]).all():
                f_std[c], d_std[c] = np.max(f_std[c]), np.max(d_std[c])
    return f_std[np.asarray(modes, dtype=int)], d_std[np.asarray(modes, dtype=int)]


def shape_scatter(ident, n: int, raw: ModalDecomposition, perm: np.ndarray, clusters, modes=None) -> np.ndarray:
    """Expected MAC deficit E[1 - MAC(φ̂_j, φ_j)] of each shape of ``ident.model(n)`` (the scatter the data leave
    in the shape), to first order from the residual blocks of era.core.uncertainty; ``raw`` is the order-n
    decomposition before the repeated modes were aligned, ``perm`` the model's mode order as indices into it,
    ``clusters`` its repeated clusters.

    The shape is the first block of H(0) b_j (b_j as in era.core.uncertainty), so a perturbation moves it by
    Δφ_j = (ΔH(0) b_j)[:p] + Σ_{k≠j} φ_k a_k (ΔH(1) - z_j ΔH(0)) b_j / (z_j - z_k) (the pencil's eigenvector
    perturbation, the sum over all n eigenvalues, conjugates included; the part of Δb_j outside the
    signal subspace is annihilated by H(0)). 1 - MAC ≈ |Δφ_⊥|² / |φ|² with Δφ_⊥ the part orthogonal to φ;
    its expectation is the sum over the independent blocks (or, with records as in :func:`records_used`,
    the records' scatter divided by n_b (n_b - 1), as era.core.uncertainty.record_covariance). Cost: n pole
    functionals per mode, so it is not part of era.Identification.model; ``modes`` indexes the model's modes
    (default all).

    A member of a repeated cluster (era.core.decomposition.repeated_clusters) leaves the cluster's other members out of
    the sum: within their shared eigenspace the basis is a choice (align_repeated), not a scatter.

    Returns
    -------
    (len(modes),) fractions in [0, 1]; the MAC between the estimate and the truth is about 1 minus this.
    """
    dec = align_repeated(raw, clusters)
    chosen = perm if modes is None else perm[np.asarray(modes, dtype=int)]
    d = ident.data
    m = d.n_inputs
    root = np.sqrt(ident.singular_values[:n])
    # every eigenvalue of the order-n model: the kept ones and the conjugates of the pairs
    pair = dec.is_pair
    z_all = np.concatenate([dec.z, dec.z[pair].conj()])
    a_all = (np.concatenate([dec.left, dec.left[pair].conj()]) / root[None, :]) @ ident.P[:, :n].T
    phi_all = np.concatenate([dec.shapes, dec.shapes[:, pair].conj()], axis=1)
    b_modes = ((ident.Q[:, :n] / root[None, :]) @ dec.right).T  # (modes, s m)
    t = int(ident.row_shifts[-1] + ident.col_shifts[-1] + 2)
    records = records_used(ident)
    if records is None:  # residual blocks of the one record
        errors = (d.markov[:t] - modal_sum(raw.z, raw.shapes, raw.amplitudes, raw.is_pair, t))[None]
        block, weight = correlation_length(errors[0], max(1, t // 20)), 1.0
    else:  # the records' scatter: each record's deviation from the mean is one draw
        errors = records[:, :t] - records[:, :t].mean(axis=0)
        block, weight = t, 1.0 / (errors.shape[0] - 1) / errors.shape[0]
    s_cols = len(ident.col_shifts)
    out = np.empty(len(chosen))
    cluster_of = {int(j): set(int(k) for k in c) for c in clusters for j in c}
    for i, j in enumerate(chosen):
        # k ≠ j, and not another member of j's repeated cluster: a change within the shared eigenspace is a
        # change of its basis (align_repeated chooses that), not a scatter of the shape
        same = np.zeros(z_all.size, dtype=bool)
        same[list(cluster_of.get(int(j), {int(j)}))] = True
        others = np.flatnonzero((np.abs(z_all - dec.z[j]) > 0) & ~same)
        c = pole_functionals(a_all[others], np.repeat(b_modes[j][None], others.size, axis=0),
                             np.full(others.size, dec.z[j]), ident.row_shifts, ident.col_shifts,
                             errors)  # (others, sets, T)
        dphi = np.einsum("po,osk->spk", phi_all[:, others] / (dec.z[j] - z_all[others]), c)  # (sets, p, T)
        bj = b_modes[j].reshape(s_cols, m)
        dphi[:, :, ident.col_shifts] += np.einsum("stpm,tm->spt", errors[:, ident.col_shifts], bj)
        phi = dec.shapes[:, j]
        unit = phi / np.linalg.norm(phi)
        dphi -= unit[None, :, None] * np.einsum("p,spk->sk", unit.conj(), dphi)[:, None, :]  # ⟂ φ
        total = sum(np.sum(np.abs(block_sums(x, block)) ** 2) for x in dphi)  # over blocks (or records)
        out[i] = float(weight * total / np.linalg.norm(phi) ** 2)
    return np.minimum(out, 1.0)  # 1 - MAC is at most 1 (first order no longer holds well before that)


def records_used(ident, records=None) -> np.ndarray | None:
    """The records whose scatter gives the covariance: ``records`` if given (n_b, N, p, m), else
    ``data.records`` when it holds at least era.core.uncertainty.MIN_RECORDS of them, else None (residual blocks)."""
    if records is not None:
        records = np.asarray(records, dtype=float)
        n_samples, p, m = ident.data.markov.shape
        if records.ndim != 4 or records.shape[0] < 2 or records.shape[2:] != (p, m) or \
                records.shape[1] < int(ident.row_shifts[-1] + ident.col_shifts[-1] + 2):
            raise EraError(f"`records` has shape {records.shape}; it must be (n_b ≥ 2, N, {p}, {m}) with N at "
                           "least the samples H(0) and H(1) use: one pulse response per independent record.")
        return records
    if ident.data.n_records >= MIN_RECORDS:
        return ident.data.records
    return None


def pole_covariance(ident, n: int, dec: ModalDecomposition, modes=None, records=None) -> PoleCovariance:
    """First-order covariance of (Re z, Im z) of the given modes of the order-n decomposition ``dec``
    (from :func:`era.core.decomposition.decompose` of ``ident.balanced(n)``): see uncertainty. ``modes`` indexes dec
    (default all); ``records`` as in era.Identification.model (default ``data.records`` if there are enough)."""
    records = records_used(ident, records)
    d = ident.data
    p, m = d.n_outputs, d.n_inputs
    idx = np.arange(dec.z.size) if modes is None else np.asarray(modes, dtype=int)
    root = np.sqrt(ident.singular_values[:n])
    left = _times_basis(dec.left[idx] / root[None, :], ident.P[:, :n])  # a_j, (k, r p)
    right = _times_basis(dec.right[:, idx].T, ident.Q[:, :n] / root[None, :])  # b_j^T, (k, s m)
    z = dec.z[idx]
    if records is not None:
        return record_covariance(left, right, z, ident.row_shifts, ident.col_shifts, records)
    t = int(ident.row_shifts[-1] + ident.col_shifts[-1] + 2)
    residual = d.markov[:t] - modal_sum(dec.z, dec.shapes, dec.amplitudes, dec.is_pair, t)
    return residual_covariance(left, right, z, ident.row_shifts, ident.col_shifts, residual, n * (p + m))


def _times_basis(x: np.ndarray, basis: np.ndarray) -> np.ndarray:
    """x basis^T for complex x (k, n) and real basis (rows, n) as one real product of [Re x; Im x]: half the flops
    of the complex product, and the basis is not copied to complex (its rows are H(0)'s, thousands)."""
    both = np.concatenate([x.real, x.imag]) @ basis.T
    k = x.shape[0]
    return both[:k] + 1j * both[k:]
