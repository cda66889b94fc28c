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
   found at most orders speaks for it, the others are its twins. A weaker cluster with a stronger mode's very
   shape (MAC ≥ 0.99 over three sensors or more) near it is that mode's shadow, a twin too (era.choice.evidence).
3. **The structure's, not the noise's** (era.choice.evidence): a mode stands above the noise poles (its pole amplitude
   over theirs) and persists over the orders from the first where it appears; the louder, the fewer orders it
   needs (persistence × log10(strength) ≥ MIN_EVIDENCE); a mode that lasts over most of the diagram, coherent
   over three sensors or more, needs only to stand above a typical noise pole (a weak mode of an ambient record);
   it is coherent (γ·μ, the paper's indicators: Pappa's consistent-mode indicator); and its damping is not far
   above the other modes'.

The chosen modes are then read at ONE order of the diagram at which each of them has a pole, so the model the
engineer sees, reconstructs and reports is a model the data gave (:class:`ModeChoice`). Pure functions.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .evidence import fold_shadows, pole_amplitudes, weigh
from ..core.indicators import mac
from ..core.stabilization import COHERENT_MIN, UNCERTAIN_FRACTION

#: Shapes of two tracks with at least this MAC may be one mode split in two (with different shapes: two modes).
TWIN_MAC = 0.9
#: Two tracks are one mode when their frequencies differ by at most this many combined standard deviations ...
TWIN_SIGMAS = 3.0
#: ... or by at most this many half-power bandwidths (2 ζ f) of the stronger: peaks that close are one peak.
TWIN_BANDWIDTHS = 1.0
#: Width of the band's edge zone as a fraction of the band's width: poles there fit the band's cut, not modes.
EDGE_FRACTION = 0.01
#: Above this damping ratio no pole is taken for a structural mode ...
MAX_DAMPING = 0.3
#: Mains frequencies (Hz) whose multiples are checked for undamped lines, and the relative tolerance.
MAINS_HZ = (50.0, 60.0)
MAINS_TOLERANCE = 0.003
#: Only the first multiples: the mains' harmonics fade above them, and higher multiples lie so densely that a
#: mode would sit on one by chance.
MAINS_MULTIPLES = 10

#: Exact rank (noise-free data) needs the last singular value kept this many times above round-off
#: (max(r p, s m)·ε·d_1): the paper's simulated cases stand 1e9 times above it, a spectrum fading into round-off
#: (a noise-free FRF cut to a band) about once. A value that far above round-off is computed to 1e-4 or better,
#: so BLAS cannot move it across the threshold.
EXACT_RANK_MARGIN = 1e4
#: Singular values below this fraction of the largest are round-off for exact rank (exact_rank's default tol).
ROUNDOFF_RANK = 1e-10

#: Reason codes of a rejected candidate, in the order they are tested.
REASONS = ("rigid", "band", "harmonic", "damping", "uncertain", "twin", "orders", "noise", "absent")


@dataclass(frozen=True, eq=False)
class Candidate:
    """One cluster of the stabilization diagram (an era.StableMode), judged.

    Attributes
    ----------
    frequency_hz : float
        The cluster's mean damped frequency over its orders, Hz.
    damping_ratio : float
        Its mean damping ratio (a fraction).
    emac : float
        Its mean EMAC γ.
    mpc : float
        Its mean MPC μ.
    orders : tuple of int
        The model orders where it appears.
    pole_indices : tuple of int
        Its poles: indices into the Stabilization's pole arrays.
    shape : complex ndarray, shape (p,)
        Its shape at its highest order.
    frequency_std_hz : float
        The data's standard deviation of the frequency at that order, Hz (NaN when the diagram was computed
        without them).
    damping_std : float
        The same for the damping ratio.
    diagram_index : int
        Its position in ``Stabilization.modes`` (-1 for a mode of an exact-rank realization, which needs no
        diagram).
    code : str
        "chosen" or one of :data:`REASONS`.
    reason : str
        The verdict in words ("" when chosen).
    mode : int or None
        The chosen mode it is (its index in ModeChoice.chosen) for a chosen cluster and for a split twin, else
        None.
    evidence : dict or None
        What the verdict weighed for the cluster's mode (with its split twins), None when a physical reason
        decided first: ``orders`` (how many of the diagram's orders have it), ``persistence`` (fraction of the
        orders from its first one), ``coverage`` (fraction of all orders), ``emac_mpc`` (mean γ·μ of its poles),
        ``strength`` (its contribution over that of a typical pole at the top order), ``first_order``.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> data, _ = modal_response([2.0, 5.0], [0.01, 0.02], 2, 1, 400, 0.02, snr_db=40, seed=1)
    >>> result = era.analyse(data, max_order=40)
    >>> first = result.choice.chosen[0]
    >>> first.chosen, first.code, round(first.frequency_hz, 3), first.mode
    (True, 'chosen', 2.0, 0)
    >>> noise = result.rejected[0]
    >>> noise.code, noise.reason.startswith("noise pole")
    ('noise', True)
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
    evidence: dict | None = None

    @property
    def chosen(self) -> bool:
        return self.code == "chosen"


@dataclass(frozen=True, eq=False)
class ModeChoice:
    """The modes chosen from a diagram.

    Made by :func:`era.choose_modes`.

    Attributes
    ----------
    order : int
        The diagram order the chosen modes are read at (each has a pole there).
    indices : int ndarray, shape (k,)
        The chosen modes' positions among the modes of ``Identification.model(order)``, in frequency order.
    chosen : tuple of Candidate
        The k chosen clusters in the same order (``mode`` = their position).
    rejected : tuple of Candidate
        Every other cluster of the diagram with its reason, by frequency.
    n_modes : int
        k, the number of chosen modes.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> data, _ = modal_response([2.0, 5.0], [0.01, 0.02], 2, 1, 400, 0.02, snr_db=40, seed=1)
    >>> choice = era.analyse(data, max_order=40).choice
    >>> choice.n_modes, choice.order, choice.indices.shape
    (2, 6, (2,))
    >>> [c.code for c in choice.candidates()]
    ['chosen', 'chosen', 'noise', 'noise']
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


