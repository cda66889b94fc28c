"""What a campaign returns: the table of every tracked mode in every record, the tracked modes, the failures."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import EraError
from .record import mode_value

#: The table's columns, in order (see :class:`CampaignResult`).
COLUMNS = ("record", "name", "time", "mode", "found", "frequency_hz", "damping_ratio", "mac_to_reference", "emac",
           "mpc", "n_orders", "frequency_std_hz", "damping_std", "order", "record_mode", "found_by")


@dataclass(frozen=True, eq=False)
class CampaignResult:
    """The result of :func:`era.campaign.run_campaign`.

    table : pandas.DataFrame, one row per (analysed record, tracked mode), sorted by time then mode, columns
        record (int, the position of the record in ``sources``), name (file name, or "record i" for bytes),
        time (pandas Timestamp when every record's time is known, from its file name or ``times=``; otherwise
        the record's position in the campaign, a float), mode (int, see ``modes``), found (bool), frequency_hz,
        damping_ratio (fraction), mac_to_reference (MAC with the tracked mode's reference shape), emac (γ),
        mpc (μ), n_orders (orders of the diagram where the mode is stable), frequency_std_hz and damping_std
        (standard deviations from the data, era.core.uncertainty), order (the diagram order the record's modes are
        read at, era.choose_modes), record_mode (the mode's index in the record's own RecordModes, -1 where
        missing; n_modes + k for the record's spare k, a cluster the choice left out: RecordModes.spares), found_by
        (where the record showed it: "choice", its chosen modes; "cluster", a cluster of its diagram the choice
        left out; "diagram", its diagram's poles looked up with the tracked mode's frequency and shape, then
        appended to the record's spares with a line in its ``rejected`` that says so, σ NaN; "" where missing).
        The values are the record's chosen model's (era.analyse), or the spare cluster's. Where a record does not
        show a tracked mode, ``found`` is False and the numbers are NaN (n_orders 0). Failed records have no rows.
    modes : tuple of era.campaign.TrackedMode: number, reference frequency, damping and shape, origin
        ("reference" or "new"), the record that defined it and how many records found it.
    failed : tuple of era.campaign.RecordFailure (record, name, reason), in record order.
    records : tuple of era.campaign.RecordModes, each analysed record's own modes (before tracking).
    settings : era.campaign.CampaignSettings, how every record was analysed.
    """

    table: object
    modes: tuple
    failed: tuple
    records: tuple
    settings: object

    def pivot(self, value: str = "frequency_hz"):
        """pandas.DataFrame of one column of the table: one row per record (indexed by time), one column per mode."""
        return self.table.pivot(index="time", columns="mode", values=value)

    def modes_frame(self):
        """pandas.DataFrame of the tracked modes (without shapes): mode, reference_frequency_hz,
        reference_damping_ratio, origin, first_record, n_found, n_held (records that hold it: from the one that
        defined it on) and identification_rate (n_found / n_held)."""
        return require_pandas().DataFrame([{"mode": m.mode, "reference_frequency_hz": m.reference_frequency_hz,
                              "reference_damping_ratio": m.reference_damping_ratio, "origin": m.origin,
                              "first_record": m.first_record, "n_found": m.n_found, "n_held": m.n_held,
                              "identification_rate": m.identification_rate} for m in self.modes])


def require_pandas():
    """The pandas module, or an EraError saying how to install it."""
    try:
        import pandas as pd
    except ImportError:
        raise EraError("Campaign tables are pandas DataFrames: install the campaign extra, "
                       "python3 -m pip install 'era-modal[campaign]' (or pandas).") from None
    return pd


def record_times(records) -> list:
    """The ``time`` of each record for the table: numpy.datetime64 when every record has one, else its position
    in the campaign (float)."""
    stamps = [r.time for r in records]
    if stamps and all(isinstance(t, np.datetime64) for t in stamps):
        return stamps
    if stamps and all(isinstance(t, (int, float, np.integer, np.floating)) and not isinstance(t, bool)
                      for t in stamps):
        return [float(t) for t in stamps]
    return [float(r.index) for r in records]


def build_table(tracking):
    """The campaign table (pandas.DataFrame, columns :data:`COLUMNS`) from an era.campaign.Tracking."""
    pd = require_pandas()
    rows = {c: [] for c in COLUMNS}
    times = record_times(tracking.records)
    for pos, rec in enumerate(tracking.records):
        for col, mode in enumerate(tracking.modes):
            i = int(tracking.assignment[pos, col])
            found = i >= 0
            value = (lambda a: mode_value(rec, a, i) if found else np.nan)  # noqa: E731
            rows["record"].append(rec.index)
            rows["name"].append(rec.name)
            rows["time"].append(times[pos])
            rows["mode"].append(mode.mode)
            rows["found"].append(found)
            rows["frequency_hz"].append(value("frequency_hz"))
            rows["damping_ratio"].append(value("damping_ratio"))
            rows["mac_to_reference"].append(float(tracking.mac_to_reference[pos, col]))
            rows["emac"].append(value("emac"))
            rows["mpc"].append(value("mpc"))
            rows["n_orders"].append(int(mode_value(rec, "n_orders", i)) if found else 0)
            rows["frequency_std_hz"].append(value("frequency_std_hz"))
            rows["damping_std"].append(value("damping_std"))
            rows["order"].append(int(rec.order))
            rows["record_mode"].append(i)
            rows["found_by"].append(str(tracking.found_by[pos, col]) if tracking.found_by is not None else
                                    ("choice" if found else ""))
    table = pd.DataFrame(rows, columns=list(COLUMNS))
    if len(table) and isinstance(times[0], np.datetime64):
        table["time"] = pd.to_datetime(table["time"])
    table = table.astype({"record": int, "mode": int, "found": bool, "n_orders": int, "order": int,
                          "record_mode": int})
    return table.sort_values(["time", "record", "mode"], kind="stable").reset_index(drop=True)
