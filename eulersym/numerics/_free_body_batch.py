"""The torque-free body's closed form over the members of a sweep: every member × every time as arrays.

The formulas and their care are those of :mod:`eulersym.numerics.exact` (read its module docstring first); here
they run on all members at once:

- the discriminants ``D_k = Σ_i I_i (I_i − I_k) ω_i²`` in double-double from error-free products and sums (Dekker,
  Knuth), so their sign — the regime — and ``m_c = (Ic − Ia) Db / ((Ic − Ib) Da)`` keep full relative accuracy up
  to ``|Db| ≈ 1e-31 Σ|terms|`` (the scalar path takes them in exact integers);
- λ, √m_c and the period 4K = 2π / AGM(1, √m_c) as double-doubles, the phase ``λ t + u0`` reduced modulo 4K in
  double-double (:func:`eulersym.numerics.elliptic.reduce_phase`), u0 from Carlson's ``R_F`` (``K − y`` above K/2,
  so a start near the separatrix keeps ~ulp(1)): the error stays at round-off relative to |L| and does not grow
  with t;
- sn, cn, dn by Landen's recurrence with one depth per block of :data:`BLOCK` members — the depth the block's
  smallest m_c needs — and the quarter-period reflection (:func:`eulersym.numerics.elliptic._sncndn_reduced`);
- symmetric bodies (two equal moments: ω turns at Ω = (I_s − I⊥)/I⊥ · ω_s), spherical ones and steady rotations
  (ω along one axis) by their trigonometric and constant forms, each kind as one array pass;
- the attitude, when asked, as :func:`~eulersym.numerics.exact.free_rigid_body_attitude_exact` forms it (Euler angles
  of the invariable frame, φ through the third-kind integral by Carlson's ``R_F``, ``R_J``), on arrays — with φ in
  double here (the scalar path reduces its secular part in double-double from 36-digit constants): the attitude's
  error is ε·|φ(t)| (φ ≈ |L| t / Ic), 1e-14 at |φ| ~ 50, ω's stays at round-off.

Members this path leaves to the scalar one (``fallback``): |ω0| beyond 2^±64 (the scalar path rescales them), a
discriminant whose sign the double-double cannot settle (a start within ~1e-31 of the separatrix, or on it), and
moments or rates whose products would leave the double range in the error-free transformations.

The block is the unit of the bits: a member's result depends on the members of its block of :data:`BLOCK` (the
Landen depth), and blocks are counted from the first member, so chunks that are multiples of :data:`BLOCK` give the
bits of one pass (the closed form's :attr:`~eulersym.numerics.methods.Cost.grain`).
"""

from __future__ import annotations

import math

import numpy as np

from eulersym.numerics._doubledouble import PI, two_prod, two_sum
from eulersym.numerics.elliptic import _agm_landen_columns, _rf, _sncndn_reduced, _third_kind
from eulersym.numerics.exact import _euler_quaternion, _quat_exp, _rotate
from eulersym.quaternion import multiply as _multiply  # the Hamilton product of eulersym.attitude, on rows

__all__ = ["members", "BLOCK"]

#: Members evaluated together (one Landen depth); a chunk of a sweep is a multiple of it.
BLOCK = 1024
_EPS = float(np.finfo(float).eps)


# ---- double-double on arrays (the operations of eulersym.numerics._doubledouble, elementwise) ---------------------
def _fast_two_sum(a, b):
    s = a + b
    return s, b - (s - a)


def _dd_add(x, y):
    s, e = two_sum(x[0], y[0])
    t, f = two_sum(x[1], y[1])
    e = e + t
    s, e = _fast_two_sum(s, e)
    e = e + f
    return _fast_two_sum(s, e)


def _dd_mul(x, y):
    p, e = two_prod(x[0], y[0])
    e = e + (x[0] * y[1] + x[1] * y[0])
    return _fast_two_sum(p, e)


def _dd_div(x, y):
    q1 = x[0] / y[0]
    r = _dd_add(x, _dd_mul((-q1, 0.0 * q1), y))
    q2 = r[0] / y[0]
    r = _dd_add(r, _dd_mul((-q2, 0.0 * q2), y))
    q3 = r[0] / y[0]
    return _dd_add(_fast_two_sum(q1, q2), (q3, 0.0 * q3))


def _dd_sqrt(x):
    r = np.sqrt(np.maximum(x[0], 0.0))
    safe = np.where(r > 0.0, r, 1.0)
    p, e = two_prod(r, r)
    residual = ((x[0] - p) - e) + x[1]
    return _fast_two_sum(r, np.where(r > 0.0, residual / (2.0 * safe), 0.0))


