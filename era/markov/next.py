"""NExT: correlation functions of ambient response as free decays (James, Carne & Lauffer, 1995).

Under stationary white-noise excitation the cross-correlation R_ij(τ) = E[y_i(t+τ) y_j(t)] of every output i with
a reference channel j obeys the same homogeneous equations as a free decay: R(τ) = C A^{τ-1} G for τ ≥ 1, with
G = E[x(k+1) y_ref(k)ᵀ]. So the correlations with r reference channels are Markov parameters with r "inputs".
R(0) also holds the measurement-noise variance, so like the direct term it is dropped.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import find_peaks, welch

from ..core.data import ResponseData
from ..errors import DataError
from ..words import counted, listed
from .common import check_dt, kept_records, positive_int, records

#: Smallest FFT length of the block-wise correlation sum; blocks stay small (cache-friendly, bounded memory).
_MIN_FFT = 1 << 15
#: Default lags: about this many periods of the lowest resonance (default_lags), within [MIN_LAGS, MAX_LAGS].
LAG_PERIODS = 4.0
MIN_LAGS = 40
MAX_LAGS = 2048
#: A resonance stands this many times above the spectrum's median (a 10 × weaker mode's peak still does).
LOW_PEAK_FACTOR = 10.0
#: One record is cut into this many consecutive segments whose correlations are kept beside the whole record's
#: (ResponseData.records): their scatter gives σ (era.core.uncertainty.record_covariance), as the blocks of
#: covariance-driven SSI (Döhler & Mevel 2013). 20 keeps the σ's own relative error near 1/√38 = 16 % and each
#: segment long (5 minutes at 25 Hz: 375 samples, against lags of a few periods).
SEGMENTS = 20


def correlations(y: np.ndarray, refs: np.ndarray, n_lags: int, start: int = 0,
                 stop: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Σ_t y(t+τ) y_ref(t)ᵀ over the reference samples t in [start, stop) (default all) for τ = 0..n_lags-1, shape
    (n_lags, p, r), and the number of terms per lag (n_lags,); y(t+τ) may reach past ``stop`` (to the record's
    end), so the sums of consecutive segments add up to the whole record's sums exactly.

    Exact sums (no circular wrap, no window), by FFT over blocks so memory does not grow with the record.
    """
    n, p = y.shape
    stop = n if stop is None else min(int(stop), n)
    total = np.zeros((n_lags, p, refs.shape[1]))
    n_fft = max(_MIN_FFT, 1 << int(np.ceil(np.log2(8 * n_lags))))
    block = n_fft - n_lags  # block + lags samples fit without circular wrap
    for s in range(int(start), stop, block):
        lead = np.fft.rfft(y[s:s + block + n_lags], n=n_fft, axis=0)
        ref = np.fft.rfft(refs[s:min(s + block, stop)], n=n_fft, axis=0)
        total += np.fft.irfft(lead[:, :, None] * ref.conj()[:, None, :], n=n_fft, axis=0)[:n_lags]
    counts = np.maximum(np.minimum(stop, n - np.arange(n_lags)) - int(start), 0)
    return total, counts


