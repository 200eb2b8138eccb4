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
:func:`eulersym.numerics.elliptic.jacobi_sncndn` (the elliptic core every closed form shares), which takes ``m_c`` as its input, and uses Bulirsch's descending Landen (AGM) recurrence on
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
``R_J`` (:mod:`eulersym.numerics.elliptic`, NumPy only) plus its quasi-periodicity over half-periods 2K. Only the
*product* of the three rotations is used, as a quaternion, so nothing is singular at θ = 0. The space attitude
is ``q(t) = q_fix ⊗ q_inv(t) ⊗ q_perm``, where ``q_fix`` is fixed by ``q(0) = q0``; hence the space direction of L
is constant to round-off for all t.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from eulersym.attitude import _from_matrices, rotate, rotvec_to_quaternion
from eulersym.quaternion import conjugate as _quat_conj, multiply as quaternion_multiply
from eulersym.numerics import _doubledouble as _dd
from eulersym.numerics.elliptic import (_agm_landen, _carlson_rf, _reduce_phase_scalar, _reduce_secular, _sncndn,
                                        _sncndn_scalar, _third_kind, complete_elliptic_k, jacobi_sncndn, reduce_phase)
from eulersym.errors import InvalidInput
from eulersym.validation import finite_array, moments

__all__ = [
    "free_rigid_body_exact",
    "free_rigid_body_attitude_exact",
    "jacobi_sncndn",  # defined in eulersym.numerics.elliptic, kept here for the names that import it from exact
    "complete_elliptic_k",  # (the same)
    "quaternion_multiply",  # eulersym.quaternion.multiply (the Hamilton product of eulersym.attitude), the same
]


# ----------------------------------------------------------------------------------------------------------------
# Quaternions (scalar first): eulersym.attitude's, on rows
# ----------------------------------------------------------------------------------------------------------------
def _quat_exp(v):
    """Unit quaternions of the rotation vectors ``v`` (rows): :func:`eulersym.attitude.rotvec_to_quaternion`."""
    v = np.asarray(v, dtype=np.float64)
    return np.stack(rotvec_to_quaternion(v[..., 0], v[..., 1], v[..., 2], np.cos, np.sin), axis=-1)


def _rotate(q, v):
    """R(q) v for unit quaternion(s) q (rows, broadcasting): :func:`eulersym.attitude.rotate`."""
    q, v = np.asarray(q, dtype=np.float64), np.asarray(v, dtype=np.float64)
    return np.stack(np.broadcast_arrays(*rotate(*np.moveaxis(q, -1, 0), *np.moveaxis(v, -1, 0))), axis=-1)


# ----------------------------------------------------------------------------------------------------------------
# The solution's constants, computed once per initial condition (exact rational discriminants): immutable records
# (a NamedTuple is made in a tenth of a frozen dataclass's time, and this module is imported by every free-body scene)
# ----------------------------------------------------------------------------------------------------------------
class _Elliptic(NamedTuple):
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

    @property
    def phase(self) -> tuple:
        """(λ, u0, 4K) as double-doubles: the arguments of :func:`~eulersym.numerics.elliptic.reduce_phase`."""
        return (self.lam, self.lam_lo), (self.u0, self.u0_lo), (self.period, self.period_lo)


class _Symmetric(NamedTuple):
    axis: int  # body index of the symmetry axis (or 0 for a spherical body)
    rate: float  # Ω = (Is − I⊥)/I⊥ · ω_s: the transverse ω turns by +Ω t about the axis
    i_perp: float


class _Constant(NamedTuple):
    """Steady rotation (or rest): ω is constant."""


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
        rate, start, period = sol.phase
        for k, tk in enumerate(t.tolist()):
            sn, cn, dn = _sncndn_scalar(_reduce_phase_scalar(tk, rate, start, period)[0], sol.rootmc, sol.landen)
            out[k, a], out[k, b], out[k, c] = sa * cn, sb * sn, sc * dn
        return out
    for start in range(0, t.size, _BLOCK):
        block = slice(start, start + _BLOCK)
        r, _ = reduce_phase(t[block], *sol.phase)
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
    """Unit quaternion of the proper rotation P with (P v)[k] = signs[k] v[idx[k]] (body → abc): the active rotation
    R = P, ``v_abc = R v_body`` (Shepperd's method, exact on a signed permutation)."""
    P = np.zeros((3, 3))
    for k in range(3):
        P[k, idx[k]] = signs[k]
    return _from_matrices(P[None])[0]


