"""The batched adaptive integrator: Dormand–Prince 8(5,3) (:mod:`~eulersym.numerics.methods._dop853_tableau`,
the tableau SciPy carries) over many members at once, one step size shared by a chunk of members, a tolerance per
member, the state first and the batch after (the layout of the batched kernels). NumPy only: no
``scipy.integrate``.

Only the methods that integrate import this module, when they run (:class:`eulersym.numerics.methods.BatchedDOP853`).
Chunking, streaming and distributed execution of sweeps wrap it.
"""

from __future__ import annotations

import numpy as np

from eulersym.errors import IntegrationFailed
from eulersym.numerics.methods import _dop853_tableau as _T

__all__ = ["dop853_batched"]


class _Tableau:
    """DOP853's numbers as arrays (the attribute names of SciPy's ``DOP853`` class)."""

    n_stages = _T.N_STAGES
    order = _T.ORDER
    error_estimator_order = _T.ERROR_ESTIMATOR_ORDER
    C = np.array(_T.C[:_T.N_STAGES])
    A = np.zeros((_T.N_STAGES, _T.N_STAGES))
    for _s in range(_T.N_STAGES):
        for _j, _a in _T.A[_s]:
            A[_s, _j] = _a
    B = np.array(_T.B)
    E3 = np.array(_T.E3)
    E5 = np.array(_T.E5)
    del _s, _j, _a


DOP853 = _Tableau


def _members_text(bad) -> str:
    bad = [int(b) for b in bad]
    return ("member " if len(bad) == 1 else "members ") + ", ".join(map(str, bad[:5])) + (", …" if len(bad) > 5 else "")


def dop853_batched(fun, y0, t_eval, *, params=(), rtol, atol, chunk=4096, progress=None, takes_out=False,
                   describe=None):
    """Integrate ``y' = fun(t, y)`` for a batch of states at once with Dormand–Prince 8(5,3).

    Parameters
    ----------
    fun : callable ``fun(t, y, *params) -> ydot``, y of shape (n, batch) (state first, batch after)
    y0 : ndarray (n, batch)
    params : sequence
        Extra arguments of ``fun``: numbers, or arrays of shape (batch,) (one value per member; sliced per chunk).
    t_eval : ndarray (m,), increasing, ``t_eval[0]`` the start
    rtol, atol : float or array_like (batch,)
        Tolerances as in ``scipy.integrate.solve_ivp``, one for all or one per member; the step of a chunk is
        accepted when the error norm of every member in it is ≤ 1 (the members share one step size).
    chunk : int
        Members integrated together (bounded memory; each chunk adapts its own step).
    progress : callable(done_fraction) or None
    takes_out : bool
        ``fun`` accepts ``out=`` (the generated batched kernels do): stages are written in place.
    describe : callable or None
        ``describe(indices)`` → the members in words, for the message of a failure (default: their indices).

    Returns
    -------
    Y : ndarray (m, n, batch), n_calls : int

    Examples
    --------
    >>> Y, calls = dop853_batched(lambda t, y: -y, np.ones((1, 3)), np.array([0.0, 1.0]), rtol=1e-10, atol=1e-12)
    >>> bool(np.allclose(Y[-1], np.exp(-1), rtol=1e-9))
    True
    """
    y0 = np.asarray(y0, dtype=float)
    n, batch = y0.shape
    rtol = np.broadcast_to(np.asarray(rtol, dtype=float), (batch,))
    atol = np.broadcast_to(np.asarray(atol, dtype=float), (batch,))
    Y = np.empty((len(t_eval), n, batch))
    calls = 0
    for lo in range(0, max(batch, 1), chunk):
        hi = min(lo + chunk, batch)
        if hi <= lo:
            break
        sliced = tuple(p[lo:hi] if np.ndim(p) == 1 and len(p) == batch else p for p in params)
        if takes_out:
            def call(tt, y, out=None, sliced=sliced):
                return fun(tt, y, *sliced, out=out)
        else:
            def call(tt, y, out=None, sliced=sliced):
                value = fun(tt, y, *sliced)
                if out is None:
                    return value
                out[...] = value
                return out
        try:
            c = _dop853_chunk(call, y0[:, lo:hi], t_eval, rtol[lo:hi], atol[lo:hi], Y[:, :, lo:hi],
                              None if progress is None else (lambda f, lo=lo, hi=hi: progress((lo + f * (hi - lo))
                                                                                              / batch)))
        except _Stopped as stop:
            bad = lo + stop.members
            who = describe(bad) if describe is not None else _members_text(bad)
            failure = IntegrationFailed("batched_dop853", f"{who}: {stop.reason} at t = {stop.t:.6g}", stop.hint)
            failure.members, failure.time, failure.cause = bad, stop.t, stop.reason  # for a sweep's own report
            raise failure from None
        calls += c
    return Y, calls


