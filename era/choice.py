"""Which clusters of the stabilization diagram are the structure's modes, and why each other one is not.

The paper's model reduction (section III) keeps the modes whose modal amplitude coherence γ and modal phase
collinearity μ say they are the system's; the stabilization diagram adds what one order cannot show: a mode of
the structure is found again at every order once the order suffices, noise is not. :func:`choose_modes` judges
every cluster of the diagram (``Stabilization.modes``: stable poles tracked across orders) on evidence the data
carry, with no constant tuned to a dataset:

1. **What is not a vibration mode**: a real pole (rigid-body motion or a drift, 0 Hz), a pole outside the band
   the data hold or at its edge (the taper of an FRF band, the anti-alias region below Nyquist), an undamped
   line at a multiple of the mains frequency (a harmonic: it does not decay over the record), a pole that grows
   (ζ ≤ 0), a damping no lightly damped structure has beside its other modes, or a frequency whose uncertainty is
   as large as the value.
2. **One mode, once** (split twins): noise and slow changes of a real structure (amplitude-dependent stiffness)
   split one mode into two or three nearby tracks at higher orders. Tracks whose frequencies lie within the
   mode's half-power bandwidth or within three standard deviations of each other and whose shapes agree
   (MAC ≥ :data:`TWIN_MAC`; with one sensor every MAC is 1 and the frequency decides) are one mode: the track
   found at most orders speaks for it, the others are its twins.
3. **The structure's, not the noise's**: a mode is found in most of the orders from where it first appears
   (persistence) and in a good part of the diagram (coverage), coherent over them (γ·μ, the paper's indicators:
   Pappa's consistent-mode indicator), and above the numerical noise of the realization.

The chosen modes are then read at ONE order of the diagram at which each of them has a pole, so the model the
engineer sees, reconstructs and reports is a model the data gave (:class:`ModeChoice`). Pure functions.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

#: Shapes of two tracks with at least this MAC may be one mode split in two (with different shapes: two modes).
TWIN_MAC = 0.9
#: Two tracks are one mode when their frequencies differ by at most this many combined standard deviations ...
TWIN_SIGMAS = 3.0
#: ... or by at most this many half-power bandwidths (2 ζ f) of the stronger: peaks that close are one peak.
TWIN_BANDWIDTHS = 1.0
#: A mode is found in at least this fraction of the diagram's orders from the one where it first appears ...
MIN_PERSISTENCE = 0.75
#: ... and in at least this fraction of all the diagram's orders.
MIN_COVERAGE = 0.3
#: Mean γ·μ of a mode's poles at least this (era.stabilization.COHERENT_MIN, Pappa's consistent-mode mark).
MIN_EMAC_MPC = 0.9
#: A mode's contribution (units of the singular values) at least this fraction of the largest singular value:
#: below it a pole describes round-off, not the data.
MIN_STRENGTH = 1e-6
#: Width of the band's edge zone as a fraction of the band's width: poles there fit the band's cut, not modes.
EDGE_FRACTION = 0.01
#: Above this damping ratio no pole is taken for a structural mode ...
MAX_DAMPING = 0.3
#: ... and above max(DAMPING_FLOOR, DAMPING_FACTOR × the median damping of the other modes) it is an outlier.
DAMPING_FLOOR = 0.05
DAMPING_FACTOR = 10.0
#: Mains frequencies (Hz) whose multiples are checked for undamped lines, and the relative tolerance.
MAINS_HZ = (50.0, 60.0)
MAINS_TOLERANCE = 0.003

#: Reason codes of a rejected candidate, in the order they are tested.
REASONS = ("rigid", "band", "harmonic", "damping", "uncertain", "twin", "orders", "noise", "absent")


@dataclass(frozen=True, eq=False)
class Candidate:
    """One cluster of the stabilization diagram (an era.StableMode), judged.

    frequency_hz, damping_ratio, emac, mpc : the cluster's means over its orders (Hz, fraction, γ, μ);
    orders, pole_indices : where it appears (model orders; indices into the Stabilization's pole arrays);
    shape : (p,) complex, at its highest order; frequency_std_hz, damping_std : the data's standard deviations
    at that order (NaN when the diagram was computed without them);
    code : "chosen" or one of :data:`REASONS`; reason : the verdict in words ("" when chosen);
    mode : the chosen mode it is (its index in ModeChoice.chosen) for a chosen cluster and for a split twin,
    else None; diagram_index : its position in ``Stabilization.modes``.
    """

    frequency_hz: float
    damping_ratio: float
    emac: float
    mpc: float
    orders: tuple
    pole_indices: tuple
    shape: np.ndarray
    frequency_std_hz: float
    damping_std: float
    diagram_index: int
    code: str = "chosen"
    reason: str = ""
    mode: int | None = None

    @property
    def chosen(self) -> bool:
        return self.code == "chosen"


@dataclass(frozen=True, eq=False)
class ModeChoice:
    """The modes chosen from a diagram.

    order : the diagram order the chosen modes are read at (each has a pole there);
    indices : (k,) int, the chosen modes' positions among the modes of ``Identification.model(order)``, in
        frequency order; chosen : the k chosen Candidates in the same order (``mode`` = their position);
    rejected : every other cluster of the diagram with its reason, by frequency.
    """

    order: int
    indices: np.ndarray
    chosen: tuple
    rejected: tuple

    @property
    def n_modes(self) -> int:
        return len(self.chosen)

    def candidates(self) -> tuple:
        """Every cluster of the diagram, chosen or not, in the diagram's order (``diagram_index``)."""
        return tuple(sorted(self.chosen + self.rejected, key=lambda c: c.diagram_index))


def _fmt_hz(f: float) -> str:
    return f"{f:.4g} Hz"


def _candidates(stab) -> list[Candidate]:
    out = []
    for k, m in enumerate(stab.modes):
        out.append(Candidate(frequency_hz=float(m.frequency_hz), damping_ratio=float(m.damping_ratio),
                             emac=float(m.emac), mpc=float(m.mpc), orders=tuple(m.orders),
                             pole_indices=tuple(m.pole_indices), shape=np.asarray(m.shape),
                             frequency_std_hz=float(m.data_frequency_std_hz),
                             damping_std=float(m.data_damping_std), diagram_index=k))
    return out


def _mac(a: np.ndarray, b: np.ndarray) -> float:
    na, nb = np.vdot(a, a).real, np.vdot(b, b).real
    return float(abs(np.vdot(a, b)) ** 2 / (na * nb)) if na > 0 and nb > 0 else 0.0


def _mains_line(f: float) -> bool:
    """f (Hz) within MAINS_TOLERANCE of a multiple of a mains frequency."""
    for base in MAINS_HZ:
        k = round(f / base)
        if k >= 1 and abs(f - k * base) <= MAINS_TOLERANCE * f:
            return True
    return False


def _physics(c: Candidate, lo: float, hi: float, edge: float, record_s: float) -> tuple[str, str] | None:
    """(code, words) when ``c`` is not a vibration mode of the structure whatever the other clusters say."""
    f, z = c.frequency_hz, c.damping_ratio
    if not f > 0 or z >= 0.999:
        return "rigid", "a real pole (0 Hz): rigid-body motion or a drift, not a vibration mode"
    if f < lo or f > hi:
        return "band", f"outside the band the data hold ({lo:.4g}-{hi:.4g} Hz)"
    if (lo > 0 and f < lo + edge) or f > hi - edge:
        where = lo if lo > 0 and f < lo + edge else hi
        return "band", f"at the band edge ({_fmt_hz(f)}, within {edge:.3g} Hz of {where:.4g} Hz): it fits the cut"
    sz = c.damping_std if np.isfinite(c.damping_std) else 0.0
    undamped = abs(z) <= 2 * sz + 1.0 / (2 * np.pi * f * max(record_s, 1e-300))
    if undamped and _mains_line(f):
        return "harmonic", (f"harmonic: an undamped line at {_fmt_hz(f)}, a multiple of the mains frequency "
                            f"(ζ {100 * z:.2g} %, no decay over the record)")
    if z <= 0:
        return "damping", f"negative damping (ζ {100 * z:.3g} %): a growing pole fits noise, not a mode"
    if z > MAX_DAMPING:
        return "damping", f"implausible damping (ζ {100 * z:.3g} %)"
    sf = c.frequency_std_hz
    if np.isfinite(sf) and sf >= 0.5 * f:
        return "uncertain", f"uncertainty as large as the value (σ {sf:.3g} Hz at {_fmt_hz(f)})"
    return None


def _twin_tolerance(a: Candidate, b: Candidate) -> float:
    """Hz: how far apart the frequencies of ``b`` and the stronger ``a`` may be for the two to be one mode."""
    sa = a.frequency_std_hz if np.isfinite(a.frequency_std_hz) else 0.0
    sb = b.frequency_std_hz if np.isfinite(b.frequency_std_hz) else 0.0
    return max(TWIN_SIGMAS * np.hypot(sa, sb), TWIN_BANDWIDTHS * 2 * a.damping_ratio * a.frequency_hz)


def choose_modes(ident, stab, *, band_hz: tuple[float, float] | None = None,
                 record_s: float | None = None) -> ModeChoice:
    """The structure's modes among the clusters of a stabilization diagram, each once, with the reasons for the rest.

    Parameters
    ----------
    ident : era.Identification the diagram was computed from (its Δτ and singular values).
    stab : era.Stabilization (``uncertainty=True`` gives the data's standard deviations the twin test uses).
    band_hz : (low, high) Hz, the band the data hold (an FRF's measured band, ``ResponseData.meta["band_hz"]``);
        default (0, Nyquist).
    record_s : duration of the pulse responses in seconds (an undamped line does not decay over it); default the
        Hankel matrix's span, (rows + cols) Δτ.

    Returns
    -------
    ModeChoice. With no cluster chosen, ``order`` is the diagram's lowest order and ``indices`` is empty.
    """
    dt = float(ident.dt)
    nyquist = 0.5 / dt
    lo, hi = (0.0, nyquist) if band_hz is None else (max(0.0, float(band_hz[0])), min(nyquist, float(band_hz[1])))
    edge = EDGE_FRACTION * (hi - lo)
    record_s = float(record_s) if record_s else (ident.rows + ident.cols) * dt
    orders = np.asarray(stab.orders)
    n_orders = max(len(orders), 1)
    d1 = float(ident.singular_values[0]) if ident.singular_values.size else 0.0

    cands = _candidates(stab)
    verdict: dict[int, tuple[str, str]] = {}
    for c in cands:
        v = _physics(c, lo, hi, edge, record_s)
        if v:
            verdict[c.diagram_index] = v

    # one mode, once: the strongest track (most orders, then largest contribution) speaks for its twins
    def strength(c):
        return float(np.median(stab.contribution[list(c.pole_indices)]))

    alive = sorted((c for c in cands if c.diagram_index not in verdict),
                   key=lambda c: (-len(c.orders), -strength(c)))
    groups: list[list[Candidate]] = []
    for c in alive:
        for g in groups:
            rep = g[0]
            if abs(c.frequency_hz - rep.frequency_hz) <= _twin_tolerance(rep, c) and _mac(rep.shape, c.shape) >= TWIN_MAC:
                g.append(c)
                break
        else:
            groups.append([c])

    # the damping of the structure's other modes: an outlier far above it is the fit's, not the structure's
    def evidence(g):
        union = sorted({o for c in g for o in c.orders})
        later = int(np.count_nonzero(orders >= union[0]))
        poles = [i for c in g for i in c.pole_indices]
        gm = float(np.mean(stab.emac[poles] * stab.mpc[poles]))
        return len(union), len(union) / max(later, 1), len(union) / n_orders, gm, strength(g[0])

    passing = []
    for g in groups:
        n, persistence, coverage, gm, s = evidence(g)
        rep = g[0]
        if persistence < MIN_PERSISTENCE or coverage < MIN_COVERAGE:
            verdict[rep.diagram_index] = ("orders", f"too few orders: found in {n} of the diagram's {n_orders} "
                                                    f"orders ({persistence:.0%} of those from order {min(rep.orders)} on)")
        elif gm < MIN_EMAC_MPC:
            verdict[rep.diagram_index] = ("noise", f"noise pole: γ·μ {gm:.2f} over its orders "
                                                   f"(a mode of the structure reaches {MIN_EMAC_MPC})")
        elif not s >= MIN_STRENGTH * d1:
            verdict[rep.diagram_index] = ("noise", f"noise pole: its contribution is {s / d1:.1e} of the largest "
                                                   "singular value (round-off)")
        else:
            passing.append(g)
    if passing:
        typical = float(np.median([g[0].damping_ratio for g in passing]))
        limit = max(DAMPING_FLOOR, DAMPING_FACTOR * typical)
        for g in list(passing):
            z = g[0].damping_ratio
            if z > limit:
                verdict[g[0].diagram_index] = ("damping", f"implausible damping (ζ {100 * z:.3g} % where the "
                                                          f"structure's other modes have {100 * typical:.2g} %)")
                passing.remove(g)

    order, at = _read_order(stab, orders, passing)
    kept = [(g, at[id(g)]) for g in passing if id(g) in at]
    for g in passing:
        if id(g) not in at:
            verdict[g[0].diagram_index] = ("absent", f"no pole at order {order}, where the other modes are read")
    kept.sort(key=lambda x: stab.frequency_hz[x[1]])
    chosen, indices = [], []
    for k, (g, pole) in enumerate(kept):
        chosen.append(replace(g[0], code="chosen", reason="", mode=k))
        indices.append(int(stab.mode_index[pole]))
        for twin in g[1:]:
            verdict[twin.diagram_index] = ("twin", f"split twin of mode {k + 1} ({_fmt_hz(g[0].frequency_hz)}): "
                                                   "one mode the model split in two")
            verdict[twin.diagram_index] += (k,)
    for g in groups:  # twins of a rejected group share its verdict
        if g[0].diagram_index in verdict:
            for twin in g[1:]:
                verdict.setdefault(twin.diagram_index, verdict[g[0].diagram_index][:2])
    rejected = []
    for c in cands:
        v = verdict.get(c.diagram_index)
        if v is None or any(c.diagram_index == x.diagram_index for x in chosen):
            continue
        rejected.append(replace(c, code=v[0], reason=v[1], mode=v[2] if len(v) > 2 else None))
    rejected.sort(key=lambda c: c.frequency_hz)
    return ModeChoice(order=int(order), indices=np.array(indices, dtype=int), chosen=tuple(chosen),
                      rejected=tuple(rejected))


def _read_order(stab, orders: np.ndarray, groups: list) -> tuple[int, dict]:
    """The diagram order to read the chosen modes at and, per group (by id), its pole there.

    The lowest order at which every group has a pole (the one of its strongest track if it has several);
    when none has all, the order with the most, ties to the lowest.
    """
    if not groups or not len(orders):
        return (int(orders[0]) if len(orders) else 1), {}
    poles_at = []
    for g in groups:
        where: dict[int, int] = {}
        for c in reversed(g):  # the strongest track last, so its pole wins
            for i in c.pole_indices:
                where[int(stab.order[i])] = int(i)
        poles_at.append(where)
    counts = np.array([sum(int(o) in w for w in poles_at) for o in orders])
    order = int(orders[int(np.argmax(counts))])  # argmax: the lowest of the best
    return order, {id(g): w[order] for g, w in zip(groups, poles_at) if order in w}
