"""Pulse responses (Markov parameters) from every kind of test: FRFs, input-output records, ambient records,
free decays. Each function returns an :class:`era.ResponseData` ready for :func:`era.identify`."""

from .decay import markov_from_decay
from .frf import markov_from_frf
from .next import markov_from_ambient
from .okid import markov_from_io

__all__ = ["markov_from_frf", "markov_from_io", "markov_from_ambient", "markov_from_decay"]
