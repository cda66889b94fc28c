"""The import step: uploaded files are kept as they came (store.staging), shown as read (era.io.preview.preview)
with the person's options, and become a dataset only when the person says so.

Every function is plain: files in ((name, bytes)), dicts out (schemas.Import, schemas.ImportPreview).
"""

from __future__ import annotations

import re

import numpy as np

import era
from era.io.preview import preview

from .loading import named_sources, read_key
from .payloads import floats

#: The options era.load takes from the import step (schemas.ImportOptions without ``kind``).
READ_OPTIONS = ("dt", "format", "orientation", "variable", "group", "resample", "frf_sign", "start_sample", "drop",
                "forces", "references", "band_hz", "points")
#: Options of the conversion to pulse responses only: the preview shows the records as read, without them.
CONVERSION_OPTIONS = ("references", "band_hz", "points")


#: The library's words (parameters of era.load) -> the import step's (its controls' labels, units a person types).
_PAGE_WORDS = (
    (re.compile(r"give the sample rate \(dt=\.\.\.\)"), "give the sample rate (Hz)"),
    (re.compile(r"say orientation='rows' or 'columns' if that is wrong"),
     "choose rows or columns under “Channels are in” if that is wrong"),
    (re.compile(r"Leave orientation out\."), "Leave “Channels are in” as detected."),
    (re.compile(r"Say which with forces=\[channel, \.\.\.\]\."), "Mark it “force” among the channels' roles."),
    (re.compile(r"Write them as UFF 58 with their frequency axis \(pyuff's write_sets, as its README shows\)"),
     "Export them as UFF 58 (with their frequency axis) from the analyser's software"),
    (re.compile(r"`start_sample`"), "“Start at sample”"),
    (re.compile(r"`orientation`"), "“Channels are in”"),
    (re.compile(r"`forces`"), "the force role"),
    (re.compile(r"`drop`"), "leaving channels out"),
    (re.compile(r"`points` is \{channel: point label\}, e\.g\. \{0: '4X'\}\."), "Type each channel's point, e.g. 4X."),
    (re.compile(r"`points`"), "the channels' points"),
    (re.compile(r"`kind`"), "“The records are”"),
    (re.compile(r"`frf_sign`"), "“FRF sign convention”"),
    (re.compile(r"`variable`"), "“Array”"),
    (re.compile(r"`group`"), "“TDMS group”"),
)


def page_words(text: str) -> str:
    """A refusal of era.load as the import step says it: its controls, not the library's parameters."""
    for pattern, words in _PAGE_WORDS:
        text = pattern.sub(words, text)
    return text


def in_page_words(exc: era.EraError) -> era.EraError:
    """The same refusal (type and option kept) in the import step's words."""
    try:
        out = type(exc)(page_words(str(exc)), option=getattr(exc, "option", None))
    except TypeError:  # an error type with other arguments: keep it as it is
        return exc
    for k, v in vars(exc).items():
        setattr(out, k, v)
    return out


def given(options: dict) -> dict:
    """The options the person set (None left out; ``kind`` "auto" too)."""
    out = {k: v for k, v in options.items() if v is not None and v is not False and k in READ_OPTIONS + ("kind",)}
    if out.get("kind") == "auto":
        del out["kind"]
    return out


def preview_json(files: list[tuple[str, bytes]], options: dict, max_points: int,
                 max_bytes: int | None = None, reads=None, upload_id: str | None = None
                 ) -> tuple[dict, str | None, str | None]:
    """(schemas.ImportPreview, problem, its option) of ``files`` read with ``options``: the problem is what still
    stops the import although the files could be shown (no sampling interval). Raises era.EraError when they cannot
    be read at all; ``max_bytes`` bounds what they inflate to (era.load's). ``reads`` (app.cache.LRU) keeps the
    files as read under :func:`read_key` of ``upload_id``, for the dataset made from them next."""
    reading = {k: v for k, v in given(options).items() if k in READ_OPTIONS and k not in CONVERSION_OPTIONS}
    sources = named_sources(files)
    pv = preview(sources if len(sources) > 1 else sources[0], name=files[0][0] if len(files) == 1 else None,
                 max_points=max_points, max_bytes=max_bytes,
                 **{k: v for k, v in reading.items() if k != "frf_sign"})
    if reads is not None and upload_id is not None and pv.read is not None:
        reads.put(read_key(upload_id, options, max_bytes), pv.read)
    time_like = pv.domain != "frequency"
    x_label = ("sample" if pv.step is None else "time (s)") if time_like else "frequency (Hz)"
    return {
        "files": pv.files, "format": pv.format, "domain": pv.domain, "dt": pv.step,
        "sample_rate_hz": (1.0 / pv.step) if pv.step and time_like else None, "start": float(pv.start),
        "channels": [vars(c) for c in pv.channels], "references": pv.references, "n_records": pv.n_records,
        "n_samples": pv.n_samples, "kind": pv.kind, "described": pv.described, "x": floats(pv.x),
        "x_label": x_label, "traces": floats(np.asarray(pv.traces)), "geometry_nodes": pv.geometry_nodes,
        "proposed_band_hz": None if pv.proposed_band_hz is None else list(pv.proposed_band_hz),
    }, pv.problem and page_words(pv.problem), pv.problem_option


def import_json(upload_id: str, files: list[tuple[str, bytes]], options: dict, max_points: int,
                max_bytes: int | None = None, reads=None) -> dict:
    """schemas.Import: the preview, or the reason there is none, with the option that fixes it. Files that inflate
    past ``max_bytes`` raise era.TooLargeError (413: no option fixes them). ``reads``: as in :func:`preview_json`."""
    out = {"id": upload_id, "files": [n for n, _ in files], "bytes": sum(len(b) for _, b in files),
           "options": given(options), "preview": None, "error": None, "option": None}
    try:
        out["preview"], out["error"], out["option"] = preview_json(files, options, max_points, max_bytes, reads,
                                                                      upload_id)
    except era.TooLargeError:
        raise
    except era.EraError as exc:
        out["error"], out["option"] = page_words(str(exc)), getattr(exc, "option", None)
    return out

