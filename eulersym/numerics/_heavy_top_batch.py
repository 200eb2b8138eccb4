"""The heavy top's closed form vectorised over the members of a sweep: constants in double precision, all members
at once (the vectorised Carlson integrals and Jacobi functions of :mod:`eulersym.numerics.elliptic`).

Same formulas as :mod:`eulersym.numerics.heavy_top_exact`, but the constants of each motion (roots, λ, K, τ0, the
rates) are computed in double rather than 36-digit decimal arithmetic and the phase is not reduced in
double-double, so the error grows with the number of nutation periods instead of staying at round-off: by ε·λ·t
from the phase and by m_c's own rounding, at most :data:`CONDITION_ULPS` ulp (~1e-14 a period), and by the other constants in double: below ~3e-13 a period
in all (tests/test_numerics_closed_form_edges.py, against the precise path). Members this
path does not treat — a steady motion (double root), a start at or near a pole (``1 ∓ w`` below 1e-6 at a turning
point), a motion whose m_c the cubic's rounding moves by more than that (next to the separatrix, where two roots
nearly meet; with an accuracy asked: by more than a tenth of it over the times' phase), or a nutation too small to
resolve in double (``Δ < 1e-6``) — are returned in a mask for the precise per-member path.
"""

from __future__ import annotations

import math

import numpy as np

from eulersym.numerics.elliptic import _agm_landen_columns, _rf, _rj, _sncndn, _sncndn_within, _third_kind

__all__ = ["batch_motion"]


def _jacobi(u, mc, landen=None):
    """sn, cn, dn of u (B, n) for complementary parameters mc (B, 1): the algorithm of
    :func:`eulersym.numerics.elliptic.jacobi_sncndn` (descending Landen from √m_c, quarter-period reflection)."""
    rootmc = np.sqrt(mc)
    return _sncndn(u, rootmc, _agm_landen_columns(rootmc) if landen is None else landen)


def _quadratic_roots(A, B, C):
    """Roots (smaller, larger) of A x² + B x + C with C ≤ 0 < A (opposite signs): stable formula."""
    disc = np.sqrt(np.maximum(B * B - 4 * A * C, 0.0))
    qq = -0.5 * (B + np.where(B >= 0, disc, -disc))
    safe = np.where(qq == 0, 1.0, qq)
    r1, r2 = qq / A, np.where(qq == 0, 0.0, C / safe)
    return np.minimum(r1, r2), np.maximum(r1, r2)


#: Harmonics of the third-kind integrands' cosine series (:func:`_W_series`): sampled at N + 1 nodes of the half
#: period, of which the Jacobi functions are evaluated at N/2 + 1 (the others by sn²(K − y) = cn² y/dn² y).
SERIES_N = 32
#: ... for members whose m_c is at least this (below, the cosine series would need more harmonics: the complementary
#: nome's few terms instead, :func:`_W_complementary`).
SERIES_MC = 0.3


def _dct1(N):
    """The DCT-I as a matrix: values at θ_i = iπ/N (i = 0 … N) → c_k of Σ c_k cos kθ (c_0, c_N halved)."""
    i = np.arange(N + 1)
    w = np.where((i == 0) | (i == N), 0.5, 1.0)
    M = (2.0 / N) * w[:, None] * np.cos(np.pi * np.outer(i, i) / N)
    M[:, 0] *= 0.5
    M[:, N] *= 0.5
    return M


_DCT = {}


