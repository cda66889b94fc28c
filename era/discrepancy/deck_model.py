"""A Nastran deck as an explain model: MatrixExplainModel's effects on the deck's matrices (a point mass, a spring
to ground, a part's stiffness or mass, spread mass) and a property off by a factor, for which the deck is
re-assembled with the changed card (a PSHELL's thickness changes membrane, bending and mass together, which no
factor on one matrix does), through era.models.nastran.variation: the matrices as a polynomial in the factor."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import DataError
from ..models.changes import EFFECT_DEFAULTS
from ..models.matrix import MatrixModel
from ..models.nastran.deck import Deck
from ..models.nastran.mesh import property_keys
from ..models.nastran.reader import NastranModel
from ..models.nastran.variation import property_variation
from ..words import listed
from .matrix_model import MatrixExplainModel
from .protocol import RitzModes

PROPERTY = "property:"     # a property change's place: "property:PSHELL 3 T"
DECK_DEFAULTS = {**EFFECT_DEFAULTS, "property_at": None, "property_factor": 1.0}
_KEPT = 16                 # re-assembled decks kept per nominal (the fits of one property's factor)


def property_key(place) -> str:
    """"PSHELL 3 T" from a place "property:PSHELL 3 T" (or the key itself)."""
    text = str(place)
    return text[len(PROPERTY):] if text.startswith(PROPERTY) else text


@dataclass(frozen=True, eq=False)
class DeckExplainModel:
    r"""A deck read by era.models.nastran.read_bdf, with explain's parameters.

    The parameters (DECK_DEFAULTS) are MatrixExplainModel's keywords, and property_at ("property:PSHELL 3 T") with
    property_factor. Made by :meth:`of`; :meth:`with_params` gives a variant.

    Parameters
    ----------
    nominal : MatrixExplainModel
        The deck as read, seen at the test's sensors.
    reduced : bool, optional
        As MatrixExplainModel's (False: every parameter set solved in full).

    Examples
    --------
    The steel strip of :func:`era.load_model`'s example, and the same strip with its bars' I 10 % larger
    (frequencies × sqrt(1.1)):

    >>> import os, tempfile
    >>> deck = ["BEGIN BULK"] + [f"GRID,{i + 1},,{0.25 * i},0.,0." for i in range(5)]
    >>> deck += [f"CBAR,{i + 1},1,{i + 1},{i + 2},0.,0.,1." for i in range(4)]
    >>> deck += ["PBAR,1,1,5.-4,4.17-9,1.04-7,1.46-8", "MAT1,1,2.+11,,0.3,7850.", "SPC1,1,123456,1", "ENDDATA"]
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "strip.bdf")
    ...     with open(path, "w") as file:
    ...         _ = file.write("\n".join(deck) + "\n")
    ...     strip = era.load_model(path)
    >>> nominal = era.DeckExplainModel.of(strip, [("3", "z"), ("5", "z")])
    >>> print(np.round(nominal.modes(2)[0], 2))
    [ 8.16 40.74]
    >>> stiffer = nominal.with_params(property_at="property:PBAR 1 I", property_factor=1.1)
    >>> print(np.round(stiffer.modes(2)[0], 2))
    [ 8.56 42.73]
    """

    nominal: MatrixExplainModel
    _params: dict = field(default_factory=lambda: dict(DECK_DEFAULTS))
    _shared: dict = field(default_factory=dict)
    reduced: bool = True

    @classmethod
    def of(cls, model: MatrixModel, sensors) -> "DeckExplainModel":
        """The nominal of a deck seen at ``sensors``.

        Parameters
        ----------
        model : NastranModel
            A deck read by :func:`era.load_model` (era.models.nastran.read_bdf).
        sensors : sequence of (grid, direction)
            One per output channel, in channel order.

        Returns
        -------
        DeckExplainModel

        Raises
        ------
        era.DataError
            When the model was not read from a Nastran deck, or a sensor is not a free DOF of it.
        """
        if not isinstance(model, NastranModel) or model.deck is None:
            raise DataError("explain: this model was not read from a Nastran deck; use MatrixExplainModel.")
        return cls(MatrixExplainModel.of(model, sensors))

    @property
    def deck_model(self) -> NastranModel:
        """The deck as read (the nominal's NastranModel)."""
        model = self.nominal.model
        assert isinstance(model, NastranModel)
        return model

    @property
    def deck(self) -> Deck:
        """The deck's cards."""
        deck = self.deck_model.deck
        assert deck is not None
        return deck

    @property
    def params(self) -> dict:
        return dict(self._params)

    @property
    def sensors(self) -> tuple:
        return self.nominal.sensors

    def with_params(self, **changes) -> "DeckExplainModel":
        unknown = set(changes) - set(DECK_DEFAULTS)
        if unknown:
            raise DataError(f"DeckExplainModel: unknown parameters {listed(sorted(unknown), quote=True)}; known: "
                            f"{listed(sorted(DECK_DEFAULTS), quote=True)}.")
        return DeckExplainModel(self.nominal, {**self._params, **changes}, self._shared, self.reduced)

    @property
    def exact(self) -> "DeckExplainModel":
        return self if not self.reduced else DeckExplainModel(self.nominal, self._params, self._shared, False)

    def _inner(self) -> MatrixExplainModel:
        """The MatrixExplainModel of this parameter set: the (re-assembled) deck with the matrix keywords."""
        p = self._params
        matrix = {k: v for k, v in p.items() if k in EFFECT_DEFAULTS}
        base = self.nominal
        factor = float(p["property_factor"])
        if p["property_at"] is not None and factor != 1.0:
            key = property_key(p["property_at"])
            if key not in property_keys(self.deck):
                raise DataError(f"{key!r} is not a property of the deck; its properties are "
                                f"{listed(property_keys(self.deck))}.")
            if not np.isfinite(factor) or factor <= 0:
                raise DataError(f"property_factor = {factor:g}: a factor on a property must be positive.")
            got = self._shared.get((key, factor))
            if got is None:
                if len(self._shared) >= _KEPT:
                    self._shared.pop(next(k for k in self._shared if k != "variations"))
                variations = self._shared.setdefault("variations", {})
                if key not in variations:
                    variations[key] = property_variation(self.deck, key, self.deck_model)
                # another deck: solved in full (a reduced basis of its own would cost more than it saves)
                got = self._shared[(key, factor)] = MatrixExplainModel.of(
                    variations[key].model(self.deck_model, factor), self.sensors, reduced=False)
            base = got
        inner = base.with_params(**matrix)
        return inner if self.reduced else inner.exact

    # what explain asks: the matrix model's answers for this parameter set
    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised shapes at the sensors (n_sensors, n), as MatrixExplainModel.modes.

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        return self._inner().modes(n_modes)

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised shapes at every free translation (rows: node_labels).

        Parameters
        ----------
        n_modes : int, optional
            The number of lowest elastic modes (default 10).
        """
        return self._inner().node_modes(n_modes)

    @property
    def node_labels(self) -> tuple:
        return self.nominal.node_labels

    has_ritz = True

    def ritz(self, reference: Any, n_modes: int) -> RitzModes | None:
        """In the span of ``reference``'s nominal modes when both are the deck as read (a changed property is
        another deck: solved in full, None)."""
        if not isinstance(reference, DeckExplainModel):
            return None
        return self._inner().ritz(reference._inner(), n_modes)

    def screening_ritz(self, reference: Any, n_modes: int) -> RitzModes | None:
        return self.ritz(reference, n_modes)

    @property
    def joints_ft(self) -> np.ndarray:
        return np.zeros((0, 2))

    def modal_rows(self, input_locations) -> tuple | None:
        return self.nominal.modal_rows(input_locations)

    @property
    def default_model_form(self) -> tuple[float, float]:
        return self.nominal.default_model_form

    @property
    def default_member_scatter(self) -> float:
        return self.nominal.default_member_scatter

    def member_energy_fractions(self, n_modes: int = 10) -> np.ndarray | None:
        return self._inner().member_energy_fractions(n_modes)

    def member_shape_sensitivity(self, n_modes: int = 10) -> np.ndarray | None:
        return None

    def member_scale_sensitivity(self, node_rows, n_modes: int = 10) -> np.ndarray | None:
        return None
