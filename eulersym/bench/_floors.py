"""The floors the sweeps bench builds itself: the same closed-form work as plain vectorised NumPy (no care for the
edges: constants in double, the phase in double, a fixed Landen depth, the upper regime's layout), and the cost of
one numba call of the heavy top's kernel — what a sweep cannot go below on this machine, measured in the same run.

Examples
--------
>>> import numpy as np
>>> w = free_body_floor(np.array([[1.0, 2.0, 3.0]]), np.array([[1.0, 0.5, 0.2]]), np.linspace(0.0, 1.0, 3))
>>> w.shape
(1, 3, 3)
"""

from __future__ import annotations

import numpy as np

from eulersym.numerics.elliptic import _rf, _sncndn_reduced

__all__ = ["free_body_floor", "heavy_top_floor", "heavy_top_omega_floor", "ns_per_kernel_call"]


def _landen(rootmc, levels=5):
    a, b = np.ones_like(rootmc), rootmc
    avals, bvals = [], []
    for _ in range(levels):
        avals.append(a[:, None])
        bvals.append(b[:, None])
        a, b = 0.5 * (a + b), np.sqrt(a * b)
    agm = 0.5 * (a + b)
    return avals, bvals, agm[:, None]


def _sncndn_floor(u, K, landen, rootmc=None):
    """sn, cn, dn of u (B, n) with the period 4K reduced in double and Landen on [0, K] (no reflection); with
    ``rootmc`` (B, 1), Landen on [0, K/2] and the quarter-period reflection above (cn near K to its own digits)."""
    r = np.mod(u, 4 * K)
    half = r >= 2 * K
    r = np.where(half, r - 2 * K, r)
    back = r > K
    x = np.where(back, 2 * K - r, r)
    if rootmc is None:
        sn, cn, dn = _sncndn_reduced(x, *landen)
    else:
        near = x > 0.5 * K
        sz, cz, dz = _sncndn_reduced(np.where(near, K - x, x), *landen)
        sn, cn, dn = np.where(near, cz / dz, sz), np.where(near, rootmc * sz / dz, cz), np.where(near, rootmc / dz, dz)
    sign = np.where(half, -1.0, 1.0)
    return sign * sn, np.where(back, -sign, sign) * cn, dn


def free_body_floor(I, w, t):
    """ω (B, n, 3) of torque-free bodies with ascending moments I (B, 3): D's, amplitudes, m_c, λ and u0 in double,
    u = λ t + u0 in double, sn, cn, dn by Landen at a fixed depth; the regime per member by the sign of D_mid."""
    I1, I2, I3 = I.T
    w1, w2, w3 = w.T
    D1 = I2 * (I2 - I1) * w2**2 + I3 * (I3 - I1) * w3**2
    D2 = I1 * (I1 - I2) * w1**2 + I3 * (I3 - I2) * w3**2
    D3 = I1 * (I1 - I3) * w1**2 + I2 * (I2 - I3) * w2**2
    upper = D2 >= 0  # c = axis 3 (else axis 1); b = axis 2; (a, b, c) proper: (1, 2, 3) or (3, 2, 1) with b flipped
    Ia, Ic = np.where(upper, I1, I3), np.where(upper, I3, I1)
    Da, Dc = np.where(upper, D1, D3), np.where(upper, D3, D1)
    wa, wc = np.where(upper, w1, w3), np.where(upper, w3, w1)
    wb = np.where(upper, w2, -w2)
    A = np.sqrt(-Dc / (Ia * (Ic - Ia)))
    C = np.copysign(np.sqrt(Da / (Ic * (Ic - Ia))), wc)
    Bm = np.copysign(np.sqrt(-Dc / (I2 * (Ic - I2))), np.sign(Ic - Ia) * C * A)
    mc = (Ic - Ia) * D2 / ((Ic - I2) * Da)
    lam = np.sqrt((Ic - I2) * Da / (Ia * I2 * Ic))
    landen = _landen(np.sqrt(mc))
    K = np.pi / (2 * landen[2][:, 0])
    xa, xb = Ia * (Ic - Ia) * wa**2, I2 * (Ic - I2) * wb**2
    tot = xa + xb
    cn0, sn0 = np.copysign(np.sqrt(xa / tot), wa), np.copysign(np.sqrt(xb / tot), wb * Bm)
    x0 = np.abs(sn0) * _rf(xa / tot, (xa + mc * xb) / tot, 1.0)
    x0 = np.where(cn0 < 0, 2 * K - x0, x0)
    u0 = np.copysign(x0, sn0)
    u = lam[:, None] * t[None, :] + u0[:, None]
    sn, cn, dn = _sncndn_floor(u, K[:, None], landen)
    a_, b_, c_ = A[:, None] * cn, Bm[:, None] * sn, C[:, None] * dn
    up = upper[:, None]
    out = np.empty(u.shape + (3,))
    out[..., 0] = np.where(up, a_, c_)
    out[..., 1] = np.where(up, b_, -b_)
    out[..., 2] = np.where(up, c_, a_)
    return out


