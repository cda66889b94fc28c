"""The error family of the ERA core.

Every error is a ``ValueError`` whose message says what is wrong and what to change,
so the web app can show it to a person as it is.
"""


class EraError(ValueError):
    """Base class of every error raised by ``era`` for bad input or bad parameters.

    A ``ValueError`` whose message says what is wrong and what to change.

    Parameters
    ----------
    *args
        The message (as ``ValueError`` takes it).
    option : str, optional
        The name of the parameter that fixes it (e.g. "dt" for a file without a sampling interval), or None;
        a form shows the message next to that control.

    Examples
    --------
    >>> try:
    ...     era.ResponseData(np.ones(10), dt=-1)
    ... except era.EraError as error:
    ...     print(type(error).__name__, "-", error)
    DataError - `dt` must be a positive, finite sampling interval in seconds, got -1.
    >>> era.EraError("no sampling interval", option="dt").option
    'dt'
    """

    def __init__(self, *args, option: str | None = None):
        super().__init__(*args)
        self.option = option

    def __reduce__(self):  # keep `option` across processes (the app computes in a worker pool)
        return _rebuild, (type(self), self.args, self.option)


class DataError(EraError):
    """The response data (or a file holding it) is malformed: shape, NaN/inf, sampling step, labels.

    Parameters
    ----------
    *args
        The message.
    option : str, optional
        The parameter that fixes it, as :class:`EraError`'s.

    Examples
    --------
    >>> try:
    ...     era.ResponseData(np.array([1.0, np.nan]), dt=0.01)
    ... except era.DataError as error:
    ...     print(error)  # doctest: +ELLIPSIS
    `markov` holds 1 NaN or infinite value, the first at sample 1, output 0, input 0; remove or interpolate...
    """


class HankelError(EraError):
    """The Hankel matrix cannot be built: bad shifts, too few samples, too large for this machine.

    Parameters
    ----------
    *args
        The message.
    option : str, optional
        The parameter that fixes it, as :class:`EraError`'s.

    Examples
    --------
    >>> try:
    ...     era.identify(era.ResponseData(np.ones(10), dt=0.01), rows=8, cols=8)
    ... except era.HankelError as error:
    ...     print(type(error).__name__, isinstance(error, era.EraError))
    HankelError True
    """


class OrderError(EraError):
    """The requested model order is impossible: above the numerical rank or the basis kept.

    Parameters
    ----------
    *args
        The message.
    option : str, optional
        The parameter that fixes it, as :class:`EraError`'s.

    Examples
    --------
    >>> from era.examples import paper_cases
    >>> ident = era.identify(paper_cases.case_1(), 40, 40)
    >>> try:
    ...     ident.realize(12)
    ... except era.OrderError as error:
    ...     print(error)
    Order 12 is above the numerical rank of H(0), 10: the singular values past it are round-off. Choose an order ≤ 10.
    """


class TooLargeError(DataError):
    """A file (or an upload) is larger than a limit allows.

    E.g. it inflates past the uncompressed size one read may produce (era.io.inflate); the web app answers 413.

    Parameters
    ----------
    *args
        The message.
    option : str, optional
        The parameter that fixes it, as :class:`EraError`'s.

    Examples
    --------
    >>> import io
    >>> buffer = io.BytesIO()
    >>> era.save_npz(buffer, era.ResponseData(np.zeros((1000, 2)), dt=0.01))
    >>> try:
    ...     era.load(io.BytesIO(buffer.getvalue()), name="big.npz", max_bytes=1000)
    ... except era.TooLargeError as error:
    ...     print(type(error).__name__, isinstance(error, era.DataError))
    TooLargeError True
    """


def _rebuild(cls, args, option):
    return cls(*args, option=option)
