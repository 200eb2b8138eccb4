"""Bodies under any torque τ(t, ω, Γ, q): a commutator-free Lie-group method that keeps |q| = 1 exactly.

State ``(ω, q)`` on the group R³ × S³ (and ``Γ = R(q)ᵀ ẑ``, the upward vertical in body components, *computed*
from q at every stage, so |Γ| = 1 and Γ = R(q)ᵀ ẑ hold to round-off). The right-hand side is a callable in the
generated kernels' batched form, ``rhs(t, y, *params) -> ydot`` with ``y`` of shape (n_state, B) stacked as
``(ω1, ω2, ω3, [Γ1, Γ2, Γ3,] q0, q1, q2, q3)`` — a model's ``rhs_batched`` plugs in unchanged; only the first
three rows of ``ydot`` (ω̇) are used: the attitude moves by the exact exponential ``q ← q ⊗ exp(h ω / 2)``.

Method ``"cf4"``: the order-4 commutator-free method of Celledoni, Marthinsen and Owren (*Future Gener. Comput.
Syst.* 19 (2003) 341), for the right action ``q̇ = q ⊗ (0, ω/2)``::

    F_i = h (ω̇_i, ω_i)                 stage i at (t_i, ω_i, q_i)
    Y2 = Y1 ∘ exp(F1/2),  Y3 = Y1 ∘ exp(F2/2),  Y4 = Y2 ∘ exp(F3 − F1/2)
    y1 = y0 ∘ exp((3F1 + 2F2 + 2F3 − F4)/12) ∘ exp((−F1 + 2F2 + 2F3 + 3F4)/12)

(on ω, the exponential is a translation: ω follows the classical RK4). Every update of q is a product of unit
quaternions, so |q| = 1 to round-off at every stage, whatever the torque, and q is renormalised after each step.
"""

from __future__ import annotations

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.numerics.batched import BatchTrajectory
from eulersym.numerics.splitting import output_steps
from eulersym.numerics.trajectory import Trajectory
from eulersym.attitude import hamilton, rotvec_to_quaternion
from eulersym.validation import choice, finite_array

__all__ = ["integrate_torqued", "TORQUED_METHODS"]

#: Names accepted by :func:`integrate_torqued`.
TORQUED_METHODS = ("cf4",)


def _exp(xi):
    """exp(ξ/2) as a unit quaternion, ξ (3, B): (cos(|ξ|/2), sin(|ξ|/2) ξ/|ξ|), the rotation vector ξ's."""
    return rotvec_to_quaternion(xi[0], xi[1], xi[2], np.cos, np.sin)


def _times(q, xi):
    return np.stack(hamilton(tuple(q), _exp(xi)))


def _gamma(q):
    a, b, c, d = q
    return np.stack([2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d])


