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
from era.setups.correlation_columns import references_only

#: The last few tests' data and analyses, by key: (id, "data") -> [(ResponseData, geometry)]; (id, refs) ->
#: [(era.analyse result, geometry)], refs None for every channel, else per setup its reference indices.
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
    the references). ``refuse(k, setup, exc)`` turns an era.EraError of setup k's analysis into the page's
    refusal."""
    if refs is not None and not _ambient(test):
        refs = None
    key = (test["id"], None if refs is None else tuple(map(tuple, refs)))
    if key in _KEPT:
        return _KEPT[key]
    out = []
    for k, ((data, geometry), s) in enumerate(zip(setup_data(read, test), test["setups"])):
        if refs is not None and s.get("ambient"):
            data = references_only(data, refs[k])
        try:
            out.append((era.analyse(data), geometry))
        except era.EraError as exc:
            if refuse is None:
                raise
            raise refuse(k, s, exc) from None
    return _keep(key, out)


def keep_analyses(test: dict, refs: list[list[int]], results: list, geometries: list) -> None:
    """Keep analyses made elsewhere (the upload's proposal through NExT with candidate references) for the merge
    that takes those references."""
    _keep((test["id"], tuple(map(tuple, refs))), list(zip(results, geometries)))


def propose(read, test: dict, refuse=None) -> era.ReferenceProposal:
    """The references the data propose (era.setups.ambient_references.propose_ambient_references on ambient
    setups: the every-channel modes, else the modes through NExT with the likeliest pairs; era.reference_evidence
    on the modes of other records); the analyses it read are kept for the merge."""
    every = analyses(read, test, None, refuse)
    if not _ambient(test):
        return era.reference_evidence([a for a, _ in every])
    datas = setup_data(read, test)
    found = era.propose_ambient_references([d for d, _ in datas], [a for a, _ in every])
    if found.way == "references" and found.references is not None:
        # the analyses behind the proposal are NExT with the candidate pair; when it is the proposal, the merge
        # with the proposed references takes them as they are
        used = [list(m) for m in found.candidate] if found.candidate is not None else None
        if used == [list(r) for r in found.references]:
            keep_analyses(test, used, found.analyses, [g for _, g in datas])
    return found.evidence
