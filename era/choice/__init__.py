"""The default analysis and the automatic choice of the structure's modes: the pipeline after the SVD
(:func:`diagram_and_choice`), the choice's rules and its evidence.

The names below are this room's public face beside ``era``'s own (``era.analyse``, ``era.choose_modes``)."""

from .analysis import (DEFAULT_MAX_ELEMENTS, DEFAULT_MAX_ORDER, DEFAULT_MAX_SIDE, DIAGRAM_MAX_ORDER, diagram_and_choice,
                       diagram_orders)

__all__ = ["DEFAULT_MAX_ELEMENTS", "DEFAULT_MAX_ORDER", "DEFAULT_MAX_SIDE", "DIAGRAM_MAX_ORDER", "diagram_and_choice",
           "diagram_orders"]
