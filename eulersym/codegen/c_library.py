"""The parts of the C target that are numerics rather than derived expressions, as C99 source text.

- ``eulersym_free_body.h/.c`` — the torque-free body's exact angular velocity ω(t): the algorithm of the NumPy oracle
  :func:`eulersym.numerics.free_rigid_body_exact` (:mod:`eulersym.numerics.exact`) in C. The discriminants
  ``D_k = Σ Iᵢ(Iᵢ − I_k)ωᵢ²`` are exact floating-point expansions (Shewchuk's arithmetic: error-free sums and
  products, no big integers), so the motion is classified exactly (regime, separatrix, steady rotation) and
  ``m_c`` keeps full relative accuracy near the separatrix; λ, √m_c and the period 4K = 2π / AGM(1, √m_c) are
  double-doubles, the phase ``λ t + u0`` is reduced modulo 4K in double-double, and sn, cn, dn come from the
  descending Landen (AGM) recurrence with the quarter-period reflection, as in the oracle.
- ``eulersym_pivoted.h/.c`` — one step of the exact-flow splitting of a pivoted body (the heavy top among them):
  :mod:`eulersym.numerics.pivoted`'s sub-flows (exact rotations about the principal axes or the symmetric top's
  exact free flow, gravity kicks), its compositions (Strang, Yoshida 4 and 6) and its renormalisation, in the same
  order of operations (the same bits as the Python loop, tests/test_codegen_c.py).

The few numbers the C shares with Python — π as a double-double, the composition coefficients — are filled in from
:mod:`eulersym.numerics._doubledouble` and :data:`eulersym.numerics.pivoted.COMPOSITIONS` when the text is rendered
(:func:`library_files`), so they are written once. The code allocates nothing and keeps no global or static state:
the caller owns every struct (reentrant). It compiles cleanly with ``gcc -std=c99 -pedantic -Wall -Wextra
-Wconversion -Werror``. Do not let the compiler contract ``a*b + c`` into fused multiply-adds (``-ffp-contract=off``,
gcc's default in ISO C mode) if you want the bits of the NumPy reference.

Examples
--------
>>> sorted(library_files())
['eulersym_free_body.c', 'eulersym_free_body.h', 'eulersym_pivoted.c', 'eulersym_pivoted.h']
"""

from __future__ import annotations

from string import Template

__all__ = ["library_files", "LIBRARY_NAMES"]

#: The file stems of the library (each a ``.h`` and a ``.c``).
LIBRARY_NAMES = ("eulersym_free_body", "eulersym_pivoted")

_NOTICE = ("/* Written by `eulersym generate --target c` from eulersym.codegen.c_library. Do not edit: regenerate.\n")

_FREE_BODY_H = _NOTICE + r""" *
 * The torque-free rigid body's exact angular velocity omega(t), from Jacobi's elliptic functions.
 *
 * Euler's equations I1 dw1/dt = (I2 - I3) w2 w3 (and cyclic), principal moments I in any order, omega in body
 * components. With 2E = sum I_i w_i^2, L^2 = sum I_i^2 w_i^2 and D_k = L^2 - 2E I_k, the body circulates about the
 * axis c of the largest moment when D_mid >= 0 and of the smallest otherwise (b: the intermediate axis, a: the
 * other), and
 *     w_a = A cn(u|m),  w_b = B sn(u|m),  w_c = C dn(u|m),  u = lambda t + u0,
 *     lambda^2 = (Ic - Ib) Da / (Ia Ib Ic),  m_c = 1 - m = (Ic - Ia) Db / ((Ic - Ib) Da).
 * On the separatrix (Db = 0) sn = tanh, cn = dn = sech; a symmetric body turns its transverse omega at the
 * constant rate (Is - Ip)/Ip ws about the symmetry axis; a steady rotation stays put.
 * The same algorithm as eulersym.numerics.free_rigid_body_exact (its docstring gives the method): the D_k exact
 * (floating-point expansions), lambda, sqrt(m_c) and the period 4K as double-doubles, the phase reduced modulo 4K
 * in double-double (the error does not grow with t), sn/cn/dn by the descending Landen (AGM) recurrence.
 *
 * Use: eulersym_free_body body;  if (eulersym_free_body_init(&body, I, omega0) == 0)
 *          eulersym_free_body_omega(&body, t, omega);     (any t, any number of times, from any thread)
 * The struct is the caller's memory (no malloc, no global or static state). C99; link with -lm.
 */

#ifndef EULERSYM_FREE_BODY_H
#define EULERSYM_FREE_BODY_H

#ifdef __cplusplus
extern "C" {
#endif

/* Most terms of the descending Landen sequence (the AGM of 1 and sqrt(m_c) converges in about 6 to 12). */
#define EULERSYM_FREE_BODY_LANDEN 64

/* The constants of one motion (filled by eulersym_free_body_init; read-only afterwards). */
typedef struct {
    int kind;            /* 0 steady rotation, 1 symmetric body, 2 elliptic, 3 separatrix */
    double scale;        /* omega(t) = scale * w(scale * t): |omega0| brought to order one by a power of two */
    double w[3];         /* omega0 / scale */
    int axis;            /* symmetric body: the symmetry axis (0, 1, 2) */
    double rate;         /* symmetric body: the rate of the transverse omega about the axis */
    int idx[3];          /* elliptic: the body axes of (a, b, c) */
    double amp[3];       /* elliptic: the signed amplitudes of w_a, w_b, w_c in body components */
    double lam, lam_lo;  /* lambda, as a double-double */
    double u0, u0_lo;    /* the phase at t = 0 */
    double period, period_lo;  /* 4K (infinite on the separatrix) */
    double rootmc;       /* sqrt(m_c) */
    int n_landen;        /* terms of the Landen sequence */
    double landen_a[EULERSYM_FREE_BODY_LANDEN];
    double landen_b[EULERSYM_FREE_BODY_LANDEN];
    double agm;          /* AGM(1, sqrt(m_c)) */
} eulersym_free_body;

/* The motion with principal moments I[3] (positive, any order) and omega(0) = omega0[3].
 * Returns 0, or 1 when a moment is not a positive finite number or omega0 is not finite (body left unusable). */
int eulersym_free_body_init(eulersym_free_body *body, const double I[3], const double omega0[3]);

/* omega(t) in body components into omega[3]. Returns 0, or 1 when scale * t is not finite. */
int eulersym_free_body_omega(const eulersym_free_body *body, double t, double omega[3]);

#ifdef __cplusplus
}
#endif

#endif /* EULERSYM_FREE_BODY_H */
"""

