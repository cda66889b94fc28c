"""era.core.lapack: the kept eigenvalues, right eigenvectors and rows of ψ^{-1} of a real matrix, GIL-free."""

import ctypes
import sys
import threading
import time

import numpy as np
import pytest
import scipy.linalg

import era
from era.core import lapack
from era.examples.paper_cases import case_2
from era.examples.synthetic import modal_response
from era.core.decomposition import decompose, mode_order


def _kept_eigvals(a):
    w = np.linalg.eigvals(a).astype(complex)
    return np.sort_complex(w[w.imag >= 0])


def _check(a, z, right, left):
    """Eigenvalues as numpy's to 1e-12 relative, A v = z v and u A = z u to 1e-12 |A| |v|, u v = I."""
    n = a.shape[0]
    pairs = int(np.count_nonzero(z.imag > 0))
    assert z.shape == (n - pairs,) and right.shape == (n, n - pairs) and left.shape == (n - pairs, n)
    scale = max(np.abs(_kept_eigvals(a)).max(initial=0.0), 1e-300)
    np.testing.assert_allclose(np.sort_complex(z), _kept_eigvals(a), rtol=0, atol=1e-12 * scale)
    norm_a = np.linalg.norm(a, 2)
    r = np.linalg.norm(a @ right - right * z, axis=0) / np.linalg.norm(right, axis=0)
    ell = np.linalg.norm(left @ a - z[:, None] * left, axis=1) / np.linalg.norm(left, axis=1)
    assert r.max(initial=0) <= 1e-12 * norm_a and ell.max(initial=0) <= 1e-12 * norm_a
    np.testing.assert_allclose(left @ right, np.eye(z.size), atol=1e-10)
    assert np.all(z.imag[z.imag <= 0] == 0)  # real poles exactly real


def _with_eigenvalues(blocks, seed):
    """V Λ V^{-1}: Λ the real block-diagonal form of ``blocks`` (a real z, or (r, θ) for r e^{±iθ}), V random."""
    parts = [np.array([[b]]) if np.isscalar(b) else b[0] * np.array([[np.cos(b[1]), -np.sin(b[1])],
                                                                        [np.sin(b[1]), np.cos(b[1])]])
             for b in blocks]
    lam = scipy.linalg.block_diag(*parts)
    v = np.random.default_rng(seed).standard_normal(lam.shape)
    return v @ lam @ np.linalg.inv(v)


@pytest.mark.parametrize("n", [1, 2, 3, 7, 30, 76, 121])
def test_random_matrices_match_numpy(n):
    a = np.random.default_rng(n).standard_normal((n, n))
    _check(a, *lapack._schur_route(a))
    _check(a, *lapack.eig_kept(a))


def test_era_like_spectrum_lightly_damped_pairs_real_poles_and_a_zero():
    """Eigenvalues near the unit circle (|z| = 0.99-0.9999), real poles of both signs and one z = 0."""
    rng = np.random.default_rng(3)
    pairs = [(r, t) for r, t in zip(1 - rng.uniform(1e-4, 1e-2, 20), rng.uniform(0.05, 3.0, 20))]
    a = _with_eigenvalues(pairs + [0.97, -0.5, 0.2, 0.0], seed=3)
    z, right, left = lapack._schur_route(a)  # the LAPACK path itself (it raises where it does not apply)
    _check(a, z, right, left)
    assert np.count_nonzero(z.imag > 0) == 20 and np.count_nonzero(z.imag == 0) == 4


