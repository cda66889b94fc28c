"""identify(): H(0), H(1) and one SVD (eqs. 16, 22-23); realize(): the minimum realization (eq. 34),
and the paper's non-minimal algorithms A1 (eq. 19) and A2 (eq. 20) for comparison."""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

import numpy as np

from . import hankel, mode_uncertainty, svd
from .blas import blas_threads, single_threaded_blas
from .data import ResponseData
from ..errors import EraError, HankelError, OrderError
from .points import with_points
from .decomposition import (
    ModalDecomposition, align_repeated, cluster_candidates, decompose, mode_order, repeated_clusters)
from .modal import ModalModel, build_model
from .uncertainty import PoleCovariance, modal_std, source_label


@dataclass(frozen=True, eq=False)
class Identification:
    """The SVD of H(0), from which every order is realized (with H(1) projected on its singular vectors).

    Made by :func:`era.identify`. The realization of every order n ≤ K is a leading block of the projection
    P^T H(1) Q (eq. 34); see :meth:`projected`.

    Attributes
    ----------
    data : ResponseData
        The pulse responses identified, (N, p, m).
    row_shifts : int ndarray, shape (r,)
        (0, j_1, ..., j_{r-1}) of eq. 16.
    col_shifts : int ndarray, shape (s,)
        (0, t_1, ..., t_{s-1}) of eq. 16.
    singular_values : ndarray, shape (k,)
        d_1 ≥ d_2 ≥ ... of H(0) (eq. 38); k = min(r p, s m) for the dense SVD and for the truncated one of a
        noisy H(0) (past K from the Gram matrix's eigenvalues: era.core.svd.truncated_svd), else the computed rank.
    P : ndarray, shape (r p, K)
        Leading K left singular vectors (eq. 22), K = :attr:`max_order`.
    Q : ndarray, shape (s m, K)
        Leading K right singular vectors (eq. 22).
    svd_method : {"dense", "truncated", "randomized"}
        The SVD that was taken.

    References
    ----------
    Juang & Pappa (1985), eqs. 16, 22, 34 and 38-39.

    Examples
    --------
    >>> from era.examples import paper_cases
    >>> ident = era.identify(paper_cases.case_1(), 40, 40)
    >>> ident.rows, ident.cols, ident.dt, ident.order()
    (40, 40, 0.05, 10)
    >>> model = ident.model(10)
    >>> print(np.round(model.frequency_hz, 4))
    [0.1592 0.3183 0.4775 0.6366 0.7958]
    """

    data: ResponseData
    row_shifts: np.ndarray
    col_shifts: np.ndarray
    singular_values: np.ndarray
    P: np.ndarray
    Q: np.ndarray
    svd_method: str
    _cache: dict = field(default_factory=dict, repr=False, compare=False)
    _lock: threading.Lock = field(default_factory=threading.Lock, repr=False, compare=False)

    def __getstate__(self) -> dict:
        """Pickled without its lock and its projection cache (rebuilt on demand): an identification can go to
        and come from another process."""
        state = {k: v for k, v in self.__dict__.items() if k not in ("_cache", "_lock")}
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state, _cache={}, _lock=threading.Lock())

    @property
    def rows(self) -> int:
        return len(self.row_shifts)

    @property
    def cols(self) -> int:
        return len(self.col_shifts)

    @property
    def dt(self) -> float:
        return self.data.dt

    @property
    def max_order(self) -> int:
        """K, the largest order that can be realized: the numerical rank of H(0), or the kept rank."""
        return self.P.shape[1]

    def order(self, tol: float = 1e-12) -> int:
        """The rank n by the δ test (eqs. 38-39): the number of singular values with d_i / d_1 > tol.

        Parameters
        ----------
        tol : float, optional
            The δ threshold on d_i / d_1 (default 1e-12).
        """
        d = self.singular_values
        if d.size == 0 or d[0] == 0:
            return 0
        return int(min(np.count_nonzero(d / d[0] > tol), self.max_order))

    def _check_order(self, order) -> int:
        if isinstance(order, bool) or not isinstance(order, (int, np.integer)):
            raise OrderError(f"`order` must be a positive integer, got {order!r}.")
        order = int(order)
        if order < 1:
            raise OrderError(f"`order` must be at least 1, got {order}.")
        if order > self.max_order:
            k = self.max_order
            d = self.singular_values
            capped = self.svd_method != "dense" or (d.size > k and d[k] > max(self.P.shape[0], self.Q.shape[0])
                                                    * np.finfo(float).eps * d[0])
            if capped:
                raise OrderError(
                    f"Order {order} is above this identification's max_order, {k}: only the leading {k} singular "
                    f"triplets of H(0) were kept. Choose an order ≤ {k}, or identify again with a larger max_order "
                    f"(at most min(r·p, s·m) = {min(self.P.shape[0], self.Q.shape[0])}).")
            raise OrderError(
                f"Order {order} is above the numerical rank of H(0), {k}: the singular values past it are "
                f"round-off. Choose an order ≤ {k}.")
        return order

    def projected(self, order: int) -> np.ndarray:
        """P_n^T H(1) Q_n, shape (n, n): the leading block of the projection of H(1) on the singular vectors.

        Computed for the first n asked and kept; a larger n extends it to at least twice its size (capped at
        K), so a slider moving up costs a few products in all. H(1) is not held in memory: with consecutive
        column shifts its block columns are those of H(0) moved by one, so P^T H(1) = [(P^T H(0)) without its
        first block column, P^T Y(j_i + t_{s-1} + 1)] with P^T H(0) = D Q^T (the SVD), and only the last block
        column is new (K² s m instead of K r p s m work); other shifts rebuild H(1) from the data.

        Parameters
        ----------
        order : int
            n, at most :attr:`max_order`.
        """
        n = self._check_order(order)
        with self._lock:
            full = self._cache.get("projected")
            if full is None or full.shape[0] < n:
                k = n if full is None else min(max(n, 2 * full.shape[0]), self.max_order)
                self._cache["projected"] = full = self._project_h1(k)
        return full[:n, :n]

    def _project_h1(self, k: int) -> np.ndarray:
        """P_k^T H(1) Q_k, (k, k): see :meth:`projected`."""
        P, Q, markov = self.P[:, :k], self.Q[:, :k], self.data.markov
        m = markov.shape[2]
        if not np.array_equal(self.col_shifts, np.arange(len(self.col_shifts))):
            return P.T @ (hankel.block_hankel(markov, self.row_shifts, self.col_shifts, 1) @ Q)
        last = markov[self.row_shifts + self.col_shifts[-1] + 1].reshape(-1, m)  # (r p, m): H(1)'s last block column
        return (self.singular_values[:k, None] * Q[m:].T) @ Q[:-m] + (P.T @ last) @ Q[-m:]

    def balanced(self, order: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """A, B, C and the state history W of the order-n realization of eq. 34 in balanced form.

        With D_n^{±1/2} splitting the singular values evenly between the two sides (a similarity transform
        of the paper's [P_d^# H(1) Q, Q^T E_m, E_p^T P_d]):
        A = D^{-1/2} P_n^T H(1) Q_n D^{-1/2}, B = D^{1/2} Q_n^T E_m, C = E_p^T P_n D^{1/2}, W = D^{1/2} Q_n^T.
        Shapes (n, n), (n, m), (p, n), (n, s m).

        Parameters
        ----------
        order : int
            n, at most :attr:`max_order`.
        """
        n = self._check_order(order)
        p, m = self.data.n_outputs, self.data.n_inputs
        root = np.sqrt(self.singular_values[:n])
        A = self.projected(n) / root[:, None] / root[None, :]
        W = root[:, None] * self.Q[:, :n].T
        C = self.P[:p, :n] * root[None, :]
        return A, W[:, :m].copy(), C, W

    def model(self, order: int, *, uncertainty: bool = True, records=None) -> ModalModel:
        """The ERA model of order n (eq. 34 in balanced form) and its modes: the one path every caller takes
        (the slider, the stabilization diagram, explain). Equal to ``realize(order)``.

        Parameters
        ----------
        order : int
            n.
        uncertainty : bool
            Compute each mode's frequency_std_hz and damping_std (era.core.uncertainty; 1.5-4× the time of the
            model without them, most at high orders with many outputs·inputs). False leaves them NaN; poles
            with a close neighbour still get theirs computed internally to decide which modes are repeated
            (era.core.decomposition.repeated_clusters).
        records : (n_b, N, p, m) array, optional
            The independent records whose mean is ``data.markov``: the covariance comes from their scatter
            (era.core.uncertainty.record_covariance) instead of from residual blocks of the mean. Default
            ``data.records`` when it holds at least era.core.uncertainty.MIN_RECORDS records (:meth:`records_used`);
            the model's ``uncertainty_source`` says which was used.

        Raises
        ------
        era.OrderError
            For an order that is not a positive integer or is above :attr:`max_order`.
        """
        return self._model(order, uncertainty, records)[0]

    def _model(self, order, uncertainty, records=None):
        """:meth:`model`, and what computing standard deviations for some of its modes later needs: the
        decomposition before the repeated modes were aligned, the model's mode order as indices into it, and
        the clusters (stabilization computes them for its stable poles only)."""
        n = self._check_order(order)
        d = self.data
        A, B, C, raw, dec, clusters, f_std, d_std = self.decomposed(n, uncertainty, records)
        W = (np.sqrt(self.singular_values[:n]), self.Q[:, :n])
        model = build_model(A, B, C, W, d.dt, self.row_shifts, self.col_shifts, d.outputs, d.inputs, "ERA",
                            dec=dec, frequency_std_hz=f_std if uncertainty else None,
                            damping_std=d_std if uncertainty else None,
                            uncertainty_source=self.uncertainty_source(records) if uncertainty else "")
        model = with_points(model, d.meta)  # the struck points' shapes too, where the inputs' points are known
        return model, raw, mode_order(dec.z, d.dt), clusters

    def decomposed(self, n: int, uncertainty: bool, records=None, histories: bool = True):
        """The balanced order-n realization A (n, n), B (n, m), C (p, n) and its modes: ``raw`` as the
        eigensolver gives them, ``dec`` with the repeated modes aligned (era.core.decomposition.align_repeated), the
        clusters, and frequency_std_hz, damping_std (modes,) in dec's order (NaN where not computed). Without
        ``histories`` the modal histories are not formed (era.core.sweep forms those of many orders together)."""
        d = self.data
        p, m = d.n_outputs, d.n_inputs
        root = np.sqrt(self.singular_values[:n])
        A = self.projected(n) / root[:, None] / root[None, :]
        C = self.P[:p, :n] * root[None, :]
        B = (root[:, None] * self.Q[:m, :n].T).copy()
        W = (root, self.Q[:, :n]) if histories else None  # W = D^{1/2} Q_n^T, not formed (balanced())
        raw = decompose(A, B, C, W)
        modes = raw.z.size
        want = np.ones(modes, dtype=bool) if uncertainty else cluster_candidates(raw.z, raw.is_pair)
        f_std, d_std = np.full(modes, np.nan), np.full(modes, np.nan)
        clusters = []
        if want.any():
            z_cov = np.full((modes, 2, 2), np.nan)
            z_cov[want] = self.pole_covariance(n, raw, np.flatnonzero(want), records).z_cov
            clusters = repeated_clusters(raw.z, raw.is_pair, np.sqrt(z_cov[:, 0, 0] + z_cov[:, 1, 1]), d.dt)
            f_std, d_std = modal_std(raw.z, z_cov, d.dt)
        for idx in clusters:  # a repeated mode: the cluster's largest
            f_std[idx], d_std[idx] = np.max(f_std[idx]), np.max(d_std[idx])
        return A, B, C, raw, align_repeated(raw, clusters), clusters, f_std, d_std

    def mode_std(self, order: int, raw: ModalDecomposition, modes, clusters=()) -> tuple[np.ndarray, np.ndarray]:
        """frequency_std_hz and damping_std of some modes of the order-n decomposition ``raw`` (indices
        ``modes``), as :meth:`model` gives them: a member of a repeated cluster gets the cluster's largest
        (era.core.mode_uncertainty.mode_std)."""
        return mode_uncertainty.mode_std(self, order, raw, modes, clusters)

    def shape_scatter(self, order: int, modes=None) -> np.ndarray:
        """Expected MAC deficit E[1 - MAC(φ̂_j, φ_j)] of each shape of ``model(order)``: the scatter the data leave
        in the shape, to first order (era.core.mode_uncertainty.shape_scatter for how). Cost: n pole functionals per
        mode, so it is not part of :meth:`model`; ``modes`` indexes the model's modes (default all).

        Parameters
        ----------
        order : int
            n.
        modes : sequence of int, optional
            Indices into the model's modes (default all).

        Returns
        -------
        (len(modes),) fractions in [0, 1]; the MAC between the estimate and the truth is about 1 minus this.
        """
        n = self._check_order(order)
        _, raw, perm, clusters = self._model(n, False)
        return mode_uncertainty.shape_scatter(self, n, raw, perm, clusters, modes)

    def records_used(self, records=None) -> np.ndarray | None:
        """The records whose scatter gives the covariance: ``records`` if given (n_b, N, p, m), else
        ``data.records`` when it holds at least uncertainty.MIN_RECORDS of them, else None (residual blocks)."""
        return mode_uncertainty.records_used(self, records)

    def uncertainty_source(self, records=None) -> str:
        """"σ from N records" or "σ from one record's residuals": which covariance :meth:`model` uses.

        Parameters
        ----------
        records : ndarray, shape (n_b, N, p, m), optional
            As in :meth:`model`.
        """
        used = self.records_used(records)
        segments = records is None and self.data.meta.get("records_are") == "segments"
        return source_label(0 if used is None else used.shape[0], segments=segments)

    def pole_covariance(self, order: int, dec: ModalDecomposition, modes=None,
                        records=None) -> PoleCovariance:
        """First-order covariance of (Re z, Im z) of the given modes of the order-n decomposition ``dec``
        (from :func:`era.core.decomposition.decompose` of :meth:`balanced`): see uncertainty. ``modes`` indexes dec
        (default all); ``records`` as in :meth:`model` (default ``data.records`` if there are enough)."""
        return mode_uncertainty.pole_covariance(self, self._check_order(order), dec, modes, records)

    def realize(self, order: int | None = None, method: str = "ERA") -> ModalModel:
        """The realization of the given order and its modes.

        Parameters
        ----------
        order : int, optional
            n; default :meth:`order` with δ = 1e-12.
        method : "ERA", "A1" or "A2"
            "ERA": the minimum realization of eq. 34 (balanced form, state dimension n).
            "A1" (eq. 19): [H(1) H^#, H(0) E_m, E_p^T], state dimension r·p.
            "A2" (eq. 20): [H^# H(1), E_m, E_p^T H(0)], state dimension s·m.
            H^# = Q_n D_n^{-1} P_n^T (eq. 27). A1 and A2 are NOT minimal: besides the n modes of the data
            they carry r·p - n (or s·m - n) eigenvalues at or near zero, reported as real poles of damping
            ratio 1. They reproduce the data but the paper does not recommend them; they are here to compare.

        Returns
        -------
        ModalModel

        Raises
        ------
        era.OrderError
            For an order that is not a positive integer or is above :attr:`max_order`.
        era.EraError
            For a method other than "ERA", "A1" and "A2".
        """
        if order is None:
            order = max(self.order(), 1)
        method = str(method).upper()
        d = self.data
        if method == "ERA":
            return self.model(order)
        if method not in ("A1", "A2"):
            raise EraError(f"`method` must be 'ERA', 'A1' or 'A2', got {method!r}.")
        n = self._check_order(order)
        h0 = hankel.block_hankel(d.markov, self.row_shifts, self.col_shifts, 0)
        h1 = hankel.block_hankel(d.markov, self.row_shifts, self.col_shifts, 1)
        h_pinv = (self.Q[:, :n] / self.singular_values[:n]) @ self.P[:, :n].T  # (s m, r p), eq. 27
        p, m = d.n_outputs, d.n_inputs
        if method == "A1":
            A, B, C, W = h1 @ h_pinv, h0[:, :m].copy(), np.eye(h0.shape[0])[:p], h0
        else:
            A, B, C, W = h_pinv @ h1, np.eye(h0.shape[1])[:, :m], h0[:p].copy(), h_pinv @ h0
        return with_points(build_model(A, B, C, W, d.dt, self.row_shifts, self.col_shifts, d.outputs, d.inputs,
                                       method), d.meta)


def _count(value, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise HankelError(f"`{name}` must be a positive integer, got {value!r}.")
    return int(value)


def identify(data: ResponseData, rows: int, cols: int, row_shifts=None, col_shifts=None, *,
             max_order: int | None = None, svd_method: str = "auto") -> Identification:
    """Build H(0) and H(1) (eq. 16), take ONE singular value decomposition of H(0) (eq. 22) and project H(1).

    Parameters
    ----------
    data : ResponseData
        Y(k) = C A^k B, shape (N, p, m), sampling interval Δτ = data.dt seconds.
    rows : int
        r, the number of block rows. H(0) is (r p) × (s m).
    cols : int
        s, the number of block columns.
    row_shifts : sequence of r - 1 increasing positive ints, optional
        j_1, ..., j_{r-1} (default j_i = i).
    col_shifts : sequence of s - 1 increasing positive ints, optional
        t_1, ..., t_{s-1} (default t_i = i). The column shifts are also the times of the ideal modal
        histories of γ (eq. 43).
    max_order : int, optional
        The largest order needed. Default: the numerical rank of H(0) (singular values above
        max(r p, s m)·ε·d_1). With the randomized SVD, the rank computed (default 200).
    svd_method : {"auto", "dense", "truncated", "randomized"}, optional
        "auto" takes the truncated SVD of rank max_order (era.core.svd.truncated_svd) when max_order is at most
        era.core.svd.TRUNCATED_RANK_FRACTION of min(shape) of H(0) — the sweep of orders 2..120 on a 900 × 2392
        H(0) then costs less than half of one dense SVD; else the dense LAPACK SVD unless min(shape)²·max(shape)
        exceeds era.core.svd.DENSE_SVD_WORK_LIMIT, then the randomized SVD of rank max_order.

    Returns
    -------
    Identification
        The SVD of H(0) and the data; ``realize(n)`` gives the model of any order n ≤ its ``max_order``.

    Raises
    ------
    era.HankelError
        For counts or shifts that are not positive and increasing, fewer than N ≥ j_{r-1} + t_{s-1} + 2
        samples, or an H(0) of more than era.core.hankel.MAX_HANKEL_ELEMENTS elements.
    era.EraError
        When ``data`` is not an era.ResponseData, or for an unknown ``svd_method``.

    References
    ----------
    Juang, J.-N. and Pappa, R. S. (1985), An eigensystem realization algorithm for modal parameter
    identification and model reduction, Journal of Guidance, Control, and Dynamics 8(5), 620-627:
    eqs. 16 (the block Hankel matrices), 22 (the SVD), 34 (the realization).

    Examples
    --------
    The paper's Case I (eqs. 58-60): one sensor, five modes s_j = -0.01 j + i j rad/s. H(0) of 40 × 40
    blocks has rank 10, and the realization of order 10 gives the five eigenvalues back:

    >>> from era.examples import paper_cases
    >>> ident = era.identify(paper_cases.case_1(), rows=40, cols=40)
    >>> ident.max_order, ident.svd_method
    (10, 'dense')
    >>> model = ident.realize(10)
    >>> print(np.round(model.eigenvalues, 4))
    [-0.01+1.j -0.02+2.j -0.03+3.j -0.04+4.j -0.05+5.j]
    """
    if not isinstance(data, ResponseData):
        raise EraError(f"`data` must be an era.ResponseData, got {type(data).__name__}; wrap your (N, p, m) "
                       "array as era.ResponseData(markov=Y, dt=...).")
    r, s = _count(rows, "rows"), _count(cols, "cols")
    js = hankel.shifts(r, row_shifts, "row_shifts")
    ts = hankel.shifts(s, col_shifts, "col_shifts")
    n_samples, p, m = data.markov.shape
    hankel.check_hankel_size(n_samples, p, m, js, ts)
    if max_order is not None:
        max_order = _count(max_order, "max_order")
    method = svd.choose_method((r * p, s * m), svd_method, max_order)
    if method == "truncated" and hankel.is_consecutive(js, ts):
        # its products by FFT, or by BLAS on H(0) formed beside the eigenvalues (era.core.svd.truncated_svd)
        h0 = hankel.HankelOperator(data.markov, r, s)
    else:
        h0 = hankel.block_hankel(data.markov, js, ts, 0)
    if method == "dense":
        P, d, Q = svd.dense_svd(h0)
    elif method == "truncated":
        threads = blas_threads()
        with single_threaded_blas():  # one limit for both: lifting it between them costs 2-4 ms (era.core.blas)
            P, d, Q = svd.truncated_svd(h0, max_order or min(200, *h0.shape),
                                        hankel.gram(data.markov, js, ts, h0, threads), threads)
    else:
        P, d, Q = svd.randomized_svd(h0, max_order or min(200, *h0.shape))
    # keep the numerical rank (and no more than max_order) of the singular triplets computed
    tol = max(h0.shape) * np.finfo(float).eps * (d[0] if d.size else 0.0)
    keep = int(np.count_nonzero(d[:P.shape[1]] > tol))
    if max_order is not None:
        keep = min(keep, max_order)
    del h0
    P, Q = np.ascontiguousarray(P[:, :keep]), np.ascontiguousarray(Q[:, :keep])
    return Identification(data=data, row_shifts=js, col_shifts=ts, singular_values=d, P=P, Q=Q, svd_method=method)
