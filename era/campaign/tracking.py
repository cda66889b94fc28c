"""Following modes through a campaign: each record's modes matched to the tracked modes by frequency and MAC.

One optimal assignment per record (scipy.optimize.linear_sum_assignment, the cost of era.core.correlation.pairing_cost:
1 − MAC plus the relative frequency error, over the pairs that pass the gates), so no mode is used twice and two
modes that cross in frequency keep their identities: the shape decides, not the frequency order. The rules:

- the frequency compared is the tracked mode's latest one (modes drift with temperature), the shape is its
  reference shape (identity does not drift); a pair is refused when MAC < ``min_mac`` or the frequency moved more
  than ``max_freq_error`` (relative);
- a tracked mode the record's chosen modes do not hold is looked for among the record's spares (the diagram's
  other clusters, which the choice left out: at a crossing, or a weak mode), with the same gates, then among its
  diagram's poles with the tracked mode's frequency and shape as the prior (era.campaign.lookup: stable poles at
  two orders at least; the record's evidence, RecordModes.rejected, then says so); found there it counts as found
  (the table's ``record_mode`` is then n_modes + the spare's index, ``found_by`` says where it came from);
- where two tracked modes are within the frequency gate of each other (a crossing), a record's modes are mixtures
  of their shapes: a tracked mode still missing there takes the record's unused mode near it that resembles it
  more than any other tracked mode, with MAC ≥ CROSSING_MIN_MAC (0.5);
- a tracked mode a record does not show at all is missing there (NaN in the table) and stays tracked: it is
  matched again whenever a later record shows it (it reappears);
- a record's mode that no tracked mode takes is a candidate, unless it is a twin of a tracked mode (its shape
  with MAC ≥ ``min_mac`` and its frequency within ``max_freq_error`` of a tracked mode's: a mode split in two
  by one record's noise, whose better half the tracked mode took); a new tracked mode is only ever a shape or
  frequency no tracked mode has. Candidates are matched across records the same way, and one found in
  ``new_mode_records`` records, with gaps of at most ``new_mode_gap`` records between them, becomes a new
  tracked mode with its own identity from the record where it was first seen (its earlier records count as
  found); others are forgotten. A spare as persistent as the record's modes (PERSISTENT_FRACTION of their orders)
  may be a candidate too (a weak mode that records' choices call noise); other spares never start a mode. A new
  mode's records between its sightings, and those before its first one back to the first that does not hold it,
  are looked for as a missing tracked mode is (a weak mode the first records left out: found in the record that
  defined the reference, it is a reference mode; a mode that appears mid-way starts at its first record);
- each tracked mode's identification rate is the share of the records that hold it (every record from the one
  that defined it on) in which it was found.

Pure functions of the records' modes; no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from ..core.correlation import pairing_cost
from ..errors import DataError
from ..core.indicators import mac
from .lookup import look_up, with_spare
from .record import RecordFailure, mode_shape, mode_value


@dataclass(frozen=True, eq=False)
class TrackedMode:
    """A mode followed through the campaign.

    mode : its number (the table's ``mode``): reference modes first, by frequency, then new modes in the order
        they were confirmed. reference_frequency_hz, reference_damping_ratio : where it was defined;
    shape : (p,) complex reference shape; origin : "reference" or "new"; first_record : the record (its
    position in the campaign's sources, the table's ``record``) that defined it, -1 for a given reference;
    n_found : how many records found it; n_held : how many records hold it (the tracked records from the one
    that defined it on).
    """

    mode: int
    reference_frequency_hz: float
    reference_damping_ratio: float
    shape: np.ndarray
    origin: str
    first_record: int
    n_found: int
    n_held: int = 0

    @property
    def identification_rate(self) -> float:
        """n_found / n_held: the share of the records holding this mode in which it was identified (NaN when
        no record holds it)."""
        return self.n_found / self.n_held if self.n_held else float("nan")


@dataclass(frozen=True, eq=False)
class Tracking:
    """The result of :func:`track_modes` for n records and k tracked modes.

    records : the RecordModes tracked, in order; modes : the k TrackedModes;
    assignment : (n, k) int, the index of the record's mode assigned to each tracked mode, −1 where missing;
    mac_to_reference : (n, k) MAC of that mode with the tracked mode's shape (NaN where missing);
    refused : RecordFailures of records that cannot be compared (other channels than the reference);
    found_by : (n, k) str, where each found mode came from: "choice" (the record's chosen modes), "cluster" (a
    cluster of its diagram the choice left out, a spare), "diagram" (its diagram's poles, looked up with the
    tracked mode's frequency and shape: era.campaign.lookup), "crossing" (a record mode of mixed shape where two
    tracked modes are within the frequency gate of each other, taken by the one it resembles most, MAC ≥
    CROSSING_MIN_MAC); "" where missing.
    """

    records: tuple
    modes: tuple
    assignment: np.ndarray
    mac_to_reference: np.ndarray
    refused: tuple
    found_by: np.ndarray | None = None


@dataclass
class _Track:
    frequency_hz: float  # the latest found
    shape: np.ndarray  # the reference shape
    hits: list  # (record position, mode index)
    origin: str
    reference: tuple  # (frequency_hz, damping_ratio, first record)


def reference_from_model(model) -> tuple:
    """(frequency_hz (k,), damping_ratio (k,), shapes (p, k)) of the decaying complex pairs of an era.ModalModel."""
    keep = np.asarray(model.is_pair, bool) & (model.damping_ratio > 0) & (model.damping_ratio < 1)
    order = np.argsort(model.frequency_hz[keep])
    return (np.asarray(model.frequency_hz)[keep][order], np.asarray(model.damping_ratio)[keep][order],
            np.asarray(model.shapes)[:, keep][:, order])


#: The cost of a pair the gates refuse: more than any assignment of admissible pairs can cost (each costs ≤ 2).
_REFUSED = 1e6


def _assign(f, shapes, tracks, *, freq_scale, min_mac, max_freq_error) -> list:
    """[(record mode i, track j)] of the optimal assignment among the pairs that pass the gates.

    The gates act before the assignment, not after it: a pair whose shapes differ (MAC < ``min_mac``) can never be
    cheaper than one whose shapes agree, whatever their frequencies say. So where two modes cross and each sits
    at the other's latest frequency, the shapes keep their identities (gated afterwards, the frequency term could
    prefer the swapped pairs, which the gate then refused: both modes lost in that record)."""
    if not len(f) or not tracks:
        return []
    ft = np.array([t.frequency_hz for t in tracks])
    st = np.stack([t.shape for t in tracks], axis=1)
    cost, m = pairing_cost(f, shapes, ft, st, freq_scale=freq_scale)
    rel = np.abs(ft[None, :] - f[:, None]) / np.maximum(np.abs(f[:, None]), 1e-12)
    ok = (m >= min_mac) & (rel <= max_freq_error)
    rows, cols = linear_sum_assignment(np.where(ok, cost, _REFUSED))
    keep = ok[rows, cols]
    return [(int(i), int(j)) for i, j in zip(rows[keep], cols[keep])]


def twins(f, shapes, tracks, *, min_mac, max_freq_error) -> np.ndarray:
    """(len(f),) bool: the record's modes that repeat a tracked mode (MAC ≥ min_mac with its reference shape and
    frequency within max_freq_error of its latest one)."""
    if not len(f) or not tracks:
        return np.zeros(len(f), dtype=bool)
    ft = np.array([t.frequency_hz for t in tracks])
    st = np.stack([t.shape for t in tracks], axis=1)
    rel = np.abs(ft[None, :] - np.asarray(f)[:, None]) / np.maximum(np.abs(np.asarray(f)[:, None]), 1e-12)
    return np.any((mac(shapes, st) >= min_mac) & (rel <= max_freq_error), axis=1)


def track_modes(records, reference=None, *, freq_scale: float = 0.01, min_mac: float = 0.8,
                max_freq_error: float = 0.05, new_mode_records: int = 3, new_mode_gap: int = 3) -> Tracking:
    """Follow the modes of ``records`` (RecordModes, in time order) from a reference.

    Parameters
    ----------
    records : sequence of era.campaign.RecordModes
    reference : None (the modes of the first record that has any), an era.ModalModel (its decaying pairs) or a
        tuple (frequency_hz (k,), damping_ratio (k,), shapes (p, k)).
    freq_scale : relative frequency error that costs as much as a MAC loss of 0.1 (1 %).
    min_mac, max_freq_error : gates of a pair (0.8 and 5 %).
    new_mode_records, new_mode_gap : how a candidate becomes a new tracked mode (see the module).

    Returns
    -------
    Tracking

    Raises era.DataError when a given reference has no modes.
    """
    records = tuple(records)
    tracks: list[_Track] = []
    if reference is not None:
        f0, z0, s0 = reference_from_model(reference) if hasattr(reference, "is_pair") else reference
        f0, z0, s0 = np.asarray(f0, float), np.asarray(z0, float), np.asarray(s0)
        if not f0.size:
            raise DataError("The reference has no decaying modes to track; give a model with modes or "
                            "reference=None to start from the first record's modes.")
        tracks = [_Track(float(f0[j]), s0[:, j].astype(complex), [], "reference", (float(f0[j]), float(z0[j]), -1))
                  for j in range(f0.size)]
    gates = dict(freq_scale=freq_scale, min_mac=min_mac, max_freq_error=max_freq_error)
    candidates: list[_Track] = []
    refused, kept, used, how = [], [], [], {}
    ref_pos = -1 if reference is not None else None
    for rec in records:
        pos = len(kept)
        if not tracks and rec.n_modes:  # the first record with modes defines the reference
            ref_pos = pos
            tracks = [_Track(float(rec.frequency_hz[i]), rec.shapes[:, i].copy(), [], "reference",
                             (float(rec.frequency_hz[i]), float(rec.damping_ratio[i]), pos))
                      for i in range(rec.n_modes)]
        p = tracks[0].shape.size if tracks else rec.shapes.shape[0]
        if rec.shapes.shape[0] != p:
            refused.append(RecordFailure(rec.index, rec.name, f"{rec.name}: {rec.shapes.shape[0]} channels where the "
                                         f"reference has {p}; every record of a campaign must hold the same "
                                         "sensors in the same order."))
            continue
        kept.append(rec)
        used.append(set())
        f, shapes = rec.frequency_hz, rec.shapes
        for i, j in _assign(f, shapes, tracks, **gates):
            _hit(tracks[j], pos, i, f[i], used, how, "choice")
        _find_missing(kept, used, how, pos, [t for t in tracks if not t.hits or t.hits[-1][0] != pos], gates,
                      chosen=False)
        _at_crossing(kept[pos], pos, tracks, used, how, gates)
        rec = kept[pos]
        free = [i for i in [*range(rec.n_modes), *persistent_spares(rec)] if i not in used[pos]]
        fr = np.array([mode_value(rec, "frequency_hz", i) for i in free])
        sh = np.stack([mode_shape(rec, i) for i in free], axis=1) if free else np.zeros((p, 0), complex)
        twin = twins(fr, sh, tracks, min_mac=min_mac, max_freq_error=max_freq_error)
        keep = [a for a, t in enumerate(twin) if not t]  # a twin of a tracked mode is never a new mode
        free, fr, sh = [free[a] for a in keep], fr[keep], sh[:, keep]
        candidates = [c for c in candidates if pos - c.hits[-1][0] <= new_mode_gap + 1]
        matched = set()
        for a, j in _assign(fr, sh, candidates, **gates):
            candidates[j].hits.append((pos, free[a]))
            candidates[j].frequency_hz = float(fr[a])
            matched.add(a)
        for a, i in enumerate(free):
            if a not in matched:
                candidates.append(_Track(float(fr[a]), sh[:, a].copy(), [(pos, i)], "new",
                                         (float(fr[a]), mode_value(rec, "damping_ratio", i), pos)))
        for c in [c for c in candidates if len(c.hits) >= new_mode_records]:
            candidates.remove(c)
            if not twins(np.array([c.frequency_hz]), c.shape[:, None], tracks, min_mac=min_mac,
                         max_freq_error=max_freq_error)[0]:  # a tracked mode drifted onto it meanwhile
                for q, i in c.hits:
                    used[q].add(i)
                    how[(q, i)] = "choice" if i < kept[q].n_modes else "cluster"
                _backfill(c, kept, used, how, gates, ref_pos)
                tracks.append(c)
    return _tracking(kept, tracks, refused, how)


#: A spare (a cluster the record's choice left out) may start or confirm a new mode when it is stable over at least
#: this fraction of the orders its record's chosen modes are stable over (their median): a cluster as persistent as
#: the modes, which one record's choice judged too weak, and which other records show again.
PERSISTENT_FRACTION = 0.5


def persistent_spares(rec) -> list:
    """Indices (n_modes + k) of the record's spares stable over at least PERSISTENT_FRACTION of the orders of its
    chosen modes (their median)."""
    if not rec.spares or not rec.n_modes:
        return []
    need = PERSISTENT_FRACTION * float(np.median(rec.n_orders))
    return [rec.n_modes + k for k, sp in enumerate(rec.spares) if sp[6] >= need]


#: Where two tracked modes are within the frequency gate of each other (a crossing), a record mode there may be
#: taken with a MAC this low: the record cannot fully tell the two shapes apart, its modes are mixtures of them.
CROSSING_MIN_MAC = 0.5


def _at_crossing(rec, pos, tracks, used, how, gates) -> None:
    """Tracked modes still missing from record ``pos`` that have a tracked neighbour within the frequency gate take
    the record's unused modes (chosen, then spares) near them that resemble them more than any other tracked mode,
    with MAC ≥ CROSSING_MIN_MAC (found_by "crossing")."""
    gate = gates["max_freq_error"]
    ft = np.array([t.frequency_hz for t in tracks])
    close = [j for j, t in enumerate(tracks) if (not t.hits or t.hits[-1][0] != pos)
             and np.sum(np.abs(ft - ft[j]) <= gate * ft[j]) > 1]
    idx = [i for i in range(rec.n_modes + len(rec.spares)) if i not in used[pos]]
    if not close or not idx:
        return
    f = np.array([mode_value(rec, "frequency_hz", i) for i in idx])
    shapes = np.stack([mode_shape(rec, i) for i in idx], axis=1)
    best = np.argmax(mac(shapes, np.stack([t.shape for t in tracks], axis=1)), axis=1)
    for a, k in _assign(f, shapes, [tracks[j] for j in close], **dict(gates, min_mac=CROSSING_MIN_MAC)):
        if best[a] == close[k]:
            _hit(tracks[close[k]], pos, idx[a], f[a], used, how, "crossing")


def _hit(track, pos, i, frequency, used, how, found_by, latest=True) -> None:
    track.hits.append((pos, int(i)))
    if latest:
        track.frequency_hz = float(frequency)
    used[pos].add(int(i))
    how[(pos, int(i))] = found_by


def _find_missing(kept, used, how, pos, missing, gates, *, chosen: bool, latest: bool = True) -> list:
    """The tracked modes ``missing`` from record ``pos``, looked for among what its choice left: its chosen modes
    no tracked mode took (``chosen``: only when filling a new mode's earlier records), then its spares (the
    diagram's other clusters, RecordModes.spares), then its diagram's poles with each mode's frequency and shape
    as the prior (era.campaign.lookup; the record in ``kept`` then holds the looked-up mode as a spare and says so
    in its evidence). Each with the same gates and one assignment; none of these ever starts a mode. Returns the
    positions in ``missing`` that were found."""
    rec = kept[pos]
    found = []
    sources = ([("choice", [i for i in range(rec.n_modes) if i not in used[pos]])] if chosen else []) + \
        [("cluster", [rec.n_modes + s for s in range(len(rec.spares)) if rec.n_modes + s not in used[pos]])]
    for found_by, idx in sources:
        rest = [k for k in range(len(missing)) if k not in found]
        if not idx or not rest:
            continue
        f = np.array([mode_value(rec, "frequency_hz", i) for i in idx])
        shapes = np.stack([mode_shape(rec, i) for i in idx], axis=1)
        for a, k in _assign(f, shapes, [missing[k] for k in rest], **gates):
            _hit(missing[rest[k]], pos, idx[a], f[a], used, how, found_by, latest)
            found.append(rest[k])
    rest = [k for k in range(len(missing)) if k not in found]
    if rest and rec.poles is not None:
        hits = look_up(rec.poles, used[pos], [missing[k].frequency_hz for k in rest],
                       np.stack([missing[k].shape for k in rest], axis=1), min_mac=gates["min_mac"],
                       max_freq_error=gates["max_freq_error"])
        for k, spare in hits:
            rec, i = with_spare(rec, spare)
            kept[pos] = rec
            used[pos].update(spare[-2])  # the record modes whose poles these are
            _hit(missing[rest[k]], pos, i, spare[0], used, how, "diagram", latest)
            found.append(rest[k])
    return found


def _backfill(c, kept, used, how, gates, ref_pos) -> None:
    """A new tracked mode's records before it was confirmed: those between its sightings that did not show it,
    then the records before its first sighting, one after the other back until one does not hold it (a weak mode
    the first records left out; a mode that appears mid-way stops at once). Looked for with its shape and the
    nearest sighting's frequency; found there, they count as found and the mode's identity starts at the
    earliest. Reaching the record that defined the reference, it is a reference mode."""
    seen = sorted(q for q, _ in c.hits)
    latest = c.frequency_hz

    def probe(q) -> bool:
        near = min(c.hits, key=lambda h: abs(h[0] - q))
        c.frequency_hz = mode_value(kept[near[0]], "frequency_hz", near[1])
        return bool(_find_missing(kept, used, how, q, [c], gates, chosen=True, latest=False))

    for q in range(seen[0] + 1, seen[-1]):
        if q not in seen:
            probe(q)
    q = seen[0] - 1
    while q >= 0 and (ref_pos is None or q >= ref_pos) and probe(q):
        q -= 1
    c.hits.sort()
    c.frequency_hz = latest
    first, i = c.hits[0]
    if first != seen[0]:
        rec = kept[first]
        c.reference = (mode_value(rec, "frequency_hz", i), mode_value(rec, "damping_ratio", i), first)
    if first == ref_pos:
        c.origin = "reference"


def _tracking(records, tracks, refused, how) -> Tracking:
    n, k = len(records), len(tracks)
    order = sorted(range(k), key=lambda j: (tracks[j].origin != "reference", tracks[j].reference[2]
                                            if tracks[j].origin == "new" else 0, tracks[j].reference[0]))
    assignment = np.full((n, k), -1, dtype=int)
    mac_ref = np.full((n, k), np.nan)
    found_by = np.full((n, k), "", dtype=object)
    modes = []
    for col, j in enumerate(order):
        t = tracks[j]
        for pos, i in t.hits:
            assignment[pos, col] = i
            found_by[pos, col] = how.get((pos, i), "choice")
            mac_ref[pos, col] = mac(mode_shape(records[pos], i)[:, None], t.shape[:, None])[0, 0]
        modes.append(TrackedMode(mode=col, reference_frequency_hz=t.reference[0],
                                 reference_damping_ratio=t.reference[1], shape=t.shape, origin=t.origin,
                                 first_record=records[t.reference[2]].index if t.reference[2] >= 0 else -1,
                                 n_found=len(t.hits), n_held=n - max(t.reference[2], 0)))
    return Tracking(records=tuple(records), modes=tuple(modes), assignment=assignment, mac_to_reference=mac_ref,
                    refused=tuple(refused), found_by=found_by)
