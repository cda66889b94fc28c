"""The stabilization diagram: the poles of every model order from ONE SVD, their stability, and the modes
that persist across orders."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import EraError
from .realization import Identification
from .blas import blas_threads, single_threaded_blas
from .sweep import in_parallel, order_indicators, realize_orders

#: A suggested mode is coherent when its mean γ·μ reaches this (marked in the diagram as a likely physical mode).
COHERENT_MIN = 0.9
#: A cluster whose poles' median frequency σ from the data reaches this fraction of its frequency is too uncertain to
#: be a mode (era.choice.choose); ``stabilization(..., uncertainty="choice")`` computes enough of the σ to tell.
UNCERTAIN_FRACTION = 0.5


@dataclass(frozen=True)
class StableMode:
    """A mode suggested by the diagram: stable poles of several orders tracked as one.

    The spread across orders (``frequency_std_hz``, ``damping_std``) is not an uncertainty of the data: it
    shrinks as more orders agree on the same biased value; ``data_frequency_std_hz`` and ``data_damping_std`` are.

    Attributes
    ----------
    frequency_hz : float
        Mean damped frequency over the orders where it appears, Hz.
    frequency_std_hz : float
        Standard deviation of the frequency across those orders (the spread), Hz.
    damping_ratio : float
        Mean damping ratio ζ over those orders (a fraction).
    damping_std : float
        Standard deviation of the damping ratio across those orders.
    emac : float
        Mean EMAC γ over those orders, in [0, 1].
    mpc : float
        Mean MPC μ over those orders, in [0, 1].
    orders : tuple of int
        The orders where it appears.
    pole_indices : tuple of int
        Its poles in the Stabilization arrays.
    shape : complex ndarray, shape (p,)
        The shape at the highest of those orders.
    data_frequency_std_hz : float
        The standard deviation of the frequency the data give at that highest order, Hz (era.core.uncertainty;
        NaN when the diagram was computed without them).
    data_damping_std : float
        The same for the damping ratio.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> data, _ = modal_response([2.0], [0.01], 2, 1, 300, 0.02, snr_db=40, seed=2)
    >>> stab = era.stabilization(era.identify(data, 40, 40), range(2, 21, 2), uncertainty=True)
    >>> mode = stab.modes[0]
    >>> print(f"{mode.frequency_hz:.3f} Hz, coherent: {mode.coherent}, data σ finite: {mode.data_frequency_std_hz > 0}")
    2.000 Hz, coherent: True, data σ finite: True
    """

    frequency_hz: float
    frequency_std_hz: float
    damping_ratio: float
    damping_std: float
    emac: float
    mpc: float
    orders: tuple
    pole_indices: tuple
    shape: np.ndarray
    data_frequency_std_hz: float = float("nan")
    data_damping_std: float = float("nan")

    @property
    def coherent(self) -> bool:
        """Mean γ·μ ≥ :data:`COHERENT_MIN`: stable AND coherent, a likely physical mode."""
        return bool(self.emac * self.mpc >= COHERENT_MIN)


@dataclass(frozen=True, eq=False)
class Stabilization:
    """Poles of every order of one identification; per-pole arrays have shape (n_poles,).

    Made by :func:`era.stabilization`.

    Attributes
    ----------
    orders : int ndarray, shape (n_orders,)
        The orders computed (requested orders above ident.max_order are left out).
    order : int ndarray, shape (n_poles,)
        Each pole's model order.
    mode_index : int ndarray, shape (n_poles,)
        Each pole's index among the modes of its order, i.e. in ``ident.model(order)``.
    frequency_hz : ndarray, shape (n_poles,)
        Each pole's damped frequency, Hz.
    damping_ratio : ndarray, shape (n_poles,)
        Each pole's damping ratio ζ.
    emac : ndarray, shape (n_poles,)
        Each pole's EMAC γ, in [0, 1].
    mpc : ndarray, shape (n_poles,)
        Each pole's MPC μ, in [0, 1].
    contribution : ndarray, shape (n_poles,)
        Each pole's contribution to H(0) (units of the singular values, as ModalModel.contribution).
    stable_frequency : bool ndarray, shape (n_poles,)
        The pole's partner at the previous computed order is within freq_tol (relative frequency change); the
        first order has no previous one, so this and the next two are all False there.
    stable_damping : bool ndarray, shape (n_poles,)
        Its partner's damping ratio is within damping_tol (relative change).
    stable_shape : bool ndarray, shape (n_poles,)
        Its partner's shape has MAC ≥ mac_min with the pole's.
    shapes : complex ndarray, shape (p, n_poles)
        Each pole's mode shape.
    modes : tuple of StableMode
        The suggested modes, sorted by frequency.
    frequency_std_hz : ndarray, shape (n_poles,)
        Each stable pole's standard deviation of the frequency from the data, Hz (ModalModel's; NaN for the
        other poles, and for all unless ``stabilization(..., uncertainty=True)``; with ``uncertainty="choice"``
        only for the poles era.choice.choose reads, see :func:`stabilization`).
    damping_std : ndarray, shape (n_poles,)
        The same for the damping ratio.
    uncertainty_source : str
        Which scatter they come from ("σ from N records" / "σ from one record's residuals", as
        ModalModel.uncertainty_source); "" without them.

    Examples
    --------
    >>> from era.examples.synthetic import modal_response
    >>> data, _ = modal_response([2.0, 5.0], [0.01, 0.02], 2, 1, 400, 0.02, snr_db=40, seed=1)
    >>> stab = era.stabilization(era.identify(data, 60, 60), range(2, 31, 2))
    >>> stab.orders.tolist()[:4], stab.order.shape == stab.frequency_hz.shape == stab.stable.shape
    ([2, 4, 6, 8], True)
    >>> print([round(mode.frequency_hz, 3) for mode in stab.modes])
    [2.0, 5.0]
    """

    orders: np.ndarray
    order: np.ndarray
    mode_index: np.ndarray
    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    emac: np.ndarray
    mpc: np.ndarray
    contribution: np.ndarray
    stable_frequency: np.ndarray
    stable_damping: np.ndarray
    stable_shape: np.ndarray
    shapes: np.ndarray
    modes: tuple
    frequency_std_hz: np.ndarray | None = None
    damping_std: np.ndarray | None = None
    uncertainty_source: str = ""

    @property
    def stable(self) -> np.ndarray:
        """Stable in frequency, damping and shape: (n_poles,) bool."""
        return self.stable_frequency & self.stable_damping & self.stable_shape


def _relative_change(new: np.ndarray, old: np.ndarray, pairwise: bool = True) -> np.ndarray:
    """|new - old| / |old| for every pair (len(new), len(old)), or element by element (``pairwise=False``);
    0/0 counts as no change."""
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.abs(new[:, None] - old[None, :]) / np.abs(old)[None, :] if pairwise else \
            np.abs(new - old) / np.abs(old)
    out[np.isnan(out)] = 0.0  # 0/0 (x/0 = inf)
    return out


def _nearest_in_previous_order(start: np.ndarray, freq: np.ndarray) -> np.ndarray:
    """For each pole, the index of the pole of the previous computed order with the least relative frequency
    change (the first of equals), -1 at the first order or when the previous order has no pole. ``start``
    (n_orders + 1,): the poles of order k are [start[k], start[k+1]). All orders in one padded array."""
    counts = np.diff(start)
    near = np.full(freq.size, -1)
    if len(counts) < 2 or not counts.any():
        return near
    width = int(counts.max())
    ref = np.full((len(counts), width), np.nan)  # each order's frequencies, padded
    within = np.arange(width)[None, :] < counts[:, None]
    ref[within] = freq
    order_of = np.repeat(np.arange(len(counts)), counts)
    later = order_of >= 1
    prev = ref[order_of[later] - 1]  # (poles after the first order, width)
    change = _relative_change(freq[later][:, None], prev, pairwise=False)  # broadcast: pole × candidate
    change[np.isnan(prev)] = np.inf  # padding
    best = np.argmin(change, axis=1)
    found = counts[order_of[later] - 1] > 0
    near[np.flatnonzero(later)[found]] = start[order_of[later][found] - 1] + best[found]
    return near


def _unit_columns(shapes: np.ndarray) -> np.ndarray:
    """Each column of ``shapes`` (p, k) scaled to unit norm (a zero column stays zero): then the MAC of two
    columns (indicators.mac) is |u_i^H u_j|², one product for many pairs."""
    norm = np.sqrt(np.einsum("pk,pk->k", shapes.conj(), shapes).real)
    return shapes / np.where(norm > 0, norm, np.inf)


def _cluster(order, freq, unit, stable, freq_tol, mac_min, min_orders) -> list[list[int]]:
    """Track stable poles across orders: each joins the cluster whose latest pole is nearest in frequency,
    within freq_tol and MAC ≥ mac_min, at most one pole per cluster and order (so repeated or close modes
    with different shapes stay apart). ``unit``: the poles' shapes as :func:`_unit_columns`."""
    clusters: list[list[int]] = []
    for n in np.unique(order):
        idx = np.flatnonzero((order == n) & stable)
        if not idx.size:
            continue
        heads = [c[-1] for c in clusters]
        taken: set[int] = set()
        filled: set[int] = set()
        if heads:
            df = _relative_change(freq[idx], freq[heads])
            near = df <= freq_tol
            near[near] = (np.abs(unit[:, idx].conj().T @ unit[:, heads]) ** 2 >= mac_min)[near]
            rows, cols = np.nonzero(near)  # the candidate (pole, track) pairs, nearest first
            by = np.argsort(df[rows, cols], kind="stable")
            for i, j in zip(idx[rows[by]].tolist(), cols[by].tolist()):
                if i not in taken and j not in filled:
                    clusters[j].append(i)
                    taken.add(i)
                    filled.add(j)
        clusters.extend([i] for i in idx.tolist() if i not in taken)
    tracks = [c for c in clusters if len(c) >= min_orders]
    return _merge_fragments(tracks, order, freq, freq_tol)


