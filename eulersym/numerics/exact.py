"""The exact torque-free motion of a rigid body: ω(t) and the attitude from Jacobi elliptic functions.

Conventions
-----------
* ``I = (I1, I2, I3)`` are principal moments in any order; ``omega`` is the angular velocity in body components.
  Euler's equations: ``I1 ω̇1 = (I2 − I3) ω2 ω3`` and cyclic.
* The attitude is a unit quaternion ``q = (q0, q1, q2, q3)`` (scalar first) whose active rotation maps body
  components to space components, ``v_space = R(q) v_body``; its kinematics is ``q̇ = ½ q ⊗ (0, ω_body)``.

The method (Jacobi 1849; Landau–Lifshitz §37; Celledoni, Fassò, Säfström, Zanna 2008)
---------------------------------------------------------------------------------------
With 2E = Σ Iᵢωᵢ², L² = Σ Iᵢ²ωᵢ² and Dₖ = L² − 2E·Iₖ = Σᵢ Iᵢ(Iᵢ − Iₖ)ωᵢ², the body circulates around the axis c
of the largest moment when D_mid ≥ 0 and of the smallest when D_mid < 0; b is the intermediate axis and a the
remaining one. In that (a, b, c) frame (a signed permutation of the body axes that is a proper rotation)::

    ωa = A cn(u | m),   ωb = B sn(u | m),   ωc = C dn(u | m),   u = λ t + u0,
    A² = −Dc / (Ia (Ic − Ia)),  B² = −Dc / (Ib (Ic − Ib)),  C² = Da / (Ic (Ic − Ia)),
    λ² = (Ic − Ib) Da / (Ia Ib Ic),
    m  = (Ib − Ia)(−Dc) / ((Ic − Ib) Da),   m_c = 1 − m = (Ic − Ia) Db / ((Ic − Ib) Da).

Every D and every ratio is computed exactly in integer arithmetic (the binary floats given, over power-of-two
denominators), then rounded once, so ``m_c`` has full relative accuracy however close the start is to the
separatrix (``m_c`` is never formed as ``1 − m``). The phase ``u = λ t + u0`` is reduced modulo the period 4K in
double-double arithmetic, with λ and 4K = 2π / AGM(1, √m_c) as double-doubles (:mod:`._doubledouble`), so the
error does not grow with the number of periods; no mpmath, no ``Fraction``. ``sn, cn, dn`` are evaluated by
:func:`jacobi_sncndn`, which takes ``m_c`` as its input, and uses Bulirsch's descending Landen (AGM) recurrence on
[0, K/2] and the exact quarter-period reflection (``sn(K − y) = cd y`` …) on [K/2, K], in blocks of a few
thousand points (flat cost per point). The phase ``u0`` comes from Carlson's ``R_F`` in double precision: directly
(``u0 = sn0 · R_F(cn0², dn0², 1)``) below K/2, and as ``K − y``, ``y = cn0 · R_F(m_c sn0², m_c, dn0²) = O(1)``,
above it, so a start near the separatrix (u0 ≈ K ≫ 1) keeps an absolute accuracy of ~ulp(1). On the separatrix
(m_c = 0) the closed forms ``sn = tanh``, ``cn = dn = sech`` are used; a symmetric body (two equal moments)
and a spherical one use trigonometric / constant forms.

Attitude: Euler angles (φ, θ, ψ) of the (a, b, c) frame relative to the invariable frame whose ẑ is L give
``(sin θ sin ψ, sin θ cos ψ, cos θ) = (Ia ωa, Ib ωb, Ic ωc) / |L|`` and::

    φ̇ = |L| / Ic + |L| (Ic − Ia) / (Ia Ic) · 1 / (1 + n sn²u),   n = Ic (Ib − Ia) / (Ia (Ic − Ib)),

whose integral is an elliptic integral of the third kind, evaluated in closed form with Carlson's ``R_F`` and
``R_J`` (``scipy.special.elliprf``/``elliprj``) plus its quasi-periodicity over half-periods 2K. Only the
*product* of the three rotations is used, as a quaternion, so nothing is singular at θ = 0. The space attitude
is ``q(t) = q_fix ⊗ q_inv(t) ⊗ q_perm``, where ``q_fix`` is fixed by ``q(0) = q0``; hence the space direction of L
is constant to round-off for all t.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from eulersym import quaternion as _quaternion
from eulersym.numerics import _doubledouble as _dd
from eulersym.errors import InvalidInput
from eulersym.validation import finite_array, moments

__all__ = [
    "free_rigid_body_exact",
    "free_rigid_body_attitude_exact",
    "jacobi_sncndn",
    "complete_elliptic_k",
    "quaternion_multiply",
]


# ----------------------------------------------------------------------------------------------------------------
# Jacobi elliptic functions with the complementary parameter as input
# ----------------------------------------------------------------------------------------------------------------
def _agm_landen(rootmc: float) -> tuple[tuple[float, ...], tuple[float, ...], float]:
    """AGM sequence a₀ = 1, b₀ = √m_c; returns (a's, b's, AGM). Requires 0 < √m_c ≤ 1."""
    a, b = 1.0, rootmc
    avals, bvals = [], []
    for _ in range(64):
        avals.append(a)
        bvals.append(b)
        if abs(a - b) <= 1e-9 * a:
            break
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return tuple(avals), tuple(bvals), 0.5 * (a + b)


def complete_elliptic_k(mc: float) -> float:
    """Complete elliptic integral of the first kind K as a function of the complementary parameter m_c = 1 − m.

    ``K = π / (2 AGM(1, √m_c))``, accurate to a few ulp for every ``0 < m_c ≤ 1`` (``K → ∞`` as ``m_c → 0``).

    Parameters
    ----------
    mc : float
        Complementary parameter, ``0 < mc <= 1``.

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
    mc = float(mc)
    if not (0.0 < mc <= 1.0):
        raise InvalidInput("mc", mc, "a complementary parameter 0 < mc <= 1")
    return math.pi / (2.0 * _agm_landen(math.sqrt(mc))[2])


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