def _dd_agm(b):
    """AGM(1, b) of double-doubles b (arrays, 0 < b ≤ 1), as :func:`eulersym.numerics._doubledouble.agm`: every
    member runs until its own ``|a − b| ≤ 2⁻⁵⁶ a`` (a converged member is left as it is)."""
    a = (np.ones_like(b[0]), np.zeros_like(b[0]))
    for _ in range(64):
        d = _dd_add(a, (-b[0], -b[1]))
        going = np.abs(d[0]) > 2.0**-56 * a[0]
        if not going.any():
            break
        s = _dd_add(a, b)
        na = (0.5 * s[0], 0.5 * s[1])
        nb = _dd_sqrt(_dd_mul(a, b))
        a = (np.where(going, na[0], a[0]), np.where(going, na[1], a[1]))
        b = (np.where(going, nb[0], b[0]), np.where(going, nb[1], b[1]))
    s = _dd_add(a, b)
    return 0.5 * s[0], 0.5 * s[1]


def _sncndn_period(r, K, rootmc, landen):
    """sn, cn, dn of a phase reduced to |r| ≤ 2K (half the period 4K): the symmetries to [0, K], Landen on
    [0, K/2], the quarter-period reflection above; ``K``, ``rootmc`` columns (B, 1)."""
    x = np.abs(r)
    back = x > K
    x = np.where(back, 2.0 * K - x, x)
    np.maximum(x, 0.0, out=x)
    near = x > 0.5 * K
    z = np.where(near, K - x, x)
    np.maximum(z, 0.0, out=z)
    sz, cz, dz = _sncndn_reduced(z, *landen)
    sn = np.where(near, cz / dz, sz)
    np.copysign(sn, r, out=sn)
    cn = np.where(near, (rootmc * sz) / dz, cz)
    np.negative(cn, out=cn, where=back)
    dn = np.where(near, rootmc / dz, dz)
    return sn, cn, dn


_SPLIT = 134217729.0  # 2**27 + 1, Veltkamp's splitter


def _split(a):
    """Veltkamp's split a = hi + lo, each half of 26 bits (so that products of halves are exact)."""
    c = _SPLIT * a
    hi = c - (c - a)
    return hi, a - hi


def reduce_phase(t, rate, start, period):
    """:func:`eulersym.numerics.elliptic.reduce_phase` with double-double constants that are columns (B, 1) of
    members (finite periods): ``(r, j)`` with ``λ t + u0 = j·period + r``, |r| ≤ period/2, the product, the sum
    and the reduction in double-double (each operand split once: t is shared by all members; j, a whole number
    below 2²⁶ periods, times the split period is exact)."""
    th, tl = _split(t)
    rh, rl = _split(rate[0])
    p_hi = rate[0] * t
    p_lo = rh * th
    p_lo -= p_hi
    p_lo += rh * tl
    p_lo += rl * th
    p_lo += rl * tl
    p_lo += rate[1] * t
    u_hi = p_hi + start[0]  # two-sum of p_hi and the start
    bb = u_hi - p_hi
    u_lo = p_hi - (u_hi - bb)
    u_lo += start[0] - bb
    u_lo += p_lo
    u_lo += start[1]
    j = u_hi + u_lo
    j *= 1.0 / period[0]
    np.rint(j, out=j)
    ph, pl = _split(period[0])
    e_hi = j * period[0]
    e_lo = j * ph
    e_lo -= e_hi
    e_lo += j * pl  # exact while |j| < 2**26
    r = u_hi - e_hi
    r -= e_lo
    u_lo -= j * period[1]
    r += u_lo
    if not np.all(np.abs(j) < 2.0**26):  # more periods: the products of j in full double-double
        return _reduce_long(t, rate, start, period)
    return r, j


def _reduce_long(t, rate, start, period):
    p_hi, p_lo = two_prod(rate[0], t)
    p_lo = p_lo + rate[1] * t
    u_hi, u_err = two_sum(p_hi, start[0])
    u_lo = u_err + p_lo + start[1]
    j = np.round((u_hi + u_lo) / period[0])
    e_hi, e_lo = two_prod(j, period[0])
    return ((u_hi - e_hi) - e_lo) + (u_lo - j * period[1]), j


