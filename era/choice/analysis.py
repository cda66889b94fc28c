"""analyse(): the default analysis in one call: Hankel size, orders, one SVD, the stabilization diagram with the
data's uncertainty, and the automatic choice of the structure's modes (era.choice.choose)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .choose import ModeChoice, choose_modes
from ..core.data import ResponseData
from ..errors import DataError, EraError
from ..core.hankel import MAX_HANKEL_ELEMENTS
from ..core.modal import ModalModel
from ..core.realization import Identification, identify
from ..core.stabilization import Stabilization, stabilization
from ..core.suggest import hankel_size

#: The largest order realized by default (H(0)'s leading singular triplets kept).
DEFAULT_MAX_ORDER = 200
#: The stabilization diagram's highest order by default (every even order from 2).
DIAGRAM_MAX_ORDER = 160
#: H(0) at most this many elements by default (rows·p × cols·m), and at most this many rows and columns.
DEFAULT_MAX_ELEMENTS = 25_000_000
DEFAULT_MAX_SIDE = 800


@dataclass(frozen=True, eq=False)
class AnalysisResult:
    """What :func:`analyse` found.

    Attributes
    ----------
    identification : Identification
        The one SVD.
    stabilization : Stabilization
        The diagram over the analysis' orders.
    choice : ModeChoice
        The verdict on every cluster (era.choice.choose.ModeChoice).
    model : ModalModel
        The model of exactly the chosen modes at ``order``, sorted by frequency, with the data's standard
        deviations (``frequency_std_hz``, ``damping_std``).
    band_hz : (float, float)
        The band the choice used, Hz.
    order : int
        The diagram order at which every chosen mode has a pole (``choice.order``).
    rejected : tuple of Candidate
        Every candidate left out, each with its reason in words (``choice.rejected``).
    indices : int ndarray, shape (modes,)
        The chosen modes' positions among ``identification.model(order)``'s modes.

    Examples
    --------
    >>> from era.examples import paper_cases
    >>> result = era.analyse(paper_cases.case_1())
    >>> result.order, result.indices.tolist(), result.rejected
    (10, [0, 1, 2, 3, 4], ())
    >>> print(np.round(result.model.eigenvalues, 4))
    [-0.01+1.j -0.02+2.j -0.03+3.j -0.04+4.j -0.05+5.j]
    """

    identification: Identification
    stabilization: Stabilization
    choice: ModeChoice
    model: ModalModel
    band_hz: tuple

    @property
    def order(self) -> int:
        return self.choice.order

    @property
    def rejected(self) -> tuple:
        return self.choice.rejected

    @property
    def indices(self) -> np.ndarray:
        """(modes,) the chosen modes' positions among ``identification.model(order)``'s modes."""
        return self.choice.indices


def diagram_orders(max_order: int, top: int = DIAGRAM_MAX_ORDER) -> range:
    """The diagram's orders: every even order from 2 up to min(max_order, top) (1, 2, … below 2)."""
    top = min(int(max_order), int(top))
    return range(2, top + 1, 2) if top >= 2 else range(1, top + 1)


