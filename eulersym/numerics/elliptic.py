"""Elliptic functions and integrals in double precision, on NumPy alone: the one core the closed forms share.

The free body (:mod:`eulersym.numerics.exact`), the heavy top (:mod:`eulersym.numerics.heavy_top_exact`), its Fourier
path and its batch path take every elliptic quantity from here, so a closed-form scene needs no ``scipy.special``.

Conventions
-----------
* The parameter is given by its complement ``m_c = 1 − m`` (``m = k²``): near the separatrix ``m → 1`` it is ``m_c``
  that carries the information, and ``1 − m`` formed in floating point would lose it.
* ``K = K(m) = ∫₀^{π/2} dφ / √(1 − m sin²φ) = π / (2 AGM(1, √m_c))``; the periods are ``sn(u + 4K) = sn u``,
  ``cn(u + 4K) = cn u``, ``dn(u + 2K) = dn u``.
* Carlson's symmetric integrals (DLMF 19.16.1–2)::

      R_F(x, y, z)    = ½ ∫₀^∞ dt / √((t + x)(t + y)(t + z)),
      R_J(x, y, z, p) = (3/2) ∫₀^∞ dt / ((t + p) √((t + x)(t + y)(t + z))),

  with ``K = R_F(0, m_c, 1)`` and the incomplete integral of the third kind from ``s = sn x``, ``c = cn x``,
  ``d² = dn² x = c² + m_c s²`` (0 ≤ x ≤ K)::

      ∫₀ˣ dy / (1 − n sn² y) = s R_F(c², d², 1) + (n/3) s³ R_J(c², d², 1, 1 − n s²).

The algorithms
--------------
* sn, cn, dn: the argument is reduced modulo 4K to [0, K] by the exact symmetries, Bulirsch's descending Landen
  (AGM) recurrence runs on [0, K/2] and the quarter-period reflection ``sn(K − y) = cn y/dn y``,
  ``cn(K − y) = √m_c sn y/dn y``, ``dn(K − y) = √m_c/dn y`` covers [K/2, K]: a few ulp for every ``0 ≤ m_c ≤ 1``.
* ``R_F`` and ``R_J`` by Carlson's duplication (Carlson, *Numer. Algorithms* 10 (1995) 13; DLMF 19.36.1–2): the
  arguments are moved together, ``x ← (x + λ)/4``, ``λ = √x√y + √y√z + √z√x``, until their relative spread is
  below 10⁻³, then the series in the spread, through degree 5: truncation below 10⁻¹⁸ relative. ``R_J`` collects
  on the way ``6 Σ 4⁻ᵐ R_C(1, 1 + e_m)/d_m`` with ``d_m = (√p + √x)(√p + √y)(√p + √z)``, ``e_m = δ_m/d_m²``,
  ``δ_m = (p − x)(p − y)(p − z)``; where ``e_m < 0`` it takes ``1 + e_m = 2√p (p + λ)/d_m`` (no cancellation
  as ``e_m → −1``, a characteristic near 1), and ``R_C(1, 1 + e) = atan(√e)/√e`` (e > 0) or
  ``½ log1p(2s(1 + s)/(1 + e))/s``, ``s = √−e`` (e < 0).
* Phases: ``u = λ t + u0`` reduced modulo a period in double-double (λ, u0 and the period double-doubles,
  :mod:`eulersym.numerics._doubledouble`), so the reduced phase does not lose digits with the number of periods.

The module's private functions (``_sncndn`` and friends: no argument checks, arrays that broadcast) are the
interface of the closed forms in :mod:`eulersym.numerics`; the public ones check their input.

Examples
--------
>>> import mpmath
>>> sn, cn, dn = jacobi_sncndn(0.7, 0.25)
>>> bool(abs(sn - float(mpmath.ellipfun("sn", 0.7, 0.75))) < 1e-15)
True
>>> bool(abs(complete_elliptic_k(0.25) - float(carlson_rf(0.0, 0.25, 1.0))) < 1e-15)   # K = R_F(0, m_c, 1)
True
"""

from __future__ import annotations

import math

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.numerics._doubledouble import two_prod, two_sum
from eulersym.validation import finite_array

__all__ = ["complete_elliptic_k", "jacobi_sncndn", "carlson_rf", "carlson_rj", "reduce_phase"]

#: Relative spread of Carlson's arguments below which the series replaces the duplication (truncation ~ 1e-18).
_SPREAD = 1e-3


