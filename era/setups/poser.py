"""merge_setups(): one mode shape over several setups of a test through the reference sensors they share.

A multi-setup ambient test (a building, a bridge) keeps a few reference sensors in place while the others rove over
the structure, one setup at a time. Each setup is identified on its own (era.analyse); its shapes are known only up to
a complex factor per mode, different in every setup. The references are in every setup, so each setup's part of a
mode can be brought onto one scale by the factor that best maps its reference components onto the others'
(post-identification rescaling, "PoSER": Döhler, Reynders, Magalhães, Mevel, De Roeck & Cunha, IMAC 2010; pyOMA2's
MultiSetup_PoSER). Unlike pyOMA2, the modes need not be picked by hand in the same order in every setup: they are
paired here by frequency and reference MAC (era.setups.pairing), and a mode some setups missed is kept (see
merge_setups).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core import indicators
from ..errors import DataError
from ..core.modal import ModalModel
from .pairing import RECOVERABLE  # noqa: F401  (the rule merge_setups' ``recover`` follows, named here)
from .pairing import DroppedMode, anchor_references, mean_frequency, pair_setup_modes
from .pairing import recover as recover_clusters

#: Two setups' modes are the same mode only if their frequencies differ by at most this fraction ...
FREQUENCY_TOLERANCE = 0.03
#: ... and their reference components have a MAC of at least this.
MIN_REFERENCE_MAC = 0.9
#: A setup's part of a mode cannot be scaled when its references move less than this (the shape's largest
#: component is 1): the references sit near a node of that mode.
MIN_REFERENCE_LEVEL = 0.05
#: A mode is kept when this many setups saw it (fewer when there are fewer setups).
MIN_SETUPS = 2


@dataclass(frozen=True, eq=False)
class SetupMerge:
    """What ``era.setups.poser.merge_with_evidence`` found: :func:`merge_setups` with its evidence.

    Attributes
    ----------
    model : ModalModel
        The merged modes (see :func:`merge_setups`).
    members : int ndarray, shape (modes, setups)
        Each merged mode's index in each setup's model, -1 where that setup did not see it.
    scales : complex ndarray, shape (modes, setups)
        The factor each setup's shape was multiplied by (before the final normalisation), NaN where not seen.
    reference_mac : ndarray, shape (modes, setups)
        MAC of each setup's reference components with the merged ones, NaN where not seen.
    reference_residual : ndarray, shape (modes, setups)
        |r̄ - α r_k| / |r̄| after the scale α: how far the references disagree.
    scale_std : ndarray, shape (modes, setups)
        The relative standard deviation of each scale |σ_α / α|, estimated from the references' misfit
        (reference_residual / sqrt(references - 1)); NaN where not seen.
    by_frequency : bool ndarray, shape (modes, setups)
        True where a setup's mode was paired by frequency alone: its reference MAC failed (references near a node
        of the mode: small, noisy components) but it was the only mode of that setup within the window of the only
        merged mode there.
    point_setup : int ndarray, shape (n_points,)
        The setup each point was measured in, -1 for the references (every setup).
    point_channel : int ndarray, shape (n_points,)
        The point's channel (output index) in that setup; a reference's in setup 1.
    dropped : tuple
        Every setup mode left out, with its reason.
    recovered : bool ndarray, shape (modes, setups)
        True where a setup's part of the shape is a cluster era.analyse had left out for want of evidence
        (``recover``).
    recovered_from : int ndarray, shape (modes, setups)
        Where recovered, the cluster's index in the setup's ``choice.rejected``.
    complete : bool ndarray, shape (modes,)
        The mode's shape is known in every setup (chosen or recovered), so its point shape has no NaN.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> models = [era.identify(modal_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 1, 300, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 30, 30).realize(6) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> merge = era.merge_choosing_next(models, None, [[0, 1], [0, 1]]).result
    >>> merge.members.tolist(), merge.point_setup.tolist(), merge.complete.tolist()
    ([[0, 0], [1, 1], [2, 2]], [-1, -1, 0, 0, 0, 1, 1], [True, True, True])
    """

    model: ModalModel
    members: np.ndarray
    scales: np.ndarray
    reference_mac: np.ndarray
    reference_residual: np.ndarray
    scale_std: np.ndarray
    by_frequency: np.ndarray
    point_setup: np.ndarray
    point_channel: np.ndarray
    dropped: tuple
    recovered: np.ndarray
    recovered_from: np.ndarray

    @property
    def complete(self) -> np.ndarray:
        """(modes,) bool: its shape is known in every setup (chosen or recovered), so its point shape has no NaN."""
        return np.all((self.members >= 0) | self.recovered, axis=1)


def merge_setups(analyses, references, *, frequency_tolerance: float = FREQUENCY_TOLERANCE,
                 min_reference_mac: float = MIN_REFERENCE_MAC, min_reference_level: float = MIN_REFERENCE_LEVEL,
                 min_setups: int = MIN_SETUPS, recover: bool = True) -> ModalModel:
    """The modes of a multi-setup test, each with one shape over every point of every setup.

    A mode seen in some setups only (often: a setup whose roving sensors sit near its nodes, or a weak mode missed
    in a short record) is kept when at least ``min_setups`` setups saw it: its frequency and damping are real
    evidence, and its shape is known where it was measured (and where ``recover`` found it). At the other setups'
    points the shape is NaN, not 0: a zero would claim a node there (``SetupMerge.complete`` says which modes are
    known everywhere, e.g. for a UFF 55 export). A mode seen in one setup only is dropped (its pairing cannot be
    confirmed through the references, and its shape would be unknown at most points).

    Two poles of one setup within the stronger one's half-power bandwidth (or the pairing window) with the same shape
    (MAC ≥ ``min_reference_mac`` at every sensor) are one mode split in two: the stronger is merged, the other
    dropped. Give two references or more: with one, modes pair by frequency alone and a wrong one cannot be told.

    Parameters
    ----------
    analyses : list of AnalysisResult or ModalModel
        One per setup, in the order of the test.
    references : list of sequences of int
        One per setup: the indices of that setup's reference channels among its outputs, the same physical
        sensors in the same order in every setup.
    frequency_tolerance : float, optional
        Two setups' modes are paired only within this relative frequency difference.
    min_reference_mac : float, optional
        ... and when the MAC of their reference components is at least this.
    min_reference_level : float, optional
        A setup's part of a mode whose reference components are all below this (its largest component being 1)
        cannot be scaled (the references are near a node of it): it is left out, with the reason.
    min_setups : int, optional
        A merged mode must have been seen in at least this many setups (at most the number of setups).
    recover : bool, optional
        Where a setup did not choose a mode that ``min_setups`` others did, take that setup's part of the shape
        from a cluster of its own diagram that era.analyse left out for want of evidence alone (reason "orders" or
        "noise", era.choice.choose) when it matches the mode in frequency (``frequency_tolerance``) and in its
        reference components (``min_reference_mac``, ``min_reference_level``): the other setups have confirmed
        that the mode exists. Only the shape is taken from it; frequency and damping come from the setups that
        chose the mode. Needs era.analyse results (a ModalModel has no diagram). Default True.

    Returns
    -------
    ModalModel
        ``points``: the references (labelled as in the first setup), then each setup's roving channels in setup
        order, each label once (prefixed "S<k>:" when labels repeat across setups, as y1, y2, ... from NExT do).
        ``point_shapes`` = ``shapes`` (n_points, modes), largest component 1, NaN at the points of a setup that
        did not see the mode. ``frequency_hz``, ``damping_ratio``: combined over the setups that saw the mode,
        weighted by 1/σ² where every σ is finite (else the plain mean); ``frequency_std_hz``, ``damping_std``:
        1/sqrt(Σ 1/σ²), widened by the setups' scatter when they disagree by more than their σ (sqrt of χ²/(k-1)
        when above 1: the setups of a test are hours apart and the structure changes with temperature), NaN when
        not all σ are finite. ``emac``: the mean over the setups; ``mpc``: of the merged shape (its finite
        points); ``contribution``: each setup's over that setup's largest, averaged (1 is the strongest mode).
        ``A``, ``B``, ``C``: NOT a realization of any record (each setup has its own excitation and NExT scaling):
        A is the real modal form of the merged eigenvalues (2 × 2 blocks as in ModalModel.select), C maps it to
        the points (2 Re φ, -2 Im φ), B has no columns (inputs = ()): ``reconstruct`` has nothing to say.

    Raises
    ------
    era.DataError
        When setups and references do not match (counts, indices out of range, repeated), a setup has no modes,
        or a setup's references do not move like the others' (the wrong channels were named as references).

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> models = [era.identify(modal_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 1, 300, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 30, 30).realize(6) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> merged = era.merge_setups(models, references=[[0, 1], [0, 1]])
    >>> merged.points
    ('y1', 'y2', 'S1:y3', 'S1:y4', 'S1:y5', 'S2:y3', 'S2:y4')
    >>> print(np.round(merged.frequency_hz, 3))
    [2.  5.5 9. ]
    >>> print(np.round(np.diag(era.mac(merged.point_shapes, shapes[[1, 4, 0, 2, 3, 5, 6]])), 4))
    [1. 1. 1.]
    """
    return merge_with_evidence(analyses, references, frequency_tolerance=frequency_tolerance,
                 min_reference_mac=min_reference_mac, min_reference_level=min_reference_level,
                 min_setups=min_setups, recover=recover).model


def merge_with_evidence(analyses, references, *, frequency_tolerance: float = FREQUENCY_TOLERANCE,
          min_reference_mac: float = MIN_REFERENCE_MAC, min_reference_level: float = MIN_REFERENCE_LEVEL,
          min_setups: int = MIN_SETUPS, recover: bool = True) -> SetupMerge:
    """:func:`merge_setups` with its evidence: which setup mode went where, the scales, the reference agreement,
    and every mode left out with its reason (parameters as there)."""
    analyses = list(analyses)
    models, refs = _checked(analyses, references)
    n_setups = len(models)
    min_setups = max(1, min(int(min_setups), n_setups))
    groups, dropped, frequency_only = pair_setup_modes(models, refs, frequency_tolerance, min_reference_mac,
                                                 min_reference_level)

    kept = []
    for g in groups:
        seen = [k for k in range(n_setups) if g[k] >= 0]
        if len(seen) >= min_setups:
            kept.append(g)
            continue
        for k in seen:
            dropped.append(DroppedMode(k, int(g[k]), float(models[k].frequency_hz[g[k]]),
                                       _unconfirmed(models, k, int(g[k]), frequency_tolerance, min_setups)))
    members = np.array(kept, dtype=int).reshape(-1, n_setups)
    order = np.argsort([mean_frequency(models, m) for m in members], kind="stable")
    members = members[order]

    found = {}
    if recover:
        found = recover_clusters(analyses, models, refs, members, frequency_tolerance, min_reference_mac,
                                 min_reference_level)
    by_frequency = np.array([[(k, j) in frequency_only for k, j in enumerate(g)] for g in members],
                            dtype=bool).reshape(members.shape)
    recovered = np.zeros(members.shape, bool)
    recovered_from = np.full(members.shape, -1)
    for (m, k), (i, _) in found.items():
        recovered[m, k], recovered_from[m, k] = True, i

    labels, point_setup, point_channel = _points(models, refs)
    shapes, scales, rmac, resid = _scaled_shapes(models, refs, members, len(labels), found)
    model = _merged_model(models, members, shapes, labels)
    scale_std = resid / np.sqrt(max(len(refs[0]) - 1, 1))
    return SetupMerge(model=model, members=members, scales=scales, reference_mac=rmac, reference_residual=resid,
                      scale_std=scale_std, by_frequency=by_frequency,
                      point_setup=point_setup, point_channel=point_channel,
                      dropped=tuple(sorted(dropped, key=lambda d: (d.setup, d.index))),
                      recovered=recovered, recovered_from=recovered_from)


# ---- checks -----------------------------------------------------------------------------------------------------
def _unconfirmed(models, k: int, j: int, tol: float, min_setups: int) -> str:
    """Why setup k's mode j is left out when no other setup was paired with it: in how many setups it was seen,
    or, when other setups have a mode at that frequency, which ones and that the references did not agree."""
    f = models[k].frequency_hz[j]
    others = [q + 1 for q, m in enumerate(models) if q != k and np.any(np.abs(m.frequency_hz - f) <= tol * f)]
    if not others:
        return (f"seen in 1 of {len(models)} setups (at least {min_setups} needed): no other setup confirms it "
                "through the references")
    return (f"setup{'s' if len(others) > 1 else ''} {', '.join(map(str, others))} also "
            f"{'have' if len(others) > 1 else 'has'} a mode within {tol:.0%} of {f:.4g} Hz, but neither its "
            "reference components nor its frequency pair it with one of theirs alone (several modes in the window, "
            "or theirs taken by another mode of this setup)")


def _checked(analyses, references) -> tuple[list[ModalModel], list[np.ndarray]]:
    analyses = list(analyses)
    references = list(references)
    if not analyses:
        raise DataError("merge_setups needs at least one setup (a list of era.analyse results).")
    if len(references) != len(analyses):
        raise DataError(f"{len(analyses)} setups but {len(references)} reference lists: give each setup the indices "
                        "of its reference channels.")
    models, refs = [], []
    for k, (a, r) in enumerate(zip(analyses, references)):
        model = getattr(a, "model", a)
        if not isinstance(model, ModalModel):
            raise DataError(f"Setup {k + 1} is a {type(a).__name__}; give era.analyse(...) results (or ModalModels).")
        p = model.shapes.shape[0]
        try:
            idx = np.asarray(r, dtype=int).reshape(-1)
        except (TypeError, ValueError):
            raise DataError(f"Setup {k + 1}'s references {r!r} are not channel indices.") from None
        if idx.size == 0:
            raise DataError(f"Setup {k + 1} names no reference channel: the setups can only be joined through "
                            "sensors that stay in place.")
        if np.any(idx < 0) or np.any(idx >= p):
            raise DataError(f"Setup {k + 1}'s reference indices {idx.tolist()} are out of range: it has {p} channels "
                            f"(0..{p - 1}).")
        if np.unique(idx).size != idx.size:
            raise DataError(f"Setup {k + 1} names a reference channel twice: {idx.tolist()}.")
        if idx.size != len(refs[0] if refs else idx):
            raise DataError(f"Setup {k + 1} has {idx.size} reference channels where setup 1 has {len(refs[0])}: the "
                            "references must be the same sensors, in the same order, in every setup.")
        if model.n_modes == 0:
            raise DataError(f"Setup {k + 1} has no modes (era.analyse chose none): nothing of it can be merged. "
                            "Check its records, or leave it out.")
        models.append(model)
        refs.append(idx)
    return models, refs


# ---- shapes -----------------------------------------------------------------------------------------------------
def _points(models, refs) -> tuple[tuple, np.ndarray, np.ndarray]:
    """The point labels (references first, then each setup's roving channels), the setup of each point (-1: a
    reference) and its channel in that setup (a reference's in setup 1)."""
    ref_labels = [_label(models[0], i) for i in refs[0]]
    roving = [[i for i in range(models[k].shapes.shape[0]) if i not in set(refs[k].tolist())]
              for k in range(len(models))]
    rov_labels = [[_label(models[k], i) for i in roving[k]] for k in range(len(models))]
    flat = ref_labels + [x for labels in rov_labels for x in labels]
    if len(set(flat)) != len(flat):  # generic channel names repeat from setup to setup
        rov_labels = [[f"S{k + 1}:{x}" for x in labels] for k, labels in enumerate(rov_labels)]
        flat = ref_labels + [x for labels in rov_labels for x in labels]
    setup = np.concatenate([np.full(len(ref_labels), -1)] + [np.full(len(r), k) for k, r in enumerate(roving)])
    channel = np.concatenate([refs[0]] + [np.asarray(r, dtype=int) for r in roving])
    return tuple(flat), setup.astype(int), channel.astype(int)


def merged_geometry(geometries, result: SetupMerge):
    """An era.Geometry whose channels are the merged model's points, or None.

    geometries : one era.Geometry or None per setup (as loaded with its records; a setup's geometry places its
        channels on its nodes). The nodes and lines drawn are those of the first setup that has a geometry; a
        point is put on the node of the same id, along its channel's direction, in its own setup's geometry (a
        reference: in setup 1's). A point no geometry places has node -1. None when no setup
        has a geometry or none of the points is placed.
    """
    from ..core.geometry import Geometry
    geometries = list(geometries)
    base = next((g for g in geometries if g is not None), None)
    if base is None:
        return None
    row = {int(n): i for i, n in enumerate(base.node_ids)}
    n_points = result.point_setup.size
    nodes, dirs = np.full(n_points, -1), np.zeros((n_points, 3))
    for q in range(n_points):
        k, ch = int(result.point_setup[q]), int(result.point_channel[q])
        g = geometries[k if k >= 0 else 0]  # a reference: where setup 1 has it (result.point_channel is its)
        if g is None or ch >= g.channel_nodes.size or g.channel_nodes[ch] < 0:
            continue
        nodes[q] = row.get(int(g.node_ids[g.channel_nodes[ch]]), -1)
        dirs[q] = g.channel_directions[ch] if nodes[q] >= 0 else 0.0
    if not (nodes >= 0).any():
        return None
    return Geometry(base.node_ids, base.coordinates, base.edges, nodes.astype(int), dirs, units=base.units,
                    edge_lines=base.edge_lines, line_ids=base.line_ids, line_names=base.line_names)


def _label(model, i) -> str:
    return str(model.outputs[i]) if i < len(model.outputs) else f"ch{i}"


def _scaled_shapes(models, refs, members, n_points, found):
    """Each mode's merged shape: every setup's part (chosen, or recovered: ``found``) times the complex
    α_k = r_k^H r_a / r_k^H r_k that best maps its reference components r_k onto the first seeing setup's r_a (least
    squares); the references the mean of the scaled ones. Largest component 1. Also the scales, each setup's
    reference MAC with the mean and its residual |r̄ - α_k r_k| / |r̄|, (modes, setups)."""
    n_modes, n_setups = members.shape
    n_ref = len(refs[0])
    shapes = np.full((n_points, n_modes), np.nan + 0j)
    scales = np.full((n_modes, n_setups), np.nan + 0j)
    rmac = np.full((n_modes, n_setups), np.nan)
    resid = np.full((n_modes, n_setups), np.nan)
    for m, g in enumerate(members):
        r_a = anchor_references(models, refs, g)
        ref_sum = np.zeros(n_ref, complex)
        seen = 0
        row = n_ref
        for k, model in enumerate(models):
            mask = np.ones(model.shapes.shape[0], bool)
            mask[refs[k]] = False
            n_rov = int(mask.sum())
            phi = model.shapes[:, g[k]] if g[k] >= 0 else found.get((m, k), (None, None))[1]
            if phi is not None:
                r_k = phi[refs[k]]
                alpha = np.vdot(r_k, r_a) / np.vdot(r_k, r_k)
                scales[m, k] = alpha
                shapes[row:row + n_rov, m] = alpha * phi[mask]
                ref_sum += alpha * r_k
                seen += 1
            row += n_rov
        r_bar = ref_sum / seen
        shapes[:n_ref, m] = r_bar
        for k, model in enumerate(models):
            if np.isfinite(scales[m, k]):
                phi = model.shapes[:, g[k]] if g[k] >= 0 else found[(m, k)][1]
                r_k = phi[refs[k]]
                rmac[m, k] = indicators.mac(r_bar, r_k)[0, 0]
                resid[m, k] = np.linalg.norm(r_bar - scales[m, k] * r_k) / np.linalg.norm(r_bar)
        finite = np.isfinite(shapes[:, m])
        big = np.flatnonzero(finite)[np.argmax(np.abs(shapes[finite, m]))]
        scale = shapes[big, m]
        shapes[:, m] /= scale
        scales[m] /= scale
    return shapes, scales, rmac, resid


# ---- the merged model -------------------------------------------------------------------------------------------
def _merged_model(models, members, shapes, labels) -> ModalModel:
    n_modes = members.shape[0]
    first = models[0]
    dt = first.dt
    f = np.empty(n_modes)
    f_sd = np.empty(n_modes)
    zeta = np.empty(n_modes)
    zeta_sd = np.empty(n_modes)
    gamma = np.empty(n_modes)
    contrib = np.empty(n_modes)
    pair = np.empty(n_modes, bool)
    sources = set()
    for m, g in enumerate(members):
        seen = [(k, j) for k, j in enumerate(g) if j >= 0]
        f[m], f_sd[m] = combine([models[k].frequency_hz[j] for k, j in seen],
                                [models[k]._std(models[k].frequency_std_hz)[j] for k, j in seen])
        zeta[m], zeta_sd[m] = combine([models[k].damping_ratio[j] for k, j in seen],
                                      [models[k]._std(models[k].damping_std)[j] for k, j in seen])
        gamma[m] = np.mean([models[k].emac[j] for k, j in seen])
        contrib[m] = np.mean([models[k].contribution[j] / np.max(models[k].contribution) for k, j in seen])
        pair[m] = all(models[k].is_pair[j] for k, j in seen)
        sources.update(models[k].uncertainty_source for k, _ in seen)
    wd = 2 * np.pi * f
    s = -zeta * wd / np.sqrt(np.maximum(1 - zeta**2, 1e-300)) + 1j * wd  # damped frequency f, ratio ζ
    for m in np.flatnonzero(~pair):  # a real pole (no frequency to weigh): the mean of the setups' s
        s[m] = np.mean([models[k].eigenvalues[j] for k, j in enumerate(members[m]) if j >= 0]).real
    z = np.exp(s * dt)
    mu = np.array([indicators.mpc(shapes[np.isfinite(shapes[:, m]), m:m + 1])[0] for m in range(n_modes)])
    A, C = _modal_form(z, shapes, pair)
    sources.discard("")
    source = f"combined over {len(models)} setups" + (f" ({'; '.join(sorted(sources))})" if sources else "")
    return ModalModel(A=A, B=np.zeros((A.shape[0], 0)), C=C, dt=dt, z=z, shapes=shapes,
                      amplitudes=np.zeros((n_modes, 0), complex), emac=gamma, mpc=mu, contribution=contrib,
                      is_pair=pair, outputs=labels, inputs=(), method=first.method, frequency_std_hz=f_sd,
                      damping_std=zeta_sd, uncertainty_source=source, points=labels, point_shapes=shapes)


def _modal_form(z, shapes, pair):
    """A in real modal form (a 2 × 2 block [[Re z, -Im z], [Im z, Re z]] per pair) and C = [2 Re φ, -2 Im φ]."""
    n = int(np.sum(np.where(pair, 2, 1)))
    A, C = np.zeros((n, n)), np.zeros((shapes.shape[0], n))
    k = 0
    for j in range(len(z)):
        if pair[j]:
            A[k:k + 2, k:k + 2] = [[z[j].real, -z[j].imag], [z[j].imag, z[j].real]]
            C[:, k], C[:, k + 1] = 2 * shapes[:, j].real, -2 * shapes[:, j].imag
            k += 2
        else:
            A[k, k], C[:, k] = z[j].real, shapes[:, j].real
            k += 1
    return A, C


def combine(values, stds) -> tuple[float, float]:
    """One estimate from several setups' (value, σ): the 1/σ²-weighted mean and its σ = 1/sqrt(Σ 1/σ²), widened
    by sqrt(χ²/(k-1)) when the values scatter more than their σ say (Birge's ratio); the plain mean and σ NaN when
    a σ is not finite (or not positive)."""
    x = np.asarray(values, dtype=float)
    sd = np.asarray(stds, dtype=float)
    if x.size == 0:
        return np.nan, np.nan
    if not np.all(np.isfinite(sd) & (sd > 0)):
        return float(np.mean(x)), np.nan
    w = 1 / sd**2
    mean = float(np.sum(w * x) / np.sum(w))
    sigma = float(1 / np.sqrt(np.sum(w)))
    if x.size > 1:
        chi2 = float(np.sum(w * (x - mean) ** 2))
        sigma *= np.sqrt(max(1.0, chi2 / (x.size - 1)))
    return mean, sigma
