"""The accuracy control's deviation of two runs (:func:`eulersym.numerics.methods._accuracy.deviation`) in one
compiled pass, for the methods that already run on numba (eulersym's DOP853): the same quantities — ω relative to
the largest |ω| of the second run, the normalised attitudes, the vertical Γ (carried, or R(q)ᵀ ẑ from the attitude)
— each the largest Euclidean distance over the output times, per member. The NumPy form costs 30–60 µs per call on
a hundred output times (two dozen small array operations); this ~2 µs, which counts on runs of a fraction of a
millisecond (the control makes one deviation per pair). Its bits may differ from the NumPy form's in the last place
(the sums' order); a method uses one form or the other, always the same. NaN in either run gives NaN.

Needs the optional ``fast`` extra (numba): import this module only when it is installed.

Examples
--------
>>> w = np.zeros((1, 2, 3)); w[0, :, 2] = 2.0
>>> v = w.copy(); v[0, 1, 0] = 2e-6
>>> q = np.zeros((1, 2, 4)); q[..., 0] = 1.0
>>> out = np.empty((3, 1))
>>> farthest(v, w, q, q, np.empty((0, 0, 3)), np.empty((0, 0, 3)), True, out)
>>> out[:, 0].tolist()
[1e-06, 0.0, 0.0]
"""

from __future__ import annotations

import functools
import math

import numba
import numpy as np

__all__ = ["farthest", "entry"]


@numba.njit(cache=True, error_model="numpy")
def _grow(largest, value):
    """max(largest, value), NaN once either is NaN."""
    return value if (value > largest or value != value) and largest == largest else largest


@numba.njit(cache=True, error_model="numpy")
def farthest(wa, wb, qa, qb, ga, gb, vertical, out):
    """Per member b: ``out[0, b]`` the largest |Δω| over the output times divided by the largest |ω| of ``wb`` (by
    1 when that is zero), ``out[1, b]`` the largest |Δq̂| (q̂ = q / |q|; ``qa`` of length 0: none), ``out[2, b]`` the
    largest |ΔΓ| (``ga``, ``gb`` when they have members, else with ``vertical`` Γ = R(q̂)ᵀ ẑ, else none); rows for
    missing quantities are left as they are."""
    batch, m = wa.shape[0], wa.shape[1]
    has_q = qa.shape[0] > 0
    has_g = ga.shape[0] > 0
    for b in range(batch):
        dw = 0.0
        sw = 0.0
        dq = 0.0
        dg = 0.0
        for i in range(m):
            d = 0.0
            s = 0.0
            for k in range(3):
                x = wa[b, i, k] - wb[b, i, k]
                d += x * x
                s += wb[b, i, k] * wb[b, i, k]
            dw = _grow(dw, d)
            sw = _grow(sw, s)
            if has_q:
                na = 0.0
                nb = 0.0
                for k in range(4):
                    na += qa[b, i, k] * qa[b, i, k]
                    nb += qb[b, i, k] * qb[b, i, k]
                na = math.sqrt(na)
                nb = math.sqrt(nb)
                a0, a1, a2, a3 = qa[b, i, 0] / na, qa[b, i, 1] / na, qa[b, i, 2] / na, qa[b, i, 3] / na
                b0, b1, b2, b3 = qb[b, i, 0] / nb, qb[b, i, 1] / nb, qb[b, i, 2] / nb, qb[b, i, 3] / nb
                dq = _grow(dq, (a0 - b0) ** 2 + (a1 - b1) ** 2 + (a2 - b2) ** 2 + (a3 - b3) ** 2)
                if vertical and not has_g:
                    x = 2.0 * (a1 * a3 - a0 * a2) - 2.0 * (b1 * b3 - b0 * b2)
                    y = 2.0 * (a2 * a3 + a0 * a1) - 2.0 * (b2 * b3 + b0 * b1)
                    z = (a0 * a0 - a1 * a1 - a2 * a2 + a3 * a3) - (b0 * b0 - b1 * b1 - b2 * b2 + b3 * b3)
                    dg = _grow(dg, x * x + y * y + z * z)
            if has_g:
                d = 0.0
                for k in range(3):
                    x = ga[b, i, k] - gb[b, i, k]
                    d += x * x
                dg = _grow(dg, d)
        scale = math.sqrt(sw)
        out[0, b] = math.sqrt(dw) / (scale if scale > 0.0 else 1.0)
        if has_q:
            out[1, b] = math.sqrt(dq)
        if has_g or (vertical and has_q):
            out[2, b] = math.sqrt(dg)


#: The one signature :func:`entry` compiles: six float64 arrays (batch, m, k) of any strides, the flag, the output.
_ARGS = (numba.float64[:, :, :],) * 6 + (numba.boolean, numba.float64[:, ::1])


@functools.lru_cache(maxsize=1)
def entry():
    """:func:`farthest` compiled for :data:`_ARGS` (cached on disk), as its entry point: called without the
    dispatcher's typing, and on the runs' own views (ω, q and Γ are strided views of the integrated state) without
    copies — 3 µs a call instead of ~20 µs. The caller passes float64 arrays (it does not check them)."""
    return farthest.compile(_ARGS)