def integrate_torqued(rhs, omega0, q0, t, *, h=None, params=(), gamma=False, method="cf4", accuracy=None):
    """Integrate ω and the attitude of bodies under any torque with a Lie-group method (|q| = 1 exactly).

    Parameters
    ----------
    rhs : callable
        ``rhs(t, y, *params) -> ydot``, ``y`` of shape (n_state, B) (a model kernel's ``rhs_batched``); rows 0–2
        of ``ydot`` are ω̇.
    omega0 : array_like, shape (3,) or (B, 3)
        Body angular velocity at ``t[0]``.
    q0 : array_like, shape (4,) or (B, 4)
        Unit quaternions, scalar first, ``v_space = R(q) v_body``.
    t : array_like, shape (n,)
        Strictly increasing output times.
    h : float, optional
        Largest step (default: 1/64 of the fastest member's rotation period, capped by the output spacing).
    params : sequence
        Passed to ``rhs`` after ``y`` (scalars or (B,) arrays).
    gamma : bool
        Whether the state holds Γ (n_state = 10) or not (7).
    method : {"cf4"}
    accuracy : float, optional
        Instead of ``h``: the global error wanted at the output times (ω relative to its largest size, q
        absolute), delivered by Richardson's estimate — runs at a step and at half of it (order 4), then the step
        proportionality asks for (:func:`eulersym.numerics.methods._accuracy.richardson`); the result's ``error``
        holds the estimate.

    Returns
    -------
    Trajectory (inputs of one member) or BatchTrajectory (batch-first inputs)
        ω, q and Γ (= R(q)ᵀ ẑ) at ``t``; ``n_rhs_calls`` / ``n_kicks`` count calls of ``rhs`` × members; with
        ``accuracy``, ``error`` maps "omega" and "attitude" to the estimate (a float, or per member).

    Raises
    ------
    eulersym.errors.InvalidInput
        Bad shapes, non-unit q0, a bad step, or a right-hand side that returns the wrong shape or non-finite values.

    Examples
    --------
    A sphere spun down by linear drag, ω̇ = −ω: exactly ω = ω0 e^{−t}, turning about a fixed axis.

    >>> import numpy as np
    >>> drag = lambda t, y: -y  # rows 0-2: ω̇ = −ω (the rest is ignored)
    >>> tr = integrate_torqued(drag, (0.0, 0.0, 2.0), (1, 0, 0, 0), [0.0, 1.0], h=0.01)
    >>> bool(abs(tr.omega[-1, 2] - 2 * np.exp(-1.0)) < 1e-9)
    True
    >>> angle = 2.0 * (1 - np.exp(-1.0))  # ∫|ω| dt
    >>> bool(np.max(np.abs(tr.q[-1] - (np.cos(angle / 2), 0, 0, np.sin(angle / 2)))) < 1e-9)
    True
    """
    choice("method", method, TORQUED_METHODS)
    if accuracy is not None:
        return _to_accuracy(rhs, omega0, q0, t, h=h, params=params, gamma=gamma, method=method, accuracy=accuracy)
    if not callable(rhs):
        raise InvalidInput("rhs", rhs, "a callable rhs(t, y, *params) -> ydot (a kernel's rhs_batched)")
    w0 = finite_array("omega0", omega0)
    qq = finite_array("q0", q0)
    single = w0.ndim == 1 and qq.ndim == 1
    B = next((a.shape[0] for a in (w0, qq) if a.ndim == 2), 1)
    if w0.shape not in ((3,), (B, 3)):
        raise InvalidInput("omega0", omega0, f"shape (3,) or ({B}, 3)")
    if qq.shape not in ((4,), (B, 4)):
        raise InvalidInput("q0", q0, f"shape (4,) or ({B}, 4)")
    w = np.broadcast_to(w0, (B, 3)).T.copy()
    q = np.broadcast_to(qq, (B, 4)).T.copy()
    norm = np.sqrt(np.sum(q * q, axis=0))
    if np.any(np.abs(norm - 1.0) > 1e-6):
        raise InvalidInput("q0", q0, "unit quaternions (q0, q1, q2, q3), scalar first, |q| = 1")
    q = q / norm
    tt = finite_array("t", t, shape=(None,))
    if tt.size == 0:
        raise InvalidInput("t", t, "at least one output time")
    if h is None:
        fastest = float(np.max(np.sqrt(np.sum(w * w, axis=0)), initial=0.0))
        h = 2 * np.pi / (64 * fastest) if fastest > 0 else np.inf
        h = min(h, float(np.min(np.diff(tt)))) if tt.size > 1 else 1.0
    counts, steps = output_steps(tt, h)
    n_state = 10 if gamma else 7

    def wdot(tk, wk, qk):
        y = np.vstack([wk, _gamma(qk), qk]) if gamma else np.vstack([wk, qk])
        out = np.asarray(rhs(tk, y, *params), dtype=np.float64)
        if out.ndim != 2 or out.shape[0] < 3 or out.shape[1] != B:
            raise InvalidInput("rhs", rhs, f"ydot of shape ({n_state}, {B}) for y of shape ({n_state}, {B})")
        return out[:3]

    W = np.empty((B, tt.size, 3))
    Q = np.empty((B, tt.size, 4))
    W[:, 0], Q[:, 0] = w.T, q.T
    tk = float(tt[0])
    calls = 0
    for i, (n, hk) in enumerate(zip(counts.tolist(), steps.tolist())):
        for j in range(n):
            tk = float(tt[i]) + j * hk
            a1 = wdot(tk, w, q)
            x1 = hk * w
            w2, q2 = w + 0.5 * hk * a1, _times(q, 0.5 * x1)
            a2 = wdot(tk + 0.5 * hk, w2, q2)
            x2 = hk * w2
            w3, q3 = w + 0.5 * hk * a2, _times(q, 0.5 * x2)
            a3 = wdot(tk + 0.5 * hk, w3, q3)
            x3 = hk * w3
            w4, q4 = w + hk * a3, _times(q2, x3 - 0.5 * x1)
            a4 = wdot(tk + hk, w4, q4)
            x4 = hk * w4
            q = _times(_times(q, (3 * x1 + 2 * x2 + 2 * x3 - x4) / 12.0), (-x1 + 2 * x2 + 2 * x3 + 3 * x4) / 12.0)
            q = q / np.sqrt(np.sum(q * q, axis=0))
            w = w + hk / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
            calls += 4
        if not (np.all(np.isfinite(w)) and np.all(np.isfinite(q))):
            raise InvalidInput("h", h, "a step small enough for a finite solution (or an rhs without NaN)")
        W[:, i + 1], Q[:, i + 1] = w.T, q.T
    G = np.moveaxis(_gamma(np.moveaxis(Q, -1, 0)), 0, -1)
    if single:
        return Trajectory(t=tt, omega=W[0], q=Q[0], gamma=G[0], n_rhs_calls=calls, method=f"lie_group:{method}")
    return BatchTrajectory(t=tt, omega=W, gamma=G, q=Q, steps=np.full(B, float(np.max(steps, initial=h))),
                           n_kicks=calls * B, method=f"lie_group:{method}")