def _phi_half_period(sol):
    """∫₀ᴷ ds / (1 + n sn² s), the increment of :func:`_phi_integral` over each half period (None on or next to the
    separatrix, where the m = 1 limit is used): once per motion."""
    if math.isinf(sol.K) or sol.mc < 1e-280:
        return None
    return float(_third_kind(1.0, 0.0, sol.mc, -sol.n, 1.0 + sol.n))


def _phi_integral(sol, r, j, whole):
    """W(u) = ∫₀ᵘ ds / (1 + n sn² s) at u = j·4K + r, via Carlson R_F, R_J and quasi-periodicity over 2K (``whole``:
    :func:`_phi_half_period`)."""
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
    if mc < 1e-280:  # m_c below double range: the m = 1 limit over each half period, error O(√m_c)
        return 2.0 * j * hyperbolic(K) + hyperbolic(r)
    s, c, _ = jacobi_sncndn(np.abs(r), mc)
    c = np.abs(c)
    c2 = c * c
    d2 = c2 + mc * s * s
    s2 = s * s
    part = _third_kind(s, c2, d2, -n, 1.0 + n * s2)  # ∫ du/(1 + n sn² u), 0 ≤ u ≤ K
    return 2.0 * j * whole + np.sign(r) * part


def _phi_secular(sol, I, w):
    """The secular part of φ as double-doubles: ``(rate, per)`` with φ = rate·t + per·h + coef·(periodic part), h the
    half periods 2K of u — ``rate = |L|/Ic`` and ``per = 2 coef Π(−n | m)``, ``coef = |L| (Ic − Ia)/(Ia Ic λ)``,
    computed once per motion at 36 digits (:mod:`eulersym.numerics._decimal_elliptic`) from the exact binary inputs,
    so that φ reduced modulo 4π in double-double does not lose digits with t (the error of q no longer grows like
    ε·φ)."""
    import decimal
    from decimal import Decimal

    from eulersym.numerics import _decimal_elliptic as _de

    with decimal.localcontext() as ctx:
        ctx.prec = _de.DIGITS
        Id = [Decimal(float(v)) for v in I]
        wd = [Decimal(float(v)) for v in w]
        a, b, c = sol.idx
        Ia, Ib, Ic = Id[a], Id[b], Id[c]

        def disc(k):  # L² − 2E I_k, exactly (the inputs are binary fractions: 36 digits hold them)
            return sum(Id[i] * (Id[i] - Id[k]) * wd[i] * wd[i] for i in range(3) if i != k)

        Da, Db = disc(a), disc(b)
        L = _de.sqrt(sum(Id[i] * Id[i] * wd[i] * wd[i] for i in range(3)))
        lam = _de.sqrt((Ic - Ib) * Da / (Ia * Ib * Ic))
        mc = (Ic - Ia) * Db / ((Ic - Ib) * Da)
        n = Ic * (Ib - Ia) / (Ia * (Ic - Ib))
        _, (whole,) = _de.complete_integrals(mc, [(-n, 1 + n)])
        coef = L * (Ic - Ia) / (Ia * Ic * lam)
        rate, per = L / Ic, 2 * coef * whole

        def dd(x):
            hi = float(x)
            return hi, float(x - Decimal(hi))

        return dd(rate), dd(per)


_FOUR_PI = (4.0 * _dd.PI[0], 4.0 * _dd.PI[1])


def _phi_parts(sol, r, j):
    """W(u) = 2h·W(K) + part at u = j·4K + r: ``(part, h)``, the periodic part (|r′| ≤ K) and the half periods h
    (:func:`_phi_integral` without its secular term)."""
    K, mc, n = sol.K, sol.mc, sol.n
    k = np.round(r / (2.0 * K))
    r = r - 2.0 * K * k
    halves = 2.0 * j + k
    s, c, _ = jacobi_sncndn(np.abs(r), mc)
    c = np.abs(c)
    c2 = c * c
    part = _third_kind(s, c2, c2 + mc * s * s, -n, 1.0 + n * s * s)
    return np.sign(r) * part, halves


def _invariable_quaternion(sol, t, whole, W0, secular=None, halves0=None):
    """q_inv(t): active rotation (a, b, c) frame → invariable frame (ẑ ∥ L); ``whole`` (:func:`_phi_half_period`)
    and ``W0`` (W at t = 0) are the motion's, computed once. ``secular`` (:func:`_phi_secular`): φ's secular part
    reduced modulo 4π in double-double from the half periods counted from the start's (``halves0``); ``W0`` is then
    the periodic part of W at t = 0."""
    r, j = reduce_phase(t, *sol.phase)
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
    if secular is None:
        W = _phi_integral(sol, r, j, whole) - W0
        phi = (L / Ic) * t + (L * (Ic - Ia) / (Ia * Ic * sol.lam)) * W
    else:
        part, halves = _phi_parts(sol, r, j)
        rate, per = secular
        phi = _reduce_secular(rate, t, per, halves - halves0, _FOUR_PI)
        phi += (L * (Ic - Ia) / (Ia * Ic * sol.lam)) * (part - W0)
    return _euler_quaternion(lc, stheta, psi, phi, flip)


