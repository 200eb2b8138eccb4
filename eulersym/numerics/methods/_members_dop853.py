"""Dormand–Prince 8(5,3) compiled by numba, one heavy top per iteration of a ``prange`` loop over members.

Scipy's DOP853 tableau, error norm and step control, as :func:`~eulersym.numerics.methods._batched_dop853.dop853_batched` uses them,
but each member adapts its own step, clipped to land on the output times; a member's numbers depend on its own
start only (chunks and Dask workers give the same bits). The right-hand side is the generated flat kernel
``eulersym.generated.heavy_top_euler_poisson.rhs_flat`` (y = ω, Γ, q; parameters I1, I2, I3, M, g, l), inlined
into the step; everything is cached on disk (``cache=True``). Needs the optional ``fast`` extra (numba): import
this module only when it is installed.

Where the time goes (``eulersym bench sweeps --only dop853``): a step is 12 kernel calls and the stage sums
Σ_j a_sj k_j. So that the compiled loop runs at the speed of that arithmetic: the state and the stages live in
registers (tuples of ten floats; no arrays, which the compiler must assume alias one another), one line per stage
names the stages its sum takes (the tableau's non-zeros: 50 of its 66 a_sj, 8 of its 12 b_j and of its 13 error
weights, checked against scipy's arrays at import; skipping an exact zero adds nothing, the sums keep scipy's
order), IEEE arithmetic throughout (:data:`FASTMATH`), the body's parameters are unpacked once per member (the
kernel's 1/I1, 1/I2 and (I1 − I2)/I3 are then computed once, not per call), the kernel is inlined into the step
(no call, no exception check per stage), f at a step's end is evaluated only once the step is accepted (the error
estimate does not use it), and division follows IEEE (``error_model="numpy"``: no zero test per division; a zero
divisor gives ∞ or NaN, caught as below, instead of an exception lost inside ``prange``). Measured on the bench's
asymmetric top, one thread: 74 ns per kernel call before, ~30 ns now (~1500 floating-point operations a step at
~1.7 per cycle: near this CPU's scalar limit; interleaving two members in one loop gained 6 %, not kept).

A member that overflows returns −1 (its start, a stage or its new state not finite), one whose tolerance no step
can meet −2 (:class:`eulersym.numerics.methods.CompiledDOP853` raises :class:`eulersym.errors.IntegrationFailed`).

Examples
--------
>>> y0 = np.array([[0.0, 0.0, 20.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0]])  # a sleeping top, upright
>>> p = np.array([[1.0, 1.0, 0.5, 1.0, 9.81, 0.1]])
>>> out = np.empty((1, 2, 10))
>>> calls = members(y0, p, np.array([0.0, 1.0]), np.array([1e-9]), np.array([1e-12]), out)
>>> bool(np.allclose(out[0, 1, 2], 20.0)), int(calls[0]) > 0
(True, True)
"""

from __future__ import annotations

import numba
import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _dc

from eulersym.generated import heavy_top_euler_poisson as _kernel

__all__ = ["members"]

S = _dc.N_STAGES  # 12 stages, the 13th (f at the step's end) is the next step's first
C = tuple(float(c) for c in _dc.C[:S])
exponent = -1.0 / 8.0  # scipy's DOP853: error estimator order 7, factor = err^(-1/(7 + 1))
N = 10  # the state: ω (3), Γ (3), q (4)

#: For each stage s = 1 … 11, the earlier stages its sum Σ_j a_sj k_j takes (the non-zero a_sj of scipy's tableau);
#: then those of the solution (b_j) and of the two error estimates (E5, E3). Checked against the tableau below.
STAGES = {1: (0,), 2: (0, 1), 3: (0, 2), 4: (0, 2, 3), 5: (0, 3, 4), 6: (0, 3, 4, 5), 7: (0, 3, 4, 5, 6),
          8: (0, 3, 4, 5, 6, 7), 9: (0, 3, 4, 5, 6, 7, 8), 10: (0, 3, 4, 5, 6, 7, 8, 9),
          11: (0, 3, 4, 5, 6, 7, 8, 9, 10)}
FINAL = (0, 5, 6, 7, 8, 9, 10, 11)