_FREE_BODY_C = _NOTICE + r""" * The torque-free body's exact omega(t); see eulersym_free_body.h.
 */

#include <math.h>

#include "eulersym_free_body.h"

/* ---- Error-free transformations (Knuth's two-sum, Dekker's two-product with Veltkamp's split: no FMA) ---- */

static void two_sum(double a, double b, double *s, double *e)
{
    double x = a + b;
    double bb = x - a;
    *s = x;
    *e = (a - (x - bb)) + (b - bb);
}

static void fast_two_sum(double a, double b, double *s, double *e)
{
    double x = a + b;
    *s = x;
    *e = b - (x - a);
}

static void two_prod(double a, double b, double *p, double *e)
{
    const double split = 134217729.0; /* 2^27 + 1 */
    double x = a * b;
    double ca = split * a, cb = split * b;
    double ah = ca - (ca - a), al = a - ah;
    double bh = cb - (cb - b), bl = b - bh;
    *p = x;
    *e = ((ah * bh - x) + ah * bl + al * bh) + al * bl;
}

/* ---- Double-doubles (hi + lo, |lo| <= ulp(hi)/2), as eulersym.numerics._doubledouble ---- */

typedef struct { double hi, lo; } dd;

static dd dd_make(double hi, double lo)
{
    dd r;
    r.hi = hi;
    r.lo = lo;
    return r;
}

static dd dd_add(dd x, dd y)
{
    double s, e, t, f;
    two_sum(x.hi, y.hi, &s, &e);
    two_sum(x.lo, y.lo, &t, &f);
    e += t;
    fast_two_sum(s, e, &s, &e);
    e += f;
    fast_two_sum(s, e, &s, &e);
    return dd_make(s, e);
}

static dd dd_mul(dd x, dd y)
{
    double p, e;
    two_prod(x.hi, y.hi, &p, &e);
    e += x.hi * y.lo + x.lo * y.hi;
    fast_two_sum(p, e, &p, &e);
    return dd_make(p, e);
}

static dd dd_div(dd x, dd y)
{
    double q1 = x.hi / y.hi, q2, q3, s, e;
    dd r = dd_add(x, dd_mul(dd_make(-q1, 0.0), y));
    q2 = r.hi / y.hi;
    r = dd_add(r, dd_mul(dd_make(-q2, 0.0), y));
    q3 = r.hi / y.hi;
    fast_two_sum(q1, q2, &s, &e);
    return dd_add(dd_make(s, e), dd_make(q3, 0.0));
}

static dd dd_sqrt(dd x)
{
    double r, p, e, residual, s, f;
    if (x.hi <= 0.0)
        return dd_make(0.0, 0.0);
    r = sqrt(x.hi);
    two_prod(r, r, &p, &e);
    residual = ((x.hi - p) - e) + x.lo;
    fast_two_sum(r, residual / (2.0 * r), &s, &f);
    return dd_make(s, f);
}

/* sqrt(num / den) for num >= 0, den > 0, scaled by an even power of two while it is formed (no underflow). */
static dd dd_sqrt_ratio(dd num, dd den)
{
    int en, ed, k;
    dd x, r;
    if (num.hi <= 0.0)
        return dd_make(0.0, 0.0);
    (void)frexp(num.hi, &en);
    (void)frexp(den.hi, &ed);
    k = (ed - en) / 2;
    x = dd_div(dd_make(ldexp(num.hi, 2 * k), ldexp(num.lo, 2 * k)), den);
    r = dd_sqrt(x);
    return dd_make(ldexp(r.hi, -k), ldexp(r.lo, -k));
}

static dd dd_agm(dd a, dd b)
{
    int i;
    for (i = 0; i < 64; i++) {
        dd d = dd_add(a, dd_make(-b.hi, -b.lo));
        dd next_a, next_b;
        if (fabs(d.hi) <= ldexp(1.0, -56) * a.hi)
            break;
        next_a = dd_mul(dd_add(a, b), dd_make(0.5, 0.0));
        next_b = dd_sqrt(dd_mul(a, b));
        a = next_a;
        b = next_b;
    }
    return dd_mul(dd_add(a, b), dd_make(0.5, 0.0));
}

/* ---- Expansions (Shewchuk 1997): exact sums of doubles, nonoverlapping, increasing magnitude ---- */

#define EXPANSION 64

/* h = e * b exactly (length at most 2 elen). */
static int scale_expansion(int elen, const double *e, double b, double *h)
{
    double q, sum, hh, p1, p0;
    int i, n = 0;
    two_prod(e[0], b, &q, &hh);
    if (hh != 0.0)
        h[n++] = hh;
    for (i = 1; i < elen; i++) {
        two_prod(e[i], b, &p1, &p0);
        two_sum(q, p0, &sum, &hh);
        if (hh != 0.0)
            h[n++] = hh;
        fast_two_sum(p1, sum, &q, &hh);
        if (hh != 0.0)
            h[n++] = hh;
    }
    if (q != 0.0 || n == 0)
        h[n++] = q;
    return n;
}

/* h = e + b exactly (length at most elen + 1). */
static int grow_expansion(int elen, const double *e, double b, double *h)
{
    double q = b, s, err;
    int i, n = 0;
    for (i = 0; i < elen; i++) {
        two_sum(q, e[i], &s, &err);
        q = s;
        if (err != 0.0)
            h[n++] = err;
    }
    if (q != 0.0 || n == 0)
        h[n++] = q;
    return n;
}

/* e += f exactly; returns the new length of e (at most elen + flen). */
static int add_expansion(int elen, double *e, int flen, const double *f)
{
    double tmp[EXPANSION];
    int i, k;
    for (i = 0; i < flen; i++) {
        elen = grow_expansion(elen, e, f[i], tmp);
        for (k = 0; k < elen; k++)
            e[k] = tmp[k];
    }
    return elen;
}

/* The expansion's value as a double-double (summed from the smallest component). */
static dd expansion_dd(int n, const double *e)
{
    dd acc = dd_make(0.0, 0.0);
    int i;
    for (i = 0; i < n; i++)
        acc = dd_add(acc, dd_make(e[i], 0.0));
    return acc;
}

/* D_k = sum over i != k of I_i (I_i - I_k) w_i^2, exactly; returns its length in d. */
static int discriminant(const double *I, const double *w, int k, double *d)
{
    int i, n = 1;
    d[0] = 0.0;
    for (i = 0; i < 3; i++) {
        double sq[2], a[4], hi_part[8], lo_part[8], diff_hi, diff_lo;
        int nsq, na, nh, nl;
        if (i == k)
            continue;
        two_prod(w[i], w[i], &sq[1], &sq[0]);
        nsq = sq[0] != 0.0 ? 2 : 1;
        na = scale_expansion(nsq, nsq == 2 ? sq : sq + 1, I[i], a);
        two_sum(I[i], -I[k], &diff_hi, &diff_lo);
        nh = scale_expansion(na, a, diff_hi, hi_part);
        n = add_expansion(n, d, nh, hi_part);
        if (diff_lo != 0.0) {
            nl = scale_expansion(na, a, diff_lo, lo_part);
            n = add_expansion(n, d, nl, lo_part);
        }
    }
    return n;
}

static int sign_of(int n, const double *e)
{
    return e[n - 1] > 0.0 ? 1 : (e[n - 1] < 0.0 ? -1 : 0);
}

/* ---- Carlson's R_F and the Jacobi functions, as eulersym.numerics.exact ---- */

static double carlson_rf(double x, double y, double z)
{
    double mu = 0.0, dx = 0.0, dy = 0.0, dz = 0.0, e2, e3;
    int i;
    for (i = 0; i < 200; i++) {
        double sx, sy, sz, lam;
        mu = (x + y + z) / 3.0;
        dx = 1.0 - x / mu;
        dy = 1.0 - y / mu;
        dz = 1.0 - z / mu;
        if (fmax(fabs(dx), fmax(fabs(dy), fabs(dz))) < 1e-3)
            break;
        sx = sqrt(x);
        sy = sqrt(y);
        sz = sqrt(z);
        lam = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
    }
    e2 = dx * dy - dz * dz;
    e3 = dx * dy * dz;
    return (1.0 + (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) * e2 + e3 / 14.0) / sqrt(mu);
}

static void landen(eulersym_free_body *body, double rootmc)
{
    double a = 1.0, b = rootmc;
    int n = 0;
    while (n < EULERSYM_FREE_BODY_LANDEN) {
        double next_a;
        body->landen_a[n] = a;
        body->landen_b[n] = b;
        n++;
        if (fabs(a - b) <= 1e-9 * a)
            break;
        next_a = 0.5 * (a + b);
        b = sqrt(a * b);
        a = next_a;
    }
    body->n_landen = n;
    body->agm = 0.5 * (a + b);
}

static void sncndn(const eulersym_free_body *body, double u, double *sn, double *cn, double *dn)
{
    const double pi = ${PI_HI};
    double agm = body->agm, K = pi / (2.0 * agm), r = fmod(fabs(u), 4.0 * K);
    double sign = 1.0, sign_sn, sign_cn, z, v, sz, cz, dz;
    int near, i;
    if (r >= 2.0 * K) {
        r -= 2.0 * K;
        sign = -1.0;
    }
    sign_sn = u < 0.0 ? -sign : sign;
    sign_cn = sign;
    if (r > K) {
        r = 2.0 * K - r;
        sign_cn = -sign;
    }
    near = r > 0.5 * K;
    z = near ? fmax(K - r, 0.0) : r;
    v = z * agm;
    if (v < 1e-150) {
        sz = z;
        cz = 1.0;
        dz = 1.0;
    } else {
        double a = cos(v) / sin(v), c = agm * a;
        dz = 1.0;
        for (i = body->n_landen - 1; i >= 0; i--) {
            a = a * c;
            c = c * dz;
            dz = (body->landen_b[i] + a) / (body->landen_a[i] + a);
            a = c / body->landen_a[i];
        }
        sz = 1.0 / sqrt(c * c + 1.0);
        cz = c * sz;
    }
    if (near) {
        *sn = sign_sn * cz / dz;
        *cn = sign_cn * body->rootmc * sz / dz;
        *dn = body->rootmc / dz;
    } else {
        *sn = sign_sn * sz;
        *cn = sign_cn * cz;
        *dn = dz;
    }
}

/* ---- The motion's constants ---- */

static int finite_positive(double x)
{
    return isfinite(x) && x > 0.0;
}

int eulersym_free_body_init(eulersym_free_body *body, const double I[3], const double omega0[3])
{
    const dd pi = {${PI_HI}, ${PI_LO}};
    double top = 0.0, big, In[3], w[3], d[3][EXPANSION];
    int k, nonzero = 0, nd[3], e, lo, mid, hi, a, b, c;
    for (k = 0; k < 3; k++) {
        if (!finite_positive(I[k]) || !isfinite(omega0[k]))
            return 1;
        top = fmax(top, fabs(omega0[k]));
    }
    body->scale = 1.0;
    if (top != 0.0 && !(ldexp(1.0, -64) <= top && top <= ldexp(1.0, 64))) {
        (void)frexp(top, &e);
        body->scale = ldexp(1.0, e);
    }
    for (k = 0; k < 3; k++) {
        body->w[k] = omega0[k] / body->scale;
        nonzero += body->w[k] != 0.0;
    }
    body->kind = 0;
    if (I[0] == I[1] && I[1] == I[2]) {
        body->kind = 1;
        body->axis = 0;
        body->rate = 0.0;
        return 0;
    }
    for (k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        if (I[i] == I[j]) {
            body->kind = 1;
            body->axis = k;
            body->rate = (I[k] - I[i]) / I[i] * body->w[k];
            return 0;
        }
    }
    if (nonzero <= 1)
        return 0;
    /* the moments by a power of two, the largest in [1, 2): every ratio below is unchanged */
    big = fmax(I[0], fmax(I[1], I[2]));
    (void)frexp(big, &e);
    for (k = 0; k < 3; k++) {
        In[k] = ldexp(I[k], 1 - e);
        w[k] = body->w[k];
    }
    lo = 0;
    hi = 0;
    for (k = 1; k < 3; k++) {
        if (In[k] < In[lo])
            lo = k;
        if (In[k] > In[hi])
            hi = k;
    }
    mid = 3 - lo - hi;
    nd[mid] = discriminant(In, w, mid, d[mid]);
    if (sign_of(nd[mid], d[mid]) >= 0) {
        a = lo;
        c = hi;
    } else {
        a = hi;
        c = lo;
    }
    b = mid;
    nd[a] = discriminant(In, w, a, d[a]);
    nd[c] = discriminant(In, w, c, d[c]);
    if (sign_of(nd[c], d[c]) == 0 || sign_of(nd[a], d[a]) == 0)
        return 0; /* steady rotation about a principal axis */
    {
        const double Ia = In[a], Ib = In[b], Ic = In[c];
        const int even = ((b - a + 3) % 3) == 1;
        const double sgn[3] = {1.0, even ? 1.0 : -1.0, 1.0};
        const double wa = sgn[0] * w[a], wb = sgn[1] * w[b], wc = sgn[2] * w[c];
        const dd Da = expansion_dd(nd[a], d[a]), Db = expansion_dd(nd[b], d[b]), Dc = expansion_dd(nd[c], d[c]);
        dd ca, cb, xa, xb, tot, mc_num, mc_den, mc, rootmc, wa2, wb2, cn0sq, sn0sq;
        double A2, B2, C2, A, B, C, sa = 1.0, cn0, sn0, s;
        const int sep = sign_of(nd[b], d[b]) == 0;
        two_sum(Ic, -Ia, &ca.hi, &ca.lo);
        two_sum(Ic, -Ib, &cb.hi, &cb.lo);
        A2 = dd_div(dd_make(-Dc.hi, -Dc.lo), dd_mul(dd_make(Ia, 0.0), ca)).hi;
        B2 = dd_div(dd_make(-Dc.hi, -Dc.lo), dd_mul(dd_make(Ib, 0.0), cb)).hi;
        C2 = dd_div(Da, dd_mul(dd_make(Ic, 0.0), ca)).hi;
        mc_num = dd_mul(ca, Db); /* m_c = mc_num / mc_den, the denominator made positive */
        mc_den = dd_mul(cb, Da);
        if (mc_den.hi < 0.0) {
            mc_num = dd_make(-mc_num.hi, -mc_num.lo);
            mc_den = dd_make(-mc_den.hi, -mc_den.lo);
        }
        mc = dd_div(mc_num, mc_den);
        if (sep && wa < 0.0)
            sa = -1.0;
        A = sa * sqrt(A2);
        C = copysign(sqrt(C2), wc);
        B = copysign(sqrt(B2), (Ic > Ia ? 1.0 : -1.0) * C * A);
        two_prod(wa, wa, &wa2.hi, &wa2.lo);
        two_prod(wb, wb, &wb2.hi, &wb2.lo);
        xa = dd_mul(dd_mul(dd_make(Ia, 0.0), ca), wa2);
        xb = dd_mul(dd_mul(dd_make(Ib, 0.0), cb), wb2);
        tot = dd_add(xa, xb);
        cn0sq = dd_div(xa, tot);
        sn0sq = dd_div(xb, tot);
        cn0 = copysign(sqrt(cn0sq.hi), wa * sa);
        sn0 = copysign(sqrt(sn0sq.hi), wb * B);
        s = sn0 < 0.0 ? -1.0 : 1.0;
        {
            const dd lam = dd_sqrt_ratio(dd_mul(cb, Da), dd_mul(dd_mul(dd_make(Ia, 0.0), dd_make(Ib, 0.0)),
                                                                 dd_make(Ic, 0.0)));
            body->lam = lam.hi;
            body->lam_lo = lam.lo;
        }
        rootmc = dd_sqrt_ratio(mc_num, mc_den);
        body->idx[0] = a;
        body->idx[1] = b;
        body->idx[2] = c;
        body->amp[0] = sgn[0] * A;
        body->amp[1] = sgn[1] * B;
        body->amp[2] = sgn[2] * C;
        body->rootmc = rootmc.hi;
        if (sep || rootmc.hi == 0.0) {
            body->kind = 3;
            body->u0 = s * log((1.0 + fabs(sn0)) / fabs(cn0));
            body->u0_lo = 0.0;
            body->period = INFINITY;
            body->period_lo = 0.0;
            body->n_landen = 0;
            return 0;
        }
        {
            const dd period = dd_div(pi, dd_mul(dd_make(0.5, 0.0), dd_agm(dd_make(1.0, 0.0), rootmc)));
            const dd K = dd_make(0.25 * period.hi, 0.25 * period.lo);
            const dd dn0sq = dd_add(cn0sq, dd_mul(mc, sn0sq));
            dd x;
            body->kind = 2;
            body->period = period.hi;
            body->period_lo = period.lo;
            if (sn0sq.hi * (1.0 + rootmc.hi) >= 1.0) {
                const double y = sqrt(dd_div(cn0sq, dn0sq).hi)
                                 * carlson_rf(dd_div(dd_mul(mc, sn0sq), dn0sq).hi, dd_div(mc, dn0sq).hi, 1.0);
                x = dd_add(K, dd_make(-y, 0.0));
            } else {
                x = dd_make(fabs(sn0) * carlson_rf(cn0sq.hi, dn0sq.hi, 1.0), 0.0);
            }
            if (cn0 < 0.0)
                x = dd_add(dd_make(2.0 * K.hi, 2.0 * K.lo), dd_make(-x.hi, -x.lo));
            body->u0 = s * x.hi;
            body->u0_lo = s * x.lo;
            landen(body, rootmc.hi);
        }
    }
    return 0;
}

/* ---- omega(t) ---- */

int eulersym_free_body_omega(const eulersym_free_body *body, double t, double omega[3])
{
    const double ts = t * body->scale;
    if (!isfinite(ts))
        return 1;
    if (body->kind == 0) {
        omega[0] = body->scale * body->w[0];
        omega[1] = body->scale * body->w[1];
        omega[2] = body->scale * body->w[2];
    } else if (body->kind == 1) {
        const int k = body->axis, i = (k + 1) % 3, j = (k + 2) % 3;
        const double ang = body->rate * ts, c = cos(ang), s = sin(ang);
        omega[k] = body->scale * body->w[k];
        omega[i] = body->scale * (c * body->w[i] - s * body->w[j]);
        omega[j] = body->scale * (s * body->w[i] + c * body->w[j]);
    } else {
        /* u = lambda t + u0 = j 4K + r, |r| <= 2K, in double-double (as eulersym.numerics.elliptic.reduce_phase) */
        double p_hi, p_lo, u_hi, u_lo, r, sn, cn, dn;
        two_prod(body->lam, ts, &p_hi, &p_lo);
        p_lo = p_lo + body->lam_lo * ts;
        u_hi = p_hi + body->u0;
        u_lo = ((body->u0 - (u_hi - p_hi)) + (p_hi - (u_hi - (u_hi - p_hi)))) + p_lo + body->u0_lo;
        if (body->kind == 3) {
            r = u_hi + u_lo;
            sn = tanh(r);
            cn = 1.0 / cosh(r);
            dn = cn;
        } else {
            const double j = nearbyint((u_hi + u_lo) / body->period);
            double e_hi, e_lo;
            two_prod(j, body->period, &e_hi, &e_lo);
            r = ((u_hi - e_hi) - e_lo) + (u_lo - j * body->period_lo);
            sncndn(body, r, &sn, &cn, &dn);
        }
        omega[body->idx[0]] = body->scale * (body->amp[0] * cn);
        omega[body->idx[1]] = body->scale * (body->amp[1] * sn);
        omega[body->idx[2]] = body->scale * (body->amp[2] * dn);
    }
    return 0;
}
"""

