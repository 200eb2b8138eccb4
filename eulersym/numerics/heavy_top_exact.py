"""The heavy symmetric top (Lagrange's top) in closed form: ω(t), Γ(t), q(t) and the Euler angles at any times.

Model and conventions as in :mod:`eulersym.numerics.heavy_top`: moments ``(I1, I1, I3)`` about the fixed pivot,
centre of mass at ``l·e3`` (``l < 0``: below the pivot, the hanging top), gravity ``−M g ẑ``; ω in body components,
the upward vertical ``Γ = R(q)ᵀ ẑ`` in body components, ``q`` scalar first with ``v_space = R(q) v_body``, Euler
angles of the text's zxz convention (``q = qz(φ) ⊗ qx(θ) ⊗ qz(ψ)``).

The method
----------
Everything follows from the three integrals of the body state alone (no angles): with ``u = cos θ = Γ3``,
``a = I3 ω3/I1``, ``b − a u = ω1Γ1 + ω2Γ2`` (= φ̇ sin²θ) and ``u̇ = Γ1ω2 − Γ2ω1``, the energy gives
``u̇² = f(u)``, the cubic of :func:`eulersym.top.turning_point_cubic`, with leading coefficient ``β = 2 M g l/I1``.
In ``w = σ u`` (σ = sign β, so the hanging top is the same problem reflected) ``f = |β| (w − w1)(w − w2)(w − w3)``,
``−1 ≤ w1 ≤ w ≤ w2 ≤ 1 ≤ w3``, and::

    w = w1 + Δ sn²(τ | m),   τ = λ t + τ0,   Δ = w2 − w1,   m = Δ/(w3 − w1),   λ = √(|β| (w3 − w1)) / 2.

The distances to the poles never cancel: ``1 − w = y2 + Δ cn²τ`` and ``1 + w = z1 + Δ sn²τ`` with ``y2 = 1 − w2``,
``z1 = 1 + w1`` ≥ 0. The attitude is ``q = (C cos χ₊/2, S cos χ₋/2, S sin χ₋/2, C sin χ₊/2)`` with the half angles
``C = cos θ/2``, ``S = sin θ/2`` and ``χ± = φ ± ψ``, whose rates split into partial fractions (``ν = a (I1/I3 − 1)``)::

    χ̇₊ = ν + (b + a)/(1 + u),   χ̇₋ = −ν + (b − a)/(1 − u),

so each half of q needs one elliptic integral of the third kind, ``∫ dτ/(y2 + Δ cn²)`` (near pole, w = 1) or
``∫ dτ/(z1 + Δ sn²)`` (far pole, w = −1; written after τ → τ + K with a characteristic in [−1, 0] so that it does
not cancel). Both are evaluated with Carlson's ``R_F`` and ``R_J`` (:mod:`eulersym.numerics.elliptic`) on the
reduced phase plus their quasi-periodicity over the nutation period 2K/λ. The body rates come from the same integrals:
``ω1 + … = (b − a u)/sin θ``, ``u̇/sin θ``, both written as bounded ratios of the pole distances, and ``ω3`` is
constant. When a pole is a turning point (``y2 = 0``: the top passes through the vertical) the half angle is
taken with a sign (``S ∝ cn τ``) and its rate coefficient ``b − a`` vanishes, so q stays smooth.

Accuracy: the roots, λ, K and the mean rates per nutation period are computed once per motion in
:mod:`decimal` arithmetic at 36 digits from the exact binary inputs (:mod:`eulersym.numerics._decimal_elliptic`;
exact deflation where a root is known: ``u̇0 = 0``, or a pole that is a turning point), then rounded to
double-double; the complete third-kind integrals W(K) by the AGM (DLMF 19.8.6, two square roots a step), τ0 by
Carlson's R_F in double where m_c > 1e-6 (to 36 digits nearer the separatrix), the start's angles in floats
(~0.15 ms a motion; for an accuracy asked, on a benign motion, the steps after the turning points — λ, τ0, K,
the third-kind integrals, the rates — in double where their error bound allows: :func:`_setup_double`, ~0.11 ms).
The phase ``λ t + τ0`` is reduced modulo ``2K`` and the secular angles modulo ``4π`` in
double-double, so the error does not grow with t. A double root (steady precession, the sleeping top) is
exact: the motion is then a uniform rotation of the Euler angles. For 4 output times or more the third-kind
integrals come from an odd Chebyshev series of W on [−K, K], obtained per call by integrating the series of its
derivative ``1/((1 − n) + n cn²)`` (32 values at the nodes, no elliptic integral) and cut at its noise floor;
where that series does not reach round-off (a pass close to the vertical) W is evaluated directly (Carlson's
R_F, R_J). With ``accuracy=`` (a scene passes its own) every output is summed instead as a Fourier series in the
nutation phase between the two secular rotations (:mod:`eulersym.numerics._heavy_top_fourier`, fitted per call from
32–128 samples, cut at round-off: a few passes per harmonic instead of the per-time Landen and Chebyshev work);
where those series decline, the direct evaluation computes the phase and the secular angles in double, and cuts its
series shorter, wherever the rounding and truncation bounds stay below a tenth of the accuracy.

Sweeps: more than :data:`BATCH_PRECISE` members are evaluated all at once with the constants in double precision
(:mod:`eulersym.numerics._heavy_top_batch`, ``precise=False``; the error then grows by up to ~3e-13 a nutation
period, the members ill-conditioned in double going the precise way).

Limits: a tilt below 2e-17 rad from a pole is taken as the pole itself; next to the separatrix of the upright top the
and a pole the constants are computed with as many more digits as m_c or the pole distance cancels
(:func:`_digits_for`); a start on (or within
m_c < 1e-150 of) it is refused; at times within a pass closer to the vertical than ~1e-8 rad (the
pass lasting less than ~1e8 ulps of the phase) ω is only as accurate as the phase resolves the pass.
"""

from __future__ import annotations

import decimal
import math
from dataclasses import dataclass, field
from typing import NamedTuple
from decimal import Decimal

import numpy as np

from eulersym.attitude import hamilton
from eulersym.errors import InvalidInput, SingularConfiguration
from eulersym.numerics import _decimal_elliptic as _de
from eulersym.numerics._odd_series import (POWERS_MAX as _MONOMIAL_MAX, clenshaw as _clenshaw_odd, horner as _horner_odd,
                                          to_powers as _odd_monomial)
from eulersym.numerics._doubledouble import PI as _PI
from eulersym.numerics.elliptic import (_agm_landen, _carlson_rf, _reduce_phase_scalar, _reduce_secular,
                                        _sncndn_half, _sncndn_scalar, _third_kind, jacobi_sncndn, reduce_phase)
from eulersym.validation import TRIANGLE_SLACK, finite_array, moments


__all__ = ["heavy_top_exact", "HeavyTopMotion", "euler_to_quaternion", "BATCH_PRECISE"]


@dataclass(frozen=True)
class HeavyTopMotion:
    """The closed-form motion of a heavy symmetric top at the requested times.

    Arrays carry a leading member axis when the inputs were a batch (see :func:`heavy_top_exact`).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times.
    omega : ndarray, shape ([B,] n, 3)
        Body angular velocity.
    gamma : ndarray, shape ([B,] n, 3)
        Body components of the upward vertical, ``Γ = R(q)ᵀ ẑ``.
    q : ndarray, shape ([B,] n, 4) or None
        Attitude quaternion, scalar first, ``v_space = R(q) v_body``; None when not asked for (``attitude=False``).
    euler : ndarray, shape ([B,] n, 3) or None
        Euler angles ``(φ, θ, ψ)`` (zxz), φ and ψ in (−π, π], θ in [0, π]; None as ``q``.
    period : float or ndarray, shape (B,)
        The nutation period (``inf`` for a steady motion: steady precession, the sleeping top).
    turning_points : ndarray, shape ([B,] 2)
        ``(u1, u2)``: ``cos θ`` between them.
    rows : ndarray, shape ([1,] 13, n) or None
        One member's ω, Γ, q and Euler angles as rows, components first: the memory that ``omega``, ``gamma``, ``q``
        and ``euler`` view (rows 0:3, 3:6, 6:10, 10:13), e.g. the state ``(ω, Γ, q)`` for a generated kernel
        without a copy; None for several members.

    Examples
    --------
    >>> m = heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 40.0), euler_to_quaternion((0, 1.0, 0)), [0.0])
    >>> m.omega.shape, m.q.shape
    ((1, 3), (1, 4))
    """

    t: np.ndarray
    omega: np.ndarray
    gamma: np.ndarray
    q: np.ndarray | None
    euler: np.ndarray | None
    period: object
    turning_points: np.ndarray
    rows: np.ndarray | None = field(default=None, repr=False, compare=False)


# ----------------------------------------------------------------------------------------------------------------
# Double-double helpers
# ----------------------------------------------------------------------------------------------------------------
def _dd(x) -> tuple[float, float]:
    """A Decimal as the double-double (hi, lo); a float as (x, 0)."""
    hi = float(x)
    return (hi, float(x - Decimal(hi))) if type(x) is Decimal else (hi, 0.0)


