"""Members known to ±2 % each: the model-form error they put on frequencies and on shapes (explain's error levels)."""

import dataclasses

import numpy as np

from era.discrepancy.weights import with_member_scatter
from era.discrepancy.fitting import ErrorLevels
from era.discrepancy.frame_model import FrameModel
from era.discrepancy.measured import modes_from_arrays
from era.examples.frames import portal, two_storey


def _unit(s):
    return s / np.linalg.norm(s, axis=0)


def test_shape_sensitivity_to_each_member_matches_finite_differences():
    """Modal superposition over 80 modes: each member's dψ within 5 % of a finite difference; over the default 30
    (what explain uses), the 2 % scatter's σ of each shape component, √(mean Σ_e dψ²), within 20 % (an error
    level: the truncated modes' share is small)."""
    for frame in (portal(), two_storey()):
        model = FrameModel.of(frame).exact
        n = 8
        fine, coarse = model.member_shape_sensitivity(n, n_basis=80), model.member_shape_sensitivity(n)
        f0, s0 = model.modes(n)
        seen = np.linalg.norm(s0, axis=0) > 1e-6 * np.linalg.norm(s0, axis=0).max()
        assert fine.shape == (len(frame.members), len(frame.sensors), n) and np.all(fine[:, :, ~seen] == 0)
        fds = []
        for k, (i, j, *_) in enumerate(frame.members):
            h = 1e-5
            f1, s1 = model.with_params(member_at=(i, j), member_factor=1 + h).modes(n)
            p0, p1 = _unit(s0[:, seen]), _unit(s1[:, seen])
            fd = (p1 * np.sign(np.sum(p0 * p1, axis=0)) - p0) / h
            fds.append(fd)
            err = np.linalg.norm(fd - fine[k][:, seen], axis=0)
            assert np.all(err <= 0.05 * np.linalg.norm(fd, axis=0) + 1e-3), (k, err)   # 1e-3: 2e-5 of σ
            # the change is normal to the unit shape (it keeps the norm)
            assert np.allclose(np.sum(p0 * fine[k][:, seen], axis=0), 0, atol=1e-10)
        sigma = lambda d: np.sqrt(np.mean(np.sum(np.asarray(d) ** 2, axis=0), axis=0))   # noqa: E731
        assert np.allclose(sigma(coarse[:, :, seen]), sigma(fds), rtol=0.2)


def test_member_scatter_widens_a_frames_shape_errors_and_not_the_grids():
    model = FrameModel.of(portal())
    f, s = model.modes(6)
    seen = np.flatnonzero(np.linalg.norm(s, axis=0) > 1e-6)      # the in-plane modes the sensors see
    fm = modes_from_arrays(f[seen], s[:, seen])
    errors = ErrorLevels()
    w0 = errors.weights(fm)
    w = with_member_scatter(w0, errors, model, fm, 12)
    d = model.member_shape_sensitivity(12)
    want = 0.02 * np.sqrt(np.mean(np.sum(d[:, :, seen] ** 2, axis=0), axis=0))   # each measured mode's partner
    assert np.allclose(w.sigma_s, np.hypot(w0.sigma_s, np.minimum(want, errors.close_shape_sigma)))
    assert np.all(w.sigma_f > w0.sigma_f) and np.max(w.sigma_s / w0.sigma_s) > 1.2
    none = with_member_scatter(w0, dataclasses.replace(errors, member_scatter=0.0), model, fm, 12)
    assert none is w0


def test_modal_constant_size_sensitivity_matches_finite_differences():
    """d ln‖φ_j(sensors) φ_j(inputs)ᵀ‖ / d a_e of the mass-normalised modes (80-mode superposition) against a
    finite difference of full solves, for impulses at F (x) and E (z) of the portal."""
    model = FrameModel.of(portal()).exact
    rows = model.modal_rows(model.frame.sensors)
    rows = (rows[0], [rows[1][0], rows[1][2]])
    n = 8
    g = model.member_scale_sensitivity(rows, n, n_basis=80)
    f0, u0 = model.node_modes(n)
    size = lambda u: np.linalg.norm(u[rows[0]], axis=0) * np.linalg.norm(u[rows[1]], axis=0)   # noqa: E731
    seen = size(u0) > 1e-8 * size(u0).max()
    for k, (i, j, *_) in enumerate(model.frame.members):
        h = 1e-5
        _, u1 = model.with_params(member_at=(i, j), member_factor=1 + h).node_modes(n)
        fd = (np.log(size(u1)[seen]) - np.log(size(u0)[seen])) / h
        assert np.allclose(g[k][seen], fd, rtol=0.05, atol=2e-3), (k, g[k][seen], fd)