_PIVOTED_H = _NOTICE + r""" *
 * One step of the exact-flow splitting of a rigid body about a fixed pivot in uniform gravity (the heavy top among
 * them): eulersym.numerics.pivoted in C, the same sub-flows in the same order.
 *
 * State s[10] in the principal frame of the inertia tensor about the pivot: the total body angular momentum
 * L = I w + h (3), the body components of the upward vertical Gamma (3) and the attitude quaternion q (4, scalar
 * first, v_space = R(q) v_body). Hamiltonian H = sum_k (L_k - h_k)^2 / (2 I_k) + M g c.Gamma. The Strang step
 * K(tau/2) F(tau) K(tau/2): F the free flow, either split into exact rotations about the axes
 * F1(tau/2) F2(tau/2) F3(tau) F2(tau/2) F1(tau/2) (any body) or exact for a symmetric body (I1 = I2, the rotor on
 * e3); K the exact gravity kick L <- L + tau Gamma x (M g c). A step of size h composes Strang steps (Yoshida's
 * triple jump, order 4; his solution A, order 6) and then puts |q| = |Gamma| = 1 and L.Gamma back on their values.
 * Every sub-flow is a rotation or a kick orthogonal to Gamma: |Gamma|, L.Gamma and |q| are kept, the energy error
 * stays bounded.
 *
 * Use: eulersym_pivoted_params par = {{1/I1, 1/I2, 1/I3}, {h1, h2, h3}, {M g c1, M g c2, M g c3}, L.Gamma};
 *      for (...) eulersym_pivoted_step(s, h, &par, EULERSYM_PIVOTED_YOSHIDA4, EULERSYM_PIVOTED_AXES);
 * No malloc, no global or static state (reentrant). C99; link with -lm.
 */

#ifndef EULERSYM_PIVOTED_H
#define EULERSYM_PIVOTED_H

#ifdef __cplusplus
extern "C" {
#endif

/* Methods: the compositions of eulersym.numerics.pivoted.COMPOSITIONS. */
#define EULERSYM_PIVOTED_STRANG 0
#define EULERSYM_PIVOTED_YOSHIDA4 1
#define EULERSYM_PIVOTED_YOSHIDA6 2
/* Free flows: split on the principal axes (any body), or exact for a symmetric body (I1 = I2, rotor on e3). */
#define EULERSYM_PIVOTED_AXES 0
#define EULERSYM_PIVOTED_SYMMETRIC 1

/* The body, in the principal frame of its inertia tensor about the pivot. */
typedef struct {
    double inv_moments[3]; /* 1/I1, 1/I2, 1/I3 */
    double rotor[3];       /* h: the rotor's constant angular momentum */
    double mgc[3];         /* M g c: mass times gravity times the centre of mass from the pivot */
    double l_dot_gamma;    /* L.Gamma of the start: put back after every step */
} eulersym_pivoted_params;

/* One step of size h of s[10] in place. Returns 0; 1 for an unknown method or free flow (s unchanged); 2 when the
 * state is no longer finite (a step far too large). */
int eulersym_pivoted_step(double s[10], double h, const eulersym_pivoted_params *par, int method, int free_flow);

#ifdef __cplusplus
}
#endif

#endif /* EULERSYM_PIVOTED_H */
"""

