"""Datasets (GET /api/datasets/...): the stored summary, its records and spectrum, and the built-in examples."""

from __future__ import annotations

from typing import Any

from pydantic import ConfigDict, Field

from .common import Floats, Matrix, Schema

class GeometrySummary(Schema):
    n_nodes: int = Field(description="nodes of the test geometry")
    n_edges: int = Field(description="lines between nodes")
    units: str = Field(description="length unit of the coordinates, e.g. 'in', 'm'")


class HankelDefaults(Schema):
    rows: int = Field(description="r, block rows of H(0) suggested for this dataset")
    cols: int = Field(description="s, block columns of H(0) suggested for this dataset")
    max_order: int = Field(description="largest order suggested: min(r·p, s·m, era's 200, ERA_MAX_ORDER)")


class DatasetLimits(Schema):
    rows_plus_cols_max: int = Field(description="rows + cols ≤ N with consecutive shifts (N samples)")
    max_hankel_elements: int = Field(description="largest H(0) rows·p × cols·m, elements (ERA_MAX_HANKEL_ELEMENTS)")
    max_order: int = Field(description="largest order this server realizes (ERA_MAX_ORDER)")
    note: str = Field(description="the limits in words, for the page")


class DatasetSource(Schema):
    """How the records were read. Keys the loader or an example did not set are absent."""

    model_config = ConfigDict(extra="allow")
    file: str | list[str] | None = Field(None, description="uploaded file name")
    bytes: int | None = Field(None, description="size of the upload, bytes")
    format: str | None = Field(None, description="uff, csv, text, npz, lvm, npy, mat, hdf5, tdms or signalcalc")
    options: dict[str, Any] | None = Field(None, description="what the person said the files could not (dt, "
                                                             "orientation, variable, group, frf_sign, format)")
    kind: str | None = Field(None, description="what the records were read as: pulse, decay, frf, io, ambient")
    records: list[str] | None = Field(None, description="what was read, one line per record group")
    conversions: list[str] | None = Field(None, description="conversions applied (FRF → pulse response, …)")
    example: str | None = Field(None, description="name of the built-in example, for examples")


class Dataset(Schema):
    id: str = Field(description="dataset id (144-bit random)")
    sha256: str = Field(description="SHA-256 of the stored (normalised) dataset")
    name: str = Field(description="file name or example title")
    outputs: list[str] = Field(description="(p,) output (sensor) labels")
    inputs: list[str] = Field(description="(m,) input (excitation or initial condition) labels")
    output_units: list[str] | None = Field(description="(p,) output units, or null when the file gave none")
    input_units: list[str] | None = Field(description="(m,) input units, or null")
    dt: float = Field(description="Δτ, sampling interval, s")
    n_samples: int = Field(description="N, samples per record")
    n_outputs: int = Field(description="p")
    n_inputs: int = Field(description="m")
    duration_s: float = Field(description="N·Δτ, s")
    nyquist_hz: float = Field(description="1/(2Δτ), Hz")
    geometry: GeometrySummary | None = Field(description="the test geometry, or null")
    source: DatasetSource
    defaults: HankelDefaults
    limits: DatasetLimits
    band_hz: list[float] | None = Field(None, description="[low, high] Hz, the band FRF records hold (the choice of "
                                                          "modes looks only there); null: 0 to Nyquist")
    has_model: bool = Field(False, description="a structure model is stored (GET /api/datasets/{id}/model answers "
                                               "it; without one that request is a 404, so the page does not send it)")


class Records(Schema):
    time_s: Floats = Field(description="(N',) time of each plotted sample, s (decimated to ≤ 4000 points)")
    input: str = Field(description="label of the input these records respond to")
    outputs: list[str] = Field(description="(p,) output labels, one per series")
    series: Matrix = Field(description="(p, N') response of each output to this input, in the output's unit")


class Spectrum(Schema):
    frequency_hz: Floats = Field(description="(F,) frequency from 0 to Nyquist, Hz")
    values: Matrix = Field(description="(min(p, m), F) CMIF: singular values of the FFT of the records × Δτ, "
                                       "descending at each frequency")


class Example(Schema):
    name: str = Field(description="what to POST to /api/examples/{name}")
    title: str
    description: str
    rows: int | None = Field(description="Hankel rows the example's source uses, or null for the default")
    cols: int | None = Field(description="Hankel columns the example's source uses, or null")