# ----------------------------------------------------------------------------------------------------------------
# The constants of one motion, in decimal arithmetic
# ----------------------------------------------------------------------------------------------------------------
class _Pole(NamedTuple):  # (a NamedTuple: made at import ~20× faster than a frozen dataclass of as many fields)
    """One pole's half of the attitude: amplitude² = base + Δ·(cn² or sn²); angle χ = χ0 + rate t + coef·W(x)."""

    base: float  # y2 (near) or z1 (far)
    signed: bool  # base == 0: the amplitude is taken with a sign
    at_pole: bool  # the motion starts at this pole (the amplitude is zero at t = 0)
    B: float  # b ∓ σ a (zero: no elliptic term)
    n: float  # characteristic of W (W = ∫ dx/(1 − n sn²))
    one_minus_n: float
    coef: float  # multiplies W(x) in χ
    WK: float  # W(K) = Π(n | m), the complete integral (0 where there is no elliptic term)
    W0: float | None  # W at t = 0 (reduced argument); None until _resolved finds it (lazy _finish)
    j0: float | None  # the half period of the argument at t = 0 (None as W0)
    rate: tuple  # double-double: the linear rate (per unit time)
    per: tuple  # double-double: coef · W(2K), the increment per nutation period
    chi0: float


class _Motion(NamedTuple):
    steady: bool
    sigma: float
    w1: float
    delta: float
    mc: float
    rootmc: float
    K: float
    lam: float
    lam_lo: float
    u0: float  # = τ0 (the phase at t = 0)
    u0_lo: float
    period: float  # 2K in the phase variable
    period_lo: float
    omega3: float
    near: _Pole
    far: _Pole
    nutation_period: float
    turning: tuple

    @property
    def phase(self) -> tuple:
        """(λ, τ0, 2K) as double-doubles: the arguments of :func:`~eulersym.numerics.elliptic.reduce_phase`."""
        return (self.lam, self.lam_lo), (self.u0, self.u0_lo), (self.period, self.period_lo)


_THROUGH = Decimal("1e-26")
_AGM_FROM = Decimal("1e-20")  # 1 − n from which Π(n | m) is taken by the AGM (below: R_J)
_MC_DOUBLE = Decimal("1e-6")  # above it, the start's phase τ0 in double  # 1 ∓ w below this at a turning point: the motion passes through the pole
#: A motion's constants may be finished in double (for an accuracy asked) where both poles are at least this far
#: (1 ∓ w) from its turning points and m_c is at least this: no cancellation near a pole or the separatrix.
_BENIGN = Decimal("1e-3")
#: ... and where 1 − n of each third-kind integral is at least this (the AGM's sum loses ~½ log₁₀(1/(1 − n)) digits).
_AGM_DOUBLE = 0.05


def _four_pi():
    """4π as a double-double (π's, scaled exactly)."""
    return (4.0 * _PI[0], 4.0 * _PI[1])


def _quadratic(A, B, C):
    """Real roots of A x² + B x + C (A > 0) in decimal; a negative discriminant (round-off) counts as zero."""
    disc = B * B - 4 * A * C
    if disc < 0:
        disc = Decimal(0)
    root = disc.sqrt()
    qq = -(B + root) / 2 if B >= 0 else -(B - root) / 2
    if qq == 0:
        return Decimal(0), Decimal(0)
    return qq / A, C / qq


def _largest_root(A, B, C, D, lo):
    """The largest root of the cubic, above ``lo`` where the cubic is < 0: bracketed Newton in decimal."""

    def g(x):
        return ((A * x + B) * x + C) * x + D

    hi = lo + 1
    while g(hi) <= 0:
        hi = lo + 2 * (hi - lo)
    x = hi
    eps = Decimal(10) ** (-decimal.getcontext().prec + 5)
    for _ in range(400):
        gx = g(x)
        if gx > 0:
            hi = x
        else:
            lo = x
        dg = (3 * A * x + 2 * B) * x + C
        step = gx / dg if dg != 0 else Decimal(0)
        xn = x - step
        if not (lo < xn < hi) or dg == 0:
            xn = (lo + hi) / 2
        if abs(xn - x) <= eps * (abs(x) + 1) or hi - lo <= eps * (abs(x) + 1):
            return xn
        x = xn
    return x


def _roots(A, B, C, D, one_m_w0, one_p_w0, Bn, Bf):
    """The roots x1 ≤ 0 ≤ x2 ≤ x3 of A x³ + B x² + C x + D (x = w − w0), deflating a known root exactly (a pole
    ``w = ±1`` at the distance ``1 ∓ w0`` computed without cancellation)."""
    if D == 0:
        known = Decimal(0)
    elif Bn == 0:
        known = one_m_w0
    elif Bf == 0:
        known = -one_p_w0
    else:
        known = _largest_root(A, B, C, D, one_m_w0)
    Bq = B + A * known
    Cq = -D / known if known != 0 else C + Bq * known
    r1, r2 = _quadratic(A, Bq, Cq)
    roots = sorted((known, r1, r2))
    return roots


def _complete(mc, *poles):
    """K and, for each pole ``(n, 1 − n, B)``, W(K) = Π(n | m) = ∫₀ᴷ dx/(1 − n sn² x) (0 where B = 0: no elliptic
    term): K and the integrals by one AGM sequence (:func:`_decimal_elliptic.complete_integrals`), or for ``1 − n``
    below 1e-20 (a pass within ~1e-10 of a pole, where the AGM's sum cancels) by Carlson's ``R_J``."""
    by_agm = [(n, one_minus_n) for n, one_minus_n, B in poles if B != 0 and one_minus_n >= _AGM_FROM]
    K, values = _de.complete_integrals(mc, by_agm)
    values = iter(values)
    out = [K]
    for n, one_minus_n, B in poles:
        if B == 0:
            out.append(K - K)
        elif one_minus_n >= _AGM_FROM:
            out.append(next(values))
        else:
            out.append(K + n / 3 * _de.rj_(Decimal(0), mc, Decimal(1), one_minus_n))
    return out


def _W_decimal(s_sq, c_sq, d_sq, n, one_minus_n):
    """W(x) = ∫₀ˣ dy/(1 − n sn² y) for 0 ≤ x ≤ K from sn² x, cn² x, dn² x (decimal, Carlson)."""
    if s_sq <= 0:
        return Decimal(0)
    s = s_sq.sqrt()
    out = s * _de.rf_(c_sq, d_sq, Decimal(1))
    if n != 0:
        out += n / 3 * s * s_sq * _de.rj_(c_sq, d_sq, Decimal(1), one_minus_n + n * c_sq)
    return out


_EPS = float(np.finfo(float).eps)
_CHEB_N = 64  # Chebyshev nodes on [−K, K]; W's periodic part is odd, its derivative even: 32 values
_HALF = _CHEB_N // 2
_NODES = np.cos(np.pi * (np.arange(_HALF) + 0.5) / _CHEB_N)  # the positive nodes
_ODD = 2 * np.arange(_HALF) + 1
_TRANSFORM = (4.0 / _CHEB_N) * np.cos(np.pi * np.outer(_ODD - 1, np.arange(_HALF) + 0.5) / _CHEB_N)


def _W_chebyshev(poles, c2, K, tolerance=0.0):
    """For each pole ``(n, 1 − n, W(K), coef)``: ``(slope, a)`` with ``W(x) = slope·x + Σ_k a_k T_{2k+1}(x/K)``
    on [−K, K], ``slope = W(K)/K`` (W(K) from the setup, to 36 digits).

    The derivative ``W′(x) − slope = 1/((1 − n) + n cn² x) − slope`` is even: its Chebyshev coefficients
    ``c_{2k}`` come from 32 values at the positive nodes ``K·_NODES`` of the 64-point grid (``c2``: cn² there,
    from the Jacobi evaluation of the output times; no elliptic integral), and the series is integrated term by term, ``a_j = K (c_{j−1} − c_{j+1})/(2j)``
    (c₀ counted twice). Two checks that the series represents W: ``Σ a_k = W(K)/K·K − W(K) = 0`` to round-off,
    and the last coefficients at the noise floor; where either fails (a pass close to the vertical: a sharp
    peak of W′), None, and W is evaluated directly. The series is cut after the last coefficient above an ulp of
    the scale of W, and, for ``tolerance`` > 0, where the tail Σ|a_k| falls below ``tolerance / |coef|`` (coef
    multiplies W in its angle)."""
    eps = _EPS
    n, one_minus_n, WK, coef = (np.array(v, dtype=float)[:, None] for v in zip(*poles))
    slope = WK / K
    values = one_minus_n + n * c2
    np.divide(1.0, values, out=values)
    values -= slope
    raw = values @ _TRANSFORM.T  # raw[:, 0] is twice c₀
    a = raw.copy()
    a[:, :-1] -= raw[:, 1:]
    a *= K / (2.0 * _ODD)
    absa = np.abs(a)
    scale = np.maximum(np.maximum(np.abs(WK[:, 0]), absa.sum(axis=1)), 1e-300)
    bad = ((absa[:, -3:].max(axis=1) > 32 * eps * scale) | (np.abs(a.sum(axis=1)) > 64 * eps * scale)
           | ~np.isfinite(absa).all(axis=1) | ~np.isfinite(scale))  # a NaN compares False: refuse it by name
    # the last coefficient above an ulp of the scale (beyond: the fit's own round-off), and the tolerance's cut
    above = absa > (eps * scale)[:, None]
    keep = np.where(above.any(axis=1), _HALF - np.argmax(above[:, ::-1], axis=1), 1)
    if tolerance > 0.0:
        tail = np.cumsum(absa[:, ::-1], axis=1)[:, ::-1]  # tail[k] = Σ_{i ≥ k} |a_i|
        need = np.count_nonzero(tail > (tolerance / np.maximum(np.abs(coef), 1e-300)), axis=1)
        keep = np.minimum(keep, np.maximum(need, 1))
    return [None if bad[k] else (float(slope[k, 0]), a[k, :int(keep[k])]) for k in range(len(poles))]