def lowest_mode_hz(y: np.ndarray, dt: float) -> float | None:
    """The lowest frequency (Hz) where the response has a resonance, or None: the lowest peak of the channels'
    mean normalised Welch spectrum that stands LOW_PEAK_FACTOR × above the spectrum's median (the broadband floor)
    and as many times above the valleys beside it (its prominence: a skirt or a wiggle of the estimate is not a
    peak; a lightly damped mode, even 10 × weaker than the strongest, is)."""
    n = y.shape[0]
    nperseg = int(min(n // 8, 4096))
    if nperseg < 16:
        return None
    f, pxx = welch(y, fs=1.0 / dt, nperseg=nperseg, axis=0)
    pxx = pxx / np.maximum(pxx.sum(axis=0, keepdims=True), 1e-300)
    level = np.log(np.maximum(pxx.mean(axis=1), 1e-300))
    factor = np.log(LOW_PEAK_FACTOR)
    peaks, _ = find_peaks(level, height=np.median(level) + factor, prominence=factor)
    peaks = peaks[peaks >= 2]  # the first bins hold the trend and the window's leakage of the mean
    return float(f[peaks[0]]) if peaks.size else None


def default_lags(y: np.ndarray, dt: float) -> int:
    """Correlation lags for ERA: about LAG_PERIODS periods of the lowest resonance (:func:`lowest_mode_hz`), at
    least MIN_LAGS, at most min(N // 4, MAX_LAGS).

    Why short: the estimation error of a correlation function does not decay with the lag (for a lightly damped
    mode it is a random oscillation at the mode's own frequency, of about constant amplitude), so lags past a
    mode's decay hold its noise, not its signal, and a realization fitted to them reads that noise as a mode that
    decays slower: damping 15-30 % low on fast-decaying or weak modes with 2048 lags, within its own σ with a
    few periods of the lowest mode (tests/bench/bench_oma_uncertainty.py). Covariance-driven SSI uses as few
    lags for the same reason.
    """
    n = y.shape[0]
    f_low = lowest_mode_hz(y, dt)
    lags = MIN_LAGS if f_low is None else int(np.ceil(LAG_PERIODS / (f_low * dt)))
    return int(max(MIN_LAGS, min(lags, n // 4, MAX_LAGS)))


def segment_sums(y: np.ndarray, refs: np.ndarray, n_lags: int, n_segments: int) -> tuple[np.ndarray, np.ndarray]:
    """The correlation sums of ``n_segments`` consecutive segments of one record, (n_segments, n_lags, p, r), and
    their counts (n_segments, n_lags): :func:`correlations` over each segment's reference samples."""
    edges = np.linspace(0, y.shape[0], n_segments + 1).round().astype(int)
    parts = [correlations(y, refs, n_lags, a, b) for a, b in zip(edges[:-1], edges[1:])]
    return np.stack([s for s, _ in parts]), np.stack([c for _, c in parts])


def _reference_indices(references, names, p: int) -> list[int]:
    if references is None:
        return list(range(p))
    refs = [references] if isinstance(references, (int, np.integer, str)) else list(references)
    out = []
    for r in refs:
        if isinstance(r, str):
            if names is None or r not in list(names):
                raise DataError(f"Reference channel {r!r} is not among the output names {list(names or [])}.")
            out.append(list(names).index(r))
        elif isinstance(r, (int, np.integer)) and -p <= r < p:
            out.append(int(r) % p)
        else:
            raise DataError(f"Reference {r!r} is not a channel: give indices 0..{p - 1} or channel names.")
    if not out or len(set(out)) != len(out):
        raise DataError(f"`references` must name distinct channels, got {references!r}.")
    return out


def markov_from_ambient(outputs, dt, references=None, *, n_lags: int | None = None, detrend: bool = True,
                        names=None, output_units=None) -> ResponseData:
    """Cross-correlation functions of ambient (output-only) records, as free decays for ERA (NExT).

    Parameters
    ----------
    outputs : (N, p) array or list of (N_r, p) arrays
        Response records (e.g. acceleration in m/s²) under broadband, stationary excitation; a list holds several
        records of the same channels, whose correlation sums are pooled; when their lengths agree within 10 %,
        each record's own correlations are kept too (ResponseData.records: σ from their scatter). One record is
        cut into SEGMENTS consecutive segments whose correlations are kept instead (σ from their scatter; the
        segments' sums add up to the record's exactly).
    dt : float
        Sampling interval in seconds.
    references : int, str or sequence of them, optional
        Reference channels (indices or names); default all channels. Pick channels that see every mode.
    n_lags : int, optional
        Correlation lags returned, τ = 1..n_lags; default :func:`default_lags` of the first record (about four
        periods of its lowest resonance: longer lags bias damping low).
    detrend : bool, optional
        Remove each channel's mean first (sensor offsets would add a constant to every correlation).
    names : sequence of p str, optional
        Channel names (default y1..yp).
    output_units : sequence of p str, optional
        Channel units.

    Returns
    -------
    ResponseData
        markov (n_lags, p, r) with markov[k, i, j] = R_ij((k+1)Δτ), the unbiased estimate
        Σ_t y_i(t+τ) y_j(t) / (N - τ) (units: output unit × reference unit); inputs are the reference names.

    Raises
    ------
    era.DataError
        For a reference that is not a channel (or named twice), or records too short for ``n_lags``.

    References
    ----------
    James, G. H., Carne, T. G. and Lauffer, J. P. (1995), The natural excitation technique (NExT) for modal
    parameter extraction from operating structures, Modal Analysis 10(4), 260-277.

    Examples
    --------
    Three sensors on a structure with modes at 2 and 5 Hz under white noise, 80 s at 50 Hz:

    >>> from era.examples.synthetic import ambient_response
    >>> records, truth = ambient_response([2.0, 5.0], [0.02, 0.02], 3, 4000, 0.02, seed=0)
    >>> data = era.markov_from_ambient(records, 0.02, references=[0])
    >>> data.markov.shape, data.inputs, data.n_records
    ((100, 3, 1), ('ref y1',), 9)
    >>> print(np.round(era.analyse(data, max_order=30).model.frequency_hz, 1))
    [2. 5.]
    """
    dt = check_dt(dt)
    ys = records(outputs, "outputs")
    p = ys[0].shape[1]
    idx = _reference_indices(references, names, p)
    n_total = min(len(y) for y in ys)
    n_lags = default_lags(ys[0], dt) if n_lags is None else positive_int(n_lags, "n_lags")
    if n_lags < 2 or n_lags + 1 > n_total // 2:
        raise DataError(f"Too few samples for NExT: {n_total} samples per record cannot give {n_lags} reliable "
                        "correlation lags (at most half the record); record longer or ask for fewer lags.")
    total = np.zeros((n_lags + 1, p, len(idx)))
    counts = np.zeros(n_lags + 1)
    each = []
    for y in ys:
        if detrend:
            y = y - y.mean(axis=0)
        s, c = correlations(y, y[:, idx], n_lags + 1)
        total += s
        counts += c
        each.append(s[1:] / np.maximum(c[1:], 1)[:, None, None])
    r = total / counts[:, None, None]
    # comparable records (lengths within 10 %: about equal variances) each give one estimate; their scatter is
    # the σ of the modes (era.core.uncertainty.record_covariance, from MIN_RECORDS of them)
    lengths = [len(y) for y in ys]
    per_record = kept_records(np.stack(each)) if len(ys) >= 2 and min(lengths) >= 0.9 * max(lengths) else None
    from ..core.uncertainty import MIN_RECORDS  # as common.kept_records: the σ's rule, read where it is used

    # one record: its segments (each at least 4 × the lags long, so its sums are mostly its own samples)
    n_segments = min(SEGMENTS, n_total // max(4 * (n_lags + 1), 1))
    segmented = len(ys) == 1 and n_segments >= MIN_RECORDS
    if segmented:
        y = ys[0] - ys[0].mean(axis=0) if detrend else ys[0]
        sums, cnt = segment_sums(y, y[:, idx], n_lags + 1, n_segments)
        per_record = kept_records(sums[:, 1:] / np.maximum(cnt[:, 1:], 1)[:, :, None, None])
    labels = [str(n) for n in names] if names is not None else [f"y{i + 1}" for i in range(p)]
    units = None
    if output_units is not None:
        units = [str(u) for u in output_units]
        ref_units = [units[i] for i in idx]
    return ResponseData(markov=r[1:], dt=dt, outputs=labels, inputs=[f"ref {labels[i]}" for i in idx],
                        output_units=units, input_units=ref_units if units is not None else None,
                        records=per_record, meta={"zero_lag": r[0], "references": idx, "source": "next",
                              "records_are": "segments" if segmented else "records",
                              "conversions": [f"NExT (James et al. 1995): correlations with reference "
                                              f"{'channels' if len(idx) > 1 else 'channel'} "
                                              f"{listed([labels[i] for i in idx])} over "
                                              f"{counted(len(ys), 'record')}, lags 1..{n_lags}"
                                              + (", means removed" if detrend else "")]})
