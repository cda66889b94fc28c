"""Which mode of one setup is which mode of another (era.merge_setups): modes paired setup by setup by
frequency and the MAC of their reference components (an optimal assignment), split twins and modes the references
cannot scale left out with their reason, a wrong reference choice refused, and the weak clusters a setup left out
taken back when the other setups confirm the mode.

Every function takes the setups' ModalModels (``models``) and their reference indices (``refs``, one int array per
setup); a group is a (setups,) int array: a mode's index in each setup, -1 where that setup did not see it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from ..core import indicators
from ..errors import DataError

#: The reasons (choose.REASONS) for which a setup's cluster, left out by era.analyse for want of evidence alone,
#: may be taken as a mode other setups confirm (see era.setups.poser.merge_setups, ``recover``).
RECOVERABLE = ("orders", "noise")
#: The cost of a pairing that is not allowed (an optimal assignment needs finite costs).
FORBIDDEN = 1e6


@dataclass(frozen=True)
class DroppedMode:
    """A setup's mode that is not in the merged model: setup (0-based), index (in that setup's model),
    frequency_hz, and the reason in words."""

    setup: int
    index: int
    frequency_hz: float
    reason: str


# ---- pairing ----------------------------------------------------------------------------------------------------
def pair_setup_modes(models, refs, tol, min_mac, min_level):
    """Groups: a list of (setups,) int arrays, one per distinct mode (its index in each setup, -1 where not seen),
    built setup by setup by an optimal assignment (frequency and reference MAC), then by frequency alone where the
    reference MAC failed but the frequency leaves no doubt (:func:`by_frequency`); the modes that cannot be scaled
    (references near a node); and the set of (setup, index) paired by frequency alone."""
    n_setups = len(models)
    dropped = []
    frequency_only: set = set()
    groups: list[np.ndarray] = []
    for k, model in enumerate(models):
        r = model.shapes[refs[k]]
        level = np.max(np.abs(r), axis=0) / np.maximum(np.max(np.abs(model.shapes), axis=0), 1e-300)
        usable = np.flatnonzero(level >= min_level)
        for j in np.flatnonzero(level < min_level):
            dropped.append(DroppedMode(k, int(j), float(model.frequency_hz[j]),
                                       f"its reference components are at most {level[j]:.3f} of its largest: the "
                                       "references sit near a node of this mode, so this setup's part of it cannot be "
                                       "scaled to the others'; put a reference where it moves"))
        usable, twins = without_twins(model, usable, min_mac, tol)
        dropped += [DroppedMode(k, j, float(model.frequency_hz[j]),
                                f"a second pole of the {model.frequency_hz[i]:.4g} Hz mode in this setup (its shape at "
                                "every sensor, within its half-power bandwidth or the pairing window): a split twin; "
                                "the stronger pole is kept") for j, i in twins]
        if not groups:
            groups = [new_group(n_setups, k, j) for j in usable]
            continue
        f_new = model.frequency_hz[usable]
        f_old = np.array([mean_frequency(models, g) for g in groups])
        r_old = np.stack([anchor_references(models, refs, g) for g in groups], axis=1)
        mac = indicators.mac(r_old, r[:, usable])  # (groups, usable)
        df = np.abs(f_old[:, None] - f_new[None, :]) / np.maximum(f_old[:, None], 1e-300)
        near = df <= tol
        check_references(k, refs[k], near, mac, min_mac, f_new)
        ok = near & (mac >= min_mac)
        cost = np.where(ok, (df / tol) ** 2 + (1 - mac) / max(1 - min_mac, 1e-12), FORBIDDEN)
        rows, cols = linear_sum_assignment(cost)
        taken = set()
        for i, c in zip(rows, cols):
            if ok[i, c]:
                groups[i][k] = usable[c]
                taken.add(c)
        for i, c in by_frequency(near, taken, [g[k] >= 0 for g in groups]):
            groups[i][k] = usable[c]
            taken.add(c)
            frequency_only.add((k, int(usable[c])))
        groups += [new_group(n_setups, k, usable[c]) for c in range(usable.size) if c not in taken]
    return groups, dropped, frequency_only


def by_frequency(near, taken, filled):
    """[(group, column)] for the modes of a setup the assignment left alone whose reference MAC failed (references
    near a node of the mode, so their components are small and noisy) but whose frequency leaves no doubt: exactly
    one group within the window, which has no mode of this setup yet, and this mode the only one of the setup
    within that group's window. near : (groups, modes) bool; taken : the columns already paired; filled : per
    group, whether it has a mode of this setup."""
    out = []
    for c in range(near.shape[1]):
        rows = np.flatnonzero(near[:, c])
        if c in taken or rows.size != 1 or filled[rows[0]]:
            continue
        if np.flatnonzero(near[rows[0]]).size == 1:
            out.append((int(rows[0]), c))
    return out


def without_twins(model, usable, min_mac, tol: float = 0.0):
    """The usable modes of one setup without split twins: of two modes within the stronger one's half-power
    bandwidth (2 ζ f, the choice's twin rule) or within the pairing window (``tol`` f) whose shapes (every sensor)
    have MAC ≥ ``min_mac``, the one with the larger contribution stays: inside the window both would pair with
    the other setups' mode, and a weaker pole with the same shape beside a mode is its noise (NExT with every
    channel as a correlation reference leaves such poles in short records). Also [(twin, kept)]."""
    f, zeta = model.frequency_hz, np.abs(model.damping_ratio)
    order = sorted(usable.tolist(), key=lambda j: -model.contribution[j])
    keep, twins = [], []
    for j in order:
        match = [i for i in keep if abs(f[i] - f[j]) <= max(2 * zeta[i], tol) * f[i]
                 and indicators.mac(model.shapes[:, i], model.shapes[:, j])[0, 0] >= min_mac]
        if match:
            twins.append((int(j), int(match[0])))
        else:
            keep.append(j)
    return np.array(sorted(keep), dtype=int), twins


def check_references(k, idx, near, mac, min_mac, f_new):
    """A setup whose modes agree with the earlier setups' in frequency but mostly not in their reference components
    named the wrong channels (or the right ones in another order) as references."""
    rows, cols = linear_sum_assignment(np.where(near, 0.0, 1.0))  # as many frequency matches as possible
    matched = [(i, c) for i, c in zip(rows, cols) if near[i, c]]
    bad = [(i, c) for i, c in matched if mac[i, c] < min_mac]
    if matched and 2 * len(bad) >= len(matched):
        detail = ", ".join(f"{f_new[c]:.4g} Hz MAC {mac[i, c]:.2f}" for i, c in bad)
        raise DataError(f"Setup {k + 1}'s reference channels {idx.tolist()} do not move like those of the setups "
                        f"before it: {len(bad)} of its {len(matched)} modes that match theirs in frequency do not "
                        f"match in the reference components ({detail}; at least {min_mac} expected). Check "
                        f"references[{k}] (or the earlier setups' references): the same sensors, in the same order, "
                        "in every setup.")


def new_group(n_setups, k, j) -> np.ndarray:
    g = np.full(n_setups, -1, dtype=int)
    g[k] = j
    return g


def mean_frequency(models, g) -> float:
    return float(np.mean([models[k].frequency_hz[j] for k, j in enumerate(g) if j >= 0]))


def anchor_references(models, refs, g) -> np.ndarray:
    """The reference components of a group's mode in the setup where they move most (relative to the mode's largest
    component): the other setups are scaled onto it, and near a node the least noisy ratio is the best anchor."""
    seen = np.flatnonzero(g >= 0)
    level = [np.linalg.norm(models[k].shapes[refs[k], g[k]]) / max(np.max(np.abs(models[k].shapes[:, g[k]])), 1e-300)
             for k in seen]
    k = int(seen[int(np.argmax(level))])
    return models[k].shapes[refs[k], g[k]]


def recover(analyses, models, refs, members, tol, min_mac, min_level) -> dict:
    """{(mode, setup): (index in that setup's choice.rejected, shape (p,))} for the merged modes a setup did not
    choose, from its clusters rejected for want of evidence that match the mode in frequency and references (one
    cluster per mode, an optimal assignment per setup)."""
    found = {}
    for k, a in enumerate(analyses):
        choice = getattr(a, "choice", None)
        missing = np.flatnonzero(members[:, k] < 0)
        if choice is None or missing.size == 0:
            continue
        pool = [(i, c) for i, c in enumerate(choice.rejected) if c.code in RECOVERABLE
                and np.asarray(c.shape).shape == (models[k].shapes.shape[0],)]
        if not pool:
            continue
        shapes = np.stack([np.asarray(c.shape, dtype=complex) for _, c in pool], axis=1)
        r = shapes[refs[k]]
        level = np.max(np.abs(r), axis=0) / np.maximum(np.max(np.abs(shapes), axis=0), 1e-300)
        f_c = np.array([c.frequency_hz for _, c in pool])
        f_m = np.array([mean_frequency(models, members[m]) for m in missing])
        r_m = np.stack([anchor_references(models, refs, members[m]) for m in missing], axis=1)
        mac = indicators.mac(r_m, r)
        df = np.abs(f_m[:, None] - f_c[None, :]) / np.maximum(f_m[:, None], 1e-300)
        ok = (df <= tol) & (mac >= min_mac) & (level >= min_level)[None, :]
        if not ok.any():
            continue
        cost = np.where(ok, (df / tol) ** 2 + (1 - mac) / max(1 - min_mac, 1e-12), FORBIDDEN)
        for i, c in zip(*linear_sum_assignment(cost)):
            if ok[i, c]:
                found[(int(missing[i]), k)] = (pool[c][0], shapes[:, c])
    return found