def _runs(weights) -> tuple:
    """Contiguous runs of non-zero weights: ((start, stop, weights[..., start:stop]), ...) (rows of weights may be
    stacked: the runs are where any row is non-zero)."""
    w = np.atleast_2d(weights)
    nonzero = np.flatnonzero(np.any(w != 0, axis=0))
    runs, start = [], None
    for k, j in enumerate(nonzero):
        if start is None:
            start = j
        if k + 1 == len(nonzero) or nonzero[k + 1] != j + 1:
            runs.append((int(start), int(j + 1), np.ascontiguousarray(np.asarray(weights)[..., start:j + 1])))
            start = None
    return tuple(runs)


def _combine(K, runs):
    """Σ_j w_j K[j] over the non-zero weights, reading K in contiguous blocks (BLAS, no copies of K)."""
    total = None
    shape = K.shape[1:]
    for a, b, w in runs:
        if b - a == 1:
            part = w[0] * K[a]
        else:
            part = np.dot(w, K[a:b].reshape(b - a, -1)).reshape(shape)
        if total is None:
            total = part
        else:
            total += part
    return total


_A_RUNS = tuple(_runs(DOP853.A[s, :s]) for s in range(DOP853.n_stages))
_B_RUNS = _runs(DOP853.B)
_E5_RUNS = _runs(DOP853.E5)
_E3_RUNS = _runs(DOP853.E3)


#: Stiffness test of Hairer's DOP853 (``nstiff``, 6.1, 15 and 6): every ``STIFF_EVERY`` accepted steps, and on each
#: step while a member looks stiff, |hλ| ≈ h ‖f(y₁) − f(y₁₂)‖ / ‖y₁ − y₁₂‖ (the last two stages, both at t + h); a
#: member past ``STIFF_HLAMBDA`` on ``STIFF_STEPS`` steps in a row (``STIFF_RESET`` calm ones start the count over)
#: has its step held by the method's stability, not by its accuracy.
STIFF_EVERY, STIFF_HLAMBDA, STIFF_STEPS, STIFF_RESET = 1000, 6.1, 15, 6
#: A stiff chunk stops when the steps still needed at its held step size, (t_end − t) / h, are more than this
#: (seconds of NumPy per step make it minutes; a few thousand steps more are left to finish).
STIFF_REMAINING = 10_000


class _Stopped(Exception):
    """A chunk stopped: which of its members, why, when."""

    def __init__(self, members, reason, t, hint):
        super().__init__(reason)
        self.members, self.reason, self.t, self.hint = np.asarray(members), reason, t, hint


def _stiffness(K, y12, y1, h, stiff, calm) -> None:
    """Count, per member, the accepted steps in a row whose |hλ| = h ‖K₁₂ − K₁₁‖ / ‖y₁ − y₁₂‖ exceeds
    :data:`STIFF_HLAMBDA` (``stiff``; ``calm`` counts the others, :data:`STIFF_RESET` of which reset it), in place.

    Examples
    --------
    >>> K = np.zeros((13, 1, 2)); K[12, 0] = [-1e4, -1.0]   # ẏ = λy: K₁₂ − K₁₁ = λ (y₁ − y₁₂)
    >>> stiff, calm = np.zeros(2, dtype=int), np.zeros(2, dtype=int)
    >>> _stiffness(K, np.zeros((1, 2)), np.ones((1, 2)), 1e-3, stiff, calm)
    >>> stiff.tolist(), calm.tolist()
    ([1, 0], [0, 1])
    """
    with np.errstate(all="ignore"):
        num = np.einsum("nb,nb->b", K[-1] - K[-2], K[-1] - K[-2])
        gap = y1 - y12
        den = np.einsum("nb,nb->b", gap, gap)
        hot = (den > 0) & (h * h * num > STIFF_HLAMBDA ** 2 * den)
    stiff[hot] += 1
    calm[hot] = 0
    calm[~hot] += 1
    stiff[calm >= STIFF_RESET] = 0