# ----------------------------------------------------------------------------------------------------------------
# The AGM (descending Landen) sequence and K
# ----------------------------------------------------------------------------------------------------------------
def _agm_landen(rootmc: float) -> tuple[tuple[float, ...], tuple[float, ...], float]:
    """AGM sequence a₀ = 1, b₀ = √m_c; returns (a's, b's, AGM). Requires 0 < √m_c ≤ 1.

    >>> _agm_landen(1.0)
    ((1.0,), (1.0,), 1.0)
    """
    a, b = 1.0, rootmc
    avals, bvals = [], []
    for _ in range(64):
        avals.append(a)
        bvals.append(b)
        if abs(a - b) <= 1e-9 * a:
            break
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return tuple(avals), tuple(bvals), 0.5 * (a + b)


def _agm_landen_columns(rootmc) -> tuple[list, list, np.ndarray]:
    """The AGM sequences of many members at once: a₀ = 1, b₀ = √m_c per member (``rootmc`` of shape (B,) or (B, 1)),
    one depth for all — the depth the slowest member needs, as :func:`_agm_landen` stops (|a − b| ≤ 1e-9 a), members
    whose √m_c is not finite ignored. Returns (a's, b's, AGM) as columns (B, 1), the arithmetic of
    :func:`_agm_landen` member by member (what the sweeps' closed forms hand to :func:`_sncndn`).

    >>> avals, bvals, agm = _agm_landen_columns(np.array([1.0, 0.5]))
    >>> len(avals), agm.shape, float(agm[1, 0]) == _agm_landen(0.5)[2]
    (5, (2, 1), True)
    """
    b = np.asarray(rootmc, dtype=np.float64).reshape(-1, 1)
    a = np.ones_like(b)
    ignored = ~np.isfinite(b)
    avals, bvals = [], []
    for _ in range(64):
        avals.append(a)
        bvals.append(b)
        if np.all((np.abs(a - b) <= 1e-9 * a) | ignored):
            break
        a, b = 0.5 * (a + b), np.sqrt(a * b)
    return avals, bvals, 0.5 * (a + b)


def complete_elliptic_k(mc: float) -> float:
    """Complete elliptic integral of the first kind K as a function of the complementary parameter m_c = 1 − m.

    ``K = π / (2 AGM(1, √m_c))``, accurate to a few ulp for every ``0 < m_c ≤ 1`` (``K → ∞`` as ``m_c → 0``).

    Parameters
    ----------
    mc : float
        Complementary parameter, ``0 < mc <= 1``.

    Raises
    ------
    eulersym.errors.InvalidInput
        ``mc`` outside (0, 1] or not a number.

    Examples
    --------
    >>> round(complete_elliptic_k(1.0), 15) == round(math.pi / 2, 15)
    True
    >>> import mpmath
    >>> with mpmath.workdps(30):
    ...     want = float(mpmath.ellipk(1 - mpmath.mpf(1e-16)))
    >>> abs(complete_elliptic_k(1e-16) - want) < 1e-14
    True
    """
    try:
        value = float(mc) if not isinstance(mc, (str, bytes)) else math.nan
    except (TypeError, ValueError):
        raise InvalidInput("mc", mc, "a complementary parameter 0 < mc <= 1") from None
    if not (0.0 < value <= 1.0):
        raise InvalidInput("mc", mc, "a complementary parameter 0 < mc <= 1")
    return math.pi / (2.0 * _agm_landen(math.sqrt(value))[2])