def _to_accuracy(rhs, omega0, q0, t, *, h, params, gamma, method, accuracy):
    """:func:`integrate_torqued` brought to ``accuracy`` by Richardson's estimate (steps shared by the members)."""
    import dataclasses
    import math

    from eulersym.numerics.methods._accuracy import richardson

    if h is not None:
        raise InvalidInput("accuracy", accuracy, "None when a step h is given (one or the other)")
    if not isinstance(accuracy, (int, float)) or not (0.0 < float(accuracy) < 1.0) or not math.isfinite(accuracy):
        raise InvalidInput("accuracy", accuracy, "a relative accuracy with 0 < accuracy < 1")
    tt = finite_array("t", t, shape=(None,))
    if tt.size < 2:
        return integrate_torqued(rhs, omega0, q0, t, params=params, gamma=gamma, method=method)
    dt = float(np.min(np.diff(tt)))
    w0 = np.atleast_2d(finite_array("omega0", omega0))
    fastest = float(np.max(np.linalg.norm(w0, axis=1), initial=0.0))
    first = 1 if fastest == 0 else max(1, math.ceil(dt / (2 * np.pi / (16 * fastest))))
    single = np.ndim(omega0) == 1 and np.ndim(q0) == 1

    def run(n):
        tr = integrate_torqued(rhs, omega0, q0, tt, h=dt / n * (1 + 1e-12), params=params, gamma=gamma,
                               method=method)
        if single:  # batch-first for the estimate
            tr = dataclasses.replace(tr, omega=tr.omega[None], q=tr.q[None], gamma=None)
        return dataclasses.replace(tr, gamma=None)

    best = richardson(run, first, float(accuracy), 4)
    G = np.moveaxis(_gamma(np.moveaxis(best.q, -1, 0)), 0, -1)
    if single:
        return dataclasses.replace(best, omega=best.omega[0], q=best.q[0], gamma=G[0],
                                   error={k: float(v[0]) for k, v in best.error.items()})
    return dataclasses.replace(best, gamma=G)
