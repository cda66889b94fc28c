"""Reports (/api/reports): the frozen document, as stored, served and downloaded."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, Field

from .analyses import Analysis, Modes, Stabilization
from .common import MAX_INT, Floats, Index, Matrix, Schema
from .datasets import Dataset
from .explain import Explanation

class ReportCreated(Schema):
    token: str = Field(description="the report's token (144-bit random)")
    url: str = Field(description="the read-only report page, /r/{token}")


class ReportPair(Schema):
    output: str
    input: str
    output_index: int
    input_index: int
    measured: Floats = Field(description="(N',) measured response")
    reconstructed: Floats = Field(description="(N',) response of the kept modes")


class ReportReconstruction(Schema):
    time_s: Floats = Field(description="(N',) s, decimated to ≤ 1500 points")
    pairs: list[ReportPair] = Field(description="channels (output, input), at most 36")


class ReportGeometry(Schema):
    node_ids: list[int]
    coordinates: Matrix = Field(description="(nodes, 3) in units")
    edges: list[list[int]] = Field(description="(lines, 2) node indices")
    channel_nodes: list[int] = Field(description="(p,) node index of each output, -1 if none")
    channel_directions: Matrix = Field(description="(p, 3) unit direction of each output")
    units: str


class FrozenModel(Schema):
    """A dataset's structure model as a report keeps it."""

    model: dict[str, Any] = Field(description="era.Frame's file format, SI units, as described; an FE model's "
                                              "{fe, mapping}")
    source: str = Field(description="geometry (described in the panel), file, or fe (an FE model: a deck or matrices)")
    name: str | None = Field(description="the uploaded file's name, or null")
    saved: float | None = Field(description="when it was saved, Unix s")
    text: str = Field(description="the model in one line")


class ReportDocument(Schema):
    """The frozen report, as stored: everything its page draws."""

    created: str = Field(description="ISO 8601, UTC")
    software: dict[str, str] = Field(description="versions of era-modal, python, numpy, scipy")
    dataset: Dataset
    analysis: Analysis
    order: int
    kept: list[int] = Field(description="kept modes at this order, ascending")
    modes: Modes = Field(description="every mode of this order, with the fit of all of them")
    kept_fit_percent: Matrix = Field(description="(p, m) fit of the kept modes per channel, %")
    reconstruction: ReportReconstruction
    stabilization: Stabilization
    geometry: ReportGeometry | None
    explanation: Explanation | None = Field(description="simulation vs test, when its panel ran before the report")
    structure_model: FrozenModel | None = Field(None, description="the dataset's structure model when the report was "
                                                                  "made (the engineer's own structure), or null")
    recordings: dict[str, str] = Field(description="{mode index: file} of the mode-shape recordings (.viser)")


class Report(ReportDocument):
    token: str
    url: str = Field(description="/r/{token}")
    playback: dict[str, str] = Field(description="{mode index: viser player page for its recording}")


class OfflineReport(ReportDocument):
    """window.REPORT_DATA of the downloaded HTML (reporting.standalone_html): no server behind it."""

    token: str
    standalone: bool = Field(description="true: the page has no server (no links to downloads)")
    offline_recordings: dict[str, str] = Field(description="{mode index: .viser recording, base64}")
    viser_marker: str | None = Field(description="what the player page holds where a recording goes, or null")


# ---- requests -----------------------------------------------------------------------------------------------
class ReportRequest(BaseModel):
    analysis_id: str = Field(min_length=1, max_length=100)
    order: int | None = Field(None, ge=1, le=MAX_INT,
                              description="the model order; default the order era's choice is read at (the "
                                          "analysis's suggested_order)")
    modes: list[Index] | None = Field(None, description="indices of the kept modes at this order; default "
                                                        "the modes era chose (chosen_indices), at the chosen "
                                                        "order only")