def _W_direct(x, n, one_minus_n, mc, rootmc, sc=None):
    """W(x) = ∫₀ˣ dy/(1 − n sn² y) for |x| ≤ K (Carlson's R_F, R_J: :mod:`eulersym.numerics.elliptic`); ``sc``:
    |sn x| and |cn x| as the caller has them (the very values its amplitudes use: near a pole W is steep, and sn
    and cn of the same x evaluated twice may differ by an ulp of K − |x|)."""
    if sc is None:
        s, c, _ = jacobi_sncndn(np.abs(x), mc, rootmc=rootmc)
    else:
        s, c = sc
    s = np.abs(s)
    c2 = c * c
    d2 = c2 + mc * s * s
    return np.sign(x) * _third_kind(s, c2, d2, n, one_minus_n + n * c2)


def _digits_for(closeness) -> int:
    """The decimal digits a motion needs: :data:`_de.DIGITS`, plus the digits its closest difference cancels —
    ``closeness`` = m_c near the separatrix (the cubic's coefficients are rounded at the working precision, and a
    near-double root moves by that rounding over the gap: m_c loses ``log₁₀(1/m_c)`` digits), or a pole distance
    over the start's, ``y2/(1 − w0)``, near a pole (its difference of a root from the start's distance)."""
    lost = max(0, -closeness.adjusted()) if closeness > 0 else 0
    return _de.DIGITS + (lost + 4 if lost > 3 else 0)


def _setup(I1, I3, M, g, l, omega, q, exact=True, digits=None):
    """Classify one motion and compute its constants: in decimal at 36 digits (more near the separatrix: the
    digits m_c cancels, :func:`_digits_for`), then rounded to double or double-double. ``exact=False`` (for an
    accuracy asked, :func:`_setup_double`): the same up to the turning points and the modulus (every difference
    that may cancel, in decimal), the rest (λ, the phase at t = 0, K, the third-kind integrals, the angles' rates)
    in double; None where that motion is not :data:`_BENIGN` (steady, near a pole or the separatrix)."""
    with decimal.localcontext() as ctx:
        ctx.prec = digits or _de.DIGITS
        Dm = [Decimal(float(v)) for v in (I1, I3, M, g, l)]
        w = [Decimal(float(v)) for v in omega]
        qd = [Decimal(float(v)) for v in q]
        i1, i3, mass, grav, arm = Dm
        n2 = sum(v * v for v in qd)
        q0, q1, q2, q3 = qd
        G1 = 2 * (q1 * q3 - q0 * q2) / n2
        G2 = 2 * (q2 * q3 + q0 * q1) / n2
        G3 = (q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3) / n2
        beta = 2 * mass * grav * arm / i1
        sigma = 1 if beta > 0 else -1
        a = i3 * w[2] / i1
        wpar = w[0] * G1 + w[1] * G2  # b − a u  (= φ̇ sin²θ)
        wperp = G1 * w[1] - G2 * w[0]  # u̇
        s2 = G1 * G1 + G2 * G2
        wt2 = w[0] * w[0] + w[1] * w[1]
        u0 = G3
        w0 = sigma * u0
        one_m_w0 = s2 / (1 + w0) if w0 > 0 else 1 - w0  # 1 − w0 = sin²θ/(1 + w0): exact where it is small
        one_p_w0 = s2 / (1 - w0) if w0 < 0 else 1 + w0
        f1 = -2 * u0 * wt2 - beta * s2 + 2 * a * wpar
        f2 = 2 * beta * u0 - wt2 - a * a
        A, B, C, D = abs(beta), f2, sigma * f1, wperp * wperp
        Bn = wpar - sigma * a * one_m_w0  # b − σ a
        Bf = wpar + sigma * a * one_p_w0  # b + σ a
        nu = w[2] - a  # χ̇₊ = ν + (b + a)/(1 + u), χ̇₋ = −ν + (b − a)/(1 − u), ν = a (I1/I3 − 1) = ω3 − a
        nu_near, nu_far = (-nu, nu) if sigma > 0 else (nu, -nu)
        steady = D == 0 and C == 0
        if steady and not exact:
            return None
        if steady:
            return _finish(*_steady(sigma, w0, one_m_w0, one_p_w0, Bn, Bf, nu_near, nu_far, w, u0), omega, q)
        x1, x2, x3 = _roots(A, B, C, D, one_m_w0, one_p_w0, Bn, Bf)
        if x1 > 0:
            x1 = Decimal(0)
        if x2 < 0:
            x2 = Decimal(0)
        delta = x2 - x1
        y2 = one_m_w0 - x2
        z1 = one_p_w0 + x1
        # near a pole the difference loses digits; the root identities (b ∓ σa)² = −f(±σ) do not:
        # (b − σa)² = |β| y2 (1 − w1)(w3 − 1),  (b + σa)² = |β| z1 (1 + w2)(1 + w3)
        w1d, w2d, w3d = w0 + x1, w0 + x2, w0 + x3
        if not exact and not (y2 >= _BENIGN and z1 >= _BENIGN and x3 - x2 >= _BENIGN * (x3 - x1)):
            return None  # near a pole or the separatrix: in decimal
        if y2 < Decimal("1e-20") and w3d > 1 and w1d < 1:
            y2 = Bn * Bn / (A * (1 - w1d) * (w3d - 1))
        if z1 < Decimal("1e-20") and w2d > -1:
            z1 = Bf * Bf / (A * (1 + w2d) * (1 + w3d))
        # a pass within 1.4e-13 rad of a pole (1 ∓ w < 1e-26) is a pass through it: the angle's jump of ±2π there
        # is the sign change of the signed half angle (the same q, to O(tilt)); its rate term goes. A start that
        # close to the pole leaves it in the direction of q̇0.
        if y2 < _THROUGH:
            y2, Bn = Decimal(0), Decimal(0)
        if z1 < _THROUGH:
            z1, Bf = Decimal(0), Decimal(0)
        span = x3 - x1
        mc = (x3 - x2) / span
        # near the separatrix (m_c = (x3 − x2)/span) or a pole (y2 = (1 − w0) − x2, z1 = (1 + w0) + x1): again,
        # with the digits those differences cancel
        closeness = min([mc] + [d / whole for d, whole in ((y2, one_m_w0), (z1, one_p_w0)) if d > 0 and whole > 0])
        if digits is None and _digits_for(closeness) > ctx.prec:
            return _setup(I1, I3, M, g, l, omega, q, exact, digits=_digits_for(closeness))
        m = delta / span
        if mc < Decimal("1e-150"):  # on the separatrix, or so close that the third-kind integrals overflow a double
            raise SingularConfiguration(
                "omega0", tuple(float(v) for v in omega),
                "a start off the separatrix of the upright top (here m_c = 1 − m is below 1e-150: the top leaves or "
                "approaches the vertical asymptotically, with no periodic closed form in double precision)")
        turning = tuple(float(sigma * x) for x in (w1d, w2d))
        if not exact:  # from here on in double: λ, τ0, K, the third-kind integrals and the rates (no cancellation)
            A, span, mc, m, delta, x1, x2, x3, y2, z1, Bn, Bf, nu_near, nu_far = (
                float(v) for v in (A, span, mc, m, delta, x1, x2, x3, y2, z1, Bn, Bf, nu_near, nu_far))
        lam = _de.sqrt(A * span) / 2
        rootmc = _de.sqrt(mc)
        # τ0: sn² τ0 = −x1/Δ, sign of sn = sign of ẇ0 (on [−K, K], cn ≥ 0 and dn > 0)
        s_sq, c_sq, d_sq = -x1 / delta, x2 / delta, x3 / span
        if s_sq <= 0:
            F = Decimal(0) if exact else 0.0
        elif mc > _MC_DOUBLE:  # K < 8: Carlson's R_F in double keeps τ0 to a few ulp of K (no growth with t)
            F = math.sqrt(float(s_sq)) * _carlson_rf(float(c_sq), float(d_sq), 1.0)
            F = Decimal(F) if exact else F
        else:  # near the separatrix (K large): to 36 digits
            F = s_sq.sqrt() * _de.rf_(c_sq, d_sq, Decimal(1))
        wdot0 = sigma * wperp
        tau0 = -F if wdot0 < 0 else F
        # the near pole: 1 − w = (y2 + Δ)(1 − n sn² τ)
        near_n = delta / (y2 + delta)
        near_1mn = y2 / (y2 + delta)
        near_coef = Bn / (lam * (y2 + delta))
        # the far pole, after τ = τ' + K: 1 + w = (z1 + Δ)(1 − n' sn² τ')/dn² τ'
        far_n = (z1 * m + delta) / (z1 + delta)
        far_1mn = z1 * mc / (z1 + delta)
        m_over_n = m * (z1 + delta) / (z1 * m + delta)
        one_m_m_over_n = delta * mc / (z1 * m + delta)
        far_rate = nu_far + Bf * m_over_n / (z1 + delta)
        far_coef = Bf * one_m_m_over_n / (lam * (z1 + delta))
        if not exact and min(near_1mn if Bn != 0 else 1.0, far_1mn if Bf != 0 else 1.0) < _AGM_DOUBLE:
            return None  # the AGM's sum for Π(n | m) cancels as 1 − n → 0: in decimal
        K, near_WK, far_WK = _complete(mc, (near_n, near_1mn, Bn), (far_n, far_1mn, Bf))
        near_per = near_coef * 2 * near_WK
        far_per = far_coef * 2 * far_WK
        lam_dd, tau0_dd, per_dd = _dd(lam), _dd(tau0), _dd(2 * K)
        nutation = 2 * K / lam
        motion = dict(
            steady=False, sigma=float(sigma), w1=float(w1d), delta=float(delta), mc=float(mc),
            rootmc=float(rootmc), K=float(K), lam=lam_dd[0], lam_lo=lam_dd[1], u0=tau0_dd[0], u0_lo=tau0_dd[1],
            period=per_dd[0], period_lo=per_dd[1], omega3=float(w[2]), nutation_period=float(nutation),
            turning=tuple(sorted(turning)),
        )
        # W(τ0) and W(τ0 − K) at t = 0, to 36 digits: near a pole W is steep, and a rounded τ0 would shift every later angle
        # (only where the start is near a pole, 1 − n sn² < 1e-4: elsewhere W is smooth and a double will do)
        steep = Decimal("1e-4")
        if not exact and (Bn != 0 and near_1mn + near_n * c_sq < steep or Bf != 0 and far_1mn + far_n * mc * s_sq / d_sq < steep):
            return None  # a start near a pole: W there in decimal
        W0n = None
        if Bn != 0 and near_1mn + near_n * c_sq < steep:
            W0n = _W_decimal(s_sq, c_sq, d_sq, near_n, near_1mn) * (-1 if tau0 < 0 else 1)
        S_sq, C_sq = c_sq / d_sq, mc * s_sq / d_sq  # sn², cn² of τ0 ∓ K (cd², k′² sd²), dn² = m_c/dn²τ0
        W0f = None
        if Bf != 0 and far_1mn + far_n * C_sq < steep:
            W0f = _W_decimal(S_sq, C_sq, mc / d_sq, far_n, far_1mn)
            W0f = W0f if tau0 < 0 else -W0f
        j0f = -1.0 if tau0 < 0 else 0.0  # τ0 − K in [−2K, 0]: wrapped by 2K when τ0 < 0
        near = dict(base=float(y2), signed=(y2 == 0), at_pole=(one_m_w0 < _THROUGH), B=float(Bn), n=float(near_n), one_minus_n=float(near_1mn),
                    coef=float(near_coef), rate=_dd(nu_near), per=_dd(near_per), WK=float(near_WK))
        far = dict(base=float(z1), signed=(z1 == 0), at_pole=(one_p_w0 < _THROUGH), B=float(Bf), n=float(far_n), one_minus_n=float(far_1mn),
                   coef=float(far_coef), rate=_dd(far_rate), per=_dd(far_per), WK=float(far_WK))
        start = {"near": (None if W0n is None else float(W0n), 0.0), "far": (None if W0f is None else float(W0f), j0f)}
    return _finish(motion, near, far, omega, q, start, lazy=not exact)