def _median_std(std, poles) -> float:
    """The median over a cluster's poles of their standard deviations from the data (NaN when none computed):
    one order's σ can be far off where the order fits noise."""
    if std is None:
        return float("nan")
    v = np.asarray(std, dtype=float)[poles]
    v = v[np.isfinite(v)]
    return float(np.median(v)) if v.size else float("nan")


def _mains_line(f: float) -> bool:
    """f (Hz) within MAINS_TOLERANCE of a multiple of a mains frequency."""
    for base in MAINS_HZ:
        k = round(f / base)
        if 1 <= k <= MAINS_MULTIPLES and abs(f - k * base) <= MAINS_TOLERANCE * f:
            return True
    return False


def _physics(c: Candidate, lo: float, hi: float, edge: float, record_s: float,
             typical_std_hz: float | None = None) -> tuple[str, str] | None:
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
    sf = c.frequency_std_hz if typical_std_hz is None else typical_std_hz
    if np.isfinite(sf) and sf >= UNCERTAIN_FRACTION * f:
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

    The noise poles a mode is weighed against are those of the diagram's top order: a diagram that stops a few
    orders past the modes has few, strong noise poles there, and the weaker modes fall below them (era.analyse
    goes to order 160; campaigns of 5-minute ambient records need 80).

    Noise-free data (H(0) of exact rank n below the order asked for, the paper's simulated cases) need no
    diagram: the realization of order n is the system, and its decaying modes with γ·μ ≥ COHERENT_MIN are
    chosen at order n (which the diagram must hold, as era.analyse makes it).

    Parameters
    ----------
    ident : Identification
        The identification the diagram was computed from (its Δτ, shifts and singular values).
    stab : Stabilization
        The diagram (``uncertainty=True`` gives the data's standard deviations the twin test uses).
    band_hz : (float, float), optional
        (low, high) Hz, the band the data hold (an FRF's measured band, ``ResponseData.meta["band_hz"]``);
        default (0, Nyquist).
    record_s : float, optional
        Duration of the pulse responses in seconds (an undamped line does not decay over it); default the
        Hankel matrix's span, (rows + cols) Δτ.

    Returns
    -------
    ModeChoice
        With no cluster chosen, ``order`` is the diagram's lowest order and ``indices`` is empty.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> data, truth = modal_response([2.0, 5.0], [0.01, 0.02], 2, 1, 400, 0.02, snr_db=40, seed=1)
    >>> ident = era.identify(data, 60, 60, max_order=40)
    >>> choice = era.choose_modes(ident, era.stabilization(ident, range(2, 41, 2), uncertainty=True))
    >>> [round(candidate.frequency_hz, 3) for candidate in choice.chosen]
    [2.0, 5.0]
    >>> print(np.round(ident.model(choice.order).frequency_hz[choice.indices], 3))
    [2. 5.]
    """
    dt = float(ident.dt)
    nyquist = 0.5 / dt
    lo, hi = (0.0, nyquist) if band_hz is None else (max(0.0, float(band_hz[0])), min(nyquist, float(band_hz[1])))
    edge = EDGE_FRACTION * (hi - lo)
    record_s = float(record_s) if record_s else (ident.rows + ident.cols) * dt
    orders = np.asarray(stab.orders)
    if exact_rank(ident) and ident.max_order in orders:
        return _choose_exact(ident, stab, lo, hi, edge, record_s)

    cands = _candidates(stab)
    verdict: dict[int, tuple] = {}  # diagram_index -> (code, words[, mode])
    for c in cands:  # the uncertainty test takes the median σ of the cluster's poles (one order's can be far off)
        v = _physics(c, lo, hi, edge, record_s, _median_std(stab.frequency_std_hz, list(c.pole_indices)))
        if v:
            verdict[c.diagram_index] = v
    groups = _twin_groups([c for c in cands if c.diagram_index not in verdict], stab)
    passing, weighed = weigh(groups, stab, pole_amplitudes(stab, ident), verdict)
    shadows = fold_shadows(passing, weighed)  # {diagram_index: words}; they join the stronger mode's group

    order, at = _read_order(stab, orders, passing)
    kept = sorted(((g, at[id(g)]) for g in passing if id(g) in at), key=lambda x: stab.frequency_hz[x[1]])
    for g in passing:
        if id(g) not in at:
            verdict[g[0].diagram_index] = ("absent", f"no pole at order {order}, where the other modes are read")
    chosen, indices = [], []
    for k, (g, pole) in enumerate(kept):
        chosen.append(replace(g[0], code="chosen", reason="", mode=k, evidence=weighed.get(g[0].diagram_index)))
        indices.append(int(stab.mode_index[pole]))
        for twin in g[1:]:
            words = shadows.get(twin.diagram_index, "one mode the model split in two")
            verdict[twin.diagram_index] = ("twin", f"split twin of mode {k + 1} ({_fmt_hz(g[0].frequency_hz)}): "
                                                   f"{words}", k)
    for g in groups:  # the twins of a rejected cluster go with it
        code, words = verdict.get(g[0].diagram_index, ("chosen", ""))[:2]
        if code != "chosen":
            for twin in g[1:]:
                verdict[twin.diagram_index] = (code, f"split twin of the {_fmt_hz(g[0].frequency_hz)} cluster, "
                                                     f"which is left out: {words}")
    rejected = sorted((replace(c, code=verdict[c.diagram_index][0], reason=verdict[c.diagram_index][1],
                               mode=verdict[c.diagram_index][2] if len(verdict[c.diagram_index]) > 2 else None,
                               evidence=weighed.get(c.diagram_index))
                       for c in cands if c.diagram_index in verdict), key=lambda c: c.frequency_hz)
    return ModeChoice(order=int(order), indices=np.array(indices, dtype=int), chosen=tuple(chosen),
                      rejected=tuple(rejected))


def exact_rank(ident, tol: float = ROUNDOFF_RANK, margin: float = EXACT_RANK_MARGIN) -> bool:
    """True when H(0) has an exact rank below what was computed (noise-free data): a singular value past the
    identification's max_order exists and is below ``tol`` × the largest, while the last one kept stands at least
    ``margin`` times above round-off (max(r p, s m)·ε·d_1).

    The values of an exact-rank H(0) (the paper's simulated cases) fall from their last mode to round-off at
    once. A spectrum that fades smoothly into round-off (an FRF cut to a band) has no rank: how many of its
    values clear the floor changes with the BLAS kernel and thread count, so it takes the diagram's path."""
    d = np.asarray(ident.singular_values)
    k = int(ident.max_order)
    if not d.size > k > 0:
        return False
    floor = max(ident.P.shape[0], ident.Q.shape[0]) * np.finfo(float).eps * d[0]
    return bool(d[k] <= tol * d[0] and d[k - 1] >= margin * floor)


def _choose_exact(ident, stab, lo, hi, edge, record_s) -> ModeChoice:
    """Noise-free data: the decaying modes of the exact realization (order = rank) with γ·μ ≥ COHERENT_MIN."""
    order = int(ident.max_order)
    poles = np.flatnonzero(stab.order == order)
    chosen, rejected, indices = [], [], []
    for i in poles[np.argsort(stab.frequency_hz[poles], kind="stable")]:
        c = Candidate(frequency_hz=float(stab.frequency_hz[i]), damping_ratio=float(stab.damping_ratio[i]),
                      emac=float(stab.emac[i]), mpc=float(stab.mpc[i]), orders=(order,), pole_indices=(int(i),),
                      shape=stab.shapes[:, i].copy(), frequency_std_hz=float(stab.frequency_std_hz[i]),
                      damping_std=float(stab.damping_std[i]), diagram_index=-1)
        v = _physics(c, lo, hi, edge, record_s)
        if v is None and c.emac * c.mpc < COHERENT_MIN:
            v = ("noise", f"noise pole: γ·μ {c.emac * c.mpc:.2f} in the exact realization (a mode reaches "
                          f"{COHERENT_MIN})")
        if v is None:
            chosen.append(replace(c, mode=len(chosen)))
            indices.append(int(stab.mode_index[i]))
        else:
            rejected.append(replace(c, code=v[0], reason=v[1]))
    return ModeChoice(order=order, indices=np.array(indices, dtype=int), chosen=tuple(chosen),
                      rejected=tuple(rejected))


def _twin_groups(alive: list, stab) -> list[list[Candidate]]:
    """The clusters grouped into modes: each joins the first group, strongest first (most orders, then largest
    contribution), whose first cluster it is a split twin of (:func:`_twin_tolerance`, MAC ≥ TWIN_MAC)."""
    def key(c):
        return -len(c.orders), -float(np.median(stab.contribution[list(c.pole_indices)]))

    groups: list[list[Candidate]] = []
    for c in sorted(alive, key=key):
        for g in groups:
            rep = g[0]
            if abs(c.frequency_hz - rep.frequency_hz) <= _twin_tolerance(rep, c) and \
                    float(mac(rep.shape, c.shape)[0, 0]) >= TWIN_MAC:
                g.append(c)
                break
        else:
            groups.append([c])
    return groups


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
