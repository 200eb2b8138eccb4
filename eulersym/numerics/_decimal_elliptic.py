"""Carlson's symmetric elliptic integrals, the AGM and π in :mod:`decimal` arithmetic (standard library only).

The closed forms of :mod:`eulersym.numerics.heavy_top_exact` need a few constants per motion (the turning points,
the nutation frequency, the quarter period K, the mean precession and spin per nutation period) to more digits
than a double holds, so that a phase reduced modulo the nutation period does not lose accuracy with t. These are
computed once per motion at :data:`DIGITS` digits with the algorithms below, which use only + − × ÷ and √:

* ``R_F`` and ``R_J`` by Carlson's duplication (Carlson 1979/1995; Numerical Recipes' ``rf``/``rj``): iterate
  until the relative spread of the arguments is below ``TOL``, then the fifth-order series, whose error is
  O(TOL⁶) ≈ 1e-39;
* ``R_C`` (inside ``R_J``) the same way;
* ``agm`` by the arithmetic–geometric mean, π by the Gauss–Legendre (Brent–Salamin) iteration;
* the complete integral of the third kind ``Π(n | m) = ∫₀ᴷ dx/(1 − n sn² x)`` by the AGM with Carlson's auxiliary
  sequence (DLMF 19.8.6–19.8.8; quadratic convergence, two square roots a step instead of the ~300 of ``R_J`` by
  duplication).

Every function must be called inside a :func:`decimal.localcontext` of at least :data:`DIGITS` digits.

Examples
--------
>>> import decimal
>>> with decimal.localcontext() as ctx:
...     ctx.prec = DIGITS
...     k = pi() / (2 * agm(decimal.Decimal(1), decimal.Decimal("0.5").sqrt()))
...     rf = rf_(decimal.Decimal(0), decimal.Decimal("0.5"), decimal.Decimal(1))
>>> abs(k - rf) < decimal.Decimal("1e-33")      # K(m = 1/2) both ways
True
>>> with decimal.localcontext() as ctx:
...     ctx.prec = DIGITS
...     zero, one, n, mc = (decimal.Decimal(v) for v in ("0", "1", "0.3", "0.5"))
...     by_agm = third_kind_complete(n, 1 - n, mc)
...     by_rj = rf_(zero, mc, one) + n / 3 * rj_(zero, mc, one, 1 - n)
>>> abs(by_agm - by_rj) < decimal.Decimal("1e-33")  # Π(0.3 | 1/2) both ways
True
"""

from __future__ import annotations

import decimal
import functools
import math
from decimal import Decimal

__all__ = ["DIGITS", "pi", "sqrt", "agm", "rf_", "rc_", "rj_", "third_kind_complete", "complete_integrals"]

#: Working precision (decimal digits) of the per-motion constants.
DIGITS = 36
_TOL = Decimal("3e-7")  # series truncation error ~ TOL⁶ ≈ 1e-39


@functools.lru_cache(maxsize=4)
def _pi(prec: int) -> Decimal:
    with decimal.localcontext() as ctx:
        ctx.prec = prec + 10
        a, b, t, p = Decimal(1), Decimal("0.5").sqrt(), Decimal("0.25"), Decimal(1)
        for _ in range(12):  # quadratic convergence: 2^12 digits
            an = (a + b) / 2
            b = (a * b).sqrt()
            t -= p * (a - an) ** 2
            a = an
            p *= 2
        return (a + b) ** 2 / (4 * t)


def pi() -> Decimal:
    """π at the current precision."""
    return +_pi(decimal.getcontext().prec)


def sqrt(x):
    """√x in the arithmetic of x: :class:`~decimal.Decimal` (at the context's precision) or float."""
    return x.sqrt() if type(x) is Decimal else math.sqrt(x)


def agm(a: Decimal, b: Decimal) -> Decimal:
    """Arithmetic–geometric mean of a, b > 0."""
    eps = Decimal(10) ** (-decimal.getcontext().prec + 2)
    for _ in range(200):
        if abs(a - b) <= eps * a:
            break
        a, b = (a + b) / 2, (a * b).sqrt()
    return (a + b) / 2


def rf_(x: Decimal, y: Decimal, z: Decimal) -> Decimal:
    """Carlson's ``R_F(x, y, z)`` for x, y, z ≥ 0, at most one zero."""
    for _ in range(200):
        sx, sy, sz = x.sqrt(), y.sqrt(), z.sqrt()
        lam = sx * (sy + sz) + sy * sz
        x, y, z = (x + lam) / 4, (y + lam) / 4, (z + lam) / 4
        ave = (x + y + z) / 3
        dx, dy, dz = (ave - x) / ave, (ave - y) / ave, (ave - z) / ave
        if max(abs(dx), abs(dy), abs(dz)) < _TOL:
            break
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    return (1 + (e2 / 24 - Decimal(1) / 10 - Decimal(3) / 44 * e3) * e2 + e3 / 14) / ave.sqrt()


def rc_(x: Decimal, y: Decimal) -> Decimal:
    """Carlson's ``R_C(x, y)`` for x ≥ 0, y > 0."""
    for _ in range(200):
        lam = 2 * x.sqrt() * y.sqrt() + y
        x, y = (x + lam) / 4, (y + lam) / 4
        ave = (x + 2 * y) / 3
        s = (y - ave) / ave
        if abs(s) < _TOL:
            break
    c1, c2, c3, c4 = Decimal(3) / 10, Decimal(1) / 7, Decimal(3) / 8, Decimal(9) / 22
    return (1 + s * s * (c1 + s * (c2 + s * (c3 + s * c4)))) / ave.sqrt()


