"""A multi-setup test merged before identifying (PreGER, era.merge_correlations) in the app: the setups' NExT
correlations with the picked references, on one scale and stacked, identified once by era.analyse. The result
takes the merged document's shape (app.setups.merged_json), so the page, its exports and reports show it as they
show PoSER's: every mode is known at every point (one identification saw them all).

The library's path, step by step: ``era.merge_correlations([era.load(f, kind="ambient", references=r).data ...],
references)`` then ``era.analyse(result.data)``; the correlations come from app.setups_analyses (the columns of the
every-channel ones: the same numbers).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

import era
from era import references_only

from . import setups_analyses

#: What the page says of the method.
SAID = ("PreGER: the setups' NExT correlations with the references scaled onto setup 1's (one factor per setup) "
        "and stacked, then one identification (era.merge_correlations, era.analyse)")


def preger(read, test: dict, refs: list[list[int]], refuse) -> tuple:
    """(result for app.setups.merged_json, the setups' geometries, what to say): the test merged by PreGER through
    ``refs`` (per setup, its reference indices). ``refuse(message)`` makes the page's refusal (next to the picker)
    of records that are not ambient or correlations that do not match."""
    not_ambient = [k + 1 for k, s in enumerate(test["setups"]) if not s.get("ambient")]
    if not_ambient:
        raise refuse(f"PreGER merges NExT correlation functions of ambient records, and setup "
                     f"{', '.join(map(str, not_ambient))} {'is' if len(not_ambient) == 1 else 'are'} not read as "
                     "ambient records: read the setups as ambient (NExT), or merge them with PoSER.")
    datas = setups_analyses.setup_data(read, test)
    key = (test["id"], "preger", tuple(map(tuple, refs)))

    def compute():
        try:
            merged = era.merge_correlations([references_only(d, r) for (d, _), r in zip(datas, refs)], refs)
            return merged, era.analyse(merged.data)
        except era.EraError as exc:
            raise refuse(f"PreGER cannot merge these setups: {exc}") from None

    merged, analysis = setups_analyses.kept(key, compute)
    model = analysis.model
    n_setups = len(test["setups"])
    shapes = np.asarray(model.shapes, dtype=complex)
    peak = shapes[np.argmax(np.abs(shapes), axis=0), np.arange(shapes.shape[1])] if shapes.size else np.ones(0)
    shapes = shapes / np.where(np.abs(peak) > 0, peak, 1)  # largest component 1, as PoSER's merged shapes
    n = model.n_modes
    result = SimpleNamespace(
        model=SimpleNamespace(points=tuple(merged.data.outputs), point_shapes=shapes, n_modes=n,
                              frequency_hz=model.frequency_hz, damping_ratio=model.damping_ratio,
                              frequency_std_hz=model.frequency_std_hz, damping_std=model.damping_std, mpc=model.mpc,
                              eigenvalues=model.eigenvalues, uncertainty_source=model.uncertainty_source),
        members=np.zeros((n, n_setups), int), recovered=np.zeros((n, n_setups), bool),
        by_frequency=np.zeros((n, n_setups), bool), scale_std=np.full((n, n_setups), np.nan), dropped=(),
        point_setup=merged.point_setup, point_channel=merged.point_channel)
    worst = int(np.argmax(merged.reference_residual))
    said = (f"{SAID}. Scales {', '.join(f'{c:.3g}' for c in merged.scales)}; the references' misfit after "
            f"scaling at most {100 * merged.reference_residual[worst]:.1f} % (setup {worst + 1}): one factor per "
            "setup holds when the excitation keeps its spectrum's shape from setup to setup.")
    return result, [g for _, g in datas], said, merged


def modes_words(modes: list[dict], n_setups: int) -> list[dict]:
    """PreGER's merged modes as the page says them: found once, from every setup's correlations."""
    return [dict(m, seen=f"identified once from all {n_setups} setups (PreGER)", seen_in=n_setups) for m in modes]
