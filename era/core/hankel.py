"""The generalized block Hankel matrix of eq. 16, with arbitrary row and column shifts."""

from __future__ import annotations

import contextlib
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.fft
import scipy.sparse.linalg

from .blas import single_threaded_blas
from ..errors import HankelError

#: Largest H(0) built, in matrix elements (8 bytes each): 2e8 elements is 1.6 GB, and H(1) is as large.
MAX_HANKEL_ELEMENTS = 200_000_000


def shifts(count: int, given, name: str) -> np.ndarray:
    """The shift sequence (0, j_1, ..., j_{count-1}) of eq. 16 as an int array of length ``count``.

    ``given`` holds the ``count - 1`` shifts after the leading 0 (the paper's j_i or t_i);
    None means the consecutive default j_i = i. ``count`` is a validated positive integer.
    """
    if given is None:
        return np.arange(count)
    arr = np.asarray(given)
    if arr.ndim != 1 or (arr.size and not np.issubdtype(arr.dtype, np.integer)):
        if arr.ndim == 1 and arr.size and np.all(np.mod(arr, 1) == 0):
            arr = arr.astype(int)
        else:
            raise HankelError(f"`{name}` must be a 1-D list of integers (sample counts), got {given!r}.")
    if arr.size != count - 1:
        raise HankelError(
            f"`{name}` has {arr.size} entries but {count - 1} are needed: one per block after the first "
            f"(the first block has shift 0)."
        )
    full = np.concatenate([[0], arr.astype(int)])
    if np.any(np.diff(full) <= 0):
        bad = int(np.argmax(np.diff(full) <= 0))
        raise HankelError(
            f"`{name}` must be strictly increasing positive integers; entry {bad} ({full[bad + 1]}) does not "
            f"exceed the one before it ({full[bad]})."
        )
    return full


def samples_needed(row_shifts: np.ndarray, col_shifts: np.ndarray) -> int:
    """Samples N that H(0) and H(1) need: Y(k) for k up to j_{r-1} + t_{s-1} + 1."""
    return int(row_shifts[-1] + col_shifts[-1] + 2)


def block_hankel(markov: np.ndarray, row_shifts: np.ndarray, col_shifts: np.ndarray, k: int = 0) -> np.ndarray:
    """H(k) of eq. 16: block (i, j) is Y(k + j_i + t_j).

    Parameters
    ----------
    markov : ndarray, shape (N, p, m)
        Y(0..N-1).
    row_shifts, col_shifts : int ndarray, shapes (r,) and (s,)
        (0, j_1, ..., j_{r-1}) and (0, t_1, ..., t_{s-1}).
    k : int
        The time shift (0 for H(0), 1 for H(1)).

    Returns
    -------
    ndarray, shape (r p, s m)
        A new C-contiguous array (the one copy the SVD needs).
    """
    n, p, m = markov.shape
    r, s = len(row_shifts), len(col_shifts)
    idx = k + row_shifts[:, None] + col_shifts[None, :]
    if idx.max() >= n:
        raise HankelError(f"H({k}) needs Y({idx.max()}) but only {n} samples are given.")
    out = np.empty((r, p, s, m))
    # One gather per block row writes straight into the output: no (r, s, p, m) temporary; with consecutive
    # column shifts the row is a slice of the data, copied once (7.3 instead of 8.6 ms for 1280 × 2000).
    slices = np.array_equal(col_shifts, np.arange(s))
    for i in range(r):
        out[i] = (markov[idx[i, 0]:idx[i, 0] + s] if slices else markov[idx[i]]).transpose(1, 0, 2)
    return out.reshape(r * p, s * m)


