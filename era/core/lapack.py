"""The eigenvalues of a real matrix and the right and left eigenvectors of ONE member per conjugate pair, from
LAPACK without the GIL; also, for era.core.svd's threads, the eigenvalues (:func:`sterf`) and, by inverse
iteration, eigenvectors (:func:`stein`) of a symmetric tridiagonal matrix, and a product of Householder
reflectors in two steps: its block factors (:func:`reflector_blocks`), then their product with a matrix
(:func:`apply_reflectors`).

A realization's modes (eq. 40) need every eigenvalue of A (n × n real) but the eigenvectors (and the rows of ψ^{-1})
of the real poles and of the member with Im z > 0 of each pair only. The steps are dgeev's, with two changes:

1. dgebal ('B': permute and scale), dgehrd, dorghr: H = Qᵀ D⁻¹ Pᵀ A P D Q upper Hessenberg, and Q;
2. dlahqr (double-shift QR; Schur form T and Schur vectors Z = Q Z_QR): dgeev's dhseqr hands matrices of order
   ≥ 75 to dlaqr0 (multishift with aggressive early deflation), 30 % slower than dlahqr up to order 120 on the
   stabilization sweep's matrices (tests/bench/bench_sweep.py's, one BLAS thread);
3. dtrevc ('B', 'S'): the right AND left eigenvectors of T for the kept eigenvalues only, back-substitution;
4. Z·X, Z·Y and dgebak: the eigenvectors of A. The rows of ψ^{-1} are then the left eigenvectors scaled by
   1/(yᴴ x), which is cheaper than inverting ψ (n³).

Each routine is scipy's own LAPACK, reached through scipy's public Cython API (the function pointers in
``scipy.linalg.cython_lapack.__pyx_capi__``) and called with ctypes, which releases the GIL during the call:
the orders of a stabilization sweep eigensolve in parallel threads (scipy.linalg's f2py wrappers hold the
GIL). The pointers are resolved once, on first use, and each one's argument count is checked against the C
signature scipy publishes with it.

Fallback to ``np.linalg.eig`` (numpy's dgeev, which releases the GIL too) and the rows of ψ^{-1} from one real
inverse, the same result to round-off: above order MAX_ORDER, when scipy does not export a routine, when a
routine reports an error (info ≠ 0: dlahqr did not converge), when two eigenvalues are closer than
REPEATED_RELATIVE·|z| (a repeated eigenvalue, Case II of the paper: ψ^{-1} is then a dual basis of the shared
eigenspace, not the scaled left eigenvectors, and decomposition.align_repeated rotates dgeev's basis of it), and
when yᴴx vanishes (near-defective).

Measured on bench_sweep's 900 × 2392 case (the 60 matrices of orders 2..120, one BLAS thread, CPU time, load
1.3-1.6 on 2 cores): numpy's dgeev + one real inverse 147-150 ms, this path 126-129 ms. Its parts: dlahqr
85 ms (eigenvalues alone: 48), dtrevc 12.5, dgehrd + dorghr 15, the products and dgebal/dgebak 6-7, Python
between the calls ~0.1 ms per matrix. Tried and slower: dhseqr('E') + dhsein (inverse iteration for the kept
vectors only) + dormhr, 150 ms (dhsein alone 46); dhseqr('S', 'V') + dtrevc, 140; dgeev itself, 133.
"""

from __future__ import annotations

import ctypes
import functools
import threading

import numpy as np

#: Two eigenvalues with |z_i - z_j| ≤ this × max(|z_i|, |z_j|) (or both exactly 0) are treated as one repeated
#: eigenvalue: the matrix is eigensolved by numpy's dgeev.
REPEATED_RELATIVE = 1e-6

#: Larger matrices go to numpy's dgeev: dlahqr's level-1 QR sweeps fall behind dlaqr0's multishift ones beyond
#: order ~170 on the sweep's matrices (tests/bench/bench_sweep.py's 900 × 2392 and 1280 × 2000, orders 60-200).
MAX_ORDER = 160

#: The routines and their numbers of arguments (LAPACK 3 reference interfaces; checked against scipy's).
_ARGUMENTS = {"dgebal": 8, "dgehrd": 9, "dorghr": 9, "dlahqr": 14, "dtrevc": 14, "dgebak": 10, "dsterf": 4,
              "dstein": 13, "dlarft": 9, "dlarfb": 15}

#: eig_kept's routines, in call order
_EIG_PATH = ("dgebal", "dgehrd", "dorghr", "dlahqr", "dtrevc", "dgebak")

