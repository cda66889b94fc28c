"""NExT correlations with fewer references, taken from the correlations already computed with more.

NExT (era.markov_from_ambient) estimates R_ij(τ) for every output i and every reference j, each column from the
same records and the same lags whatever the other references are. The correlations with the reference sensors only
are therefore the columns of those sensors in the every-channel correlations: a multi-setup test's second NExT way
(the reference sensors only, era.setups.next_references) needs no second pass over the records.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..core.data import ResponseData
from ..errors import DataError


def references_only(data: ResponseData, references) -> ResponseData:
    """The NExT correlation functions of ``data`` with ``references`` as the only correlation references.

    Parameters
    ----------
    data : era.ResponseData
        From NExT (``era.markov_from_ambient`` or ``era.load(..., kind="ambient")``): markov (N, p, r) with r
        references among its p outputs (``data.meta["references"]``, their output indices).
    references : sequence of int
        Indices (among the p outputs) of the channels to keep as references; each must be one of ``data``'s
        references.

    Returns
    -------
    era.ResponseData
        markov (N, p, len(references)): exactly what NExT with these references gives on the same records
        (``era.load(file, kind="ambient", references=references)``): the same lags, records or segments
        (``records`` (n, N, p, len(references))), zero lag and conversion note.

    Raises
    ------
    era.DataError
        When ``data`` is not NExT correlations or a reference was not correlated with.

    Examples
    --------
    >>> from era.examples.synthetic import ambient_response
    >>> y = ambient_response([2.0, 5.5], 0.02, 4, 6000, 0.02, seed=1)[0]
    >>> every = era.markov_from_ambient(y, 0.02, n_lags=100)
    >>> only = era.references_only(every, [0, 1])
    >>> every.markov.shape, only.markov.shape
    ((100, 4, 4), (100, 4, 2))
    >>> bool(np.allclose(only.markov, era.markov_from_ambient(y, 0.02, [0, 1], n_lags=100).markov))
    True
    """
    correlated = data.meta.get("references")
    if data.meta.get("source") != "next" or correlated is None:
        raise DataError("These data are not NExT correlation functions (era.markov_from_ambient): the references "
                        "only can be taken from ambient records' correlations.")
    correlated = [int(i) for i in correlated]
    refs = [int(i) for i in np.asarray(references, dtype=int).reshape(-1)]
    if not refs or len(set(refs)) != len(refs):
        raise DataError(f"references must name distinct channels, got {refs}.")
    missing = [i for i in refs if i not in correlated]
    if missing:
        raise DataError(f"Channel {missing[0] + 1} was not a NExT reference of these correlations: correlate the "
                        "records with it (era.markov_from_ambient(..., references=...)).")
    cols = [correlated.index(i) for i in refs]
    labels = list(data.outputs) if data.outputs is not None else [f"y{i + 1}" for i in range(data.markov.shape[1])]
    meta = dict(data.meta, references=refs)
    if meta.get("zero_lag") is not None:
        meta["zero_lag"] = np.asarray(meta["zero_lag"])[:, cols]
    meta["conversions"] = [_said(text, [labels[i] for i in refs]) for text in meta.get("conversions") or ()]
    return replace(data, markov=data.markov[:, :, cols],
                   inputs=tuple(data.inputs[c] for c in cols) if data.inputs is not None else None,
                   input_units=tuple(data.input_units[c] for c in cols) if data.input_units is not None else None,
                   records=None if data.records is None else data.records[..., cols], meta=meta)


def _said(text: str, names: list) -> str:
    """NExT's conversion note with the references named anew (other notes unchanged)."""
    from ..words import listed  # the words NExT itself uses

    head = "NExT (James et al. 1995): correlations with reference "
    if not text.startswith(head) or " over " not in text:
        return text
    rest = text[text.index(" over "):]
    return head + ("channels " if len(names) > 1 else "channel ") + listed(names) + rest
