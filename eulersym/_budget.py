"""Budgets for a block of symbolic work: ``with time_budget(2.0): ...`` raises :class:`BudgetExceeded` inside the
block once two seconds have passed; ``with symbolic_budget("proving H", seconds=60, memory=2**31): ...`` also
watches the process's resident memory and ends in :class:`eulersym.errors.OverBudget` naming what was being computed.

The interval timer (``SIGALRM``) interrupts SymPy wherever it is; it works on POSIX, in the main thread, when no
other timer is running (it never disturbs a timer someone else set). Elsewhere the block runs unbounded and the
context value is False, so callers that must stop on time also check the clock between steps.

Budgets nest: each block has its own deadline (and memory limit); the timer fires at the nearest one, and every
``memory_tick`` seconds while a memory limit is watched. An outer budget wins over an inner one: when the outer one
is spent inside an inner block — even one whose caller catches :class:`BudgetExceeded` and carries on — the timer
fires again as soon as the inner block ends, until the outer block has ended too.

The timer raises only where the exception can reach the block: Python drops (reports as "unraisable") an exception
raised in a ``__del__``, a garbage-collector callback or anything the collector runs, so when the timer finds the
interpreter there it does not raise; it fires again ``retry`` seconds later, and raises in the budgeted code itself
(after ``patience`` seconds of that it raises wherever it is, so that a budget always ends). Raising inside the
collector would not end it sooner anyway: it drops the exception and goes on with the next finalizer.

Examples
--------
>>> import time
>>> try:
...     with time_budget(0.05):
...         time.sleep(1)
... except BudgetExceeded:
...     print("stopped")
stopped
"""

from __future__ import annotations

import contextlib
import gc
import os
import signal
import threading
import time

__all__ = ["BudgetExceeded", "time_budget", "symbolic_budget", "resident_memory"]

#: Seconds between two looks at the resident memory while a memory limit is watched.
memory_tick = 0.05
#: Seconds until the timer fires again when it found the interpreter where an exception would be dropped, and the
#: most seconds it waits so (a full collection of a large heap takes seconds; past them it raises wherever the
#: interpreter is — ending a finalizer that runs away —, so that a budget always ends).
retry, patience = 1e-3, 10.0


class BudgetExceeded(BaseException):
    """Raised by the interval timer; a BaseException so that SymPy's ``except Exception`` cannot swallow it.

    ``frame`` is the budget that was spent (its ``spent`` says "time" or "memory")."""

    def __init__(self, frame=None):
        super().__init__()
        self.frame = frame


class _OuterSpent(BaseException):
    """An outer budget spent inside an inner block: not a :class:`BudgetExceeded`, so that the inner block's caller
    (``except BudgetExceeded``) does not take it for its own; it becomes one when it reaches its own block."""

    def __init__(self, frame):
        super().__init__()
        self.frame = frame


class _Frame:
    """One armed budget: a deadline (``time.monotonic``) and an optional resident-memory limit in bytes."""

    __slots__ = ("deadline", "memory", "spent", "rss", "spent_at")

    def __init__(self, deadline: float, memory: int | None):
        self.deadline, self.memory, self.spent, self.rss, self.spent_at = deadline, memory, None, 0, 0.0


_frames: list[_Frame] = []  # the budgets armed in the main thread, outermost first


def resident_memory() -> int:
    """The process's resident memory in bytes now (``/proc/self/statm``), or 0 where it cannot be read.

    Examples
    --------
    >>> resident_memory() > 0
    True
    """
    try:
        with open("/proc/self/statm", "rb") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


def _arm(at_least: float = 1e-3) -> None:
    """Set the timer for the nearest deadline of the armed budgets (sooner while memory is watched)."""
    if not _frames:
        signal.setitimer(signal.ITIMER_REAL, 0)
        return
    delay = min(f.deadline for f in _frames) - time.monotonic()
    if any(f.memory is not None for f in _frames):
        delay = min(delay, memory_tick)
    signal.setitimer(signal.ITIMER_REAL, max(delay, at_least))


def _tick(signum, frame) -> None:
    now = time.monotonic()
    rss = resident_memory() if any(f.memory is not None for f in _frames) else 0
    for f in _frames:  # outermost first: an outer budget that is spent wins
        if f.spent is None and now >= f.deadline:
            f.spent, f.spent_at = "time", now
        elif f.spent is None and f.memory is not None and rss > f.memory:
            f.spent, f.rss, f.spent_at = "memory", rss, now
        if f.spent is not None:
            if now - f.spent_at < patience and _dropped_here(frame):
                signal.setitimer(signal.ITIMER_REAL, retry)
                return
            _arm(at_least=memory_tick)  # again, should a catcher carry on, until its block has ended
            raise BudgetExceeded(f) if f is _frames[-1] else _OuterSpent(f)
    _arm()


_collecting = False  # a garbage collection is running (set by _watch_collections while a budget is armed)


