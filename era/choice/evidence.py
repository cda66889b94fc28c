"""How much a cluster of the stabilization diagram is worth as a mode of the structure (era.choice.choose's step 3).

A mode of the structure stands above the noise and persists over the orders: its poles' amplitude |c||b| (the
contribution to H(0) without the decay factor, so nearly undamped poles that fit noise do not rank with modes)
over the median amplitude of the top order's poles that are not modes, and the fraction of the orders, from the
first where it appears, that hold it; a mode found at most of ALL the diagram's orders, coherent over three sensors
or more, needs only to stand above a typical noise pole. The paper's γ·μ counts too (Pappa's consistent-mode
indicator). Pure functions of the diagram's arrays and the groups of clusters (each a list of
era.choice.choose.Candidate, the strongest first).
"""

from __future__ import annotations

import numpy as np

from ..core.indicators import mac
from ..core.stabilization import COHERENT_MIN

#: The evidence a mode needs: persistence × log10(strength) ≥ MIN_EVIDENCE, where persistence is the fraction of
#: the diagram's orders, from the first where it appears, that have it, and strength its pole amplitude over that
#: of a typical pole at the top order (noise). A mode present at every order needs 10^0.6 = 4 times the noise's
#: amplitude, one present at half of them 16 times: the louder a mode, the less its presence in every order
#: matters (noise breaks the tracks of strong modes of ambient records too).
MIN_EVIDENCE = 0.6
#: A steady mode (found at ≥ 95 % of the orders from its first, over ≥ half the diagram, γ·μ ≥ COHERENT_MIN) needs
#: only 3 times the noise's amplitude: no noise cluster of the test records was that steady.
STEADY_PERSISTENCE = 0.95
STEADY_COVERAGE = 0.5
STEADY_STRENGTH = 3.0
#: A lasting mode (found at ≥ 60 % of ALL the diagram's orders, γ·μ ≥ COHERENT_MIN, a shape over ≥ LASTING_SENSORS
#: sensors) needs only to stand above a typical noise pole (strength ≥ LASTING_STRENGTH): a mode 10 × weaker than
#: the strongest in acceleration stands only 1.5-5 times above the noise poles of a high order, yet it is found at
#: 65-95 % of the orders with γ·μ 0.94-1.0 over 6-12 sensors (tests/bench/bench_oma_uncertainty.py), while no
#: noise cluster of the test records over three sensors or more lasted that long coherently (their γ·μ 0.6-0.8).
#: With one or two sensors μ and the shape's stability say little, so the rule needs three.
LASTING_COVERAGE = 0.6
LASTING_SENSORS = 3
LASTING_STRENGTH = 1.0
#: A mode is found in at least this fraction of all the diagram's orders.
MIN_COVERAGE = 0.15
#: Mean γ·μ of a mode's poles at least this: the paper's indicators, low for a pole fitting noise (one sensor
#: makes μ = 1, so the other evidence carries that case).
MIN_EMAC_MPC = 0.5
#: A weaker cluster with a stronger mode's shape (MAC ≥ SHADOW_MAC over at least SHADOW_SENSORS sensors), within
#: SHADOW_SPAN of its frequency and SHADOW_RATIO times weaker or more, is that mode's shadow (a split twin).
SHADOW_MAC = 0.99
SHADOW_SENSORS = 3
SHADOW_SPAN = 0.2
SHADOW_RATIO = 3.0
#: A mode whose damping is above max(DAMPING_FLOOR, DAMPING_FACTOR × the median damping of the other modes) is an
#: outlier: the fit's, not the structure's.
DAMPING_FLOOR = 0.05
DAMPING_FACTOR = 10.0

def weigh(groups: list, stab, amplitude: np.ndarray, verdict: dict) -> tuple[list, dict]:
    """The groups that are modes of the structure, and every group's evidence (by diagram_index of each member).

    The noise scale is the median pole amplitude at the diagram's top order without the poles of the modes
    found so far, found again until the modes found do not change (a structure with many modes has many of
    them among the top order's poles)."""
    orders = np.asarray(stab.orders)
    n_orders = max(len(orders), 1)
    top = np.flatnonzero(stab.order == orders[-1]) if len(orders) else np.zeros(0, int)
    facts = []
    for g in groups:
        present = np.unique([o for c in g for o in c.orders])
        later = int(np.count_nonzero(orders >= present[0]))
        poles = [i for c in g for i in c.pole_indices]
        facts.append(dict(orders=len(present), persistence=len(present) / max(later, 1),
                          coverage=len(present) / n_orders,
                          emac_mpc=float(np.mean(stab.emac[poles] * stab.mpc[poles])),
                          loud=float(np.median(amplitude[list(g[0].pole_indices)])), first_order=int(present[0]),
                          poles=set(poles), sensors=int(np.asarray(g[0].shape).size)))
    passing_idx: list[int] = []
    verdicts: dict[int, tuple] = {}
    for _ in range(6):
        taken = set().union(*(facts[k]["poles"] for k in passing_idx)) if passing_idx else set()
        background = amplitude[[i for i in top if i not in taken and amplitude[i] > 0]]
        noise = float(np.median(background)) if background.size else 1.0
        now, verdicts = [], {}
        for k, f in enumerate(facts):
            f["strength"] = f["loud"] / noise if noise > 0 else np.inf
            v = _verdict(f, n_orders)
            if v is None:
                now.append(k)
            else:
                verdicts[k] = v
        if now == passing_idx:
            break
        passing_idx = now
    weighed = {}
    for k, g in enumerate(groups):
        e = {key: facts[k][key] for key in ("orders", "persistence", "coverage", "emac_mpc", "strength",
                                             "first_order")}
        for c in g:
            weighed[c.diagram_index] = e
        if k in verdicts:
            verdict[g[0].diagram_index] = verdicts[k]
    passing = [groups[k] for k in passing_idx]
    # the damping of the structure's other modes: an outlier far above it is the fit's, not the structure's
    if passing:
        typical = float(np.median([g[0].damping_ratio for g in passing]))
        limit = max(DAMPING_FLOOR, DAMPING_FACTOR * typical)
        for g in list(passing):
            z = g[0].damping_ratio
            if z > limit:
                verdict[g[0].diagram_index] = ("damping", f"implausible damping (ζ {100 * z:.3g} % where the "
                                                          f"structure's other modes have {100 * typical:.2g} %)")
                passing.remove(g)
    return passing, weighed


