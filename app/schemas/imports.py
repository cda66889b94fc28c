"""The import step (POST /api/imports): the options a person gives, and the preview of what was read."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import ConfigDict, Field

from .common import MAX_INT, Floats, Index, Matrix, Schema

class ImportOptions(Schema):
    """What the person says about uploaded files that they cannot say themselves (the import step). Channels are
    numbered as read (0-based), before any is dropped."""

    model_config = ConfigDict(extra="forbid")
    kind: Literal["auto", "pulse", "decay", "frf", "io", "ambient"] = Field(
        "auto", description="what the records are: auto (guessed), pulse, decay, frf, io (OKID) or ambient (NExT)")
    dt: float | None = Field(None, gt=0, description="sampling interval, s, when the files carry none")
    format: str | None = Field(None, description="the format when sniffing should not decide, e.g. text")
    orientation: Literal["rows", "columns"] | None = Field(None, description="channels of a headerless table")
    variable: str | None = Field(None, description="the array to read in a MAT or HDF5 file")
    group: str | None = Field(None, description="the TDMS group to read")
    resample: bool | None = Field(None, description="true: put CSV/text records whose time stamps scatter about a "
                                                    "steady rate (no sample missing) onto an even grid at the mean "
                                                    "rate; what was done is written into the dataset's source")
    frf_sign: Literal["auto", "+", "-"] | None = Field(None, description="the FRFs' sign convention")
    start_sample: int | None = Field(None, ge=0, le=MAX_INT, description="samples skipped at the start of every record "
                                                            "(pre-trigger)")
    drop: list[Index] | None = Field(None, description="channels left out")
    forces: list[Index] | None = Field(None, description="channels that measure the excitation (input-output records); "
                                                       "null: as the files' units and names say")
    references: list[Index] | None = Field(None, description="reference channels of ambient records (NExT); null: all")
    points: dict[str, str] | None = Field(None, max_length=4096, description="where time channels are: {channel "
                                          "position as read: point label such as 4X}; a force channel's point is "
                                          "where the structure was struck or driven; null: none known")
    band_hz: list[float] | None = Field(None, min_length=2, max_length=2,
                                        description="[low, high] Hz, the band FRFs are valid in (e.g. the analyser's "
                                                    "fMin, fMax): lines outside it are cut and no mode is chosen "
                                                    "there; null: all lines")


class ImportChannel(Schema):
    index: int = Field(description="position in the files, 0-based (what drop/forces/references take)")
    name: str
    unit: str = Field(description="unit as the file gives it ('' when none)")
    node: int | None = Field(description="test-geometry node of the sensor, when the file says")
    direction: str | None = Field(description="+X, -Z, ... (global), when the file says")
    force: bool = Field(description="measures the excitation")
    dropped: bool = Field(description="left out by the person's choice")


class ImportPreview(Schema):
    """What was read, before anything is identified (POST /api/imports)."""

    files: list[str]
    format: str
    domain: str = Field(description="time, pulse (impulse responses) or frequency (FRFs)")
    dt: float | None = Field(description="Δt, s (or Δf, Hz, for FRFs); null when the files carry none")
    sample_rate_hz: float | None = Field(description="1/Δt for time data, Hz")
    start: float = Field(description="abscissa of the first kept sample, s or Hz")
    channels: list[ImportChannel]
    references: list[str] = Field(description="the references (inputs) of FRFs or impulse responses")
    n_records: int = Field(description="records (files, runs or initial conditions)")
    n_samples: list[int] = Field(description="samples of each record after start_sample")
    kind: str = Field(description="what kind=auto would read the records as")
    described: list[str] = Field(description="what was read and done")
    x: Floats = Field(description="abscissa of the plotted points: s, Hz, or sample numbers when dt is null")
    x_label: str
    traces: Matrix = Field(description="(channels, points) first record of every channel, thinned "
                                       "(|FRF| of the first reference)")
    geometry_nodes: int = Field(description="nodes of the test geometry in the files")
    proposed_band_hz: list[float] | None = Field(None, description="[low, high] Hz, the band the test's setup "
                                                 "proposes (a SignalCalc setup.csv's fMin, fMax), or null")


class Import(Schema):
    """An upload waiting for the import step: its files, what was read, and what still stops it."""

    id: str = Field(description="upload id (kept a day unless it becomes a dataset)")
    files: list[str]
    bytes: int
    options: dict[str, Any] = Field(description="the options this preview used")
    preview: ImportPreview | None = Field(description="what was read, or null when nothing could be")
    error: str | None = Field(description="what still stops the import, and what to do")
    option: str | None = Field(description="the option that fixes the error (dt, orientation, variable, group, "
                                           "kind, forces, start_sample, drop, format)")
