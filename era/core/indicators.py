"""Accuracy indicators of ERA: modal amplitude coherence γ (eqs. 42-45), modal phase collinearity μ
(eqs. 46-54), modal contribution, and the MAC used to compare shapes."""

from __future__ import annotations

import numpy as np


def emac(histories: np.ndarray, z: np.ndarray, col_shifts: np.ndarray, n_inputs: int,
         growth: np.ndarray | None = None) -> np.ndarray:
    """Modal amplitude coherence γ_j (eqs. 42-45).

    Parameters
    ----------
    histories : complex ndarray, shape (modes, s·m)
        Row j is q_j^*, the modal amplitude history ψ^{-1} W of mode j (eq. 44) at the column shifts
        t_0 = 0, t_1, ..., t_{s-1}; its first m entries are the initial modal amplitude b_j^* (eq. 42).
    z : complex ndarray, shape (modes,)
        Discrete eigenvalues z_j = exp(s_j Δτ).
    col_shifts : int ndarray, shape (s,)
        (0, t_1, ..., t_{s-1}).
    n_inputs : int
        m.
    growth : complex ndarray, shape (modes, s), optional
        powers(z, col_shifts), when the caller already has it.

    Returns
    -------
    ndarray, shape (modes,)
        γ_j = |q̄_j^* q_j| / (|q̄_j| |q_j|) in [0, 1], with q̄_j the ideal history
        [b_j^*, z_j^{t_1} b_j^*, ...] of eq. 43 (exp(t_i Δτ s_j) = z_j^{t_i}). A mode whose history is
        identically zero gets γ = 0.
    """
    return emac_parts(histories.real, histories.imag, z, col_shifts, n_inputs, growth)


def emac_parts(real: np.ndarray, imag: np.ndarray, z: np.ndarray, col_shifts: np.ndarray, n_inputs: int,
               growth: np.ndarray | None = None) -> np.ndarray:
    """:func:`emac` of histories given as their real and imaginary parts, each (modes, s·m) real: the form a
    real matrix product gives them in, so no complex copy of the histories is made."""
    modes = real.shape[0]
    s = len(col_shifts)
    qr, qi = real.reshape(modes, s, n_inputs), imag.reshape(modes, s, n_inputs)
    br, bi = qr[:, 0, :], qi[:, 0, :]
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        if growth is None:
            growth = powers(z, col_shifts)  # (modes, s): exp(t_i Δτ s_j) = z_j^{t_i}
        # q̄^* q = Σ_i conj(z^{t_i}) (b^* q_i), without forming q̄; b^* q_i in real arithmetic (four
        # contractions over the m inputs: faster than a batched product of m × 2 matrices)
        bq = (np.einsum("jsm,jm->js", qr, br) + np.einsum("jsm,jm->js", qi, bi)) \
            + 1j * (np.einsum("jsm,jm->js", qi, br) - np.einsum("jsm,jm->js", qr, bi))
        inner = np.abs(np.einsum("js,js->j", growth.conj(), bq))
        b2 = np.einsum("jm,jm->j", br, br) + np.einsum("jm,jm->j", bi, bi)
        q2 = np.einsum("jk,jk->j", real, real) + np.einsum("jk,jk->j", imag, imag)
        norms = np.sqrt(np.sum(np.abs(growth) ** 2, axis=1) * b2 * q2)
    ok = np.isfinite(norms) & (norms > 0) & np.isfinite(inner)
    out = np.zeros(modes)
    out[ok] = inner[ok] / norms[ok]
    return np.clip(out, 0.0, 1.0)


def powers(z: np.ndarray, exponents: np.ndarray) -> np.ndarray:
    """z_j ** t_i for every mode j and shift t_i: (modes, len(exponents)); 0 ** 0 = 1."""
    z = np.asarray(z, dtype=complex)
    t = np.asarray(exponents)
    if t.size > 2 and np.array_equal(t, np.arange(t.size)):  # 0, 1, 2, ...: repeated products (no exp/log)
        with np.errstate(over="ignore", invalid="ignore", under="ignore"):
            return _consecutive_powers(z, t.size)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        out = np.exp(np.log(z)[:, None] * t[None, :])
    out[:, t == 0] = 1.0
    out[(z == 0)[:, None] & (t != 0)[None, :]] = 0.0
    return out


