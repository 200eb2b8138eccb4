"""eulersym's own DOP853: Dormand–Prince 8(5,3) compiled by numba over any generated kernel, a step per member,
with dense output — no ``scipy.integrate``, no per-call overhead of ``solve_ivp``.

The algorithm is SciPy's DOP853 (:mod:`~eulersym.numerics.methods._dop853_tableau`: Hairer's coefficients, the
error norm with the 3rd- and 5th-order estimates, the initial step of Hairer, Nørsett & Wanner, the step control
with safety 0.9 and factors in [0.2, 10], no growth right after a rejection) with three changes that matter for the
*global* error over long spans:

- **dense output**: steps are not cut at the output times; the output values come from the 7th-order interpolant of
  the step that holds them (its three extra stages are evaluated only in steps that hold an output time);
- **compensated summation** of the state (``y ← y + Δ`` carried as a sum of two doubles, as Hairer, Lubich & Wanner
  recommend for long integrations, §VIII.5): the round-off of 10⁶ additions no longer walks the state;
- **the time in double-double**: the exact sum of the steps taken, so an output at t = 10³ is interpolated at
  t = 10³, not at 10³ plus the round-off of 10⁵ additions.

and, as SciPy's ``max_step``, a **step cap** per member: near round-off, where a tolerance alone no longer lowers the
error, more and shorter steps do (a step's round-off is ∝ its length, so over N steps ∝ 1/√N) — what the accuracy
control asks for (:func:`eulersym.numerics.methods._accuracy.deliver`).

A kernel is any module with ``rhs_flat(t, *state, *parameters)`` (every generated module, a model's own included,
and ``STATE``/``PARAMETERS``). Its right-hand side is wrapped once in a numba ``cfunc`` (cached on disk beside the
kernel's file, named by the kernel's bytes), and the one stepping loop — compiled once, cached, shared by every
kernel — calls it through a function pointer. Members run in a ``prange`` loop when there are several, each with its
own step, so a member's numbers depend on its own start only.

A member that leaves the finite numbers (an overflow; ``log``, ``sqrt``, ``asin`` of a value outside their domain
give NaN here, not an exception) stops with :data:`NOT_FINITE`, one whose step underflows with
:data:`STEP_UNDERFLOW`, one past ``max_steps`` with :data:`TOO_MANY_STEPS`; its time and its last finite state are
kept for the message (:func:`integrate` returns them; the methods raise
:class:`~eulersym.errors.IntegrationFailed`).

Needs the optional ``fast`` extra (numba): import this module only when it is installed.

Examples
--------
>>> from eulersym.generated import euler_principal as kernel
>>> t = np.linspace(0.0, 10.0, 5)
>>> run = integrate(kernel, [[1.0, 0.5, 0.2]], t, [[1.0, 2.0, 3.0, 0.0, 0.0, 0.0]], rtol=1e-10, atol=1e-13)
>>> run.y.shape, int(run.status[0])
((1, 5, 3), 0)
>>> w = run.y[0]; E = 0.5 * (w[:, 0]**2 + 2 * w[:, 1]**2 + 3 * w[:, 2]**2)
>>> bool(np.ptp(E) < 1e-10)
True
"""

from __future__ import annotations

import hashlib
import marshal
import math
import operator
import os
import types
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numba
import numpy as np
from numba import types as nt
from numba.core import sigutils
from numba.np.unsafe.ndarray import to_fixed_tuple

from eulersym.numerics.methods import _dop853_tableau as _T

__all__ = ["integrate", "Run", "rhs_function", "variational_function", "OK", "NOT_FINITE", "STEP_UNDERFLOW", "TOO_MANY_STEPS", "STATUS"]

OK, NOT_FINITE, STEP_UNDERFLOW, TOO_MANY_STEPS = 0, 1, 2, 3
#: What each status means, for messages.
STATUS = {
    OK: "reached the last output time",
    NOT_FINITE: "the right-hand side left the finite numbers (an overflow, or log/sqrt/asin/acos of a value outside "
                "its domain, or a division by zero)",
    STEP_UNDERFLOW: "the step size underflowed (no step meets the tolerance: a singularity of the right-hand side, "
                    "or a tolerance below round-off)",
    TOO_MANY_STEPS: "it took more steps than allowed (the motion is too fast for the span, or the tolerance too "
                    "tight)",
}