# ----------------------------------------------------------------------------------------------------------------
# Jacobi sn, cn, dn with the complementary parameter as input
# ----------------------------------------------------------------------------------------------------------------
def _sncndn_reduced(x: np.ndarray, avals, bvals, agm: float):
    """sn, cn, dn for 0 ≤ x ≤ K/2 by Bulirsch's descending Landen recurrence (x scaled by AGM ≤ π/4).

    The recurrence starts from ``cot v = 1/tan v`` (NumPy's tan is vectorised where its sin and cos are not: five
    times faster) and runs into a few temporaries; the Landen values may be arrays broadcasting against x."""
    v = x * agm
    tan = np.tan(v)
    zero = v < 1e-150  # sn x = x, cn x = dn x = 1 to within x² (and cot v would overflow)
    anyzero = bool(zero.any())
    if anyzero:
        tan = np.where(zero, 1.0, tan)
    a = np.divide(1.0, tan, out=tan)
    c = a * agm
    dn = None
    tmp = np.empty_like(c)
    for ai, bi in zip(reversed(avals), reversed(bvals)):
        a *= c
        if dn is not None:
            c *= dn
        else:
            dn = np.empty_like(c)
        np.add(a, bi, out=dn)
        np.add(a, ai, out=tmp)
        dn /= tmp
        np.divide(c, ai, out=a)
    if dn is None:
        dn = np.ones_like(c)
    np.multiply(c, c, out=tmp)
    tmp += 1.0
    np.sqrt(tmp, out=tmp)
    sn = np.divide(1.0, tmp, out=tmp)
    cn = c * sn
    if anyzero:
        sn, cn, dn = np.where(zero, x, sn), np.where(zero, 1.0, cn), np.where(zero, 1.0, dn)
    return sn, cn, dn


def jacobi_sncndn(u, mc, *, rootmc=None):
    """Jacobi elliptic functions ``sn(u|m), cn(u|m), dn(u|m)`` with the complementary parameter ``mc = 1 − m``.

    Accurate to a few ulp (absolute) for every ``0 ≤ mc ≤ 1`` including ``mc`` down to 1e-300 and ``mc = 0``
    (``tanh, sech, sech``), unlike routines that take m and so lose ``1 − m`` to rounding.

    Algorithm: reduce u modulo 4K (K from the AGM on √m_c) to x ∈ [0, K] with the symmetries
    ``sn(u + 2K) = −sn u``, ``cn(u + 2K) = −cn u``, ``sn(2K − x) = sn x``, ``cn(2K − x) = −cn x``; Bulirsch's
    descending Landen recurrence (Numerical Recipes' ``sncndn``) on [0, K/2]; and on (K/2, K] the reflection
    ``sn(K − y) = cn y / dn y``, ``cn(K − y) = √m_c sn y / dn y``, ``dn(K − y) = √m_c / dn y``.

    Parameters
    ----------
    u : array_like
        Arguments.
    mc : float
        Complementary parameter ``0 <= mc <= 1``.
    rootmc : float, optional
        ``√m_c`` when known more precisely than ``mc`` itself (m_c below the smallest double, ~1e-308).

    Returns
    -------
    sn, cn, dn : ndarray
        Same shape as ``u``.

    Raises
    ------
    eulersym.errors.InvalidInput
        ``mc`` outside [0, 1], non-finite ``u``.

    Examples
    --------
    >>> import mpmath
    >>> sn, cn, dn = jacobi_sncndn([0.5, 30.0], 1e-12)
    >>> with mpmath.workdps(30):
    ...     want = float(mpmath.ellipfun("sn", 30, 1 - mpmath.mpf(1e-12)))
    >>> bool(abs(sn[1] - want) < 1e-14)
    True
    >>> [float(v) for v in jacobi_sncndn(0.0, 0.3)]
    [0.0, 1.0, 1.0]
    """
    u = np.asarray(u, dtype=np.float64)
    mc = float(mc)
    if not (0.0 <= mc <= 1.0) or not math.isfinite(mc):
        raise InvalidInput("mc", mc, "a complementary parameter 0 <= mc <= 1")
    if not np.all(np.isfinite(u)):
        raise InvalidInput("u", u, "finite arguments")
    rootmc = math.sqrt(mc) if rootmc is None else float(rootmc)
    if rootmc == 0.0:
        return np.tanh(u), 1.0 / np.cosh(u), 1.0 / np.cosh(u)
    shape = u.shape
    sn, cn, dn = _sncndn(u.ravel(), rootmc, _agm_landen(rootmc))
    return sn.reshape(shape), cn.reshape(shape), dn.reshape(shape)


def _sncndn_quarter(x: np.ndarray, K, rootmc, landen):
    """sn, cn, dn for 0 ≤ x ≤ K: Landen on [0, K/2], the quarter-period reflection above."""
    near = x > 0.5 * K
    z = np.where(near, K - x, x)
    z = np.maximum(z, 0.0)
    sz, cz, dz = _sncndn_reduced(z, *landen)
    sn = np.where(near, cz / dz, sz)
    cn = np.where(near, rootmc * sz / dz, cz)
    dn = np.where(near, rootmc / dz, dz)
    return sn, cn, dn


