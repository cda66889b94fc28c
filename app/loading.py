"""Uploaded files -> (ResponseData, Geometry | None, source) through era.load: every format era/io reads, one file
or several read as one dataset, with what the files cannot say given as options (dt, orientation, variable, ...)."""

from __future__ import annotations

import io

import era

#: What the records are, as the person may say it (era.io.records.to_response); "auto" lets the loader guess.
KINDS = ("auto", "pulse", "decay", "frf", "io", "ambient")
#: The options of era.load that change how files are read (era.io.read's), not what is done with the records.
READING = ("format", "dt", "orientation", "variable", "group", "resample")
#: Files in one upload at most (one per hammer hit or reference; a roving test of 64 points fits).
MAX_FILES = 256


def check_files(files: list[tuple[str, bytes]]) -> None:
    """DataError for an upload with no file, too many files, or an empty file."""
    if not files:
        raise era.DataError("No file in the upload: add at least one file part named `file`.")
    if len(files) > MAX_FILES:
        raise era.DataError(f"{len(files)} files in one upload; at most {MAX_FILES} are read as one dataset.")
    for name, blob in files:
        if not blob:
            raise era.DataError(f"{name!r} is empty: choose a file with the measured records.")


def named_sources(files: list[tuple[str, bytes]]) -> list:
    """File objects of uploaded (name, bytes), each named so that era names the file in its messages."""
    sources = []
    for name, blob in files:
        src = io.BytesIO(blob)
        src.name = name
        sources.append(src)
    return sources


def read_key(upload_id: str, options: dict, max_bytes: int | None) -> tuple:
    """The key of an upload read with ``options`` (the import step's): equal for a preview and a dataset that read
    the files the same way, whatever else they choose."""
    said = {k: v for k, v in options.items() if v is not None and v is not False}
    return (upload_id, max_bytes) + tuple((k, repr(said.get(k))) for k in READING)


def load_upload(files: list[tuple[str, bytes]], kind: str = "auto", max_bytes: int | None = None, read=None,
                **options):
    """Parse uploaded files (name, bytes) as one dataset. ``options`` go to era.load (dt, format, orientation,
    variable, group, frf_sign, start_sample, drop, forces, references, band_hz; None means not given);
    ``max_bytes`` bounds what the files inflate to (era.load's, ERA_MAX_UPLOAD_MB). ``read``: the files as already
    read with the same reading options (era.io.Read, a preview's), converted without reading them again. Raises an
    era.EraError (shown to the person as is; era.TooLargeError: 413)."""
    if kind not in KINDS:
        raise era.DataError(f"`kind` must be one of {', '.join(KINDS)}, got {kind!r}.", option="kind")
    sources = named_sources(files)  # checked on arrival (routes/datasets.read_parts)
    given = {k: v for k, v in options.items() if v is not None}
    try:
        if read is not None:
            ds = era.io.convert(read, kind=kind, **{k: v for k, v in given.items() if k not in READING})
        else:
            ds = era.load(sources if len(sources) > 1 else sources[0],
                          name=files[0][0] if len(files) == 1 else None, kind=kind, max_bytes=max_bytes, **given)
    except era.DataError as exc:
        if "band_hz" in given and "argument 'band_hz'" in str(exc):  # the conversion of time records takes none
            raise era.DataError(f"{files[0][0]}: a band applies to FRF records only; leave it out for these "
                                "records.", option="band_hz") from None
        raise
    if ds.data is None:
        raise era.DataError(f"{files[0][0]}: the file holds geometry or modes but no response records; upload the "
                            "measured responses.")
    return ds.data, ds.geometry, dict(ds.source or {})


def channel_list(text: str | None, option: str) -> list[int] | None:
    """Channel positions from a form field such as "0, 2" (None or blank: not given)."""
    if text is None or not text.strip():
        return None
    try:
        return [int(x) for x in text.replace(";", ",").split(",") if x.strip()]
    except ValueError:
        raise era.DataError(f"`{option}` lists channel positions (0-based), comma-separated, e.g. 0,2; got {text!r}.",
                            option=option) from None


def band(text: str | None) -> list[float] | None:
    """The band [low, high] Hz from a form field such as "65, 1000" (None or blank: not given)."""
    if text is None or not text.strip():
        return None
    try:
        low, high = (float(x) for x in text.replace(";", ",").split(","))
    except ValueError:
        raise era.DataError(f"`band_hz` is two frequencies in Hz, low,high, e.g. 65,1000; got {text!r}.",
                            option="band_hz") from None
    return [low, high]


#: A stored dataset's arrays (pulse responses and records, float64) at most this many times ERA_MAX_UPLOAD_MB:
#: 16-bit samples read as float64 take 4 times their bytes.
STORED_FACTOR = 4


def check_stored(data: era.ResponseData, max_upload_bytes: int) -> None:
    """era.TooLargeError when the dataset made from an upload would be stored larger than STORED_FACTOR × the
    upload limit (a conversion that multiplies the data must not fill the disk)."""
    nbytes = data.markov.nbytes + (data.records.nbytes if data.records is not None else 0)
    limit = STORED_FACTOR * max_upload_bytes
    if nbytes > limit:
        raise era.TooLargeError(f"The dataset would hold {nbytes / 2**20:,.1f} MB of pulse responses, above "
                                f"{STORED_FACTOR} × the upload limit ({limit / 2**20:,.0f} MB). Send fewer channels "
                                "or samples.")


def new_dataset(cache, files: list[tuple[str, bytes]], kind: str, options: dict, upload_id: str | None = None
                ) -> dict:
    """Read ``files`` with ``options`` into a stored dataset; returns its summary (schemas.Dataset), whose
    ``source.options`` keeps what the person said (shown in the summary, frozen into reports). The files of a
    staged upload (``upload_id``) that its preview read the same way are not read again (``cache.reads``)."""
    from .payloads import dataset_summary

    got = None if upload_id is None else cache.reads.get(read_key(upload_id, options, cache.settings.max_upload_bytes))
    data, geometry, source = load_upload(files, kind, cache.settings.max_upload_bytes, got, **options)
    check_stored(data, cache.settings.max_upload_bytes)
    name = files[0][0] if len(files) == 1 else f"{files[0][0]} + {len(files) - 1} more"
    said = {k: v for k, v in options.items() if v is not None}
    if kind != "auto":
        said["kind"] = kind
    source = dict(source, file=name if len(files) == 1 else [n for n, _ in files],
                  bytes=sum(len(b) for _, b in files), options=said)
    return cache.add_dataset(data, geometry, name, dataset_summary(data, geometry, name, cache.settings, source))
