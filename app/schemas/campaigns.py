"""Campaigns (/api/campaigns, app/campaigns.py): a folder of records tracked through time."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from .common import Floats, Schema

class CampaignAnalysis(Schema):
    kind: str = Field(description="how each record became Markov parameters: auto, ambient (NExT), decay, ...")
    dt: float | None = Field(description="sampling interval given for files without a time column, s, or null")
    orders: list[int] = Field(description="model orders of each record's stabilization diagram")


class CampaignRecord(Schema):
    record: int = Field(description="position of the record among the campaign's files (0-based)")
    name: str = Field(description="its file name")
    time: str | float = Field(description="ISO 8601 date-time from the file name, or the record's position when "
                                          "not every file name holds one")


class CampaignMode(Schema):
    mode: int = Field(description="the tracked mode's number")
    reference_frequency_hz: float | None = Field(description="frequency where it was defined, Hz")
    reference_damping_ratio: float | None = Field(description="damping where it was defined, fraction")
    origin: str = Field(description="reference (a mode of the first record) or new (appeared later and persisted)")
    first_record: int = Field(description="the record that defined it (-1 for a given reference)")
    n_found: int = Field(description="records that show it")
    n_held: int = Field(0, description="records that hold it: every analysed record from the one that defined it on")
    identification_rate: float | None = Field(None, description="n_found / n_held, the share of the records "
                                                                "holding the mode in which it was identified")


class CampaignSeries(Schema):
    mode: int
    frequency_hz: Floats = Field(description="one per analysed record, in time order; null where it is missing")
    damping_ratio: Floats = Field(description="fraction, one per analysed record")
    mac_to_reference: Floats = Field(description="MAC of the record's mode with the reference shape")


class CampaignFailure(Schema):
    record: int
    name: str = Field(description="the file name")
    reason: str = Field(description="why the record could not be analysed, for a person")


class CampaignResult(Schema):
    """campaigns/{id}/campaign.json: everything the campaign page draws."""

    id: str
    name: str
    engine: str = Field(description="where the records ran: the Dask scheduler's address or local processes")
    analysis: CampaignAnalysis
    seconds: float = Field(description="wall time of the campaign, s")
    n_records: int = Field(description="records (files) in the campaign, analysed or failed")
    time_axis: Literal["date", "record"] = Field(description="what the records' time is")
    records: list[CampaignRecord] = Field(description="the analysed records, in time order")
    modes: list[CampaignMode]
    series: list[CampaignSeries] = Field(description="one per tracked mode")
    failed: list[CampaignFailure]


class Campaign(Schema):
    id: str = Field(description="the campaign's id (144-bit random): its link is the secret")
    name: str
    url: str = Field(description="the campaign's page and report link, /c/{id}")
    state: Literal["queued", "running", "done", "failed"]
    done: int = Field(description="records finished so far (analysed or failed)")
    total: int = Field(description="records in the campaign")
    message: str | None = Field(description="why the campaign failed as a whole, or a warning; null otherwise")
    engine: str = Field(description="where the records run")
    result: CampaignResult | None = Field(description="once done")


class CampaignFolder(Schema):
    name: str = Field(description="a folder under ERA_CAMPAIGN_ROOT ('.' is the root itself)")
    n_files: int


class CampaignFolders(Schema):
    enabled: bool = Field(description="whether this server runs campaigns on its own folders (ERA_CAMPAIGN_ROOT)")
    folders: list[CampaignFolder]
    engine: str = Field(description="where campaigns run on this server")
    max_records: int = Field(description="records in one campaign at most (ERA_MAX_CAMPAIGN_RECORDS)")