_lock = threading.Lock()
_routines: dict = {}  # name -> ctypes function, or None when scipy does not export it


def _capsule_table() -> dict:
    """scipy's table of Cython-exported LAPACK function pointers (name -> PyCapsule); {} without scipy."""
    try:
        from scipy.linalg import cython_lapack
    except ImportError:  # pragma: no cover - scipy is a dependency
        return {}
    return getattr(cython_lapack, "__pyx_capi__", {})


def _resolve(name: str):
    """The ctypes function for LAPACK routine ``name``, or None if scipy does not export it as expected."""
    capsule = _capsule_table().get(name)
    if capsule is None:
        return None
    # private prototypes: ctypes.pythonapi's own are shared with the rest of the process
    name_of = ctypes.PYFUNCTYPE(ctypes.c_char_p, ctypes.py_object)(("PyCapsule_GetName", ctypes.pythonapi))
    pointer_of = ctypes.PYFUNCTYPE(ctypes.c_void_p, ctypes.py_object, ctypes.c_char_p)(
        ("PyCapsule_GetPointer", ctypes.pythonapi))
    signature = name_of(capsule)  # e.g. b"void (char *, int *, ...)"
    if not signature or not signature.startswith(b"void (") or signature.count(b",") + 1 != _ARGUMENTS[name]:
        return None
    address = pointer_of(capsule, signature)
    if not address:
        return None
    return ctypes.CFUNCTYPE(None, *([ctypes.c_void_p] * _ARGUMENTS[name]))(address)


def routine(name: str):
    """The ctypes function of LAPACK routine ``name`` (a key of _ARGUMENTS), resolved on first use; None when
    scipy does not export it. Every argument is a pointer (Fortran convention); the call releases the GIL."""
    if name not in _routines:
        with _lock:
            if name not in _routines:
                _routines[name] = _resolve(name)
    return _routines[name]


def available() -> bool:
    """True when every routine of eig_kept's path is available (else eig_kept uses numpy's dgeev)."""
    return all(routine(name) is not None for name in _EIG_PATH)


class _Failed(Exception):
    """The LAPACK path does not apply (a routine missing or reporting info ≠ 0, a repeated eigenvalue, a
    near-defective matrix): eig_kept uses numpy's dgeev."""


#: LAPACK's character arguments (read only), and their addresses
_CHARS = {c: ctypes.c_char(c) for c in (b"B", b"C", b"F", b"L", b"N", b"R", b"S")}
_CHAR = {c: ctypes.addressof(v) for c, v in _CHARS.items()}


def _functions() -> tuple:
    """The six routines of the path in call order, or _Failed if scipy does not export one of them."""
    fns = tuple(routine(name) for name in _EIG_PATH)
    if any(fn is None for fn in fns):
        raise _Failed("a LAPACK routine is not exported by scipy")
    return fns


def _repeated(z: np.ndarray) -> bool:
    """True when two eigenvalues of a real matrix are within REPEATED_RELATIVE of each other (relative to the
    larger |z|; two zeros are repeated). ``z``: the kept ones (every real one and the member with Im z > 0 of
    each pair); a pair and its own conjugate are 2 Im z apart."""
    mag = np.abs(z)
    dist = np.abs(z[:, None] - z[None, :])
    dist.flat[::z.size + 1] = np.where(z.imag > 0, 2 * z.imag, np.inf)  # a pair's distance to its conjugate
    return bool(np.any(dist <= REPEATED_RELATIVE * np.maximum(mag[:, None], mag[None, :])))


@functools.lru_cache(maxsize=None)
def _hessenberg_mask(n: int) -> np.ndarray:
    """(n, n) float, Fortran order: 1 on and above the first subdiagonal, 0 below."""
    return np.asfortranarray(np.triu(np.ones((n, n)), -1))