def _sncndn(u: np.ndarray, rootmc: float, landen):
    """sn, cn, dn of a float array (checked by the caller), ``0 < √m_c ≤ 1``, Landen sequence given; ``rootmc`` and
    the sequence may be arrays broadcasting against ``u`` (one modulus per member of a batch)."""
    avals, bvals, agm = landen
    K = math.pi / (2.0 * agm)
    r = np.mod(np.abs(u), 4.0 * K)  # sn is odd, cn and dn even: reduce |u| so small arguments stay exact
    upper = r >= 2.0 * K
    r = np.where(upper, r - 2.0 * K, r)
    sign = np.where(upper, -1.0, 1.0)
    sign_sn = np.where(u < 0, -sign, sign)
    back = r > K
    x = np.where(back, 2.0 * K - r, r)
    sign_cn = np.where(back, -sign, sign)
    near = x > 0.5 * K
    z = np.where(near, K - x, x)
    z = np.maximum(z, 0.0)
    sz, cz, dz = _sncndn_reduced(z, avals, bvals, agm)
    sn = np.where(near, cz / dz, sz)
    cn = np.where(near, rootmc * sz / dz, cz)
    dn = np.where(near, rootmc / dz, dz)
    return sign_sn * sn, sign_cn * cn, dn


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
# Quaternions (scalar first)
# ----------------------------------------------------------------------------------------------------------------
def quaternion_multiply(p, q):
    """Hamilton product ``p ⊗ q`` of quaternions (scalar first), broadcasting over leading axes
    (:func:`eulersym.quaternion.multiply`).

    Examples
    --------
    >>> quaternion_multiply([0, 1, 0, 0], [0, 0, 1, 0])   # i j = k
    array([0., 0., 0., 1.])
    """
    return _quaternion.multiply(p, q)


_quat_conj = _quaternion.conjugate


def _quat_exp(v):
    """Unit quaternion of the rotation vector ``v`` (rows), ``(cos |v|/2, sin(|v|/2) v/|v|)``."""
    v = np.asarray(v, dtype=np.float64)
    angle = np.sqrt(np.sum(v * v, axis=-1))
    half = 0.5 * angle
    # sin(half)/angle, with its limit 1/2 at 0
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    factor = np.where(small, 0.5 - angle * angle / 48.0, np.sin(half) / safe)
    return np.concatenate([np.cos(half)[..., None], factor[..., None] * v], axis=-1)


