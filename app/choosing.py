"""The default path of an analysis within this server's limits: era's Hankel size and orders, the stabilization
diagram with the data's uncertainty, and era's choice of the structure's modes (era.choose_modes, the one rule the
library's era.analyse follows too).

The app does not run era.analyse itself: a person may choose the Hankel size and the shifts, and the SVD is cached
apart from the diagram (the slider realizes orders from it). So the steps are taken here one by one (the SVD, then
era.choice.analysis.diagram_and_choice, era.analyse's steps after it), with the server's settings only as caps on
era's defaults. Functions run in a worker process (app/compute.py): they are
module-level and take and return picklable values.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import era
from era.choice import (DEFAULT_MAX_ELEMENTS, DEFAULT_MAX_ORDER, DEFAULT_MAX_SIDE, DIAGRAM_MAX_ORDER,
                                 diagram_and_choice, diagram_orders)
from era.core import HankelChoice, hankel_size, order_cap, order_from_singular_values

from . import limits
from .config import Settings


@dataclass(frozen=True, eq=False)
class Diagram:
    """An analysis's stabilization diagram and the modes chosen from it.

    stabilization : era.Stabilization over ``orders(...)``; choice : era.ModeChoice; band_hz : (low, high) Hz,
    the band the choice used (the dataset's, else 0 to Nyquist); order : the diagram order an analysis opens at
    (:func:`opening_order`).
    """

    stabilization: era.Stabilization
    choice: era.ModeChoice
    band_hz: tuple
    order: int

    @property
    def chosen_indices(self) -> list[int]:
        """The chosen modes' indices among the modes of ``order`` (empty when era chose none)."""
        return [int(k) for k in self.choice.indices] if self.choice.n_modes else []


def default_hankel(n_samples: int, n_outputs: int, n_inputs: int, settings: Settings) -> HankelChoice:
    """era's Hankel size for a dataset (era.core.suggest.hankel_size, era.analyse's defaults), within the server's
    ERA_MAX_HANKEL_ELEMENTS and ERA_MAX_ORDER."""
    return hankel_size(n_samples, n_outputs, n_inputs, max_side=DEFAULT_MAX_SIDE,
                       max_elements=min(DEFAULT_MAX_ELEMENTS, settings.max_hankel_elements),
                       max_order=min(DEFAULT_MAX_ORDER, settings.max_order))


def named_hankel(rows: int, cols: int, n_outputs: int, n_inputs: int, settings: Settings) -> HankelChoice:
    """A Hankel size someone named (an example's paper size), with era's default largest order for it."""
    return HankelChoice(rows=int(rows), cols=int(cols),
                        max_order=order_cap(rows, cols, n_outputs, n_inputs, min(DEFAULT_MAX_ORDER, settings.max_order)))


def orders(max_order: int, settings: Settings) -> range:
    """The diagram's orders (era.choice.analysis.diagram_orders) up to the identification's max_order, at most
    min(era's DIAGRAM_MAX_ORDER, the server's max_stabilization_order)."""
    return diagram_orders(max_order, min(DIAGRAM_MAX_ORDER, settings.max_stabilization_order))


def band_of(data: era.ResponseData) -> tuple[float, float] | None:
    """The band the records hold, (low, high) Hz: ``data.meta["band_hz"]`` of FRF data, else None (0 to Nyquist)."""
    band = (data.meta or {}).get("band_hz")
    return None if band is None else (float(band[0]), float(band[1]))


def diagram(ident: era.Identification, band_hz: tuple[float, float] | None, settings: Settings) -> Diagram:
    """The stabilization diagram of ``ident`` (with the data's standard deviations) and era's choice of modes in
    ``band_hz``. Blocking: run it in a worker process."""
    stab, picked = diagram_and_choice(ident, orders(ident.max_order, settings), band_hz,
                                      workers=settings.analysis_threads)
    return Diagram(stabilization=stab, choice=picked, band_hz=band_hz or (0.0, 0.5 / float(ident.dt)),
                   order=opening_order(ident, stab, picked))


def opening_order(ident: era.Identification, stab: era.Stabilization, picked: era.ModeChoice) -> int:
    """The order an analysis opens at: the choice's order, or, when era chose no mode, the diagram order nearest
    the singular values' order (era.core.suggest.order_from_singular_values; the lower of two).

    Noise-free records of exact rank n (the paper's Case I and II) give the diagram no cluster below n, so the
    choice is empty and its order is the diagram's lowest; the person is then better served at the order the
    singular values show, where the table ticks by its thresholds (nothing is chosen for them)."""
    if picked.n_modes or not len(stab.orders):
        return int(picked.order)
    at = np.asarray(stab.orders)
    n = order_from_singular_values(ident.singular_values, ident.max_order)
    return int(at[np.argmin(np.abs(at - n))])


def analyse_dataset(data: era.ResponseData, params: dict, settings: Settings) -> tuple[era.Identification, Diagram]:
    """One SVD (limits.identify_within_limits) and its diagram and choice, in one worker call (the identification is not sent
    back and forth between the two)."""
    ident = limits.identify_within_limits(data, params, settings)
    return ident, diagram(ident, band_of(data), settings)
