/* Written by `eulersym generate --target c` from eulersym.codegen.c_library. Do not edit: regenerate.
 *
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
