"""A wall-clock budget for a block of symbolic work: ``with time_budget(2.0): ...`` raises
:class:`BudgetExceeded` inside the block once two seconds have passed.

The interval timer (``SIGALRM``) interrupts SymPy wherever it is; it works on POSIX, in the main thread, when no
other timer is running (it never disturbs a timer someone else set). Elsewhere the block runs unbounded and the
context value is False, so callers that must stop on time also check the clock between steps.

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
import signal
import threading

__all__ = ["BudgetExceeded", "time_budget"]


class BudgetExceeded(BaseException):
    """Raised by the interval timer; a BaseException so that SymPy's ``except Exception`` cannot swallow it."""


@contextlib.contextmanager
def time_budget(seconds: float | None):
    """Raise :class:`BudgetExceeded` inside the block after ``seconds`` (see the module docstring); the context
    value says whether the timer is armed."""
    usable = (seconds is not None and seconds > 0 and hasattr(signal, "setitimer")
              and threading.current_thread() is threading.main_thread()
              and signal.getitimer(signal.ITIMER_REAL)[0] == 0)  # never disturb a timer someone else set
    if not usable:
        yield False
        return

    def _expired(signum, frame):
        raise BudgetExceeded()

    previous = signal.signal(signal.SIGALRM, _expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield True
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
