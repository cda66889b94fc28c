"""The reference sensors of an ambient multi-setup test, proposed from the analyses its merge will use.

era.propose_references reads the setups' modes: the reference part of every mode keeps its ratios in every setup.
On ambient records those modes come from NExT, and which channels NExT correlates with decides how many modes each
setup finds: with noisy roving channels (a laser vibrometer's speckle) every channel as a NExT reference leaves too
few modes shared by every setup to tell anything, while the reference sensors alone find them (the merge keeps that
way then, era.setups.next_references). So the proposal follows the merge's two ways:

1. the modes of the every-channel analyses (era's default way), when they tell;
2. else the candidate pairs whose correlation functions look alike in every setup (:func:`correlation_candidates`:
   two sensors that stay in place see the same normalised 2 × 2 correlation block in every setup, roving sensors
   do not), each setup analysed through NExT with that pair only (era.setups.correlation_columns: the columns of
   the correlations already computed), and those modes checked by era.reference_evidence.

A candidate is only ever proposed when era.reference_evidence's check passes on the modes (the shapes are the
outputs' whichever channels NExT correlates with), so the candidates' ranking can be wrong without the proposal
being wrong: a wrong proposal is worse than none.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations, permutations

import numpy as np

from ..choice.analysis import analyse
from ..core.data import ResponseData
from ..errors import DataError
from .correlation_columns import references_only
from .references import MIN_MAC, ReferenceProposal, reference_evidence

#: How many candidate pairs (best correlation likeness first) are analysed and checked at most: each costs one
#: analysis per setup.
CANDIDATES_TRIED = 2


@dataclass(frozen=True, eq=False)
class AmbientReferences:
    """What :func:`propose_ambient_references` found.

    Parameters
    ----------
    evidence : era.ReferenceProposal
        The evidence that decided (``evidence.references``: per setup the indices, or None).
    analyses : list of era.AnalysisResult
        The analyses the evidence was read from, one per setup: the every-channel ones, or those through NExT
        with a candidate pair only (``way`` says which).
    way : str
        "every" (every channel a NExT reference) or "references" (a candidate pair only).
    candidate : list or None
        With way "references", per setup the pair NExT correlated with (setup 1's order); else None.
    tried : tuple
        Per way tried, (what was tried in words, what its evidence said).

    Examples
    --------
    >>> from era.examples.synthetic import ambient_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> setups = [era.markov_from_ambient(ambient_response([2.0, 5.5, 9.0], 0.02, len(c), 6000, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 0.02, n_lags=100) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> found = era.propose_ambient_references(setups)
    >>> found.candidate is None, len(found.analyses), found.tried[0][0]
    (True, 2, 'every channel as NExT reference')
    """

    evidence: ReferenceProposal
    analyses: list
    way: str
    candidate: list | None
    tried: tuple

    @property
    def references(self) -> list | None:
        return self.evidence.references


def correlation_candidates(setups, n: int = CANDIDATES_TRIED) -> list:
    """The pairs of channels most likely to be the reference sensors, from the setups' NExT correlations.

    Parameters
    ----------
    setups : list of era.ResponseData, one per setup, NExT correlations with every channel as a reference
        (markov (N_k, p_k, p_k), ``era.load(file, kind="ambient").data``).
    n : how many candidates to return at most.

    Returns
    -------
    list of (mapping, likeness): mapping per setup the ordered pair of channel indices (setup 1's pair first, in
    its order), likeness the smallest over the setups of the correlation coefficient between setup 1's pair's
    normalised 2 × 2 correlation block (every lag) and that setup's pair's; best first.
    """
    blocks = [_normalised(d) for d in setups]
    n_lags = min(b.shape[0] for b in blocks)
    blocks = [b[:n_lags] for b in blocks]
    out = []
    for pair in combinations(range(blocks[0].shape[1]), 2):
        a = _block(blocks[0], pair)
        mapping, worst = [pair], np.inf
        for b in blocks[1:]:
            best, where = max((float(np.sum(a * _block(b, q))), q) for q in permutations(range(b.shape[1]), 2))
            mapping.append(where)
            worst = min(worst, best)
        out.append(([tuple(int(i) for i in m) for m in mapping], worst))
    out.sort(key=lambda t: -t[1])
    return out[:n]


def _normalised(data: ResponseData) -> np.ndarray:
    """(N, p, p) each correlation R_ij(τ) over sqrt(R_ii(0) R_jj(0)): the setup's excitation level divided out."""
    if data.meta.get("source") != "next" or data.markov.shape[2] != data.markov.shape[1]:
        raise DataError("The reference candidates are read from NExT correlations with every channel as a "
                        "reference (era.load(file, kind=\"ambient\").data).")
    zero = np.asarray(data.meta.get("zero_lag"), dtype=float)
    level = np.sqrt(np.maximum(np.diag(zero), 1e-300))
    return data.markov / level[None, :, None] / level[None, None, :]


def _block(r: np.ndarray, pair) -> np.ndarray:
    """The pair's 2 × 2 correlation block over every lag, unit norm."""
    b = r[:, list(pair)][:, :, list(pair)]
    return b / max(float(np.linalg.norm(b)), 1e-300)


def propose_ambient_references(setups, every=None, *, min_mac: float = MIN_MAC,
                               n_candidates: int = CANDIDATES_TRIED) -> AmbientReferences:
    """Per setup, the reference channels of an ambient multi-setup test (or None), from the data the merge uses.

    The every-channel modes are asked first (era.reference_evidence); when they do not tell, the channel pairs
    whose correlations are most alike in every setup (:func:`correlation_candidates`) are analysed through NExT
    with that pair only and checked the same way. No proposal is made that the check does not pass.

    Parameters
    ----------
    setups : list of era.ResponseData
        One per setup: NExT correlations with every channel as a reference
        (``era.load(file, kind="ambient").data``).
    every : list of era.AnalysisResult, optional
        Their era.analyse results, when already made (else they are made here).
    min_mac : float, optional
        era.reference_evidence's check: the least MAC of the candidates' components over the shared modes.
    n_candidates : int, optional
        How many candidate pairs are analysed and checked when the every-channel modes do not tell.

    Returns
    -------
    AmbientReferences
        ``references`` is None when no proposal passes era.reference_evidence's check.

    Examples
    --------
    >>> from era.examples.synthetic import ambient_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> setups = [era.markov_from_ambient(ambient_response([2.0, 5.5, 9.0], 0.02, len(c), 6000, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 0.02, n_lags=100) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> found = era.propose_ambient_references(setups)
    >>> found.references, found.way
    ([[0, 1], [0, 1]], 'every')
    """
    setups = list(setups)
    every = [analyse(d) for d in setups] if every is None else list(every)
    first = reference_evidence(every, min_mac=min_mac)
    tried = [("every channel as NExT reference", first.reason)]
    if first.references is not None or len(setups) < 2:
        return AmbientReferences(first, every, "every", None, tuple(tried))
    for mapping, likeness in correlation_candidates(setups, n_candidates):
        analyses = [analyse(references_only(d, list(m))) for d, m in zip(setups, mapping)]
        found = reference_evidence(analyses, min_mac=min_mac)
        said = f"NExT with channels {mapping[0][0] + 1} and {mapping[0][1] + 1} of setup 1 (and their likes)"
        tried.append((said, found.reason))
        if found.references is not None:
            said = ReferenceProposal(found.references, found.shared_hz, found.shared, found.candidates,
                                     f"through {said}, as the merge correlates them: {found.reason}")
            return AmbientReferences(said, analyses, "references", [list(m) for m in mapping], tuple(tried))
    reasons = "; ".join(f"{way}: {reason}" for way, reason in tried)
    return AmbientReferences(ReferenceProposal(None, first.shared_hz, first.shared, first.candidates, reasons),
                             every, "every", None, tuple(tried))