def _sncndn(u: np.ndarray, rootmc: float, landen):
    """sn, cn, dn of a float array (checked by the caller), ``0 < √m_c ≤ 1``, Landen sequence given; ``rootmc`` and
    the sequence may be arrays broadcasting against ``u`` (one modulus per member of a batch)."""
    K = math.pi / (2.0 * landen[2])
    r = np.mod(np.abs(u), 4.0 * K)  # sn is odd, cn and dn even: reduce |u| so small arguments stay exact
    upper = r >= 2.0 * K
    r = np.where(upper, r - 2.0 * K, r)
    sign = np.where(upper, -1.0, 1.0)
    sign_sn = np.where(u < 0, -sign, sign)
    back = r > K
    x = np.where(back, 2.0 * K - r, r)
    sign_cn = np.where(back, -sign, sign)
    sn, cn, dn = _sncndn_quarter(x, K, rootmc, landen)
    return sign_sn * sn, sign_cn * cn, dn


def _sncndn_within(u: np.ndarray, rootmc, landen):
    """:func:`_sncndn` of arguments already within |u| < 2K (a phase the caller reduced), bit for bit, without its
    reduction modulo 4K (``np.mod``: the dearest of its passes): there ``|u| mod 4K = |u|`` exactly and the upper
    half-period never applies, so the signs are those of u (sn) and of the reflection past K (cn)."""
    K = math.pi / (2.0 * landen[2])
    r = np.abs(u)
    back = r > K
    x = np.where(back, 2.0 * K - r, r)
    sn, cn, dn = _sncndn_quarter(x, K, rootmc, landen)
    np.negative(sn, out=sn, where=u < 0)  # −1 · sn, as _sncndn's sign
    np.negative(cn, out=cn, where=back)
    return sn, cn, dn


def _sncndn_half(r: np.ndarray, K: float, rootmc: float, landen):
    """sn, cn, dn of a phase already reduced to |r| ≤ K (no reduction modulo 4K: Landen on [0, K/2], the
    quarter-period reflection above), as new arrays."""
    x = np.abs(r)
    np.minimum(x, K, out=x)
    near = x > 0.5 * K
    z = np.where(near, K - x, x)
    sz, cz, dz = _sncndn_reduced(z, *landen)
    sn = np.where(near, cz / dz, sz)
    np.copysign(sn, r, out=sn)
    cn = np.where(near, (rootmc * sz) / dz, cz)
    dn = np.where(near, rootmc / dz, dz)
    return sn, cn, dn


def _sncndn_scalar(u: float, rootmc: float, landen):
    """:func:`_sncndn` for one float, in ``math`` (the same steps; for a handful of points NumPy's per-call
    overhead would dominate)."""
    avals, bvals, agm = landen
    K = math.pi / (2.0 * agm)
    r = math.fmod(abs(u), 4.0 * K)
    sign = 1.0
    if r >= 2.0 * K:
        r -= 2.0 * K
        sign = -1.0
    sign_sn = -sign if u < 0 else sign
    sign_cn = sign
    if r > K:
        r = 2.0 * K - r
        sign_cn = -sign
    near = r > 0.5 * K
    z = max(K - r, 0.0) if near else r
    v = z * agm
    if v < 1e-150:
        sz, cz, dz = z, 1.0, 1.0
    else:
        a = math.cos(v) / math.sin(v)
        c = agm * a
        dz = 1.0
        for ai, bi in zip(reversed(avals), reversed(bvals)):
            a = a * c
            c = c * dz
            dz = (bi + a) / (ai + a)
            a = c / ai
        sz = 1.0 / math.sqrt(c * c + 1.0)
        cz = c * sz
    if near:
        return sign_sn * cz / dz, sign_cn * rootmc * sz / dz, rootmc / dz
    return sign_sn * sz, sign_cn * cz, dz


# ----------------------------------------------------------------------------------------------------------------
# Carlson's symmetric integrals
# ----------------------------------------------------------------------------------------------------------------
#: Up to this many points the integrals are evaluated point by point in ``math``: NumPy's per-call overhead (~40
#: array operations a duplication step, ~8 steps) costs what ~16 points do in ``math`` (~9 µs a point for R_F + R_J).
_FEW = 16


