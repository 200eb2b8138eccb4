"""The heavy top's closed form vectorised over the members of a sweep: constants in double precision, all members
at once (the vectorised Carlson integrals and Jacobi functions of :mod:`eulersym.numerics.elliptic`).

Same formulas as :mod:`eulersym.numerics.heavy_top_exact`, but the constants of each motion (roots, λ, K, τ0, the
rates) are computed in double rather than 36-digit decimal arithmetic and the phase is not reduced in
double-double, so the error grows like ~1e-16 × (number of nutation periods) instead of staying at round-off; it
is ~1e-13 relative to ω after 10³ periods. Members this path does not treat — a steady motion (double root), a
start at or near a pole (``1 ∓ w`` below 1e-6 at a turning point), a motion near the separatrix (``m_c < 1e-12``),
or a nutation too small to resolve in double (``Δ < 1e-6``) — are returned in a mask for the precise per-member
path.
"""

from __future__ import annotations

import math

import numpy as np

from eulersym.numerics.elliptic import _rf, _rj, _sncndn, _third_kind

__all__ = ["batch_motion"]


def _jacobi(u, mc):
    """sn, cn, dn of u (B, n) for complementary parameters mc (B, 1), 1e-12 ≤ mc ≤ 1: the algorithm of
    :func:`eulersym.numerics.elliptic.jacobi_sncndn` (descending Landen from √m_c, quarter-period reflection), with a
    fixed number of AGM levels so that every member runs the same array operations."""
    rootmc = np.sqrt(mc)
    a, b = np.ones_like(rootmc), rootmc
    avals, bvals = [], []
    for _ in range(12):  # from √m_c ≥ 1e-6 the AGM has converged to the last bit after ≤ 9 levels
        avals.append(a)
        bvals.append(b)
        a, b = 0.5 * (a + b), np.sqrt(a * b)
    agm = 0.5 * (a + b)
    return _sncndn(u, rootmc, (avals, bvals, agm))


def _quadratic_roots(A, B, C):
    """Roots (smaller, larger) of A x² + B x + C with C ≤ 0 < A (opposite signs): stable formula."""
    disc = np.sqrt(np.maximum(B * B - 4 * A * C, 0.0))
    qq = -0.5 * (B + np.where(B >= 0, disc, -disc))
    safe = np.where(qq == 0, 1.0, qq)
    r1, r2 = qq / A, np.where(qq == 0, 0.0, C / safe)
    return np.minimum(r1, r2), np.maximum(r1, r2)


def _cubic(A, B, C, D, x):
    return ((A * x + B) * x + C) * x + D


def _W(s, c, n, one_minus_n, mc):
    """∫₀ˣ dy/(1 − n sn² y) from s = |sn x|, c = |cn x| (0 ≤ x ≤ K), vectorised."""
    c2 = c * c
    return _third_kind(s, c2, c2 + mc * s * s, n, one_minus_n + n * c2)


def batch_motion(I1, I3, mgl, omega, q, t):
    with np.errstate(invalid="ignore", divide="ignore"):  # the rows left to the precise path may be nan here
        return _batch_motion(I1, I3, mgl, omega, q, t)