def _dense(rows, width):
    a = np.zeros((len(rows), width))
    for s, row in enumerate(rows):
        for j, value in row:
            a[s, j] = value
    return a


_A = _dense(_T.A, _T.N_STAGES_EXTENDED)
_C = np.array(_T.C)
_B = np.array(_T.B)
_E3 = np.array(_T.E3[:_T.N_STAGES])  # the 13th weight (f at the step's end) is zero in both estimates
_E5 = np.array(_T.E5[:_T.N_STAGES])
_D = _dense(_T.D, _T.N_STAGES_EXTENDED)
if _T.E3[-1] != 0.0 or _T.E5[-1] != 0.0:  # pragma: no cover - the tableau is fixed
    raise RuntimeError("DOP853's error estimates are expected not to use f at the step's end")
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
EXPONENT = -1.0 / (_T.ERROR_ESTIMATOR_ORDER + 1)

#: The right-hand side as the stepping loop calls it: ``f(t, y*, p*, out*)``, pointers to float64.
SIGNATURE = nt.void(nt.float64, nt.CPointer(nt.float64), nt.CPointer(nt.float64), nt.CPointer(nt.float64))
_SIGNATURE = sigutils.normalize_signature(SIGNATURE)  # (arguments, return type), as a cfunc's signature has them


# ----------------------------------------------------------------------------------------------------------------
# The stepping loop (compiled once, cached; the right-hand side comes in as a function pointer)
# ----------------------------------------------------------------------------------------------------------------
@numba.njit(cache=True, error_model="numpy")
def _finite(x):
    for i in range(x.shape[0]):
        if not np.isfinite(x[i]):
            return False
    return True


@numba.njit(cache=True, error_model="numpy")
def _stage(y, K, s, h, out):
    """out = y + h Σ_{j<s} A[s, j] K[j]."""
    n = y.shape[0]
    for i in range(n):
        acc = 0.0
        for j in range(s):
            acc += _A[s, j] * K[j, i]
        out[i] = y[i] + h * acc