def _lagrange_roots(I1, I3, mgl, w, q):
    """The Lagrange top's constants in plain double (Goldstein's a, b, α, β; the cubic's roots u1 ≤ u2 ≤ u3 of
    f(u) = (α − βu)(1 − u²) − (b − au)²) and the start's vertical Γ0 = R(q)ᵀ ẑ in the body."""
    q0, q1, q2, q3 = q.T
    G1, G2, G3 = 2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3
    beta = 2 * mgl / I1
    a = I3 * w[:, 2] / I1
    b = w[:, 0] * G1 + w[:, 1] * G2 + a * G3
    alpha = w[:, 0] ** 2 + w[:, 1] ** 2 + beta * G3
    A3, B3, C3, D3 = beta, -(alpha + a * a), 2 * a * b - beta, alpha - b * b
    u3 = 1.0 + np.maximum(np.abs(B3), np.maximum(np.abs(C3), np.abs(D3))) / A3
    for _ in range(60):
        u3 = u3 - (((A3 * u3 + B3) * u3 + C3) * u3 + D3) / ((3 * A3 * u3 + 2 * B3) * u3 + C3)
    Bq, Cq = B3 + A3 * u3, C3 + (B3 + A3 * u3) * u3  # the quadratic A u² + Bq u + Cq of the other two roots
    disc = np.sqrt(np.maximum(Bq * Bq - 4 * A3 * Cq, 0.0))
    qq = -0.5 * (Bq + np.copysign(disc, Bq))
    r1, r2 = qq / A3, Cq / np.where(qq != 0, qq, 1.0)
    return a, b, beta, np.minimum(r1, r2), np.maximum(r1, r2), u3, (G1, G2, G3), (A3, B3, C3, D3)


def heavy_top_floor(I1, I3, mgl, w, q, t):
    """cos θ (B, n) of heavy symmetric tops: the largest root of the cubic by Newton from above, the others from the
    deflated quadratic, λ, m, K, τ0 in double, then u = u1 + Δ sn²(λ t + τ0) with sn by Landen at a fixed depth.
    Less work than the sweep's ω (no ψ): informational, not its floor (:func:`heavy_top_omega_floor` is)."""
    a, b, beta, u1, u2, u3, (G1, G2, G3), _ = _lagrange_roots(I1, I3, mgl, w, q)
    delta, span = u2 - u1, u3 - u1
    m = delta / span
    lam = np.sqrt(np.abs(beta) * span) / 2
    landen = _landen(np.sqrt(np.clip(1 - m, 1e-300, 1.0)), levels=7)
    K = np.pi / (2 * landen[2][:, 0])
    s2 = np.clip((G3 - u1) / np.where(delta > 0, delta, 1.0), 0, 1)
    tau0 = np.copysign(np.sqrt(s2) * _rf(1 - s2, 1 - m * s2, 1.0), G1 * w[:, 1] - G2 * w[:, 0])
    tau = lam[:, None] * t[None, :] + tau0[:, None]
    x = np.abs(np.mod(tau + K[:, None], 2 * K[:, None]) - K[:, None])
    sn, _, _ = _sncndn_reduced(x, *landen)
    return u1[:, None] + delta[:, None] * sn * sn