def _W_series(mc, landen, K, characteristics):
    """The sine-series parts of ∫₀ˣ dy/(1 − n sn² y) = c_0·x + Σ_{k=1}^{N} b_k sin(kπx/K) per member and
    characteristic n (columns (B, 1)), from the cosine series Σ c_k cos(kπy/K) of the integrand (period 2K, even)
    fitted at N + 1 nodes of [0, K] (no elliptic integral). Returns c_0 (P, B, 1), b (P, B, N) and a mask (B,) of
    the members whose every series has converged: its last three coefficients below 16 ε of c_0."""
    N = SERIES_N
    M = _DCT.get(N)
    if M is None:
        M = _DCT[N] = _dct1(N)
    half = N // 2
    y = K * (np.arange(half + 1) / N)[None, :]
    sn, cn, dn = _sncndn_within(y, np.sqrt(mc), landen)  # 0 ≤ y ≤ K/2
    s2 = np.empty((mc.shape[0], N + 1))
    s2[:, :half + 1] = sn * sn
    s2[:, N:half - 1:-1] = (cn / dn) ** 2  # sn²(K − y) = cd² y
    c0 = np.empty((len(characteristics), mc.shape[0], 1))
    out = np.empty((len(characteristics), mc.shape[0], N))
    ok = np.ones(mc.shape[0], dtype=bool)
    k = np.arange(1, N + 1)
    for p, n in enumerate(characteristics):
        c = (1.0 / (1.0 - n * s2)) @ M  # c_0 … c_N
        ok &= np.isfinite(c).all(axis=1) & (np.abs(c[:, -3:]).sum(axis=1) <= 16 * 2.0 ** -52 * np.abs(c[:, 0]))
        c0[p] = c[:, :1]
        out[p] = c[:, 1:] * (K / (np.pi * k))
    return c0, out, ok


def _sine_series(b, c2, s1):
    """Σ_k b_k sin kθ by Clenshaw's recurrence, from b (P, B, N), 2 cos θ and sin θ (P, B, n)."""
    u1 = np.zeros_like(c2)
    u2 = np.zeros_like(c2)
    u = np.empty_like(c2)
    for k in range(b.shape[-1] - 1, -1, -1):  # three buffers in turn: no allocation a step
        np.multiply(c2, u1, out=u)
        u -= u2
        u += b[:, :, k, None]
        u, u1, u2 = u2, u, u1
    return u1 * s1


def _cubic(A, B, C, D, x):
    return ((A * x + B) * x + C) * x + D


def _W(s, c, n, one_minus_n, mc):
    """∫₀ˣ dy/(1 − n sn² y) from s = |sn x|, c = |cn x| (0 ≤ x ≤ K), vectorised."""
    c2 = c * c
    return _third_kind(s, c2, c2 + mc * s * s, n, one_minus_n + n * c2)


#: Terms of the complementary theta series (:func:`_W_complementary`) are kept down to this size.
_TERMS_BELOW = 2.0 ** -56