#: The relative error of a constant computed in double by :func:`_setup` (``exact=False``), in ulp, with a margin:
#: tests/test_numerics_heavy_top_exact.py measures it against the decimal constants over random benign motions.
_DOUBLE_ULPS = 16


def _setup_double(I1, I3, M, g, l, omega, q, accuracy, tmax):
    """The motion's constants with their last steps in double, where that is accurate enough for ``accuracy`` over
    |t| ≤ tmax; else None (and :func:`_setup` computes them all in decimal).

    :func:`_setup` with ``exact=False``: everything up to the turning points and the modulus in decimal as always
    (every difference that may cancel: the integrals of the start, the cubic's roots, the distances to the poles),
    the rest in double — λ = √(|β|(w3 − w1))/2, τ0, K and the complete third-kind integrals by the AGM, the angles'
    rates — for benign motions only (both poles and the separatrix at least :data:`_BENIGN` away; steady motions are
    left to the decimal path). Those are products, quotients and square roots of numbers known to an ulp and one sum
    (the far pole's rate ``ν + B·m/(n (z1 + Δ))``): each within :data:`_DOUBLE_ULPS` ulp of its scale (the rate's:
    the sum of its terms' sizes). The phase ``λ t + τ0`` reduced by ``j`` half periods 2K, and each secular angle
    ``rate·t + per·j``, are then off by at most ``_DOUBLE_ULPS·ε·(|λ| tmax + |τ0| + 2K·j)`` and
    ``_DOUBLE_ULPS·ε·(scale·tmax + |per|·j)`` radians: accepted where both stay below a tenth of the accuracy (the
    evaluation's own rounding and truncation bounds, at the same tenth, come on top)."""
    mo = _setup(I1, I3, M, g, l, omega, q, exact=False)
    if mo is None:
        return None
    bound = _DOUBLE_ULPS * _EPS
    jmax = (abs(mo.lam) * tmax + abs(mo.u0)) / mo.period + 2.0
    phase = bound * (abs(mo.lam) * tmax + abs(mo.u0) + mo.period * jmax)
    nu = abs(mo.near.rate[0])  # the near pole's rate is ∓ν itself; the far pole's is ±ν plus its elliptic term
    scales = (nu, nu + abs(mo.far.rate[0] + mo.near.rate[0]))
    angles = bound * max(scale * tmax + abs(p.per[0]) * jmax for scale, p in zip(scales, (mo.near, mo.far)))
    return mo if max(phase, angles) <= 0.1 * accuracy else None


def _steady(sigma, w0, one_m_w0, one_p_w0, Bn, Bf, nu_near, nu_far, w, u0):
    """A double root at w0: u, θ and the rates are constant (steady precession, the sleeping top)."""
    rate_near = nu_near + (Bn / one_m_w0 if Bn != 0 else 0)
    rate_far = nu_far + (Bf / one_p_w0 if Bf != 0 else 0)
    motion = dict(
        steady=True, sigma=float(sigma), w1=float(w0), delta=0.0, mc=1.0, rootmc=1.0, K=math.pi / 2, lam=0.0,
        lam_lo=0.0, u0=0.0, u0_lo=0.0, period=math.inf, period_lo=0.0, omega3=float(w[2]), nutation_period=math.inf,
        turning=(float(u0), float(u0)),
    )
    near = dict(base=float(one_m_w0), signed=False, at_pole=False, B=float(Bn), n=0.0, one_minus_n=1.0, coef=0.0,
                rate=_dd(rate_near), per=(0.0, 0.0), WK=0.0)
    far = dict(base=float(one_p_w0), signed=False, at_pole=False, B=float(Bf), n=0.0, one_minus_n=1.0, coef=0.0,
               rate=_dd(rate_far), per=(0.0, 0.0), WK=0.0)
    return motion, near, far


def _pairs(sigma):
    """(near pair, far pair) of quaternion components: σ > 0: near = (q1, q2) (S, χ₋); σ < 0: near = (q0, q3)."""
    return ((1, 2), (0, 3)) if sigma > 0 else ((0, 3), (1, 2))


def _W_points(points, mc, rootmc, landen):
    """:func:`_W_direct` at a few floats: ``[W(x) for (x, n, 1 − n) in points]`` (|x| ≤ K), sn and cn in ``math``,
    Carlson's integrals in one call for all of them."""
    s, c2, d2, p, ns = (np.empty(len(points)) for _ in range(5))
    for k, (x, n, one_minus_n) in enumerate(points):
        sk, ck, _ = _sncndn_scalar(abs(x), rootmc, landen)
        s[k], c2[k], ns[k] = abs(sk), ck * ck, n
        d2[k] = c2[k] + mc * s[k] * s[k]
        p[k] = one_minus_n + n * c2[k]
    val = _third_kind(s, c2, d2, ns, p)  # n = 0: R_J finite, the term 0
    return [math.copysign(float(v), x) if x != 0.0 else 0.0 for v, (x, _, _) in zip(val, points)]