def _carlson_rf(x: float, y: float, z: float) -> float:
    """``R_F`` of one point in ``math`` (the steps of :func:`_rf`)."""
    for _ in range(200):
        mu = (x + y + z) / 3.0
        dx, dy, dz = 1.0 - x / mu, 1.0 - y / mu, 1.0 - z / mu
        if max(abs(dx), abs(dy), abs(dz)) < _SPREAD:
            break
        sx, sy, sz = math.sqrt(x), math.sqrt(y), math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        x, y, z = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam)
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    return (1.0 + (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) * e2 + e3 / 14.0) / math.sqrt(mu)


def _carlson_rj(x: float, y: float, z: float, p: float) -> float:
    """``R_J`` of one point in ``math`` (the steps of :func:`_rj`)."""
    delta = (p - x) * (p - y) * (p - z)
    total, scale = 0.0, 1.0
    for _ in range(200):
        mu = (x + y + z + 2.0 * p) / 5.0
        dx, dy, dz = 1.0 - x / mu, 1.0 - y / mu, 1.0 - z / mu
        if max(abs(dx), abs(dy), abs(dz), abs(1.0 - p / mu)) < _SPREAD:
            break
        sx, sy, sz, sp = math.sqrt(x), math.sqrt(y), math.sqrt(z), math.sqrt(p)
        lam = sx * (sy + sz) + sy * sz
        d = (sp + sx) * (sp + sy) * (sp + sz)
        e = delta / (d * d)
        if e > 0.0:
            root = math.sqrt(e)
            rc = math.atan(root) / root
        elif e < 0.0:
            root = math.sqrt(-e)
            rc = math.log1p(root * (1.0 + root) * d / (sp * (p + lam))) / (2.0 * root)  # 1 + e = 2√p (p + λ)/d
        else:
            rc = 1.0
        total += (scale / d) * rc
        x, y, z, p = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam), 0.25 * (p + lam)
        delta *= 1.0 / 64.0
        scale *= 0.25
    return scale * _rj_series(dx, dy, dz) / (mu * math.sqrt(mu)) + 6.0 * total


def _rj_series(dx, dy, dz):
    """The series of DLMF 19.36.2 through degree 5 in the spread (X, Y, Z; P = −(X + Y + Z)/2)."""
    P = -0.5 * (dx + dy + dz)
    xyz = dx * dy * dz
    P2 = P * P
    e2 = dx * dy + dx * dz + dy * dz - 3.0 * P2
    e3 = xyz + 2.0 * e2 * P + 4.0 * P2 * P
    e4 = (2.0 * xyz + e2 * P + 3.0 * P2 * P) * P
    e5 = xyz * P2
    return (1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0 - 3.0 * e4 / 22.0 - 9.0 * e2 * e3 / 52.0
            + 3.0 * e5 / 26.0)


def _largest(spread) -> float:
    """The largest spread, NaN ignored (a point outside the domain does not hold the others' iteration)."""
    return float(np.fmax.reduce(spread, axis=None, initial=0.0))


def _pointwise(fn, arrays):
    """``fn`` of the scalar loops at each point of the broadcast arrays (a handful of points); a point outside the
    domain is NaN, as the array loops leave it."""
    out = np.empty(arrays[0].shape)
    flat = out.reshape(-1)
    for k, values in enumerate(zip(*(a.reshape(-1).tolist() for a in arrays))):
        try:
            flat[k] = fn(*values)
        except (ValueError, ZeroDivisionError, OverflowError):
            flat[k] = math.nan
    return out


