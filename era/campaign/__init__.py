"""Campaigns: the same analysis over many records (hourly monitoring, test series), each record a task on a Dask
cluster or on local processes, and every mode followed through time.

``run_campaign(sources, ...)`` → :class:`CampaignResult` with ``table`` (a pandas.DataFrame, one row per record and
tracked mode), ``modes`` (the tracked modes) and ``failed`` (records that could not be analysed, with the reason).
Needs the ``campaign`` extra (``pip install 'era-modal[campaign]'``: dask[distributed], pandas, threadpoolctl).

record.py  one record → its modes, chosen by era.analyse (the task); tracking.py  modes matched through the
records; lookup.py  a tracked mode looked up in a record's diagram with its frequency and shape as the prior;
runner.py  the tasks and the cache; result.py  the table; simulated.py  simulated monitored structures for tests
and demos; scenarios.py  hard ones (a weak mode, a local mode appearing mid-way, twins in one record).
"""

from .record import (CampaignSettings, DiagramPoles, RecordFailure, RecordModes, analyse_record, modes_of,
                     record_modes, time_from_name)
from .result import COLUMNS, CampaignResult, require_pandas
from .runner import run_campaign
from .tracking import TrackedMode, Tracking, track_modes

__all__ = ["run_campaign", "CampaignResult", "COLUMNS", "RecordModes", "RecordFailure", "CampaignSettings",
           "DiagramPoles", "analyse_record", "modes_of", "record_modes", "time_from_name", "track_modes", "Tracking",
           "TrackedMode", "require_pandas"]