def _discriminants(I, w):
    """``D_k = Σ_{i≠k} I_i (I_i − I_k) ω_i²`` (k = 0, 1, 2) as double-doubles, and bounds of their errors."""
    w2 = [two_prod(w[:, i], w[:, i]) for i in range(3)]
    out, bounds = [], []
    for k in range(3):
        terms = []
        for i in range(3):
            if i == k:
                continue
            d = two_sum(I[:, i], -I[:, k])  # I_i − I_k exactly
            p, e = two_prod(I[:, i], d[0])
            p = _fast_two_sum(p, e + I[:, i] * d[1])
            terms.append(_dd_mul(p, w2[i]))
        out.append(_dd_add(terms[0], terms[1]))
        bounds.append(64.0 * _EPS * _EPS * (np.abs(terms[0][0]) + np.abs(terms[1][0])))
    return out, bounds


def members(I, omega0, t, q0=None):
    """ω (and q) of B torque-free bodies at the times t, vectorised over members × times.

    Parameters
    ----------
    I : ndarray (B, 3)
        Principal moments (any order; validated by the caller).
    omega0 : ndarray (B, 3)
    t : ndarray (n,)
    q0 : ndarray (B, 4) or None
        Unit quaternions at t = 0: the attitude is computed too.

    Returns
    -------
    omega : ndarray (B, n, 3)
    q : ndarray (B, n, 4) or None
    fallback : ndarray of int
        Members not computed here (their rows are left unset): the caller runs them one by one.

    Examples
    --------
    >>> from eulersym.numerics.exact import free_rigid_body_exact
    >>> I = np.array([[1.0, 2.0, 3.0], [2.0, 2.0, 1.0]])
    >>> w0 = np.array([[1.0, 0.5, 0.2], [0.3, 0.0, 5.0]])
    >>> omega, _, fallback = members(I, w0, np.array([0.0, 10.0]))
    >>> fallback.tolist(), bool(np.allclose(omega[0], free_rigid_body_exact(I[0], w0[0], [0.0, 10.0]), rtol=0, atol=1e-14))
    ([], True)
    """
    I = np.asarray(I, dtype=np.float64)
    w = np.asarray(omega0, dtype=np.float64)
    t = np.asarray(t, dtype=np.float64)
    B, n = len(I), t.size
    omega = np.empty((B, n, 3))
    q = None if q0 is None else np.empty((B, n, 4))
    top = np.max(np.abs(w), axis=1) if B else np.zeros(0)
    scalar = (top != 0.0) & ((top < 2.0**-64) | (top > 2.0**64))
    scalar |= (np.max(I, axis=1) > 1e100) | (np.min(I, axis=1) < 1e-100)
    e01, e12, e02 = I[:, 0] == I[:, 1], I[:, 1] == I[:, 2], I[:, 0] == I[:, 2]
    spherical = e01 & e12
    symmetric = (e01 | e12 | e02) & ~spherical
    asym = ~(e01 | e12 | e02)
    single = np.count_nonzero(w != 0.0, axis=1) <= 1
    constant = (spherical | (asym & single)) & ~scalar
    symmetric &= ~scalar
    elliptic = asym & ~single & ~scalar
    if constant.any():
        _constant(np.flatnonzero(constant), w, t, q0, omega, q)
    if symmetric.any():
        _symmetric(np.flatnonzero(symmetric), I, w, t, q0, omega, q)
    rows = np.flatnonzero(elliptic)
    left = _elliptic(rows, I, w, t, q0, omega, q) if len(rows) else rows
    fallback = np.sort(np.concatenate([np.flatnonzero(scalar), np.asarray(left, dtype=np.intp)])).astype(np.intp)
    return omega, q, fallback


def _unit(q):
    return q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))


def _constant(rows, w, t, q0, omega, q):
    """ω constant (a spherical body, or ω along one principal axis): q = q0 ⊗ exp(t ω / 2)."""
    omega[rows] = w[rows, None, :]
    if q is not None:
        turn = _quat_exp(t[None, :, None] * w[rows, None, :])
        q[rows] = _unit(_multiply(_unit(q0[rows])[:, None, :], turn))