def analyse(data: ResponseData, *, rows: int | None = None, cols: int | None = None, max_order: int | None = None,
            orders=None, band_hz: tuple[float, float] | None = None,
            max_elements: int = DEFAULT_MAX_ELEMENTS, workers: int | None = None,
            pole_std: str = "choice") -> AnalysisResult:
    """The structure's modes from a ResponseData, chosen for you, with the evidence for and against every pole.

    The default path: the Hankel size, one SVD (:func:`era.identify`), the stabilization diagram with the data's
    standard deviations (:func:`era.stabilization`) and the choice of modes (:func:`era.choose_modes`).

    Parameters
    ----------
    data : ResponseData
        Pulse responses, free decays, or NExT correlation functions, (N, p, m).
    rows : int, optional
        Block rows r of H(0) (eq. 16, consecutive shifts); default :func:`era.core.suggest.hankel_size` (about
        45 % of N, H(0) at most ``max_elements`` elements).
    cols : int, optional
        Block columns s of H(0); default as ``rows``.
    max_order : int, optional
        The largest order realized; default min(r·p, s·m, DEFAULT_MAX_ORDER).
    orders : iterable of int, optional
        The diagram's orders; default every even order from 2 to min(max_order, DIAGRAM_MAX_ORDER).
    band_hz : (float, float), optional
        (low, high) Hz, the band the data hold; default ``data.meta["band_hz"]`` (FRF data), else (0, Nyquist).
    max_elements : int, optional
        The most elements H(0) may hold when its size is chosen here (default DEFAULT_MAX_ELEMENTS).
    workers : int, optional
        Threads for the diagram's orders (:func:`era.stabilization`).
    pole_std : {"choice", "all"}, optional
        The diagram's poles whose standard deviations from the data are computed
        (``stabilization.frequency_std_hz``): those the choice reads (``era.stabilization(...,
        uncertainty="choice")``, a third of the work; the default) or every stable pole. The choice, and the
        chosen modes and their σ (``model``), are the same with both.

    Returns
    -------
    AnalysisResult
        The identification, the diagram, the verdict on every cluster and the model of the chosen modes.

    Raises
    ------
    era.DataError
        When the records hold nothing to identify (H(0) of rank 0).
    era.EraError
        (HankelError, OrderError) for parameters that do not fit the data.

    References
    ----------
    Juang & Pappa (1985), eqs. 16, 22 and 34; the diagram and the choice are era's (docs/choosing-modes.md).

    Examples
    --------
    Two modes (2 Hz, 1 % and 5 Hz, 2 %) at two sensors, noise 40 dB below the signal:

    >>> from era.examples.synthetic import modal_response
    >>> data, truth = modal_response([2.0, 5.0], [0.01, 0.02], 2, 1, 400, 0.02, snr_db=40, seed=1)
    >>> result = era.analyse(data, max_order=40)
    >>> print(np.round(result.model.frequency_hz, 3), np.round(result.model.damping_ratio, 3))
    [2. 5.] [0.01 0.02]
    >>> result.band_hz, [candidate.code for candidate in result.rejected]
    ((0.0, 25.0), ['noise', 'noise'])
    """
    if not isinstance(data, ResponseData):
        raise EraError(f"analyse needs an era.ResponseData (era.load(...).data), got {type(data).__name__}.")
    if pole_std not in ("choice", "all"):
        raise EraError(f"`pole_std` must be \"choice\" or \"all\", got {pole_std!r}.")
    n, p, m = data.markov.shape
    if rows is None or cols is None:
        choice = hankel_size(n, p, m, max_side=DEFAULT_MAX_SIDE, max_elements=min(max_elements, MAX_HANKEL_ELEMENTS),
                             max_order=DEFAULT_MAX_ORDER)
        rows = choice.rows if rows is None else rows
        cols = choice.cols if cols is None else cols
    if max_order is None:
        max_order = min(int(rows) * p, int(cols) * m, DEFAULT_MAX_ORDER)
    ident = identify(data, rows, cols, max_order=max_order)
    if ident.max_order == 0:
        raise DataError("H(0) has rank 0: the records are zero (or round-off) throughout, so there is nothing to "
                        "identify. Check the file's channels and scaling.")
    orders = diagram_orders(ident.max_order) if orders is None else orders
    if band_hz is None and data.meta.get("band_hz") is not None:
        band_hz = tuple(float(x) for x in data.meta["band_hz"])
    stab, picked = diagram_and_choice(ident, orders, band_hz, pole_std=pole_std, workers=workers)
    return AnalysisResult(identification=ident, stabilization=stab, choice=picked,
                          model=chosen_model(ident, picked), band_hz=band_hz or (0.0, 0.5 / data.dt))


def diagram_and_choice(ident: Identification, orders, band_hz: tuple[float, float] | None = None, *,
                       pole_std: str = "choice", workers: int | None = None) -> tuple[Stabilization, ModeChoice]:
    """The stabilization diagram of ``ident`` at ``orders`` with the data's standard deviations, and the modes
    :func:`era.choose_modes` chooses from it in ``band_hz`` (Hz; None: 0 to Nyquist): the default analysis's
    steps after the SVD, one place for :func:`analyse`, the app and explain.

    pole_std : "choice" (the poles the choice reads get their σ) or "all" (every stable pole); the choice and the
        chosen modes' σ are the same with both.
    """
    if pole_std not in ("choice", "all"):
        raise EraError(f"`pole_std` must be \"choice\" or \"all\", got {pole_std!r}.")
    stab = stabilization(ident, orders, uncertainty=True if pole_std == "all" else "choice", workers=workers)
    return stab, choose_modes(ident, stab, band_hz=band_hz)


def chosen_model(ident: Identification, picked: ModeChoice) -> ModalModel:
    """The ModalModel of exactly the chosen modes at the chosen order (with the data's standard deviations)."""
    return ident.model(picked.order).select(picked.indices)
