"""The exceptions eulersym raises on purpose.

Every error names the argument, the value that was given, and what would have been valid::

    >>> from eulersym.errors import InvalidInput
    >>> raise InvalidInput("convention", "zzz", "one of the 12 sequences such as 'zxz' or 'xyz'")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: convention='zzz' is not valid: expected one of the 12 sequences such as 'zxz' or 'xyz'
"""

from __future__ import annotations

__all__ = [
    "EulersymError",
    "InvalidInput",
    "SingularConfiguration",
    "UnsafeExpression",
    "CheckFailed",
    "IntegrationFailed",
    "CacheError",
    "EulersymWarning",
    "CacheRepaired",
    "AccuracyNotReached",
]

_MAX_REPR = 120


def _short_repr(value: object) -> str:
    text = " ".join(repr(value).split())  # one line, whatever the value (an array's repr spans several)
    if len(text) > _MAX_REPR:
        text = text[: _MAX_REPR - 3] + "..."
    return text


class EulersymError(Exception):
    """Base class of every error eulersym raises on purpose."""


class InvalidInput(EulersymError, ValueError):
    """An argument has a value the function cannot accept.

    Parameters
    ----------
    argument : str
        The name of the argument, as the caller wrote it.
    value : object
        The value that was given (shown through ``repr``, shortened).
    expected : str
        What would have been valid.

    Examples
    --------
    >>> err = InvalidInput("M", -1, "a positive mass")
    >>> print(err)
    M=-1 is not valid: expected a positive mass
    >>> err.argument, err.value
    ('M', -1)
    """

    def __init__(self, argument: str, value: object, expected: str):
        self.argument = argument
        self.value = value
        self.expected = expected
        super().__init__(f"{argument}={_short_repr(value)} is not valid: expected {expected}")

    def __reduce__(self):  # keep pickling (multiprocessing, pytest-xdist) working
        return (type(self), (self.argument, self.value, self.expected))


class SingularConfiguration(InvalidInput):
    """The configuration sits on a singularity of the chosen coordinates (e.g. sin θ = 0 for Euler angles).

    Examples
    --------
    >>> raise SingularConfiguration("theta", 0.0, "sin(theta) != 0; use quaternions at this attitude")
    Traceback (most recent call last):
    ...
    eulersym.errors.SingularConfiguration: theta=0.0 is not valid: expected sin(theta) != 0; use quaternions at this attitude
    """


class UnsafeExpression(InvalidInput):
    """A string given as a formula holds something other than plain mathematics.

    Examples
    --------
    >>> print(UnsafeExpression("candidate", "os.system", "plain math: names, numbers, + - * / ^ and known functions"))
    candidate='os.system' is not valid: expected plain math: names, numbers, + - * / ^ and known functions
    """


class CheckFailed(EulersymError):
    """A check of a derived result (against the text, a generated file or a tolerance) did not pass.

    Examples
    --------
    >>> raise CheckFailed("generated/euler.py is stale; run `eulersym generate`")
    Traceback (most recent call last):
    ...
    eulersym.errors.CheckFailed: generated/euler.py is stale; run `eulersym generate`
    """


class IntegrationFailed(EulersymError, RuntimeError):
    """A method could not get the motion of an input that was valid: a state overflowed, no step could meet the
    tolerance. (Bad input is :class:`InvalidInput`; this is the run's own failure, as ``solve_ivp`` reports it with
    ``success = False``.)

    Parameters
    ----------
    method : str
        The method that failed (``"batched_dop853"``, ``"ivp"``...).
    reason : str
        What happened.
    hint : str, optional
        What might get the motion instead.

    Examples
    --------
    >>> raise IntegrationFailed("ivp", "DOP853: required step size is less than spacing between numbers", "a looser accuracy")
    Traceback (most recent call last):
    ...
    eulersym.errors.IntegrationFailed: the method 'ivp' could not get the motion: DOP853: required step size is less than spacing between numbers (try a looser accuracy)
    """

    def __init__(self, method: str, reason: str, hint: str = ""):
        self.method = method
        self.reason = reason
        self.hint = hint
        text = f"the method {method!r} could not get the motion: {reason}" + (f" (try {hint})" if hint else "")
        Exception.__init__(self, text)

    def __reduce__(self):
        return (type(self), (self.method, self.reason, self.hint))


class CacheError(EulersymError, OSError):
    """The kernel cache cannot be used: a folder another user could write into, a full disk, no permission.

    Parameters
    ----------
    path : path-like
        The folder or file concerned.
    reason : str
        What is wrong with it.
    errno : int, optional
        The operating system's error number, when one caused it.

    Examples
    --------
    >>> raise CacheError("/tmp/cache/models", "it is writable by others (mode 0777)")
    Traceback (most recent call last):
    ...
    eulersym.errors.CacheError: the kernel cache /tmp/cache/models cannot be used: it is writable by others (mode 0777)
    """

    def __init__(self, path, reason: str, errno: int | None = None):
        self.path = str(path)
        self.reason = reason
        text = f"the kernel cache {self.path} cannot be used: {reason}"
        if errno is not None:
            import errno as _errno

            text += f" [errno {errno}: {_errno.errorcode.get(errno, '?')}]"
        Exception.__init__(self, text)
        self.errno = errno
        self.strerror = reason
        self.filename = self.path

    def __str__(self) -> str:
        return self.args[0]

    def __reduce__(self):
        return (type(self), (self.path, self.reason, self.errno))


class EulersymWarning(UserWarning):
    """Base class of the warnings eulersym issues (the command line prints them as one ``eulersym: note:`` line)."""


class CacheRepaired(EulersymWarning):
    """A damaged entry of the kernel cache was removed and built again (the message says which and why).

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warnings.warn("the cached kernel x.py was damaged: rebuilt", CacheRepaired)
    >>> caught[0].category.__name__
    'CacheRepaired'
    """


class AccuracyNotReached(EulersymWarning):
    """The accuracy asked cannot be delivered in double precision over the run's span: the motion amplifies the
    round-off of its steps beyond it (a chaotic motion, or one near a separatrix, or simply a long one). The run still
    returns the best motion it could get, with its estimated error (``Result.error``), never a silently worse one;
    the message gives the amplification (the largest singular value of the state-transition matrix, from the
    variational equations), the best accuracy reached, and what would help (a coarser accuracy, a shorter span).

    Attributes
    ----------
    accuracy, reached : float
        What was asked, and the estimated error of the result.
    amplification : float or None
        How much a change of the start grows over the span (None when it was not computed).

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warnings.warn(AccuracyNotReached("accuracy 1e-12 is not reachable", accuracy=1e-12, reached=6e-12,
    ...                                      amplification=2e3))
    >>> caught[0].category.__name__, caught[0].message.reached
    ('AccuracyNotReached', 6e-12)
    """

    def __init__(self, message: str, *, accuracy: float = float("nan"), reached: float = float("nan"),
                 amplification: float | None = None):
        super().__init__(message)
        self.accuracy = accuracy
        self.reached = reached
        self.amplification = amplification

    def __reduce__(self):
        return (_rebuild_not_reached, (str(self), self.accuracy, self.reached, self.amplification))


def _rebuild_not_reached(message, accuracy, reached, amplification):
    return AccuracyNotReached(message, accuracy=accuracy, reached=reached, amplification=amplification)