def test_the_lapack_path_is_taken_on_a_realization_and_decompose_agrees_with_numpys_path(monkeypatch):
    """The sweep's matrices take the Schur path (no fallback), and decompose gives dgeev's modes to round-off."""
    data, _ = modal_response([1.0, 2.2, 2.5, 6.0], 0.02, 6, 2, 400, 0.02, snr_db=40, seed=4)
    ident = era.identify(data, 40, 80)
    A, B, C, W = ident.balanced(30)
    fallbacks = []
    numpy_path = lapack._eig_numpy
    monkeypatch.setattr(lapack, "_eig_numpy", lambda a: fallbacks.append(a) or numpy_path(a))
    new = decompose(A, B, C, W)
    assert not fallbacks
    monkeypatch.setattr(lapack, "eig_kept", numpy_path)
    old = decompose(A, B, C, W)
    i, j = mode_order(new.z, data.dt), mode_order(old.z, data.dt)
    np.testing.assert_allclose(new.z[i], old.z[j], rtol=1e-12)
    np.testing.assert_allclose(new.shapes[:, i], old.shapes[:, j], rtol=1e-8, atol=1e-10)
    response_new = np.einsum("pj,jm->jpm", new.shapes, new.amplitudes)[i]
    response_old = np.einsum("pj,jm->jpm", old.shapes, old.amplitudes)[j]
    np.testing.assert_allclose(response_new, response_old, atol=1e-8 * np.abs(response_old).max())
    np.testing.assert_allclose(new.histories[i], old.histories[j], atol=1e-8 * np.abs(old.histories).max())


def test_one_by_one_and_two_by_two():
    for a in (np.array([[0.3]]), np.array([[0.0]]), np.array([[0.9, 0.2], [-0.3, 0.8]]),
              np.array([[0.9, 0.2], [0.1, 0.5]]), np.array([[0.0, 1.0], [-1.0, 0.0]])):
        _check(a, *lapack.eig_kept(a))
    z, right, left = lapack.eig_kept(np.zeros((0, 0)))
    assert z.shape == (0,) and right.shape == (0, 0) and left.shape == (0, 0)


def test_a_repeated_eigenvalue_goes_to_dgeev_which_returns_a_basis_of_its_eigenspace(monkeypatch):
    """Case II of the paper (a repeated pair): the eigensolution is numpy's, and spans the shared eigenspace."""
    ident = era.identify(case_2(), 20, 40)
    A = ident.balanced(10)[0]  # the true order: 5 pairs, -0.01 + i twice (split by round-off, ~1e-11)
    calls = []
    real_eig = np.linalg.eig
    monkeypatch.setattr(np.linalg, "eig", lambda a: calls.append(a) or real_eig(a))
    z, right, left = lapack.eig_kept(A)
    assert len(calls) == 1
    _check(A, z, right, left)
    assert lapack._repeated(z)
    a = _with_eigenvalues([(0.99, 0.4), (0.99, 0.4), 0.5], seed=1)  # an exactly repeated pair
    calls.clear()
    z, right, left = lapack.eig_kept(a)
    assert len(calls) == 1
    rep = np.flatnonzero(np.abs(z - 0.99 * np.exp(0.4j)) < 1e-6)
    assert rep.size == 2 and np.linalg.matrix_rank(right[:, rep], tol=1e-6) == 2
    np.testing.assert_allclose(left @ right, np.eye(z.size), atol=1e-8)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_a_non_finite_matrix_gets_numpys_error_and_no_lapack_message(bad, capfd):
    a = np.eye(5)
    a[1, 3] = bad
    with pytest.raises(np.linalg.LinAlgError):
        lapack.eig_kept(a)
    assert "DGEBAL" not in capfd.readouterr().err


def test_above_max_order_numpy_solves(monkeypatch):
    monkeypatch.setattr(lapack, "MAX_ORDER", 10)
    calls = []
    real_eig = np.linalg.eig
    monkeypatch.setattr(np.linalg, "eig", lambda a: calls.append(a.shape[0]) or real_eig(a))
    for n in (8, 10, 11, 14):
        a = np.random.default_rng(n).standard_normal((n, n))
        _check(a, *lapack.eig_kept(a))
    assert calls == [11, 14]