def rj_(x: Decimal, y: Decimal, z: Decimal, p: Decimal) -> Decimal:
    """Carlson's ``R_J(x, y, z, p)`` for x, y, z ≥ 0 (at most one zero), p > 0."""
    total, fac = Decimal(0), Decimal(1)
    for _ in range(200):
        sx, sy, sz = x.sqrt(), y.sqrt(), z.sqrt()
        lam = sx * (sy + sz) + sy * sz
        alpha = (p * (sx + sy + sz) + sx * sy * sz) ** 2
        beta = p * (p + lam) ** 2
        total += fac * rc_(alpha, beta)
        fac /= 4
        x, y, z, p = (x + lam) / 4, (y + lam) / 4, (z + lam) / 4, (p + lam) / 4
        ave = (x + y + z + 2 * p) / 5
        dx, dy, dz, dp = (ave - x) / ave, (ave - y) / ave, (ave - z) / ave, (ave - p) / ave
        if max(abs(dx), abs(dy), abs(dz), abs(dp)) < _TOL:
            break
    c1, c2, c3, c4 = Decimal(3) / 14, Decimal(1) / 3, Decimal(3) / 22, Decimal(3) / 26
    c5, c6, c7, c8 = c3 * 3 / 4, c4 * 3 / 2, c2 / 2, 2 * c3
    ea = dx * (dy + dz) + dy * dz
    eb = dx * dy * dz
    ec = dp * dp
    ed = ea - 3 * ec
    ee = eb + 2 * dp * (ea - ec)
    series = (1 + ed * (-c1 + c5 * ed - c6 * ee) + eb * (c7 + dp * (-c8 + dp * c4))
              + dp * ea * (c2 - dp * c3) - c2 * dp * ec)
    return 3 * total + fac * series / (ave * ave.sqrt())


def third_kind_complete(n: Decimal, one_minus_n: Decimal, mc: Decimal) -> Decimal:
    """``Π(n | m) = ∫₀ᴷ dx/(1 − n sn² x)`` for ``n < 1`` (``one_minus_n = 1 − n > 0`` given exactly) and
    ``0 < m_c = 1 − m ≤ 1``, by DLMF 19.8.6–19.8.8::

        Π = π/(4 M) · (2 + n/(1 − n) · Σ Q_k),   M = AGM(1, √m_c),   p₀ = √(1 − n),  Q₀ = 1,
        ε_k = (p_k² − a_k g_k)/(p_k² + a_k g_k),  p_{k+1} = (p_k² + a_k g_k)/(2 p_k),  Q_{k+1} = Q_k ε_k / 2.

    Every term is a ratio of sums of positive numbers except ε_k; as ``1 − n → 0`` the sum Σ Q loses about
    ``½ log₁₀(1/(1 − n))`` digits to cancellation (e.g. 13 of the 36 at ``1 − n = 1e-26``, still ~1e-23 relative;
    ~4e-24 at ``m_c = 1e-40``).
    Call inside a :func:`decimal.localcontext` of at least :data:`DIGITS` digits.
    """
    return complete_integrals(mc, ((n, one_minus_n),))[1][0]


def complete_integrals(mc: Decimal, characteristics) -> tuple:
    """``(K(m), [Π(n | m) for (n, 1 − n) in characteristics])`` from one AGM sequence of ``(1, √m_c)``: K = π/(2M)
    and each Π by :func:`third_kind_complete`'s recurrence, which shares the AGM's ``a_k, g_k`` (one sequence
    instead of one per integral). ``n = 0`` gives Π = K. In the arithmetic of ``mc``: Decimal (call inside a
    :func:`decimal.localcontext` of at least :data:`DIGITS` digits) or float (a few ulp where ``1 − n`` is not
    small: the recurrence's terms are ratios of sums of positive numbers but ε_k, see :func:`third_kind_complete`).

    Examples
    --------
    >>> import decimal
    >>> with decimal.localcontext() as ctx:
    ...     ctx.prec = DIGITS
    ...     mc, n = decimal.Decimal("0.5"), decimal.Decimal("0.3")
    ...     K, (P0, P) = complete_integrals(mc, ((decimal.Decimal(0), decimal.Decimal(1)), (n, 1 - n)))
    ...     checks = (abs(K - rf_(decimal.Decimal(0), mc, decimal.Decimal(1))), abs(P0 - K),
    ...               abs(P - third_kind_complete(n, 1 - n, mc)))
    >>> max(checks) < decimal.Decimal("1e-33")
    True
    """
    exact = type(mc) is Decimal
    eps = Decimal(10) ** (-decimal.getcontext().prec + 1) if exact else 2.0 ** -52
    one = mc / mc
    a, g = one, sqrt(mc)
    ps = [sqrt(one_minus_n) for _, one_minus_n in characteristics]
    qs = [one] * len(ps)
    totals = [one - one] * len(ps)
    for _ in range(400):
        ag = a * g
        done = abs(a - g) <= eps * a
        for k, p in enumerate(ps):
            pp = p * p
            totals[k] += qs[k]
            qs[k] = qs[k] * (pp - ag) / (2 * (pp + ag))
            ps[k] = (pp + ag) / (2 * p)
            done = done and abs(qs[k]) <= eps * abs(totals[k])
        if done:
            break
        a, g = (a + g) / 2, sqrt(ag)
    half = (pi() if exact else math.pi) / (2 * (a + g))
    return 2 * half, [half * (2 + n / one_minus_n * total) for (n, one_minus_n), total in zip(characteristics, totals)]
