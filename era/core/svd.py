"""The singular value decomposition of H(0) (eq. 22): dense LAPACK, a truncated one of the leading triplets only
when the largest order is far below min(shape), or a randomized one for very large matrices."""

from __future__ import annotations

import contextlib
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.linalg

from .blas import blas_threads, blas_threads_limited, single_threaded_blas, workers_can_rest
from ..errors import EraError
from .lapack import apply_reflectors, reflector_blocks, stein, sterf

#: H(0) switches to the randomized path when min(shape)² · max(shape) exceeds this (about 3-5 s of dense
#: gesdd on one core of this machine; 900 × 2392 is 1.9e9 and takes about 0.6 s).
DENSE_SVD_WORK_LIMIT = 8e9

#: "auto" takes the truncated SVD when the rank asked is at most this fraction of min(shape) ("far below"):
#: its cost, the Gram matrix (era.core.hankel.gram: a recursion for a block Hankel H(0)) and one tridiagonal
#: reduction of min(shape)², is then at most about 0.6 of gesdd's on a square H(0) (792 × 798: 0.48 at rank
#: 200, 0.70 at rank 300) and less on an oblong one (900 × 2392 at rank 120: 0.15; tests/bench/bench_sweep.py).
TRUNCATED_RANK_FRACTION = 1 / 3

#: ... and min(shape) at most this: the Gram matrix's eigensolution grows as min(shape)³ (above it, randomized).
TRUNCATED_MAX_SIDE = 6000

#: truncated_svd reduces a Gram matrix of at least this order to tridiagonal form with the caller's BLAS threads
#: even when OpenBLAS's workers cannot be stopped afterwards (era.core.blas.workers_can_rest: another Python thread
#: runs); below it the reduction is too short for that: on 900 × 2392 two threads take it from 41 to 26 ms, but
#: the workers then spin into the sweep's threads 35 ms later and cost them more (the 2-thread sweep 245 → 250
#: ms); on 1280 × 2000 they take it from ~120 to ~75 ms, ahead of 70 ms of one-thread work
#: (tests/bench/bench_sweep.py). When they can be stopped, every order is reduced with the caller's threads.
THREADED_REDUCTION_MIN = 1000

#: truncated_svd skips its Rayleigh-Ritz step when the smallest eigenvalue kept of the Gram matrix is at least
#: this fraction of the largest (every singular value kept ≥ 1e-3 d_1, as in a noisy measured H(0)).
GRAM_DIRECT_MIN = 1e-6

#: With two or more BLAS threads, stein runs in two threads, this share of the values (the smallest) in the
#: calling one and the rest in the other (tests/bench/bench_sweep.py's Gram matrices: at 0.5 the calling
#: thread's part, slower per vector, finished last).
STEIN_LOWER_SHARE = 0.45

#: ... and refuses the split when a vector of the lower part loses more than this fraction of its norm to the
#: projection on the upper part (inverse iteration did not separate the two parts): one stein instead.
STEIN_PART_LOSS = 1e-8


