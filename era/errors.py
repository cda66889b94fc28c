"""The error family of the ERA core.

Every error is a ``ValueError`` whose message says what is wrong and what to change,
so the web app can show it to a person as it is.
"""


class EraError(ValueError):
    """Base class of every error raised by ``era`` for bad input or bad parameters."""


class DataError(EraError):
    """The response data (or a file holding it) is malformed: shape, NaN/inf, sampling step, labels."""


class HankelError(EraError):
    """The Hankel matrix cannot be built: bad shifts, too few samples, too large for this machine."""


class OrderError(EraError):
    """The requested model order is impossible: above the numerical rank or the basis kept."""