def test_without_scipys_capsules_numpy_gives_the_same_result(monkeypatch):
    a = _with_eigenvalues([(0.995, 0.3), (0.98, 1.1), 0.6, -0.2], seed=2)
    with_lapack = lapack.eig_kept(a)
    monkeypatch.setattr(lapack, "_capsule_table", lambda: {})
    monkeypatch.setattr(lapack, "_routines", {})
    assert not lapack.available() and lapack.routine("dlahqr") is None
    z, right, left = lapack.eig_kept(a)
    _check(a, z, right, left)
    np.testing.assert_allclose(np.sort_complex(z), np.sort_complex(with_lapack[0]), rtol=1e-13)


def test_a_routine_reporting_info_nonzero_falls_back(monkeypatch):
    """dlahqr failing to converge (INFO > 0, here simulated through its INFO pointer) → numpy's dgeev."""
    def failing(*args):
        ctypes.c_int.from_address(args[-1]).value = 3  # INFO is the last argument

    monkeypatch.setattr(lapack, "_routines", {**{n: lapack.routine(n) for n in lapack._ARGUMENTS}, "dlahqr": failing})
    calls = []
    real_eig = np.linalg.eig
    monkeypatch.setattr(np.linalg, "eig", lambda a: calls.append(a) or real_eig(a))
    a = np.random.default_rng(8).standard_normal((12, 12))
    _check(a, *lapack.eig_kept(a))
    assert len(calls) == 1


def test_a_signature_that_does_not_match_is_refused(monkeypatch):
    monkeypatch.setattr(lapack, "_ARGUMENTS", {**lapack._ARGUMENTS, "dgebal": 9})
    assert lapack._resolve("dgebal") is None and lapack._resolve("dgehrd") is not None


def _progress_during(fn, args) -> int:
    """How many times a second Python thread went round its loop while fn(*args) ran in this one. With the
    switch interval at 5 s the GIL changes hands only when released: the other thread gives it back at once
    (sleep(0)), this one never during pure Python, so the count moves only while fn runs without the GIL."""
    count, stop, running = [0], [False], threading.Event()

    def spin():
        running.set()
        while not stop[0]:
            count[0] += 1
            time.sleep(0)

    old = sys.getswitchinterval()
    sys.setswitchinterval(5.0)
    other = threading.Thread(target=spin)
    try:
        other.start()
        running.wait()
        before = count[0]
        fn(*args)
        after = count[0]
    finally:
        stop[0] = True
        sys.setswitchinterval(old)
        other.join()
    return after - before


def test_a_second_thread_runs_while_one_is_inside_lapack():
    """ctypes releases the GIL for the call (the orders of a sweep eigensolve in parallel threads): another
    thread makes progress during it, and none through the same function pointer called with the GIL held
    (ctypes.PYFUNCTYPE, the control). Counts, not speeds: no timing threshold."""
    lahqr = lapack.routine("dlahqr")
    holding = ctypes.PYFUNCTYPE(None, *([ctypes.c_void_p] * 14))(ctypes.cast(lahqr, ctypes.c_void_p).value)
    n = 300
    hess = np.triu(np.random.default_rng(1).standard_normal((n, n)), -1)
    alive = []

    def args():  # WANTT = WANTZ = 0: the eigenvalues of a Hessenberg matrix
        t, wr, wi, z = np.array(hess, order="F"), np.empty(n), np.empty(n), np.zeros(1)
        ints = np.array([n, 1, n, 0, 0], dtype=np.int32)  # N, ILO, IHI, INFO, 0
        alive.append((t, wr, wi, z, ints))
        p = ints.ctypes.data
        return (p + 16, p + 16, p, p + 4, p + 8, t.ctypes.data, p, wr.ctypes.data, wi.ctypes.data, p + 4, p + 8,
                z.ctypes.data, p + 4, p + 12)

    assert _progress_during(lahqr, args()) > 0
    assert _progress_during(holding, args()) == 0
    t, wr, wi, _, ints = alive[0]
    assert ints[3] == 0
    np.testing.assert_allclose(np.sort_complex(wr + 1j * wi), np.sort_complex(np.linalg.eigvals(hess)), atol=1e-10)
