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

    used : "every" or "references", the way kept.
    result : the kept era.SetupMerge (its ``model`` is what era.merge_setups returns).
    merges : (2,) the SetupMerge of each way (in WAYS order), None where the merge was refused.
    complete : (2,) int, each way's complete modes (known at every point) at distinct frequencies (modes within the
        pairing window of a counted one are not counted again: noise can split one mode in two); -1 when refused.
    quality : (2,) float, the mean MPC of each way's complete merged shapes (NaN when none or refused).
    refused : (2,) str, why a way's merge was refused ("" when it was not).
    reason : the choice in words.
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
    """The rule: of two merges of one test (``every``: NExT with every channel as reference; ``references``: with
    the reference sensors only; each an era.SetupMerge or the era.DataError its merge raised), keep the one with
    more complete modes (:func:`count_complete_modes`), ties to the higher mean MPC of the complete shapes, then to every
    channel (era's default). Raises the DataError of the default way when both were refused."""
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
    every : list of era.AnalysisResult, one per setup: its ambient records through NExT with every channel as
        reference (``era.analyse(era.load(file, kind="ambient").data)``, era's default).
    references_only : the same setups through NExT with their reference channels only
        (``era.load(file, kind="ambient", references=references[k])``); None (or ``every`` itself) when the
        records are not ambient: the every-channel merge is then kept.
    references : per setup, the indices of its reference channels (as era.merge_setups).
    frequency_tolerance, options : era.merge_setups' options, the same for both merges.

    Returns
    -------
    NextChoice; its ``result.model`` is the merged era.ModalModel.
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

    Parameters
    ----------
    records : list (one per setup) of (N_k, p_k) arrays of response records (or lists of such records, as
        era.markov_from_ambient takes), in the test's order.
    dt : sampling interval, s (the same for every setup).
    references : per setup, the indices of its reference channels: the same sensors, in the same order.
    names : per setup, its p_k channel names (optional).
    n_lags : NExT's correlation lags (default era.markov_from_ambient's).
    options : era.merge_setups' options.

    Each setup goes through era.markov_from_ambient twice (every channel as reference; its references only) and
    era.analyse, as ``era.load(file, kind="ambient"[, references=...])`` then era.analyse do; the setups are merged
    both ways and :func:`choose_next` keeps one. Returns NextChoice (``result.model``: the merged era.ModalModel).
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