def _W_complementary(u, n, n1, nm, mc, m, K, Pi, Kp=None):
    """∫₀ᵘ dy/(1 − n sn²(y|m)) for |u| ≤ K by Jacobi's imaginary transformation: a few terms in the complementary
    nome q′ = exp(−πK/K′) (6e-5 at m_c = 1e-3), for the members whose nome series converge slowly (small m_c).

    Columns (B, 1): ``n``, ``n1 = 1 − n``, ``nm = n − m`` (formed by the caller where it keeps its digits), ``mc``,
    ``m``, ``K = K(m)``, ``Pi = Π(n|m)`` and (optional) ``Kp = K(m_c)``; ``u`` (B, T). With Jacobi's form
    ``W = u + c·(u Z(a) + ½ ln Θ(u−a)/Θ(u+a))``, ``n = m sn² a``, ``c = sn a/(cn a dn a)``, its secular part ``u Π/K``
    apart, and Θ turned into the complementary variables (h = π/(2K′), V = K − |u|)

        Θ(w) ∝ exp(−h w²/(2K)) · C(hw),   C(x) = Σ_{j≥0} q′^{j(j+1)} cosh((2j+1)x),

    - 0 < n < m (a = K − a′ real, sn²(a′|m) = (m − n)/(m(1 − n)), c² = n/((m − n)(1 − n))):
      ``W = |u| Π/K + (c/2)·[2hVa′/K + ln C(h(V − a′)) − ln C(h(V + a′))]``;
    - m < n < 1 (a = K + ib, dn²(b|m_c) = m/n, b′ = K′ − b, ρ² = (1 − n)(n − m)/n):
      ``W = |u| Π/K − (1/ρ)·[arg C(h(V + ib)) − hVb/K]``;

    times sign u. Each bracket is formed from differences that keep their digits: ln cosh(x − y) − ln cosh(x + y) =
    −2 atanh(tanh x tanh y), cosh((2j+1)x)/cosh x = (−1)ʲ(1 + 2 Σ_{i≤j} (−1)ⁱ cosh 2ix), arg cosh(X + iY) =
    atan2(tanh X sin Y, cos Y) with cos Y = sin(hb′); b and b′ each from its own R_F. Accuracy: ~4e-15 of
    max(|W|, Π) (the phase's scale: the motion takes coef·W, and coef·Π is its advance a half period) for m_c from
    1e-12 to 0.3 on both sides of n = m and up to n → 1, besides the argument's own rounding magnified by W′ next to
    a pole (tests/test_numerics_heavy_top_complementary.py, against mpmath)."""
    Kp = _rf(0.0, m, 1.0) if Kp is None else Kp
    h = math.pi / (2.0 * Kp)
    qp = np.exp(-2.0 * h * K)
    U = np.abs(u)
    out = np.empty_like(U)
    J = 1  # the terms beyond j = J are below q′^{j(j−1)} (arguments up to 2K)
    qmax = float(qp.max()) if qp.size else 0.0
    while qmax ** (J * (J + 1)) > _TERMS_BELOW:
        J += 1
    circ = nm[:, 0] > 0
    rows = np.flatnonzero(~circ)
    if rows.size:
        n_, n1_, nm_, mc_, m_, K_, Pi_, h_, q_ = (v[rows] for v in (n, n1, nm, mc, m, K, Pi, h, qp))
        ap = np.sqrt(-nm_ / (m_ * n1_)) * _rf(mc_ * n_ / (m_ * n1_), mc_ / n1_, 1.0)
        x = h_ * (K_ - U[rows])
        y = h_ * ap
        tt = np.tanh(x) * np.tanh(y)
        far = tt > 0.5  # atanh near 1 loses digits: the logarithms instead, −2 min(x, y) + …
        main = np.where(far, np.log1p(np.exp(-2.0 * np.abs(x - y))) - np.log1p(np.exp(-2.0 * (x + y)))
                        - 2.0 * np.minimum(x, y), -2.0 * np.arctanh(np.where(far, 0.0, tt)))
        main += x * (2.0 * ap / K_)
        dD = np.zeros_like(x)  # Σ q′^{j(j+1)} (f_j(x − y) − f_j(x + y)), f_j = cosh((2j+1)·)/cosh
        Dp = np.ones_like(x)  # 1 + Σ q′^{j(j+1)} f_j(x + y)
        xp = x + y
        for j in range(1, J + 1):
            sign, w = (-1.0) ** j, q_ ** (j * (j + 1))
            for i in range(1, j + 1):
                si = sign * (-1.0) ** i
                dD -= (4.0 * si * w * np.sinh(2 * i * y)) * np.sinh(2 * i * x)
                Dp += (2.0 * si * w) * np.cosh(2 * i * xp)
            Dp += sign * w
        main += np.log1p(dD / Dp)
        out[rows] = U[rows] * (Pi_ / K_) + (0.5 * np.sqrt(n_ / (-nm_ * n1_))) * main
    rows = np.flatnonzero(circ)
    if rows.size:
        n_, n1_, nm_, mc_, m_, K_, Pi_, h_, q_ = (v[rows] for v in (n, n1, nm, mc, m, K, Pi, h, qp))
        b = np.sqrt(nm_ / (n_ * mc_)) * _rf(m_ * n1_ / (n_ * mc_), m_ / n_, 1.0)
        bp = np.sqrt(n1_ / mc_) * _rf(nm_ / mc_, n_, 1.0)
        sY, cY = np.sin(h_ * b), np.sin(h_ * bp)  # Y = hb, cos Y = sin(hb′)
        X = h_ * (K_ - U[rows])
        # C(x)/cosh x = 1 + Σ_{j≥1} q′^{j(j+1)} z^{−j} Σ_{i≤2j} (−z)^i, z = e^{−2x} = E e^{−2iY}, E = e^{−2X}:
        # 1 + Σ_{|k|≤J} c_k z^k, c_k = c_{−k} = Σ_{j≥max(|k|,1)} (−1)^{j+k} q′^{j(j+1)} — real polynomials in E, 1/E
        # with the members' cos 2kY, sin 2kY
        em = np.expm1(-2.0 * X)
        E = 1.0 + em
        tX = -em / (2.0 + em)  # tanh X
        re = np.ones_like(X)
        im = np.zeros_like(X)
        c2, s2 = cY * cY - sY * sY, 2.0 * sY * cY  # cos 2Y, sin 2Y
        ck, sk = np.ones_like(c2), np.zeros_like(s2)
        Ek, Ei = np.ones_like(X), 1.0 / E
        Eik = np.ones_like(X)
        for k in range(J + 1):
            c = sum((-1.0) ** (j + k) * q_ ** (j * (j + 1)) for j in range(max(k, 1), J + 1))
            if k == 0:
                re += c
                continue
            ck, sk = ck * c2 - sk * s2, sk * c2 + ck * s2
            Ek = Ek * E
            Eik = Eik * Ei
            re += (c * ck) * (Ek + Eik)
            im -= (c * sk) * (Ek - Eik)
        # arg of cosh(X + iY)/cosh X = cos Y + i tanh X sin Y, times 1 + Σ c_k z^k: one atan2 (|Σ| < 3q′: no wrap)
        tX *= sY
        ang = np.arctan2(tX * re + cY * im, cY * re - tX * im)
        ang -= X * (b / K_)
        out[rows] = U[rows] * (Pi_ / K_) - ang / np.sqrt(n1_ * nm_ / n_)
    return np.copysign(out, u)


