"""Multi-setup tests (/api/setups, app/setups.py): several files, one per setup, merged through their reference
sensors (era.merge_setups). Shapes: k merged modes, q points (the references once, then every setup's roving
channels)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from .common import Floats, Index, Matrix, Schema
from .reports import ReportGeometry


class SetupChannels(Schema):
    file: str = Field(description="the file the setup was read from")
    outputs: list[str] = Field(description="its channels, in the order the references index them")
    n_samples: int
    dt: float = Field(description="sampling interval of its pulse responses (or correlation functions), s")
    has_geometry: bool = Field(description="whether its file placed its channels on a geometry")
    ambient: bool = Field(description="ambient records (NExT): the merge correlates them with the picked references")


class MergedMode(Schema):
    frequency_hz: float = Field(description="damped frequency, combined over the setups that saw it, Hz")
    damping_ratio: float = Field(description="fraction of critical")
    frequency_std_hz: float | None = Field(description="its standard deviation, Hz, or null")
    damping_std: float | None = Field(description="its standard deviation, or null")
    mpc: float | None = Field(description="modal phase collinearity of the merged shape (its known points)")
    seen_in: int = Field(description="setups whose analysis chose the mode")
    seen: str = Field(description='the same in words: "seen in 3 of 4 setups"')
    complete: bool = Field(description="its shape is known at every point (so it is in the UFF 55 export)")
    missing_setups: list[int] = Field(description="setups (1-based) at whose points the shape is unknown")
    paired_by_frequency: list[int] = Field(default=[], description="setups (1-based) whose part was paired by "
                                           "frequency alone (its reference MAC failed: references near a node)")
    scale_std: list[float | None] = Field(default=[], description="(setups,) the relative σ of the factor each "
                                          "setup's part was scaled by (from the references' misfit), null where "
                                          "not seen")
    note: str = Field(description="what the page says about it: where its shape is unknown, what was recovered, "
                                  "what was paired by frequency, an uncertain scale")


class DroppedSetupMode(Schema):
    setup: int = Field(description="the setup (1-based)")
    file: str
    frequency_hz: float
    reason: str = Field(description="why it is not a merged mode, in words")


class SetupsMerged(Schema):
    references: list[list[int]] = Field(description="per setup, the indices of its reference channels")
    reference_names: list[str] = Field(description="the references' names in setup 1")
    setups: list[str] = Field(description="the setups' files, in order")
    points: list[str] = Field(description="(q,) the merged points: the references, then each setup's roving "
                                          "channels (S<k>: prefixed when names repeat)")
    point_setup: list[int] = Field(description="(q,) the setup (1-based) each point was measured in; 0 for a "
                                               "reference (every setup)")
    modes: list[MergedMode]
    eigenvalue_re: Floats = Field(description="(k,) Re s, rad/s")
    eigenvalue_im: Floats = Field(description="(k,) Im s, rad/s")
    shapes_re: Matrix = Field(description="(k, q) real part of each merged shape, largest component 1; null where "
                                          "unknown (a setup that did not see the mode)")
    shapes_im: Matrix = Field(description="(k, q) imaginary part")
    dropped: list[DroppedSetupMode] = Field(description="every setup mode left out of the merge, with its reason")
    geometry: ReportGeometry | None = Field(description="the setups' geometry with the merged points as its "
                                                        "channels, or null")
    uncertainty_source: str
    points_table: str = Field(default="", description="the points table the merge was given (CSV point,x,y,z,"
                                                      "direction, then from,to lines), or empty")
    next_references: str = Field(default="every", description="how ambient records were correlated in the kept "
                                 "merge: \"every\" channel a NExT reference or the picked \"references\" only")
    next_asked: str = Field(default="every", description="what was asked: \"auto\" (both ways, the merge with more "
                            "modes complete kept: era.merge_choosing_next), \"every\" or \"references\"")
    next_choice: str = Field(default="", description="why that way, in words (each way's complete modes and mean "
                             "MPC)")
    next_complete: list[int] = Field(default=[], description="with \"auto\": complete modes at distinct frequencies "
                                     "with every channel, then with the references only (-1: refused)")
    method: Literal["poser", "preger"] = Field(default="poser", description="how the setups were merged: \"poser\" "
                                               "(each identified, the shapes joined through the references) or "
                                               "\"preger\" (the correlations joined, one identification)")
    preger_scales: Floats = Field(default=[], description="PreGER: (setups,) the factor each setup's correlations "
                                  "were multiplied by (setup 1: 1)")
    preger_residual: Floats = Field(default=[], description="PreGER: (setups,) the references' relative misfit after "
                                    "the scale (large when the excitation's spectrum changed shape)")
    merged: float = Field(description="when the merge was made, Unix s")


class SetupsUnmatched(Schema):
    name: str = Field(description="a channel name of setup 1")
    missing_in: list[int] = Field(description="the setups (1-based) without a channel of that name")


class ReferencePairEvidence(Schema):
    channels: list[list[str]] = Field(description="per setup, the pair's channel names (setup 1's pair, then the "
                                                  "pair of each setup that best keeps its ratio)")
    indices: list[list[int]] = Field(description="the same as channel indices")
    score: float = Field(description="the smallest over the setups of its MAC over the shared modes (each "
                                     "weighted by how much the pair moves)")
    runner_up: float | None = Field(description="the same for the next best pair of some setup (ambiguous when "
                                                "it passes too)")
    mac: Matrix = Field(description="(setups, shared modes) its MAC with setup 1's pair, mode by mode")


class SetupsNodes(Schema):
    file: str = Field(description="the UFF file of the test's nodes")
    n_nodes: int
    n_lines: int = Field(description="its trace lines (UFF 82)")
    node_ids: list[int] = Field(description="its node numbers (the first 200), for a points table "
                                            "point,node,direction")


class SetupsReport(Schema):
    token: str = Field(description="the report's token")
    url: str = Field(description="its read-only page, /s/{id}/r/{token}")
    created: float = Field(description="when it was frozen, Unix s")


class SetupsTest(Schema):
    id: str
    name: str
    created: float = Field(description="Unix s")
    kind: str = Field(description="what the records are: auto, ambient (NExT), decay, pulse, frf or io")
    dt: float | None = Field(description="the sampling interval given for files without a time column, s, or null")
    setups: list[SetupChannels]
    proposed: list[list[int]] = Field(description="the proposed references: per setup, the indices of the "
                                                  "proposed channels (setup 1's order); empty lists when none")
    proposed_names: list[str] = Field(description="their names in setup 1")
    proposed_from: str = Field(default="names", description='"data" (era.propose_references: the channels whose '
                               'components keep their ratios in every setup), "names" (the same names in every '
                               'setup, when the data cannot tell and the names are not generic) or "" (none)')
    data_proposal: str = Field(default="", description="what the data said about the references, in words")
    shared_hz: Floats = Field(default=[], description="the frequencies of the modes every setup found, Hz (the "
                                                      "evidence's columns)")
    candidates: list[ReferencePairEvidence] = Field(default=[], description="the best pairs of channels, best first")
    unmatched: list[SetupsUnmatched] = Field(description="setup 1's channel names that some setups lack (a "
                                                         "reference renamed or missing there)")
    nodes: SetupsNodes | None = Field(default=None, description="the UFF file of nodes given for the points "
                                      "table (point,node,direction), or null")
    merged: SetupsMerged | None = Field(description="the last merge, or null")
    report: SetupsReport | None = Field(default=None, description="set on a frozen report (the merge as it was "
                                        "when the report was made), null on the test itself")


class SetupsRequest(BaseModel):
    references: list[list[Index]] = Field(max_length=64, description="per setup (in order), the indices of its "
                                        "reference channels: the same sensors, in the same order, in every setup")
    points: str | None = Field(None, max_length=200_000, description="where the points are: a CSV "
                               "point,x,y,z,direction (direction x, -z, or \"dx dy dz\"; point named as the merged "
                               "modes name it, or S<setup>:<channel>), optionally followed by from,to rows (the "
                               "lines between points)")
    next_references: Literal["auto", "every", "references"] = Field(
        "auto", description="ambient records: \"auto\" merges with both NExT references and keeps the merge with "
        "more modes complete (ties: more consistent shapes), as era.merge_ambient_setups; \"every\" channel a NExT "
        "correlation reference (era.load's default), or the picked \"references\" only")
    method: Literal["poser", "preger"] = Field(
        "poser", description="\"poser\": each setup identified (era.analyse), the shapes joined through the "
        "references (era.merge_setups); \"preger\": ambient setups' NExT correlations with the references joined "
        "on one scale, then one identification (era.merge_correlations, era.analyse)")

    model_config = {"json_schema_extra": {"examples": [{"references": [[0, 1], [0, 1]]}]}}


__all__ = ["SetupsReport", "SetupsNodes", "SetupChannels", "ReferencePairEvidence", "MergedMode", "DroppedSetupMode",
           "SetupsMerged", "SetupsTest", "SetupsRequest", "SetupsUnmatched"]