def _schur_route(A: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """eig_kept by the path of the module docstring; raises _Failed where it does not apply.

    Every array LAPACK sees lives in one buffer (the ints in its tail), passed as base address + offset: the
    Python work between the calls (which holds the GIL) stays small next to the calls (which do not)."""
    gebal, gehrd, orghr, lahqr, trevc, gebak = _functions()
    n = A.shape[0]
    nn, lwork = n * n, 64 * n  # ≥ the block size (32) × n that dgehrd and dorghr use at their best; dtrevc 3 n
    # a | t | x | y | zl (n × n each) | scale | wr | wi | tau (n each) | work (lwork) | the ints
    f = np.empty(5 * nn + 4 * n + lwork + (7 + n + 1) // 2)
    i = f[5 * nn + 4 * n + lwork:].view(np.int32)  # n, ilo, ihi, info, lwork, 1, m | select (n)
    fp = f.ctypes.data
    ip = fp + 8 * (5 * nn + 4 * n + lwork)
    A_, T_, X_, Y_, ZL_, SCALE, WR, WI, TAU, WORK = (fp + 8 * k for k in (
        0, nn, 2 * nn, 3 * nn, 4 * nn, 5 * nn, 5 * nn + n, 5 * nn + 2 * n, 5 * nn + 3 * n, 5 * nn + 4 * n))
    N, ILO, IHI, INFO, LWORK, ONE, M, SELECT = (ip + 4 * k for k in range(8))
    i[:7] = n, 0, 0, 0, lwork, 1, 0
    a, t, x, y, zl = (f[k * nn:(k + 1) * nn].reshape(n, n, order="F") for k in range(5))
    wr, wi = f[5 * nn + n:5 * nn + 2 * n], f[5 * nn + 2 * n:5 * nn + 3 * n]

    def check(name):
        if i[3] != 0:
            raise _Failed(f"{name}: info = {int(i[3])}")

    a[...] = A
    gebal(_CHAR[b"B"], N, A_, N, ILO, IHI, SCALE, INFO)  # a = D⁻¹ Pᵀ A P D
    check("dgebal")
    gehrd(N, ILO, IHI, A_, N, TAU, WORK, LWORK, INFO)
    check("dgehrd")
    np.multiply(a, _hessenberg_mask(n), out=t)  # H (the reflectors stay below the subdiagonal of a)
    orghr(N, ILO, IHI, A_, N, TAU, WORK, LWORK, INFO)  # a = Q
    check("dorghr")
    wr[:], wi[:] = t.diagonal(), 0.0  # dlahqr sets ilo..ihi; the others were isolated by dgebal
    lahqr(ONE, ONE, N, ILO, IHI, T_, N, WR, WI, ILO, IHI, A_, N, INFO)  # t = T, a = Z = Q Z_QR
    check("dlahqr")
    keep = wi >= 0  # the real ones and the member with Im z > 0 of each pair (its partner follows it)
    kept = wr[keep] + 1j * wi[keep]
    if _repeated(kept):
        raise _Failed("repeated eigenvalue")
    # the kept vectors of T fill all n columns of x, y: a real one in one, a pair's Re and Im parts in two
    i[7:7 + n] = keep
    trevc(_CHAR[b"B"], _CHAR[b"S"], SELECT, N, T_, N, Y_, N, X_, N, N, M, WORK, INFO)
    check("dtrevc")
    zl[...] = a
    gebak(_CHAR[b"B"], _CHAR[b"R"], N, ILO, IHI, SCALE, N, A_, N, INFO)  # a = P D Z: right vectors of A
    check("dgebak")
    gebak(_CHAR[b"B"], _CHAR[b"L"], N, ILO, IHI, SCALE, N, ZL_, N, INFO)  # zl = P D⁻¹ Z: left vectors
    check("dgebak")
    cols = np.flatnonzero(keep)
    pair = wi[cols] > 0
    sign = -1.0 * pair  # Im of ȳ: -Im y for a pair, 0 for a real one
    xa, ya = a @ x, zl @ y  # column j: Re of mode j's vector, column j + 1: Im if mode j is a pair
    im = cols + pair  # (a real one's own column, zeroed below)
    right, left = np.empty((n, cols.size), complex), np.empty((n, cols.size), complex)
    right.real, right.imag = xa[:, cols], xa[:, im] * pair
    left.real, left.imag = ya[:, cols], ya[:, im] * sign  # the conjugate ȳ: ȳᵀ A = z ȳᵀ
    dual = np.einsum("ij,ij->j", left, right)  # ȳᵀ x
    if not np.all(np.abs(dual) > 1e-13 * np.abs(left).max(axis=0)):  # also False for NaN
        raise _Failed("near-defective")
    return kept, right, (left / dual).T


def eig_kept(A: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The eigenvalues of real A that a modal model keeps, their right eigenvectors and their rows of ψ^{-1}.

    Parameters
    ----------
    A : (n, n) real, finite (else numpy's LinAlgError)

    Returns
    -------
    z : (kept,) complex, every real eigenvalue (Im z = 0 exactly) and the member with Im z > 0 of each
        conjugate pair, in LAPACK's order; kept = n - (number of pairs). The other eigenvalues are the
        conjugates of the pairs'.
    right : (n, kept) complex, A right_j = z_j right_j (of no particular scale: O(1) in the largest component).
    left : (kept, n) complex, the rows of ψ^{-1} for these modes (ψ = all n eigenvectors, the partners being
        the conjugates): left_j A = z_j left_j and left_j right_k = δ_jk.

    The path is in the module docstring (for n ≤ MAX_ORDER); it falls back to ``np.linalg.eig``. Both release
    the GIL.
    """
    A = np.asarray(A, dtype=float)
    if A.shape[0] == 0:
        return np.zeros(0, complex), np.zeros((0, 0), complex), np.zeros((0, 0), complex)
    if A.shape[0] <= MAX_ORDER and np.isfinite(A).all():  # (numpy's error for NaN/inf, not LAPACK's xerbla)
        try:
            return _schur_route(A)
        except _Failed:
            pass
    return _eig_numpy(A)


def _eig_numpy(A: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """eig_kept by numpy's dgeev (all eigenvectors) and one real inverse (pseudo-inverse when singular)."""
    z_all, psi = np.linalg.eig(A)
    z_all, psi = z_all.astype(complex), psi.astype(complex)
    keep = z_all.imag >= 0  # LAPACK returns exact conjugate pairs and exactly real eigenvalues
    z, right = z_all[keep], psi[:, keep]
    try:
        left = _inverse_rows(right, z.imag > 0)
    except np.linalg.LinAlgError:  # defective A (a Jordan block): best effort
        left = np.linalg.pinv(np.hstack([right, right[:, z.imag > 0].conj()]))[:z.size]
    return z, right, left


def _inverse_rows(right: np.ndarray, is_pair: np.ndarray) -> np.ndarray:
    """The rows of ψ^{-1} (kept, n) complex for the kept eigenvectors ``right`` (n, kept) of a real matrix:
    every real one and the member with Im z > 0 of each pair (ψ holds the partners' conjugates too).

    With R (n × n, real) holding Re ψ_j and Im ψ_j of each pair and each real ψ_j, [ψ_j, ψ̄_j] = [Re, Im] T with
    T = [[1, 1], [i, -i]], so the row of ψ^{-1} for ψ_j is (R^{-1}_Re - i R^{-1}_Im) / 2: one real inverse, a
    quarter of the work of the complex one. Raises LinAlgError when R is singular (defective A).
    """
    width = np.where(is_pair, 2, 1)
    first = np.cumsum(width) - width  # each kept mode's first column in R
    real_form = np.empty((right.shape[0], int(width.sum())))
    real_form[:, first] = right.real
    real_form[:, first[is_pair] + 1] = right[:, is_pair].imag
    inv = np.linalg.inv(real_form)
    out = inv[first].astype(complex)
    out[is_pair] = (inv[first[is_pair]] - 1j * inv[first[is_pair] + 1]) / 2
    return out


def sterf(diag: np.ndarray, off: np.ndarray) -> np.ndarray | None:
    """All eigenvalues (a,), ascending, of the symmetric tridiagonal matrix (``diag`` (a,), ``off`` (a - 1,)):
    LAPACK's dsterf (Pal-Walker-Kahan QL/QR) without the GIL, so that another thread runs meanwhile (scipy's
    wrapper holds it). None when scipy does not export dsterf or it did not converge."""
    fn = routine("dsterf")
    a = diag.size
    if fn is None or a < 1:
        return None
    d = np.array(diag, dtype=float)
    e = np.zeros(max(a - 1, 1))
    e[:a - 1] = off
    ints = np.array([a, 0], dtype=np.int32)  # n, info
    fn(ints.ctypes.data, d.ctypes.data, e.ctypes.data, ints.ctypes.data + 4)
    return d if ints[1] == 0 else None


def stein(diag: np.ndarray, off: np.ndarray, values: np.ndarray) -> np.ndarray | None:
    """Eigenvectors (a, k) of the symmetric tridiagonal matrix (``diag`` (a,), ``off`` (a - 1,)) for its
    eigenvalues ``values`` (k,), ascending: LAPACK's dstein (inverse iteration, which re-orthogonalises the
    vectors of close eigenvalues among themselves) on one block, without the GIL, so that parts of the values
    can go to threads (era.core.svd). None when scipy does not export dstein or it did not converge."""
    fn = routine("dstein")
    a, k = diag.size, values.size
    if fn is None or a < 2 or k < 1:
        return None
    d, e, w = (np.ascontiguousarray(x, dtype=float) for x in (diag, off, values))
    ints = np.zeros(3 + 2 * k + 2 * a, dtype=np.int32)  # n, m, info | iblock (k) | ifail (k) | isplit, iwork (a)
    ints[:2], ints[3:3 + k], ints[3 + 2 * k] = (a, k), 1, a  # one block, ending at a
    z, work = np.empty((k, a)), np.empty(5 * a)  # z: Fortran's (a, k)
    n_, m_, info, block, fail, split, iwork = (ints.ctypes.data + 4 * i for i in (
        0, 1, 2, 3, 3 + k, 3 + 2 * k, 3 + 2 * k + a))
    fn(n_, d.ctypes.data, e.ctypes.data, m_, w.ctypes.data, block, split, z.ctypes.data, n_, work.ctypes.data,
       iwork, fail, info)
    if ints[2] != 0 or not np.isfinite(z).all():
        return None
    return z.T


#: Reflectors per block of :func:`reflector_blocks` (dormqr's own block size).
REFLECTOR_BLOCK = 64


def reflector_blocks(v: np.ndarray, tau: np.ndarray) -> list | None:
    """The triangular factors of Q = H(1) H(2) ... H(k), H(i) = I - tau_i v_i v_i^T, by blocks of
    REFLECTOR_BLOCK reflectors: block b (reflectors i = b·64 ...) is I - V_b T_b V_b^T (LAPACK's dlarft,
    forward, columnwise), without the GIL. The first half of dormqr's work, which needs only the reflectors,
    so it can run before the matrix they multiply is known (era.core.svd).

    v : (n, k) Fortran order, v_i in column i below the diagonal (1 on it, implied; as geqrf or sytrd leave
    them); tau : (k,). Returns the factors (ib, ib) in block order, or None when scipy does not export dlarft
    or ``v`` is not such a view.
    """
    fn, where = routine("dlarft"), _in_place(v)
    if fn is None or where is None:
        return None
    n, k = v.shape
    ld, base = where
    ints = np.zeros(4, dtype=np.int32)  # rows, reflectors, ldv, ldt
    out = []
    for i in range(0, k, REFLECTOR_BLOCK):
        ib = min(REFLECTOR_BLOCK, k - i)
        t = np.zeros((ib, ib), order="F")
        ints[:] = n - i, ib, ld, ib
        at = ints.ctypes.data
        fn(_CHAR[b"F"], _CHAR[b"C"], at, at + 4, base + 8 * (i + i * ld), at + 8, tau.ctypes.data + 8 * i,
           t.ctypes.data, at + 12)
        out.append(t)
    return out


def apply_reflectors(v: np.ndarray, blocks: list, c: np.ndarray) -> np.ndarray | None:
    """Q c for Q = H(1) ... H(k) given by ``v`` (n, k) and its :func:`reflector_blocks`: LAPACK's dlarfb per
    block, from the last to the first (as dormqr('L', 'N')), BLAS-3 with the caller's threads; ``c`` (n, w) is
    overwritten when Fortran-ordered float (else copied). None when scipy does not export dlarfb or ``v`` is not
    a Fortran-ordered view."""
    fn, where = routine("dlarfb"), _in_place(v)
    if fn is None or where is None:
        return None
    n, k = v.shape
    ld, base = where
    c = np.asfortranarray(c, dtype=float)
    w = c.shape[1]
    work = np.empty((w, REFLECTOR_BLOCK), order="F")
    ints = np.zeros(6, dtype=np.int32)  # rows, columns, reflectors, ldv, ldt, ldc | ldwork = columns
    for b in range(len(blocks) - 1, -1, -1):
        i = b * REFLECTOR_BLOCK
        ib = blocks[b].shape[0]
        ints[:] = n - i, w, ib, ld, ib, n
        at = ints.ctypes.data
        fn(_CHAR[b"L"], _CHAR[b"N"], _CHAR[b"F"], _CHAR[b"C"], at, at + 4, at + 8, base + 8 * (i + i * ld), at + 12,
           blocks[b].ctypes.data, at + 16, c.ctypes.data + 8 * i, at + 20, work.ctypes.data, at + 4)
    return c


def _in_place(v: np.ndarray) -> tuple[int, int] | None:
    """(leading dimension, address) of a float64 (n, k) view that LAPACK can read in place: unit row stride
    and a column stride of whole numbers ≥ n (a Fortran-ordered array or a block of one, such as c[1:, :-1]);
    None for any other."""
    if not (v.ndim == 2 and v.dtype == np.float64 and v.strides[0] == 8 and v.strides[1] % 8 == 0
            and v.strides[1] // 8 >= max(v.shape[0], 1)):
        return None
    return v.strides[1] // 8, v.ctypes.data