#: A member stays on this path where the relative error of its m_c (from the rounding of the cubic's coefficients,
#: moved over the gap between its two nearest roots) is at most this many ulp: the phase then errs by at most
#: ~this × ε (1.4e-14) per nutation period.
CONDITION_ULPS = 64.0


def batch_motion(I1, I3, mgl, omega, q, t, accuracy=None, *, attitude=True):
    with np.errstate(invalid="ignore", divide="ignore"):  # the rows left to the precise path may be nan here
        return _batch_motion(I1, I3, mgl, omega, q, t, accuracy, attitude=attitude)


def _conditioning(A, B, C, D, Bmag, Cmag, x1, x2, x3):
    """The relative error of m_c = (x3 − x2)/(x3 − x1) in double: each root of the cubic moves by the rounding of
    the cubic there (its terms' sizes, a few ε each: ``Bmag``, ``Cmag`` are the sums of the sizes of the terms B and
    C were formed from, ε each) over the cubic's slope ``A (x − x_i)(x − x_j)``; m_c's two differences by both roots'."""
    eps = 2.0 ** -52

    def moved(x, a, b):
        slope = A * np.abs((x - a) * (x - b))
        return 2.0 * eps * (A * np.abs(x) ** 3 + Bmag * x * x + Cmag * np.abs(x) + D) / slope

    d1, d2, d3 = moved(x1, x2, x3), moved(x2, x1, x3), moved(x3, x1, x2)
    return (d2 + d3) / (x3 - x2) + (d1 + d3) / (x3 - x1)