def _symmetric(rows, I, w, t, q0, omega, q):
    """Two equal moments: the transverse ω turns at Ω = (I_s − I⊥)/I⊥ · ω_s about the symmetry axis s;
    q = exp(t L_space / (2 I⊥)) ⊗ q0 ⊗ exp(−Ω t e_s / 2)."""
    Is = I[rows]
    axis = np.where(Is[:, 1] == Is[:, 2], 0, np.where(Is[:, 0] == Is[:, 2], 1, 2))
    for k in range(3):
        sel = rows[axis == k]
        if not len(sel):
            continue
        i, j = (k + 1) % 3, (k + 2) % 3
        iperp = I[sel, i]
        rate = (I[sel, k] - iperp) / iperp * w[sel, k]
        ang = rate[:, None] * t[None, :]
        c, s = np.cos(ang), np.sin(ang)
        wi, wj = w[sel, i][:, None], w[sel, j][:, None]
        omega[sel, :, k] = w[sel, k][:, None]
        omega[sel, :, i] = c * wi - s * wj
        omega[sel, :, j] = s * wi + c * wj
        if q is not None:
            unit = _unit(q0[sel])
            L_space = _rotate(unit, I[sel] * w[sel])
            left = _quat_exp(t[None, :, None] * (L_space / iperp[:, None])[:, None, :])
            e = np.zeros((len(sel), 1, 3))
            e[:, 0, k] = 1.0
            right = _quat_exp(-rate[:, None, None] * t[None, :, None] * e)
            q[sel] = _unit(_multiply(_multiply(left, unit[:, None, :]), right))