def dense_svd(h: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Thin SVD ``h = P diag(d) Q^T`` with LAPACK's divide-and-conquer driver (gesdd).

    Falls back to the slower but more robust gesvd driver when gesdd does not converge.

    Returns
    -------
    P : (rows, k), d : (k,) descending, Q : (cols, k) with k = min(rows, cols).
    """
    try:
        u, d, vt = scipy.linalg.svd(h, full_matrices=False, lapack_driver="gesdd", check_finite=False)
    except np.linalg.LinAlgError:
        u, d, vt = scipy.linalg.svd(h, full_matrices=False, lapack_driver="gesvd", check_finite=False)
    return u, d, vt.T


def randomized_svd(
    h: np.ndarray, rank: int, oversample: int | None = None, power_iterations: int = 4, seed: int = 0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Leading ``rank`` singular triplets of ``h`` by randomized subspace iteration (Halko, Martinsson & Tropp 2011).

    A Gaussian test matrix of ``rank + oversample`` columns is pushed through ``power_iterations`` rounds of
    ``h h^T`` with re-orthonormalisation, then the small projected matrix is decomposed exactly. For the steep
    singular value spectra of structural pulse responses the leading values agree with the dense SVD to about
    machine precision (tests/test_svd.py); the seed makes the result repeatable.

    Returns
    -------
    P : (rows, rank), d : (rank,) descending, Q : (cols, rank).
    """
    rows, cols = h.shape
    rank = int(min(rank, rows, cols))
    width = min(rank + (oversample if oversample is not None else max(20, rank // 2)), rows, cols)
    rng = np.random.default_rng(seed)
    basis, _ = np.linalg.qr(h @ rng.standard_normal((cols, width)))
    for _ in range(power_iterations):
        z, _ = np.linalg.qr(h.T @ basis)
        basis, _ = np.linalg.qr(h @ z)
    u_small, d, vt = np.linalg.svd(basis.T @ h, full_matrices=False)
    return (basis @ u_small[:, :rank]), d[:rank], vt[:rank].T


def truncated_svd(h: np.ndarray, rank: int, gram: np.ndarray | None = None,
                  threads: int | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Leading ``rank`` singular triplets of ``h`` from the Gram matrix of its shorter side, refined by one
    Rayleigh-Ritz step on ``h`` itself.

    For ``h`` of shape (a, b) with a ≤ b: G = h h^T (a × a, one BLAS-3 product of half the work of the SVD's
    bidiagonalization), its ``rank`` leading eigenvectors V (:func:`gram_eigen`), then the exact
    SVD of the small projection V^T h = U S W^T gives P = V U, d = S, Q = W. This is the Rayleigh-Ritz step of a
    subspace method (Halko, Martinsson & Tropp 2011, sec. 5) with the Gram eigenvectors as the subspace:

    * the singular values and Q come from ``h``, not from G, so they carry round-off ε·d_1 (as gesdd's), not
      ε·d_1²/d_i: a singular value of 1e-14·d_1 (a noise-free record past its rank) is still seen as one, and
      the δ test (eqs. 38-39) works as on the dense path. When every value kept is ≥ 1e-3 d_1 (a noisy
      H(0): GRAM_DIRECT_MIN) the Gram values are already that accurate and Q = h^T V / d, without the step;
    * the subspace spanned by the leading n of them, which is all that a realization of order n uses, is the
      dense one's to about ε·d_1² / (d_n² - d_{n+1}²) — 1e-12 relative on the poles of the benchmarks'
      noisy H(0) (tests/bench/bench_sweep.py compares every stable pole with the dense path's).

    Unlike subspace iteration from a random start (:func:`randomized_svd`), it needs no gap after the last
    triplet kept: the flat noise floor of a measured H(0) (d_120 / d_121 = 1.0003 in the benchmark) is where
    power iterations stall. Lanczos (scipy.sparse.linalg.svds with PROPACK or ARPACK) is as accurate but, at
    rank 120, is no faster than gesdd on these sizes.

    ``h`` may also be a linear operator with ``h.T @ v`` (era.core.hankel.HankelOperator: products by FFT, without
    forming H(0)); when it has a ``prepare()`` (one that forms H(0) for BLAS products), that runs in a second
    thread while the first finds the eigenvalues (:func:`gram_eigen`'s ``beside``). ``gram``: the Gram matrix
    of the shorter side (its upper triangle) when the caller has it (era.core.hankel.gram builds that of a block
    Hankel matrix by a recursion, without the product); its memory is reused, so it is lost to the caller.
    ``threads``: the BLAS threads to use (default: as the caller has; a caller already inside a one-thread
    limit passes its own count).

    BLAS runs with one thread (era.core.blas: the stabilization's own threads follow) except in the tridiagonal
    reduction of the Gram matrix, which takes the caller's threads when OpenBLAS's idle workers can be stopped
    after it (era.core.blas.rest_blas_workers) or the Gram matrix's order is ≥ THREADED_REDUCTION_MIN. With two or
    more threads the steps after it go in two Python threads with one BLAS thread each (:func:`gram_eigen`,
    :func:`_product_t`), so no OpenBLAS worker is left spinning.

    Returns
    -------
    P : (rows, rank), d : descending, Q : (cols, rank). d has the ``rank`` values of the triplets and, on the
    direct route (every value kept ≥ 1e-3 d_1), all min(rows, cols) values: the ones past the rank from the Gram
    matrix's eigenvalues, for the singular value plot and the order suggestion of a noisy H(0). When the kept
    values reach round-off (a noise-free record), the ones past them are round-off too and are left out.
    """
    rows, cols = h.shape
    threads = blas_threads() if threads is None else threads
    with single_threaded_blas():
        threaded = min(rows, cols) >= THREADED_REDUCTION_MIN or workers_can_rest()
        P, d, Q = _truncated_svd(h if rows <= cols else h.T, int(min(rank, rows, cols)), gram,
                                 threads if threaded else 1, threads, getattr(h, "prepare", None))
    return (P, d, Q) if rows <= cols else (Q, d, P)


def _truncated_svd(h, rank: int, gram: np.ndarray | None, threads: int, workers: int,
                   prepare=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`truncated_svd` of a wide ``h`` (rows ≤ cols): the tridiagonal reduction with ``threads`` BLAS
    threads; with ``workers`` > 1 the steps after it in two threads of one BLAS thread each, else with
    ``threads``. ``prepare``: run beside sterf (:func:`gram_eigen`'s ``beside``)."""
    if gram is None:
        gram = h @ h.T if isinstance(h, np.ndarray) else h @ (h.T @ np.eye(h.shape[0]))
    every, v = gram_eigen(gram, rank, threads, workers, overwrite=True, beside=prepare)
    del gram
    w = every[:rank]
    if w[-1] >= GRAM_DIRECT_MIN * w[0]:
        # every value kept is ≥ 1e-3 d_1: the Gram route alone is accurate to ε d_1²/d_k² ≤ 1e-10 (relative,
        # values and Q's orthogonality), and the small SVD, slower with threads than the rest, is not needed;
        # the values past the rank come with it (to ε d_1²/d_i² relative, 1e-4 at d_i = 1e-6 d_1)
        d = np.sqrt(np.maximum(every, 0.0))
        return np.ascontiguousarray(v), d, _product_t(h, v, threads, workers) / d[:rank]
    u_small, d, wt = scipy.linalg.svd((h.T @ v).T, full_matrices=False, lapack_driver="gesdd", check_finite=False)
    return v @ u_small, d, np.ascontiguousarray(wt.T)


def _product_t(h, v: np.ndarray, threads: int, workers: int) -> np.ndarray:
    """h^T v (h (a, b) a matrix or an operator, v (a, k)): with ``workers`` > 1, v's columns in two halves in
    two threads with one BLAS thread each (no OpenBLAS worker left spinning: stopping one costs 1.6-3.2 ms
    after a threaded product, era.core.blas), else one product with ``threads`` BLAS threads."""
    if workers < 2:
        with blas_threads_limited(threads):  # for a dense H(0) one BLAS-3 product (by FFT: small ones)
            return h.T @ v
    with single_threaded_blas(), ThreadPoolExecutor(1) as helper:
        return np.hstack(_by_halves(lambda part: h.T @ part, v, helper))


def _by_halves(fn, x: np.ndarray, helper: ThreadPoolExecutor | None) -> list:
    """[fn(x[:, :half]), fn(x[:, half:])], the second half in the ``helper`` thread meanwhile; [fn(x)] without
    a helper or for one column."""
    half = x.shape[1] // 2 if helper is not None else 0
    if not half:
        return [fn(x)]
    pending = helper.submit(fn, x[:, half:])
    return [fn(x[:, :half]), pending.result()]


def gram_eigen(gram: np.ndarray, rank: int, threads: int | None = None, workers: int = 1, *,
               overwrite: bool = False, beside=None) -> tuple[np.ndarray, np.ndarray]:
    """All eigenvalues of the symmetric ``gram`` (a, a), descending, and the eigenvectors (a, rank) of the
    leading ``rank``. Only the upper triangle of a C-ordered ``gram`` is read (era.core.hankel.gram builds no more);
    ``overwrite``: the reduction may work in ``gram``'s memory (no copy; its contents are then lost).

    One tridiagonal reduction (LAPACK sytrd) for both, its eigenvalues by sterf (a² work),
    the leading eigenvectors by inverse iteration on those eigenvalues (:func:`_tridiagonal_vectors`), and back
    to ``gram``'s basis by the reduction's reflectors (ormqr) — what syevr does for the subset, plus every
    eigenvalue for a² more work. ``threads``: BLAS threads for the reduction, and for the reflectors with
    one worker (default: as the caller has); ormqr's workspace is its optimum, 64 k + 65 · 64 for k vectors.

    ``workers`` > 1: a second thread takes what does not wait for sterf (sequential, one core), the reflectors'
    block factors (era.core.lapack.reflector_blocks, the first part of ormqr's work), and half of the inverse
    iteration (:func:`_stein_in_parts`); then the factors are applied to the two halves of the vectors
    (:func:`_reflected`), all with one BLAS thread. On tests/bench/bench_sweep.py's Gram matrices with 2
    threads, gram_eigen less its reduction took 33 → 22 ms (900 × 900) and 50 → 40 ms (1280 × 1280) against
    one thread's steps with a threaded ormqr (sessions 8-9). ``beside``: a callable of the
    caller's that the helper runs after the factors, while sterf still runs (the sweep's dense H(0), built
    there: era.core.hankel.HankelOperator.prepare); with one worker it runs first.
    """
    a = gram.shape[0]
    lapack = scipy.linalg.lapack
    try:
        lwork = int(lapack.dsytrd_lwork(a, lower=1)[0])
        # one limit for the reduction and, with one worker, the reflectors (sterf and stein use no BLAS threads)
        with blas_threads_limited(threads) if threads else contextlib.nullcontext():
            # gram's transpose is a Fortran view whose lower triangle is gram's upper one: no transposing copy
            c, diag, off, tau, info = lapack.dsytrd(np.asarray(gram).T, lower=1, lwork=max(lwork, 1),
                                                    overwrite_a=overwrite)
            if info != 0:
                raise np.linalg.LinAlgError(f"sytrd info {info}")
            v = c[1:, :a - 1]  # G = H T H^T with H = diag(1, H'), H' the reflectors v (sytrd)
            two = workers > 1 and a > 2  # a helper thread, with one BLAS thread each (era.core.blas: OpenBLAS's
            # workers would take the second core from them)
            with single_threaded_blas() if two else contextlib.nullcontext(), \
                    ThreadPoolExecutor(1) if two else contextlib.nullcontext() as helper:
                pending = helper.submit(_factors_then, v, tau, beside) if helper else None  # beside sterf
                if beside is not None and not helper:
                    beside()
                every = _tridiagonal_values(diag, off)
                y = _tridiagonal_vectors(diag, off, every[a - rank:], helper)
                blocks = pending.result() if pending else None
                if a > 1:
                    y = np.vstack([y[:1], _reflected(v, tau, blocks, y[1:], helper)])
        return every[::-1], np.ascontiguousarray(y[:, ::-1])
    except (np.linalg.LinAlgError, ValueError):  # not expected; the library's driver as a fallback
        if overwrite:  # gram's memory may hold the reduction now: nothing to fall back on
            raise
        w, v = scipy.linalg.eigh(gram, lower=False, subset_by_index=[a - rank, a - 1], driver="evr",
                                 check_finite=False)
        every = np.concatenate([w[::-1], scipy.linalg.eigvalsh(gram, lower=False, subset_by_index=[
            0, a - rank - 1])[::-1]]) if rank < a else w[::-1]
        return every, np.ascontiguousarray(v[:, ::-1])


def _reflected(v: np.ndarray, tau: np.ndarray, blocks: list | None, y: np.ndarray,
               helper: ThreadPoolExecutor | None = None) -> np.ndarray:
    """H' y for the reflectors ``v``, ``tau`` of sytrd and ``y`` (a - 1, k): by their block factors
    (era.core.lapack.apply_reflectors; with a ``helper`` thread, the columns in two halves, one BLAS thread each, so
    no OpenBLAS worker is left spinning after it), else by ormqr."""
    if blocks is not None:
        parts = _by_halves(lambda part: apply_reflectors(v, blocks, part), y, helper)
        if all(x is not None for x in parts):
            return np.hstack(parts) if len(parts) > 1 else parts[0]
    out, _, info = scipy.linalg.lapack.dormqr("L", "N", v, tau, y, lwork=64 * y.shape[1] + 4160)
    if info != 0:
        raise np.linalg.LinAlgError(f"ormqr info {info}")
    return out


def _factors_then(v: np.ndarray, tau: np.ndarray, beside=None):
    """The reflectors' block factors (era.core.lapack.reflector_blocks, without the GIL), then ``beside()``."""
    blocks = reflector_blocks(v, tau)
    if beside is not None:
        beside()
    return blocks


def _tridiagonal_values(diag: np.ndarray, off: np.ndarray) -> np.ndarray:
    """All eigenvalues (a,), ascending, of the symmetric tridiagonal matrix (``diag`` (a,), ``off`` (a - 1,)) by
    sterf: era.core.lapack's (without the GIL), else scipy's wrapper."""
    every = sterf(diag, off)
    return every if every is not None else scipy.linalg.eigvalsh_tridiagonal(diag, off, lapack_driver="sterf",
                                                                             check_finite=False)


def _tridiagonal_vectors(diag: np.ndarray, off: np.ndarray, values: np.ndarray,
                         helper: ThreadPoolExecutor | None = None) -> np.ndarray:
    """Eigenvectors (a, k) of the symmetric tridiagonal matrix (``diag`` (a,), ``off`` (a - 1,)) for its
    eigenvalues ``values`` (k,), ascending, as sterf gives them: inverse iteration (LAPACK stein), which
    re-orthogonalises the vectors of close eigenvalues (the flat noise floor of a measured H(0)).

    Given the eigenvalues, that is a k a work: 10 ms for 120 of 900 where MRRR on the subset (stemr, which
    finds the subset's eigenvalues again by bisection) takes 29 ms, as orthogonal (1e-14 to 3e-13)
    (tests/core/test_truncated_svd.py). With a ``helper`` thread, in two parts (:func:`_stein_in_parts`).
    If stein does not converge, MRRR."""
    a, k = diag.size, values.size
    if a > 1:
        y = _stein_in_parts(diag, off, values, helper) if helper is not None else None
        if y is not None:
            return y
        block, split = np.ones(a, dtype=np.int32), np.zeros(a, dtype=np.int32)
        split[0] = a  # one block: stein's inverse iteration copes with a tiny off-diagonal
        y, info = scipy.linalg.lapack.dstein(diag, off, values, block, split)
        if info == 0 and np.all(np.isfinite(y)):
            return y[:, :k]
    _, y = scipy.linalg.eigh_tridiagonal(diag, off, select="i", select_range=(a - k, a - 1),
                                         check_finite=False, lapack_driver="stemr")
    return y


def _stein_in_parts(diag: np.ndarray, off: np.ndarray, values: np.ndarray,
                    helper: ThreadPoolExecutor) -> np.ndarray | None:
    """:func:`_tridiagonal_vectors` in two threads, this one and ``helper``: stein (:func:`era.core.lapack.stein`,
    without the GIL) on the smallest STEIN_LOWER_SHARE of ``values`` and on the rest at the same time, then the
    lower part's vectors made orthogonal to the upper part's (projected out, normalised). Run it with one
    BLAS thread (era.core.blas.single_threaded_blas): OpenBLAS's idle workers would take a core from the two.

    stein re-orthogonalises only within its call, so across the split the two parts are orthogonal only as far
    as inverse iteration separates their eigenvalues: their inner products were 1e-12 at most on the
    benchmark's spectra (tests/bench/bench_sweep.py), and each vector equals one stein's to 1e-15. When a
    vector loses more than STEIN_PART_LOSS of its norm to the projection (eigenvalues that the split cut so
    close that the parts share directions) the result is refused: None, and the caller runs one stein.
    Returns (a, k) in Fortran order, as the reflectors take it."""
    k = values.size
    cut = int(round(STEIN_LOWER_SHARE * k))
    if not 0 < cut < k:
        return None
    pending = helper.submit(stein, diag, off, values[cut:])
    lower = stein(diag, off, values[:cut])
    upper = pending.result()
    if lower is None or upper is None:
        return None
    out = np.empty((diag.size, k), order="F")
    out[:, cut:] = upper
    for _ in range(2):  # Gram-Schmidt with re-orthogonalisation, the second pass only if the first removed more
        # than round-off: after removing components c the cross products are ~ c ε
        cross = upper.T @ lower
        lower = lower - upper @ cross
        norm = np.linalg.norm(lower, axis=0)
        if not np.all(norm >= 1 - STEIN_PART_LOSS):
            return None
        lower /= norm
        if np.abs(cross).max() <= 1e-8:
            break
    out[:, :cut] = lower
    return out


def choose_method(shape: tuple[int, int], method: str, rank: int | None = None) -> str:
    """``"dense"``, ``"truncated"`` or ``"randomized"`` for ``method`` in {"auto", "dense", "truncated",
    "randomized"}.

    "auto": the truncated SVD when ``rank`` (the largest order asked) is at most TRUNCATED_RANK_FRACTION of
    min(shape) and min(shape) ≤ TRUNCATED_MAX_SIDE; else dense below DENSE_SVD_WORK_LIMIT, randomized above.
    """
    if method not in ("auto", "dense", "truncated", "randomized"):
        raise EraError(f"`svd` must be 'auto', 'dense', 'truncated' or 'randomized', got {method!r}.")
    if method != "auto":
        return method
    small, large = sorted(shape)
    if rank is not None and rank <= TRUNCATED_RANK_FRACTION * small and small <= TRUNCATED_MAX_SIDE:
        return "truncated"
    return "dense" if small * small * large <= DENSE_SVD_WORK_LIMIT else "randomized"