def _duplicate(x, y, z, p=None):
    """``(R_F(x, y, z), R_J(x, y, z, p))`` of broadcast float arrays by one Carlson duplication (λ depends on x, y, z
    alone, so both integrals ride on one loop; R_J is None without p). Each step divides every deviation from a mean
    by exactly 4, so each integral's spread is followed from its first deviations; the loop runs until both are below
    :data:`_SPREAD`. ``δ_m = (p − x)(p − y)(p − z)`` keeps its sign, so which form of ``R_C(1, 1 + e_m)`` a point
    takes is known from the start (:func:`_rc_terms`)."""
    mu_f = (x + y + z) / 3.0
    spread_f = np.maximum(np.maximum(np.abs(x - mu_f), np.abs(y - mu_f)), np.abs(z - mu_f))
    if p is not None:
        delta = (p - x) * (p - y) * (p - z)
        above, below = delta > 0.0, delta < 0.0  # e_m > 0: the atan form; e_m < 0: the log form; e_m = 0: 1
        forms = (above, below, bool(above.any()), bool(below.any()))
        mu_j = (x + y + z + 2.0 * p) / 5.0
        spread_j = np.maximum(np.maximum(np.abs(x - mu_j), np.abs(y - mu_j)),
                              np.maximum(np.abs(z - mu_j), np.abs(p - mu_j)))
    total = 0.0
    scale = 1.0  # 4⁻ᵐ
    for _ in range(200):
        widest = _largest(spread_f / mu_f) if p is None else max(_largest(spread_f / mu_f), _largest(spread_j / mu_j))
        if not scale * widest >= _SPREAD:
            break
        sx, sy, sz = np.sqrt(x), np.sqrt(y), np.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        x, y, z = x + lam, y + lam, z + lam
        if p is not None:
            sp = np.sqrt(p)
            d = (sp + sx) * (sp + sy) * (sp + sz)
            total = total + _rc_terms(delta / (d * d), d, sp, p, lam, *forms) * (scale / d)
            p = p + lam
            p *= 0.25
            delta *= 1.0 / 64.0
        x *= 0.25
        y *= 0.25
        z *= 0.25
        mu_f = (x + y + z) / 3.0
        if p is not None:
            mu_j = (x + y + z + 2.0 * p) / 5.0
        scale *= 0.25
    dx, dy, dz = 1.0 - x / mu_f, 1.0 - y / mu_f, 1.0 - z / mu_f
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    rf = (1.0 + (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) * e2 + e3 / 14.0) / np.sqrt(mu_f)
    if p is None:
        return rf, None
    rj = scale * _rj_series(1.0 - x / mu_j, 1.0 - y / mu_j, 1.0 - z / mu_j) / (mu_j * np.sqrt(mu_j)) + 6.0 * total
    return rf, rj


def _rc_terms(e, d, sp, p, lam, above, below, some_above, some_below):
    """``R_C(1, 1 + e)`` of one duplication step: ``atan(√e)/√e`` where δ > 0, ``½ log1p(2s(1 + s)/(1 + e))/s``
    (s = √−e) where δ < 0 with ``1 + e = (d² + δ)/d² = 2√p (p + λ)/d`` (no cancellation as e → −1), 1 where δ = 0;
    the masks (the sign of δ never changes) say which forms are needed."""
    if some_above and above.all():
        root = np.sqrt(e)
        return np.arctan(root) / root
    if some_below and below.all():
        root = np.sqrt(-e)
        return np.log1p(root * (1.0 + root) * d / (sp * (p + lam))) / (2.0 * root)
    root = np.sqrt(np.abs(e))  # both forms, or points of e = 0
    safe = np.where(root == 0.0, 1.0, root)
    rc = np.where(above, np.arctan(safe) / safe, 1.0)
    if some_below:
        rc = np.where(below, np.log1p(safe * (1.0 + safe) * d / (sp * (p + lam))) / (2.0 * safe), rc)
    return rc


def _arrays(*values):
    """The values as float arrays broadcast together."""
    return np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in values))


def _rf(x, y, z):
    """``R_F`` of arrays that broadcast (non-negative, at most one zero per point; unchecked): the duplication until
    every point's spread is below :data:`_SPREAD`, then the fifth-order series (DLMF 19.36.1); up to :data:`_FEW`
    points one by one in ``math``."""
    x, y, z = _arrays(x, y, z)
    return _pointwise(_carlson_rf, (x, y, z)) if x.size <= _FEW else _duplicate(x, y, z)[0]


def _rj(x, y, z, p):
    """``R_J`` of arrays that broadcast (x, y, z ≥ 0 with at most one zero, p > 0; unchecked): Carlson's duplication
    with the R_C terms (see the module docstring), then the series of DLMF 19.36.2 through degree 5; up to
    :data:`_FEW` points one by one in ``math``."""
    x, y, z, p = _arrays(x, y, z, p)
    return _pointwise(_carlson_rj, (x, y, z, p)) if x.size <= _FEW else _duplicate(x, y, z, p)[1]


