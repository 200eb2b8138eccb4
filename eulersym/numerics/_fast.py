"""Optional numba JIT of the stepping loops (the ``fast`` extra).

The compiled loops are the very functions of :mod:`eulersym.numerics.splitting` and
:mod:`eulersym.numerics.heavy_top` (written in the subset numba compiles), registered with
``numba.extending.register_jitable`` and compiled with ``cache=True`` so the machine code is reused across
processes. Without numba nothing here is imported and the same functions run as plain Python.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["available", "select", "free_body_runner", "heavy_top_runner"]


def available() -> bool:
    """True when numba can be imported.

    Examples
    --------
    >>> isinstance(available(), bool)
    True
    """
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def select(fast, runner):
    """The compiled loop ``runner()`` per the ``fast`` option, or None for the plain-Python loop.

    ``fast``: None = compiled when numba is installed, True = compiled (numba required), False = plain Python.

    Examples
    --------
    >>> select(False, free_body_runner) is None
    True
    """
    from eulersym.errors import InvalidInput

    if not (fast is None or isinstance(fast, bool)):
        raise InvalidInput("fast", fast, "None (numba when installed), True or False")
    if fast is False:
        return None
    if not available():
        if fast:
            raise InvalidInput("fast", fast, "numba installed (pip install 'eulersym[fast]'), or fast=False/None")
        return None
    return runner()


@lru_cache(maxsize=1)
def free_body_runner():
    """``runner(kind, state, counts, steps, inv, par) -> out`` compiled from ``splitting._run_free``."""
    import numba
    from numba.extending import register_jitable

    from eulersym.numerics import splitting as S

    for fn in (S._flow1, S._flow2, S._flow3, S._strang, S._yoshida4, S._dmv_step):
        register_jitable(fn)
    run = numba.njit(cache=True)(S._run_free)

    def runner(kind, state, counts, steps, inv, par):
        return run(kind, np.asarray(state, dtype=np.float64), np.asarray(counts, dtype=np.int64),
                   np.asarray(steps, dtype=np.float64), tuple(inv), tuple(par), None, None)

    return runner


@lru_cache(maxsize=1)
def heavy_top_runner():
    """``runner(state, counts, steps, subs, i1inv, nu_coef, mgl) -> (out, kicks)`` compiled from ``heavy_top._run_top``."""
    import numba
    from numba.extending import register_jitable

    from eulersym.numerics import heavy_top as H
    from eulersym.quaternion import hamilton

    for fn in (hamilton, H._rotate_back, H._exp_half, H._free, H._kick, H._renormalise):
        register_jitable(fn)
    run = numba.njit(cache=True)(H._run_top)

    def runner(state, counts, steps, subs, i1inv, nu_coef, mgl):
        return run(np.asarray(state, dtype=np.float64), np.asarray(counts, dtype=np.int64),
                   np.asarray(steps, dtype=np.float64), tuple(subs), i1inv, nu_coef, mgl)

    return runner
