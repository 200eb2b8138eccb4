/* Written by `eulersym generate --target c` from eulersym.codegen.c_library. Do not edit: regenerate.
 * One step of the exact-flow splitting of a pivoted body; see eulersym_pivoted.h.
 */

#include <math.h>

#include "eulersym_pivoted.h"

/* Below this angle sin(x/2)/x rounds to 1/2 (eulersym.attitude.SMALL_ROTATION). */
#define SMALL_ROTATION 1.4901161193847656e-08

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
    const double strang[1] = {1.0};
    const double yoshida4[3] = {1.3512071919596578, -1.7024143839193153, 1.3512071919596578};
    const double yoshida6[7] = {0.78451361047756, 0.235573213359357, -1.17767998417887, 1.3151863206839063, -1.17767998417887, 0.235573213359357, 0.78451361047756};
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
