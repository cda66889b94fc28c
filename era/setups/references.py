"""propose_references(): which channels of a multi-setup test are the reference sensors, found from the identified
modes, not from the channel names (generic names such as ch1..ch8 say nothing).

The references stay in place, so the reference part of every mode is the same vector in every setup, up to the
complex factor each setup's shape carries. A roving channel measures another point in every setup, so its
components do not keep that proportion over several modes. The proposal therefore:

1. pairs the setups' modes by frequency alone where that is unambiguous (one mode of the other setup within the
   window, and that mode has one of the first setup's modes within its window): the shared modes;
2. scores every pair of channels of setup 1 against every ordered pair of each other setup: the MAC of their two
   components, mode by mode, over the shared modes (1 when the two channels keep the same ratio in both setups);
3. keeps the pairs whose MAC over the shared modes (each mode weighted by how much the pair moves in it) passes in every setup, and proposes their channels only when they form one
   consistent set (each channel of setup 1 the same channel in a given setup, whichever pair it is in, and every
   two of them a passing pair). Anything else (no passing pair, a channel that would map to two channels, a pair
   that passes in its swapped order as well: a symmetric structure with references at mirror points) is no
   proposal: a wrong proposal is worse than none.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations, permutations

import numpy as np

from ..core.modal import ModalModel
from ..words import counted

#: Two setups' modes are one shared mode when their frequencies differ by at most this fraction (and uniquely).
FREQUENCY_TOLERANCE = 0.03
#: A pair of channels is the references' when its MAC over the shared modes (weighted by how much the pair moves in
#: each, see _score) is at least this in every setup.
MIN_MAC = 0.99
#: The pair is ambiguous when its runner-up (another ordered pair of some setup) passes too and misfits less than
#: this many times as much (1 - MAC): a roving sensor beside a reference, or references at mirror points.
MIN_MARGIN = 3.0
#: A channel is a candidate when it moves by at least this fraction of each mode's largest component in half the
#: shared modes or more.
MIN_LEVEL = 0.1
#: ... over at least this many shared modes (with fewer, a roving pair can keep a ratio by chance).
MIN_SHARED_MODES = 3


@dataclass(frozen=True)
class ReferenceCandidate:
    """A pair of channels of setup 1 and, per setup, the ordered pair of channels that best keeps their ratio.

    channels : (setups,) tuples of 2 int, the pair's indices in each setup (setup 1's first).
    mac : (setups, shared modes) MAC of the pair's components with setup 1's, mode by mode (row 0: ones).
    score : the smallest over the other setups of the weighted mean MAC over the shared modes (_score).
    runner_up : the same score of the second best ordered pair in the setup where it comes closest (NaN with one
        setup): a runner-up that passes too makes the pair ambiguous.
    """

    channels: tuple
    mac: np.ndarray
    score: float
    runner_up: float


@dataclass(frozen=True)
class ReferenceProposal:
    """What :func:`reference_evidence` found.

    Attributes
    ----------
    references : list of list of int, or None
        Per setup, the indices of the proposed reference channels (setup 1's order), or None.
    shared_hz : ndarray, shape (shared modes,)
        The frequencies of the modes every setup saw (setup 1's), Hz.
    shared : int ndarray, shape (setups, shared modes)
        Each shared mode's index in each setup's model.
    candidates : tuple
        Every pair of setup 1's channels, best score first.
    reason : str
        Why this proposal (or none), in words.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> models = [era.identify(modal_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 1, 300, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 30, 30).realize(6) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> proposal = era.reference_evidence(models)
    >>> print(np.round(proposal.shared_hz, 3), len(proposal.candidates))
    [2.  5.5 9. ] 10
    """

    references: list | None
    shared_hz: np.ndarray
    shared: np.ndarray
    candidates: tuple
    reason: str


def propose_references(analyses, *, min_mac: float = MIN_MAC,
                       frequency_tolerance: float = FREQUENCY_TOLERANCE) -> list | None:
    """The proposed reference channels of a multi-setup test, found from its modes.

    The same sensors in the same order in every setup (setup 1's order); see :func:`reference_evidence` for the
    evidence and the reason.

    Parameters
    ----------
    analyses : list of AnalysisResult or ModalModel
        One per setup, in the order of the test.
    min_mac : float, optional
        A pair of channels is the references' when the MAC of its two components with setup 1's, averaged over the
        shared modes (each weighted by how much the pair moves in it), is at least this in every setup.
    frequency_tolerance : float, optional
        The relative frequency window in which two setups' modes are one shared mode.

    Returns
    -------
    list of list of int, or None
        Per setup, the indices of the proposed reference channels; None when no proposal passes its check.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> models = [era.identify(modal_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 1, 300, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 30, 30).realize(6) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> era.propose_references(models)
    [[0, 1], [0, 1]]
    """
    return reference_evidence(analyses, min_mac=min_mac, frequency_tolerance=frequency_tolerance).references


def reference_evidence(analyses, *, min_mac: float = MIN_MAC,
                       frequency_tolerance: float = FREQUENCY_TOLERANCE) -> ReferenceProposal:
    """The reference channels of a multi-setup test, found from its modes, with the evidence.

    Parameters
    ----------
    analyses : list of AnalysisResult or ModalModel
        One per setup, in the order of the test.
    min_mac : float, optional
        A pair of channels is the references' when the MAC of its two components with setup 1's, averaged over the
        shared modes (each weighted by how much the pair moves in it), is at least this in every setup.
    frequency_tolerance : float, optional
        The relative frequency window in which two setups' modes are one shared mode.

    Returns
    -------
    ReferenceProposal
        references None when no proposal passes; reason says why.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> models = [era.identify(modal_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 1, 300, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 30, 30).realize(6) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> proposal = era.reference_evidence(models)
    >>> proposal.references, proposal.shared.tolist()
    ([[0, 1], [0, 1]], [[0, 1, 2], [0, 1, 2]])
    >>> proposal.reason  # doctest: +ELLIPSIS
    '2 channels keep the same ratios in every setup over the shared modes (MAC ≥ 1.0000); no other channel does'
    """
    models = [getattr(a, "model", a) for a in analyses]
    if len(models) < 2 or not all(isinstance(m, ModalModel) for m in models):
        return ReferenceProposal(None, np.zeros(0), np.zeros((len(models), 0), int), (),
                                 "references are proposed for two setups or more (era.analyse results)")
    shared = shared_modes(models, frequency_tolerance)
    f = models[0].frequency_hz[shared[0]] if shared.size else np.zeros(0)
    if shared.shape[1] < MIN_SHARED_MODES:
        return ReferenceProposal(None, f, shared, (), f"only {counted(shared.shape[1], 'mode')} found in every "
                                 f"setup at one frequency: {MIN_SHARED_MODES} or more are needed to tell the references by their "
                                 "components; pick them by hand")
    phis = [m.shapes[:, shared[k]] for k, m in enumerate(models)]  # (channels, shared) per setup
    moving = [np.flatnonzero(_moves(phi)) for phi in phis]
    candidates = sorted((_candidate(phis, pair, moving) for pair in combinations(moving[0].tolist(), 2)),
                        key=lambda c: -c.score)
    passing = [c for c in candidates if c.score >= min_mac]
    refs, reason = _consistent(passing, len(models), min_mac)
    return ReferenceProposal(refs, f, shared, tuple(candidates), reason)


def shared_modes(models, tol: float) -> np.ndarray:
    """(setups, shared) int: setup 1's modes with exactly one mode of every other setup within ``tol`` (and that
    mode with exactly one of setup 1's within its window), their index in every setup."""
    f0 = models[0].frequency_hz
    cols = []
    for j, fj in enumerate(f0):
        col = [j]
        for m in models[1:]:
            near = np.flatnonzero(np.abs(m.frequency_hz - fj) <= tol * fj)
            back = near.size == 1 and np.sum(np.abs(f0 - m.frequency_hz[near[0]]) <= tol * m.frequency_hz[near[0]])
            if near.size != 1 or back != 1:
                break
            col.append(int(near[0]))
        if len(col) == len(models):
            cols.append(col)
    return np.array(cols, dtype=int).T.reshape(len(models), -1)


def pair_mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(modes,) the MAC of two-component vectors a[:, m] and b[:, m] (each (2, modes) complex)."""
    num = np.abs(np.sum(np.conj(a) * b, axis=0)) ** 2
    den = np.sum(np.abs(a) ** 2, axis=0) * np.sum(np.abs(b) ** 2, axis=0)
    return num / np.maximum(den, 1e-300)


def _moves(phi: np.ndarray) -> np.ndarray:
    """(channels,) bool: the channel moves in at least half the shared modes (|φ| ≥ MIN_LEVEL of the mode's
    largest). A channel that barely moves (a vertical sensor on a swaying frame) keeps a "ratio" near 0 with
    anything, so its ratios tell nothing."""
    level = np.abs(phi) / np.maximum(np.max(np.abs(phi), axis=0), 1e-300)
    return np.mean(level >= MIN_LEVEL, axis=1) >= 0.5


def _candidate(phis, pair, moving) -> ReferenceCandidate:
    a = phis[0][list(pair)]
    peak0 = np.max(np.abs(phis[0]), axis=0)
    channels, rows, score, runner = [tuple(pair)], [np.ones(a.shape[1])], np.inf, -np.inf
    for k, phi in enumerate(phis[1:], start=1):
        if moving[k].size < 2:
            return ReferenceCandidate(tuple([tuple(pair)] + [(-1, -1)] * (len(phis) - 1)), np.zeros((len(phis), 0)),
                                      0.0, np.nan)
        options = sorted(((_score(a, phi[list(b)], peak0, np.max(np.abs(phi), axis=0)), b)
                          for b in permutations(moving[k].tolist(), 2)), key=lambda t: -t[0])
        best, b = options[0]
        channels.append(tuple(int(i) for i in b))
        rows.append(pair_mac(a, phi[list(b)]))
        score = min(score, float(best))
        runner = max(runner, float(options[1][0]) if len(options) > 1 else -np.inf)
    return ReferenceCandidate(tuple(channels), np.array(rows), score, runner if np.isfinite(runner) else np.nan)


def _score(a, b, peak_a, peak_b) -> float:
    """1 - the mean of 1 - MAC over the shared modes, each weighted by how much the two channels move in it (the
    smaller of the pair's energy over the mode's largest component², in either setup): a mode whose references sit
    near its node has a noisy ratio and says little."""
    w = np.minimum(np.sum(np.abs(a) ** 2, axis=0) / peak_a**2, np.sum(np.abs(b) ** 2, axis=0) / peak_b**2)
    return float(1 - np.sum(w * (1 - pair_mac(a, b))) / max(np.sum(w), 1e-300))


def _consistent(passing, n_setups: int, min_mac: float):
    """(references or None, reason) from the passing pairs: one set of channels, each mapped to one channel per
    setup, every two of them a passing pair, no runner-up passing."""
    if not passing:
        return None, (f"no two channels keep the same ratio in every setup (MAC ≥ {min_mac} over the shared modes)"
                      ": no reference sensors are found in the data; pick them by hand")
    maps: dict = {}
    for c in passing:
        if c.runner_up >= min_mac and 1 - c.runner_up < MIN_MARGIN * max(1 - c.score, 1e-12):
            return None, (f"channels {c.channels[0][0] + 1} and {c.channels[0][1] + 1} of setup 1 match two "
                          f"different pairs in another setup equally well (MAC {c.score:.3f} and "
                          f"{c.runner_up:.3f}; a symmetric structure with references at mirror points): the data "
                          "cannot tell which is which; pick them by hand")
        for i in range(2):
            got = maps.setdefault(c.channels[0][i], [ch[i] for ch in c.channels])
            if got != [ch[i] for ch in c.channels]:
                return None, (f"channel {c.channels[0][i] + 1} of setup 1 matches different channels of another "
                              "setup in different pairs: the data do not tell one set of references; pick them by "
                              "hand")
    members = sorted(maps)
    pairs = {c.channels[0] for c in passing}
    if any((a, b) not in pairs for a, b in combinations(members, 2)):
        return None, ("the channels that keep their ratios do not all agree with each other: the data do not tell "
                      "one set of references; pick them by hand")
    refs = [[int(maps[a][k]) for a in members] for k in range(n_setups)]
    for k in range(n_setups):
        if len(set(refs[k])) != len(refs[k]):
            return None, f"two reference channels of setup 1 match one channel of setup {k + 1}; pick them by hand"
    worst = min(c.score for c in passing)
    return refs, (f"{len(members)} channels keep the same ratios in every setup over the shared modes (MAC "
                  f"≥ {worst:.4f}); no other channel does")
