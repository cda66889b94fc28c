"""The truncated SVD (Gram matrix + one Rayleigh-Ritz step) that the sweep takes when max_order is far below
min(H(0) shape): the same singular values, poles and indicators as the dense path."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import era
from era.examples.paper_cases import case_1
from era.examples.synthetic import modal_response
from era.core.svd import dense_svd, truncated_svd


def test_auto_takes_the_truncated_svd_only_when_the_order_is_far_below_the_shape():
    data, _ = modal_response(np.linspace(2, 40, 12), 0.01, 6, 4, 900, 0.01, snr_db=40, seed=2)
    assert era.identify(data, rows=50, cols=100, max_order=40).svd_method == "truncated"  # 40 ≤ 300 / 4
    assert era.identify(data, rows=50, cols=100, max_order=200).svd_method == "dense"
    assert era.identify(data, rows=50, cols=100).svd_method == "dense"


def test_truncated_sweep_equals_the_dense_one_pole_by_pole():
    data, _ = modal_response(np.linspace(2, 40, 12), 0.01, 6, 4, 900, 0.01, snr_db=30, seed=2)
    fast = era.identify(data, rows=50, cols=100, max_order=60)
    dense = era.identify(data, rows=50, cols=100, svd_method="dense")
    np.testing.assert_allclose(fast.singular_values[:60], dense.singular_values[:60], rtol=1e-11)
    orders = range(2, 61, 2)
    a, b = era.stabilization(fast, orders), era.stabilization(dense, orders)
    assert np.array_equal(a.order, b.order) and np.array_equal(a.stable, b.stable)
    np.testing.assert_allclose(a.frequency_hz, b.frequency_hz, rtol=1e-8)
    np.testing.assert_allclose(a.damping_ratio[a.stable], b.damping_ratio[b.stable], rtol=1e-7)
    np.testing.assert_allclose(a.emac[a.stable], b.emac[b.stable], atol=1e-8)
    np.testing.assert_allclose(a.mpc[a.stable], b.mpc[b.stable], atol=1e-8)


def test_truncated_singular_values_keep_the_round_off_of_the_dense_ones():
    """Noise-free Case I: past the rank, the values stay at round-off (not ε·d_1²/d_i as a Gram matrix alone
    would give), so the δ test (eqs. 38-39) finds order 10 on this path too."""
    ident = era.identify(case_1(), rows=90, cols=90, max_order=20)
    assert ident.svd_method == "truncated"
    d = ident.singular_values
    assert ident.order(tol=1e-12) == 10 and d[10] / d[0] < 1e-13
    np.testing.assert_allclose(ident.realize(10).frequency_hz, np.arange(1, 6) / (2 * np.pi), rtol=1e-8)


def test_truncated_triplets_are_orthonormal_and_wide_matrices_work():
    rng = np.random.default_rng(0)
    h = (rng.standard_normal((120, 30)) * np.logspace(0, -4, 30)) @ rng.standard_normal((30, 200))
    for m in (h, h.T):  # values down to 2e-3 d_1: the direct Gram route (orthogonality to ε d_1²/d_k²)
        p, d, q = truncated_svd(m, 20)
        np.testing.assert_allclose(p.T @ p, np.eye(20), atol=1e-10)
        np.testing.assert_allclose(q.T @ q, np.eye(20), atol=1e-10)
        exact = dense_svd(m)[1]
        np.testing.assert_allclose(d[:20], exact[:20], rtol=1e-10)
        np.testing.assert_allclose(m @ q, p * d[:20], atol=1e-10 * d[0])
        # the values past the rank, from the Gram matrix (the plot and the order suggestion): to ε d_1²/d_i²
        # relative above its round-off, at its round-off (√ε d_1, not ε d_1) where H(0) has none (rank 30)
        assert d.size == 120 and np.all(np.diff(d) <= 0)
        np.testing.assert_allclose(d[20:30], exact[20:30], rtol=1e-6)
        assert np.all(d[30:] < 1e-6 * d[0])


def test_gram_eigenvectors_by_inverse_iteration_on_a_flat_noise_floor_match_the_library_and_are_orthonormal():
    """gram_eigen's leading vectors (sterf's eigenvalues, then stein) against LAPACK's syevd on a Gram matrix
    whose trailing eigenvalues crowd together (a signal of 10 values over a noise floor of 390 within 3 %),
    and the MRRR fallback when inverse iteration reports failure."""
    import scipy.linalg
    from unittest import mock
    from era.core import svd

    rng = np.random.default_rng(3)
    basis, _ = np.linalg.qr(rng.standard_normal((400, 400)))
    values = np.concatenate([np.logspace(3, 1, 10), 1.0 + 0.03 * rng.random(390)])
    gram = (basis * values) @ basis.T
    gram = (gram + gram.T) / 2
    w, v = scipy.linalg.eigh(gram)
    for patch in (None, (np.zeros((400, 60)), 1)):  # (vectors, info > 0): stein failed
        ctx = mock.patch.object(scipy.linalg.lapack, "dstein", return_value=patch) if patch else mock.MagicMock()
        with ctx:
            every, lead = svd.gram_eigen(gram, 60)
        np.testing.assert_allclose(every, w[::-1], rtol=1e-12, atol=1e-12 * w[-1])
        assert np.abs(lead.T @ lead - np.eye(60)).max() < 1e-12
        assert np.abs(gram @ lead - lead * every[:60]).max() < 1e-12 * every[0]
        # the signal subspace equals the library's to round-off (the noise floor's vectors are not unique)
        np.testing.assert_allclose(np.abs(lead[:, :10].T @ v[:, ::-1][:, :10]), np.eye(10), atol=1e-10)


def test_inverse_iteration_in_two_threads_equals_one_stein_and_refuses_a_split_through_a_repeated_value():
    """_stein_in_parts (two steins in threads, the lower part made orthogonal to the upper) against one stein on
    the tridiagonal form of a Gram matrix with a crowded noise floor; and on a matrix whose eigenvalue at the
    cut is repeated (the two parts then find the same directions) the split is refused and the caller runs one
    stein."""
    import scipy.linalg
    from era.core import svd

    rng = np.random.default_rng(4)
    basis, _ = np.linalg.qr(rng.standard_normal((300, 300)))
    gram = (basis * np.concatenate([np.logspace(4, 1, 20), 1.0 + 0.03 * rng.random(280)])) @ basis.T
    c, diag, off, tau, info = scipy.linalg.lapack.dsytrd((gram + gram.T) / 2, lower=1)
    values = scipy.linalg.eigvalsh_tridiagonal(diag, off, lapack_driver="sterf")[-80:]
    tri = np.diag(diag) + np.diag(off, 1) + np.diag(off, -1)
    one = svd._tridiagonal_vectors(diag, off, values)
    with ThreadPoolExecutor(1) as helper:
        two = svd._stein_in_parts(diag, off, values, helper)
    assert two is not None and two.flags.f_contiguous
    assert np.abs(two.T @ two - np.eye(80)).max() < 1e-13
    assert np.abs(tri @ two - two * values).max() < 1e-12 * values[-1]
    np.testing.assert_allclose(np.abs(np.einsum("ij,ij->j", one, two)), 1.0, atol=1e-12)

    # eigenvalue 2 three times (blocks split by zero off-diagonals), cut between its copies
    diag = np.array([2.0, 2.0, 2.0, 5.0, 7.0, 1.0])
    off = np.array([0.0, 0.0, 0.0, 0.3, 0.2])
    values = scipy.linalg.eigvalsh_tridiagonal(diag, off)[-5:]  # 2, 2, 2, ~5, ~7: the cut falls among the 2s
    with ThreadPoolExecutor(1) as helper:
        assert svd._stein_in_parts(diag, off, values, helper) is None
        np.testing.assert_array_equal(svd._tridiagonal_vectors(diag, off, values, helper),
                                      svd._tridiagonal_vectors(diag, off, values))


def test_gram_eigen_with_a_second_thread_equals_one_thread_and_the_reflectors_in_two_steps_equal_ormqr():
    """gram_eigen(workers=2) (the reflectors' block factors beside sterf, stein in two parts, the factors
    applied after) against workers=1 (sterf, one stein, ormqr), and era.core.lapack's two steps against ormqr on
    sizes around the block of 64 reflectors."""
    from unittest import mock

    import scipy.linalg
    from era.core import lapack, svd

    rng = np.random.default_rng(6)
    basis, _ = np.linalg.qr(rng.standard_normal((260, 260)))
    gram = (basis * np.concatenate([np.logspace(5, 2, 15), 1.0 + 0.05 * rng.random(245)])) @ basis.T
    gram = (gram + gram.T) / 2
    w1, v1 = svd.gram_eigen(gram, 70, workers=1)
    w2, v2 = svd.gram_eigen(gram, 70, workers=2)
    np.testing.assert_array_equal(w1, w2)
    assert np.abs(v2.T @ v2 - np.eye(70)).max() < 1e-13
    assert np.abs(gram @ v2 - v2 * w2[:70]).max() < 1e-12 * w2[0]
    np.testing.assert_allclose(np.abs(np.einsum("ij,ij->j", v1, v2)), 1.0, atol=1e-12)
    # only the upper triangle is read (era.core.hankel.gram leaves the rest unset), in the matrix's own memory when
    # allowed; the caller's ``beside`` runs once, in the helper thread beside sterf or first with one worker
    for workers in (1, 2):
        upper, called = np.triu(gram) + np.tril(np.full_like(gram, np.nan), -1), []
        w4, v4 = svd.gram_eigen(upper, 70, workers=workers, overwrite=True, beside=lambda: called.append(1))
        assert called == [1] and not np.allclose(np.triu(upper, 1), np.triu(gram, 1))  # reduced in place
        np.testing.assert_array_equal(w4, w1)
        np.testing.assert_allclose(np.abs(np.einsum("ij,ij->j", v1, v4)), 1.0, atol=1e-12)
    for n in (2, 63, 64, 65, 129, 200):
        g = rng.standard_normal((n + 1, n + 1))
        c, _, _, tau, _ = scipy.linalg.lapack.dsytrd(g + g.T, lower=1)
        y = rng.standard_normal((n, 9))
        ref = scipy.linalg.lapack.dormqr("L", "N", c[1:, :n], tau, y, lwork=64 * 9 + 4160)[0]
        out = lapack.apply_reflectors(c[1:, :n], lapack.reflector_blocks(c[1:, :n], tau), y)
        np.testing.assert_allclose(out, ref, atol=1e-13 * np.abs(ref).max())
    assert lapack.reflector_blocks(np.ascontiguousarray(c[1:, :n]), tau) is None  # not a Fortran view: ormqr
    # without scipy's dlarft, dsterf and dstein (the ctypes routines), the same result by scipy's wrappers
    missing = {name: None for name in ("dlarft", "dlarfb", "dsterf", "dstein")}
    with mock.patch.dict(lapack._routines, missing):
        w3, v3 = svd.gram_eigen(gram, 70, workers=2)
    np.testing.assert_array_equal(w3, w1)
    np.testing.assert_allclose(np.abs(np.einsum("ij,ij->j", v1, v3)), 1.0, atol=1e-12)


def test_hankel_products_by_fft_equal_the_dense_matrix_and_identify_does_not_change():
    """HankelOperator's H X, H^T X, its blocks and the Gram matrix built from it against the dense H(0), on
    square, wide and tall shapes; then identify (which takes the FFT products on 900 × 2392) against the same
    identification from the dense H(0)."""
    from unittest import mock
    from era.core import hankel

    rng = np.random.default_rng(5)
    for p, m, r, s in [(3, 2, 7, 7), (2, 3, 5, 11), (4, 1, 13, 3), (1, 1, 1, 1)]:
        y = rng.standard_normal((r + s + 2, p, m))
        dense = hankel.block_hankel(y, np.arange(r), np.arange(s))
        op = hankel.HankelOperator(y, r, s, by_fft=True)  # the FFT products, whatever fft_pays says
        x, u = rng.standard_normal((s * m, 4)), rng.standard_normal((r * p, 3))
        scale = np.linalg.norm(dense)
        np.testing.assert_allclose(op @ x, dense @ x, atol=1e-13 * scale * np.linalg.norm(x))
        np.testing.assert_allclose(op.T @ u, dense.T @ u, atol=1e-13 * scale * np.linalg.norm(u))
        np.testing.assert_allclose(op.matvec(x[:, 0]), dense @ x[:, 0], atol=1e-13 * scale * np.linalg.norm(x))
        np.testing.assert_allclose(op.rmatvec(u[:, 0]), dense.T @ u[:, 0], atol=1e-13 * scale * np.linalg.norm(u))
        np.testing.assert_allclose(op.dense(), dense)
        np.testing.assert_array_equal(op.first_block_row(), dense[:p])
        np.testing.assert_array_equal(op.first_block_column(), dense[:, :m])
        # the Gram matrix's upper triangle (all gram builds) by the recursion from each first block row (FFT,
        # lag by lag without H(0), the dense product), in one thread and split in two, against the product
        exact = np.triu(dense @ dense.T if r * p <= s * m else dense.T @ dense)
        plain = hankel.HankelOperator(y, r, s, by_fft=False)
        with mock.patch.object(hankel, "SPLIT_MIN", 0):  # the lags in two threads whatever the size
            for h, workers in [(op, 1), (op, 2), (plain, 1), (plain, 2), (dense, 1), (dense, 2)]:
                np.testing.assert_allclose(np.triu(hankel.gram(y, np.arange(r), np.arange(s), h, workers)),
                                           exact, atol=1e-13 * scale ** 2)
        assert plain._dense is None  # the Gram matrix did not need H(0); its products do
        np.testing.assert_allclose(plain.T @ u, dense.T @ u, atol=1e-13 * scale * np.linalg.norm(u))
        np.testing.assert_array_equal(plain.dense(), dense)
    with pytest.raises(era.EraError, match="samples"):
        hankel.HankelOperator(np.zeros((5, 1, 1)), 3, 4)

    data, _ = modal_response(np.linspace(0.3, 14, 20), 0.01, 9, 8, 400, 1 / 32, snr_db=30, seed=0)
    assert hankel.fft_pays(100, 299) and not hankel.fft_pays(40, 500)
    fast = era.identify(data, 100, 299, max_order=120)
    with mock.patch.object(hankel, "fft_pays", return_value=False):
        plain = era.identify(data, 100, 299, max_order=120)
    np.testing.assert_allclose(fast.singular_values[:120], plain.singular_values[:120], rtol=1e-12)
    # past the rank, from the Gram matrix's eigenvalues: to ε d_1² / d_i² (era.core.svd.truncated_svd)
    np.testing.assert_allclose(fast.singular_values, plain.singular_values, rtol=1e-9)
    np.testing.assert_allclose(np.abs(np.sum(fast.Q * plain.Q, axis=0)), 1.0, atol=1e-9)
    np.testing.assert_allclose(fast.model(40, uncertainty=False).eigenvalues,
                               plain.model(40, uncertainty=False).eigenvalues, rtol=1e-10)
    # noise-free: the kept values reach round-off, so the Rayleigh-Ritz step runs, on the operator too
    exact, _ = modal_response(np.linspace(0.3, 14, 20), 0.01, 9, 8, 400, 1 / 32, snr_db=None, seed=0)
    fast, dense = era.identify(exact, 100, 299, max_order=120), era.identify(exact, 100, 299, svd_method="dense")
    assert fast.P.shape == (900, 40)  # the numerical rank, 2 × 20 modes
    np.testing.assert_allclose(fast.singular_values[:40], dense.singular_values[:40], rtol=1e-13)
    np.testing.assert_allclose(np.sort_complex(fast.model(40, uncertainty=False).eigenvalues),
                               np.sort_complex(dense.model(40, uncertainty=False).eigenvalues), atol=1e-12)