def _elliptic(rows, I, w, t, q0, omega, q):
    """Three distinct moments, Jacobi's sn, cn, dn: the members ``rows`` (one block); returns the rows left to the
    scalar path."""
    Ib, wb = I[rows], w[rows]
    D, bounds = _discriminants(Ib, wb)
    order = np.argsort(Ib, axis=1, kind="stable")
    lo, mid, hi = order[:, 0], order[:, 1], order[:, 2]
    m = np.arange(len(rows))
    d_mid = (D[0][0] * (mid == 0) + D[1][0] * (mid == 1) + D[2][0] * (mid == 2))
    bound_mid = (bounds[0] * (mid == 0) + bounds[1] * (mid == 1) + bounds[2] * (mid == 2))
    unsettled = np.abs(d_mid) <= bound_mid  # on the separatrix, or too near it for the double-double: exactly
    if unsettled.any():
        keep = ~unsettled
        left = rows[unsettled]
        rows, Ib, wb, order = rows[keep], Ib[keep], wb[keep], order[keep]
        lo, mid, hi, d_mid = lo[keep], mid[keep], hi[keep], d_mid[keep]
        D = [(x[0][keep], x[1][keep]) for x in D]
        m = np.arange(len(rows))
    else:
        left = rows[:0]
    if not len(rows):
        return left
    upper = d_mid >= 0
    a, b, c = np.where(upper, lo, hi), mid, np.where(upper, hi, lo)
    even = (b - a) % 3 == 1
    sgn_b = np.where(even, 1.0, -1.0)
    Ia, Ibb, Ic = Ib[m, a], Ib[m, b], Ib[m, c]
    wa, wbb, wc = wb[m, a], sgn_b * wb[m, b], wb[m, c]

    def pick(k):
        return (np.choose(k, [D[0][0], D[1][0], D[2][0]]), np.choose(k, [D[0][1], D[1][1], D[2][1]]))

    Da, Dbb, Dc = pick(a), pick(b), pick(c)
    ca = two_sum(Ic, -Ia)  # Ic − Ia, Ic − Ib exactly
    cb = two_sum(Ic, -Ibb)
    ca_d, cb_d = ca[0] + ca[1], cb[0] + cb[1]
    Dc_d, Da_d = Dc[0] + Dc[1], Da[0] + Da[1]
    A2 = -Dc_d / (Ia * ca_d)
    B2 = -Dc_d / (Ibb * cb_d)
    C2 = Da_d / (Ic * ca_d)
    mc_dd = _dd_div(_dd_mul(ca, Dbb), _dd_mul(cb, Da))
    mc = mc_dd[0]
    A = np.sqrt(A2)
    C = np.copysign(np.sqrt(C2), wc)
    Bamp = np.copysign(np.sqrt(B2), np.where(ca_d > 0, 1.0, -1.0) * C * A)
    xa = Ia * ca_d * wa * wa
    xb = Ibb * cb_d * wbb * wbb
    tot = xa + xb
    cn0 = np.copysign(np.sqrt(xa / tot), wa)
    sn0 = np.copysign(np.sqrt(xb / tot), wbb * Bamp)
    s = np.where(sn0 < 0, -1.0, 1.0)
    prod = _dd_mul(_dd_mul((Ia, 0.0 * Ia), (Ibb, 0.0 * Ia)), (Ic, 0.0 * Ia))
    lam = _dd_sqrt(_dd_div(_dd_mul(cb, Da), prod))
    rootmc_dd = _dd_sqrt(mc_dd)
    agm = _dd_agm(rootmc_dd)
    period = _dd_div((2.0 * PI[0] + 0.0 * mc, 2.0 * PI[1] + 0.0 * mc), agm)  # 4K = 2π / AGM(1, √m_c)
    K = 0.25 * period[0]
    K_dd = (0.25 * period[0], 0.25 * period[1])
    rootmc = rootmc_dd[0]
    dn_num = xa + mc * xb  # dn0² = dn_num / tot
    high = (xb / tot) * (1.0 + rootmc) >= 1.0
    # x ≥ K/2: x = K − y, y = cn0 · R_F(m_c sn0², m_c, dn0²) = O(1); else x = sn0 · R_F(cn0², dn0², 1)
    fx = np.where(high, mc * xb / dn_num, xa / tot)
    fy = np.where(high, mc * tot / dn_num, dn_num / tot)
    back = cn0 < 0

    def start(k):  # u0 of the members k, a block at a time (Carlson's duplication runs until its block converges)
        rf = _rf(fx[k], fy[k], 1.0)
        y = np.sqrt(xa[k] / dn_num[k]) * rf
        x_low = np.abs(sn0[k]) * rf
        x = _dd_add((K_dd[0][k], K_dd[1][k]), (-y, 0.0 * y))
        x = (np.where(high[k], x[0], x_low), np.where(high[k], x[1], 0.0))
        x2 = _dd_add((2.0 * K_dd[0][k], 2.0 * K_dd[1][k]), (-x[0], -x[1]))
        x = (np.where(back[k], x2[0], x[0]), np.where(back[k], x2[1], x[1]))
        return s[k] * x[0], s[k] * x[1]

    amps = np.stack([A, sgn_b * Bamp, C], axis=1)  # ω_a = A cn, ω_b = ±B sn, ω_c = C dn
    place = np.empty((len(rows), 3), dtype=np.intp)
    place[m, a], place[m, b], place[m, c] = 0, 1, 2
    L = np.sqrt(np.sum((Ib * wb) ** 2, axis=1)) if q is not None else None
    col = lambda v: v[:, None]  # noqa: E731
    # the evaluation a block of BLOCK members (counted from the first member of the call) at a time: one Landen depth
    # a block, temporaries that stay in the cache
    edges = np.searchsorted(rows, np.arange(0, rows[-1] + BLOCK + 1, BLOCK))
    for lo, hi in zip(edges[:-1], edges[1:]):
        if lo == hi:
            continue
        k = slice(lo, hi)
        part = rows[k]
        landen = _agm_landen_columns(rootmc[k])
        u0 = start(k)
        r, j = reduce_phase(t[None, :], (col(lam[0][k]), col(lam[1][k])), (col(u0[0]), col(u0[1])),
                            (col(period[0][k]), col(period[1][k])))
        contiguous = part[-1] - part[0] + 1 == len(part)
        target = omega[part[0]:part[-1] + 1] if contiguous else np.empty((len(part), t.size, 3))
        found = _omega_abc(r, col(K[k]), col(rootmc[k]), landen, amps[k], place[k], target, q is not None)
        if not contiguous:
            omega[part] = target
        if q is not None:
            sn, cn, dn = found
            _elliptic_attitude(part, q0, t, q, L[k], Ia[k], Ibb[k], Ic[k], A[k], Bamp[k], C[k], mc[k], rootmc[k], K[k],
                               (lam[0][k], lam[1][k]), u0, (period[0][k], period[1][k]), landen,
                               a[k], b[k], c[k], sgn_b[k], r, j, sn, cn, dn)
    return left


