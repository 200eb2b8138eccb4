/* Written by `eulersym generate --target c` from eulersym.codegen.c_library. Do not edit: regenerate.
 * The torque-free body's exact omega(t); see eulersym_free_body.h.
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
    const double pi = 3.141592653589793;
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
    const dd pi = {3.141592653589793, 1.2246467991473532e-16};
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
