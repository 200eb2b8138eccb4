"""Whether the process that left a temporary file is still running (the generator's and the scene writer's
clean-up of what killed runs left behind)."""

from __future__ import annotations

import os

__all__ = ["alive"]


def alive(pid: int) -> bool:
    """True when process ``pid`` exists (this one included; one that is not ours counts as running).

    Examples
    --------
    >>> alive(os.getpid())
    True
    """
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, but not ours
        return True
    return True
