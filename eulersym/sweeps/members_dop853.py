"""Dormand–Prince 8(5,3) compiled by numba, one heavy top per iteration of a ``prange`` loop over members.

Scipy's DOP853 tableau, error norm and step control, as :func:`eulersym.scene.dop853.dop853_batched` uses them,
but each member adapts its own step, clipped to land on the output times; a member's numbers depend on its own
start only (chunks and Dask workers give the same bits). The right-hand side is the generated flat kernel
``eulersym.generated.heavy_top_euler_poisson.rhs_flat`` (y = ω, Γ, q; parameters I1, I2, I3, M, g, l), inlined
into the step; everything is cached on disk (``cache=True``). Needs the optional ``fast`` extra (numba): import
this module only when it is installed.

Where the time goes (``eulersym bench sweeps --only dop853``): a step is 12 kernel calls and the stage sums
Σ_j a_sj k_j. So that the compiled loop runs at the speed of that arithmetic, the state and the stage sums live in
registers (tuples of ten floats, not arrays that the compiler must assume alias the stages), the sums skip the
tableau's zeros (50 of its 66 a_sj are non-zero, 8 of its 12 b_j, 8 of its 13 error weights; skipping an exact
zero adds nothing: the sums keep scipy's order), products and sums are fused (``FASTMATH``), the body's
parameters are unpacked once per member (the kernel's 1/I1, 1/I2 and (I1 − I2)/I3 are then computed once, not per
call), the kernel is inlined into the step (no call, no exception check per stage), and division follows IEEE
(``error_model="numpy"``: no zero test per division; a zero divisor gives ∞ or NaN, caught as below, instead of an
exception lost inside ``prange``). The only memory a step touches is the member's 13 × 10 stages. Measured on
the bench's asymmetric top, one thread: 74 ns per kernel call before, 29 ns now (~1500 floating-point operations
a step at ~1.5 per cycle: near this CPU's scalar limit; interleaving two members gained 6 %, not kept).

A member that overflows returns −1 (its start, a stage or its new state not finite), one whose tolerance no step
can meet −2 (the engine turns both into :class:`eulersym.errors.InvalidInput`).

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
N = 10  # the state: ω (3), Γ (3), q (4)


def _nonzero(rows):
    """Per row of ``rows``: the columns of its non-zero weights (padded with 0) and their count."""
    cols = np.zeros(rows.shape, dtype=np.int64)
    count = np.zeros(rows.shape[0], dtype=np.int64)
    for r, row in enumerate(rows):
        nz = np.flatnonzero(row)
        cols[r, :len(nz)] = nz
        count[r] = len(nz)
    return cols, count


A_COLS, A_COUNT = _nonzero(np.tril(A, -1))
B_COLS = np.flatnonzero(B).astype(np.int64)
E_COLS = np.flatnonzero((E5 != 0) | (E3 != 0)).astype(np.int64)

#: Fused multiply-adds (``a*b + c`` rounded once) and nothing else of fastmath: no reassociation, no assumption of
#: finite values (the overflow check stays), sums in scipy's order. Which products are fused is decided once, when
#: :func:`members` is compiled, and every member runs that one machine code: a member's bits depend on its start
#: only (on a given CPU and numba; in-process, chunked and on Dask workers alike). 36 → 29 ns per kernel call.
FASTMATH = {"contract"}

_rhs = numba.njit(inline="always", fastmath=FASTMATH, error_model="numpy")(_kernel.rhs_flat)


@numba.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def _stage_sum(K, weights, cols, count):
    """Σ_j weights[j] K[j] over the non-zero weights (their columns ``cols[:count]``), as a tuple of ten floats."""
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = a8 = a9 = 0.0
    for jj in range(count):
        j = cols[jj]
        w = weights[j]
        a0 += w * K[j, 0]
        a1 += w * K[j, 1]
        a2 += w * K[j, 2]
        a3 += w * K[j, 3]
        a4 += w * K[j, 4]
        a5 += w * K[j, 5]
        a6 += w * K[j, 6]
        a7 += w * K[j, 7]
        a8 += w * K[j, 8]
        a9 += w * K[j, 9]
    return (a0, a1, a2, a3, a4, a5, a6, a7, a8, a9)


@numba.njit(inline="always", fastmath=FASTMATH, error_model="numpy")
def _f(t, y, h, a, p, K, s):
    """K[s] = f(t, y + h a) by the generated kernel (``y``, ``a``: tuples of ten floats; ``p``: six)."""
    r = _rhs(t, y[0] + h * a[0], y[1] + h * a[1], y[2] + h * a[2], y[3] + h * a[3], y[4] + h * a[4],
             y[5] + h * a[5], y[6] + h * a[6], y[7] + h * a[7], y[8] + h * a[8], y[9] + h * a[9],
             p[0], p[1], p[2], p[3], p[4], p[5])
    for i in range(N):
        K[s, i] = r[i]


@numba.njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def _member(y0, params, t_eval, rtol, atol, out, K):
    n = N
    p = (params[0], params[1], params[2], params[3], params[4], params[5])
    y = (y0[0], y0[1], y0[2], y0[3], y0[4], y0[5], y0[6], y0[7], y0[8], y0[9])
    zero = (0.0,) * 10
    t = t_eval[0]
    for i in range(n):
        out[0, i] = y[i]
    _f(t, y, 0.0, zero, p, K, 0)
    calls = 1
    # initial step: scipy's rule (Hairer, Nørsett & Wanner)
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = atol + abs(y[i]) * rtol
        d0 += (y[i] / sc) ** 2
        d1 += (K[0, i] / sc) ** 2
    d0 = np.sqrt(d0 / n)
    d1 = np.sqrt(d1 / n)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    f0 = (K[0, 0], K[0, 1], K[0, 2], K[0, 3], K[0, 4], K[0, 5], K[0, 6], K[0, 7], K[0, 8], K[0, 9])
    _f(t + h0, y, h0, f0, p, K, 1)
    calls += 1
    d2 = 0.0
    for i in range(n):
        sc = atol + abs(y[i]) * rtol
        d2 += ((K[1, i] - K[0, i]) / sc) ** 2
    d2 = np.sqrt(d2 / n) / h0
    if max(d1, d2) <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 9.0)
    h = min(100 * h0, h1, t_eval[-1] - t_eval[0])
    for i in range(n):
        if not np.isfinite(K[0, i]):  # the start overflows the kernel
            return -1
    if not h > 0.0:  # the tolerance scales |y| / (atol + |y| rtol) overflow: nothing can meet them
        return -2
    for k in range(1, t_eval.shape[0]):
        target = t_eval[k]
        while t < target:
            h_use = min(h, target - t)
            clipped = h_use < h
            for s in range(1, S):
                _f(t + C[s] * h_use, y, h_use, _stage_sum(K, A[s], A_COLS[s], A_COUNT[s]), p, K, s)
            b = _stage_sum(K, B, B_COLS, B_COLS.shape[0])
            y_new = (y[0] + h_use * b[0], y[1] + h_use * b[1], y[2] + h_use * b[2], y[3] + h_use * b[3],
                     y[4] + h_use * b[4], y[5] + h_use * b[5], y[6] + h_use * b[6], y[7] + h_use * b[7],
                     y[8] + h_use * b[8], y[9] + h_use * b[9])
            _f(t + h_use, y_new, 0.0, zero, p, K, S)
            calls += S
            v5 = _stage_sum(K, E5, E_COLS, E_COLS.shape[0])
            v3 = _stage_sum(K, E3, E_COLS, E_COLS.shape[0])
            e5 = 0.0
            e3 = 0.0
            largest = 0.0
            for i in range(n):
                sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
                largest = max(largest, sc)
                e5 += (v5[i] / sc) ** 2
                e3 += (v3[i] / sc) ** 2
            denom = e5 + 0.01 * e3
            err = h_use * e5 / np.sqrt(denom * n) if denom > 0 else (0.0 if denom == 0 else np.nan)
            if not (np.isfinite(err) and np.isfinite(largest)):  # NaN or ∞ in the stages or the new state
                return -1
            if err < 1.0:
                factor = 10.0 if err == 0.0 else min(10.0, 0.9 * err ** exponent)
                t = target if h_use == target - t else t + h_use
                y = y_new
                for i in range(n):
                    K[0, i] = K[S, i]
                h = max(h, h_use * factor) if clipped else h_use * factor
            else:
                h = h_use * max(0.2, 0.9 * err ** exponent)
                if h < 1e-14 * max(1.0, abs(t)):
                    return -2
        for i in range(n):
            out[k, i] = y[i]
    return calls


@numba.njit(parallel=True, cache=True, error_model="numpy")
def members(y0, params, t_eval, rtol, atol, out):
    """Every member (rows of ``y0`` (B, 10), ``params`` (B, 6): I1, I2, I3, M, g, l) over ``t_eval`` into
    ``out`` (B, n, 10); returns the kernel calls per member (−1: overflow, −2: step underflow)."""
    B_ = y0.shape[0]
    calls = np.zeros(B_, dtype=np.int64)
    for b in numba.prange(B_):
        K = np.empty((S + 1, N))  # the member's stages: 1 KiB, in the thread's cache
        calls[b] = _member(y0[b], params[b], t_eval, rtol, atol, out[b], K)
    return calls