def _merge_fragments(clusters, order, freq, freq_tol) -> list[list[int]]:
    """Join tracks of one mode that broke apart (a shape that turned within a repeated pair's plane, an
    order where the pole was not stable): same mean frequency within freq_tol and no order in common.
    Only tracks that already pass min_orders are joined, so stray noise poles do not add up to a mode."""
    merged: list[list[int]] = []
    means: list[float] = []  # of each merged track, kept with it
    orders: list[set] = []
    for c in sorted(clusters, key=len, reverse=True):
        f = freq[c].mean()
        mine = set(order[c].tolist())
        for k, m in enumerate(merged):
            if abs(means[k] - f) <= freq_tol * max(abs(f), 1e-300) and not orders[k] & mine:
                m.extend(c)
                m.sort()
                means[k], orders[k] = freq[m].mean(), orders[k] | mine
                break
        else:
            merged.append(list(c))
            means.append(f)
            orders.append(mine)
    return merged


def stabilization(ident: Identification, orders=range(2, 121, 2), *, freq_tol: float = 0.01,
                  damping_tol: float = 0.05, mac_min: float = 0.98, min_orders: int = 3,
                  uncertainty: bool | str = False, workers: int | None = None) -> Stabilization:
    """Poles of every requested order, each realized from the leading block of the SAME projected H(1).

    Every order is ``ident.model(order)`` (same numbers, also for repeated modes): the projection of H(1) is
    made once for the largest order, then the orders are realized in parallel and compared in order.

    Parameters
    ----------
    ident : Identification
        From :func:`era.identify`; no SVD is recomputed here.
    orders : iterable of int, optional
        Model orders n (state dimensions); default every even order from 2 to 120. Orders above
        ident.max_order are skipped.
    freq_tol : float, optional
        Relative change of frequency to the nearest pole of the previous order below which a pole is stable in
        frequency (default 0.01, 1 %).
    damping_tol : float, optional
        Relative change of damping ratio to that pole below which it is stable in damping (default 0.05, 5 %).
    mac_min : float, optional
        MAC with that pole at or above which the shape is stable (default 0.98).
    min_orders : int, optional
        A suggested mode must be found stable (all three) in at least this many orders (default 3).
    uncertainty : bool or "choice", optional
        True: also the standard deviations from the data (ModalModel.frequency_std_hz, damping_std) of every
        stable pole (NaN for the others): about the work of the sweep again (tests/bench/bench_sweep.py).
        "choice": the same numbers for the poles whose σ era.choice.choose reads, NaN for the others, and the same
        choice for about a third of the work: each suggested mode's last pole (``data_frequency_std_hz``), the
        stable poles of the top order when it is the identification's max_order (the exact-rank choice), and
        of each mode's other poles enough to tell whether their median σ of the frequency reaches
        UNCERTAIN_FRACTION of its frequency: the lowest orders' until more than half are below it, all of them
        when one is not (era.analyse's default). False (default): none.
    workers : int, optional
        Orders realized at a time in threads (numpy's eigensolver releases the GIL); default the BLAS thread
        count (:func:`blas_threads`), so one BLAS thread means one core.

    Returns
    -------
    Stabilization
        Every pole of every computed order, its stability flags and the suggested modes.

    Raises
    ------
    era.EraError
        For ``orders`` that are not positive integers or an ``uncertainty`` other than False, True, "choice".

    References
    ----------
    Juang & Pappa (1985), eq. 34: every order's realization is a leading block of one projection of H(1).

    Examples
    --------
    Two modes (2 Hz, 1 % and 5 Hz, 2 %) seen by two sensors, with noise 40 dB below the signal:

    >>> from era.examples.synthetic import modal_response
    >>> data, truth = modal_response([2.0, 5.0], [0.01, 0.02], 2, 1, 400, 0.02, snr_db=40, seed=1)
    >>> stab = era.stabilization(era.identify(data, 60, 60), range(2, 31, 2))
    >>> for mode in stab.modes:
    ...     print(f"{mode.frequency_hz:.3f} Hz, zeta {mode.damping_ratio:.3f}, stable from order {mode.orders[0]}")
    2.000 Hz, zeta 0.010, stable from order 6
    5.000 Hz, zeta 0.020, stable from order 6
    """
    req = sorted({int(n) for n in orders})
    if uncertainty not in (False, True, "choice"):
        raise EraError(f"`uncertainty` must be False, True or \"choice\", got {uncertainty!r}.")
    if not req or req[0] < 1:
        raise EraError("`orders` must hold positive integers (model orders), e.g. range(2, 121, 2).")
    done = [n for n in req if n <= ident.max_order]
    workers = blas_threads() if workers is None else max(1, int(workers))
    with single_threaded_blas():  # all of it: its threads have one BLAS thread each, and one limit for the
        # whole (each limit lifted costs 0.2-4 ms, era.core.blas) keeps the small products after them on one thread
        return _stabilization(ident, done, freq_tol, damping_tol, mac_min, min_orders, uncertainty, workers)


