"""The ± a repeated cluster shares (issue 28's review: the close pair 116.88 / 117.23 Hz of the USC cantilever
carried identical ± 0.3473 Hz, 0.229 %). By design: poles closer together than their scatter are one eigenvalue as
far as the data can tell (era.core.decomposition.repeated_clusters), and each member carries the cluster's largest σ
(era.core.mode_uncertainty.mode_std); the payload says which modes share one (schemas.Modes.std_group), so the page can
say "the ± of the group" instead of showing one number twice as if computed twice."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import era
from app.payloads import modes_json, std_groups

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from shared_data import SHARED_DATASETS, require_shared  # noqa: E402

USC = SHARED_DATASETS / "usc_cantilever_free_decay" / "timeseries_data.lvm"
ORDER = 64  # the order era chooses on this record, the one of the screenshots


def test_the_close_pair_of_the_usc_cantilever_shares_the_larger_of_its_two_own_sigmas():
    data = era.load(require_shared(USC)).data
    ident = era.analyse(data).identification
    model = ident.model(ORDER)
    f = model.frequency_hz
    pair = [int(np.argmin(np.abs(f - 116.88))), int(np.argmin(np.abs(f - 117.23)))]
    groups = std_groups(model)
    assert groups[pair[0]] == groups[pair[1]] == sorted(pair)
    single = int(np.argmin(np.abs(f - 6.6143)))  # the first bending mode: alone, its own σ
    assert groups[single] is None
    assert all(len(g) >= 2 and all(groups[j] == g for j in g) for g in groups if g is not None)
    f_std, d_std = model.standard_deviations()
    assert f_std[pair[0]] == f_std[pair[1]] and d_std[pair[0]] == d_std[pair[1]]
    # each pole's own σ (no cluster given) differs, the shared one is the larger: copied by design, not by mistake
    _, _, _, raw, _, clusters, _, _ = ident.decomposed(ORDER, True)
    own_f, own_d = ident.mode_std(ORDER, raw, np.arange(raw.z.size))
    near = [int(np.argmin(np.abs(np.angle(raw.z) / (2 * np.pi * data.dt) - f[k]))) for k in pair]
    assert any(sorted(near) == sorted(int(i) for i in c) for c in clusters)
    assert own_f[near[0]] != own_f[near[1]]
    assert f_std[pair[0]] == max(own_f[near]) and d_std[pair[0]] == max(own_d[near])
    assert modes_json(model, data, with_fit=False)["std_group"] == groups