def fold_shadows(passing: list, weighed: dict) -> dict:
    """Fold into a stronger mode's group each passing group with the same shape (MAC ≥ SHADOW_MAC over at least
    SHADOW_SENSORS sensors), at most SHADOW_SPAN away in frequency and SHADOW_RATIO times weaker or more: two
    modes of a structure do not share a shape, and such a pole fits the stronger mode's estimation error (an
    ambient record's correlation functions, a drifting frequency). ``passing`` is changed in place; returns the
    words for each folded cluster by diagram_index."""
    words: dict[int, str] = {}
    loud = sorted(passing, key=lambda g: -weighed[g[0].diagram_index]["strength"])
    for i, g in enumerate(loud):
        rep = g[0]
        if rep.shape.size < SHADOW_SENSORS or g not in passing:
            continue
        s = weighed[rep.diagram_index]["strength"]
        for h in loud[:i]:
            if h not in passing:
                continue
            strong = h[0]
            ratio = weighed[strong.diagram_index]["strength"] / max(s, 1e-300)
            away = abs(rep.frequency_hz - strong.frequency_hz) / strong.frequency_hz
            m = float(mac(rep.shape, strong.shape)[0, 0])
            if m >= SHADOW_MAC and away <= SHADOW_SPAN and ratio >= SHADOW_RATIO:
                for c in g:
                    words[c.diagram_index] = (f"its shape (MAC {m:.3f}), {away:.0%} away and {ratio:.0f} times "
                                              "weaker: it fits the mode's estimation error")
                h.extend(g)
                passing.remove(g)
                break
    return words


def _verdict(f: dict, n_orders: int) -> tuple | None:
    """(code, words) when a group's evidence ``f`` does not make it a mode of the structure, else None."""
    s, persistence = f["strength"], f["persistence"]
    if (persistence >= STEADY_PERSISTENCE and f["coverage"] >= STEADY_COVERAGE and s >= STEADY_STRENGTH
            and f["emac_mpc"] >= COHERENT_MIN):
        return None  # steady: at nearly every order from its first, over half the diagram, coherent, above noise
    if (f["coverage"] >= LASTING_COVERAGE and f["emac_mpc"] >= COHERENT_MIN and f["sensors"] >= LASTING_SENSORS
            and s >= LASTING_STRENGTH):
        return None  # lasting: at most of the diagram's orders, coherent over three sensors or more, above noise
    if not s >= 10 ** MIN_EVIDENCE:
        return "noise", (f"noise pole: its amplitude is {s:.2g} times a typical noise pole's (a mode of the "
                         f"structure stands {10 ** MIN_EVIDENCE:.0f} times above)")
    if persistence * np.log10(s) < MIN_EVIDENCE or f["coverage"] < MIN_COVERAGE:
        return "orders", (f"too few orders for its strength: found in {f['orders']} of the diagram's {n_orders} "
                          f"orders ({persistence:.0%} of those from order {f['first_order']} on) at {s:.3g} times "
                          "a noise pole's amplitude")
    if f["emac_mpc"] < MIN_EMAC_MPC:
        return "noise", (f"noise pole: γ·μ {f['emac_mpc']:.2f} over its orders (a mode of the structure reaches "
                         f"{MIN_EMAC_MPC})")
    return None


def pole_amplitudes(stab, ident) -> np.ndarray:
    """(n_poles,) each pole's initial amplitude |c||b|: its contribution to H(0) (era.core.indicators.contribution)
    without the factor its decay over the Hankel matrix's shifts gives it, sqrt(Σ_i |z|^{2 j_i} Σ_i |z|^{2 t_i}).
    A nearly undamped pole that fits noise spreads a small amplitude over the whole matrix; its contribution
    would rank it with the modes, its amplitude does not."""
    zeta = np.clip(stab.damping_ratio, -0.999, 0.999)
    wn = 2 * np.pi * np.abs(stab.frequency_hz) / np.sqrt(1 - zeta**2)
    two_log = -2 * zeta * wn * float(ident.dt)  # ln |z|²
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        amp = stab.contribution / np.sqrt(_power_sums(two_log, ident.row_shifts) *
                                          _power_sums(two_log, ident.col_shifts))
    return np.where(np.isfinite(amp), amp, 0.0)


def _power_sums(two_log: np.ndarray, shifts) -> np.ndarray:
    """Σ_i |z|^{2 t_i} for each pole (ln |z|² given), by the geometric series when the shifts are 0, 1, …, s-1."""
    t = np.asarray(shifts)
    if t.size and t[0] == 0 and np.array_equal(t, np.arange(t.size)):
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            ratio = np.expm1(t.size * two_log) / np.expm1(two_log)
        return np.where(two_log == 0, float(t.size), ratio)
    return np.exp(two_log[:, None] * t[None, :]).sum(axis=1)