def _stabilization(ident, done, freq_tol, damping_tol, mac_min, min_orders, uncertainty, workers):
    """:func:`stabilization` of the orders ``done``."""
    sw = realize_orders(ident, done, workers)
    order, freq, damp, shapes = sw.order, sw.frequency_hz, sw.damping_ratio, sw.shapes
    gamma, mu, contribution = order_indicators(ident, sw, workers)
    unit = _unit_columns(shapes)  # MAC = |u_i^H u_j|²
    near = _nearest_in_previous_order(sw.start, freq)  # each pole's partner at the previous order, or -1
    has = near >= 0
    sf, sd, ss = (np.zeros(freq.size, dtype=bool) for _ in range(3))
    partner = near[has]
    sf[has] = _relative_change(freq[has], freq[partner], pairwise=False) <= freq_tol
    sd[has] = _relative_change(damp[has], damp[partner], pairwise=False) <= damping_tol
    ss[has] = np.abs(np.einsum("pk,pk->k", unit[:, has].conj(), unit[:, partner])) ** 2 >= mac_min
    stable = sf & sd & ss
    tracks = _cluster(order, freq, unit, stable, freq_tol, mac_min, min_orders)
    f_std, d_std = np.full(freq.size, np.nan), np.full(freq.size, np.nan)
    if uncertainty == "choice":
        _choice_std(ident, sw, done, stable, tracks, f_std, d_std, workers)
    elif uncertainty:  # the data's standard deviations of the stable poles (the others are not worth their cost)
        _data_std(ident, sw, done, stable, f_std, d_std, workers)
    modes = []
    for c in tracks:
        c = np.array(c)
        modes.append(StableMode(
            frequency_hz=float(freq[c].mean()), frequency_std_hz=float(freq[c].std()),
            damping_ratio=float(damp[c].mean()), damping_std=float(damp[c].std()),
            emac=float(gamma[c].mean()), mpc=float(mu[c].mean()), orders=tuple(int(x) for x in order[c]),
            pole_indices=tuple(int(x) for x in c), shape=shapes[:, c[-1]].copy(),
            data_frequency_std_hz=float(f_std[c[-1]]), data_damping_std=float(d_std[c[-1]])))
    modes.sort(key=lambda m: m.frequency_hz)
    return Stabilization(orders=np.array(done, dtype=int), order=order, mode_index=sw.mode_index,
                         frequency_hz=freq, damping_ratio=damp, emac=gamma, mpc=mu, contribution=contribution,
                         stable_frequency=sf, stable_damping=sd, stable_shape=ss, shapes=shapes, modes=tuple(modes),
                         frequency_std_hz=f_std, damping_std=d_std,
                         uncertainty_source=ident.uncertainty_source() if uncertainty else "")