def _finish(motion, near, far, omega, q, start=None, lazy=False):
    """Fix the angles χ0 from q0 (and, where a half angle starts at zero, from the direction q̇0), and W and the
    half period at t = 0 (:func:`_start_W`) — with ``lazy`` (no signed half angle) left as None for
    :func:`_resolved` to find where the direct evaluation needs them (the Fourier series do not)."""
    qn = [float(v) for v in q]
    norm = math.sqrt(sum(v * v for v in qn))
    qn = [v / norm for v in qn]
    w1, w2, w3 = (float(v) for v in omega)
    qdot = [0.5 * c for c in hamilton(qn, (0.0, w1, w2, w3))]  # q̇0 = ½ q0 ⊗ (0, ω0)
    lazy = lazy and not (motion["steady"] or near["signed"] or far["signed"])
    landen = None
    if motion["steady"] or lazy:  # no signed amplitude: its sign at t = 0 does not enter
        amp_n, amp_f, dn_sign, df_sign = (math.sqrt(near["base"]), math.sqrt(far["base"]), 1.0, 1.0)
    else:  # the amplitudes at t = 0 as _amplitudes finds them
        r0, j0 = _reduce_phase_scalar(0.0, (motion["lam"], motion["lam_lo"]), (motion["u0"], motion["u0_lo"]),
                                      (motion["period"], motion["period_lo"]))
        landen = _agm_landen(motion["rootmc"])
        sn, cn, _ = _sncndn_scalar(r0, motion["rootmc"], landen)
        parity = 1.0 - 2.0 * (j0 % 2.0)
        sn, cn = parity * sn, parity * cn
        sd = math.sqrt(motion["delta"])
        amp_n = sd * cn if near["signed"] else 1.0
        amp_f = sd * sn if far["signed"] else 1.0
        dn_sign = -1.0 if sn >= 0 else 1.0
        df_sign = 1.0 if cn >= 0 else -1.0
    pn, pf = _pairs(motion["sigma"])
    out = []
    for pole, pair, amp, dsign in ((near, pn, amp_n, dn_sign), (far, pf, amp_f, df_sign)):
        c, s = qn[pair[0]], qn[pair[1]]
        if not (pole["signed"] and pole["at_pole"]):
            half = math.atan2(s, c) if amp >= 0.0 else math.atan2(-s, -c)
        else:  # the half angle starts at zero: the direction it leaves in, from q̇0 = ½ q0 ⊗ (0, ω0)
            dc, ds = qdot[pair[0]], qdot[pair[1]]
            half = math.atan2(ds * dsign, dc * dsign)
        out.append(2.0 * half)
    chi_near0, chi_far0 = out
    W0n = W0f = j0n = j0f = 0.0
    if lazy:
        W0n = W0f = j0n = j0f = None
    elif not motion["steady"]:
        poles = [(p["B"], p["n"], p["one_minus_n"], p["WK"]) for p in (near, far)]
        W0n, j0n, W0f, j0f = _start_W(motion["K"], motion["period"], motion["mc"], motion["rootmc"], r0, j0, landen,
                                      poles, start)
    return _Motion(near=_Pole(**near, W0=W0n, j0=j0n, chi0=chi_near0),
                   far=_Pole(**far, W0=W0f, j0=j0f, chi0=chi_far0), **motion)


def _start_W(K, period, mc, rootmc, r0, j0, landen, poles, start):
    """W at t = 0 and the half period it is reduced to, per pole ``(B, n, 1 − n, W(K))``: ``(W0n, j0n, W0f, j0f)``
    exactly as the evaluation will find them (the near pole's argument r0, the far pole's r0 − K wrapped into
    [−K, K]); ``start``: each pole's W(τ0) to 36 digits and its half period where it was computed so (near a pole),
    else None (then in double, Carlson's integrals)."""
    x0 = r0 - K
    j0n = j0
    j0f = j0n - 1.0 if x0 < -K else j0n
    x0 = x0 + period if x0 < -K else x0
    (exact_n, jn_exact), (exact_f, jf_exact) = start["near"], start["far"]
    values = []
    in_double = []  # off the poles: W at the reduced argument, in double
    for (B, n, one_minus_n, WK), x, jj, exact, j_exact in zip(poles, (r0, x0), (j0n, j0f), (exact_n, exact_f),
                                                              (jn_exact, jf_exact)):
        if not B:
            values.append(0.0)
        elif exact is None:
            in_double.append((len(values), (x, n, one_minus_n)))
            values.append(None)
        else:  # the decimal value, moved to the branch (half period) the evaluation uses: W(x + 2K) = W(x) + W(2K)
            values.append(exact + (j_exact - jj) * 2.0 * WK)
    if in_double:
        found = _W_points([point for _, point in in_double], mc, rootmc, landen)
        for (k, _), value in zip(in_double, found):
            values[k] = value
    return values[0], j0n, values[1], j0f


def _resolved(mo):
    """The motion with W and the half period at t = 0 found where :func:`_finish` left them (``lazy``)."""
    if mo.near.j0 is not None:
        return mo
    r0, j0 = _reduce_phase_scalar(0.0, *mo.phase)
    poles = [(p.B, p.n, p.one_minus_n, p.WK) for p in (mo.near, mo.far)]
    W0n, j0n, W0f, j0f = _start_W(mo.K, mo.period, mo.mc, mo.rootmc, r0, j0, _agm_landen(mo.rootmc), poles,
                                  {"near": (None, 0.0), "far": (None, 0.0)})
    return mo._replace(near=mo.near._replace(W0=W0n, j0=j0n), far=mo.far._replace(W0=W0f, j0=j0f))


#: From this many output times on, W comes from its Chebyshev series (fitted per call at 32 nodes, both poles at once:
#: ~40 array operations) rather than from Carlson's integrals at every time (~300 array operations for both poles in
#: NumPy's duplication loop, or ~9 µs a time and pole one by one).
_SERIES_FROM = 4


def _phase_double(mo, t):
    """``λ t + τ0`` reduced modulo the half period 2K in double: (r, j) with the rounding bound
    ``4 ε (|λ| max|t| + |τ0| + 2K)`` (the caller checks it against the accuracy asked)."""
    u = mo.lam * t
    u += mo.lam_lo * t + mo.u0
    j = np.rint(u / mo.period)
    r = u - j * mo.period
    step = np.where(r > 0.5 * mo.period, 1.0, np.where(r < -0.5 * mo.period, -1.0, 0.0))  # a quotient rounded over
    if step.any():
        r -= step * mo.period
        j += step
    return r, j


def _phase_and_jacobi(mo, t, tolerance, tmax):
    """The reduced phase r (|r| ≤ K) and half-period index j at t, sn, cn (with the sign of the half period), dn,
    and cn² at W's Chebyshev nodes when its series will be used (else None)."""
    eps = _EPS
    if 0.0 < 4.0 * eps * (abs(mo.lam) * tmax + abs(mo.u0) + mo.period) <= 0.5 * tolerance:
        r, j = _phase_double(mo, t)
    else:
        r, j = reduce_phase(t, *mo.phase)
    nodes = t.size >= _SERIES_FROM and not (mo.near.B == 0.0 and mo.far.B == 0.0)
    if nodes:  # the Chebyshev nodes of W's series ride along (one Jacobi evaluation)
        sn, cn, dn = _sncndn_half(np.concatenate([r, mo.K * _NODES]), mo.K, mo.rootmc, _agm_landen(mo.rootmc))
        node_c2 = cn[t.size:] ** 2
        sn, cn, dn = sn[:t.size], cn[:t.size], dn[:t.size]
    else:
        sn, cn, dn = _sncndn_half(r, mo.K, mo.rootmc, _agm_landen(mo.rootmc))
        node_c2 = None
    odd = (j.astype(np.int64) & 1).astype(bool)  # sn and cn change sign over each half period 2K
    np.negative(sn, out=sn, where=odd)
    np.negative(cn, out=cn, where=odd)
    return r, j, sn, cn, dn, node_c2


