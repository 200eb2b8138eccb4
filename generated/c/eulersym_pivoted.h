/* Written by `eulersym generate --target c` from eulersym.codegen.c_library. Do not edit: regenerate.
 *
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