def _dop853_chunk(fun, y0, t_eval, rtol, atol, Y, progress):
    C = DOP853.C
    S = DOP853.n_stages
    exponent = -1.0 / (DOP853.error_estimator_order + 1)
    n, b = y0.shape
    K = np.empty((S + 1, n, b))
    Y[0] = y0
    t, y = float(t_eval[0]), y0.copy()
    with np.errstate(all="ignore"):  # a member out of its domain gives NaN (log, sqrt, ...): named below
        f = np.array(fun(t, y), dtype=float)
    calls = 1
    if not np.all(np.isfinite(f)):
        raise _Stopped(np.flatnonzero(~np.all(np.isfinite(f), axis=0)), "the right-hand side is not finite at the "
                       "start (an overflow, or log/sqrt/asin/acos of a value outside its domain)", t,
                       "a start and parameters that keep the right-hand side in its domain")
    # initial step: scipy's rule (Hairer, Nørsett & Wanner), the smallest over the members
    scale = atol + np.abs(y) * rtol
    d0 = np.sqrt(np.mean((y / scale) ** 2, axis=0))
    d1 = np.sqrt(np.mean((f / scale) ** 2, axis=0))
    h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / np.maximum(d1, 1e-300))
    h0 = float(np.min(h0))
    with np.errstate(all="ignore"):
        f1 = np.asarray(fun(t + h0, y + h0 * f))
    calls += 1
    d2 = np.max(np.sqrt(np.mean(((f1 - f) / scale) ** 2, axis=0))) / h0
    d1m = float(np.max(d1))
    h1 = max(1e-6, h0 * 1e-3) if max(d1m, d2) <= 1e-15 else (0.01 / max(d1m, d2)) ** (1.0 / (DOP853.order + 1))
    h = min(100 * h0, h1, float(t_eval[-1] - t_eval[0]))
    m = len(t_eval)
    accepted, stiff, calm = 0, np.zeros(b, dtype=int), np.zeros(b, dtype=int)
    for i in range(1, m):
        target = float(t_eval[i])
        while t < target:
            h_use = min(h, target - t)
            clipped = h_use < h
            K[0] = f
            with np.errstate(all="ignore"):  # a member leaving its domain becomes NaN, named below
                for s in range(1, S):
                    dy = _combine(K, _A_RUNS[s])
                    dy *= h_use
                    dy += y
                    fun(t + C[s] * h_use, dy, out=K[s])
                y_new = _combine(K, _B_RUNS)
                y_new *= h_use
                y_new += y
                fun(t + h_use, y_new, out=K[S])
                f_new = K[S].copy()
                calls += S
                scale = np.maximum(np.abs(y), np.abs(y_new))
                scale *= rtol
                scale += atol
                err5 = _combine(K, _E5_RUNS)
                err5 /= scale
                err3 = _combine(K, _E3_RUNS)
                err3 /= scale
                e5 = np.einsum("nb,nb->b", err5, err5)
                e3 = np.einsum("nb,nb->b", err3, err3)
                denom = e5 + 0.01 * e3
                norms = np.where(denom > 0, h_use * e5 / np.sqrt(denom * n), 0.0)
                norms[~np.isfinite(denom) | ~np.all(np.isfinite(y_new), axis=0)] = np.nan  # NaN: never a small error
            err = float(np.max(norms)) if norms.size else 0.0
            if not np.isfinite(err):
                bad = np.flatnonzero(~np.isfinite(norms))
                raise _Stopped(bad, "the state or the right-hand side left the finite numbers (an overflow, or "
                               "log/sqrt/asin/acos of a value outside its domain)", t,
                               "a start and parameters that keep the right-hand side in its domain (or a shorter "
                               "t_end)")
            if err < 1:
                accepted += 1
                if accepted % STIFF_EVERY == 0 or stiff.any():  # dy: the last stage's point y₁₂, at t + h as y₁
                    _stiffness(K, dy, y_new, h_use, stiff, calm)
                    if np.any(stiff >= STIFF_STEPS) and (float(t_eval[-1]) - t) / h_use > STIFF_REMAINING:
                        raise _Stopped(np.flatnonzero(stiff >= STIFF_STEPS), "the motion is stiff (the explicit step "
                                       f"is held by stability at h ≈ {h_use:.2g}, |hλ| > {STIFF_HLAMBDA:g}: "
                                       f"{(float(t_eval[-1]) - t) / h_use:.2g} steps more to t_end)", t,
                                       "an implicit method member by member (method = \"Radau\" or \"LSODA\", one "
                                       "member at a time), a shorter t_end, or parameters of a less stiff motion")
                factor = 10.0 if err == 0 else min(10.0, 0.9 * err ** exponent)
                t = target if h_use == target - t else t + h_use
                y, f = y_new, f_new
                h = max(h, h_use * factor) if clipped else h_use * factor
            else:
                h = h_use * max(0.2, 0.9 * err ** exponent)
                if h < 1e-14 * max(1.0, abs(t)):
                    raise _Stopped(np.flatnonzero(norms >= 1), "the step size underflowed (no step meets the "
                                   f"tolerance, rtol ≥ {float(np.min(rtol)):g})", t,
                                   "a looser accuracy, or a shorter t_end (before a singularity)")
        Y[i] = y
        if progress is not None:
            progress(i / (m - 1))
    return calls
