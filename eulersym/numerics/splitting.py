"""Geometric integrators for the free rigid body: exact-rotation splittings and the discrete Moser–Veselov method.

State: the body angular momentum ``m = I ω`` and the attitude quaternion ``q`` (scalar first,
``v_space = R(q) v_body``, ``q̇ = ½ q ⊗ (0, ω)``). Euler's equations read ``ṁ = m × ω``, ``ω = I⁻¹ m``.

Methods
-------
``"strang"``
    The symmetric splitting ``H = H1 + H2 + H3``, ``Hᵢ = mᵢ² / (2 Iᵢ)`` (Touma–Wisdom; McLachlan; Reich;
    Dullweber–Leimkuhler–McLachlan 1997, the rotation splitting that NO_SQUISH performs on quaternions). Each
    sub-flow is an *exact* rotation about a body axis: m turns about eᵢ by −(mᵢ/Iᵢ)τ and ``q ← q ⊗ exp(τ mᵢ/Iᵢ eᵢ / 2)``.
    Step ``Φ1(h/2) Φ2(h/2) Φ3(h) Φ2(h/2) Φ1(h/2)``; order 2, symplectic, time-reversible; |m| and |q| are kept to
    round-off.
``"yoshida4"``
    Yoshida's triple-jump composition of the Strang step, ``γ1 = 1/(2 − 2^{1/3})``, ``γ2 = 1 − 2γ1``; order 4.
``"dmv2"``, ``"dmv4"``, ``"dmv6"``
    The discrete Moser–Veselov algorithm in Hairer–Vilmart's quaternion form, with their modified moments of
    inertia for orders 4 and 6 (E. Hairer, G. Vilmart, *Preprocessed discrete Moser–Veselov algorithm for the
    full dynamics of a rigid body*, J. Phys. A 39 (2006) 13225). Each step solves for ``c`` (the vector part of
    the body-frame increment quaternion (1, c)) by fixed-point iteration, then ``q ← q ⊗ (1, c)/√(1+|c|²)`` and
    ``mᵢ ← mᵢ + 4/h (Jⱼ − Jₖ) cⱼ cₖ / (1 + |c|²)``.
``"rk4"``
    The classical Runge–Kutta method on (ω, q): a non-geometric reference that drifts, for the stress tests.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from eulersym.attitude import hamilton
from eulersym.errors import InvalidInput
from eulersym.numerics import _fast
from eulersym.numerics.exact import _unit_quaternion
from eulersym.numerics.trajectory import Trajectory
from eulersym.validation import choice, finite_array, moments

__all__ = ["integrate_free_body", "FREE_BODY_METHODS", "NOMINAL_ORDER", "step_free_bodies", "output_steps"]

#: Names accepted by :func:`integrate_free_body`.
FREE_BODY_METHODS = ("strang", "yoshida4", "dmv2", "dmv4", "dmv6", "rk4")
#: Nominal order of each method.
NOMINAL_ORDER = {"strang": 2, "yoshida4": 4, "dmv2": 2, "dmv4": 4, "dmv6": 6, "rk4": 4}
#: Sub-flow / kernel evaluations per step (for ``Trajectory.n_rhs_calls``).
_CALLS_PER_STEP = {"strang": 5, "yoshida4": 15, "dmv2": 1, "dmv4": 1, "dmv6": 1, "rk4": 4}

_CBRT2 = 2.0 ** (1.0 / 3.0)
YOSHIDA_GAMMA = (1.0 / (2.0 - _CBRT2), -_CBRT2 / (2.0 - _CBRT2), 1.0 / (2.0 - _CBRT2))


# ----------------------------------------------------------------------------------------------------------------
# Exact sub-flows Φᵢ(τ) of Hᵢ = mᵢ²/(2Iᵢ) (work on floats and on NumPy arrays alike)
# ----------------------------------------------------------------------------------------------------------------
def _flow1(s, tau, inv, cos, sin):
    m1, m2, m3, q0, q1, q2, q3 = s
    half = 0.5 * tau * m1 * inv[0]
    if cos is None:  # scalars (and numba); NumPy arrays pass np.cos, np.sin
        c, sn = math.cos(half), math.sin(half)
    else:
        c, sn = cos(half), sin(half)
    # increment form of the rotation by 2·half (C − 1 = −2 s², S = 2 s c): round-off ∝ the increment, not |m|
    a, b = 2.0 * sn * (sn * m2 - c * m3), 2.0 * sn * (sn * m3 + c * m2)
    return (m1, m2 - a, m3 - b, q0 * c - q1 * sn, q1 * c + q0 * sn, q2 * c + q3 * sn, q3 * c - q2 * sn)


def _flow2(s, tau, inv, cos, sin):
    m1, m2, m3, q0, q1, q2, q3 = s
    half = 0.5 * tau * m2 * inv[1]
    if cos is None:  # scalars (and numba); NumPy arrays pass np.cos, np.sin
        c, sn = math.cos(half), math.sin(half)
    else:
        c, sn = cos(half), sin(half)
    a, b = 2.0 * sn * (sn * m1 + c * m3), 2.0 * sn * (sn * m3 - c * m1)
    return (m1 - a, m2, m3 - b, q0 * c - q2 * sn, q1 * c - q3 * sn, q2 * c + q0 * sn, q3 * c + q1 * sn)


def _flow3(s, tau, inv, cos, sin):
    m1, m2, m3, q0, q1, q2, q3 = s
    half = 0.5 * tau * m3 * inv[2]
    if cos is None:  # scalars (and numba); NumPy arrays pass np.cos, np.sin
        c, sn = math.cos(half), math.sin(half)
    else:
        c, sn = cos(half), sin(half)
    a, b = 2.0 * sn * (sn * m1 - c * m2), 2.0 * sn * (sn * m2 + c * m1)
    return (m1 - a, m2 - b, m3, q0 * c - q3 * sn, q1 * c + q2 * sn, q2 * c - q1 * sn, q3 * c + q0 * sn)


def _strang(s, h, inv, par, cos, sin):
    hh = 0.5 * h
    s = _flow1(s, hh, inv, cos, sin)
    s = _flow2(s, hh, inv, cos, sin)
    s = _flow3(s, h, inv, cos, sin)
    s = _flow2(s, hh, inv, cos, sin)
    return _flow1(s, hh, inv, cos, sin)


def _yoshida4(s, h, inv, par, cos, sin):
    g1, g2, _ = YOSHIDA_GAMMA
    s = _strang(s, g1 * h, inv, par, cos, sin)
    s = _strang(s, g2 * h, inv, par, cos, sin)
    return _strang(s, g1 * h, inv, par, cos, sin)


def _rk4_rhs(s, inv):
    m1, m2, m3, q0, q1, q2, q3 = s
    w1, w2, w3 = m1 * inv[0], m2 * inv[1], m3 * inv[2]
    qd = hamilton((q0, q1, q2, q3), (0.0, w1, w2, w3))  # q̇ = ½ q ⊗ (0, ω)
    return (m2 * w3 - m3 * w2, m3 * w1 - m1 * w3, m1 * w2 - m2 * w1,
            0.5 * qd[0], 0.5 * qd[1], 0.5 * qd[2], 0.5 * qd[3])


def _rk4(s, h, inv, par, cos, sin):
    k1 = _rk4_rhs(s, inv)
    k2 = _rk4_rhs(tuple(a + 0.5 * h * b for a, b in zip(s, k1)), inv)
    k3 = _rk4_rhs(tuple(a + 0.5 * h * b for a, b in zip(s, k2)), inv)
    k4 = _rk4_rhs(tuple(a + h * b for a, b in zip(s, k3)), inv)
    return tuple(a + h / 6.0 * (b + 2.0 * c + 2.0 * d + e) for a, b, c, d, e in zip(s, k1, k2, k3, k4))


# ----------------------------------------------------------------------------------------------------------------
# Discrete Moser–Veselov with Hairer–Vilmart's modified moments
# ----------------------------------------------------------------------------------------------------------------
def _dmv_coefficients(I, order):
    """Coefficients of the modified inverse moments 1/Jᵢ = css/Iᵢ + cdd (Hairer & Vilmart 2006, eqs. for p = 4, 6)."""
    a1, a2, a3 = I
    xi1 = 1 / a1 + 1 / a2 + 1 / a3
    xi2 = 1 / a1**2 + 1 / a2**2 + 1 / a3**2
    det = a1 * a2 * a3
    s1 = a1 + a2 + a3
    s2 = a1**2 + a2**2 + a3**2
    si = (a1 + a2) / a3 + (a2 + a3) / a1 + (a3 + a1) / a2
    c = {"s3": (0.0, 0.0), "d3": (0.0, 0.0), "s5": (0.0, 0.0, 0.0), "d5": (0.0, 0.0, 0.0)}
    if order >= 4:
        c["s3"] = (s1 / (6 * det), -xi1 / 3)
        c["d3"] = (-1 / (3 * det), s1 / (6 * det))
    if order >= 6:
        c["s5"] = ((s2 / det - xi1) / (30 * det), (1 - si) / (30 * det), (3 * s1 / det + 2 * xi2) / 60)
        c["d5"] = (-s1 / det**2 / 60, xi1 / det / 10 - s2 / det**2 / 60, -(9 + si) / det / 60)
    return c


def _dmv_parameters(I, order):
    """(I1, I2, I3, s31, s32, d31, d32, s51, s52, s53, d51, d52, d53) for :func:`_dmv_step`."""
    coef = _dmv_coefficients(I, order)
    return (*I, *coef["s3"], *coef["d3"], *coef["s5"], *coef["d5"])


def _dmv_step(s, h, inv, par, cos, sin):
    """One DMV step; a NaN state when the fixed-point iteration does not converge (the driver raises)."""
    m1, m2, m3, q0, q1, q2, q3 = s
    a1, a2, a3, s31, s32, d31, d32, s51, s52, s53, d51, d52, d53 = par
    h2 = h * h
    ham = 0.5 * h2 * (m1 * m1 / a1 + m2 * m2 / a2 + m3 * m3 / a3)
    nor = 0.5 * h2 * (m1 * m1 + m2 * m2 + m3 * m3)
    css = 1.0 + s31 * nor + s32 * ham + s51 * nor * nor + s52 * nor * ham + s53 * ham * ham
    cdd = d31 * nor + d32 * ham + d51 * nor * nor + d52 * nor * ham + d53 * ham * ham
    j1i, j2i, j3i = css / a1 + cdd, css / a2 + cdd, css / a3 + cdd
    j1, j2, j3 = 1.0 / j1i, 1.0 / j2i, 1.0 / j3i
    fad1, fad2, fad3 = j2 - j3, j3 - j1, j1 - j2
    fac1, fac2, fac3 = fad1 * j1i, fad2 * j2i, fad3 * j3i
    hh = 0.5 * h
    b1, b2, b3 = m1 * hh * j1i, m2 * hh * j2i, m3 * hh * j3i
    c1 = b1 + fac1 * b2 * b3
    c2 = b2 + fac2 * c1 * b3
    c3 = b3 + fac3 * c1 * c2
    converged = False
    for _ in range(100):
        o1, o2, o3 = c1, c2, c3
        alpha = 1.0 + c1 * c1 + c2 * c2 + c3 * c3
        c1 = alpha * b1 + fac1 * c2 * c3
        c2 = alpha * b2 + fac2 * c1 * c3
        c3 = alpha * b3 + fac3 * c1 * c2
        err = abs(o1 - c1) + abs(o2 - c2) + abs(o3 - c3)
        if err <= 4e-16 * (abs(c1) + abs(c2) + abs(c3)) or err == 0.0:
            converged = True
            break
    if not converged:
        nan = math.nan
        return (nan, nan, nan, nan, nan, nan, nan)
    alpha = 1.0 + c1 * c1 + c2 * c2 + c3 * c3
    n0 = q0 - c1 * q1 - c2 * q2 - c3 * q3
    n1 = q1 + c1 * q0 + c3 * q2 - c2 * q3
    n2 = q2 + c2 * q0 + c1 * q3 - c3 * q1
    n3 = q3 + c3 * q0 + c2 * q1 - c1 * q2
    r = 1.0 / math.sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3)
    k = 4.0 / (h * alpha)
    return (m1 + k * fad1 * c2 * c3, m2 + k * fad2 * c1 * c3, m3 + k * fad3 * c1 * c2, n0 * r, n1 * r, n2 * r, n3 * r)


def _run_free(kind, state, counts, steps, inv, par, cos, sin):
    """The stepping loop (plain Python; compiled unchanged by numba in :mod:`eulersym.numerics._fast`).

    kind: 0 Strang, 1 Yoshida 4, 2 DMV. Returns the states at the outputs, shape (len(counts) + 1, 7); rows after
    a failed step are NaN.
    """
    out = np.full((len(counts) + 1, 7), np.nan)
    s = (state[0], state[1], state[2], state[3], state[4], state[5], state[6])
    for k in range(7):
        out[0, k] = s[k]
    for i in range(len(counts)):
        hk = steps[i]
        for _ in range(counts[i]):
            if kind == 0:
                s = _strang(s, hk, inv, par, cos, sin)
            elif kind == 1:
                s = _yoshida4(s, hk, inv, par, cos, sin)
            else:
                s = _dmv_step(s, hk, inv, par, cos, sin)
            if kind < 2:  # the DMV normalises q inside its step
                r = 1.0 / math.sqrt(s[3] * s[3] + s[4] * s[4] + s[5] * s[5] + s[6] * s[6])
                s = (s[0], s[1], s[2], s[3] * r, s[4] * r, s[5] * r, s[6] * r)
        if s[0] != s[0]:
            break
        for k in range(7):
            out[i + 1, k] = s[k]
    return out


def _run_rk4(state, counts, steps, inv):
    """RK4 loop (plain Python only: a reference that is left to drift, |q| included)."""
    out = np.full((len(counts) + 1, 7), np.nan)
    s = tuple(state)
    out[0] = s
    for i, (n, hk) in enumerate(zip(counts, steps)):
        for _ in range(n):
            s = _rk4(s, hk, inv, None, None, None)
        out[i + 1] = s
    return out


def output_steps(t, h):
    """Split each output interval of ``t`` into equal steps no longer than ``h``: returns (counts, step sizes).

    Raises InvalidInput when ``t`` is not strictly increasing, or ``h`` is not positive or exceeds the span.

    Examples
    --------
    >>> output_steps(np.array([0.0, 1.0, 1.5]), 0.3)
    (array([4, 2]), array([0.25, 0.25]))
    """
    t = np.asarray(t, dtype=np.float64)
    if t.size < 2:
        return np.zeros(0, dtype=int), np.zeros(0)
    dt = np.diff(t)
    if np.any(dt <= 0):
        raise InvalidInput("t", t, "strictly increasing output times")
    span = t[-1] - t[0]
    h = float(h)
    if not math.isfinite(h) or h <= 0.0 or h > span * (1 + 1e-12):
        raise InvalidInput("h", h, f"a step size with 0 < h <= the span t[-1] - t[0] = {span:g}")
    counts = np.maximum(1, np.ceil(dt / h * (1 - 1e-12)).astype(int))
    return counts, dt / counts


def default_step(I, omega0, t):
    """The step used when ``h=None``: 1/64 of the fastest rotation period, capped by the output spacing."""
    w = float(np.max(np.abs(omega0))) * max(I) / min(I)
    h = 2 * math.pi / (64 * w) if w > 0 else np.inf
    dt = np.diff(np.asarray(t, dtype=np.float64))
    return float(min(h, np.min(dt))) if dt.size else 1.0


def integrate_free_body(I, omega0, q0, t, *, method="dmv4", h=None, check_body=True, fast=None):
    """Integrate the torque-free rigid body (ω and attitude) with a geometric fixed-step method.

    Parameters
    ----------
    I : sequence of 3 floats
        Principal moments.
    omega0 : array_like, shape (3,)
        Body angular velocity at ``t[0]``.
    q0 : array_like, shape (4,)
        Unit quaternion at ``t[0]`` (scalar first, ``v_space = R(q) v_body``).
    t : array_like, shape (n,)
        Strictly increasing output times.
    method : {"strang", "yoshida4", "dmv2", "dmv4", "dmv6", "rk4"}
        See the module docstring.
    h : float, optional
        Largest step; each output interval is split into equal steps no longer than ``h``. Default:
        :func:`default_step`.
    check_body : bool, optional
        Require physical moments (triangle inequalities).
    fast : bool or None, optional
        Run the stepping loop compiled by numba (the optional ``fast`` extra; cached on disk). ``None`` (default):
        when numba is installed; ``True``: require it; ``False``: plain Python. Both run the same functions.

    Returns
    -------
    Trajectory
        ``omega`` (n, 3), ``q`` (n, 4); ``n_rhs_calls`` counts sub-flow evaluations.

    Raises
    ------
    eulersym.errors.InvalidInput
        Bad moments, non-finite state, ``h <= 0`` or ``h`` larger than the span, unknown method, a step too large
        for the DMV iteration.

    Examples
    --------
    >>> import numpy as np
    >>> from eulersym.numerics import free_rigid_body_exact
    >>> tr = integrate_free_body((1.0, 2.0, 3.0), (1.0, 0.5, 0.2), (1, 0, 0, 0), [0.0, 10.0], method="dmv6", h=0.01)
    >>> exact = free_rigid_body_exact((1.0, 2.0, 3.0), (1.0, 0.5, 0.2), [10.0])
    >>> bool(np.max(np.abs(tr.omega[-1] - exact[0])) < 1e-10)
    True
    """
    I = tuple(float(x) for x in moments("I", I, body=check_body))
    method = choice("method", method, FREE_BODY_METHODS)
    w0 = finite_array("omega0", omega0, shape=(3,))
    qq = _unit_quaternion(q0)
    tt = finite_array("t", t, shape=(None,))
    if tt.size == 0:
        raise InvalidInput("t", t, "at least one output time")
    if h is None:
        h = default_step(I, w0, tt)
    counts, steps = output_steps(tt, h)
    inv = (1.0 / I[0], 1.0 / I[1], 1.0 / I[2])
    state = tuple(float(x) for x in (I[0] * w0[0], I[1] * w0[1], I[2] * w0[2], *qq))
    if method == "rk4":
        out = _run_rk4(state, counts.tolist(), steps.tolist(), inv)
    else:
        kind = {"strang": 0, "yoshida4": 1}.get(method, 2)
        par = _dmv_parameters(I, int(method[-1])) if kind == 2 else (0.0,) * 13
        runner = _fast.select(fast, _compiled_runner)
        if runner is not None:
            out = runner(kind, state, counts, steps, inv, par)
        else:
            out = _run_free(kind, state, counts.tolist(), steps.tolist(), inv, par, None, None)
    if not np.all(np.isfinite(out)):
        raise InvalidInput("h", h, "a step small enough for a finite solution")
    omega = out[:, :3] * np.array(inv)
    return Trajectory(
        t=tt, omega=omega, q=out[:, 3:], gamma=None, n_rhs_calls=int(counts.sum()) * _CALLS_PER_STEP[method], method=method
    )


def step_free_bodies(I, omega, q, h, *, method="strang"):
    """One step of many free bodies at once (NumPy, vectorised over the last axis).

    Parameters
    ----------
    I : sequence of 3 floats
        Common principal moments.
    omega : ndarray, shape (3, N)
    q : ndarray, shape (4, N)
    h : float
    method : {"strang", "yoshida4", "rk4"}

    Returns
    -------
    omega, q : ndarray, shapes (3, N), (4, N)

    Examples
    --------
    >>> import numpy as np
    >>> w, q = step_free_bodies((1.0, 2.0, 3.0), np.ones((3, 5)), np.tile([[1.0], [0], [0], [0]], 5), 0.01)
    >>> w.shape, q.shape
    ((3, 5), (4, 5))
    """
    I = tuple(float(x) for x in moments("I", I))
    choice("method", method, ("strang", "yoshida4", "rk4"))
    inv = (1.0 / I[0], 1.0 / I[1], 1.0 / I[2])
    omega = np.asarray(omega, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    s = (omega[0] * I[0], omega[1] * I[1], omega[2] * I[2], q[0], q[1], q[2], q[3])
    step = {"strang": _strang, "yoshida4": _yoshida4, "rk4": _rk4}[method]
    s = step(s, float(h), inv, None, np.cos, np.sin)
    return np.stack([s[0] * inv[0], s[1] * inv[1], s[2] * inv[2]]), np.stack(s[3:])


@lru_cache(maxsize=1)
def _compiled_runner():
    """``runner(kind, state, counts, steps, inv, par) -> out`` compiled from :func:`_run_free` (numba, cached on disk)."""
    import numba
    from numba.extending import register_jitable

    for fn in (_flow1, _flow2, _flow3, _strang, _yoshida4, _dmv_step):
        register_jitable(fn)
    run = numba.njit(cache=True)(_run_free)

    def runner(kind, state, counts, steps, inv, par):
        return run(kind, np.asarray(state, dtype=np.float64), np.asarray(counts, dtype=np.int64),
                   np.asarray(steps, dtype=np.float64), tuple(inv), tuple(par), None, None)

    return runner