def _carlson_arguments(names, values, *, positive_last=False):
    """The arguments as float arrays that broadcast: finite, non-negative, at most one zero per point among the
    first three (and the last positive when ``positive_last``), or InvalidInput naming the first bad one."""
    arrays = []
    for name, value in zip(names, values):
        arr = finite_array(name, value)
        if np.any(arr < 0.0):
            raise InvalidInput(name, value, "non-negative numbers")
        arrays.append(arr)
    try:
        arrays = np.broadcast_arrays(*arrays)
    except ValueError:
        raise InvalidInput(names[0], values[0], "arrays whose shapes broadcast together, got shapes "
                           + ", ".join(str(np.shape(v)) for v in values)) from None
    zeros = sum((a == 0.0).astype(int) for a in arrays[:3])
    if np.any(zeros > 1):
        raise InvalidInput(", ".join(names[:3]), tuple(values[:3]), "at most one of x, y, z zero at each point "
                           "(the integral diverges)")
    if positive_last and np.any(arrays[-1] == 0.0):
        raise InvalidInput(names[-1], values[-1], "p > 0 (the integral diverges at p = 0)")
    return arrays


def carlson_rf(x, y, z):
    """Carlson's symmetric elliptic integral of the first kind, ``R_F(x, y, z) = ½ ∫₀^∞ dt/√((t + x)(t + y)(t + z))``.

    Duplication until the arguments' relative spread is below 10⁻³, then the fifth-order series (DLMF 19.36.1):
    a few ulp. ``K(m) = R_F(0, 1 − m, 1)``.

    Parameters
    ----------
    x, y, z : array_like
        Non-negative, at most one of them zero at each point; broadcast together.

    Returns
    -------
    ndarray (0-d for scalar input)

    Raises
    ------
    eulersym.errors.InvalidInput
        A negative or non-finite argument, two zeros at a point, shapes that do not broadcast.

    Examples
    --------
    >>> float(carlson_rf(1.0, 1.0, 1.0))            # R_F(x, x, x) = 1/√x
    1.0
    >>> bool(abs(carlson_rf(0.0, 1.0, 1.0) - math.pi / 2) < 1e-15)   # K(0) = π/2
    True
    """
    return _rf(*_carlson_arguments(("x", "y", "z"), (x, y, z)))


def carlson_rj(x, y, z, p):
    """Carlson's symmetric elliptic integral of the third kind,
    ``R_J(x, y, z, p) = (3/2) ∫₀^∞ dt / ((t + p) √((t + x)(t + y)(t + z)))``.

    Carlson's duplication with its ``R_C`` terms, ``1 + e_m`` formed without cancellation where ``e_m < 0`` (p small
    against x, y, z: a characteristic near 1), then the series of DLMF 19.36.2 through degree 5: a few ulp.

    Parameters
    ----------
    x, y, z : array_like
        Non-negative, at most one of them zero at each point.
    p : array_like
        Positive.

    Returns
    -------
    ndarray (0-d for scalar input)

    Raises
    ------
    eulersym.errors.InvalidInput
        A negative or non-finite argument, two zeros among x, y, z, ``p = 0``, shapes that do not broadcast.

    Examples
    --------
    >>> abs(float(carlson_rj(2.0, 2.0, 2.0, 2.0)) - 2.0 ** -1.5) < 1e-16   # R_J(x, x, x, x) = x^(−3/2)
    True
    >>> import mpmath
    >>> bool(abs(carlson_rj(0.0, 0.5, 1.0, 1e-12) - float(mpmath.elliprj(0, 0.5, 1, 1e-12))) < 1e-9)
    True
    """
    return _rj(*_carlson_arguments(("x", "y", "z", "p"), (x, y, z, p), positive_last=True))


def _third_kind(s, c2, d2, n, p):
    """``∫₀ˣ dy/(1 − n sn² y) = s R_F(c², d², 1) + (n/3) s³ R_J(c², d², 1, p)`` for 0 ≤ x ≤ K from ``s = sn x ≥ 0``,
    ``c2 = cn² x``, ``d2 = dn² x`` and ``p = 1 − n s²`` (formed by the caller as ``(1 − n) + n c²`` where that keeps
    the digits); ``n`` a number or an array (a term whose n is 0 adds 0; a scalar 0 needs no R_J). R_F and R_J share
    one duplication (:func:`_duplicate`); up to :data:`_FEW` points one by one in ``math``."""
    if np.ndim(n) == 0 and n == 0.0:
        return s * _rf(c2, d2, 1.0)
    x, y, z, p, _ = _arrays(c2, d2, 1.0, p, n)
    if x.size <= _FEW:
        rf, rj = _pointwise(_carlson_rf, (x, y, z)), _pointwise(_carlson_rj, (x, y, z, p))
    else:
        rf, rj = _duplicate(x, y, z, p)
    return s * rf + (n / 3.0) * s * s * s * rj


