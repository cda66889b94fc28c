"""What a file holds before it becomes Markov parameters, and the choice of conversion.

Every reader returns :class:`Records`; :func:`to_response` turns them into an :class:`era.ResponseData` with the
builder that fits the test (era.markov): FRFs by inverse FFT, impulse responses and free decays from their start,
force-response records by OKID, output-only records by NExT.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.data import ResponseData
from ..errors import DataError
from ..markov import markov_from_ambient, markov_from_decay, markov_from_frf, markov_from_io
from ..words import counted

KINDS = ("frf", "pulse", "decay", "io", "ambient")
#: Fewest samples from which any identification is attempted (a 2 × 2 block Hankel needs 4 at the least).
MIN_SAMPLES = 8


@dataclass(frozen=True, eq=False)
class Records:
    """Data as read from a file.

    domain : "time" (channel histories), "pulse" (impulse responses / Markov parameters, (N, p, m)) or
        "frequency" (FRFs, (K, p, m) complex).
    values : list of (N_r, c) float arrays for "time" (one per record/test); a one-element list holding the
        (N, p, m) array for "pulse" and "frequency".
    step : Δτ in s or Δf in Hz.  start : abscissa of the first sample (s or Hz; negative = pre-trigger).
    outputs, output_units : names and units of the c channels ("time") or p outputs.
    inputs, input_units : names and units of the m references ("pulse", "frequency").
    force : (c,) bool, True for channels that measure excitation ("time" only).
    nodes : (c or p,) int node label of each channel (0 = unknown); directions : (c or p, 3) unit vectors.
    frf_type : "accelerance", "mobility", "receptance" or None.
    described : list of str, what was read (for Dataset.source).
    points : where the channels are, for ResponseData.meta (setups.points: output_points, output_signs, input_points,
        input_signs; and proposed_band_hz, a band the test's setup proposes), or None; for time histories also
        channel_points (c,), a point label per channel ("" unknown), the person's (era.io.choices.choose), split by
        :func:`to_response` into the inputs' and outputs' points.
    conversions : list of str, what the reader did to the values (a resampled clock), for Dataset.source.
    named : False when the channel names were made up from the file name (an .npy file names nothing): files of
        one dataset then match by channel count, and the first file's names are used.
    """

    domain: str
    values: list
    step: float
    start: float
    outputs: tuple
    output_units: tuple
    inputs: tuple = ()
    input_units: tuple = ()
    force: np.ndarray | None = None
    nodes: np.ndarray | None = None
    directions: np.ndarray | None = None
    frf_type: str | None = None
    described: list = field(default_factory=list)
    named: bool = True
    points: dict | None = None
    conversions: list = field(default_factory=list)


#: Units a force channel is written in (lower case).
FORCE_UNITS = frozenset({"n", "kn", "lbf", "lb", "kgf"})
#: Words in a channel's name that say it is the force.
FORCE_WORDS = ("force", "hammer", "impact")


def force_channels(names, units) -> np.ndarray:
    """(n,) bool: the channels whose unit is a force unit or whose name says force, hammer or impact."""
    return np.array([str(u).lower() in FORCE_UNITS or any(w in str(n).lower() for w in FORCE_WORDS)
                     for n, u in zip(names, units)], bool)


def hammer_channel(y: np.ndarray) -> int | None:
    """The one channel of ``y`` (N, c) that is a short pulse (99 % of its energy within 1 % of the record around
    its peak: a hammer's force) when the others are not; else None."""
    if y.shape[1] < 2 or len(y) < 200:
        return None
    half = max(len(y) // 200, 1)
    pulses = []
    for c in range(y.shape[1]):
        col = np.asarray(y[:, c], dtype=float)
        total = float(col @ col)
        k = int(np.argmax(np.abs(col)))
        window = col[max(k - half, 0):k + half]
        pulses.append(total > 0 and float(window @ window) >= 0.99 * total)
    return pulses.index(True) if sum(pulses) == 1 else None


def guess_kind(rec: Records) -> str:
    """The conversion a file's records call for when the caller does not say (see :func:`to_response`)."""
    if rec.domain == "frequency":
        return "frf"
    if rec.domain == "pulse":
        return "pulse"
    if rec.force is not None and rec.force.any():
        return "io"
    # a free decay dies out within the record; ambient response does not
    y = rec.values[0]
    tenth = max(len(y) // 10, 1)
    head, tail = np.sqrt(np.mean(y[:tenth] ** 2)), np.sqrt(np.mean(y[-tenth:] ** 2))
    return "decay" if tail < 0.1 * head else "ambient"


def _time_points(labels: np.ndarray, kind: str, force: np.ndarray | None) -> dict:
    """ResponseData.meta's points of time records converted as ``kind``: with OKID ("io") the force channels'
    labels are the inputs' points (where the structure was struck or driven) and the others the outputs'; the
    outputs' only otherwise (NExT's references and a decay's records are no places the structure was driven)."""
    if kind == "io" and force is not None:
        return {"output_points": tuple(labels[~force]), "input_points": tuple(labels[force])}
    return {"output_points": tuple(labels)}


def to_response(rec: Records, kind: str = "auto", **options) -> tuple[ResponseData, str]:
    """Markov parameters from records. Returns (ResponseData, kind used).

    kind: "auto" (guess: FRF records -> "frf"; impulse responses -> "pulse"; time records with a force channel ->
    "io"; time records that decay ten-fold -> "decay"; otherwise "ambient"), or one of
    "frf" (:func:`era.markov_from_frf`), "pulse" (impulse responses from t = 0, Y(0) dropped),
    "decay" (:func:`era.markov.markov_from_decay`, each record one initial condition), "io" (OKID,
    :func:`era.markov_from_io`, force channels as inputs), "ambient" (NExT, :func:`era.markov_from_ambient`).
    ``options`` go to that function.
    """
    kind = guess_kind(rec) if kind == "auto" else kind
    force = None
    if kind not in KINDS:
        raise DataError(f"`kind` must be 'auto' or one of {KINDS}, got {kind!r}.", option="kind")
    wrong = {"frf": "frequency", "pulse": "pulse"}
    if kind in wrong and rec.domain != wrong[kind]:
        raise DataError(f"The file holds {rec.domain} records; they cannot be converted as {kind!r}.", option="kind")
    if kind not in wrong and rec.domain != "time":
        raise DataError(f"The file holds {rec.domain} records; {kind!r} needs time histories.", option="kind")
    units = list(rec.output_units) if rec.output_units else None
    if kind == "frf":
        f = rec.start + rec.step * np.arange(rec.values[0].shape[0])
        frf, note = _sign_convention(rec.values[0], options.pop("frf_sign", "auto"))
        data = markov_from_frf(f, frf, frf_type=options.pop("frf_type", rec.frf_type),
                               outputs=rec.outputs, inputs=rec.inputs, output_units=units,
                               input_units=list(rec.input_units) or None, **options)
    elif kind == "pulse":
        y = rec.values[0]
        zero = int(round(-rec.start / rec.step)) if rec.start < 0 else 0
        start = options.pop("start", zero + 1)  # the sample after t = 0: Y(0) = D is dropped
        data = markov_from_decay(y, rec.step, start=start, outputs=rec.outputs, inputs=rec.inputs,
                                 output_units=units, input_units=list(rec.input_units) or None, **options)
    else:
        _check_time(rec)
        if kind == "decay":
            n = min(len(v) for v in rec.values)
            stack = np.stack([v[:n] for v in rec.values], axis=2)
            inputs = [f"record {i + 1}" for i in range(len(rec.values))]
            data = markov_from_decay(stack, rec.step, outputs=rec.outputs, inputs=inputs, output_units=units,
                                     **options)
        elif kind == "io":
            force = rec.force if rec.force is not None else np.zeros(len(rec.outputs), bool)
            if "inputs" in options:  # explicit input channels, by index or name
                force = np.zeros(len(rec.outputs), bool)
                for c in options.pop("inputs"):
                    force[rec.outputs.index(c) if isinstance(c, str) else int(c)] = True
            if not force.any() or force.all():
                raise DataError("OKID needs both excitation and response channels; none of the channels is marked "
                                "as force (unit N/lbf or name 'force'). Say which with forces=[channel, ...].", option="forces")
            names = np.array(rec.outputs)
            u_units = [rec.output_units[i] for i in np.flatnonzero(force)] if rec.output_units else None
            y_units = [rec.output_units[i] for i in np.flatnonzero(~force)] if rec.output_units else None
            data = markov_from_io([v[:, force] for v in rec.values], [v[:, ~force] for v in rec.values], rec.step,
                                  output_names=list(names[~force]), input_names=list(names[force]),
                                  output_units=y_units, input_units=u_units, **options)
        else:
            data = markov_from_ambient(list(rec.values), rec.step, options.pop("references", None),
                                       names=rec.outputs, output_units=units, **options)
    if kind == "frf" and note:
        data.meta["conversions"].insert(0, note)
    if rec.points and kind in ("frf", "pulse"):  # the channels stay as read: their points hold
        data.meta.update(rec.points)
    elif rec.points and rec.points.get("channel_points") and any(rec.points["channel_points"]):
        data.meta.update(_time_points(np.array(rec.points["channel_points"], dtype=object), kind, force))
    if data.n_samples < MIN_SAMPLES:
        raise DataError(f"Only {data.n_samples} pulse-response samples; ERA needs at least {MIN_SAMPLES} (and "
                        "usually hundreds). Record longer or at a higher sampling rate.")
    return data, kind


def _sign_convention(frf: np.ndarray, sign: str) -> tuple[np.ndarray, str | None]:
    """FRFs (K, p, m) in ERA's convention (response = H e^{+iωt} for a force e^{+iωt}), and a note when converted.

    sign: "+" (the file uses that convention), "-" (the other one, e^{-iωt}: H is conjugated) or "auto": the
    impulse response of a real structure is causal, so the inverse FFT of FRFs in the other convention puts the
    decay at the end of the record (negative times) instead of at its start; the energy in the first and last
    quarters decides (a 100:1 contrast and more on measured FRFs), and a contrast under 2:1 leaves them as they are.
    """
    if sign not in ("auto", "+", "-"):
        raise DataError(f"`frf_sign` must be 'auto', '+' (response = H·e^(+iωt), the usual convention) or '-' "
                        f"(e^(-iωt): the FRFs are conjugated), got {sign!r}.")
    if sign == "+":
        return frf, None
    if sign == "-":
        return frf.conj(), "FRFs conjugated: the e^(-iωt) sign convention was given (frf_sign='-')"
    h = np.fft.irfft(frf, axis=0)
    energy = (h ** 2).reshape(len(h), -1).sum(axis=1)
    quarter = max(len(energy) // 4, 1)
    early, late = energy[1:quarter].sum(), energy[-quarter:].sum()
    if late > 2 * early:
        return frf.conj(), (f"FRFs conjugated: their impulse responses ran backwards in time (energy "
                            f"{late / max(early, 1e-300):.3g}× larger at the end), the mark of the e^(-iωt) sign "
                            "convention; say frf_sign='+' to keep them as they are")
    return frf, None


def _check_time(rec: Records) -> None:
    for r, v in enumerate(rec.values):
        if len(v) < MIN_SAMPLES:
            raise DataError(f"Record {r + 1} has {len(v)} samples; at least {MIN_SAMPLES} are needed for any "
                            "identification.")


def check_finite(values: np.ndarray, where: str, row_offset: int = 0, row_name: str = "sample") -> None:
    """DataError naming the first NaN/inf: ``where`` says the file/record, rows are counted from row_offset."""
    bad = ~np.isfinite(values)
    if bad.any():
        first = np.argwhere(bad)[0]
        col = f", column {first[1] + 1}" if values.ndim > 1 else ""
        raise DataError(f"{where}: {counted(bad.sum(), 'NaN or infinite value')}, the first at {row_name} "
                        f"{int(first[0]) + row_offset}{col}. Remove or interpolate them, then load again.")


def merge_records(records: list[Records], labels: list[str]) -> Records:
    """Several files of the same channels as several records (one or more per file).

    The files must hold the same channels in the same units, sampled with the same step, and records of the same
    length; DataError names the file that differs and the first file.
    """
    first = records[0]
    if len(records) == 1:
        return first
    n = len(first.values[0])
    for r, lab in zip(records[1:], labels[1:]):
        if (r.outputs if r.named and first.named else len(r.outputs)) != \
                (first.outputs if r.named and first.named else len(first.outputs)):
            raise DataError(f"{lab}: channels {list(r.outputs)} differ from those of {labels[0]} "
                            f"{list(first.outputs)}; every file must hold the same channels.")
        if abs(r.step - first.step) > 1e-6 * first.step:
            raise DataError(f"{lab}: sampled every {r.step:g} s but {labels[0]} every {first.step:g} s; the files of "
                            "one dataset must share the sampling rate.")
        if tuple(r.output_units) != tuple(first.output_units):
            raise DataError(f"{lab}: units {list(r.output_units)} but {labels[0]} has {list(first.output_units)}; "
                            "the files of one dataset must measure in the same units.")
        lengths = {len(v) for v in r.values}
        if lengths != {n}:
            raise DataError(f"{lab}: records of {sorted(lengths)} samples but {labels[0]} has {n}; the files of one "
                            "dataset must be equally long (cut them to the same length).")
    return Records(domain="time", values=[v for r in records for v in r.values], step=first.step,
                   start=first.start, outputs=first.outputs, output_units=first.output_units, force=first.force,
                   nodes=first.nodes, directions=first.directions,
                   described=[d for r in records for d in r.described],
                   conversions=[c for r in records for c in r.conversions])