def check_hankel_size(n_samples: int, p: int, m: int, row_shifts: np.ndarray, col_shifts: np.ndarray) -> None:
    """Raise a HankelError that says what fits when the data or the memory limit cannot hold H(0), H(1)."""
    need = samples_needed(row_shifts, col_shifts)
    r, s = len(row_shifts), len(col_shifts)
    if need > n_samples:
        room = n_samples - 2  # j_{r-1} + t_{s-1} may be at most N - 2
        hint = ""
        if r > 1 and s > 1 and room >= 2 and row_shifts[-1] == r - 1 and col_shifts[-1] == s - 1:
            hint = f" With consecutive shifts, rows + cols may be at most {room + 2} (e.g. rows={(room + 2) // 2}, cols={(room + 2) - (room + 2) // 2})."
        raise HankelError(
            f"The Hankel matrices need {need} samples (largest row shift {row_shifts[-1]} + largest column "
            f"shift {col_shifts[-1]} + 2) but the data have {n_samples}. Use fewer rows/columns or smaller "
            f"shifts, or give longer records.{hint}"
        )
    elements = r * p * s * m
    if elements > MAX_HANKEL_ELEMENTS:
        raise HankelError(
            f"H(0) would be {r * p} × {s * m} = {elements:.3g} elements, above the limit of "
            f"{MAX_HANKEL_ELEMENTS:.3g} ({MAX_HANKEL_ELEMENTS * 8 / 1e9:.1f} GB each for H(0) and H(1)). "
            f"Reduce rows or cols so that rows·p × cols·m stays below it."
        )


def gram(markov: np.ndarray, row_shifts: np.ndarray, col_shifts: np.ndarray, h0, workers: int = 1) -> np.ndarray:
    """The Gram matrix of the shorter side of H(0) = ``h0``: H H^T (r p × r p) when r p ≤ s m, else H^T H.
    Only its upper triangle is meant to be read (era.core.svd.gram_eigen reads no more): with consecutive shifts the
    blocks below the diagonal blocks are left unset.

    With consecutive shifts (the default) it is built by the Hankel recursion instead of a product: block
    (i + 1, j + 1) of H H^T is block (i, j) plus Y(i + s) Y(j + s)^T minus Y(i) Y(j)^T (the window of column
    shifts slides by one sample), so only the first block row is a product and each further block row costs
    two products of rank m: r p · r p · m work instead of (r p)² s m / 2 for the product (about 1/100 of it
    for H(0) 900 × 2392). Its round-off, r additions of terms no larger than the entries, is of the order of
    the product's. The first block row, G_0j = Σ_k Y(k) Y(j + k)^T: by FFT when ``h0`` is a
    :class:`HankelOperator` whose products go that way, else lag by lag from the data
    (:func:`_first_gram_row`), without H(0) (also when ``h0`` is the dense H(0)). ``workers`` > 1: that first
    block row in two threads (by lags) when its blocks are large enough to gain (:data:`SPLIT_MIN`). Other
    shifts: ``h0 @ h0.T`` (or ``h0.T @ h0``).

    Returns
    -------
    (min(shape), min(shape)) ndarray, its upper triangle (with the diagonal blocks) the Gram matrix's.
    """
    rows, cols = h0.shape
    if not is_consecutive(row_shifts, col_shifts):
        return h0 @ h0.T if rows <= cols else h0.T @ h0
    y, r, s = markov, len(row_shifts), len(col_shifts)
    if rows > cols:  # H^T is the block Hankel matrix of the blocks Y(k)^T, rows and columns swapped
        y, r, s = markov.transpose(0, 2, 1), s, r
    fft = isinstance(h0, HankelOperator) and h0.by_fft
    two = not fft and workers > 1 and r * y.shape[1] ** 2 >= SPLIT_MIN
    with single_threaded_blas(), ThreadPoolExecutor(1) if two else contextlib.nullcontext() as helper:
        if fft:
            first = (h0 @ h0.first_block_row().T).T if rows <= cols else (h0.T @ h0.first_block_column()).T
        else:
            first = _first_gram_row(y, r, s, helper)
        return _sliding_gram(y, r, s, first)


