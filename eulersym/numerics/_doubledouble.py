"""Double-double arithmetic in plain Python floats, for the few constants that need ~32 digits.

A double-double ``(hi, lo)`` stands for the unevaluated sum ``hi + lo`` with ``|lo| ≤ ulp(hi)/2``; sums and
products are built from the error-free transformations of Knuth (two-sum) and Dekker (two-product, with
Veltkamp's split, so no fused multiply-add is needed). The relative error of each operation is a small multiple
of ``2**-104`` (Dekker 1971; Bailey's QD library). Conversions from exact rationals (pairs of Python ints) round
the quotient once with Python's correctly rounded ``int / int`` and take the remainder exactly in integers.

Used by :mod:`eulersym.numerics.exact` for λ, √m_c and the period 4K = 2π / AGM(1, √m_c) of the free rigid body,
so that the phase ``λ t + u0`` reduced modulo 4K does not lose accuracy with the number of periods.

Examples
--------
>>> hi, lo = sqrt_ratio(2, 1)                      # √2 to ~32 digits
>>> hi, abs(lo) < 1e-16
(1.4142135623730951, True)
>>> import mpmath
>>> with mpmath.workdps(40):
...     err = abs((mpmath.mpf(hi) + mpmath.mpf(lo)) - mpmath.sqrt(2))
>>> bool(err < 1e-31)
True
"""

from __future__ import annotations

import math

__all__ = ["two_sum", "two_prod", "add", "mul", "div", "sqrt", "ratio", "sqrt_ratio", "agm", "PI"]

_SPLIT = 134217729.0  # 2**27 + 1, Veltkamp's splitter for 53-bit doubles

#: π as a double-double.
PI = (3.141592653589793, 1.2246467991473532e-16)


def two_sum(a: float, b: float) -> tuple[float, float]:
    """``a + b = s + e`` exactly (Knuth).

    Examples
    --------
    >>> two_sum(1.0, 1e-20)
    (1.0, 1e-20)
    """
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def two_prod(a: float, b: float) -> tuple[float, float]:
    """``a · b = p + e`` exactly (Dekker; no FMA needed), barring overflow.

    Examples
    --------
    >>> p, e = two_prod(1.0 + 2.0**-30, 1.0 + 2.0**-30)
    >>> p == 1.0 + 2.0**-29, e == 2.0**-60
    (True, True)
    """
    p = a * b
    ca = _SPLIT * a
    ah = ca - (ca - a)
    al = a - ah
    cb = _SPLIT * b
    bh = cb - (cb - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _fast_two_sum(a: float, b: float) -> tuple[float, float]:
    s = a + b
    return s, b - (s - a)


def add(x: tuple[float, float], y: tuple[float, float]) -> tuple[float, float]:
    """Double-double sum (the accurate, IEEE-style variant).

    Examples
    --------
    >>> add((1.0, 2.0**-70), (2.0, 2.0**-70)) == (3.0, 2.0**-69)
    True
    """
    s, e = two_sum(x[0], y[0])
    t, f = two_sum(x[1], y[1])
    e += t
    s, e = _fast_two_sum(s, e)
    e += f
    return _fast_two_sum(s, e)


def mul(x: tuple[float, float], y: tuple[float, float]) -> tuple[float, float]:
    """Double-double product.

    Examples
    --------
    >>> mul((3.0, 0.0), (0.5, 2.0**-70)) == (1.5, 3 * 2.0**-70)
    True
    """
    p, e = two_prod(x[0], y[0])
    e += x[0] * y[1] + x[1] * y[0]
    return _fast_two_sum(p, e)


def div(x: tuple[float, float], y: tuple[float, float]) -> tuple[float, float]:
    """Double-double quotient (one correction step of the double quotient).

    Examples
    --------
    >>> div((1.0, 0.0), (3.0, 0.0))[0] == 1 / 3
    True
    """
    q1 = x[0] / y[0]
    r = add(x, mul((-q1, 0.0), y))
    q2 = r[0] / y[0]
    r = add(r, mul((-q2, 0.0), y))
    q3 = r[0] / y[0]
    return add(_fast_two_sum(q1, q2), (q3, 0.0))


def sqrt(x: tuple[float, float]) -> tuple[float, float]:
    """Double-double square root of a non-negative double-double (one Newton step from the double root).

    Examples
    --------
    >>> sqrt((4.0, 0.0))
    (2.0, 0.0)
    """
    if x[0] <= 0.0:
        return (0.0, 0.0)
    r = math.sqrt(x[0])
    p, e = two_prod(r, r)
    residual = ((x[0] - p) - e) + x[1]
    return _fast_two_sum(r, residual / (2.0 * r))


def ratio(num: int, den: int) -> tuple[float, float]:
    """The rational ``num / den`` (Python ints, ``den > 0``) as a double-double: hi correctly rounded, lo the
    correctly rounded remainder.

    Examples
    --------
    >>> ratio(1, 3)
    (0.3333333333333333, 1.850371707708594e-17)
    """
    hi = num / den
    if hi == 0.0 or math.isinf(hi):
        return hi, 0.0
    p, q = hi.as_integer_ratio()
    return hi, (num * q - p * den) / (den * q)


def sqrt_ratio(num: int, den: int) -> tuple[float, float]:
    """``√(num / den)`` as a double-double, for a non-negative rational of any size (exact power-of-two scaling
    keeps it away from underflow and overflow while it is formed).

    Examples
    --------
    >>> sqrt_ratio(1, 10**600)[0]
    1e-300
    """
    if num <= 0:
        return (0.0, 0.0)
    k = (den.bit_length() - num.bit_length()) // 2  # num·4^k / den is near 1
    if k >= 0:
        x = ratio(num << (2 * k), den)
    else:
        x = ratio(num, den << (-2 * k))
    hi, lo = sqrt(x)
    return math.ldexp(hi, -k), math.ldexp(lo, -k)


def agm(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    """The arithmetic-geometric mean of two positive double-doubles.

    Stops once ``|a − b| ≤ 2**-56 a``: the next arithmetic mean then differs from the limit by ≲ (a − b)² / (8a),
    below the double-double rounding.

    Examples
    --------
    >>> g = agm((1.0, 0.0), (2.0 ** -0.5, 0.0))   # Gauss's constant 1/AGM(1, √2) = 0.8346268...
    >>> round(1 / (g[0] * 2 ** 0.5), 15)
    0.834626841674073
    """
    for _ in range(64):
        d = add(a, (-b[0], -b[1]))
        if abs(d[0]) <= 2.0**-56 * a[0]:
            break
        a, b = mul(add(a, b), (0.5, 0.0)), sqrt(mul(a, b))
    return mul(add(a, b), (0.5, 0.0))