def _rotate(q, v):
    """R(q) v for unit quaternion(s) q."""
    qv = np.concatenate([np.zeros(np.shape(v)[:-1] + (1,)), v], axis=-1)
    return quaternion_multiply(quaternion_multiply(q, qv), _quat_conj(q))[..., 1:]


# ----------------------------------------------------------------------------------------------------------------
# The solution's constants, computed once per initial condition (exact rational discriminants)
# ----------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Elliptic:
    idx: tuple[int, int, int]  # body indices of the (a, b, c) axes
    signs: tuple[float, float, float]  # ω_abc[k] = signs[k] * ω_body[idx[k]]
    moments: tuple[float, float, float]  # (Ia, Ib, Ic)
    amp: tuple[float, float, float]  # signed (A, B, C)
    lam: float
    u0: float
    lam_lo: float  # λ = lam + lam_lo and u0 = u0 + u0_lo and 4K = period + period_lo (double-double)
    u0_lo: float
    period: float
    period_lo: float
    mc: float
    rootmc: float  # √m_c, kept separately: m_c may underflow while √m_c does not
    K: float  # inf on the separatrix
    L: float
    n: float  # characteristic of the φ integral
    landen: tuple = ()  # (a's, b's, AGM) of the descending Landen sequence on √m_c (empty on the separatrix)


@dataclass(frozen=True)
class _Symmetric:
    axis: int  # body index of the symmetry axis (or 0 for a spherical body)
    rate: float  # Ω = (Is − I⊥)/I⊥ · ω_s: the transverse ω turns by +Ω t about the axis
    i_perp: float


@dataclass(frozen=True)
class _Constant:
    pass


def _carlson_rf(x: float, y: float, z: float) -> float:
    """Carlson's symmetric ``R_F(x, y, z)`` of non-negative doubles (at most one zero), to a few ulp.

    Duplication ``x ← (x + λ)/4`` with ``λ = √x√y + √y√z + √z√x`` until the spread is below 10⁻³, then the
    fifth-order series (Carlson 1995; DLMF 19.36.1): relative truncation error below 10⁻¹⁸.
    """
    for _ in range(200):
        mu = (x + y + z) / 3.0
        dx, dy, dz = 1.0 - x / mu, 1.0 - y / mu, 1.0 - z / mu
        if max(abs(dx), abs(dy), abs(dz)) < 1e-3:
            break
        sx, sy, sz = math.sqrt(x), math.sqrt(y), math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        x, y, z = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam)
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    return (1.0 + (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) * e2 + e3 / 14.0) / math.sqrt(mu)