def _weights(row, cols) -> tuple:
    """``row``'s weights at ``cols``, after checking that every other weight of ``row`` is zero."""
    row = np.asarray(row, dtype=float)
    if tuple(np.flatnonzero(row)) != tuple(cols):
        raise RuntimeError(f"scipy's DOP853 tableau changed: non-zeros {tuple(np.flatnonzero(row))}, expected {cols}")
    return tuple(float(row[j]) for j in cols)


W1, W2, W3, W4, W5, W6, W7, W8, W9, W10, W11 = (_weights(_dc.A[s, :s], STAGES[s]) for s in range(1, S))
WB = _weights(_dc.B, FINAL)
WE5 = _weights(_dc.E5, FINAL)
WE3 = _weights(_dc.E3, FINAL)
C1, C2, C3, C4, C5, C6, C7, C8, C9, C10, C11 = C[1:]

#: No fastmath, not even fused multiply-adds (``contract``, 29 instead of 36 ns per kernel call): which products LLVM
#: fuses depends on the compilation's context, and a freshly compiled :func:`members` and the copy numba loads from
#: its disk cache gave different bits for 1.7 % of a 10⁵-member sweep (in-process against a Dask worker;
#: tests/test_sweeps_members.py runs both). With IEEE arithmetic a member's bits depend on its start only: in-process,
#: chunked and on Dask workers alike, compiled now or loaded from the cache.
FASTMATH = False

_rhs = numba.njit(inline="always", fastmath=FASTMATH, error_model="numpy")(_kernel.rhs_flat)


@numba.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def _sum(weights, stages):
    """Σ_m weights[m] stages[m] (tuples of ten floats), in order."""
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = a8 = a9 = 0.0
    for m in range(len(weights)):
        w = weights[m]
        k = stages[m]
        a0 += w * k[0]
        a1 += w * k[1]
        a2 += w * k[2]
        a3 += w * k[3]
        a4 += w * k[4]
        a5 += w * k[5]
        a6 += w * k[6]
        a7 += w * k[7]
        a8 += w * k[8]
        a9 += w * k[9]
    return (a0, a1, a2, a3, a4, a5, a6, a7, a8, a9)


@numba.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def _f(t, y, h, a, p):
    """f(t, y + h a) by the generated kernel (``y``, ``a``: tuples of ten floats; ``p``: six), a tuple."""
    return _rhs(t, y[0] + h * a[0], y[1] + h * a[1], y[2] + h * a[2], y[3] + h * a[3], y[4] + h * a[4],
                y[5] + h * a[5], y[6] + h * a[6], y[7] + h * a[7], y[8] + h * a[8], y[9] + h * a[9],
                p[0], p[1], p[2], p[3], p[4], p[5])