def _data_std(ident, sw, done, wanted, f_std, d_std, workers) -> None:
    """Fill ``f_std``, ``d_std`` (n_poles,) of the poles ``wanted`` (bool) not computed yet, order by order."""
    def of_order(k):
        raw, perm, clusters = sw.raw[k]
        at = np.flatnonzero(wanted[sw.of(k)] & np.isnan(f_std[sw.of(k)]))
        if sw.known_std and at.size:  # the repeated-mode test's σ, computed with the order: the same numbers
            known_f, known_d = (x[perm[at]] for x in sw.known_std[k])
            have = np.isfinite(known_f) & np.isfinite(known_d)
            f_std[at[have] + sw.start[k]], d_std[at[have] + sw.start[k]] = known_f[have], known_d[have]
            at = at[~have]
        if at.size:
            f_std[at + sw.start[k]], d_std[at + sw.start[k]] = ident.mode_std(done[k], raw, perm[at], clusters)

    in_parallel(of_order, [k for k in range(len(done)) if wanted[sw.of(k)].any()], workers)


def _choice_std(ident, sw, done, stable, tracks, f_std, d_std, workers) -> None:
    """The σ era.choice.choose reads (``stabilization(..., uncertainty="choice")``), in two rounds: each track's last
    pole and its ⌊N/2⌋ lowest others (a median below UNCERTAIN_FRACTION of the frequency needs ⌊N/2⌋ + 1 of
    the N values below it, and then the median of any superset of them is below too), then every pole of the
    tracks where one of those is not below."""
    first = np.zeros(sw.order.size, dtype=bool)
    if done and done[-1] == ident.max_order:  # the exact-rank choice reads the top order's stable poles
        first[sw.of(len(done) - 1)] = stable[sw.of(len(done) - 1)]
    for c in tracks:  # c: increasing orders (the merged ones sorted), so c[-1] is the last pole
        first[c[-1]] = True
        first[c[:len(c) // 2]] = True
    _data_std(ident, sw, done, first, f_std, d_std, workers)
    rest = np.zeros(sw.order.size, dtype=bool)
    for c in tracks:
        known = f_std[c][first[c]]
        if not np.all(known < UNCERTAIN_FRACTION * sw.frequency_hz[c].mean()):  # NaN is not below either
            rest[c] = True
    _data_std(ident, sw, done, rest, f_std, d_std, workers)
