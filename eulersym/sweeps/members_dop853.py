"""Dormand–Prince 8(5,3) compiled by numba, one heavy top per iteration of a ``prange`` loop over members.

Scipy's DOP853 tableau, error norm and step control, as :func:`eulersym.scene.dop853.dop853_batched` uses them,
but each member adapts its own step, clipped to land on the output times; a member's numbers depend on its own
start only (chunks and Dask workers give the same bits). The right-hand side is the generated flat kernel
``eulersym.generated.heavy_top_euler_poisson.rhs_flat`` (y = ω, Γ, q; parameters I1, I2, I3, M, g, l), compiled
here; everything is cached on disk (``cache=True``). Needs the optional ``fast`` extra (numba): import this
module only when it is installed.

Examples
--------
>>> y0 = np.array([[0.0, 0.0, 20.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0]])  # a sleeping top, upright
>>> p = np.array([[1.0, 1.0, 0.5, 1.0, 9.81, 0.1]])
>>> out = np.empty((1, 2, 10))
>>> calls = members(y0, p, np.array([0.0, 1.0]), 1e-9, 1e-12, out)
>>> bool(np.allclose(out[0, 1, 2], 20.0)), int(calls[0]) > 0
(True, True)
"""

from __future__ import annotations

import numba
import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _dc

from eulersym.generated import heavy_top_euler_poisson as _kernel

__all__ = ["members"]

S = _dc.N_STAGES
A = np.ascontiguousarray(_dc.A[:S, :S])
B = np.ascontiguousarray(_dc.B)
C = np.ascontiguousarray(_dc.C[:S])
E3 = np.ascontiguousarray(_dc.E3)
E5 = np.ascontiguousarray(_dc.E5)
exponent = -1.0 / 8.0  # scipy's DOP853: error estimator order 7, factor = err^(-1/(7 + 1))

_rhs = numba.njit(cache=True)(_kernel.rhs_flat)


@numba.njit(cache=True)
def _f(t, y, p, out):
    r = _rhs(t, y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7], y[8], y[9], p[0], p[1], p[2], p[3], p[4], p[5])
    for i in range(10):
        out[i] = r[i]


@numba.njit(cache=True)
def _member(y0, p, t_eval, rtol, atol, out):
    n = 10
    K = np.empty((S + 1, n))
    y = y0.copy()
    ynew = np.empty(n)
    tmp = np.empty(n)
    f0 = np.empty(n)
    f1 = np.empty(n)
    t = t_eval[0]
    for i in range(n):
        out[0, i] = y[i]
    _f(t, y, p, f0)
    calls = 1
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = atol + abs(y[i]) * rtol
        d0 += (y[i] / sc) ** 2
        d1 += (f0[i] / sc) ** 2
    d0 = np.sqrt(d0 / n)
    d1 = np.sqrt(d1 / n)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    for i in range(n):
        tmp[i] = y[i] + h0 * f0[i]
    _f(t + h0, tmp, p, f1)
    calls += 1
    d2 = 0.0
    for i in range(n):
        sc = atol + abs(y[i]) * rtol
        d2 += ((f1[i] - f0[i]) / sc) ** 2
    d2 = np.sqrt(d2 / n) / h0
    if max(d1, d2) <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 9.0)
    h = min(100 * h0, h1, t_eval[-1] - t_eval[0])
    for i in range(n):
        K[0, i] = f0[i]
    for k in range(1, t_eval.shape[0]):
        target = t_eval[k]
        while t < target:
            h_use = min(h, target - t)
            clipped = h_use < h
            for s in range(1, S):
                for i in range(n):
                    acc = 0.0
                    for j in range(s):
                        acc += A[s, j] * K[j, i]
                    tmp[i] = y[i] + h_use * acc
                _f(t + C[s] * h_use, tmp, p, K[s])
            for i in range(n):
                acc = 0.0
                for j in range(S):
                    acc += B[j] * K[j, i]
                ynew[i] = y[i] + h_use * acc
            _f(t + h_use, ynew, p, K[S])
            calls += S
            e5 = 0.0
            e3 = 0.0
            for i in range(n):
                sc = atol + max(abs(y[i]), abs(ynew[i])) * rtol
                a5 = 0.0
                a3 = 0.0
                for j in range(S + 1):
                    a5 += E5[j] * K[j, i]
                    a3 += E3[j] * K[j, i]
                e5 += (a5 / sc) ** 2
                e3 += (a3 / sc) ** 2
            denom = e5 + 0.01 * e3
            err = h_use * e5 / np.sqrt(denom * n) if denom > 0 else 0.0
            if not np.isfinite(err):
                return -1
            if err < 1.0:
                factor = 10.0 if err == 0.0 else min(10.0, 0.9 * err ** exponent)
                t = target if h_use == target - t else t + h_use
                for i in range(n):
                    y[i] = ynew[i]
                    K[0, i] = K[S, i]
                h = max(h, h_use * factor) if clipped else h_use * factor
            else:
                h = h_use * max(0.2, 0.9 * err ** exponent)
                if h < 1e-14 * max(1.0, abs(t)):
                    return -2
        for i in range(n):
            out[k, i] = y[i]
    return calls


@numba.njit(parallel=True, cache=True)
def members(y0, params, t_eval, rtol, atol, out):
    """Every member (rows of ``y0`` (B, 10), ``params`` (B, 6): I1, I2, I3, M, g, l) over ``t_eval`` into
    ``out`` (B, n, 10); returns the kernel calls per member (−1: overflow, −2: step underflow)."""
    B_ = y0.shape[0]
    calls = np.zeros(B_, dtype=np.int64)
    for b in numba.prange(B_):
        calls[b] = _member(y0[b], params[b], t_eval, rtol, atol, out[b])
    return calls