#: z^0 .. z^(N-1) in blocks of this many: z^(qB + r) = (z^B)^q z^r, two short running products and one outer
#: product, 3.5× faster than one running product over N (numpy's complex cumprod is a scalar loop) and no less
#: accurate (q + r products per value instead of qB + r).
POWER_BLOCK = 64


def _consecutive_powers(z: np.ndarray, n: int) -> np.ndarray:
    """(modes, n) z_j ** k for k = 0 .. n - 1 by running products; by blocks (:data:`POWER_BLOCK`) for the modes
    with |z| ≤ 1, whose powers cannot overflow (an overflowing block would turn inf·0 into NaN)."""
    out = np.empty((z.size, n), dtype=complex)
    out[:, 0] = 1.0
    out[:, 1:] = z[:, None]
    bounded = np.abs(z) <= 1.0
    if n <= 2 * POWER_BLOCK or not bounded.any():
        return np.cumprod(out, axis=1)
    rest = ~bounded
    if rest.any():
        out[rest] = np.cumprod(out[rest], axis=1)
    zb = z[bounded]
    q = -(-n // POWER_BLOCK)
    inner = np.cumprod(out[bounded, :POWER_BLOCK], axis=1)  # z^0 .. z^(B-1)
    outer = np.empty((zb.size, q), dtype=complex)
    outer[:, 0] = 1.0
    outer[:, 1:] = (inner[:, -1] * zb)[:, None]  # z^B
    outer = np.cumprod(outer, axis=1)  # (z^B)^0 .. (z^B)^(q-1)
    out[bounded] = (outer[:, :, None] * inner[:, None, :]).reshape(zb.size, q * POWER_BLOCK)[:, :n]
    return out


def mpc(shapes: np.ndarray) -> np.ndarray:
    """Modal phase collinearity μ_j (eqs. 46-54), invariant to the complex scaling of each shape.

    The paper centres each shape c_j (eq. 48) and forms c_rr, c_ri, c_ii (eqs. 49-51): the entries of the
    2 × 2 scatter matrix S of the points (Re c_k, Im c_k) in the complex plane. Eqs. 52-54 rotate the
    points by θ onto their principal axis and take the share of the scatter that lies along it. As
    printed, θ (eq. 53) lands on the MINOR axis for some phases of the shape (whenever e and c_ri have
    opposite signs), and eq. 54 then returns λ_2/(λ_1 + λ_2) instead: ≈ 0 for a real shape rotated by
    such an angle. The quantity eq. 54 means is, with λ_1 ≥ λ_2 ≥ 0 the eigenvalues of S,

        μ = λ_1 / (λ_1 + λ_2),      λ_{1,2} = (c_rr + c_ii)/2 ± sqrt(((c_rr - c_ii)/2)² + c_ri²),

    which is what eq. 54 gives on the major-axis branch, needs no angle, and is unchanged when the shape is
    multiplied by any complex number (that rotates the points, not S's eigenvalues). μ = 1 when the
    centred points lie on one line (0°/180° behaviour, any real shape times a complex number); its
    lowest value, 1/2, is reached when they are spread evenly in phase. (Pappa, Elliott & Schenk 1993
    later rescaled it to MPC = (2μ - 1)², which spans [0, 1]; this is the 1985 definition.)

    Degenerate cases: when the centred shape vanishes (a single sensor, or all sensors moving as one)
    the shape is a complex multiple of a real vector, so μ = 1; a shape that is identically zero
    (an unobserved mode) gets μ = 0, so thresholds on μ drop it.

    Parameters
    ----------
    shapes : complex ndarray, shape (p, modes)

    Returns
    -------
    ndarray, shape (modes,) in [1/2, 1], or 0 for a zero shape.
    """
    c = np.asarray(shapes, dtype=complex)
    centred = c - c.mean(axis=0, keepdims=True)
    re, im = centred.real, centred.imag
    c_rr = np.einsum("pj,pj->j", re, re)
    c_ii = np.einsum("pj,pj->j", im, im)
    c_ri = np.einsum("pj,pj->j", re, im)
    trace = c_rr + c_ii  # λ_1 + λ_2
    spread = np.hypot(c_rr - c_ii, 2.0 * c_ri)  # λ_1 - λ_2, without cancellation
    scale = np.einsum("pj,pj->j", c.conj(), c).real
    out = np.ones(c.shape[1])
    informative = trace > 16 * np.finfo(float).eps * scale
    out[informative] = 0.5 * (1.0 + spread[informative] / trace[informative])
    out[scale == 0] = 0.0
    return np.clip(out, 0.0, 1.0)


def contribution(shapes, amplitudes, z, row_shifts, col_shifts, is_pair, col_growth=None) -> np.ndarray:
    """Each mode's share of H(0): the Frobenius norm of its term in H(0), in the units of the singular values.

    Mode j adds o_j r_j^T to H(0) (plus the complex conjugate for a pair), with o_j = [c_j z_j^{j_i}]_i
    (length r·p) and r_j = [b_j z_j^{t_i}]_i (length s·m). For a real pole the norm is |o_j| |r_j|; for a
    pair, ‖2 Re(o r^T)‖_F² = 2 (|o|²|r|² + Re((o^T o)(r^T r))). Comparable with the singular values d_i,
    so strong and weak modes can be told apart (the modal singular value).

    Parameters
    ----------
    shapes : (p, modes) complex; amplitudes : (modes, m) complex; z : (modes,) complex;
    row_shifts : (r,) int; col_shifts : (s,) int; is_pair : (modes,) bool;
    col_growth : (modes, s) complex, powers(z, col_shifts) when the caller already has it.

    Returns
    -------
    ndarray, shape (modes,)
    """
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        rows = powers(z, row_shifts)  # (modes, r)
        cols = powers(z, col_shifts) if col_growth is None else col_growth  # (modes, s)
        # o^T o = (Σ_i z^{2 j_i}) (c^T c) and |o|² = (Σ_i |z|^{2 j_i}) |c|², likewise for r
        o2 = np.sum(np.abs(rows) ** 2, axis=1) * np.sum(np.abs(shapes) ** 2, axis=0)
        r2 = np.sum(np.abs(cols) ** 2, axis=1) * np.sum(np.abs(amplitudes) ** 2, axis=1)
        oo = np.sum(rows**2, axis=1) * np.sum(shapes**2, axis=0)
        rr = np.sum(cols**2, axis=1) * np.sum(amplitudes**2, axis=1)
        pair = 2.0 * (o2 * r2 + (oo * rr).real)
        out = np.sqrt(np.maximum(np.where(is_pair, pair, o2 * r2), 0.0))
    return np.where(np.isfinite(out), out, np.inf)


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion between the columns of ``a`` and ``b``.

    MAC = |a^H b|² / ((a^H a)(b^H b)); a zero column gives MAC 0 with every other column.

    Parameters
    ----------
    a : array_like, shape (p, i) or (p,)
        Shapes at p sensors, real or complex, one per column.
    b : array_like, shape (p, j) or (p,)
        Shapes at the same p sensors.

    Returns
    -------
    ndarray, shape (i, j)
        The MAC of every pair of columns, in [0, 1].

    Examples
    --------
    >>> a = np.array([[1.0, 0.0], [1.0, 1.0]])
    >>> print(np.round(era.mac(a, a), 3))
    [[1.  0.5]
     [0.5 1. ]]
    >>> era.mac([1, 2, 3], [2j, 4j, 6j])
    array([[1.]])
    """
    a = np.asarray(a, dtype=complex)
    b = np.asarray(b, dtype=complex)
    if a.ndim == 1:
        a = a[:, None]
    if b.ndim == 1:
        b = b[:, None]
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    out = np.zeros_like(num)
    np.divide(num, den, out=out, where=den > 0)
    return np.clip(out, 0.0, 1.0)