def _integers(values) -> tuple[list[int], int]:
    """Doubles as integers over one common power-of-two denominator: ``values[k] = ints[k] / den`` exactly."""
    ratios = [float(v).as_integer_ratio() for v in values]
    den = max(q for _, q in ratios)
    return [p * (den // q) for p, q in ratios], den


def _setup(I: tuple[float, float, float], w: np.ndarray):
    """Classify the motion and compute its constants: exact integer arithmetic, each constant rounded once.

    The moments and ω are written as integers over power-of-two denominators, so every discriminant
    ``D_k = Σ Iᵢ(Iᵢ − I_k)ωᵢ²``, every ratio (m_c, A², λ², ...) and the initial phase's arguments are exact
    rationals rounded once (Python's ``int / int`` rounds correctly): no cancellation near the separatrix.
    λ, √m_c and the period 4K = 2π / AGM(1, √m_c) are double-doubles (:mod:`._doubledouble`); the initial phase
    u0 is K minus a phase of order one near the separatrix, so it too keeps ~ulp(1) absolute accuracy.
    """
    if I[0] == I[1] == I[2]:
        return _Symmetric(0, 0.0, I[0])
    for k in range(3):
        i, j = (k + 1) % 3, (k + 2) % 3
        if I[i] == I[j]:
            return _Symmetric(k, (I[k] - I[i]) / I[i] * w[k], I[i])
    wl = [float(x) for x in w]
    if sum(x != 0.0 for x in wl) <= 1:
        return _Constant()
    # I_k = nI[k] / qI and ω_k = nw[k] / qw exactly; D_k = disc(k) / (qI² qw²).
    nI, qI = _integers(I)
    nw, qw = _integers(wl)
    w2 = [x * x for x in nw]

    def disc(k):  # L² − 2E I_k (times qI² qw²), exactly
        return sum(nI[i] * (nI[i] - nI[k]) * w2[i] for i in range(3) if i != k)

    lo, mid, hi = sorted(range(3), key=lambda k: I[k])
    idx = (lo, mid, hi) if disc(mid) >= 0 else (hi, mid, lo)
    a, b, c = idx
    na, nb, nc = nI[a], nI[b], nI[c]
    Da, Db, Dc = disc(a), disc(b), disc(c)
    if Dc == 0 or Da == 0:  # steady rotation about a principal axis
        return _Constant()
    even = (idx[1] - idx[0]) % 3 == 1
    signs = (1.0, 1.0, 1.0) if even else (1.0, -1.0, 1.0)
    wa, wb, wc = (signs[k] * wl[idx[k]] for k in range(3))
    qw2 = qw * qw
    A2 = -Dc / (na * (nc - na) * qw2)
    B2 = -Dc / (nb * (nc - nb) * qw2)
    C2 = Da / (nc * (nc - na) * qw2)
    mc_num, mc_den = (nc - na) * Db, (nc - nb) * Da  # m_c = mc_num / mc_den
    if mc_den < 0:
        mc_num, mc_den = -mc_num, -mc_den
    sep = Db == 0
    sa = -1.0 if (sep and wa < 0) else 1.0
    A = sa * math.sqrt(A2)
    C = math.copysign(math.sqrt(C2), wc)
    B = math.copysign(math.sqrt(B2), (1.0 if nc > na else -1.0) * C * A)
    # initial phase: cn0² = xa / tot, sn0² = xb / tot, dn0² = cn0² + m_c sn0² (exact integers)
    xa = na * (nc - na) * nw[a] * nw[a]
    xb = nb * (nc - nb) * nw[b] * nw[b]
    tot = xa + xb
    cn0 = math.copysign(math.sqrt(xa / tot), wa * sa)
    sn0 = math.copysign(math.sqrt(xb / tot), wb * B)
    s = -1.0 if sn0 < 0 else 1.0
    lam_dd = _dd.sqrt_ratio((nc - nb) * Da, na * nb * nc * qw2)
    rootmc = _dd.sqrt_ratio(mc_num, mc_den)
    n = nc * (nb - na) / (na * (nc - nb))
    L = math.sqrt(sum(nI[i] * nI[i] * w2[i] for i in range(3)) / (qI * qI * qw2))
    if sep:  # x = artanh|sn0| = ln((1 + |sn0|)/|cn0|), accurate in absolute terms
        u0_dd = (s * math.log((1.0 + abs(sn0)) / abs(cn0)), 0.0)
        period_dd = (math.inf, 0.0)
        K = math.inf
    else:
        period_dd = _dd.div(_dd.PI, _dd.mul((0.5, 0.0), _dd.agm((1.0, 0.0), rootmc)))  # 4K = 2π / AGM
        K = 0.25 * period_dd[0]
        K_dd = (0.25 * period_dd[0], 0.25 * period_dd[1])
        dn_num = xa * mc_den + mc_num * xb  # dn0² = dn_num / (tot · mc_den)
        if (xb / tot) * (1.0 + rootmc[0]) >= 1.0:
            # x ≥ K/2: x = K − y, y = cn0 · R_F(m_c sn0², m_c, dn0²) = O(1) however close to the separatrix
            y = math.sqrt(xa * mc_den / dn_num) * _carlson_rf(mc_num * xb / dn_num, mc_num * tot / dn_num, 1.0)
            x = _dd.add(K_dd, (-y, 0.0))
        else:  # x ≤ K/2: x = sn0 · R_F(cn0², dn0², 1)
            x = (abs(sn0) * _carlson_rf(xa / tot, dn_num / (tot * mc_den), 1.0), 0.0)
        if cn0 < 0:  # the amplitude lies in (π/2, π): u = 2K − x
            x = _dd.add((2.0 * K_dd[0], 2.0 * K_dd[1]), (-x[0], -x[1]))
        u0_dd = (s * x[0], s * x[1])
    return _Elliptic(
        idx=idx,
        signs=signs,
        moments=(float(I[a]), float(I[b]), float(I[c])),
        amp=(A, B, C),
        lam=lam_dd[0],
        lam_lo=lam_dd[1],
        u0=u0_dd[0],
        u0_lo=u0_dd[1],
        period=period_dd[0],
        period_lo=period_dd[1],
        mc=mc_num / mc_den,
        rootmc=rootmc[0],
        K=K,
        L=L,
        n=n,
        landen=() if sep else _agm_landen(rootmc[0]),
    )


def _two_prod(a, b):
    """Dekker's error-free product: a·b = p + e exactly (no FMA needed)."""
    p = a * b
    ca = 134217729.0 * a
    ah = ca - (ca - a)
    al = a - ah
    cb = 134217729.0 * b
    bh = cb - (cb - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _phase(sol, t):
    """The reduced phase: u = λ t + u0 = j·4K + r with |r| ≤ 2K, in double-double arithmetic.

    Returns (r, j). The rounding of λ·t and of 4K would otherwise cost ~ε·u in r, i.e. grow with the number
    of periods.
    """
    p_hi, p_lo = _two_prod(sol.lam, t)
    p_lo = p_lo + sol.lam_lo * t
    u_hi = p_hi + sol.u0
    u_lo = ((sol.u0 - (u_hi - p_hi)) + (p_hi - (u_hi - (u_hi - p_hi)))) + p_lo + sol.u0_lo  # two-sum error
    if math.isinf(sol.period):
        return u_hi + u_lo, np.zeros_like(t)
    j = np.round((u_hi + u_lo) / sol.period)
    e_hi, e_lo = _two_prod(j, sol.period)
    r = ((u_hi - e_hi) - e_lo) + (u_lo - j * sol.period_lo)
    return r, j


def _phase_scalar(sol, t: float) -> float:
    """:func:`_phase`'s reduced phase r for one float t (finite period)."""
    p_hi, p_lo = _two_prod(sol.lam, t)
    p_lo = p_lo + sol.lam_lo * t
    u_hi = p_hi + sol.u0
    u_lo = ((sol.u0 - (u_hi - p_hi)) + (p_hi - (u_hi - (u_hi - p_hi)))) + p_lo + sol.u0_lo
    j = float(round((u_hi + u_lo) / sol.period))
    e_hi, e_lo = _two_prod(j, sol.period)
    return ((u_hi - e_hi) - e_lo) + (u_lo - j * sol.period_lo)


def _rescale(w, tt):
    """Map a huge or tiny ω0 to order one: Euler's equations are homogeneous, ω(t) = s·ω̂(s t) with ω̂(0) = ω0/s.

    ``s`` is a power of two, so the scaling is exact; it is 1 for |ω0| within 2^±64.
    """
    top = float(np.max(np.abs(w)))
    if top == 0.0 or 2.0**-64 <= top <= 2.0**64:
        return w, tt, 1.0
    scale = 2.0 ** math.frexp(top)[1]
    scaled_t = tt * scale
    if not np.all(np.isfinite(scaled_t)):
        raise InvalidInput("t", _times_summary(tt),
                           f"times with |omega0|·|t| inside the float range (|omega0| ≈ {top:.3g})")
    return w / scale, scaled_t, scale


def _times_summary(tt) -> str:
    return f"array of {tt.size} times up to {np.max(np.abs(tt)):.3g}"


def _validate(I, omega0, t, check_body):
    I = tuple(float(x) for x in moments("I", I, body=check_body))
    w = finite_array("omega0", omega0, shape=(3,))
    tt = finite_array("t", np.atleast_1d(np.asarray(t, dtype=np.float64)) if np.ndim(t) == 0 else t, shape=(None,))
    return I, w, tt


#: Points per block when evaluating ω: the temporaries of a block stay in cache, so the cost per point is flat.
_BLOCK = 4096
#: Up to this many points ω is evaluated point by point with ``math`` (NumPy's per-call overhead dominates).
_SMALL = 8


def _omega(sol, w, t):
    if isinstance(sol, _Constant):
        return np.broadcast_to(w, (t.size, 3)).copy()
    if isinstance(sol, _Symmetric):
        k = sol.axis
        i, j = (k + 1) % 3, (k + 2) % 3
        ang = sol.rate * t
        c, s = np.cos(ang), np.sin(ang)
        out = np.empty((t.size, 3))
        out[:, k] = w[k]
        out[:, i] = c * w[i] - s * w[j]
        out[:, j] = s * w[i] + c * w[j]
        return out
    A, B, C = sol.amp
    a, b, c = sol.idx
    sa, sb, sc = sol.signs[0] * A, sol.signs[1] * B, sol.signs[2] * C
    out = np.empty((t.size, 3))
    if t.size <= _SMALL and sol.landen:
        for k, tk in enumerate(t.tolist()):
            sn, cn, dn = _sncndn_scalar(_phase_scalar(sol, tk), sol.rootmc, sol.landen)
            out[k, a], out[k, b], out[k, c] = sa * cn, sb * sn, sc * dn
        return out
    for start in range(0, t.size, _BLOCK):
        block = slice(start, start + _BLOCK)
        r, _ = _phase(sol, t[block])
        if sol.landen:
            sn, cn, dn = _sncndn(r, sol.rootmc, sol.landen)
        else:  # the separatrix
            sn, cn = np.tanh(r), 1.0 / np.cosh(r)
            dn = cn
        np.multiply(cn, sa, out=out[block, a])
        np.multiply(sn, sb, out=out[block, b])
        np.multiply(dn, sc, out=out[block, c])
    return out


def free_rigid_body_exact(I, omega0, t, *, check_body=True):
    """Exact body angular velocity ω(t) of a torque-free rigid body, from Jacobi elliptic functions.

    Solves Euler's equations ``I1 ω̇1 = (I2 − I3) ω2 ω3`` (and cyclic) with ``ω(0) = omega0`` in closed form; see
    the module docstring for the formulas. Valid for any ordering of the moments, both regimes
    (L² < 2E·I_mid and L² > 2E·I_mid), the separatrix L² = 2E·I_mid (``tanh``/``sech``), symmetric bodies
    (a trigonometric rotation of the transverse components at Ω = (I_s − I⊥)/I⊥ · ω_s) and spherical ones
    (constant ω). The error is at round-off level relative to |L| (≈ 3e-15 against 40-digit mpmath over a
    random suite with |t| up to 10⁴ and ``m_c`` down to 1e-17), and does not grow with t.

    Parameters
    ----------
    I : sequence of 3 floats
        Principal moments (any order).
    omega0 : array_like, shape (3,)
        Body angular velocity at t = 0.
    t : array_like, shape (n,)
        Times (any order, negative allowed).
    check_body : bool, optional
        Require the triangle inequalities of a physical body (default). ``False`` accepts any positive moments,
        as in test problems such as Hairer–Wanner's EULR.

    Returns
    -------
    ndarray, shape (n, 3)
        ω(t) in body components.

    Raises
    ------
    eulersym.errors.InvalidInput
        Non-positive or non-physical moments, non-finite ``omega0`` or ``t``.

    Examples
    --------
    >>> import numpy as np
    >>> w = free_rigid_body_exact((1.0, 2.0, 3.0), (1.0, 0.5, 0.2), [0.0, 10.0])
    >>> w[0]
    array([1. , 0.5, 0.2])
    >>> I = np.array([1.0, 2.0, 3.0])
    >>> bool(abs(np.sum(I * w[1]**2) - np.sum(I * w[0]**2)) < 1e-14)   # energy is conserved
    True
    """
    I, w, tt = _validate(I, omega0, t, check_body)
    w, tt, scale = _rescale(w, tt)
    return scale * _omega(_setup(I, w), w, tt)


def _unit_quaternion(q0):
    q = finite_array("q0", q0, shape=(4,))
    norm = float(np.sqrt(np.sum(q * q)))
    if abs(norm - 1.0) > 1e-6:
        raise InvalidInput("q0", q0, "a unit quaternion (q0, q1, q2, q3), scalar first, |q| = 1")
    return q / norm


def _perm_quaternion(idx, signs):
    """Unit quaternion of the proper rotation P with (P v)[k] = signs[k] v[idx[k]] (body → abc)."""
    P = np.zeros((3, 3))
    for k in range(3):
        P[k, idx[k]] = signs[k]
    # P maps body components to abc components; as an active rotation R with v_abc = R v_body, R = P.
    tr = np.trace(P)
    if tr > -0.5:
        w = 0.5 * math.sqrt(1.0 + tr)
        return np.array([w, (P[2, 1] - P[1, 2]) / (4 * w), (P[0, 2] - P[2, 0]) / (4 * w), (P[1, 0] - P[0, 1]) / (4 * w)])
    k = int(np.argmax(np.diag(P)))
    i, j = (k + 1) % 3, (k + 2) % 3
    x = 0.5 * math.sqrt(1.0 + P[k, k] - P[i, i] - P[j, j])
    q = np.zeros(4)
    q[1 + k] = x
    q[0] = (P[j, i] - P[i, j]) / (4 * x)
    q[1 + i] = (P[i, k] + P[k, i]) / (4 * x)
    q[1 + j] = (P[j, k] + P[k, j]) / (4 * x)
    return q


def _phi_integral(sol, r, j):
    """W(u) = ∫₀ᵘ ds / (1 + n sn² s) at u = j·4K + r, via Carlson R_F, R_J and quasi-periodicity over 2K."""
    n = sol.n
    rn = math.sqrt(n)

    def hyperbolic(x):  # the m = 1 limit, exact on the separatrix
        return (x + rn * np.arctan(rn * np.tanh(x))) / (1.0 + n)

    if math.isinf(sol.K):
        return hyperbolic(r)
    K, mc = sol.K, sol.mc
    k = np.round(r / (2.0 * K))
    r = r - 2.0 * K * k  # [-K, K]
    j = 2.0 * j + k  # half periods
    from scipy.special import elliprf, elliprj  # the attitude only (ω needs no SciPy)

    if mc < 1e-280:  # m_c below double range: the m = 1 limit over each half period, error O(√m_c)
        return 2.0 * j * hyperbolic(K) + hyperbolic(r)
    s, c, _ = jacobi_sncndn(np.abs(r), mc)
    c = np.abs(c)
    c2 = c * c
    d2 = c2 + mc * s * s
    s2 = s * s
    part = s * elliprf(c2, d2, 1.0) - (n / 3.0) * s * s2 * elliprj(c2, d2, 1.0, 1.0 + n * s2)
    whole = float(elliprf(0.0, mc, 1.0) - (n / 3.0) * elliprj(0.0, mc, 1.0, 1.0 + n))
    return 2.0 * j * whole + np.sign(r) * part


def _invariable_quaternion(sol, t):
    """q_inv(t): active rotation (a, b, c) frame → invariable frame (ẑ ∥ L), and ω_abc."""
    r, j = _phase(sol, t)
    sn, cn, dn = jacobi_sncndn(r, sol.mc, rootmc=sol.rootmc)
    A, B, C = sol.amp
    Ia, Ib, Ic = sol.moments
    L = sol.L
    la, lb, lc = Ia * A * cn / L, Ib * B * sn / L, Ic * C * dn / L
    stheta = np.hypot(la, lb)
    # ψ' = π/2 − ψ = atan2(l_b, l_a), continuous in u, unwrapped over periods 4K of u
    sa = 1.0 if A > 0 else -1.0
    psi_p = np.arctan2(sa * Ib * B * sn, Ia * abs(A) * cn) + (0.0 if A > 0 else math.pi)
    # ψ = π/2 − ψ' − 2π·sign(B)·j is continuous; qz(ψ) = (−1)^j qz(π/2 − ψ'), so keep ψ small (accurate)
    flip = np.where(np.mod(j, 2.0) == 0.0, 1.0, -1.0)
    psi = 0.5 * math.pi - psi_p
    r0, j0 = _phase(sol, np.zeros(1))
    W = _phi_integral(sol, r, j) - _phi_integral(sol, r0, j0)[0]
    phi = (L / Ic) * t + (L * (Ic - Ia) / (Ia * Ic * sol.lam)) * W
    # half angles of θ without cancellation
    half_c = np.sqrt(np.maximum(0.5 * (1.0 + lc), 0.0))
    half_s = np.sqrt(np.maximum(0.5 * (1.0 - lc), 0.0))
    pos = lc >= 0
    half_s = np.where(pos, stheta / (2.0 * np.where(half_c > 0, half_c, 1.0)), half_s)
    half_c = np.where(pos, half_c, stheta / (2.0 * np.where(half_s > 0, half_s, 1.0)))
    cp, sp = flip * np.cos(0.5 * psi), flip * np.sin(0.5 * psi)
    inner = np.stack([half_c * cp, half_s * cp, -half_s * sp, half_c * sp], axis=-1)  # qx(θ) ⊗ qz(ψ)
    zero = np.zeros_like(phi)
    outer = np.stack([np.cos(0.5 * phi), zero, zero, np.sin(0.5 * phi)], axis=-1)  # qz(φ)
    q = quaternion_multiply(outer, inner)
    return q


def free_rigid_body_attitude_exact(I, omega0, q0, t, *, check_body=True):
    """Exact angular velocity and attitude quaternion of a torque-free rigid body.

    ω(t) as in :func:`free_rigid_body_exact`; the attitude q(t) (scalar first, ``v_space = R(q) v_body``,
    ``q̇ = ½ q ⊗ (0, ω)``) from the Euler angles relative to the invariable frame, with φ(t) in closed form through
    the elliptic integral of the third kind (Carlson ``R_F``, ``R_J``); see the module docstring. Symmetric and
    spherical bodies use ``q(t) = exp(t L_space / (2 I⊥)) ⊗ q0 ⊗ exp(−Ω t e_s / 2)`` and steady rotations
    ``q(t) = q0 ⊗ exp(t ω / 2)``. The space direction of L is constant to round-off for all t.

    Parameters
    ----------
    I : sequence of 3 floats
        Principal moments (any order).
    omega0 : array_like, shape (3,)
        Body angular velocity at t = 0.
    q0 : array_like, shape (4,)
        Unit quaternion at t = 0.
    t : array_like, shape (n,)
        Times.
    check_body : bool, optional
        See :func:`free_rigid_body_exact`.

    Returns
    -------
    omega : ndarray, shape (n, 3)
    q : ndarray, shape (n, 4)

    Examples
    --------
    >>> import numpy as np
    >>> I = np.array([1.0, 2.0, 3.0])
    >>> w, q = free_rigid_body_attitude_exact(I, (1.0, 0.5, 0.2), (1, 0, 0, 0), [0.0, 7.0])
    >>> bool(np.allclose(q[0], [1, 0, 0, 0], rtol=0, atol=1e-15))
    True
    >>> L = _rotate(q, I * w)            # space components of L stay fixed
    >>> bool(np.max(np.abs(L[1] - L[0])) < 1e-14)
    True
    """
    I, w, tt = _validate(I, omega0, t, check_body)
    q0 = _unit_quaternion(q0)
    w, tt, scale = _rescale(w, tt)
    sol = _setup(I, w)
    omega = scale * _omega(sol, w, tt)
    if isinstance(sol, _Constant):
        q = quaternion_multiply(q0, _quat_exp(tt[:, None] * w[None, :]))
    elif isinstance(sol, _Symmetric):
        L_space = _rotate(q0, np.asarray(I) * w)
        e_s = np.zeros(3)
        e_s[sol.axis] = 1.0
        left = _quat_exp(tt[:, None] * (L_space / sol.i_perp)[None, :])
        right = _quat_exp(-sol.rate * tt[:, None] * e_s[None, :])
        q = quaternion_multiply(quaternion_multiply(left, q0), right)
    else:
        q_perm = _perm_quaternion(sol.idx, sol.signs)
        q_inv0 = _invariable_quaternion(sol, np.zeros(1))[0]
        q_fix = quaternion_multiply(quaternion_multiply(q0, _quat_conj(q_perm)), _quat_conj(q_inv0))
        q = np.empty((tt.size, 4))
        for start in range(0, tt.size, _BLOCK):  # blocks: the temporaries stay in cache, the cost per point flat
            block = slice(start, start + _BLOCK)
            q[block] = quaternion_multiply(quaternion_multiply(q_fix, _invariable_quaternion(sol, tt[block])), q_perm)
    q = q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))
    return omega, q
