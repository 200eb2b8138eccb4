"""The heavy symmetric top without coordinate singularities: Strang splitting in the Euler–Poisson form.

Model: principal moments ``(I1, I1, I3)`` about the fixed pivot, centre of mass at ``l·e3`` in the body, gravity
``−M g ẑ``. State: body angular momentum ``m = I ω``, the body components of the upward vertical
``Γ = R(q)ᵀ ẑ`` and the attitude quaternion ``q`` (scalar first, ``v_space = R(q) v_body``). Hamiltonian
``H = T(m) + V(Γ)``, ``T = ½ m·I⁻¹m``, ``V = M g l Γ3`` (= M g l cos θ). Equations (Euler–Poisson)::

    ṁ = m × ω + Γ × ∂V/∂Γ,   Γ̇ = Γ × ω,   q̇ = ½ q ⊗ (0, ω),   ω = I⁻¹ m.

Splitting (exact sub-flows, Strang ``K(h/2) F(h) K(h/2)``, kicks of neighbouring steps merged):

* ``K(τ)``, the flow of V: Γ and q fixed, ``m ← m + τ Γ × ∂V/∂Γ = m + τ M g l (Γ × e3)``.
* ``F(τ)``, the free symmetric top, exactly: ``T = |m|²/(2 I1) + ½ (1/I3 − 1/I1) m3²`` is a sum of two commuting
  flows, each a rotation with constant body angular velocity ``ω_a = m / I1`` and ``ω_b = ν e3``,
  ``ν = (1/I3 − 1/I1) m3``: ``q ← q ⊗ p``, ``Γ ← R(p)ᵀ Γ``, ``m ← R(p)ᵀ m`` with ``p = exp(τ ω / 2)``.

Every sub-flow is a rotation or a kick orthogonal to Γ, so |Γ|², L·Γ and |q| are conserved to round-off and the
energy error stays bounded. Euler angles appear only as outputs (:func:`eulersym.numerics.invariants.euler_angles`);
the vertical sleeping top (Γ = e3) is an exact fixed point of every sub-flow.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.numerics import _fast
from eulersym.numerics.exact import _unit_quaternion
from eulersym.numerics.splitting import YOSHIDA_GAMMA, output_steps
from eulersym.numerics.trajectory import Trajectory
from eulersym.attitude import hamilton, rotate, rotate_back as _rotate_back, rotvec_to_quaternion
from eulersym.validation import choice, finite_array, moments, positive

__all__ = ["integrate_heavy_top", "HEAVY_TOP_METHODS", "sleeping_top_threshold_numeric"]

HEAVY_TOP_METHODS = ("strang", "yoshida4")



def _free(s, tau, i1inv, nu_coef):
    """Exact flow of the free symmetric top for time τ."""
    m0, m1, m2, g0, g1, g2, q0, q1, q2, q3 = s
    # ω_a = m / I1: m is fixed, Γ and q turn
    k = tau * i1inv
    p = rotvec_to_quaternion(k * m0, k * m1, k * m2, None, None)  # exp(τ ω_a / 2)
    g0, g1, g2 = _rotate_back(*p, g0, g1, g2)
    q0, q1, q2, q3 = hamilton((q0, q1, q2, q3), p)
    # ω_b = ν e3: m, Γ and q turn about e3
    half = 0.5 * tau * nu_coef * m2
    c, sn = math.cos(half), math.sin(half)
    # rotation by −2·half about e3 in increment form (C − 1 = −2 s², S = 2 s c): round-off ∝ the increment
    m0, m1 = m0 - 2.0 * sn * (sn * m0 - c * m1), m1 - 2.0 * sn * (sn * m1 + c * m0)
    g0, g1 = g0 - 2.0 * sn * (sn * g0 - c * g1), g1 - 2.0 * sn * (sn * g1 + c * g0)
    q0, q1, q2, q3 = q0 * c - q3 * sn, q1 * c + q2 * sn, q2 * c - q1 * sn, q3 * c + q0 * sn
    return (m0, m1, m2, g0, g1, g2, q0, q1, q2, q3)


def _kick(s, tau, mgl):
    m0, m1, m2, g0, g1, g2, q0, q1, q2, q3 = s
    k = tau * mgl  # Γ × e3 = (Γ2, −Γ1, 0)
    return (m0 + k * g1, m1 - k * g0, m2, g0, g1, g2, q0, q1, q2, q3)


def _renormalise(s):
    m0, m1, m2, g0, g1, g2, q0, q1, q2, q3 = s
    r = 1.0 / math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return (m0, m1, m2, g0, g1, g2, q0 * r, q1 * r, q2 * r, q3 * r)


def _run_top(state, counts, steps, subs, i1inv, nu_coef, mgl):
    """The stepping loop (plain Python; compiled unchanged by numba in :mod:`eulersym.numerics._fast`)."""
    out = np.full((len(counts) + 1, 10), np.nan)
    s = (state[0], state[1], state[2], state[3], state[4], state[5], state[6], state[7], state[8], state[9])
    for k in range(10):
        out[0, k] = s[k]
    kicks = 0
    for i in range(len(counts)):
        hk = steps[i]
        for _ in range(counts[i]):
            for gam in subs:
                tau = gam * hk
                s = _kick(s, 0.5 * tau, mgl)
                s = _free(s, tau, i1inv, nu_coef)
                s = _kick(s, 0.5 * tau, mgl)
                kicks += 1
            s = _renormalise(s)
        for k in range(10):
            out[i + 1, k] = s[k]
    return out, kicks


def integrate_heavy_top(I, M, g, l, omega0, q0, t, *, h=None, method="strang", fast=None):
    """Integrate the heavy symmetric top with a non-singular splitting in the Euler–Poisson form.

    Parameters
    ----------
    I : sequence of 3 floats
        Principal moments about the pivot, ``(I1, I1, I3)`` (the first two equal).
    M, g, l : float
        Mass, gravitational acceleration, distance from the pivot to the centre of mass (along e3).
    omega0 : array_like, shape (3,)
        Body angular velocity at ``t[0]``.
    q0 : array_like, shape (4,)
        Unit attitude quaternion at ``t[0]``; ``Γ0 = R(q0)ᵀ ẑ`` (``q0 = (1, 0, 0, 0)`` is the upright top, θ = 0).
    t : array_like, shape (n,)
        Strictly increasing output times.
    h : float, optional
        Largest step (default: 1/32 of the shortest of the rotation, nutation (2π I1 / (I3 |ω3|)) and pendulum
        periods, capped by the output spacing).
    method : {"strang", "yoshida4"}
        Order 2 (Strang) or its order-4 triple-jump composition.
    fast : bool or None, optional
        Compiled loop with numba (the ``fast`` extra): None = when installed, True = required, False = plain Python.

    Returns
    -------
    Trajectory
        ``omega``, ``q`` and ``gamma``; ``n_rhs_calls`` counts the potential kicks (the only force evaluations).

    Raises
    ------
    eulersym.errors.InvalidInput
        Non-symmetric or non-physical moments, non-positive M, g or l, non-finite state, bad step size.

    Examples
    --------
    >>> import numpy as np
    >>> tr = integrate_heavy_top((1.0, 1.0, 2.0), 1.0, 9.81, 0.5, (0, 0, 8.0), (1, 0, 0, 0), [0.0, 100.0])
    >>> tr.gamma[-1]            # the sleeping top at θ = 0 stays exactly upright
    array([0., 0., 1.])
    >>> tr.n_rhs_calls <= 10_000
    True
    """
    I = tuple(float(x) for x in moments("I", I))
    if abs(I[0] - I[1]) > 1e-14 * max(I):
        raise InvalidInput("I", I, "a symmetric top (I1, I1, I3): the first two moments equal")
    M, g, l = (float(positive(name, v)) for name, v in (("M", M), ("g", g), ("l", l)))
    method = choice("method", method, HEAVY_TOP_METHODS)
    w0 = finite_array("omega0", omega0, shape=(3,))
    qq = _unit_quaternion(q0)
    tt = finite_array("t", t, shape=(None,))
    if tt.size == 0:
        raise InvalidInput("t", t, "at least one output time")
    mgl = M * g * l
    if h is None:
        fastest = max(float(np.max(np.abs(w0))), I[2] * abs(float(w0[2])) / I[0], math.sqrt(mgl / I[0]))
        h = 2 * math.pi / (32 * fastest)
        if tt.size > 1:
            h = min(h, float(np.min(np.diff(tt))))
    counts, steps = output_steps(tt, h)
    a, b, c, d = qq
    gamma0 = (2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d)  # R(q)ᵀ ẑ
    state = tuple(float(x) for x in (I[0] * w0[0], I[1] * w0[1], I[2] * w0[2], *gamma0, *qq))
    i1inv, nu_coef = 1.0 / I[0], 1.0 / I[2] - 1.0 / I[0]
    subs = (1.0,) if method == "strang" else YOSHIDA_GAMMA
    runner = _fast.select(fast, _compiled_runner)
    if runner is not None:
        out, kicks = runner(state, counts, steps, subs, i1inv, nu_coef, mgl)
    else:
        out, kicks = _run_top(state, counts.tolist(), steps.tolist(), subs, i1inv, nu_coef, mgl)
    if not np.all(np.isfinite(out)):
        raise InvalidInput("h", h, "a step small enough for a finite solution")
    inv = np.array([1.0 / I[0], 1.0 / I[1], 1.0 / I[2]])
    # merged half kicks: one force evaluation per sub-step, plus one to start
    return Trajectory(
        t=tt, omega=out[:, :3] * inv, q=out[:, 6:], gamma=out[:, 3:6], n_rhs_calls=kicks + 1, method=f"heavy_top:{method}"
    )


def _euler_poisson_field(x, inertia, mgl):
    """The Euler–Poisson vector field in (m, Γ): ṁ = m × ω + M g l Γ × e3, Γ̇ = Γ × ω, ω = m / I."""
    m, G = x[:3], x[3:]
    w = m / inertia
    return np.concatenate([np.cross(m, w) + mgl * np.array([G[1], -G[0], 0.0]), np.cross(G, w)])


def _upright_growth(I1, I3, mgl, w3):
    """Largest growth rate Re λ of the linearised motion about the upright top spinning at w3, and |λ|max.

    The Jacobian of the Euler–Poisson field at (m, Γ) = (I3 w3 e3, e3) by central differences (exact up to
    rounding: the field is quadratic), and its eigenvalues.
    """
    inertia = np.array([I1, I1, I3])
    x0 = np.array([0.0, 0.0, I3 * w3, 0.0, 0.0, 1.0])
    scale = np.array([max(abs(I3 * w3), math.sqrt(I1 * mgl))] * 3 + [1.0] * 3)
    J = np.empty((6, 6))
    for k in range(6):
        h = 1e-3 * scale[k]
        e = np.zeros(6)
        e[k] = h
        J[:, k] = (_euler_poisson_field(x0 + e, inertia, mgl) - _euler_poisson_field(x0 - e, inertia, mgl)) / (2 * h)
    lam = np.linalg.eigvals(J)
    return float(np.max(lam.real)), float(np.max(np.abs(lam)))


def sleeping_top_threshold_numeric(I1, I3, M, g, l, *, theta0=1e-6, periods=60.0, rtol=1e-3, method="linear"):
    """Locate the sleeping-top stability threshold on ω3² numerically, by bisection on a stability test.

    The returned ω3² brackets the transition to relative width ``rtol`` (and is within ``rtol`` of the exact
    threshold). Linear theory predicts ω3² = 4 M g l I1 / I3²; this function does not use it. Two tests of "asleep":

    * ``method="linear"`` (default): the Jacobian of the Euler–Poisson vector field at the upright top, by central
      differences (exact up to rounding: the field is quadratic), has no eigenvalue with a growing real part
      (``Re λ ≤ 1e-6 |λ|max``). Just under the threshold ω3² = ω_c²(1 − δ) the growth rate is ~√δ/τ with
      ``τ = √(I1/(M g l))``, so the test resolves δ down to ~1e-11: every ``rtol ≥ 1e-10`` is honoured.
    * ``method="integrate"``: a top started at θ = ``theta0`` with spin ω3 and no other rates is asleep when θ
      stays below ``100·theta0`` over the horizon; the horizon is ``periods`` pendulum times τ, extended to
      ``3 ln(100) τ/√(rtol/2)`` — three e-foldings past the 100× growth of a top just ``rtol/2`` under the
      threshold, whose growth rate is ~√δ/τ — so the slow growth there is seen (slow for small rtol).

    Parameters
    ----------
    I1, I3, M, g, l : float
        Moments about the pivot, mass, gravity, distance to the centre of mass (all positive).
    theta0, periods : float, optional
        The start tilt and minimum horizon of ``method="integrate"``.
    rtol : float, optional
        Relative width of the final bracket on ω3², ``1e-10 <= rtol <= 0.5``.
    method : {"linear", "integrate"}

    Returns
    -------
    float
        The numerically located threshold on ω3².

    Examples
    --------
    >>> w2 = sleeping_top_threshold_numeric(1.0, 2.0, 1.0, 1.0, 1.0, rtol=1e-6)
    >>> abs(w2 - 1.0) < 1e-6
    True
    >>> w2 = sleeping_top_threshold_numeric(1.0, 2.0, 1.0, 1.0, 1.0, rtol=0.05, method="integrate")
    >>> abs(w2 - 1.0) < 0.05
    True
    """
    I = (float(I1), float(I1), float(I3))
    moments("I", I)
    M, g, l = (float(positive(name, v)) for name, v in (("M", M), ("g", g), ("l", l)))
    method = choice("method", method, ("linear", "integrate"))
    rtol = float(positive("rtol", rtol))
    if not 1e-10 <= rtol <= 0.5:
        raise InvalidInput("rtol", rtol, "a relative width 1e-10 <= rtol <= 0.5")
    mgl = M * g * l
    tau = math.sqrt(I[0] / mgl)

    if method == "linear":
        def asleep(w3):
            growth, size = _upright_growth(I[0], I[2], mgl, w3)
            return growth <= 1e-6 * size
    else:
        T = max(float(periods), 3 * math.log(100.0) / math.sqrt(0.5 * rtol)) * tau
        half = 0.5 * float(theta0)
        qtilt = (math.cos(half), math.sin(half), 0.0, 0.0)

        def asleep(w3):
            ts = np.linspace(0.0, T, 201)
            tr = integrate_heavy_top(I, M, g, l, (0.0, 0.0, w3), qtilt, ts, h=min(tau, 2 * math.pi / w3) / 40)
            return bool(np.all(tr.gamma[:, 2] > math.cos(100 * theta0)))

    hi = 1.0 / tau
    while not asleep(hi):
        hi *= 2.0
    lo = hi / 2.0
    while asleep(lo):
        lo /= 2.0
    while (hi * hi - lo * lo) > rtol * lo * lo:
        mid = 0.5 * (lo + hi)
        if asleep(mid):
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo * lo + hi * hi)


@lru_cache(maxsize=1)
def _compiled_runner():
    """``runner(state, counts, steps, subs, i1inv, nu_coef, mgl) -> (out, kicks)`` compiled from :func:`_run_top` (numba, cached on disk)."""
    import numba
    from numba.extending import register_jitable

    for fn in (hamilton, rotate, _rotate_back, rotvec_to_quaternion, _free, _kick, _renormalise):
        register_jitable(fn)
    run = numba.njit(cache=True)(_run_top)

    def runner(state, counts, steps, subs, i1inv, nu_coef, mgl):
        return run(np.asarray(state, dtype=np.float64), np.asarray(counts, dtype=np.int64),
                   np.asarray(steps, dtype=np.float64), tuple(subs), i1inv, nu_coef, mgl)

    return runner
