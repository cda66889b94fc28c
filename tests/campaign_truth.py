"""A campaign's result scored against the simulated truth (era.campaign.simulated / scenarios): each true mode's
identification rate, counted here from the truth and the records' own values, not from the tracker's counts.

Used by tests/campaign/ and tests/bench/bench_campaign_modes.py. A true mode is matched to the tracked mode whose
reference shape is closest (one assignment on MAC, at least 0.9); a tracked mode no true mode takes is a false
identity. In a record that holds true mode j, the tracked mode's cell counts as found when it is there, its shape
is j's rather than another's (MAC with j's shape the largest) and its frequency within ``tolerance`` of j's true
frequency (either half's in a record where the mode changes half-way); a found cell whose shape is another true
mode's is a wrong cell.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from era.campaign.record import mode_shape, mode_value
from era.core.indicators import mac


@dataclass(frozen=True)
class TruthScore:
    """tracked : (k_true,) the tracked mode of each true mode (-1: none); held, found, wrong : (k_true,) records
    that hold the mode, in which it was found, in which its tracked mode held another mode; extra : tracked modes
    that are no true mode; first_record : (k_true,) the record where the tracked mode was defined; missed :
    (k_true,) tuples of the records that hold the mode and did not find it."""

    tracked: np.ndarray
    held: np.ndarray
    found: np.ndarray
    wrong: np.ndarray
    extra: tuple
    first_record: np.ndarray
    missed: tuple = ()

    @property
    def rate(self) -> np.ndarray:
        return self.found / np.maximum(self.held, 1)

    def lines(self, truth) -> list[str]:
        out = []
        for j in range(self.held.size):
            out.append(f"mode {j + 1} ({truth.frequency_hz[0, j]:.2f} Hz) -> tracked {self.tracked[j]}: found "
                       f"{self.found[j]} of {self.held[j]} ({100 * self.rate[j]:.1f} %), wrong {self.wrong[j]}, "
                       f"defined at record {self.first_record[j]}"
                       + (f", missed in records {list(self.missed[j])}" if self.missed and self.missed[j] else ""))
        out.append(f"false identities: {len(self.extra)}; all modes: {self.found.sum()} of {self.held.sum()} "
                   f"({100 * self.found.sum() / self.held.sum():.2f} %)")
        return out


def score(result, truth, tolerance: float = 0.01) -> TruthScore:
    """The :class:`TruthScore` of an era.campaign.CampaignResult whose records are truth's (record index = row)."""
    k = truth.shapes.shape[1]
    true_shapes = truth.shapes.astype(complex)
    refs = np.stack([m.shape for m in result.modes], axis=1)
    m = mac(true_shapes, refs)
    rows, cols = linear_sum_assignment(-m)
    tracked = np.full(k, -1)
    for j, c in zip(rows, cols):
        if m[j, c] >= 0.9:
            tracked[j] = result.modes[c].mode
    extra = tuple(md.mode for md in result.modes if md.mode not in set(tracked))
    present = np.ones(truth.frequency_hz.shape, bool) if truth.present is None else truth.present
    held, found, wrong = np.zeros(k, int), np.zeros(k, int), np.zeros(k, int)
    first = np.full(k, -1)
    missed = [[] for _ in range(k)]
    by_index = {r.index: r for r in result.records}
    t = result.table
    for j in range(k):
        if tracked[j] < 0:
            held[j] = present[:, j].sum()
            missed[j] = [r.index for r in result.records if present[r.index, j]]
            continue
        first[j] = next(md.first_record for md in result.modes if md.mode == tracked[j])
        rows_j = t[t["mode"] == tracked[j]]
        for rec_index, i in zip(rows_j["record"], rows_j["record_mode"]):
            if present[rec_index, j]:
                held[j] += 1
            if i < 0:
                if present[rec_index, j]:
                    missed[j].append(int(rec_index))
                continue
            rec = by_index[rec_index]
            own = mac(mode_shape(rec, i)[:, None], true_shapes)[0]
            if int(np.argmax(own)) != j or not present[rec_index, j]:
                wrong[j] += 1
                continue
            f = mode_value(rec, "frequency_hz", i)
            targets = [truth.frequency_hz[rec_index, j]]
            if truth.second_half_hz is not None and np.isfinite(truth.second_half_hz[rec_index, j]):
                targets.append(truth.second_half_hz[rec_index, j])
            if min(abs(f / x - 1) for x in targets) <= tolerance:
                found[j] += 1
            else:
                missed[j].append(int(rec_index))
    return TruthScore(tracked=tracked, held=held, found=found, wrong=wrong, extra=extra, first_record=first,
                      missed=tuple(tuple(sorted(m)) for m in missed))