def _chis(mo, t, r, j, tolerance=0.0, tmax=0.0, node_c2=None, jacobi=None):
    """χ_near, χ_far at t (shape (2, n)): the secular part ``rate·t + per·(j − j0)`` reduced modulo 4π in
    double-double (both poles at once), plus ``coef·(W(x) − W0)`` with x = r (near) and x = r ∓ K (far: r − K
    wrapped into [−K, K], a half period back where r < 0). ``tolerance`` > 0 (radians): the secular part in double
    where its rounding bound allows, and W's series cut at that tolerance."""
    four_pi = _four_pi()
    near, far = mo.near, mo.far
    back = r < 0.0
    jj = np.empty((2,) + t.shape)
    np.subtract(j, near.j0, out=jj[0])
    np.subtract(j, back, out=jj[1])
    jj[1] -= far.j0
    col = lambda a, b: np.array([[a], [b]])  # noqa: E731
    rate = (col(near.rate[0], far.rate[0]), col(near.rate[1], far.rate[1]))
    per = (col(near.per[0], far.per[0]), col(near.per[1], far.per[1]))
    eps = _EPS
    jmax = (abs(mo.lam) * tmax + abs(mo.u0)) / mo.period + 2.0 if not mo.steady else 0.0
    bound = 4.0 * eps * max(abs(p.rate[0]) * tmax + abs(p.per[0]) * jmax + four_pi[0] for p in (near, far))
    if 0.0 < bound <= 0.5 * tolerance:  # plain double: the rounding of rate·t, per·j and the reduction
        chi = np.empty_like(jj)
        for k, pole in enumerate((near, far)):  # row by row with numbers (NumPy's fast loops; no column broadcast)
            np.multiply(jj[k], pole.per[0], out=chi[k])
            chi[k] += pole.rate[0] * t
        chi -= four_pi[0] * np.rint(chi * (1.0 / four_pi[0]))
    else:
        chi = _reduce_secular(rate, t, per, jj, four_pi)
    if mo.steady:
        chi += col(near.chi0, far.chi0)
        return chi
    poles = (near, far)
    active = [k for k, pole in enumerate(poles) if pole.B != 0.0]
    chi[0] += near.chi0 - near.coef * near.W0 * (near.B != 0.0)
    chi[1] += far.chi0 - far.coef * far.W0 * (far.B != 0.0)
    if not active:
        return chi
    x = np.empty((2,) + t.shape)
    x[0] = r
    np.subtract(r, np.copysign(mo.K, r), out=x[1])
    fits = [None, None]
    if node_c2 is not None:
        found = _W_chebyshev([(poles[k].n, poles[k].one_minus_n, poles[k].WK, poles[k].coef) for k in active],
                             node_c2, mo.K, 0.25 * tolerance)
        for k, fit in zip(active, found):
            fits[k] = fit
    series = [k for k in active if fits[k] is not None]
    if series:  # coef·W as one series: slope·x = slope·K·T₁(x/K) joins the first term; both poles' at once
        length = max(len(fits[k][1]) for k in series)
        a = np.zeros((len(series), length))  # the shorter series padded with zeros (exact: they add nothing)
        for row, k in enumerate(series):
            slope, coefficients = fits[k]
            a[row, :len(coefficients)] = poles[k].coef * coefficients
            a[row, 0] += poles[k].coef * slope * mo.K
        rows = slice(None) if len(series) == 2 else series[0]
        y = x[rows]
        y *= 1.0 / mo.K
        b = _odd_monomial(a, tolerance) if tolerance > 0.0 else None
        if b is not None:  # y·Σ b_j y^{2j} by Horner: two operations a term where Clenshaw takes three
            chi[rows] += _horner_odd(y, b if len(series) == 2 else b[0])
        else:
            chi[rows] += _clenshaw_odd(y, list(a.T[:, :, None]) if len(series) == 2 else [float(v) for v in a[0]])
    direct = [k for k in active if fits[k] is None]
    if direct:  # both poles' W at once (one pass of Carlson's duplication over both rows)
        column = lambda name: np.array([[getattr(poles[k], name)] for k in direct])  # noqa: E731
        sc = None
        if jacobi is not None:  # |sn|, |cn| at r (near) and at r ∓ K (far: |cd r| and k′|sd r|), as the amplitudes
            sn, cn, dn = jacobi
            s_abs, c_abs = np.abs(sn), np.abs(cn)
            pairs = {0: (s_abs, c_abs), 1: (c_abs / dn, mo.rootmc * s_abs / dn)}
            sc = (np.stack([pairs[k][0] for k in direct]), np.stack([pairs[k][1] for k in direct]))
        chi[direct] += column("coef") * _W_direct(x[direct], column("n"), column("one_minus_n"), mo.mc, mo.rootmc, sc)
    return chi


def _cos_sin(x):
    """cos x and sin x from τ = tan(x/2): ``(1 − τ²)/(1 + τ²)``, ``2τ/(1 + τ²)`` (a few ulp; NumPy's tan is
    vectorised where its sin and cos are not, five times faster here)."""
    tau = np.tan(0.5 * x)
    tau2 = tau * tau
    inv = tau2 + 1.0
    np.divide(1.0, inv, out=inv)
    cos = 1.0 - tau2
    cos *= inv
    tau *= inv
    tau *= 2.0
    return cos, tau


def _evaluate(mo, t, accuracy=None):
    """ω, Γ, q and Euler angles of one motion at the times t, as the rows of one (13, n) block (components first:
    ω 0:3, Γ 3:6, q 6:10, the angles 10:13); ``accuracy`` (relative to ω): the Fourier series in the phase where
    they converge (:mod:`eulersym.numerics._heavy_top_fourier`), else the direct evaluation with the phase and the
    secular angles in double, and W's series cut, where their error bounds stay below a tenth of it (None:
    round-off everywhere, directly)."""
    if accuracy:  # at an accuracy asked: Fourier series in the phase, where they converge (else None: on below)
        from eulersym.numerics._heavy_top_fourier import fourier_rows

        block = fourier_rows(mo, t, float(accuracy))
        if block is not None:
            return block
    mo = _resolved(mo)
    tolerance = 0.1 * float(accuracy) if accuracy else 0.0
    tmax = float(np.max(np.abs(t))) if (tolerance and t.size) else 0.0
    near, far = mo.near, mo.far
    if mo.steady:
        rn2, rf2 = np.full(t.shape, near.base), np.full(t.shape, far.base)
        rn, rf = np.sqrt(rn2), np.sqrt(rf2)
        chi = _chis(mo, t, np.zeros_like(t), np.zeros_like(t), tolerance, tmax)
        B_ = None
    else:
        r, j, sn, cn, dn, node_c2 = _phase_and_jacobi(mo, t, tolerance, tmax)
        chi = _chis(mo, t, r, j, tolerance, tmax, node_c2, (sn, cn, dn))
        sd = math.sqrt(mo.delta)
        # the pole distances 1 ∓ w = R² (R signed where its base is 0: the top passes through that pole)
        rn2 = cn * cn
        rn2 *= mo.delta
        rn2 += near.base
        rf2 = sn * sn
        rf2 *= mo.delta
        rf2 += far.base
        rn = sd * cn if near.signed else np.sqrt(rn2)
        rf = sd * sn if far.signed else np.sqrt(rf2)
        # u̇/sin θ = σ 2λ dn (√Δ cn/R_n)(√Δ sn/R_f), each ratio 1 where R is signed
        B_ = (mo.sigma * 2.0 * mo.lam) * dn
        if not near.signed:
            B_ *= sd * cn / rn
        if not far.signed:
            B_ *= sd * sn / rf
    s_theta = rn * rf  # signed sin θ
    cos_half, sin_half = _cos_sin(0.5 * chi)
    half_n, half_f = rn * math.sqrt(0.5), rf * math.sqrt(0.5)
    # every output as rows of one block, components first: ω (0:3), Γ (3:6), q (6:10), the Euler angles (10:13);
    # the arrays returned are its transposed views (n, 3), (n, 4) — contiguous writes, one state for the kernels
    block = np.empty((13,) + t.shape)
    qr = block[6:10]
    pn, pf = _pairs(mo.sigma)
    np.multiply(half_n, cos_half[0], out=qr[pn[0]])
    np.multiply(half_n, sin_half[0], out=qr[pn[1]])
    np.multiply(half_f, cos_half[1], out=qr[pf[0]])
    np.multiply(half_f, sin_half[1], out=qr[pf[1]])
    norm = qr[0] * qr[0]  # |q|² row by row (einsum over the leading axis takes NumPy's slow path)
    for k in (1, 2, 3):
        norm += qr[k] * qr[k]
    np.sqrt(norm, out=norm)
    qr /= norm
    plus, minus = (1, 0) if mo.sigma > 0 else (0, 1)
    # e^{iψ} with ψ = (χ₊ − χ₋)/2
    cp, sp_, cm, sm = cos_half[plus], sin_half[plus], cos_half[minus], sin_half[minus]
    cos_psi = cp * cm
    cos_psi += sp_ * sm
    sin_psi = sp_ * cm
    sin_psi -= cp * sm
    unit = cos_psi * cos_psi  # cos² + sin² = 1 to round-off again (the half angles' tan formulas leave a few ulp)
    unit += sin_psi * sin_psi
    np.sqrt(unit, out=unit)
    cos_psi /= unit
    sin_psi /= unit
    # (b − a u)/sin θ = ½ [B_n R_f/R_n + B_f R_n/R_f] (a term whose B is 0 vanishes, also where its R does)
    A_ = np.multiply(rf / rn, 0.5 * near.B) if near.B != 0.0 else np.zeros_like(t)
    if far.B != 0.0:
        A_ += (0.5 * far.B) * (rn / rf)
    omega, gamma, euler = block[0:3], block[3:6], block[10:13]
    if B_ is None:
        np.multiply(A_, sin_psi, out=omega[0])
        np.multiply(A_, cos_psi, out=omega[1])
    else:
        np.multiply(A_, sin_psi, out=omega[0])
        omega[0] -= B_ * cos_psi
        np.multiply(A_, cos_psi, out=omega[1])
        omega[1] += B_ * sin_psi
    omega[2] = mo.omega3
    np.multiply(s_theta, sin_psi, out=gamma[0])
    np.multiply(s_theta, cos_psi, out=gamma[1])
    np.subtract(1.0, rn2, out=gamma[2])
    np.subtract(rf2, 1.0, out=gamma[2], where=rn2 >= rf2)
    if mo.sigma < 0:
        gamma[2] *= -1.0
    # Euler angles (zxz), θ ≥ 0: a negative signed sin θ/2 or cos θ/2 is absorbed in φ, ψ
    S, Cc = (half_n, half_f) if mo.sigma > 0 else (half_f, half_n)
    np.arctan2(np.abs(S), np.abs(Cc), out=euler[1])
    euler[1] *= 2.0
    flip = S * Cc < 0
    for k, sign in ((0, 1.0), (2, -1.0)):  # φ, ψ = (χ₊ ± χ₋)/2 ± flip, wrapped to [−π, π]
        angle = euler[k]
        np.multiply(chi[minus], sign, out=angle)
        angle += chi[plus]
        angle *= 0.5
        np.add(angle, sign * math.pi, out=angle, where=flip)
        angle -= (2.0 * math.pi) * np.rint(angle * (0.5 / math.pi))
    return block


