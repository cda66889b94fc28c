"""Which channels NExT correlates ambient setups with, chosen per test from the merges themselves.

NExT (era.markov_from_ambient) turns each setup's ambient records into correlation functions with some channels as
references. Every channel as a reference (era's default) keeps a mode whose reference sensors sit near its node:
other channels see it. The reference sensors alone are better when the roving channels are noisy (a scanning laser
vibrometer's speckle): a noisy channel as a correlation reference adds its noise to every correlation with it, and
era.analyse then finds fewer modes in each setup, so fewer are seen in every setup. Which effect wins depends on the
test (a simulated tower: every channel; pyOMA's steel frame, vibrometer channels: the references, 10 complete modes
against 5 incomplete ones), so the test's own merges decide: :func:`merge_choosing_next` merges the setups both ways
and keeps the merge with more modes complete (known at every point), ties to the one whose complete shapes are the
more consistent (mean MPC of the merged shapes: noise spreads a shape's phases).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..choice.analysis import analyse
from ..errors import DataError
from ..markov import markov_from_ambient
from .poser import FREQUENCY_TOLERANCE, SetupMerge, merge_with_evidence

#: The two ways, in the order of NextChoice's arrays: every channel a NExT reference, or the reference sensors only.
WAYS = ("every", "references")
#: Said of each way.
WAY_WORDS = {"every": "every channel as NExT reference", "references": "the reference sensors only as NExT references"}
#: Two merges' mean MPCs closer than this are a tie, kept by the default way (every channel).
MPC_TIE = 1e-3


@dataclass(frozen=True, eq=False)
class NextChoice:
    """What :func:`choose_next` found.

    Attributes
    ----------
    used : {"every", "references"}
        The way kept.
    result : SetupMerge
        The kept merge (its ``model`` is what era.merge_setups returns).
    merges : tuple of SetupMerge or None, (2,)
        The merge of each way (in WAYS order), None where the merge was refused.
    complete : int ndarray, shape (2,)
        Each way's complete modes (known at every point) at distinct frequencies (modes within the pairing window
        of a counted one are not counted again: noise can split one mode in two); -1 when refused.
    quality : ndarray, shape (2,)
        The mean MPC of each way's complete merged shapes (NaN when none or refused).
    refused : tuple of str, (2,)
        Why a way's merge was refused ("" when it was not).
    reason : str
        The choice in words.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> models = [era.identify(modal_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 1, 300, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 30, 30).realize(6) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> choice = era.merge_choosing_next(models, None, [[0, 1], [0, 1]])
    >>> choice.used, choice.complete.tolist(), choice.merges[1], choice.refused
    ('every', [3, -1], None, ('', 'not ambient records'))
    """

    used: str
    result: SetupMerge
    merges: tuple
    complete: np.ndarray
    quality: np.ndarray
    refused: tuple
    reason: str


def count_complete_modes(result: SetupMerge, frequency_tolerance: float = FREQUENCY_TOLERANCE) -> int:
    """How many of a merge's complete modes lie at distinct frequencies (a mode within ``frequency_tolerance`` of
    the last counted one is not counted)."""
    f = np.sort(result.model.frequency_hz[result.complete])
    count, last = 0, -np.inf
    for x in f:
        if x > last * (1 + frequency_tolerance):
            count, last = count + 1, x
    return count


def choose_next(every, references, *, frequency_tolerance: float = FREQUENCY_TOLERANCE) -> NextChoice:
    """Of two merges of one test, the one to keep.

    The rule: keep the merge with more complete modes (:func:`count_complete_modes`), ties to the higher mean MPC of the
    complete shapes, then to every channel (era's default).

    Parameters
    ----------
    every : SetupMerge or era.DataError
        The merge of the setups through NExT with every channel as reference, or the error its merge raised.
    references : SetupMerge or era.DataError
        The merge of the setups through NExT with the reference sensors only, or the error its merge raised.
    frequency_tolerance : float, optional
        The pairing window (relative) within which two complete modes count once.

    Returns
    -------
    NextChoice

    Raises
    ------
    era.DataError
        The error of the default way when both were refused.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> models = [era.identify(modal_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 1, 300, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 30, 30).realize(6) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> merge = era.merge_choosing_next(models, None, [[0, 1], [0, 1]]).result
    >>> choice = era.choose_next(merge, era.DataError("a setup's references are silent"))
    >>> choice.used, choice.complete.tolist(), choice.refused[1]
    ('every', [3, -1], "a setup's references are silent")
    """
    merges, refused = [], []
    for m in (every, references):
        merges.append(m if isinstance(m, SetupMerge) else None)
        refused.append("" if isinstance(m, SetupMerge) else str(m))
    if merges[0] is None and merges[1] is None:
        raise every if isinstance(every, Exception) else DataError(refused[0])
    complete = np.array([-1 if m is None else count_complete_modes(m, frequency_tolerance) for m in merges])
    quality = np.array([np.nan if m is None or not m.complete.any() else float(np.mean(m.model.mpc[m.complete]))
                        for m in merges])
    q = np.nan_to_num(quality, nan=-1.0)
    if complete[0] != complete[1]:
        k = int(np.argmax(complete))
        why = "more modes complete"
    elif abs(q[0] - q[1]) > MPC_TIE:
        k = int(np.argmax(q))
        why = "as many modes complete, with more consistent shapes (mean MPC)"
    else:
        k, why = 0, "as many modes complete, as consistent: era's default kept"
    said = [f"{WAY_WORDS[w]}: " + (f"refused ({refused[i]})" if merges[i] is None else
                                   f"{complete[i]} complete, mean MPC {quality[i]:.3f}" if complete[i] else
                                   "no mode complete") for i, w in enumerate(WAYS)]
    reason = f"Kept {WAY_WORDS[WAYS[k]]} ({why}): " + "; ".join(said) + "."
    return NextChoice(used=WAYS[k], result=merges[k], merges=tuple(merges), complete=complete, quality=quality,
                      refused=tuple(refused), reason=reason)


def merge_choosing_next(every, references_only, references, *, frequency_tolerance: float = FREQUENCY_TOLERANCE,
                        **options) -> NextChoice:
    """Merge a test's setups analysed both ways and keep the better merge (:func:`choose_next`).

    Parameters
    ----------
    every : list of AnalysisResult
        One per setup: its ambient records through NExT with every channel as reference
        (``era.analyse(era.load(file, kind="ambient").data)``, era's default).
    references_only : list of AnalysisResult, optional
        The same setups through NExT with their reference channels only
        (``era.load(file, kind="ambient", references=references[k])``); None (or ``every`` itself) when the
        records are not ambient: the every-channel merge is then kept.
    references : list of sequences of int
        Per setup, the indices of its reference channels (as era.merge_setups).
    frequency_tolerance : float, optional
        era.merge_setups' option, the same for both merges.
    **options
        era.merge_setups' other options, the same for both merges.

    Returns
    -------
    NextChoice
        Its ``result.model`` is the merged era.ModalModel.

    Raises
    ------
    era.DataError
        When the merge of ``every`` is refused and there is no other way (or both are refused).

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # 3 modes at 7 points; 1 and 4 in both setups
    >>> models = [era.identify(modal_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 1, 300, 0.02, seed=k,
    ...           shapes=shapes[c])[0], 30, 30).realize(6) for k, c in enumerate([[1, 4, 0, 2, 3], [1, 4, 5, 6]])]
    >>> choice = era.merge_choosing_next(models, None, [[0, 1], [0, 1]])
    >>> choice.used, choice.reason
    ('every', 'Not ambient records: no NExT references to choose.')
    >>> print(np.round(choice.result.model.frequency_hz, 3))
    [2.  5.5 9. ]
    """
    def attempt(analyses):
        try:
            return merge_with_evidence(analyses, references, frequency_tolerance=frequency_tolerance, **options)
        except DataError as exc:
            return exc

    first = attempt(every)
    if references_only is None or references_only is every:
        if isinstance(first, Exception):
            raise first
        return NextChoice(used="every", result=first, merges=(first, None), complete=np.array(
            [count_complete_modes(first, frequency_tolerance), -1]), quality=np.array([np.nan, np.nan]),
            refused=("", "not ambient records"), reason="Not ambient records: no NExT references to choose.")
    return choose_next(first, attempt(references_only), frequency_tolerance=frequency_tolerance)


def merge_ambient_setups(records, dt: float, references, *, names=None, n_lags: int | None = None,
                         **options) -> NextChoice:
    """The merged modes of an ambient multi-setup test from its records, NExT's references chosen from the data.

    Each setup goes through era.markov_from_ambient twice (every channel as reference; its references only) and
    era.analyse, as ``era.load(file, kind="ambient"[, references=...])`` then era.analyse do; the setups are merged
    both ways and :func:`choose_next` keeps one.

    Parameters
    ----------
    records : list of array_like
        One per setup, in the test's order: an (N_k, p_k) array of response records (or a list of such records,
        as era.markov_from_ambient takes).
    dt : float
        Sampling interval, s (the same for every setup).
    references : list of sequences of int
        Per setup, the indices of its reference channels: the same sensors, in the same order.
    names : list of sequences of str, optional
        Per setup, its p_k channel names.
    n_lags : int, optional
        NExT's correlation lags (default era.markov_from_ambient's).
    **options
        era.merge_setups' options.

    Returns
    -------
    NextChoice
        ``result.model``: the merged era.ModalModel.

    Raises
    ------
    era.DataError
        When records and references do not match, or both merges are refused.

    Examples
    --------
    Two setups of an ambient test (60 s at 50 Hz), five and four sensors, two of them in both:

    >>> from era.examples.synthetic import ambient_response
    >>> shapes = np.random.default_rng(3).standard_normal((7, 3))  # three modes at seven points
    >>> channels = [[1, 4, 0, 2, 3], [1, 4, 5, 6]]
    >>> records = [ambient_response([2.0, 5.5, 9.0], [0.02, 0.01, 0.01], len(c), 3000, 0.02, seed=k,
    ...                             shapes=shapes[c])[0] for k, c in enumerate(channels)]
    >>> choice = era.merge_ambient_setups(records, 0.02, [[0, 1], [0, 1]], n_lags=20)
    >>> choice.used, choice.result.model.points[:3]
    ('every', ('y1', 'y2', 'S1:y3'))
    >>> print(np.round(choice.result.model.frequency_hz, 1))
    [2.  5.5 9. ]
    """
    records = list(records)
    references = [list(r) for r in references]
    if len(references) != len(records):
        raise DataError(f"{len(records)} setups but {len(references)} reference lists: give each setup the indices "
                        "of its reference channels.")
    names = [None] * len(records) if names is None else list(names)

    def run(k, refs):
        return analyse(markov_from_ambient(records[k], dt, refs, n_lags=n_lags, names=names[k]))

    every = [run(k, None) for k in range(len(records))]
    only = [run(k, references[k]) for k in range(len(records))]
    return merge_choosing_next(every, only, references, **options)
