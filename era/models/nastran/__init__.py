"""Nastran bulk data in: a deck (small, large or free field, INCLUDE files) as the engineer's FE model
(:func:`read_bdf`, a MatrixModel with notes), a property changed by a factor (:func:`deck_model`), and a named
effect written back as bulk data the engineer includes (era.models.nastran.patch)."""

from .deck import Deck, read_deck
from .patch import DeckPatch, deck_patch, deck_patch_for, write_patched_deck
from .reader import NastranModel, deck_model, read_bdf

__all__ = ["read_bdf", "read_deck", "deck_model", "NastranModel", "Deck", "DeckPatch", "deck_patch",
           "deck_patch_for", "write_patched_deck"]
