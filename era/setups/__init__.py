"""Multi-setup tests: one shape through the reference sensors (PoSER: :mod:`era.setups.poser`; PreGER), the
references found from the data, NExT's references chosen, the pairing of modes across setups and the test's points
table.

The names below are this room's public face beside ``era``'s own (``era.merge_setups``, ``era.propose_references``,
``era.merge_ambient_setups``, ``era.merge_correlations``)."""

from .geometry import PointTable, parse_points, point_aliases, points_geometry
from .next_references import WAY_WORDS
from .poser import merge_with_evidence, merged_geometry

__all__ = ["PointTable", "WAY_WORDS", "merge_with_evidence", "merged_geometry", "parse_points", "point_aliases",
           "points_geometry"]
