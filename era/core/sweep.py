"""Every order of one identification realized at once (the stabilization diagram's models): each order's
eigensolution on its own, then γ, μ and the contribution of the modes of a run of orders in one batch.

Per order n the realization is the leading n × n block of one projection of H(1) (Identification.projected),
so only its eigensolution (LAPACK's Hessenberg QR through era.core.lapack, about 25 n³ flops, not BLAS-3) is per
order. What is per mode is then done on the modes of a run of orders together (:func:`chunks_of`, about
CHUNK_MODES modes):

* γ (eqs. 42-45) without the modal histories ψ^{-1} D^{1/2} Q_n^T (eq. 44): their inner products with the
  ideal histories come from one BLAS-3 product of Q^T, arranged by column shift, with the modes' conjugate
  powers z^{-t_i} (:func:`sweep_emac`), about 2 M × K × s m flops for M modes instead of a thin product per
  order, and an output K m × 2 M instead of the histories' 2 M × s m;
* μ (eqs. 46-54) and the contribution: one call each.

Both the orders and the runs go ``workers`` at a time in threads with one BLAS thread each (LAPACK through
ctypes, numpy's BLAS and element-wise loops release the GIL), so all of it scales with the threads.
The numbers are those of ``ident.model(n)`` for every n (to round-off: tests/core/test_stabilization.py).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from . import indicators
from .blas import single_threaded_blas
from .decomposition import ModalDecomposition, continuous_eigenvalues, mode_order

#: modes per batched product (bounds its memory: K m × 2 CHUNK_MODES numbers, 3 MB for K = 120, m = 8):
#: large enough to run at BLAS-3 speed, small enough that two threads get runs of about equal work. On
#: tests/bench/bench_sweep.py's sweeps, γ, μ and the contribution of all orders with 2 threads took (median of
#: 15, interleaved) 35.1 / 30.2 / 28.9 ms on 1280 × 2000 and 34.9 / 32.8 / 31.6 ms on 900 × 2392 for 300 / 250 /
#: 200 modes, the same or less with one thread (100, in a shorter run of 7: 38.8 ms on 1280 × 2000).
CHUNK_MODES = 200


@dataclass(frozen=True, eq=False)
class OrderSweep:
    """The modes of every order, as one array per quantity (modes of order orders[0] first, each order's modes
    sorted by frequency as in ``ident.model(order)``).

    orders : (n_orders,) int; start : (n_orders + 1,) int, the modes of orders[i] are [start[i], start[i+1]);
    order, mode_index : (n_modes,) int, each mode's order and its index in ``ident.model(order)``;
    z : (n_modes,) complex; frequency_hz, damping_ratio : (n_modes,); shapes : (p, n_modes) complex;
    raw : per order, (the decomposition as the eigensolver gave it, the model's mode order as indices into it,
        the repeated clusters): what Identification.mode_std needs for the standard deviations of some modes;
    aligned : per order, the decomposition with its repeated modes aligned, in the solver's order;
    known_std : per order, (frequency_std_hz, damping_std) in the solver's order, computed while realizing it:
        those of the poles that may be repeated (era.core.decomposition.cluster_candidates, the test needs them),
        NaN for the others; what Identification.mode_std would give them, so they are not computed twice;
    perm : (n_modes,) int, the sweep's order of the modes as indices into those decompositions concatenated.
    γ, μ and the contribution come from :func:`order_indicators`.
    """

    orders: np.ndarray
    start: np.ndarray
    order: np.ndarray
    mode_index: np.ndarray
    z: np.ndarray
    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    raw: tuple
    aligned: tuple
    perm: np.ndarray
    known_std: tuple = ()

    def of(self, k: int) -> slice:
        """The modes of orders[k]."""
        return slice(int(self.start[k]), int(self.start[k + 1]))


def in_parallel(fn, items: list, workers: int) -> list:
    """[fn(x) for x in items], ``workers`` at a time in threads (numpy's LAPACK calls release the GIL), each
    with one BLAS thread while they run: the cores go to items, not to BLAS threads that would fight over them
    (threadpoolctl's limit is process-wide for the duration). The largest items (the last) start first."""
    if workers > 1 and len(items) > 1:
        with single_threaded_blas(), ThreadPoolExecutor(workers) as pool:
            out = dict(zip(range(len(items))[::-1], pool.map(fn, items[::-1])))
        return [out[i] for i in range(len(items))]
    return [fn(x) for x in items]


def chunks_of(sizes: list[int], limit: int = CHUNK_MODES) -> list[tuple[int, int]]:
    """Consecutive runs [i, j) of orders whose modes (``sizes``) add up to at most ``limit`` (at least one order
    each): the units of the batched products."""
    out, i = [], 0
    while i < len(sizes):
        j, rows = i, 0
        while j < len(sizes) and (rows == 0 or rows + sizes[j] <= limit):
            rows += sizes[j]
            j += 1
        out.append((i, j))
        i = j
    return out


def sweep_emac(left: list, z: np.ndarray, by_shift: np.ndarray, root: np.ndarray, growth: np.ndarray) -> np.ndarray:
    """γ of the modes of some orders (eqs. 42-45) from their left eigenvectors, without forming their histories.

    With L_j = ψ^{-1}_j D^{1/2} (the row of mode j, zero past its order) the history is q_j = L_j Q^T, its
    first block b_j = L_j Q_0^T, and the inner product with the ideal history b_j z_j^{t_i} (eq. 43) is

        Σ_i conj(z_j^{t_i}) b_j^H q_j(t_i) = Σ_n L_jn Σ_m conj(b_jm) F_j[n, m],   F_j = Σ_i conj(z_j^{t_i}) Q_i^T

    where Q_i^T (K × m) is Q^T's block of column shift t_i. All F_j are ONE real product of Q^T arranged by
    shift (K m × s) with the conjugate powers (s × 2 M): the flops of the histories' product, but an output of
    K m × 2 M instead of 2 M × s m and no pass over the histories after it; |q_j| = |L_j| as Q's columns are
    orthonormal (to ε d_1²/d_n², 2e-10 relative at most on the truncated SVD's direct route, era.core.svd).

    Parameters
    ----------
    left : list of (modes_i, n_i) complex, the rows of ψ^{-1} of each order's kept modes (ModalDecomposition.left)
    z : (M,) complex, their eigenvalues in the same order (M = Σ modes_i)
    by_shift : (K, m, s) Q^T arranged by column shift, K ≥ every n_i; root : (K,) D^{1/2}
    growth : (M, s) powers(z, col_shifts)

    Returns
    -------
    (M,) γ, equal (to round-off) to indicators.emac of each order's histories ψ^{-1} D^{1/2} Q_n^T.
    """
    modes = len(z)
    width = max((x.shape[1] for x in left), default=0)
    _, m, s = by_shift.shape
    rows = np.zeros((modes, width), complex)  # L_j, zero-padded to the widest order
    at = 0
    for x in left:
        rows[at:at + len(x), :x.shape[1]] = x * root[:x.shape[1]]
        at += len(x)
    powers_t = np.concatenate([growth.real.T, -growth.imag.T], axis=1)  # (s, 2 M): conj(z^{t_i}) as Re, Im
    both = by_shift[:width].reshape(width * m, s) @ powers_t
    f = (both[:, :modes] + 1j * both[:, modes:]).reshape(width, m, modes)
    t = np.einsum("jn,nmj->jm", rows, f)  # Σ_n L_jn F_j[n, m]
    b = rows @ by_shift[:width, :, 0]  # the first block of each history, (M, m)
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        inner = np.abs(np.einsum("jm,jm->j", b.conj(), t))
        norms = np.sqrt(np.einsum("js,js->j", growth.real, growth.real) + np.einsum("js,js->j", growth.imag,
                                                                                    growth.imag)) \
            * np.linalg.norm(b, axis=1) * np.linalg.norm(rows, axis=1)
    ok = np.isfinite(norms) & (norms > 0) & np.isfinite(inner)
    out = np.zeros(modes)
    out[ok] = inner[ok] / norms[ok]
    return np.clip(out, 0.0, 1.0)


def realize_orders(ident, orders: list, workers: int = 1) -> OrderSweep:
    """The modes of ``ident.model(n, uncertainty=False)`` for every n in ``orders`` (increasing, each ≤
    ident.max_order), as an :class:`OrderSweep`; ``workers`` orders are eigensolved at a time."""
    d = ident.data
    if orders:
        with single_threaded_blas():  # era.core.blas: the threads below would share their cores with BLAS's
            ident.projected(orders[-1])  # one projection of H(1) for every order

    def decomposed(n):
        _, _, _, raw, dec, clusters, f_std, d_std = ident.decomposed(n, False, histories=False)
        return raw, dec, clusters, (f_std, d_std)

    parts = in_parallel(decomposed, list(orders), workers)
    decs: list[ModalDecomposition] = [dec for _, dec, _, _ in parts]
    sizes = np.array([dec.z.size for dec in decs], dtype=int)
    start = np.concatenate([[0], np.cumsum(sizes)])
    group = np.repeat(np.asarray(orders, dtype=int), sizes)
    z = np.concatenate([dec.z for dec in decs]) if decs else np.zeros(0, complex)
    shapes = np.concatenate([dec.shapes for dec in decs], axis=1) if decs else np.zeros((d.n_outputs, 0), complex)
    perm = mode_order(z, d.dt, group)  # each order's modes by frequency, as in its model
    local = [perm[start[k]:start[k + 1]] - start[k] for k in range(len(decs))]
    s = continuous_eigenvalues(z[perm], d.dt)
    mag = np.abs(s)
    damping = np.zeros(len(s))
    np.divide(-s.real, mag, out=damping, where=mag > 0)
    return OrderSweep(orders=np.asarray(orders, dtype=int), start=start, order=group,
                      mode_index=np.concatenate([np.arange(k) for k in sizes]) if decs else np.zeros(0, int),
                      z=z[perm], frequency_hz=s.imag / (2 * np.pi), damping_ratio=damping, shapes=shapes[:, perm],
                      raw=tuple((raw, loc, clusters) for (raw, _, clusters, _), loc in zip(parts, local)),
                      aligned=tuple(decs), perm=perm, known_std=tuple(known for *_, known in parts))


def order_indicators(ident, sweep: OrderSweep, workers: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """γ, μ and the contribution (each (n_modes,), in the sweep's order) of every mode of ``sweep``: the modes
    of a run of orders (:func:`chunks_of`) in one batch, ``workers`` runs at a time in threads with one BLAS
    thread each (the products and the element-wise work around them both scale with the threads, where a
    threaded product would leave that work on one core)."""
    decs = sweep.aligned
    if not decs:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    m = ident.data.n_inputs
    start = sweep.start  # the modes of decs[k] are [start[k], start[k+1]) of the concatenation
    z = np.concatenate([dec.z for dec in decs])
    root = np.sqrt(ident.singular_values[:sweep.orders[-1]])
    s = len(ident.col_shifts)  # Q^T arranged by column shift: (K, m, s)
    by_shift = np.ascontiguousarray(ident.Q[:, :sweep.orders[-1]].T.reshape(-1, s, m).transpose(0, 2, 1))

    def indicators_of(chunk):  # the modes of orders [i, j)
        i, j = chunk
        at = slice(int(start[i]), int(start[j]))
        run = decs[i:j]
        shapes = np.concatenate([dec.shapes for dec in run], axis=1)
        growth = indicators.powers(z[at], ident.col_shifts)  # z^{t_i}, shared by γ and the contribution
        gamma = sweep_emac([dec.left for dec in run], z[at], by_shift, root, growth)
        contrib = indicators.contribution(shapes, np.concatenate([dec.amplitudes for dec in run]), z[at],
                                          ident.row_shifts, ident.col_shifts,
                                          np.concatenate([dec.is_pair for dec in run]), growth)
        return gamma, indicators.mpc(shapes), contrib

    found = in_parallel(indicators_of, chunks_of(np.diff(start).tolist()), workers)
    return tuple(np.concatenate([x[k] for x in found])[sweep.perm] for k in range(3))