# ----------------------------------------------------------------------------------------------------------------
# Phases reduced modulo a period in double-double
# ----------------------------------------------------------------------------------------------------------------
def reduce_phase(t, rate, start, period):
    """The phase ``u = rate·t + start`` reduced modulo ``period``: ``u = j·period + r``, ``|r| ≤ period/2`` (to
    the rounding of r: the quotient that picks j is rounded, and a j one off is corrected by one more period;
    while ``u/period`` is below 2⁵², beyond which j itself is not a whole number of periods).

    ``rate``, ``start`` and ``period`` are double-doubles ``(hi, lo)`` (:mod:`eulersym.numerics._doubledouble`) and
    the product, the sum and the reduction are carried out in double-double, so r keeps ~ulp(period) absolute
    accuracy however many periods u spans (rounding ``rate·t`` in double would cost ``ε·u``). An infinite period
    (a separatrix: no reduction) returns ``(u, 0)``.

    Parameters
    ----------
    t : array_like
        Times.
    rate, start, period : tuple of two floats
        Double-doubles.

    Returns
    -------
    r, j : ndarray
        The reduced phase and the number of whole periods (as floats).

    Examples
    --------
    >>> r, j = reduce_phase([1e12], (math.pi, 1.2246467991473532e-16), (0.0, 0.0), (2 * math.pi, 2.4492935982947064e-16))
    >>> float(j[0]), bool(abs(r[0]) < 1e-3)        # π·10¹² is a whole number of half turns: r ≈ 0
    (500000000000.0, True)
    """
    t = np.asarray(t, dtype=np.float64)
    p_hi, p_lo = two_prod(rate[0], t)
    p_lo = p_lo + rate[1] * t
    u_hi, u_err = two_sum(p_hi, start[0])
    u_lo = u_err + p_lo + start[1]
    if math.isinf(period[0]):
        return u_hi + u_lo, np.zeros_like(t)
    j = np.round((u_hi + u_lo) / period[0])
    e_hi, e_lo = two_prod(j, period[0])
    r = ((u_hi - e_hi) - e_lo) + (u_lo - j * period[1])
    # the quotient's rounding (ε·u/period periods) may pick the neighbouring j: one more period brings r back
    # (while j is an exact integer: beyond 2⁵², u/period has no unit digit left to correct)
    step = np.where(r > 0.5 * period[0], 1.0, np.where(r < -0.5 * period[0], -1.0, 0.0))
    step = np.where(np.abs(j) < 2.0 ** 52, step, 0.0)
    if step.any():
        r = (r - step * period[0]) - step * period[1]
        j = j + step
    return r, j


def _reduce_phase_scalar(t: float, rate, start, period):
    """:func:`reduce_phase` of one float t (finite period), in floats: ``(r, j)``."""
    p_hi, p_lo = two_prod(rate[0], t)
    p_lo = p_lo + rate[1] * t
    u_hi, u_err = two_sum(p_hi, start[0])
    u_lo = u_err + p_lo + start[1]
    j = float(round((u_hi + u_lo) / period[0]))
    e_hi, e_lo = two_prod(j, period[0])
    r = ((u_hi - e_hi) - e_lo) + (u_lo - j * period[1])
    if abs(r) > 0.5 * period[0] and abs(j) < 2.0 ** 52:  # the quotient rounded to the neighbouring j
        step = math.copysign(1.0, r)
        r, j = (r - step * period[0]) - step * period[1], j + step
    return r, j


def _reduce_secular(rate, t, per, j, modulus):
    """``rate·t + per·j`` reduced modulo ``modulus`` (all constants double-double (hi, lo)), as a double: the
    secular angles of the heavy top, carried in double-double so they do not lose digits with t."""
    p_hi, p_lo = two_prod(rate[0], t)
    p_lo = p_lo + rate[1] * t
    q_hi, q_lo = two_prod(per[0], j)
    q_lo = q_lo + per[1] * j
    s_hi, s_lo = two_sum(p_hi, q_hi)
    s_lo = s_lo + p_lo + q_lo
    k = np.round((s_hi + s_lo) / modulus[0])
    e_hi, e_lo = two_prod(k, modulus[0])
    return ((s_hi - e_hi) - e_lo) + (s_lo - k * modulus[1])