def _write_start(block, cols, omega0, snapped, q0, angles):
    """Write the start's own state into the columns ``cols`` of an evaluation block (t = 0: the closed form's value
    there is within round-off or the accuracy of it): ω0, q0 (snapped, of unit length), Γ of it and, with
    ``angles``, its Euler angles on the branches the block's angles took (:func:`_start_angles`)."""
    a, b, c, d = q0.tolist()
    norm = math.sqrt(a * a + b * b + c * c + d * d)
    q = [v / norm for v in snapped.tolist()]
    a, b, c, d = q
    values = [*omega0.tolist(), *_gamma_of(q).tolist(), *q]
    for col in cols:
        block[:10, col] = values
        if angles:
            block[10:13, col] = _start_angles([block[10:13, col].tolist()], q)[0]


def _start_angles(approx, q):
    """The zxz angles of the unit quaternion ``q`` on the branches of ``approx`` (rows of angles within the accuracy
    asked of them): each angle moved by its wrapped difference to q's own, where q gives one (θ ≠ 0, π: else φ and
    ψ are split as the closed form split them, and stay). Rows of floats in, a list of rows out (a start is one
    time or a few: scalar arithmetic)."""
    q0, q1, q2, q3 = (float(v) for v in q)
    theta = 2.0 * math.atan2(math.hypot(q1, q2), math.hypot(q0, q3))
    exact = None
    if min(math.hypot(q1, q2), math.hypot(q0, q3)) > 1e-8:
        plus, minus = 2.0 * math.atan2(q3, q0), 2.0 * math.atan2(q2, q1)
        exact = (0.5 * (plus + minus), 0.5 * (plus - minus))
    out = []
    for phi, _, psi in approx:
        row = [float(phi), theta, float(psi)]
        if exact is not None:
            for k, value in zip((0, 2), exact):
                step = value - row[k]
                step -= 2.0 * math.pi * round(step / (2.0 * math.pi))
                if abs(step) < 1e-3:  # a half-turn apart: the flip's other branch
                    row[k] += step
        out.append(row)
    return out


def euler_to_quaternion(euler):
    """The attitude quaternion ``qz(φ) ⊗ qx(θ) ⊗ qz(ψ)`` (scalar first) of zxz Euler angles ``(φ, θ, ψ)``.

    Parameters
    ----------
    euler : array_like, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 4)

    Examples
    --------
    >>> euler_to_quaternion((0.0, 0.0, 0.0))
    array([1., 0., 0., 0.])
    """
    e = finite_array("euler", euler)
    if e.shape[-1:] != (3,):
        raise InvalidInput("euler", euler, "Euler angles (phi, theta, psi) in the last axis")
    phi, theta, psi = e[..., 0], e[..., 1], e[..., 2]
    c, s = np.cos(0.5 * theta), np.sin(0.5 * theta)
    sp_, dm = 0.5 * (phi + psi), 0.5 * (phi - psi)
    return np.stack([c * np.cos(sp_), s * np.cos(dm), s * np.sin(dm), c * np.sin(sp_)], axis=-1)


def _one_member(I, M, g, l, omega0, q0):
    """:func:`_members` for one member given as float64 arrays (as a scene passes them), accepted by the same checks
    on floats; None for anything else, and wherever a check fails (the general path then decides and names it)."""
    shapes = ((I, ((3,), (1, 3))), (omega0, ((3,), (1, 3))), (q0, ((4,), (1, 4))), (M, ((), (1,))), (g, ((), (1,))),
              (l, ((), (1,))))
    if not all(type(a) is np.ndarray and a.dtype == np.float64 and a.shape in ok for a, ok in shapes):
        return None
    I1, I2, I3, w1, w2, w3, a, b, c, d, Mf, gf, lf = (*I.ravel().tolist(), *omega0.ravel().tolist(),
                                                       *q0.ravel().tolist(), M.item(), g.item(), l.item())
    values = (I1, I2, I3, w1, w2, w3, a, b, c, d, Mf, gf, lf)
    if not all(map(math.isfinite, values)) or not (I1 == I2 and I1 > 0.0 and I3 > 0.0 and Mf > 0.0):
        return None
    if gf == 0.0 or lf == 0.0 or 2.0 * I1 < I3 - TRIANGLE_SLACK * max(I1, I3):
        return None
    if abs(math.sqrt(a * a + b * b + c * c + d * d) - 1.0) > 1e-6:
        return None
    batched = I.ndim == 2 or omega0.ndim == 2 or q0.ndim == 2 or M.ndim == 1 or g.ndim == 1 or l.ndim == 1
    return (batched, 1, I.reshape(1, 3), M.reshape(1), g.reshape(1), l.reshape(1), omega0.reshape(1, 3),
            q0.reshape(1, 4))


def _members(I, M, g, l, omega0, q0):
    """Validate and broadcast the inputs to B members."""
    one = _one_member(I, M, g, l, omega0, q0)
    if one is not None:
        return one
    Iarr = finite_array("I", I)
    if Iarr.shape[-1:] != (3,) or Iarr.ndim > 2:
        raise InvalidInput("I", I, "moments (I1, I1, I3), or an array of them of shape (B, 3)")
    w = finite_array("omega0", omega0)
    if w.shape[-1:] != (3,) or w.ndim > 2:
        raise InvalidInput("omega0", omega0, "a body angular velocity of shape (3,) or (B, 3)")
    qq = finite_array("q0", q0)
    if qq.shape[-1:] != (4,) or qq.ndim > 2:
        raise InvalidInput("q0", q0, "a unit quaternion of shape (4,) or (B, 4)")
    scal = [finite_array(name, v) for name, v in (("M", M), ("g", g), ("l", l))]
    for name, v in zip(("M", "g", "l"), scal):
        if v.ndim > 1:
            raise InvalidInput(name, v, "a number or an array of shape (B,)")
    batched = any(x.ndim == 2 for x in (Iarr, w, qq)) or any(x.ndim == 1 for x in scal)
    sizes = {x.shape[0] for x in (Iarr, w, qq) if x.ndim == 2} | {x.shape[0] for x in scal if x.ndim == 1}
    if len(sizes) > 1:
        raise InvalidInput("omega0", omega0, f"inputs with one common number of members (got sizes {sorted(sizes)})")
    nb = sizes.pop() if sizes else 1
    Iarr = np.broadcast_to(Iarr, (nb, 3))
    w = np.broadcast_to(w, (nb, 3))
    qq = np.broadcast_to(qq, (nb, 4))
    Mv, gv, lv = (np.broadcast_to(x, (nb,)) for x in scal)
    moments("I", Iarr)  # every member at once (the one check of a body's moments: positive, the triangle)
    first = lambda bad: int(np.argmax(bad))  # noqa: E731  (the first member that fails, for the message)
    bad = Iarr[:, 0] != Iarr[:, 1]
    if bad.any():
        raise InvalidInput("I", tuple(Iarr[first(bad)]), "a symmetric top (I1, I1, I3): I1 == I2 exactly "
                           "(for I1 != I2 integrate: there is no closed form)")
    bad = ~(Mv > 0)
    if bad.any():
        raise InvalidInput("M", float(Mv[first(bad)]), "a positive mass")
    bad = gv == 0
    if bad.any():
        raise InvalidInput("g", float(gv[first(bad)]), "a non-zero gravitational acceleration (g = 0 is torque-free: "
                           "use free_rigid_body_attitude_exact)")
    bad = lv == 0
    if bad.any():
        raise InvalidInput("l", float(lv[first(bad)]), "a non-zero distance from the pivot to the centre of mass "
                           "(l = 0 is torque-free: use free_rigid_body_attitude_exact)")
    bad = np.abs(np.sqrt(np.sum(qq * qq, axis=1)) - 1.0) > 1e-6
    if bad.any():
        raise InvalidInput("q0", tuple(qq[first(bad)]), "a unit quaternion (q0, q1, q2, q3), scalar first, |q| = 1")
    return batched, nb, Iarr, Mv, gv, lv, w, qq


def _gamma_of(q):
    """Γ = R(q)ᵀ ẑ of a unit quaternion."""
    a, b, c, d = q
    return np.array([2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d])


def _gammas(q):
    """Γ = R(q)ᵀ ẑ of unit quaternions (rows)."""
    a, b, c, d = q.T
    return np.stack([2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d], axis=1)


def _snap_rows(q):
    """:func:`_snap_to_poles` of quaternions as rows, all at once (the same comparisons, elementwise)."""
    q = np.array(q, dtype=np.float64)
    n2 = np.sum(q * q, axis=1)
    up = q[:, 1] ** 2 + q[:, 2] ** 2 < 1e-34 * n2
    down = ~up & (q[:, 0] ** 2 + q[:, 3] ** 2 < 1e-34 * n2)
    q[up, 1:3] = 0.0
    q[down, 0] = 0.0
    q[down, 3] = 0.0
    return q


def _snap_to_poles(q):
    """A tilt θ (or π − θ) below 2e-17 rad is taken as exactly upright (down): a change of q0 below half an ulp of
    its unit components, and a pass through the pole that the double phase could not resolve."""
    a, b, c, d = (float(v) for v in np.asarray(q, dtype=np.float64).tolist())
    n2 = a * a + b * b + c * c + d * d
    if b * b + c * c < 1e-34 * n2:
        b = c = 0.0
    elif a * a + d * d < 1e-34 * n2:
        a = d = 0.0
    return np.array([a, b, c, d])


#: Up to this many members, :func:`heavy_top_exact` computes every member's constants to 36 digits (~0.2 ms each).
BATCH_PRECISE = 64