def _batch_motion(I1, I3, mgl, omega, q, t):
    """Constants and motion of B members at the times t (n,): returns (ok (B,), omega, gamma, q, euler, period,
    turning) with the motion arrays of shape (B, n, ·); rows where ``ok`` is False are to be computed precisely."""
    I1, I3, mgl = (np.asarray(x, dtype=float) for x in (I1, I3, mgl))
    w = np.asarray(omega, dtype=float)
    qn = np.asarray(q, dtype=float)
    qn = qn / np.sqrt(np.sum(qn * qn, axis=1, keepdims=True))
    q0, q1, q2, q3 = qn.T
    G1, G2, G3 = 2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3
    beta = 2 * mgl / I1
    sigma = np.where(beta > 0, 1.0, -1.0)
    a = I3 * w[:, 2] / I1
    wpar = w[:, 0] * G1 + w[:, 1] * G2
    wperp = G1 * w[:, 1] - G2 * w[:, 0]
    s2 = G1 * G1 + G2 * G2
    wt2 = w[:, 0] ** 2 + w[:, 1] ** 2
    u0 = G3
    w0 = sigma * u0
    one_m_w0 = np.where(w0 > 0, s2 / (1 + np.abs(w0)), 1 - w0)
    one_p_w0 = np.where(w0 < 0, s2 / (1 + np.abs(w0)), 1 + w0)
    f1 = -2 * u0 * wt2 - beta * s2 + 2 * a * wpar
    f2 = 2 * beta * u0 - wt2 - a * a
    A, B, C, D = np.abs(beta), f2, sigma * f1, wperp * wperp
    Bn = wpar - sigma * a * one_m_w0
    Bf = wpar + sigma * a * one_p_w0
    nu = w[:, 2] - a
    nu_near, nu_far = np.where(sigma > 0, -nu, nu), np.where(sigma > 0, nu, -nu)
    # the largest root: Newton from above the Cauchy bound (the cubic is convex there: monotone convergence)
    x3 = np.maximum(one_m_w0, 0.0) + 1.0 + np.maximum(np.abs(B), np.maximum(np.abs(C), np.abs(D))) / A
    for _ in range(200):
        g = _cubic(A, B, C, D, x3)
        dg = (3 * A * x3 + 2 * B) * x3 + C
        step = np.where(dg > 0, g / np.where(dg > 0, dg, 1.0), 0.0)
        x3 = x3 - step
        if np.all(np.abs(step) <= 1e-16 * np.abs(x3)):
            break
    Bq = B + A * x3
    Cq = -D / np.where(x3 > 0, x3, 1.0)
    x1, x2 = _quadratic_roots(A, Bq, Cq)
    # released at a turning point (u̇0 = 0): x = 0 is a root exactly; the others from the deflated quadratic
    at_turn = D == 0
    r_lo, r_hi = _quadratic_roots(A, B, np.where(C < 0, C, -1.0))  # C < 0: x1 < 0 = x2 < x3
    disc = np.sqrt(np.maximum(B * B - 4 * A * C, 0.0))  # C > 0: 0 = x1 < x2 ≤ x3, both roots positive
    qq = -0.5 * (B - disc)
    p_lo = np.where(qq > 0, C / np.where(qq > 0, qq, 1.0), 0.0)
    p_hi = qq / A
    x1 = np.where(at_turn, np.where(C < 0, r_lo, 0.0), x1)
    x2 = np.where(at_turn, np.where(C < 0, 0.0, np.minimum(p_lo, p_hi)), x2)
    x3 = np.where(at_turn, np.where(C < 0, r_hi, np.maximum(p_lo, p_hi)), x3)
    for _ in range(2):  # polish the roots near the start on the cubic itself (accurate near x = 0)
        for x in (x1, x2):
            dg = (3 * A * x + 2 * B) * x + C
            x -= np.where((dg != 0) & (D > 0), _cubic(A, B, C, D, x) / np.where(dg != 0, dg, 1.0), 0.0)
    x1, x2 = np.minimum(x1, 0.0), np.maximum(x2, 0.0)
    delta = x2 - x1
    span = x3 - x1
    y2 = one_m_w0 - x2
    z1 = one_p_w0 + x1
    mc = (x3 - x2) / span
    m = delta / span
    ok = ~((D == 0) & (C == 0)) & (delta > 1e-6) & (mc > 1e-12) & (y2 > 1e-6) & (z1 > 1e-6) & (x3 > 0) & np.isfinite(span)
    ok &= (Bn != 0) & (Bf != 0)
    # for the members this path does not treat, harmless placeholders (their rows are replaced)
    fill = ~ok
    delta, span, mc, m = (np.where(fill, v, x) for v, x in ((1.0, delta), (2.0, span), (0.5, mc), (0.5, m)))
    y2, z1 = np.where(fill, 0.5, y2), np.where(fill, 0.5, z1)
    lam = np.sqrt(A * span) / 2
    K = _rf(0.0, mc, 1.0)
    s_sq, c_sq, d_sq = np.clip(-x1 / delta, 0, 1), np.clip(x2 / delta, 0, 1), x3 / span
    d_sq = np.where(fill, 0.5, d_sq)
    F = np.sqrt(s_sq) * _rf(c_sq, d_sq, 1.0)
    tau0 = np.where(sigma * wperp < 0, -F, F)
    n_n, n_n1 = delta / (y2 + delta), y2 / (y2 + delta)
    coef_n = Bn / (lam * (y2 + delta))
    half_n = _rf(0.0, mc, 1.0) + n_n / 3 * _rj(0.0, mc, 1.0, n_n1)
    per_n = coef_n * 2 * half_n
    n_f, n_f1 = (z1 * m + delta) / (z1 + delta), z1 * mc / (z1 + delta)
    m_over_n = m * (z1 + delta) / (z1 * m + delta)
    rate_f = nu_far + Bf * m_over_n / (z1 + delta)
    coef_f = Bf * delta * mc / (z1 * m + delta) / (lam * (z1 + delta))
    half_f = _rf(0.0, mc, 1.0) + n_f / 3 * _rj(0.0, mc, 1.0, n_f1)
    per_f = coef_f * 2 * half_f
    W0n = np.sign(tau0) * _W(np.sqrt(s_sq), np.sqrt(c_sq), n_n, n_n1, mc)
    # τ0 − K: sn² = cd² τ0, cn² = k′² sd² τ0; in [−2K, 0], wrapped by 2K (one half period back) when τ0 < 0
    S, Cc = np.sqrt(c_sq / d_sq), np.sqrt(mc * s_sq / d_sq)
    W0f_abs = _W(S, Cc, n_f, n_f1, mc)
    x0 = tau0 - K  # as the evaluation below reduces it (a τ0 within rounding of 0 may land on either side)
    low0 = x0 < -K
    x0 = np.where(low0, x0 + 2 * K, x0)
    W0f, j0f = np.sign(x0) * W0f_abs, np.where(low0, -1.0, 0.0)
    # the angles at t = 0 from q0 (amplitudes positive off the poles)
    near_pair, far_pair = np.where(sigma[:, None] > 0, [[1, 2]], [[0, 3]]), np.where(sigma[:, None] > 0, [[0, 3]], [[1, 2]])
    rows = np.arange(len(sigma))
    chi_n0 = 2 * np.arctan2(qn[rows, near_pair[:, 1]], qn[rows, near_pair[:, 0]])
    chi_f0 = 2 * np.arctan2(qn[rows, far_pair[:, 1]], qn[rows, far_pair[:, 0]])

    # ---- the motion at the times (B, n) --------------------------------------------------------------------------
    tt = np.asarray(t, dtype=float)[None, :]
    col = lambda v: np.asarray(v)[:, None]  # noqa: E731
    tau = col(lam) * tt + col(tau0)
    j = np.round(tau / col(2 * K))
    r = tau - j * col(2 * K)
    sn, cn, dn = _jacobi(r, col(mc))
    parity = 1.0 - 2.0 * np.mod(j, 2.0)
    sn_t, cn_t = parity * sn, parity * cn
    dl = col(delta)
    rn = np.sqrt(col(y2) + dl * cn * cn)
    rf = np.sqrt(col(z1) + dl * sn * sn)
    sd = np.sqrt(dl)
    ratio_n, ratio_f = sd * cn_t / rn, sd * sn_t / rf
    # W of the near pole at r (|r| ≤ K), of the far pole at r − K (wrapped to [−K, K])
    Wn = np.sign(r) * _W(np.abs(sn), np.abs(cn), col(n_n), col(n_n1), col(mc))
    x = r - col(K)
    low = x < -col(K)
    x = np.where(low, x + col(2 * K), x)
    jf = np.where(low, j - 1.0, j)
    # |sn|, |cn| at r − K (or r + K): |cd r| and k′ |sd r| — no second Jacobi evaluation
    Wf = np.sign(x) * _W(np.abs(cn / dn), np.sqrt(col(mc)) * np.abs(sn / dn), col(n_f), col(n_f1), col(mc))
    four_pi = 4 * math.pi
    chi_n = np.mod(col(nu_near) * tt + col(per_n) * j, four_pi) + col(chi_n0) + col(coef_n) * (Wn - col(W0n))
    chi_f = np.mod(col(rate_f) * tt + col(per_f) * (jf - col(j0f)), four_pi) + col(chi_f0) + col(coef_f) * (Wf - col(W0f))
    half_near, half_far = rn / math.sqrt(2.0), rf / math.sqrt(2.0)
    out_q = np.empty(r.shape + (4,))
    pos = col(sigma) > 0
    a0, a1 = np.where(pos, 1, 0), np.where(pos, 2, 3)  # near pair indices
    b0, b1 = np.where(pos, 0, 1), np.where(pos, 3, 2)  # far pair indices
    cn_n, sn_n = half_near * np.cos(0.5 * chi_n), half_near * np.sin(0.5 * chi_n)
    cf, sf = half_far * np.cos(0.5 * chi_f), half_far * np.sin(0.5 * chi_f)
    out_q[..., 0] = np.where(pos, cf, cn_n)
    out_q[..., 3] = np.where(pos, sf, sn_n)
    out_q[..., 1] = np.where(pos, cn_n, cf)
    out_q[..., 2] = np.where(pos, sn_n, sf)
    del a0, a1, b0, b1
    out_q /= np.sqrt(np.sum(out_q * out_q, axis=-1, keepdims=True))
    chi_plus, chi_minus = np.where(pos, chi_f, chi_n), np.where(pos, chi_n, chi_f)
    cp, sp_ = np.cos(0.5 * chi_plus), np.sin(0.5 * chi_plus)
    cm, sm = np.cos(0.5 * chi_minus), np.sin(0.5 * chi_minus)
    cos_psi, sin_psi = cp * cm + sp_ * sm, sp_ * cm - cp * sm
    A_ = 0.5 * col(Bn) * rf / rn + 0.5 * col(Bf) * rn / rf
    B_ = col(sigma) * 2.0 * col(lam) * dn * ratio_n * ratio_f
    out_w = np.stack([A_ * sin_psi - B_ * cos_psi, A_ * cos_psi + B_ * sin_psi,
                      np.broadcast_to(col(w[:, 2]), r.shape)], axis=-1)
    s_theta = rn * rf
    rn2, rf2 = rn * rn, rf * rf
    ww = np.where(rn2 < rf2, 1.0 - rn2, rf2 - 1.0)
    out_g = np.stack([s_theta * sin_psi, s_theta * cos_psi, col(sigma) * ww], axis=-1)
    Sh, Ch = np.where(pos, half_near, half_far), np.where(pos, half_far, half_near)
    theta = 2.0 * np.arctan2(Sh, Ch)
    wrap = lambda v: np.mod(v + math.pi, 2 * math.pi) - math.pi  # noqa: E731
    euler = np.stack([wrap(0.5 * (chi_plus + chi_minus)), theta, wrap(0.5 * (chi_plus - chi_minus))], axis=-1)
    period = 2 * K / lam
    turning = np.sort(np.stack([sigma * (w0 + x1), sigma * (w0 + x2)], axis=1), axis=1)
    return ok, out_w, out_g, out_q, euler, period, turning
