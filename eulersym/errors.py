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
    "OverBudget",
    "EulersymWarning",
    "CacheRepaired",
    "AccuracyNotReached",
    "accuracy_status",
    "ACCURACY_NOT_REACHED_EXIT",
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


class OverBudget(EulersymError, RuntimeError):
    """A piece of symbolic work (a derivation, a proof, a comparison) did not finish within its time or memory
    budget: it was stopped, and nothing it would have produced was kept.

    Parameters
    ----------
    what : str
        What was being computed (the model, the expression, the step).
    budget : str
        The budget that was spent ("60 s", "2048 MiB of memory").
    detail : str, optional
        How far it got.

    Examples
    --------
    >>> raise OverBudget("the kernel of model 'spin'", "60 s", "it was stopped after 60 s")
    Traceback (most recent call last):
    ...
    eulersym.errors.OverBudget: the kernel of model 'spin' did not finish within its budget of 60 s (it was stopped after 60 s)
    """

    def __init__(self, what: str, budget: str, detail: str = ""):
        self.what, self.budget, self.detail = what, budget, detail
        Exception.__init__(self, f"{what} did not finish within its budget of {budget}" + (f" ({detail})" if detail
                                                                                            else ""))

    def __reduce__(self):
        return (type(self), (self.what, self.budget, self.detail))


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
    ``eulersym simulate`` still prints and writes that result, names the members beyond the accuracy, and exits with
    status :data:`ACCURACY_NOT_REACHED_EXIT` (3; :func:`accuracy_status`).

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


#: The exit status of ``eulersym simulate`` when the run finished — its report printed, its result written — but its
#: estimated error exceeds the accuracy asked, for the motion or for some members of a sweep (0: reached; 1: a check
#: failed; 2: bad usage or input, nothing written). :func:`accuracy_status` decides it from the result.
ACCURACY_NOT_REACHED_EXIT = 3


def accuracy_status(result, *, shown: int = 10) -> tuple:
    """``(exit status, message)`` of a finished run against the accuracy it asked: ``(0, "")`` when every estimate is
    within it (or nothing was estimated: a closed form is exact to round-off), else
    ``(ACCURACY_NOT_REACHED_EXIT, message)``, the message naming the members beyond it (index, swept values and
    estimate; the first ``shown``, the worst first) — what ``eulersym simulate`` prints and returns after writing the
    result. The run has already warned (:class:`AccuracyNotReached`: why, and what would help).

    Parameters
    ----------
    result : eulersym.scene.Result
        Read through ``error`` (quantity → estimate, a float or one per member), ``accuracy`` and ``sweep`` (label →
        the members' values).
    shown : int
        Members named at most.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> accuracy_status(NS(error={"omega": 3e-10}, accuracy=1e-9, sweep={}))
    (0, '')
    >>> accuracy_status(NS(error={}, accuracy=1e-9, sweep={}))  # a closed form
    (0, '')
    >>> print(accuracy_status(NS(error={"omega": 6e-12, "gamma": 2e-12}, accuracy=1e-12, sweep={}))[1])
    accuracy 1e-12 not reached: estimated error 6e-12 (the result is reported and written with its estimate)
    >>> import numpy as np
    >>> sweep = NS(error={"omega": np.array([1e-10, 4e-9, 2e-9])}, accuracy=1e-9, sweep={"omega3": np.array([1., 2., 3.])})
    >>> status, message = accuracy_status(sweep)
    >>> status
    3
    >>> print(message)
    accuracy 1e-09 not reached for 2 of 3 members: 1 (omega3 = 2; estimated 4e-09), 2 (omega3 = 3; estimated 2e-09) (the result is reported and written with each member's estimate)
    """
    import numpy as np

    asked = getattr(result, "accuracy", None)
    error = getattr(result, "error", None) or {}
    if asked is None or not error:
        return 0, ""
    worst = np.max(np.stack([np.atleast_1d(np.asarray(v, dtype=float)) for v in error.values()]), axis=0)
    beyond = np.flatnonzero(~(worst <= asked))  # NaN counts as not reached
    if not len(beyond):
        return 0, ""
    if len(worst) == 1:
        return ACCURACY_NOT_REACHED_EXIT, (f"accuracy {asked:g} not reached: estimated error {float(worst[0]):.2g} "
                                           "(the result is reported and written with its estimate)")
    sweep = getattr(result, "sweep", None) or {}
    order = beyond[np.argsort(-worst[beyond], kind="stable")][:max(1, int(shown))]
    names = []
    for b in order:
        values = "; ".join(f"{label} = {float(np.asarray(v)[b]):.6g}" for label, v in sweep.items())
        names.append(f"{int(b)} ({values + '; ' if values else ''}estimated {float(worst[b]):.2g})")
    more = ", …" if len(beyond) > len(order) else ""
    return ACCURACY_NOT_REACHED_EXIT, (f"accuracy {asked:g} not reached for {len(beyond)} of {len(worst)} members: "
                                       + ", ".join(names) + more
                                       + " (the result is reported and written with each member's estimate)")