def _batch(batched, nb, Iarr, Mv, gv, lv, w, qq, tt, accuracy=None, attitude=True):
    """All members at once in double precision; the members that path leaves out, one by one, precisely."""
    from eulersym.numerics._heavy_top_batch import batch_motion

    snapped = _snap_rows(qq)
    ok, omega, gamma, q, euler, period, turning = batch_motion(Iarr[:, 0], Iarr[:, 2], Mv * gv * lv, w, snapped, tt,
                                                               accuracy, attitude=attitude)
    for k in np.flatnonzero(~ok):
        one = heavy_top_exact(Iarr[k], Mv[k], gv[k], lv[k], w[k], qq[k], tt, precise=True, accuracy=accuracy)
        omega[k], gamma[k], period[k], turning[k] = one.omega, one.gamma, one.period, one.turning_points
        if attitude:
            q[k], euler[k] = one.q, one.euler
    start = tt == 0.0
    if np.any(start):
        omega[:, start] = w[:, None, :]
        unit = snapped / np.sqrt(np.sum(snapped * snapped, axis=1, keepdims=True))
        if attitude:
            q[:, start] = unit[:, None, :]
        gamma[:, start] = _gammas(unit)[:, None, :]
    if not batched:
        return HeavyTopMotion(t=tt, omega=omega[0], gamma=gamma[0], q=None if q is None else q[0],
                              euler=None if euler is None else euler[0], period=float(period[0]),
                              turning_points=turning[0])
    return HeavyTopMotion(t=tt, omega=omega, gamma=gamma, q=q, euler=euler, period=period, turning_points=turning)


def heavy_top_exact(I, M, g, l, omega0, q0, t, *, precise=None, accuracy=None, attitude=True):
    """The heavy symmetric top in closed form: ω(t), Γ(t), q(t) and the Euler angles at any times.

    Solves ``I ω̇ + ω × I ω = M g l Γ × e3``, ``Γ̇ = Γ × ω``, ``q̇ = ½ q ⊗ (0, ω)`` exactly (see the module
    docstring): u = cos θ from Jacobi's sn, φ ± ψ from elliptic integrals of the third kind; every start (θ̇0 zero
    or not, looping, wavy and cusped precession, the hanging top with ``l < 0``, the sleeping and the near-sleeping
    top, steady precession, fast and slow spin). The error is at round-off relative to the scale of ω and does not
    grow with t (the phase and the secular angles are reduced in double-double).

    Parameters
    ----------
    I : array_like, shape (3,) or (B, 3)
        Moments about the pivot ``(I1, I1, I3)``; the first two must be equal.
    M, g : float or array_like (B,)
        Mass (positive) and gravitational acceleration (non-zero; only ``M g l`` enters).
    l : float or array_like (B,)
        Signed distance from the pivot to the centre of mass along e3 (negative: below the pivot), non-zero.
    omega0 : array_like, shape (3,) or (B, 3)
        Body angular velocity at t = 0.
    q0 : array_like, shape (4,) or (B, 4)
        Unit attitude quaternion at t = 0 (:func:`euler_to_quaternion` makes one from zxz Euler angles).
    t : array_like, shape (n,)
        Times (any order, negative allowed).
    precise : bool or None, optional
        True: every member's constants to 36 digits and the phase in double-double (round-off error at any t,
        ~0.2 ms per member). False: all members at once in double precision (error below ~3e-13 × the number
        of nutation periods; members at a double root, near a pole, or whose m_c the rounding of the cubic's
        coefficients moves by more than 64 ulp — next to the separatrix — or, for an ``accuracy`` asked, by more
        than a tenth of it over the times' phase, still go the precise way).
        None (default): precise up to :data:`BATCH_PRECISE` members.
    accuracy : float or None, optional
        Relative accuracy asked (of ω, relative to its scale) for the precise path (a scene passes its accuracy):
        the motion's constants are then finished in double where their error bound allows, and the outputs summed as Fourier series in the nutation phase, fitted per call from 32–128 samples of
        the closed form (:mod:`eulersym.numerics._heavy_top_fourier`: cut at round-off, the phase and the secular
        angles in double where their rounding bound stays below a tenth of the accuracy, else in double-double);
        where those series decline (a pole that is a turning point, a pass close to a pole, a start near the
        separatrix, a steady motion), the direct evaluation computes the phase and the secular angles in double,
        and cuts the Chebyshev series of the third-kind integrals, wherever their bounds stay below a tenth of it.
        None (default): round-off at every t, by the direct evaluation.
    attitude : bool, optional
        True (default): q and the Euler angles too. False: ω and Γ only (``q`` and ``euler`` are None), for a caller
        that keeps no attitude — the sweep of a map of ω: the members in double skip a fifth of their work.

    Returns
    -------
    HeavyTopMotion
        With a leading member axis of length B when any input has one (a sweep: the members share t).

    Raises
    ------
    eulersym.errors.InvalidInput
        ``I1 != I2``, non-physical moments, non-positive M, ``g = 0`` or ``l = 0``, non-unit q0, non-finite input.
    eulersym.errors.SingularConfiguration
        A start exactly on a separatrix (the top tends to the vertical as t → ∞: no periodic closed form).

    Examples
    --------
    A fast top released at θ = 1 rad with only its spin: cusped precession; energy and p_φ are kept.

    >>> import numpy as np
    >>> q0 = euler_to_quaternion((0.0, 1.0, 0.0))
    >>> m = heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 40.0), q0, np.linspace(0, 50, 6))
    >>> E = 0.5 * np.sum(np.array([1.0, 1.0, 0.5]) * m.omega**2, axis=1) + 9.81 * 0.1 * m.gamma[:, 2]
    >>> bool(np.max(np.abs(E - E[0])) < 1e-12 * E[0])
    True
    >>> round(m.period, 6)                 # the nutation period, ≈ 2π I1/(I3 ω3) = 0.314159 for a fast top
    0.314991

    At an accuracy asked (as a scene asks), double precision where its rounding bound allows:

    >>> t = np.linspace(0, 50, 101)
    >>> fast = heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 40.0), q0, t, accuracy=1e-11)
    >>> exact = heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 40.0), q0, t)
    >>> bool(np.max(np.abs(fast.omega - exact.omega)) <= 1e-11 * 40.0)
    True

    ω and Γ only (no attitude kept), the same ω:

    >>> bare = heavy_top_exact((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 40.0), q0, t, attitude=False)
    >>> bare.q is None, bool(np.array_equal(bare.omega, exact.omega))
    (True, True)
    """
    batched, nb, Iarr, Mv, gv, lv, w, qq = _members(I, M, g, l, omega0, q0)
    if type(t) is np.ndarray and t.dtype == np.float64 and t.ndim == 1 and np.isfinite(t).all():
        tt = t  # float times as a scene passes them: finite_array's checks, without its conversions
    else:
        tt = finite_array("t", np.atleast_1d(np.asarray(t, dtype=np.float64)) if np.ndim(t) == 0 else t, shape=(None,))
    if accuracy is not None:
        if isinstance(accuracy, (bool, str)) or not (isinstance(accuracy, (int, float, np.floating))
                                                       and math.isfinite(accuracy) and 0.0 < accuracy < 1.0):
            raise InvalidInput("accuracy", accuracy, "a relative accuracy between 0 and 1 (e.g. 1e-11), or None "
                               "for round-off")
    if precise is None:
        precise = nb <= BATCH_PRECISE
    if not precise:
        return _batch(batched, nb, Iarr, Mv, gv, lv, w, qq, tt, accuracy, bool(attitude))
    outs = ([], [], [], [], [], [])
    block = None
    tmax = float(np.max(np.abs(tt))) if accuracy is not None and tt.size else 0.0
    for k in range(nb):
        snapped = _snap_to_poles(qq[k])
        mo = None
        if accuracy is not None:  # the constants in double where their error bound allows
            mo = _setup_double(Iarr[k, 0], Iarr[k, 2], Mv[k], gv[k], lv[k], w[k], snapped, float(accuracy), tmax)
        if mo is None:
            mo = _setup(Iarr[k, 0], Iarr[k, 2], Mv[k], gv[k], lv[k], w[k], snapped)
        block = _evaluate(mo, tt, accuracy)
        omega, gamma, q, euler = block[0:3].T, block[3:6].T, block[6:10].T, block[10:13].T
        cols = np.flatnonzero(tt == 0.0)  # the start (also where a pass through a pole at t = 0 is below the phase resolution)
        if cols.size:
            _write_start(block, cols.tolist(), w[k], snapped, qq[k], accuracy is not None)
        for lst, val in zip(outs, (omega, gamma, q, euler, mo.nutation_period, mo.turning)):
            lst.append(val)
    arrays = [np.stack(x) if len(x) > 1 else np.asarray(x[0])[None] for x in outs]  # one member: views
    rows = block[None] if nb == 1 else None
    if not batched:
        arrays = [x[0] for x in arrays]
        arrays[4] = float(arrays[4])
        rows = block
    omega, gamma, q, euler, period, turning = arrays
    if not attitude:  # computed on the way (the rows hold them), not handed back: as the batch path does
        q = euler = None
    return HeavyTopMotion(t=tt, omega=omega, gamma=gamma, q=q, euler=euler, period=period, turning_points=turning,
                          rows=rows)
