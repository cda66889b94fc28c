"""Merge before identifying (PreGER): the setups' correlation functions on one scale, one identification.

PoSER (setups.merge) identifies every setup on its own and rescales the shapes afterwards, so a mode must be found in
every setup to be complete. With short setups a weak mode is often missed somewhere. Pre-identification rescaling
("PreGER": Döhler, Reynders, Magalhães, Mevel, De Roeck & Cunha, IMAC 2010; Reynders, Magalhães, Lombaert,
De Roeck & Cunha 2009) puts the setups' correlation functions with respect to the reference sensors on one scale
first, and identifies the stacked functions once: every mode found is known at every point.

Each setup's excitation has its own level, so its correlations R_k(τ) (outputs × references) carry a factor of
their own. The references are in every setup, so the factor is the one that maps setup k's reference block
R_k,ref(τ) onto setup 1's (least squares over every lag). This assumes that the excitation's spectrum keeps its
shape from setup to setup and only its level changes (wind, traffic in one weather); when its shape changes, the
modes' scales differ from setup to setup and one factor cannot hold them all: PoSER, which scales mode by mode,
does not need that assumption. The residual of the fit (``reference_residual``) says how well it holds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.data import ResponseData
from ..errors import DataError


@dataclass(frozen=True, eq=False)
class PregerMerge:
    """What :func:`merge_correlations` made.

    Attributes
    ----------
    data : ResponseData
        markov (N, n_points, r): the references' correlations (the mean over the setups, scaled), then each
        setup's roving channels'; outputs the point labels (as era.merge_setups names them).
    scales : ndarray, shape (setups,)
        The factor each setup's correlations were multiplied by (setup 1: 1).
    reference_residual : ndarray, shape (setups,)
        |R̄_ref - c_k R_k,ref| / |R̄_ref| after the scale: how well one factor per setup holds (large when the
        excitation's spectrum changed shape between setups).
    point_setup : int ndarray, shape (n_points,)
        The setup each point was measured in, -1 for the references.
    point_channel : int ndarray, shape (n_points,)
        Its channel in that setup (a reference's in setup 1).

    Examples
    --------
    >>> from era.examples.synthetic import ambient_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))
    >>> channels = [[1, 4, 0, 2, 3], [1, 4, 5, 6]]
    >>> records = [ambient_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 3000, 0.02, seed=k,
    ...                             shapes=shapes[c])[0] for k, c in enumerate(channels)]
    >>> merged = era.merge_correlations([era.markov_from_ambient(y, 0.02, [0, 1]) for y in records],
    ...                                 [[0, 1], [0, 1]])
    >>> merged.point_setup.tolist(), merged.point_channel.tolist(), float(merged.scales[0])
    ([-1, -1, 0, 0, 0, 1, 1], [0, 1, 2, 3, 4, 2, 3], 1.0)
    """

    data: ResponseData
    scales: np.ndarray
    reference_residual: np.ndarray
    point_setup: np.ndarray
    point_channel: np.ndarray


def merge_correlations(setups, references) -> PregerMerge:
    """The setups' NExT correlation functions with respect to their references, on one scale and stacked (PreGER).

    Parameters
    ----------
    setups : list of ResponseData
        One per setup, each through NExT with that setup's reference channels as the only correlation references
        (``era.markov_from_ambient(y, dt, references[k])`` or
        ``era.load(file, kind="ambient", references=references[k]).data``): markov (N_k, p_k, r), the same Δτ and
        r in every setup; the first min N_k lags are used.
    references : list of sequences of int
        Per setup, the indices of its reference channels among its outputs (the same sensors in the same order
        in every setup; the order of NExT's references).

    Returns
    -------
    PregerMerge
        ``era.analyse(result.data)`` identifies every setup's points at once.

    Raises
    ------
    era.DataError
        When the setups do not match (Δτ, references) or a setup's references are silent.

    Examples
    --------
    Two setups of an ambient test (60 s at 50 Hz), five and four sensors, two of them in both:

    >>> from era.examples.synthetic import ambient_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # three modes at seven points
    >>> channels = [[1, 4, 0, 2, 3], [1, 4, 5, 6]]
    >>> records = [ambient_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 3000, 0.02, seed=k,
    ...                             shapes=shapes[c])[0] for k, c in enumerate(channels)]
    >>> merged = era.merge_correlations([era.markov_from_ambient(y, 0.02, [0, 1]) for y in records],
    ...                                 [[0, 1], [0, 1]])
    >>> merged.data.markov.shape, merged.data.outputs
    ((100, 7, 2), ('y1', 'y2', 'S1:y3', 'S1:y4', 'S1:y5', 'S2:y3', 'S2:y4'))
    >>> model = era.identify(merged.data, 20, 20).model(6, uncertainty=False)
    >>> print(np.round(model.frequency_hz, 1))
    [2.  5.5 9. ]
    """
    setups, refs = list(setups), [np.asarray(r, dtype=int).reshape(-1) for r in references]
    if len(setups) < 1 or len(refs) != len(setups):
        raise DataError(f"{len(setups)} setups but {len(refs)} reference lists: give each setup its references.")
    first = setups[0]
    for k, d in enumerate(setups):
        if not isinstance(d, ResponseData):
            raise DataError(f"Setup {k + 1} is a {type(d).__name__}; give era.ResponseData (NExT correlations).")
        if not np.isclose(d.dt, first.dt):
            raise DataError(f"Setup {k + 1} is sampled at Δτ = {d.dt:g} s where setup 1 is at {first.dt:g} s: "
                            "resample the setups to one rate.")
    # NExT's default lags follow each record's own spectrum: the lags every setup has are kept
    n, r = min(d.markov.shape[0] for d in setups), first.markov.shape[2]
    for k, (d, idx) in enumerate(zip(setups, refs)):
        if d.markov.shape[2] != r or idx.size != r:
            raise DataError(f"Setup {k + 1} is correlated with {d.markov.shape[2]} references and names {idx.size}; "
                            f"setup 1 has {r}: NExT with the reference channels only, the same in every setup.")
        if np.any(idx < 0) or np.any(idx >= d.markov.shape[1]):
            raise DataError(f"Setup {k + 1}'s reference indices {idx.tolist()} are out of range.")
    anchor = first.markov[:n, refs[0], :]
    blocks = [d.markov[:n, idx, :] for d, idx in zip(setups, refs)]
    scales = np.ones(len(setups))
    for k, block in enumerate(blocks):
        power = float(np.sum(block * block))
        if not power > 0:
            raise DataError(f"Setup {k + 1}'s reference channels are silent (their correlations are 0).")
        scales[k] = float(np.sum(block * anchor)) / power
    mean_ref = np.mean([c * b for c, b in zip(scales, blocks)], axis=0)
    residual = np.array([np.linalg.norm(mean_ref - c * b) / np.linalg.norm(mean_ref) for c, b in zip(scales, blocks)])
    labels, point_setup, point_channel, parts = _stacked(setups, refs, scales, n)
    markov = np.concatenate([mean_ref] + parts, axis=1)
    data = ResponseData(markov, first.dt, outputs=labels, inputs=first.inputs,
                        meta={"conversions": [f"PreGER: {len(setups)} setups' NExT correlations scaled onto setup "
                                              "1's references and stacked"]})
    return PregerMerge(data=data, scales=scales, reference_residual=residual, point_setup=point_setup,
                       point_channel=point_channel)


def _stacked(setups, refs, scales, n: int):
    """Labels (the references as setup 1 names them, then each setup's roving channels, "S<k>:" prefixed when
    names repeat), each point's setup and channel, and the roving rows scaled."""
    names = [list(d.outputs) for d in setups]
    roving = [[i for i in range(d.markov.shape[1]) if i not in set(idx.tolist())] for d, idx in zip(setups, refs)]
    ref_labels = [names[0][i] for i in refs[0]]
    rov_labels = [[names[k][i] for i in rov] for k, rov in enumerate(roving)]
    flat = ref_labels + [x for labels in rov_labels for x in labels]
    if len(set(flat)) != len(flat):
        rov_labels = [[f"S{k + 1}:{x}" for x in labels] for k, labels in enumerate(rov_labels)]
    labels = tuple(ref_labels + [x for labels in rov_labels for x in labels])
    point_setup = np.concatenate([np.full(len(ref_labels), -1)] + [np.full(len(r), k) for k, r in enumerate(roving)])
    point_channel = np.concatenate([refs[0]] + [np.asarray(r, dtype=int) for r in roving])
    parts = [scales[k] * d.markov[:n, rov, :] for k, (d, rov) in enumerate(zip(setups, roving))]
    return labels, point_setup.astype(int), point_channel.astype(int), parts
