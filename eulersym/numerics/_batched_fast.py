"""numba-compiled member loops of the splittings (the ``fast`` extra): one member per thread with ``prange``.

The loop body is the plain-Python sub-flows of :mod:`eulersym.numerics.pivoted` (registered with
``numba.extending.register_jitable``), so the compiled and NumPy paths run the same arithmetic. Every function is
compiled with ``cache=True`` (eulersym's checked cache: :func:`eulersym.numerics._fast.njit`); ``parallel=True`` spreads members over the cores (``eulersym bench stress`` measures
when that pays). Nothing here is imported unless numba is installed and asked for.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from eulersym.numerics._fast import njit

__all__ = ["member_runner"]


def _members(state, par, hs, t, subs, kind, out):
    """Each member b: its own step ``hs[b]``, each output interval split in equal steps ≤ hs[b]; writes out[b]."""
    B = state.shape[1]
    n_out = t.shape[0]
    for b in _range(B):
        s = (state[0, b], state[1, b], state[2, b], state[3, b], state[4, b], state[5, b], state[6, b], state[7, b],
             state[8, b], state[9, b])
        p = (par[0, b], par[1, b], par[2, b], par[3, b], par[4, b], par[5, b], par[6, b], par[7, b], par[8, b],
             par[9, b])
        for k in range(10):
            out[b, 0, k] = s[k]
        for i in range(n_out - 1):
            dt = t[i + 1] - t[i]
            n = max(1, int(math.ceil(dt / hs[b] * (1.0 - 1e-12))))
            hk = dt / n
            for _ in range(n):
                for gam in subs:
                    s = _substep(s, gam * hk, p, kind, None, None)
                s = _renormalise(s, p)
            for k in range(10):
                out[b, i + 1, k] = s[k]
    return out


_range = range
_substep = None
_renormalise = None


@lru_cache(maxsize=4)
def _compiled(substep, renormalise, jitable, parallel: bool):
    import types

    import numba
    from numba.extending import register_jitable

    for fn in jitable:
        register_jitable(fn)
    glob = dict(_members.__globals__)
    glob.update(_range=numba.prange if parallel else range, _substep=substep, _renormalise=renormalise)
    name = "_members_parallel" if parallel else "_members_serial"
    fn = types.FunctionType(_members.__code__, glob, name)
    fn.__qualname__ = name  # distinct cache entries for the two variants
    return njit(fn, cache=True, parallel=parallel)


def member_runner(substep, renormalise, jitable, parallel: bool = False):
    """``runner(state (10, B), par (10, B), hs (B,), t (n,), subs, kind) -> out (B, n, 10)``, compiled.

    ``substep(s, tau, par, kind, None, None)`` and ``renormalise(s, par)`` are the plain-Python step functions
    (:mod:`eulersym.numerics.pivoted`), ``jitable`` every function they call (registered for numba).

    Examples
    --------
    >>> import numpy as np
    >>> from eulersym.numerics import pivoted
    >>> run = pivoted._compiled_runner(False)
    >>> s = np.array([[0.0], [0.0], [1.0], [0.0], [0.0], [1.0], [1.0], [0.0], [0.0], [0.0]])
    >>> par = np.array([[1.0], [1.0], [1.0], [0.0], [0.0], [0.0], [0.0], [0.0], [0.0], [1.0]])
    >>> out = run(s, par, np.array([0.1]), np.array([0.0, 1.0]), (1.0,), 0)
    >>> out.shape
    (1, 2, 10)
    """
    run = _compiled(substep, renormalise, tuple(jitable), bool(parallel))

    def runner(state, par, hs, t, subs, kind):
        state = np.ascontiguousarray(state, dtype=np.float64)
        out = np.empty((state.shape[1], len(t), 10))
        return run(state, np.ascontiguousarray(par, dtype=np.float64), np.asarray(hs, dtype=np.float64),
                   np.asarray(t, dtype=np.float64), tuple(float(x) for x in subs), int(kind), out)

    return runner