def heavy_top_omega_floor(I1, I3, mgl, w, q, t):
    """ω (B, n, 3) of heavy symmetric tops, the sweep's own output, the textbook way in plain double (Goldstein §5.7,
    zxz angles): u = cos θ = u1 + Δ sn²(τ), τ = λt + τ0, and

    ψ(t) = ψ0 + (ω3 − a) t − (b − a)/(2(1 − u1)λ) [W₊]_{τ0}^{τ} + (b + a)/(2(1 + u1)λ) [W₋]_{τ0}^{τ},

    the partial fractions of ψ̇ = ω3 − u(b − au)/(1 − u²), with W_n(τ) = ∫₀^τ dy/(1 − n sn² y) (n₊ = Δ/(1 − u1),
    n₋ = −Δ/(1 + u1)) by Carlson's R_F and R_J at every time (:func:`scipy.special.elliprf`, ``elliprj``: compiled,
    vectorised) and its quasi-period 2Π(n); then θ̇ = −u̇/sin θ, φ̇ = (b − au)/(1 − u²) and ω1 = φ̇ sin θ sin ψ + θ̇ cos ψ,
    ω2 = φ̇ sin θ cos ψ − θ̇ sin ψ. The same outputs as the sweep, with no care for the edges (poles, separatrix)."""
    from scipy.special import elliprf, elliprj

    a, b, beta, u1, u2, u3, (G1, G2, G3), (A3, B3, C3, D3) = _lagrange_roots(I1, I3, mgl, w, q)
    for _ in range(2):  # the two smaller roots polished on the cubic itself (the deflation loses digits near a pole)
        u1, u2 = (x - (((A3 * x + B3) * x + C3) * x + D3) / ((3 * A3 * x + 2 * B3) * x + C3) for x in (u1, u2))
    delta, span = u2 - u1, u3 - u1
    m = delta / span
    mc = np.clip(1 - m, 1e-300, 1.0)
    lam = np.sqrt(np.abs(beta) * span) / 2
    landen = _landen(np.sqrt(mc), levels=12)
    K = np.pi / (2 * landen[2][:, 0])
    s2 = np.clip((G3 - u1) / np.where(delta > 0, delta, 1.0), 0, 1)
    du0 = G1 * w[:, 1] - G2 * w[:, 0]  # u̇(0) = −sin θ θ̇
    tau0 = np.copysign(np.sqrt(s2) * _rf(1 - s2, 1 - m * s2, 1.0), du0)
    col = lambda v: v[:, None]  # noqa: E731
    tau = col(lam) * t[None, :] + col(tau0)
    sn, cn, dn = _sncndn_floor(tau, col(K), landen, col(np.sqrt(mc)))
    j = np.round(tau / col(2 * K))
    sign = np.sign(tau - j * col(2 * K))
    s, c2, d2 = np.abs(sn), cn * cn, dn * dn
    rf = elliprf(c2, d2, 1.0)
    psi = col(np.arctan2(G1, G2) + 0.0) + col(w[:, 2] - a) * t[None, :]
    for n, coef in ((delta / (1 - u1), -(b - a) / (2 * (1 - u1) * lam)), (-delta / (1 + u1), (b + a) / (2 * (1 + u1) * lam))):
        whole = K + n / 3 * elliprj(0.0, mc, 1.0, 1 - n)  # Π(n)
        W = 2 * j * col(whole) + sign * (s * rf + col(n / 3) * s ** 3 * elliprj(c2, d2, 1.0, 1 - col(n) * s * s))
        s0 = np.sqrt(s2)
        W0 = np.sign(tau0) * (s0 * _rf(1 - s2, 1 - m * s2, 1.0) + n / 3 * s0 ** 3 * elliprj(1 - s2, 1 - m * s2, 1.0, 1 - n * s2))
        psi += col(coef) * (W - col(W0))
    u = col(u1) + col(delta) * sn * sn
    sin_theta = np.sqrt(1 - u * u)
    theta_dot = -2 * col(delta * lam) * sn * cn * dn / sin_theta
    phi_dot_sin = (col(b) - col(a) * u) / sin_theta
    sp, cp = np.sin(psi), np.cos(psi)
    out = np.empty(u.shape + (3,))
    out[..., 0] = phi_dot_sin * sp + theta_dot * cp
    out[..., 1] = phi_dot_sin * cp - theta_dot * sp
    out[..., 2] = col(w[:, 2])
    return out


def ns_per_kernel_call(calls: int = 2_000_000) -> float:
    """Nanoseconds per call of the heavy top's generated kernel compiled by numba and inlined in a loop (the state
    fed back, so no call can be skipped): the cost a compiled sweep pays per kernel evaluation, at best, on one
    core (None without numba)."""
    try:
        import numba
    except ImportError:
        return None
    import time

    from eulersym.generated import heavy_top_euler_poisson as kernel

    rhs = numba.njit(inline="always", error_model="numpy")(kernel.rhs_flat)

    @numba.njit(error_model="numpy")
    def loop(n, y, p):
        acc = 0.0
        for k in range(n):
            f = rhs(0.0, y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7], y[8], y[9], p[0], p[1], p[2], p[3],
                    p[4], p[5])
            acc += f[0] + f[5] + f[9]
            y = (y[0] + 1e-300 * acc, y[1], y[2], y[3], y[4], y[5], y[6], y[7], y[8], y[9])
        return acc

    y = (0.1, 0.2, 20.0, 0.1, 0.2, 0.97, 0.99, 0.1, 0.05, 0.0)
    p = (1.0e-3, 1.4e-3, 6.0e-4, 0.5, 9.81, 0.04)
    loop(10, y, p)
    best = float("inf")
    for _ in range(3):
        start = time.process_time()
        loop(calls, y, p)
        best = min(best, time.process_time() - start)
    return 1e9 * best / calls
