"""The analyses of a multi-setup test's setups, read and computed once and kept for the upload and its merges.

Every setup is read as era.load reads it and analysed by era.analyse: the library's path with the library's
defaults, so the page and a script give one answer. Ambient records go through NExT with every channel as a
correlation reference (era.load's default); the reference sensors' way is taken from those correlations
(era.setups.correlation_columns.references_only: the same numbers as era.load(..., references=...), without a
second pass over the records). The upload proposes the references from these analyses
(era.setups.ambient_references) and the merge takes the same ones: nothing is analysed twice while a test is kept
here.
"""

from __future__ import annotations

import era
from era import references_only

#: The last few tests' data and analyses, by key: (id, "data") -> [(ResponseData, geometry)]; (id, k, refs) -> setup
#: k's era.analyse result, refs None for every channel, else its reference indices (a tuple); (id, "preger", refs)
#: -> PreGER's merge and analysis.
_KEPT: dict = {}
_KEPT_TESTS = 4


def _keep(key, value):
    tests = {k[0] for k in _KEPT}
    while key[0] not in tests and len(tests) >= _KEPT_TESTS:  # the oldest test's entries go
        oldest = next(iter(_KEPT))[0]
        for k in [k for k in _KEPT if k[0] == oldest]:
            _KEPT.pop(k)
        tests = {k[0] for k in _KEPT}
    _KEPT[key] = value
    return value


def kept(key, compute):
    """What ``compute()`` returns, kept under ``key`` (a tuple, the test's id first) with the test's analyses."""
    if key not in _KEPT:
        _keep(key, compute())
    return _KEPT[key]


def setup_data(read, test: dict) -> list:
    """[(era.ResponseData, geometry or None)] of every setup as era.load reads its kept file. ``read(k, setup)``
    reads setup k (app.setups' reader, which says a refusal next to its control)."""
    key = (test["id"], "data")
    if key not in _KEPT:
        _keep(key, [read(k, s) for k, s in enumerate(test["setups"])])
    return _KEPT[key]


def _ambient(test: dict) -> bool:
    return any(s.get("ambient") for s in test["setups"])


def analyses(read, test: dict, refs: list[list[int]] | None = None, refuse=None) -> list:
    """[(era.analyse result, geometry or None)] of every setup: NExT with every channel as reference, or with
    ``refs`` (per setup, its reference indices) only when the records are ambient (other records do not depend on
    the references). Each setup's analysis is kept by its own references: a new pick that changes one setup's
    references analyses that setup alone. ``refuse(k, setup, exc)`` turns an era.EraError of setup k's analysis
    into the page's refusal."""
    out = []
    for k, ((data, geometry), s) in enumerate(zip(setup_data(read, test), test["setups"])):
        mine = tuple(refs[k]) if refs is not None and s.get("ambient") else None
        key = (test["id"], k, mine)
        if key not in _KEPT:
            try:
                _keep(key, era.analyse(data if mine is None else references_only(data, list(mine))))
            except era.EraError as exc:
                if refuse is None:
                    raise
                raise refuse(k, s, exc) from None
        out.append((_KEPT[key], geometry))
    return out


def keep_analyses(test: dict, refs: list[list[int]], results: list) -> None:
    """Keep analyses made elsewhere (the upload's proposal through NExT with candidate references) for the merge
    that takes those references: setup k's under its references refs[k]."""
    for k, (r, result) in enumerate(zip(refs, results)):
        _keep((test["id"], k, tuple(r)), result)


def propose_from_data(read, test: dict, refuse=None) -> era.ReferenceProposal:
    """The references the data propose (era.setups.ambient_references.propose_ambient_references on ambient
    setups: the every-channel modes, else the modes through NExT with the likeliest pairs; era.reference_evidence
    on the modes of other records); the analyses it read are kept for the merge."""
    every = analyses(read, test, None, refuse)
    if not _ambient(test):
        return era.reference_evidence([a for a, _ in every])
    datas = setup_data(read, test)
    try:
        found = era.propose_ambient_references([d for d, _ in datas], [a for a, _ in every])
    except era.EraError as exc:  # a candidate's analysis failed: the every-channel modes say what they can
        first = era.reference_evidence([a for a, _ in every])
        return era.ReferenceProposal(first.references, first.shared_hz, first.shared, first.candidates,
                                     f"{first.reason} (the likeliest pairs could not be analysed: {exc})")
    if found.way == "references" and found.references is not None:
        # the analyses behind the proposal are NExT with the candidate pair; when it is the proposal, the merge
        # with the proposed references takes them as they are
        used = [list(m) for m in found.candidate] if found.candidate is not None else None
        if used == [list(r) for r in found.references]:
            keep_analyses(test, used, found.analyses)
    return found.evidence