def _watch_collections(phase, info) -> None:
    global _collecting
    _collecting = phase == "start"


def _watch(on: bool) -> None:
    """Follow the collector's runs (``gc.callbacks``) from the outermost budget's start to its end."""
    global _collecting
    _collecting = False
    if on:
        gc.callbacks.append(_watch_collections)
    else:
        gc.callbacks.remove(_watch_collections)


def _code(callback):
    """The code object a gc callback runs (a function, a bound method, or an object's ``__call__``)."""
    function = getattr(callback, "__func__", callback)
    return getattr(function, "__code__", None) or getattr(getattr(type(callback), "__call__", None), "__code__", None)


def _dropped_here(frame) -> bool:
    """Whether an exception raised in ``frame`` would be dropped by Python rather than reach the budgeted block:
    the collector is running (its callbacks, finalizers and weak-reference callbacks), or the stack holds a
    ``__del__`` or a gc callback (one that runs before or after ``_watch_collections`` in ``gc.callbacks``)."""
    if _collecting:
        return True
    callbacks = {_code(c) for c in gc.callbacks}
    while frame is not None:
        if frame.f_code.co_name == "__del__" or frame.f_code in callbacks:
            return True
        frame = frame.f_back
    return False


@contextlib.contextmanager
def _quiet():
    """The timer's signal held back (bookkeeping must not be interrupted half-way)."""
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGALRM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGALRM})


def _usable() -> bool:
    if not (hasattr(signal, "setitimer") and hasattr(signal, "pthread_sigmask")) or \
            threading.current_thread() is not threading.main_thread():
        return False
    if _frames:
        return signal.getsignal(signal.SIGALRM) is _tick
    return signal.getitimer(signal.ITIMER_REAL)[0] == 0  # never disturb a timer someone else set


@contextlib.contextmanager
def _budget(seconds: float | None, memory: int | None):
    """Arm one budget for the block; the context value is its frame, or None where no timer can be used."""
    if (seconds is None or seconds <= 0) and memory is None or not _usable():
        yield None
        return
    frame = _Frame(time.monotonic() + (seconds if seconds and seconds > 0 else float("inf")), memory)
    with _quiet():
        outermost = not _frames
        previous = signal.signal(signal.SIGALRM, _tick) if outermost else None
        if outermost:
            _watch(True)
        _frames.append(frame)
        _arm()
    try:
        yield frame
    except _OuterSpent as exc:
        if exc.frame is frame:
            raise BudgetExceeded(frame) from None
        raise
    finally:
        with _quiet():
            _frames.remove(frame)
            if outermost:
                signal.setitimer(signal.ITIMER_REAL, 0)
                if signal.SIGALRM in signal.sigpending():  # fired while held back: consume it here
                    signal.sigwait({signal.SIGALRM})
                signal.signal(signal.SIGALRM, previous)
                _watch(False)
            else:
                _arm()


@contextlib.contextmanager
def time_budget(seconds: float | None):
    """Raise :class:`BudgetExceeded` inside the block after ``seconds`` (see the module docstring); the context
    value says whether the timer is armed."""
    with _budget(seconds, None) as frame:
        yield frame is not None


@contextlib.contextmanager
def symbolic_budget(what: str, *, seconds: float | None = 60.0, memory: int | None = 2 << 30):
    """Run a block of symbolic work within ``seconds`` and ``memory`` bytes of resident memory beyond what the
    process holds on entry; past either, :class:`eulersym.errors.OverBudget` names ``what`` was being computed.

    Examples
    --------
    >>> import time
    >>> with symbolic_budget("counting sheep", seconds=0.05):
    ...     time.sleep(1)
    Traceback (most recent call last):
    ...
    eulersym.errors.OverBudget: counting sheep did not finish within its budget of 0.05 s (it was stopped after ... s)
    >>> hoard = []
    >>> with symbolic_budget("a list", memory=20 << 20):
    ...     for _ in range(400):
    ...         hoard.append(b"x" * (1 << 20))
    ...         time.sleep(0.002)
    Traceback (most recent call last):
    ...
    eulersym.errors.OverBudget: a list did not finish within its budget of 20 MiB of memory (it held ... MiB more)
    >>> del hoard
    """
    from eulersym.errors import OverBudget

    base = resident_memory()
    limit = base + memory if memory is not None and base else None
    start = time.monotonic()
    frame = None
    try:
        with _budget(seconds, limit) as frame:
            yield
    except BudgetExceeded as exc:
        if frame is None or exc.frame is not frame:
            raise
        if frame.spent == "memory":
            raise OverBudget(what, f"{memory / 2**20:.0f} MiB of memory",
                             f"it held {(frame.rss - base) / 2**20:.0f} MiB more") from None
        raise OverBudget(what, f"{seconds:g} s", f"it was stopped after {time.monotonic() - start:.2g} s") from None