def _omega_abc(r, K, rootmc, landen, amps, place, out, keep):
    """ω of the members at phases r (B, n), |r| ≤ 2K: ``ω_a = A cn, ω_b = B sn, ω_c = C dn`` written into ``out``
    (B, n, 3) at the body axes ``place`` (B, 3: the (a, b, c) index of each body axis); sn, cn, dn themselves
    returned where ``keep`` (else None). The symmetries bring |r| to [0, K] (cn changes sign beyond K), Landen runs on
    [0, K/2] and the reflection ``sn(K − y) = cd y``, ``cn(K − y) = √m_c sd y``, ``dn(K − y) = √m_c/dn y`` covers
    (K/2, K]."""
    x = np.abs(r)
    back = x > K
    d = np.subtract(x, K, out=x)
    np.abs(d, out=d)  # |x − K| = K − (x reflected into [0, K])
    near = d < 0.5 * K
    z = np.where(near, d, K - d)
    sz, cz, dz = _sncndn_reduced(z, *landen)
    inv = np.divide(1.0, dz, out=z)
    sn = np.where(near, cz * inv, sz)
    np.copysign(sn, r, out=sn)
    cn = np.where(near, sz * (rootmc * inv), cz)
    np.negative(cn, out=cn, where=back)
    dn = np.where(near, rootmc * inv, dz)
    values = (cn, sn, dn)
    coef = np.zeros(place.shape + (3,))  # ω_axis = Σ_k coef[:, axis, k] · (cn, sn, dn)_k: a signed permutation
    rows = np.arange(len(place))
    for axis in range(3):
        coef[rows, axis, place[:, axis]] = amps[rows, place[:, axis]]
    for axis in range(3):
        used = [k for k in range(3) if coef[:, axis, k].any()]
        target = out[:, :, axis]
        if not used:
            target[...] = 0.0
            continue
        np.multiply(values[used[0]], coef[:, axis, used[0], None], out=target)
        for k in used[1:]:
            target += values[k] * coef[:, axis, k, None]
    return (sn, cn, dn) if keep else None


def _third(s, c, mc, n):
    """∫₀ˣ dy/(1 + n sn² y) for 0 ≤ x ≤ K from s = sn x ≥ 0, c = |cn x| (Carlson, members × times)."""
    c2 = c * c
    return _third_kind(s, c2, c2 + mc * s * s, -n, 1.0 + n * s * s)


def _elliptic_attitude(rows, q0, t, q, L, Ia, Ib, Ic, A, Bamp, C, mc, rootmc, K, lam, u0, period, landen, a, b, c,
                       sgn_b, r, j, sn, cn, dn):
    """q(t) = q_fix ⊗ q_inv(t) ⊗ q_perm (see :func:`eulersym.numerics.exact.free_rigid_body_attitude_exact`)."""
    col = lambda v: v[:, None]  # noqa: E731
    n_char = Ic * (Ib - Ia) / (Ia * (Ic - Ib))
    whole = _third(np.ones_like(mc), np.zeros_like(mc), mc, n_char)  # W(K)

    def W(rr, jj, s_abs, c_abs):
        k = np.round(rr / col(2.0 * K))
        red = rr - col(2.0 * K) * k
        halves = 2.0 * jj + k
        return 2.0 * halves * col(whole) + np.sign(red) * _third(s_abs, c_abs, col(mc), col(n_char))

    r0, j0 = reduce_phase(np.zeros((1, 1)), (col(lam[0]), col(lam[1])), (col(u0[0]), col(u0[1])),
                          (col(period[0]), col(period[1])))
    s0, c0, d0 = _sncndn_period(r0, col(K), col(rootmc), landen)
    W0 = W(r0, j0, np.abs(s0), np.abs(c0))

    def inv(sn_, cn_, dn_, jj, Wt, tt):
        la, lb, lc = col(Ia * A) * cn_ / col(L), col(Ib * Bamp) * sn_ / col(L), col(Ic * C) * dn_ / col(L)
        stheta = np.hypot(la, lb)
        psi_p = np.arctan2(col(Ib * Bamp) * sn_, col(Ia * np.abs(A)) * cn_)
        flip = np.where(np.mod(jj, 2.0) == 0.0, 1.0, -1.0)
        psi = 0.5 * math.pi - psi_p
        phi = col(L / Ic) * tt + col(L * (Ic - Ia) / (Ia * Ic * lam[0])) * (Wt - W0)
        return _euler_quaternion(lc, stheta, psi, phi, flip)

    q_inv0 = inv(s0, c0, d0, j0, W0, np.zeros((1, 1)))[:, 0]
    P = np.zeros((len(rows), 3, 3))
    m = np.arange(len(rows))
    P[m, 0, a], P[m, 1, b], P[m, 2, c] = 1.0, sgn_b, 1.0
    from eulersym.attitude import _from_matrices

    q_perm = _from_matrices(P)
    conj = np.array([1.0, -1.0, -1.0, -1.0])
    q_fix = _multiply(_multiply(_unit(q0[rows]), q_perm * conj), q_inv0 * conj)
    Wt = W(r, j, np.abs(sn), np.abs(cn))
    q_inv = inv(sn, cn, dn, j, Wt, t[None, :])
    q[rows] = _unit(_multiply(_multiply(q_fix[:, None, :], q_inv), q_perm[:, None, :]))
