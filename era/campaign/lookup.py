"""A tracked mode the record's choice left out, looked up in the record's own diagram with what the campaign knows.

One record's choice (era.choose_modes) judges its diagram alone: a weak mode whose poles stand little above the
noise, or two modes at a crossing whose shapes the top orders mix, can be left out, or kept only as a cluster of
mixed shape, although some of the diagram's orders hold the mode cleanly. The campaign knows the mode exists and
what it looks like: the tracked mode's latest frequency and its reference shape are the prior. The record's poles
that are stable in frequency (RecordModes.poles), of no record mode already taken, within the frequency gate and
with MAC ≥ the shape gate with the tracked shape, at two orders at least, are that mode in this record; its values
are their medians (frequency, damping) and the shape of the best-matching pole. The record's evidence says so
(a line in RecordModes.rejected), and the value has no σ from the data (NaN): no single order's model holds it.

Pure functions; no I/O.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..core.indicators import mac

#: Poles of a looked-up mode lie within this relative frequency of its best-matching pole.
GROUP_TOLERANCE = 0.01
#: A looked-up mode needs poles at this many of the diagram's orders (one pole is no evidence).
MIN_ORDERS = 2
#: The code of a looked-up mode in RecordModes.rejected (its evidence line).
CODE = "prior"


def look_up(poles, used, frequencies, shapes, *, min_mac: float, max_freq_error: float) -> list:
    """[(tracked mode k, spare)] of the tracked modes (``frequencies`` (k,) Hz, ``shapes`` (p, k)) found among the
    record's diagram ``poles`` (era.campaign.record.DiagramPoles or None) whose cluster is not in ``used`` (the
    record's modes already taken). spare : the values in RecordModes.spares' order (frequency_hz, damping_ratio,
    frequency σ NaN, damping σ NaN, emac, mpc, orders, shape (p,)), then the record's modes (chosen k < n_modes,
    spares n_modes + k) whose poles these are, and the evidence text. Each pole serves one
    tracked mode at most; the best-matching tracked mode (mean MAC) is served first."""
    if poles is None or not poles.size or not len(frequencies):
        return []
    free = ~np.isin(poles.cluster, list(used)) if used else np.ones(poles.size, bool)
    m = mac(poles.shapes, np.asarray(shapes, complex))  # (q, k)
    f = poles.frequency_hz
    groups = []
    for k, fk in enumerate(np.asarray(frequencies, float)):
        ok = free & (m[:, k] >= min_mac) & (np.abs(f - fk) <= max_freq_error * abs(fk))
        if not ok.any():
            continue
        best = np.flatnonzero(ok)[np.argmax(m[ok, k])]
        ok &= np.abs(f - f[best]) <= GROUP_TOLERANCE * f[best]
        members = _one_per_order(np.flatnonzero(ok), poles.order, m[:, k])
        if len(members) >= MIN_ORDERS:
            groups.append((float(np.mean(m[members, k])), k, members, best))
    out, taken = [], set()
    for score, k, members, best in sorted(groups, key=lambda g: -g[0]):
        members = [i for i in members if i not in taken]
        if len(members) < MIN_ORDERS:
            continue
        taken.update(members)
        orders = sorted(int(poles.order[i]) for i in members)
        text = (f"left out by this record's choice; found by the campaign in the record's diagram at the tracked "
                f"mode's frequency and shape: stable poles at {len(orders)} orders ({orders[0]}–{orders[-1]}), "
                f"MAC {score:.2f} with its reference shape")
        owners = sorted({int(c) for c in poles.cluster[members] if c >= 0})
        if owners:  # a record mode of mixed shape (a crossing) whose poles these are is spent: never a candidate
            text += f"; poles of the record's mode {', '.join(str(c) for c in owners)}"
        out.append((k, (float(np.median(f[members])), float(np.median(poles.damping_ratio[members])), float("nan"),
                        float("nan"), float(np.mean(poles.emac[members])), float(np.mean(poles.mpc[members])),
                        len(orders), poles.shapes[:, best].copy(), tuple(owners), text)))
    return out


def _one_per_order(idx, order, score) -> list:
    """The best-scoring pole of each order among ``idx``."""
    best = {}
    for i in idx:
        o = int(order[i])
        if o not in best or score[i] > score[best[o]]:
            best[o] = i
    return sorted(best.values())


def with_spare(rec, spare):
    """(record with the looked-up mode appended to its spares and its evidence line to ``rejected``, its index)."""
    *values, _, text = spare
    index = rec.n_modes + len(rec.spares)
    return replace(rec, spares=rec.spares + (tuple(values),),
                   rejected=rec.rejected + ((float(values[0]), CODE, text),)), index