def _euler_quaternion(lc, stheta, psi, phi, flip):
    """``qz(φ) ⊗ qx(θ) ⊗ qz(ψ)`` of the attitude relative to the invariable frame, from ``cos θ = lc`` and
    ``sin θ = stheta`` (θ's half angles formed without cancellation on either side of π/2) and ``flip = ±1`` the sign
    of ψ's half-angle pair (``qz(ψ + 2π) = −qz(ψ)``); arrays that broadcast (one member, or members × times)."""
    half_c = np.sqrt(np.maximum(0.5 * (1.0 + lc), 0.0))
    half_s = np.sqrt(np.maximum(0.5 * (1.0 - lc), 0.0))
    pos = lc >= 0
    half_s = np.where(pos, stheta / (2.0 * np.where(half_c > 0, half_c, 1.0)), half_s)
    half_c = np.where(pos, half_c, stheta / (2.0 * np.where(half_s > 0, half_s, 1.0)))
    cp, sp = flip * np.cos(0.5 * psi), flip * np.sin(0.5 * psi)
    inner = np.stack([half_c * cp, half_s * cp, -half_s * sp, half_c * sp], axis=-1)  # qx(θ) ⊗ qz(ψ)
    zero = np.zeros_like(phi)
    outer = np.stack([np.cos(0.5 * phi), zero, zero, np.sin(0.5 * phi)], axis=-1)  # qz(φ)
    return quaternion_multiply(outer, inner)


def free_rigid_body_attitude_exact(I, omega0, q0, t, *, check_body=True):
    """Exact angular velocity and attitude quaternion of a torque-free rigid body.

    ω(t) as in :func:`free_rigid_body_exact`; the attitude q(t) (scalar first, ``v_space = R(q) v_body``,
    ``q̇ = ½ q ⊗ (0, ω)``) from the Euler angles relative to the invariable frame, with φ(t) in closed form through
    the elliptic integral of the third kind (Carlson ``R_F``, ``R_J``); see the module docstring. Symmetric and
    spherical bodies use ``q(t) = exp(t L_space / (2 I⊥)) ⊗ q0 ⊗ exp(−Ω t e_s / 2)`` and steady rotations
    ``q(t) = q0 ⊗ exp(t ω / 2)``. The space direction of L is constant to round-off for all t.

    Accuracy: φ's secular part ``|L|/Ic · t + 2 coef Π(−n | m) · h`` (h half periods) is reduced modulo 4π in
    double-double from constants computed once at 36 digits, so the asymmetric body's attitude stays at round-off
    however long the run (5.8e-16 at t = 1e9 against a 40-digit reference of the closed form in
    tests/test_numerics_exact_long.py; a double φ cost ε·|φ|, 3.4e-7 there). Beyond that, t itself is a double: the
    motion at the double t is returned, and the attitude moves by ~|ω|·ulp(t) between neighbouring doubles (1.2e-7
    rad at t = 1e9, |ω| = 1) — the bound any evaluation at a double t has. Symmetric and steady bodies turn at
    constant rates by ``exp`` of ``rate · t`` in double: their error is ε·(rate·t).

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
        whole = _phi_half_period(sol)
        secular = halves0 = None
        if whole is not None and sol.mc >= 1e-280:  # φ's secular part in double-double (off the separatrix)
            secular = _phi_secular(sol, I, w)
            part0, halves0 = _phi_parts(sol, *reduce_phase(np.zeros(1), *sol.phase))
            W0, halves0 = part0[0], halves0[0]
        else:
            W0 = _phi_integral(sol, *reduce_phase(np.zeros(1), *sol.phase), whole)[0]
        q_inv0 = _invariable_quaternion(sol, np.zeros(1), whole, W0, secular, halves0)[0]
        q_fix = quaternion_multiply(quaternion_multiply(q0, _quat_conj(q_perm)), _quat_conj(q_inv0))
        q = np.empty((tt.size, 4))
        for start in range(0, tt.size, _BLOCK):  # blocks: the temporaries stay in cache, the cost per point flat
            block = slice(start, start + _BLOCK)
            q_inv = _invariable_quaternion(sol, tt[block], whole, W0, secular, halves0)
            q[block] = quaternion_multiply(quaternion_multiply(q_fix, q_inv), q_perm)
    q = q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))
    return omega, q