@numba.njit(cache=True, error_model="numpy")
def _member(f, y0, p, t_eval, rtol, atol, max_step, max_steps, out, last):
    """One member over ``t_eval`` into ``out`` (m, n), no step longer than ``max_step``; returns (calls, status, time
    reached, steps accepted) and leaves its last finite state in ``last``."""
    n = y0.shape[0]
    m = t_eval.shape[0]
    K = np.empty((16, n))
    y = y0.copy()
    comp = np.zeros(n)  # y + comp is the state: compensated summation
    ynew = np.empty(n)
    cnew = np.empty(n)
    inc = np.empty(n)
    stage = np.empty(n)
    F = np.empty((7, n))
    for i in range(n):
        out[0, i] = y[i]
        last[i] = y[i]
    th = t_eval[0]
    tl = 0.0  # the time is th + tl, the exact sum of the steps
    t_end = t_eval[m - 1]
    f(th, y.ctypes, p.ctypes, K[0].ctypes)
    calls = 1
    if not _finite(K[0]):
        return calls, 1, th, 0
    span = t_end - th
    if m == 1 or not span > 0.0:
        for k in range(1, m):
            for i in range(n):
                out[k, i] = y[i]
        return calls, 0, th, 0
    # the initial step: scipy's select_initial_step (Hairer, Nørsett & Wanner), order 8
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = atol + abs(y[i]) * rtol
        d0 += (y[i] / sc) ** 2
        d1 += (K[0, i] / sc) ** 2
    d0 = math.sqrt(d0 / n)
    d1 = math.sqrt(d1 / n)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, span)
    for i in range(n):
        stage[i] = y[i] + h0 * K[0, i]
    f(th + h0, stage.ctypes, p.ctypes, K[1].ctypes)
    calls += 1
    d2 = 0.0
    for i in range(n):
        sc = atol + abs(y[i]) * rtol
        d2 += ((K[1, i] - K[0, i]) / sc) ** 2
    d2 = math.sqrt(d2 / n) / h0
    if not np.isfinite(d2):
        return calls, 1, th, 0
    if max(d1, d2) <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 9.0)
    h = min(100.0 * h0, h1, span, max_step)
    k_out = 1
    steps = 0
    while k_out < m:
        remaining = (t_end - th) - tl
        min_step = 10.0 * (np.nextafter(th, np.inf) - th)
        if h < min_step:
            h = min_step
        rejected = False
        factor = 1.0
        hu = h
        final = False
        while True:
            if h < min_step:
                return calls, 2, th + tl, steps
            hu = h
            final = hu >= remaining
            if final:
                hu = remaining
            for s in range(1, 12):
                _stage(y, K, s, hu, stage)
                f(th + (tl + _C[s] * hu), stage.ctypes, p.ctypes, K[s].ctypes)
            calls += 11
            e5 = 0.0
            e3 = 0.0
            for i in range(n):
                acc = 0.0
                v5 = 0.0
                v3 = 0.0
                for j in range(12):
                    k = K[j, i]
                    acc += _B[j] * k
                    v5 += _E5[j] * k
                    v3 += _E3[j] * k
                inc[i] = hu * acc
                d = inc[i] + comp[i]
                s_ = y[i] + d
                bb = s_ - y[i]
                cnew[i] = (y[i] - (s_ - bb)) + (d - bb)  # TwoSum: y + d = s_ + cnew exactly
                ynew[i] = s_
                sc = atol + max(abs(y[i]), abs(s_)) * rtol
                e5 += (v5 / sc) ** 2
                e3 += (v3 / sc) ** 2
            denom = e5 + 0.01 * e3
            if not np.isfinite(denom) or not _finite(ynew):
                return calls, 1, th + tl, steps
            err = hu * e5 / math.sqrt(denom * n) if denom > 0.0 else 0.0
            if err < 1.0:
                if err == 0.0:
                    factor = MAX_FACTOR
                else:
                    factor = min(MAX_FACTOR, SAFETY * err ** EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                break
            h = hu * max(MIN_FACTOR, SAFETY * err ** EXPONENT)
            rejected = True
        steps += 1
        if steps > max_steps:
            return calls, 3, th + tl, steps
        if final:
            nh = t_end
            nl = 0.0
        else:
            nh = th + hu
            bb = nh - th
            nl = ((th - (nh - bb)) + (hu - bb)) + tl
            s_ = nh + nl
            nl = nl - (s_ - nh)
            nh = s_
        f(nh + nl, ynew.ctypes, p.ctypes, K[12].ctypes)
        calls += 1
        if not _finite(K[12]):
            return calls, 1, nh + nl, steps
        if (t_eval[k_out] - nh) - nl <= 0.0:  # outputs in this step: the dense output
            for s in range(13, 16):
                _stage(y, K, s, hu, stage)
                f(th + (tl + _C[s] * hu), stage.ctypes, p.ctypes, K[s].ctypes)
            calls += 3
            for i in range(n):
                F[0, i] = inc[i]
                F[1, i] = hu * K[0, i] - inc[i]
                F[2, i] = 2.0 * inc[i] - hu * (K[12, i] + K[0, i])
                for r in range(4):
                    acc = 0.0
                    for j in range(16):
                        acc += _D[r, j] * K[j, i]
                    F[3 + r, i] = hu * acc
            if not _finite(F[3]) or not _finite(F[6]):
                return calls, 1, th + tl, steps
            while k_out < m and (t_eval[k_out] - nh) - nl <= 0.0:
                x = ((t_eval[k_out] - th) - tl) / hu
                for i in range(n):
                    v = 0.0
                    for r in range(6, -1, -1):
                        v += F[r, i]
                        v *= x if (6 - r) % 2 == 0 else 1.0 - x
                    out[k_out, i] = y[i] + (comp[i] + v)
                k_out += 1
        for i in range(n):
            y[i] = ynew[i]
            comp[i] = cnew[i]
            K[0, i] = K[12, i]
            last[i] = y[i]
        th = nh
        tl = nl
        h = min(hu * factor, max_step) if not final else h
    return calls, 0, th + tl, steps


def _members(f, Y0, P, t_eval, rtol, atol, max_step, max_steps, out, last, info):
    """Every member b (rows of ``Y0``, ``P``; tolerances ``rtol[b]``, ``atol[b]``, steps at most ``max_step[b]``) into
    ``out[b]``; ``info[b]`` = (calls, status, time reached, steps)."""
    for b in _range(Y0.shape[0]):
        calls, status, reached, steps = _member(f, Y0[b], P[b], t_eval, rtol[b], atol[b], max_step[b], max_steps,
                                                out[b], last[b])
        info[b, 0] = calls
        info[b, 1] = status
        info[b, 2] = reached
        info[b, 3] = steps


_range = range


#: The one signature the member loop is compiled for: (f, Y0, P, t_eval, rtol, atol, max_step, max_steps, out, last,
#: info), every array float64, C-contiguous and writable (:func:`integrate` makes them so).
_ARGS = (nt.FunctionType(SIGNATURE), nt.float64[:, ::1], nt.float64[:, ::1], nt.float64[::1], nt.float64[::1],
         nt.float64[::1], nt.float64[::1], nt.int64, nt.float64[:, :, ::1], nt.float64[:, ::1], nt.float64[:, ::1])


@lru_cache(maxsize=2)
def _driver(parallel: bool):
    """The member loop, serial (without the GIL: the accuracy control runs a pair's two runs on two threads) or over
    the cores (``prange``), as the compiled entry point of its one signature (:data:`_ARGS`; compiled once, cached
    on disk): called directly, without the dispatcher's typing of the arguments on every call (17 µs → 5 µs a call;
    the control makes three to five calls on runs of a fraction of a millisecond)."""
    glob = dict(_members.__globals__)
    glob["_range"] = numba.prange if parallel else range
    name = "_members_parallel" if parallel else "_members_serial"
    fn = types.FunctionType(_members.__code__, glob, name)
    fn.__qualname__ = name  # a cache entry of its own for each variant
    return numba.njit(cache=True, parallel=parallel, nogil=not parallel, error_model="numpy")(fn).compile(_ARGS)


def _owned(a, ndim: int) -> np.ndarray:
    """``a`` as a C-contiguous, writable float64 array of ``ndim`` dimensions (copied only when it is not one): the
    layout :data:`_ARGS` promises the compiled loop, which does not check it."""
    a = np.asarray(a, dtype=np.float64)
    if a.ndim != ndim:
        raise ValueError(f"expected {ndim} dimensions, got shape {a.shape}")
    if a.flags.c_contiguous and a.flags.writeable:
        return a
    return np.array(a, dtype=np.float64, order="C")


# ----------------------------------------------------------------------------------------------------------------
# A kernel's right-hand side as a function pointer (one small compilation per kernel, cached beside it)
# ----------------------------------------------------------------------------------------------------------------
def _adapter(t, y, p, out):
    """``out[:] = rhs_flat(t, *y, *p)`` for pointers ``y`` (_N), ``p`` (_K), ``out`` (_N)."""
    state = numba.carray(y, (_N,))
    params = numba.carray(p, (_K,))
    values = _rhs(t, *(to_fixed_tuple(state, _N) + to_fixed_tuple(params, _K)))
    o = numba.carray(out, (_N,))
    i = 0
    for v in numba.literal_unroll(values):
        o[i] = v
        i += 1


def _variational(t, y, p, out):
    """The variational system: ``y = (x, Φ)`` (_N + _N² values, Φ row-major), ``out = (f(x), J(x) Φ)``."""
    state = numba.carray(y, (_N + _N * _N,))
    params = numba.carray(p, (_K,))
    args = to_fixed_tuple(state[:_N], _N) + to_fixed_tuple(params, _K)
    values = _rhs(t, *args)
    J = _jac(t, *args)
    o = numba.carray(out, (_N + _N * _N,))
    i = 0
    for v in numba.literal_unroll(values):
        o[i] = v
        i += 1
    for r in range(_N):
        row = J[r]
        for c in range(_N):
            acc = 0.0
            for m in range(_N):
                acc += row[m] * state[_N + m * _N + c]
            o[_N + r * _N + c] = acc


_N = _K = 0
_rhs = _jac = None


def _source_of(module) -> tuple:
    """(path, bytes) of a kernel module's file (the adapter's cache sits beside it and is named by its bytes); for a
    kernel compiled in memory (:meth:`eulersym.model.Model.compile`) no path, and the bytes of its ``rhs_flat``."""
    path = getattr(module, "__file__", None)
    if path is None or not os.path.isfile(path):
        return None, marshal.dumps(module.rhs_flat.__code__)
    with open(path, "rb") as fh:
        return path, fh.read()


def _own(function):
    """``function`` under this module's (importable) name: numba's cache rebuilds a compiled function's environment
    by importing its module, and a model's kernel is executed from its checked bytes, not imported."""
    return types.FunctionType(function.__code__, {**function.__globals__, "__name__": __name__}, function.__name__,
                              function.__defaults__, function.__closure__)


#: SHA-256 of this module's source: the adapters' templates live here, so a changed eulersym never loads an adapter
#: compiled from older templates (the cached name carries it beside the kernel's bytes).
_TEMPLATES = hashlib.sha256(Path(__file__).read_bytes()).hexdigest()[:16]


def _compiled(template, module, kind: str, extra: dict):
    """``template`` (an adapter of this module) compiled as a ``cfunc`` for ``module``'s kernel, cached beside it."""
    n = len(module.STATE)
    k = len(module.PARAMETERS)
    path, text = _source_of(module)
    tag = hashlib.sha256(text + f"|{kind}|{n}|{k}|{_TEMPLATES}".encode()).hexdigest()[:20]
    glob = dict(template.__globals__)
    glob.update(extra, _N=n, _K=k)
    name = f"_dop853_{kind}_{tag}"
    code = template.__code__.replace(co_name=name, co_qualname=name,
                                     co_filename=path if path is not None else template.__code__.co_filename)
    fn = types.FunctionType(code, glob, name)
    fn.__qualname__ = name
    if path is None or not _private(path):
        return numba.cfunc(SIGNATURE, cache=path is not None, error_model="numpy")(fn)
    # A kernel in a private folder (a model's entry in eulersym's cache): numba's own disk cache would add a
    # __pycache__ there with the process's umask, so the adapter goes to eulersym's checked, private numba cache.
    from numba.core.ccallback import CFunc

    from eulersym.numerics._numba_cache import CheckedCache

    compiled = CFunc(fn, _SIGNATURE, locals={}, options={"error_model": "numpy"})
    compiled._cache = CheckedCache(fn)  # what CFunc.enable_caching does, with eulersym's cache
    compiled.compile()
    return compiled


def _private(path) -> bool:
    """True when the kernel's folder is private (no access for group or others: a model's entry in eulersym's cache,
    which holds only the files the cache wrote and checks): its compiled adapter is cached in eulersym's private
    numba cache (:class:`eulersym.numerics._numba_cache.CheckedCache`), not beside it."""
    try:
        return not (os.stat(os.path.dirname(path)).st_mode & 0o077)
    except OSError:
        return True


@lru_cache(maxsize=64)
def variational_function(module):
    """The numba ``cfunc`` of the variational system of ``module``'s kernel — ``(x, Φ)' = (f(x), J(x) Φ)`` with the
    symbolic Jacobian ``jac_flat`` — for :func:`integrate` over n + n² components (cached as :func:`rhs_function`).

    Examples
    --------
    >>> from eulersym.generated import euler_principal as kernel
    >>> y0 = np.concatenate([[0.0, 1.0, 0.01], np.eye(3).ravel()])
    >>> r = integrate(kernel, [y0], [0.0, 1.0], [[1.0, 2.0, 3.0, 0.0, 0.0, 0.0]], rtol=1e-10, atol=1e-13,
    ...               function=variational_function(kernel))
    >>> r.y.shape
    (1, 2, 12)
    """
    return _compiled(_variational, module, "variational",
                     {"_rhs": numba.njit(error_model="numpy")(_own(module.rhs_flat)),
                      "_jac": numba.njit(error_model="numpy")(_own(module.jac_flat))})


@lru_cache(maxsize=64)
def rhs_function(module):
    """The numba ``cfunc`` of ``module.rhs_flat`` that the stepping loop calls: ``f(t, y*, p*, out*)``.

    Compiled once per kernel and cached on disk beside the kernel's file (``__pycache__``), under a name made of
    the kernel's bytes: a changed kernel gets a new entry, never a stale one; a kernel in a private folder (a model's
    entry in eulersym's cache: :func:`_private`) has its adapter in eulersym's checked, private numba cache instead.

    Examples
    --------
    >>> from eulersym.generated import euler_principal as kernel
    >>> rhs_function(kernel) is rhs_function(kernel)
    True
    """
    return _compiled(_adapter, module, "rhs", {"_rhs": numba.njit(error_model="numpy")(_own(module.rhs_flat))})


# ----------------------------------------------------------------------------------------------------------------
# The entry point
# ----------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Run:
    """What :func:`integrate` returns, batch-first.

    Attributes
    ----------
    y : ndarray (batch, m, n)
        The state at the output times (a failed member: up to where it stopped; the rest unspecified).
    calls : ndarray (batch,) of int
        Right-hand-side evaluations per member.
    status : ndarray (batch,) of int
        :data:`OK`, or why the member stopped (:data:`STATUS`).
    reached : ndarray (batch,)
        The time each member reached.
    steps : ndarray (batch,) of int
        Accepted steps per member.
    last : ndarray (batch, n)
        Each member's last finite state (where a failed member stopped).
    """

    y: np.ndarray
    calls: np.ndarray
    status: np.ndarray
    reached: np.ndarray
    steps: np.ndarray
    last: np.ndarray


def integrate(module, y0, t, params, *, rtol, atol, max_steps: int = 10**8, parallel=None, function=None,
              max_step=math.inf) -> Run:
    """Integrate every member of ``y' = module.rhs_flat(t, *y, *params)`` with eulersym's compiled DOP853.

    Parameters
    ----------
    module : module
        A generated kernel (``rhs_flat``, ``STATE``, ``PARAMETERS``).
    y0 : array_like (batch, n)
    t : array_like (m,)
        Non-decreasing output times, ``t[0]`` the start.
    params : array_like (batch, k)
    rtol, atol : float or array_like (batch,)
        Tolerances of each member (its local error per step ≤ atol + rtol |y|, SciPy's norm).
    max_steps : int
        Steps a member may take before it stops with :data:`TOO_MANY_STEPS`.
    parallel : bool or None
        Members over the cores (``prange``); None: when there is more than one.
    function : cfunc, optional
        The system to integrate instead of ``module``'s right-hand side (:func:`variational_function`).
    max_step : float or array_like (batch,)
        The longest step a member may take (its step otherwise from the tolerances alone): more, shorter steps,
        each adding less round-off — what the accuracy control asks for when a tolerance at round-off is not enough
        (:func:`eulersym.numerics.methods._accuracy.deliver`).

    Returns
    -------
    Run

    Examples
    --------
    >>> from eulersym.generated import euler_principal as kernel
    >>> r = integrate(kernel, [[0.0, 0.0, 1.0]], [0.0, 1.0], [[1.0, 2.0, 3.0, 0.0, 0.0, 0.5]], rtol=1e-12, atol=1e-15)
    >>> round(float(r.y[0, -1, 2]), 12)  # spun up about e3 by N3: ω3 = 1 + N3 t / I3
    1.166666666667
    """
    sig = getattr(function, "_sig", None)
    if function is not None and (getattr(sig, "args", None), getattr(sig, "return_type", None)) != _SIGNATURE:
        raise TypeError(f"function must be a numba cfunc of signature {SIGNATURE} (rhs_function, "
                        f"variational_function), not {function!r}")
    max_steps = operator.index(max_steps)
    y0 = _owned(np.atleast_2d(np.asarray(y0, dtype=np.float64)), 2)
    P = _owned(np.asarray(params, dtype=np.float64).reshape(len(y0), -1), 2)
    t = _owned(t, 1)
    batch, n = y0.shape
    rt = np.empty(batch)  # fresh: writable and contiguous (a tolerance per member, or one for all)
    rt[:] = rtol
    at = np.empty(batch)
    at[:] = atol
    cap = np.empty(batch)
    cap[:] = max_step
    if not np.all(cap > 0):
        raise ValueError(f"max_step must be positive, got {max_step!r}")
    out = np.empty((batch, len(t), n))
    last = np.empty((batch, n))
    info = np.zeros((batch, 4))
    if batch:
        run = _driver(batch > 1 if parallel is None else bool(parallel))
        run(rhs_function(module) if function is None else function, y0, P, t, rt, at, cap, int(max_steps), out, last,
            info)
    return Run(y=out, calls=info[:, 0].astype(np.int64), status=info[:, 1].astype(np.int64), reached=info[:, 2],
               steps=info[:, 3].astype(np.int64), last=last)