@numba.njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def _member(y0, params, t_eval, rtol, atol, out):
    n = N
    p = (params[0], params[1], params[2], params[3], params[4], params[5])
    y = (y0[0], y0[1], y0[2], y0[3], y0[4], y0[5], y0[6], y0[7], y0[8], y0[9])
    zero = (0.0,) * 10
    t = t_eval[0]
    for i in range(n):
        out[0, i] = y[i]
    k0 = _f(t, y, 0.0, zero, p)
    calls = 1
    for i in range(n):
        if not np.isfinite(k0[i]):  # the start overflows the kernel
            return -1
    # initial step: scipy's rule (Hairer, Nørsett & Wanner)
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = atol + abs(y[i]) * rtol
        d0 += (y[i] / sc) ** 2
        d1 += (k0[i] / sc) ** 2
    d0 = np.sqrt(d0 / n)
    d1 = np.sqrt(d1 / n)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    k1 = _f(t + h0, y, h0, k0, p)
    calls += 1
    d2 = 0.0
    for i in range(n):
        sc = atol + abs(y[i]) * rtol
        d2 += ((k1[i] - k0[i]) / sc) ** 2
    d2 = np.sqrt(d2 / n) / h0
    if max(d1, d2) <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 9.0)
    h = min(100 * h0, h1, t_eval[-1] - t_eval[0])
    if not h > 0.0:  # the tolerance scales |y| / (atol + |y| rtol) overflow: nothing can meet them
        return -2
    for k in range(1, t_eval.shape[0]):
        target = t_eval[k]
        while t < target:
            hu = min(h, target - t)
            clipped = hu < h
            k1 = _f(t + C1 * hu, y, hu, _sum(W1, (k0,)), p)
            k2 = _f(t + C2 * hu, y, hu, _sum(W2, (k0, k1)), p)
            k3 = _f(t + C3 * hu, y, hu, _sum(W3, (k0, k2)), p)
            k4 = _f(t + C4 * hu, y, hu, _sum(W4, (k0, k2, k3)), p)
            k5 = _f(t + C5 * hu, y, hu, _sum(W5, (k0, k3, k4)), p)
            k6 = _f(t + C6 * hu, y, hu, _sum(W6, (k0, k3, k4, k5)), p)
            k7 = _f(t + C7 * hu, y, hu, _sum(W7, (k0, k3, k4, k5, k6)), p)
            k8 = _f(t + C8 * hu, y, hu, _sum(W8, (k0, k3, k4, k5, k6, k7)), p)
            k9 = _f(t + C9 * hu, y, hu, _sum(W9, (k0, k3, k4, k5, k6, k7, k8)), p)
            k10 = _f(t + C10 * hu, y, hu, _sum(W10, (k0, k3, k4, k5, k6, k7, k8, k9)), p)
            k11 = _f(t + C11 * hu, y, hu, _sum(W11, (k0, k3, k4, k5, k6, k7, k8, k9, k10)), p)
            final = (k0, k5, k6, k7, k8, k9, k10, k11)
            b = _sum(WB, final)
            y_new = (y[0] + hu * b[0], y[1] + hu * b[1], y[2] + hu * b[2], y[3] + hu * b[3], y[4] + hu * b[4],
                     y[5] + hu * b[5], y[6] + hu * b[6], y[7] + hu * b[7], y[8] + hu * b[8], y[9] + hu * b[9])
            calls += S
            v5 = _sum(WE5, final)
            v3 = _sum(WE3, final)
            e5 = 0.0
            e3 = 0.0
            largest = 0.0
            for i in range(n):
                sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
                largest = max(largest, sc)
                e5 += (v5[i] / sc) ** 2
                e3 += (v3[i] / sc) ** 2
            denom = e5 + 0.01 * e3
            err = hu * e5 / np.sqrt(denom * n) if denom > 0 else (0.0 if denom == 0 else np.nan)
            if not (np.isfinite(err) and np.isfinite(largest)):  # NaN or ∞ in the stages or the new state
                return -1
            if err < 1.0:
                factor = 10.0 if err == 0.0 else min(10.0, 0.9 * err ** exponent)
                t = target if hu == target - t else t + hu
                y = y_new
                k0 = _f(t, y, 0.0, zero, p)  # scipy's 13th stage, f at the step's end: the next step's first
                h = max(h, hu * factor) if clipped else hu * factor
            else:
                h = hu * max(0.2, 0.9 * err ** exponent)
                if h < 1e-14 * max(1.0, abs(t)):
                    return -2
        for i in range(n):
            out[k, i] = y[i]
    return calls


def members(y0, params, t_eval, rtol, atol, out):
    """Every member (rows of ``y0`` (B, 10), ``params`` (B, 6): I1, I2, I3, M, g, l; tolerances one for all, or
    ``rtol[b]``, ``atol[b]`` each) over ``t_eval`` into ``out`` (B, n, 10); returns the kernel calls per member as
    scipy counts them, 12 per step tried (one fewer is made for a rejected step), or −1 (overflow) or −2 (step
    underflow)."""
    batch = len(y0)
    rtol = np.ascontiguousarray(np.broadcast_to(np.asarray(rtol, dtype=np.float64), (batch,)))
    atol = np.ascontiguousarray(np.broadcast_to(np.asarray(atol, dtype=np.float64), (batch,)))
    return _members(y0, params, t_eval, rtol, atol, out)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def _members(y0, params, t_eval, rtol, atol, out):
    B_ = y0.shape[0]
    calls = np.zeros(B_, dtype=np.int64)
    for b in numba.prange(B_):
        calls[b] = _member(y0[b], params[b], t_eval, rtol[b], atol[b], out[b])
    return calls
