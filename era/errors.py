"""The error family of the ERA core.

Every error is a ``ValueError`` whose message says what is wrong and what to change,
so the web app can show it to a person as it is.
"""


class EraError(ValueError):
    """Base class of every error raised by ``era`` for bad input or bad parameters.

    option : the name of the parameter that fixes it (e.g. "dt" for a file without a sampling interval), or None;
        a form shows the message next to that control.
    """

    def __init__(self, *args, option: str | None = None):
        super().__init__(*args)
        self.option = option

    def __reduce__(self):  # keep `option` across processes (the app computes in a worker pool)
        return _rebuild, (type(self), self.args, self.option)


class DataError(EraError):
    """The response data (or a file holding it) is malformed: shape, NaN/inf, sampling step, labels."""


class HankelError(EraError):
    """The Hankel matrix cannot be built: bad shifts, too few samples, too large for this machine."""


class OrderError(EraError):
    """The requested model order is impossible: above the numerical rank or the basis kept."""


class TooLargeError(DataError):
    """A file (or an upload) is larger than a limit allows, e.g. it inflates past the uncompressed size one read
    may produce (era.io.inflate); the web app answers 413."""


def _rebuild(cls, args, option):
    return cls(*args, option=option)
