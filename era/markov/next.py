"""NExT: correlation functions of ambient response as free decays (James, Carne & Lauffer, 1995).

Under stationary white-noise excitation the cross-correlation R_ij(τ) = E[y_i(t+τ) y_j(t)] of every output i with
a reference channel j obeys the same homogeneous equations as a free decay: R(τ) = C A^{τ-1} G for τ ≥ 1, with
G = E[x(k+1) y_ref(k)ᵀ]. So the correlations with r reference channels are Markov parameters with r "inputs".
R(0) also holds the measurement-noise variance, so like the direct term it is dropped.
"""

from __future__ import annotations

import numpy as np

from ..data import ResponseData
from ..errors import DataError
from ..words import counted, listed
from .common import check_dt, kept_records, positive_int, records

#: Smallest FFT length of the block-wise correlation sum; blocks stay small (cache-friendly, bounded memory).
_MIN_FFT = 1 << 15


def correlations(y: np.ndarray, refs: np.ndarray, n_lags: int) -> tuple[np.ndarray, np.ndarray]:
    """Σ_t y(t+τ) y_ref(t)ᵀ for τ = 0..n_lags-1, shape (n_lags, p, r), and the number of terms per lag (n_lags,).

    Exact sums (no circular wrap, no window), by FFT over blocks so memory does not grow with the record.
    """
    n, p = y.shape
    total = np.zeros((n_lags, p, refs.shape[1]))
    n_fft = max(_MIN_FFT, 1 << int(np.ceil(np.log2(8 * n_lags))))
    block = n_fft - n_lags  # block + lags samples fit without circular wrap
    for s in range(0, n, block):
        lead = np.fft.rfft(y[s:s + block + n_lags], n=n_fft, axis=0)
        ref = np.fft.rfft(refs[s:s + block], n=n_fft, axis=0)
        total += np.fft.irfft(lead[:, :, None] * ref.conj()[:, None, :], n=n_fft, axis=0)[:n_lags]
    counts = np.maximum(n - np.arange(n_lags), 0)
    return total, counts


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
        each record's own correlations are kept too (ResponseData.records: σ from their scatter).
    dt : float
        Sampling interval in seconds.
    references : int, str or sequence of them, optional
        Reference channels (indices or names); default all channels. Pick channels that see every mode.
    n_lags : int, optional
        Correlation lags returned, τ = 1..n_lags; default min(N // 4, 2048).
    detrend : bool
        Remove each channel's mean first (sensor offsets would add a constant to every correlation).
    names, output_units : sequence of p str, optional
        Channel names and units.

    Returns
    -------
    ResponseData
        markov (n_lags, p, r) with markov[k, i, j] = R_ij((k+1)Δτ), the unbiased estimate
        Σ_t y_i(t+τ) y_j(t) / (N - τ) (units: output unit × reference unit); inputs are the reference names.
    """
    dt = check_dt(dt)
    ys = records(outputs, "outputs")
    p = ys[0].shape[1]
    idx = _reference_indices(references, names, p)
    n_total = min(len(y) for y in ys)
    n_lags = min(n_total // 4, 2048) if n_lags is None else positive_int(n_lags, "n_lags")
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
    # the σ of the modes (era.uncertainty.record_covariance, from MIN_RECORDS of them)
    lengths = [len(y) for y in ys]
    per_record = kept_records(np.stack(each)) if len(ys) >= 2 and min(lengths) >= 0.9 * max(lengths) else None
    labels = [str(n) for n in names] if names is not None else [f"y{i + 1}" for i in range(p)]
    units = None
    if output_units is not None:
        units = [str(u) for u in output_units]
        ref_units = [units[i] for i in idx]
    return ResponseData(markov=r[1:], dt=dt, outputs=labels, inputs=[f"ref {labels[i]}" for i in idx],
                        output_units=units, input_units=ref_units if units is not None else None,
                        records=per_record, meta={"zero_lag": r[0], "references": idx, "source": "next",
                              "conversions": [f"NExT (James et al. 1995): correlations with reference "
                                              f"{'channels' if len(idx) > 1 else 'channel'} "
                                              f"{listed([labels[i] for i in idx])} over "
                                              f"{counted(len(ys), 'record')}, lags 1..{n_lags}"
                                              + (", means removed" if detrend else "")]})