#: gram's first block row, lag by lag, goes in two threads when r p² is at least this: 1280 × 2000 (r = 40,
#: p = 32) gains (5.3 → 3.0-3.2 ms); on 900 × 2392 (r = 100, p = 9) it goes by FFT (0.7 ms).
SPLIT_MIN = 20000


def _first_gram_row(y: np.ndarray, r: int, s: int, helper=None) -> np.ndarray:
    """G_0j = Σ_{k<s} Y(k) Y(j + k)^T for j < r, (p, r p), from the blocks ``y`` (N, p, m): with the data
    ordered (m, N, p) each lag j is m products of a (p × s) and an (s × p) slice of it, no copy of H(0)
    (5.4 ms one thread on 1280 × 2000, where building H(0) takes 7-9 ms and its product 4.7). With a
    ``helper`` thread, the lags in two halves."""
    p = y.shape[1]
    w = np.ascontiguousarray(y[:r + s - 1].transpose(2, 0, 1))  # (m, r + s - 1, p)
    lead = w[:, :s, :].transpose(0, 2, 1)
    out = np.empty((p, r * p))

    def lags(lo, hi):
        for j in range(lo, hi):
            out[:, j * p:(j + 1) * p] = np.matmul(lead, w[:, j:j + s, :]).sum(axis=0)

    pending = helper.submit(lags, r // 2, r) if helper is not None else None
    lags(0, r // 2 if pending else r)
    if pending:
        pending.result()
    return out


def _sliding_gram(y: np.ndarray, r: int, s: int, first: np.ndarray) -> np.ndarray:
    """The upper triangle of H H^T for H with consecutive shifts (block (i, k) = Y(i + k), r × s blocks of
    p × m) from its first block row ``first`` (p, r p) by G_{i+1, j+1} = G_{i, j} + Y(i + s) Y(j + s)^T -
    Y(i) Y(j)^T. (Split by block diagonals between two threads it gained nothing: 4.5 → 4.3 ms on 1280 × 2000,
    3.6 → 6.2 ms on 900 × 2392, its small steps serialized by the GIL.)"""
    p, m = y.shape[1], y.shape[2]
    g = np.empty((r * p, r * p))
    g[:p] = first
    for i in range(r - 1):
        later = y[i + s:r - 1 + s].transpose(2, 0, 1).reshape(m, -1)  # [Y(j + s)^T]_j for j = i..r-2
        early = y[i:r - 1].transpose(2, 0, 1).reshape(m, -1)
        g[(i + 1) * p:(i + 2) * p, (i + 1) * p:] = (g[i * p:(i + 1) * p, i * p:(r - 1) * p]
                                                     + y[i + s] @ later - y[i] @ early)
    return g


def is_consecutive(row_shifts: np.ndarray, col_shifts: np.ndarray) -> bool:
    """True for the default shifts 0, 1, 2, ... in both directions (a plain block Hankel matrix)."""
    return bool(np.array_equal(row_shifts, np.arange(len(row_shifts))) and
                np.array_equal(col_shifts, np.arange(len(col_shifts))))


def _correlate(y: np.ndarray, x: np.ndarray, count: int) -> np.ndarray:
    """c_i = Σ_j y(i + j) x_j for i = 0..count - 1, by FFT: y (n, a, b) a sequence of blocks, x (J, b, K)
    blocks; returns (count, a, K). One real FFT of y and of the reversed x, one small product per frequency."""
    n, J = y.shape[0], x.shape[0]
    size = scipy.fft.next_fast_len(n + J - 1, real=True)
    # contiguous spectra, so the product per frequency goes to BLAS (numpy loops itself over strided ones)
    yf = np.ascontiguousarray(scipy.fft.rfft(y, n=size, axis=0))
    xf = np.ascontiguousarray(scipy.fft.rfft(x[::-1], n=size, axis=0))
    return scipy.fft.irfft(yf @ xf, n=size, axis=0)[J - 1:J - 1 + count]  # (y * reversed x)[i + J - 1]


def fft_pays(rows: int, cols: int) -> bool:
    """Products with a plain block Hankel matrix of r × s blocks go by FFT (:class:`HankelOperator`) when
    80 F < r s, F ≈ (2 r + s) / 2 the frequencies: measured on the benchmark's sizes (one core), the small
    product per frequency runs far below the speed of one large product. 900 × 2392 (r = 100, s = 299): H(0)^T P
    (P 900 × 120) in 4.0 ms instead of 15.5 ms with building H(0), the Gram matrix's first block row 0.7 ms
    instead of 1.9 ms; 1280 × 2000 (r = 40, s = 500): 15.2 + 11.2 ms against 20.8 + 5.0 ms, so not there."""
    return 40 * (2 * rows + cols) < rows * cols


class HankelOperator(scipy.sparse.linalg.LinearOperator):
    """H(k) of eq. 16 with consecutive shifts as a linear operator: H @ X and H^T @ X by FFT without forming H
    when that pays (:func:`fft_pays`, ``by_fft``), else by BLAS on H itself, formed once when first needed or
    ahead of that by :meth:`prepare` (era.core.svd.truncated_svd calls it in a second thread while the main one is
    busy, so the copy is not on the path).

    Block (i, j) of H is Y(k + i + j), so (H X)_i = Σ_j Y(k + i + j) X_j and (H^T X)_j = Σ_i Y(k + i + j)^T X_i
    are correlations of the data with the blocks of X: ≈ F p m K work (F the FFT length) instead of r p s m K.
    Round-off is that of the FFT, ε log F times the norms (3e-15 of each column's norm on the benchmark's
    H(0)^T P: tests/core/test_truncated_svd.py). ``markov`` (N, p, m); r, s the numbers of block rows, columns.
    """

    def __init__(self, markov: np.ndarray, rows: int, cols: int, k: int = 0, by_fft: bool | None = None):
        n, p, m = markov.shape
        if k + rows + cols - 1 > n:
            raise HankelError(f"H({k}) needs Y({k + rows + cols - 2}) but only {n} samples are given.")
        self.y = markov[k:k + rows + cols - 1]
        self.rows, self.cols = rows, cols
        self.by_fft = fft_pays(rows, cols) if by_fft is None else bool(by_fft)
        self._dense = None
        super().__init__(dtype=np.float64, shape=(rows * p, cols * m))

    def prepare(self) -> None:
        """Form H now if its products go by BLAS (nothing when they go by FFT)."""
        if not self.by_fft and self._dense is None:
            self._dense = self.dense()

    def _matmat(self, x):
        n, p, m = self.y.shape
        x = np.asarray(x, dtype=float)
        if not self.by_fft:
            self.prepare()
            return self._dense @ x
        return _correlate(self.y, x.reshape(self.cols, m, -1), self.rows).reshape(self.rows * p, -1)

    def _rmatmat(self, x):
        n, p, m = self.y.shape
        x = np.asarray(x, dtype=float)
        if not self.by_fft:
            self.prepare()
            return self._dense.T @ x
        out = _correlate(self.y.transpose(0, 2, 1), x.reshape(self.rows, p, -1), self.cols)
        return out.reshape(self.cols * m, -1)

    def _rmatvec(self, x):
        return self._rmatmat(np.reshape(x, (-1, 1)))[:, 0]

    def first_block_row(self) -> np.ndarray:
        """Its first block row [Y(0), ..., Y(s - 1)] (p, s m)."""
        n, p, m = self.y.shape
        return self.y[:self.cols].transpose(1, 0, 2).reshape(p, -1)

    def first_block_column(self) -> np.ndarray:
        """Its first block column [Y(0); ...; Y(r - 1)] (r p, m)."""
        return self.y[:self.rows].reshape(-1, self.y.shape[2])

    def dense(self) -> np.ndarray:
        """H itself (r p, s m)."""
        return self._dense if self._dense is not None else block_hankel(self.y, np.arange(self.rows),
                                                                          np.arange(self.cols))