_PIVOTED_C = _NOTICE + r""" * One step of the exact-flow splitting of a pivoted body; see eulersym_pivoted.h.
 */

#include <math.h>

#include "eulersym_pivoted.h"

/* Below this angle sin(x/2)/x rounds to 1/2 (eulersym.attitude.SMALL_ROTATION). */
#define SMALL_ROTATION ${SMALL_ROTATION}

/* L and Gamma turned by -2 half about e1, q <- q (x) (cos half, sin half e1) (increment form). */
static void turn1(double *s, double half)
{
    const double c = cos(half), sn = sin(half), a = 2.0 * sn;
    const double L2 = s[1], L3 = s[2], G2 = s[4], G3 = s[5], q0 = s[6], q1 = s[7], q2 = s[8], q3 = s[9];
    s[1] = L2 - a * (sn * L2 - c * L3);
    s[2] = L3 - a * (sn * L3 + c * L2);
    s[4] = G2 - a * (sn * G2 - c * G3);
    s[5] = G3 - a * (sn * G3 + c * G2);
    s[6] = q0 * c - q1 * sn;
    s[7] = q1 * c + q0 * sn;
    s[8] = q2 * c + q3 * sn;
    s[9] = q3 * c - q2 * sn;
}

static void turn2(double *s, double half)
{
    const double c = cos(half), sn = sin(half), a = 2.0 * sn;
    const double L1 = s[0], L3 = s[2], G1 = s[3], G3 = s[5], q0 = s[6], q1 = s[7], q2 = s[8], q3 = s[9];
    s[0] = L1 - a * (sn * L1 + c * L3);
    s[2] = L3 - a * (sn * L3 - c * L1);
    s[3] = G1 - a * (sn * G1 + c * G3);
    s[5] = G3 - a * (sn * G3 - c * G1);
    s[6] = q0 * c - q2 * sn;
    s[7] = q1 * c - q3 * sn;
    s[8] = q2 * c + q0 * sn;
    s[9] = q3 * c + q1 * sn;
}

static void turn3(double *s, double half)
{
    const double c = cos(half), sn = sin(half), a = 2.0 * sn;
    const double L1 = s[0], L2 = s[1], G1 = s[3], G2 = s[4], q0 = s[6], q1 = s[7], q2 = s[8], q3 = s[9];
    s[0] = L1 - a * (sn * L1 - c * L2);
    s[1] = L2 - a * (sn * L2 + c * L1);
    s[3] = G1 - a * (sn * G1 - c * G2);
    s[4] = G2 - a * (sn * G2 + c * G1);
    s[6] = q0 * c - q3 * sn;
    s[7] = q1 * c + q2 * sn;
    s[8] = q2 * c - q1 * sn;
    s[9] = q3 * c + q0 * sn;
}

static void free_axes(double *s, double tau, const eulersym_pivoted_params *par)
{
    const double quarter = 0.25 * tau;
    turn1(s, quarter * (s[0] - par->rotor[0]) * par->inv_moments[0]);
    turn2(s, quarter * (s[1] - par->rotor[1]) * par->inv_moments[1]);
    turn3(s, 0.5 * tau * (s[2] - par->rotor[2]) * par->inv_moments[2]);
    turn2(s, quarter * (s[1] - par->rotor[1]) * par->inv_moments[1]);
    turn1(s, quarter * (s[0] - par->rotor[0]) * par->inv_moments[0]);
}

/* The symmetric body's exact free flow: about L at the rate |L|/I1, then about e3 at (L3 - h3)/I3 - L3/I1. */
static void free_symmetric(double *s, double tau, const eulersym_pivoted_params *par)
{
    const double i1 = par->inv_moments[0];
    const double L1 = s[0], L2 = s[1], L3 = s[2], G1 = s[3], G2 = s[4], G3 = s[5];
    const double q0 = s[6], q1 = s[7], q2 = s[8], q3 = s[9];
    /* p = exp(tau omega / 2), omega = L / I1: eulersym.attitude.rotvec_to_quaternion (one small-angle rule) */
    const double k = tau * i1, v0 = k * L1, v1 = k * L2, v2 = k * L3;
    const double angle = pow(v0 * v0 + v1 * v1 + v2 * v2, 0.5);
    const double small = angle < SMALL_ROTATION ? 1.0 : 0.0, safe = angle + small;
    const double c = cos(0.5 * angle), sn = sin(0.5 * safe);
    const double f = sn / safe * (1.0 - small) + 0.5 * small;
    const double p0 = c, p1 = f * v0, p2 = f * v1, p3 = f * v2;
    /* Gamma <- R(p)^T Gamma = R(p*) Gamma: v + 2 u x (u x v + p0 v), u = -(p1, p2, p3) (eulersym.attitude.rotate) */
    const double n1 = -p1, n2 = -p2, n3 = -p3;
    const double w0 = (n2 * G3 - n3 * G2) + p0 * G1;
    const double w1 = (n3 * G1 - n1 * G3) + p0 * G2;
    const double w2 = (n1 * G2 - n2 * G1) + p0 * G3;
    s[3] = G1 + 2.0 * (n2 * w2 - n3 * w1);
    s[4] = G2 + 2.0 * (n3 * w0 - n1 * w2);
    s[5] = G3 + 2.0 * (n1 * w1 - n2 * w0);
    /* q <- q (x) p */
    s[6] = q0 * p0 - q1 * p1 - q2 * p2 - q3 * p3;
    s[7] = q0 * p1 + q1 * p0 + q2 * p3 - q3 * p2;
    s[8] = q0 * p2 - q1 * p3 + q2 * p0 + q3 * p1;
    s[9] = q0 * p3 + q1 * p2 - q2 * p1 + q3 * p0;
    turn3(s, 0.5 * tau * ((L3 - par->rotor[2]) * par->inv_moments[2] - L3 * i1));
}

static void kick(double *s, double tau, const eulersym_pivoted_params *par)
{
    const double k1 = tau * par->mgc[0], k2 = tau * par->mgc[1], k3 = tau * par->mgc[2];
    const double G1 = s[3], G2 = s[4], G3 = s[5];
    s[0] = s[0] + (G2 * k3 - G3 * k2);
    s[1] = s[1] + (G3 * k1 - G1 * k3);
    s[2] = s[2] + (G1 * k2 - G2 * k1);
}

/* |q| = |Gamma| = 1 and L.Gamma = par->l_dot_gamma again (changes at round-off level). */
static void renormalise(double *s, const eulersym_pivoted_params *par)
{
    const double r = 1.0 / pow(s[6] * s[6] + s[7] * s[7] + s[8] * s[8] + s[9] * s[9], 0.5);
    const double rg = 1.0 / pow(s[3] * s[3] + s[4] * s[4] + s[5] * s[5], 0.5);
    const double G1 = s[3] * rg, G2 = s[4] * rg, G3 = s[5] * rg;
    const double d = par->l_dot_gamma - (s[0] * G1 + s[1] * G2 + s[2] * G3);
    s[0] = s[0] + d * G1;
    s[1] = s[1] + d * G2;
    s[2] = s[2] + d * G3;
    s[3] = G1;
    s[4] = G2;
    s[5] = G3;
    s[6] = s[6] * r;
    s[7] = s[7] * r;
    s[8] = s[8] * r;
    s[9] = s[9] * r;
}

int eulersym_pivoted_step(double s[10], double h, const eulersym_pivoted_params *par, int method, int free_flow)
{
    const double strang[1] = {${STRANG}};
    const double yoshida4[3] = {${YOSHIDA4}};
    const double yoshida6[7] = {${YOSHIDA6}};
    const double *fractions;
    int n, i, k;
    if (method == EULERSYM_PIVOTED_STRANG) {
        fractions = strang;
        n = 1;
    } else if (method == EULERSYM_PIVOTED_YOSHIDA4) {
        fractions = yoshida4;
        n = 3;
    } else if (method == EULERSYM_PIVOTED_YOSHIDA6) {
        fractions = yoshida6;
        n = 7;
    } else {
        return 1;
    }
    if (free_flow != EULERSYM_PIVOTED_AXES && free_flow != EULERSYM_PIVOTED_SYMMETRIC)
        return 1;
    for (i = 0; i < n; i++) {
        const double tau = fractions[i] * h;
        kick(s, 0.5 * tau, par);
        if (free_flow == EULERSYM_PIVOTED_AXES)
            free_axes(s, tau, par);
        else
            free_symmetric(s, tau, par);
        kick(s, 0.5 * tau, par);
    }
    renormalise(s, par);
    for (k = 0; k < 10; k++)
        if (!isfinite(s[k]))
            return 2;
    return 0;
}
"""


def _numbers(values) -> str:
    return ", ".join(repr(float(v)) for v in values)


def library_files() -> dict[str, str]:
    """``{file name: text}`` of the C library (the free body's exact ω(t), the pivoted body's splitting step).

    Examples
    --------
    >>> "eulersym_free_body_omega" in library_files()["eulersym_free_body.h"]
    True
    """
    from eulersym.attitude import SMALL_ROTATION
    from eulersym.numerics._doubledouble import PI
    from eulersym.numerics.pivoted import COMPOSITIONS

    values = {"PI_HI": repr(PI[0]), "PI_LO": repr(PI[1]), "SMALL_ROTATION": repr(SMALL_ROTATION),
              "STRANG": _numbers(COMPOSITIONS["strang"]),
              "YOSHIDA4": _numbers(COMPOSITIONS["yoshida4"]), "YOSHIDA6": _numbers(COMPOSITIONS["yoshida6"])}
    texts = {"eulersym_free_body.h": _FREE_BODY_H, "eulersym_free_body.c": _FREE_BODY_C,
             "eulersym_pivoted.h": _PIVOTED_H, "eulersym_pivoted.c": _PIVOTED_C}
    return {name: Template(text).substitute(values) for name, text in texts.items()}
