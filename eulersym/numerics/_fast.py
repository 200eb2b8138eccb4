"""Optional numba JIT of the stepping loops (the ``fast`` extra).

The compiled loops are the very functions of :mod:`eulersym.numerics.splitting` and
:mod:`eulersym.numerics.heavy_top` (written in the subset numba compiles), registered with
``numba.extending.register_jitable`` and compiled by :func:`njit` with ``cache=True`` so the machine code is reused
across processes. Without numba nothing here is imported and the same functions run as plain Python.

:func:`njit` is ``numba.njit`` whose on-disk cache is eulersym's (:mod:`eulersym.numerics._numba_cache`): in a
private folder under eulersym's cache root, every file checked by its hash before it is unpickled, a damaged entry
removed and compiled again with a one-line :class:`~eulersym.errors.CacheRepaired` warning, and no cache (instead
of numba's "no locator available") where no folder can be written. Every ``cache=True`` function of eulersym is
compiled through it.

:func:`batched` compiles the ``<name>_loop`` flavour of a generated kernel module (plain loops over the columns
calling ``<name>_flat``) the same way: the generated module never imports numba, and the machine code is cached on
disk beside it, so a second process loads it instead of compiling.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["available", "select", "batched", "njit"]


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


def njit(function=None, /, *, cache: bool = False, **options):
    """``numba.njit(**options)``, with eulersym's checked, private, self-repairing on-disk cache when ``cache=True``
    (see the module docstring). Used as numba's: ``@njit(cache=True, parallel=True)`` or ``njit(f, cache=True)``.

    numba is imported when a function is decorated (call this only where numba is to be used).

    Examples
    --------
    >>> def twice(x):
    ...     return 2.0 * x
    >>> njit(twice, cache=True)(1.5) if available() else 3.0
    3.0
    """
    import numba

    def decorate(py_func):
        dispatcher = numba.njit(**options)(py_func)
        if cache:
            from eulersym.numerics._numba_cache import CheckedCache

            dispatcher._cache = CheckedCache(py_func)  # what Dispatcher.enable_caching does, with eulersym's cache
        return dispatcher

    return decorate if function is None else decorate(function)


def select(fast, runner):
    """The compiled loop ``runner()`` per the ``fast`` option, or None for the plain-Python loop.

    ``fast``: None = compiled when numba is installed, True = compiled (numba required), False = plain Python.

    Examples
    --------
    >>> select(False, lambda: 'compiled') is None
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


@lru_cache(maxsize=None)
def _compiled_loop(module, name):
    from numba.extending import register_jitable

    register_jitable(error_model="numpy")(getattr(module, name + "_flat"))
    return njit(getattr(module, name + "_loop"), cache=True, error_model="numpy")


def batched(module, name="rhs"):
    """``f(*args, out=None)``: the generated ``module.<name>_loop`` compiled by numba (cached on disk).

    The same values as ``module.<name>_batched`` (to round-off) at about the speed of copying the state: vectors
    of shape ``(k, n)`` (a 1-d batch of n), every other argument a float. Arguments are checked like the
    batched flavour (on one column); ``out``, if given, is a C-contiguous float64 array of the output's shape
    that does not overlap the inputs. Requires numba (the ``fast`` extra).

    Parameters
    ----------
    module : module
        A generated kernel module (``eulersym.generated.<name>`` or a model's).
    name : str
        The function: ``"rhs"``, ``"jac"``, ``"invariants"``, ...

    Examples
    --------
    >>> import numpy as np
    >>> from eulersym.generated import euler_principal as kernel
    >>> rhs = batched(kernel, "rhs")
    >>> y = np.array([[1.0, 0.0], [0.5, 1.0], [0.2, 2.0]])
    >>> bool(np.allclose(rhs(0.0, y, 1.0, 2.0, 3.0, 0.0, 0.0, 0.0), kernel.rhs_batched(0.0, y, 1, 2, 3, 0, 0, 0)))
    True
    """
    from eulersym.errors import InvalidInput

    if not hasattr(module, f"{name}_loop"):
        raise InvalidInput("name", name, f"a function of {getattr(module, '__name__', module)} with a _loop flavour "
                           "(regenerate the module with this eulersym)")
    if not available():
        raise InvalidInput("numba", "not installed", "numba (pip install 'eulersym[fast]') for the compiled path")
    loop = _compiled_loop(module, name)
    check = getattr(module, f"{name}_batched")

    def run(*args, out=None):
        args = [np.ascontiguousarray(a, dtype=np.float64) if np.ndim(a) else float(a) for a in args]
        widths = {a.shape[-1] for a in args if isinstance(a, np.ndarray)}
        if any(isinstance(a, np.ndarray) and a.ndim != 2 for a in args) or len(widths) != 1:
            shapes = [np.shape(a) for a in args]
            raise InvalidInput("arguments", f"shapes {shapes}", "vectors of shape (k, n) with one batch n and "
                               f"float parameters (per-member parameters: {name}_batched)")
        n = widths.pop()
        head = check(*[a[:, :1] if isinstance(a, np.ndarray) else a for a in args]).shape[:-1]
        shape = head + (n,)
        if out is None:
            out = np.empty(shape)
        elif (not isinstance(out, np.ndarray) or out.shape != shape or out.dtype != np.float64
              or not out.flags.c_contiguous):
            raise InvalidInput("out", f"{type(out).__name__} of shape {getattr(out, 'shape', None)}",
                               f"a C-contiguous float64 ndarray of shape {shape}")
        elif any(isinstance(a, np.ndarray) and np.may_share_memory(out, a) for a in args):
            raise InvalidInput("out", "an array overlapping an input", "a separate array (out is written in place)")
        return loop(*args, out)

    run.__doc__ = f"{name}_loop of {module.__name__}, compiled by numba; see eulersym.numerics._fast.batched."
    return run