def _batch_motion(I1, I3, mgl, omega, q, t, accuracy=None, *, attitude=True):
    """Constants and motion of B members at the times t (n,): returns (ok (B,), omega, gamma, q, euler, period,
    turning) with the motion arrays of shape (B, n, ·) (q and euler None unless ``attitude``: ω and Γ need only the
    half angles' cosines and sines, not the quaternion nor the angles themselves); rows where ``ok`` is False are to be computed precisely:
    among them every member whose m_c is ill-conditioned in double (:func:`_conditioning`) beyond
    :data:`CONDITION_ULPS` ulp — or, for an ``accuracy`` asked, beyond a tenth of it over the phase λ·max|t| the
    times span (a near-double root: next to the upright top's separatrix, where the cubic's coefficients cancel)."""
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
    for _ in range(200):  # from above, the steps shrink to the cubic's rounding, where they turn negative
        g = _cubic(A, B, C, D, x3)
        dg = (3 * A * x3 + 2 * B) * x3 + C
        step = np.where((dg > 0) & (g > 0), g / np.where(dg > 0, dg, 1.0), 0.0)
        x3 = x3 - step
        if np.all(step <= 4.0 * 2.0 ** -52 * np.abs(x3)):
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
    Bmag = 2 * np.abs(beta * u0) + wt2 + a * a
    Cmag = 2 * np.abs(u0) * wt2 + np.abs(beta) * s2 + 2 * np.abs(a * wpar)
    cond = _conditioning(A, B, C, D, Bmag, Cmag, x1, x2, x3)
    tmax = float(np.max(np.abs(t))) if np.size(t) else 0.0
    allowed = CONDITION_ULPS * 2.0 ** -52
    if accuracy is not None:  # the phase's relative error e spans e·λ·tmax radians by the last time
        allowed = np.maximum(allowed, 0.1 * accuracy / (np.sqrt(A * np.abs(x3 - x1)) / 2 * tmax + 1.0))
    ok &= cond <= allowed
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
    half_n = K + n_n / 3 * _rj(0.0, mc, 1.0, n_n1)  # K = R_F(0, m_c, 1)
    per_n = coef_n * 2 * half_n
    n_f, n_f1 = (z1 * m + delta) / (z1 + delta), z1 * mc / (z1 + delta)
    m_over_n = m * (z1 + delta) / (z1 * m + delta)
    one_m_m_over_n = delta * mc / (z1 * m + delta)
    rate_f = nu_far + Bf * m_over_n / (z1 + delta)
    coef_f = Bf * delta * mc / (z1 * m + delta) / (lam * (z1 + delta))
    half_f = K + n_f / 3 * _rj(0.0, mc, 1.0, n_f1)
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
    landen = _agm_landen_columns(np.sqrt(mc))
    sn, cn, dn = _sncndn_within(r, np.sqrt(col(mc)), landen)  # |r| ≤ K: no reduction modulo 4K
    parity = 1.0 - 2.0 * np.mod(j, 2.0)
    sn_t, cn_t = parity * sn, parity * cn
    dl = col(delta)
    rn = np.sqrt(col(y2) + dl * cn * cn)
    rf = np.sqrt(col(z1) + dl * sn * sn)
    sd = np.sqrt(dl)
    ratio_n, ratio_f = sd * cn_t / rn, sd * sn_t / rf
    # W of the near pole at r (|r| ≤ K), of the far pole at r − K (wrapped to [−K, K])
    x = r - col(K)
    low = x < -col(K)
    x = np.where(low, x + col(2 * K), x)
    jf = np.where(low, j - 1.0, j)
    # by the integrands' cosine series (no elliptic integral at the times) where they converge: θ = πr/K for the
    # near pole, θ − π for the far one (its wrap by 2K is a whole turn). A steep integrand (1 − n < ½: a pass near
    # a pole) by DLMF 19.7.9 instead: W_n(x) = x − W_{m/n}(x) + atan2(|sn x| ρ, cn x dn x)/ρ · sign x, with
    # ρ² = (1 − n)(1 − m/n) — the steep part in closed form, the series of the smooth W_{m/n}
    one_m_mn_n = (x3 - one_m_w0) / span  # 1 − m/n of the near pole: (w3 − 1)/(w3 − w1)
    steep_n, steep_f = (n_n1 < 0.5) & (one_m_mn_n > 0), (n_f1 < 0.5) & (one_m_m_over_n > 0)
    n_eff = (col(np.where(steep_n, 1.0 - one_m_mn_n, n_n)), col(np.where(steep_f, m_over_n, n_f)))
    # the series converge like the nome q = exp(−πK′/K)^k: members with m_c below SERIES_MC (q^N above round-off)
    # go to the complementary nome's series at once (below)
    fits = mc >= SERIES_MC
    rows = np.flatnonzero(fits)
    c0 = np.zeros((2, mc.size, 1))
    series = np.zeros((2,) + r.shape)
    if rows.size:
        sub = lambda v: v[rows]  # noqa: E731
        landen_rows = ([sub(a) for a in landen[0]], [sub(b_) for b_ in landen[1]], sub(landen[2]))
        c0r, b, fits_rows = _W_series(col(mc[rows]), landen_rows, col(K[rows]), tuple(sub(n) for n in n_eff))
        fits[rows] = fits_rows
        c0[:, rows] = c0r
        theta = (np.pi / col(K[rows])) * r[rows]
        c2 = np.empty((2,) + theta.shape)
        s1 = np.empty((2,) + theta.shape)
        np.cos(theta, out=c2[0])
        np.sin(theta, out=s1[0])
        c2[0] *= 2.0
        np.negative(c2[0], out=c2[1])
        np.negative(s1[0], out=s1[1])
        series[:, rows] = _sine_series(b, c2, s1)
    Wn = np.where(col(steep_n), r - series[0] - c0[0] * r, series[0] + col(half_n / K) * r)
    Wf = np.where(col(steep_f), x - series[1] - c0[1] * x, series[1] + col(half_f / K) * x)
    for W, steep, rho2, s_abs, c_d in ((Wn, steep_n, n_n1 * one_m_mn_n, np.abs(sn), np.abs(cn) * dn),
                                       (Wf, steep_f, n_f1 * one_m_m_over_n, np.abs(cn / dn),
                                        col(mc) * np.abs(sn) / (dn * dn))):
        rows = np.flatnonzero(steep)
        if rows.size:
            rho = np.sqrt(rho2[rows])[:, None]
            sign = np.sign(r[rows]) if W is Wn else np.sign(x[rows])
            W[rows] += sign * np.arctan2(s_abs[rows] * rho, c_d[rows]) / rho
    slow = ~(fits & np.isfinite(Wn).all(axis=1) & np.isfinite(Wf).all(axis=1))
    # small m_c (the nome series would need many harmonics): the complementary nome's few terms
    nm_n, nm_f = n_n * one_m_mn_n, delta * mc / (z1 + delta)  # n − m of each pole
    comp = np.flatnonzero(slow & ok & (mc < SERIES_MC) & (nm_n != 0) & np.isfinite(nm_n) & np.isfinite(nm_f))
    if comp.size:
        pick = lambda v: np.asarray(v)[comp][:, None]  # noqa: E731
        Kc, mcc, mm = pick(K), pick(mc), pick(m)
        Kp = _rf(0.0, mm, 1.0)  # K′ = K(m_c), both poles'
        Wn[comp] = _W_complementary(r[comp], pick(n_n), pick(n_n1), pick(nm_n), mcc, mm, Kc, pick(half_n), Kp)
        Wf[comp] = _W_complementary(x[comp], pick(n_f), pick(n_f1), pick(nm_f), mcc, mm, Kc, pick(half_f), Kp)
        slow[comp] = ~(np.isfinite(Wn[comp]).all(axis=1) & np.isfinite(Wf[comp]).all(axis=1))
    slow = np.flatnonzero(slow)
    if slow.size:  # the rest (m_c ≥ SERIES_MC, a steep integrand): Carlson's integrals at the times, these members only
        rs, ss, cs, ds, xs = r[slow], sn[slow], cn[slow], dn[slow], x[slow]
        pick = lambda v: np.asarray(v)[slow][:, None]  # noqa: E731
        Wn[slow] = np.sign(rs) * _W(np.abs(ss), np.abs(cs), pick(n_n), pick(n_n1), pick(mc))
        # |sn|, |cn| at r − K (or r + K): |cd r| and k′ |sd r| — no second Jacobi evaluation
        Wf[slow] = np.sign(xs) * _W(np.abs(cs / ds), np.sqrt(pick(mc)) * np.abs(ss / ds), pick(n_f), pick(n_f1),
                                    pick(mc))
    four_pi = 4 * math.pi
    chi_n = np.mod(col(nu_near) * tt + col(per_n) * j, four_pi) + col(chi_n0) + col(coef_n) * (Wn - col(W0n))
    chi_f = np.mod(col(rate_f) * tt + col(per_f) * (jf - col(j0f)), four_pi) + col(chi_f0) + col(coef_f) * (Wf - col(W0f))
    half_near, half_far = rn / math.sqrt(2.0), rf / math.sqrt(2.0)
    pos = col(sigma) > 0
    cos_n, sin_n = np.cos(0.5 * chi_n), np.sin(0.5 * chi_n)  # the half angles' cosines and sines, once
    cos_f, sin_f = np.cos(0.5 * chi_f), np.sin(0.5 * chi_f)
    if pos.all() or not pos.any():  # one sign of M g l for every member (a sweep of one body): no selection
        cp, sp_, cm, sm = (cos_f, sin_f, cos_n, sin_n) if pos.all() else (cos_n, sin_n, cos_f, sin_f)
    else:
        cp, sp_ = np.where(pos, cos_f, cos_n), np.where(pos, sin_f, sin_n)
        cm, sm = np.where(pos, cos_n, cos_f), np.where(pos, sin_n, sin_f)
    cos_psi, sin_psi = cp * cm + sp_ * sm, sp_ * cm - cp * sm
    A_ = 0.5 * col(Bn) * rf / rn + 0.5 * col(Bf) * rn / rf
    B_ = col(sigma) * 2.0 * col(lam) * dn * ratio_n * ratio_f
    out_w = np.empty(r.shape + (3,))  # each component written in place (no stack of temporaries)
    np.multiply(A_, sin_psi, out=out_w[..., 0])
    out_w[..., 0] -= B_ * cos_psi
    np.multiply(A_, cos_psi, out=out_w[..., 1])
    out_w[..., 1] += B_ * sin_psi
    out_w[..., 2] = col(w[:, 2])
    s_theta = rn * rf
    rn2, rf2 = rn * rn, rf * rf
    out_g = np.empty(r.shape + (3,))
    np.multiply(s_theta, sin_psi, out=out_g[..., 0])
    np.multiply(s_theta, cos_psi, out=out_g[..., 1])
    np.multiply(col(sigma), np.where(rn2 < rf2, 1.0 - rn2, rf2 - 1.0), out=out_g[..., 2])
    period = 2 * K / lam
    turning = np.sort(np.stack([sigma * (w0 + x1), sigma * (w0 + x2)], axis=1), axis=1)
    if not attitude:
        return ok, out_w, out_g, None, None, period, turning
    out_q = np.empty(r.shape + (4,))
    cn_n, sn_n = half_near * cos_n, half_near * sin_n
    cf, sf = half_far * cos_f, half_far * sin_f
    out_q[..., 0] = np.where(pos, cf, cn_n)
    out_q[..., 3] = np.where(pos, sf, sn_n)
    out_q[..., 1] = np.where(pos, cn_n, cf)
    out_q[..., 2] = np.where(pos, sn_n, sf)
    out_q /= np.sqrt(np.sum(out_q * out_q, axis=-1, keepdims=True))
    chi_plus, chi_minus = np.where(pos, chi_f, chi_n), np.where(pos, chi_n, chi_f)
    Sh, Ch = np.where(pos, half_near, half_far), np.where(pos, half_far, half_near)
    theta = 2.0 * np.arctan2(Sh, Ch)
    wrap = lambda v: np.mod(v + math.pi, 2 * math.pi) - math.pi  # noqa: E731
    euler = np.stack([wrap(0.5 * (chi_plus + chi_minus)), theta, wrap(0.5 * (chi_plus - chi_minus))], axis=-1)
    return ok, out_w, out_g, out_q, euler, period, turning
