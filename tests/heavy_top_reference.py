"""The 40-digit mpmath reference for tests/test_numerics_heavy_top_exact.py, independent of the closed form.

* Short times: ``mpmath.odefun`` (Taylor series at 40 digits) on the Euler–Poisson equations in the state
  (ω, Γ, q): ``I ω̇ = I ω × ω + M g l Γ × e3``, ``Γ̇ = Γ × ω``, ``q̇ = ½ q ⊗ (0, ω)``.
* Long times (up to 10⁴ nutation periods): the textbook quadratures from the state — the cubic
  ``f(u) = (1 − u²)(α − β u) − (b − a u)²`` (Goldstein), its roots by ``mpmath.polyroots``, and with
  ``w = σ u = w1 + (w2 − w1) sin² χ`` the period ``T = 4 ∫ dχ/√(|β|(w3 − w))`` and the increments of φ and ψ per
  period by ``mpmath.quad`` — then ``q(t + N T) = qz(N Δφ) ⊗ q(t) ⊗ qz(N Δψ)`` and ``ω2 + i ω1``, ``Γ2 + i Γ1``
  turned by ``e^{i N Δψ}``, applied to an odefun state at ``t = t_long − N T``.

Run ``python tests/heavy_top_reference.py`` to regenerate tests/data/heavy_top_reference.json (a few minutes).
"""

from __future__ import annotations

import json
import math
import pathlib
import sys

DATA = pathlib.Path(__file__).parent / "data" / "heavy_top_reference.json"


def _q(euler):
    phi, theta, psi = euler
    c, s = math.cos(0.5 * theta), math.sin(0.5 * theta)
    return [c * math.cos(0.5 * (phi + psi)), s * math.cos(0.5 * (phi - psi)), s * math.sin(0.5 * (phi - psi)),
            c * math.sin(0.5 * (phi + psi))]


def _steady_omega(I1, I3, M, g, l, theta, w3, which):
    """Body ω of steady precession at tilt θ (ψ = 0): the rates of Example 4.3's quadratic."""
    disc = math.sqrt(I3**2 * w3**2 - 4 * I1 * M * g * l * math.cos(theta))
    phid = (I3 * w3 - disc) / (2 * I1 * math.cos(theta)) if which == "slow" else \
        (I3 * w3 + disc) / (2 * I1 * math.cos(theta))
    return [0.0, phid * math.sin(theta), w3]


#: name → (I1, I3, M, g, l, omega0, q0): every kind of start.
CASES = {
    "cusped": (1.0, 0.5, 1.0, 9.81, 0.1, [0.0, 0.0, 40.0], _q((0.0, 1.0, 0.0))),
    "wavy": (1.0, 0.5, 1.0, 9.81, 0.1, [0.3, -0.2, 40.0], _q((0.3, 1.0, 0.2))),
    "looping": (1.0, 0.5, 1.0, 9.81, 0.1, [2.0, 0.0, 20.0], _q((0.3, 1.0, 0.2))),
    "thetadot": (1.2, 0.7, 2.0, 9.81, 0.2, [1.5, -0.7, 15.0], _q((-0.4, 0.6, 1.1))),
    "hanging": (1.0, 0.5, 1.0, 9.81, -0.3, [0.5, 0.7, 3.0], _q((0.3, 0.5, 0.2))),
    "below_horizontal": (1.0, 0.5, 1.0, 9.81, 0.3, [0.5, 0.7, 3.0], _q((0.3, 2.2, 0.2))),
    "near_sleeping": (1.0, 1.5, 1.0, 9.81, 0.1, [0.0, 0.0, 10.0], _q((0.0, 1e-3, 0.0))),
    "sleeping": (1.0, 0.5, 1.0, 9.81, 0.1, [0.0, 0.0, 20.0], [1.0, 0.0, 0.0, 0.0]),
    "steady_slow": (1.0, 0.5, 1.0, 9.81, 0.1, _steady_omega(1.0, 0.5, 1.0, 9.81, 0.1, 0.8, 20.0, "slow"),
                    _q((0.2, 0.8, 0.0))),
    "steady_fast": (1.0, 0.5, 1.0, 9.81, 0.1, _steady_omega(1.0, 0.5, 1.0, 9.81, 0.1, 0.8, 20.0, "fast"),
                    _q((0.2, 0.8, 0.0))),
    "fast_spin": (1.0, 0.5, 1.0, 9.81, 0.1, [0.1, 0.2, 200.0], _q((0.1, 0.7, 0.3))),
    "slow_spin": (1.0, 0.5, 1.0, 9.81, 0.5, [0.5, 0.1, 1e-3], _q((0.1, 2.0, 0.3))),
    "zero_spin": (1.0, 0.5, 1.0, 9.81, 0.3, [0.5, 0.3, 0.0], _q((0.3, 1.0, 0.1))),
    "waking": (1.0, 1.5, 1.0, 9.81, 0.1, [0.0, 0.0, 1.0], _q((0.0, 1e-3, 0.0))),
    "through_vertical": (1.0, 0.5, 1.0, 9.81, 0.1, [0.5, 0.3, 2.0], _q((0.3, 0.0, 0.1))),
    "through_bottom": (1.0, 0.5, 1.0, 9.81, 0.3, [0.5, 0.3, 2.0], [0.0, 1.0, 0.0, 0.0]),
}


def _state0(mp, case):
    I1, I3, M, g, l, w0, q0 = case
    q = [mp.mpf(float(x)) for x in q0]
    n2 = sum(x * x for x in q)
    a, b, c, d = q
    G = [2 * (b * d - a * c) / n2, 2 * (c * d + a * b) / n2, (a * a - b * b - c * c + d * d) / n2]
    n = mp.sqrt(n2)
    return [mp.mpf(float(x)) for x in w0] + G + [x / n for x in q]


def _odefun(mp, case):
    I1, I3, M, g, l = (mp.mpf(float(x)) for x in case[:5])
    mgl = M * g * l

    def f(t, y):
        w1, w2, w3, G1, G2, G3, q0, q1, q2, q3 = y
        return [((I1 - I3) * w2 * w3 + mgl * G2) / I1, ((I3 - I1) * w3 * w1 - mgl * G1) / I1, mp.mpf(0),
                G2 * w3 - G3 * w2, G3 * w1 - G1 * w3, G1 * w2 - G2 * w1,
                (-q1 * w1 - q2 * w2 - q3 * w3) / 2, (q0 * w1 + q2 * w3 - q3 * w2) / 2,
                (q0 * w2 + q3 * w1 - q1 * w3) / 2, (q0 * w3 + q1 * w2 - q2 * w1) / 2]

    return mp.odefun(f, 0, _state0(mp, case))


def _quadratures(mp, case):
    """(T, Δφ, Δψ) per nutation period from the textbook cubic; steady motions: (1, φ̇, ψ̇)."""
    I1, I3, M, g, l = (mp.mpf(float(x)) for x in case[:5])
    w1, w2, w3, G1, G2, G3 = _state0(mp, case)[:6]
    beta = 2 * M * g * l / I1
    a = I3 * w3 / I1
    b = (I1 * (w1 * G1 + w2 * G2) + I3 * w3 * G3) / I1  # p_φ / I1, p_φ = L·ẑ
    alpha = w1 * w1 + w2 * w2 + beta * G3  # (2E − I3 ω3²)/I1
    u0 = G3
    # f(u) = (1 − u²)(α − β u) − (b − a u)² = β u³ − (α + a²) u² + (2ab − β) u + (α − b²)
    coeffs = [beta, -(alpha + a * a), 2 * a * b - beta, alpha - b * b]
    sigma = 1 if beta > 0 else -1

    def phidot(u):
        return (b - a * u) / (1 - u * u)

    def psidot(u):
        return w3 - u * phidot(u)

    udot0 = G1 * w2 - G2 * w1
    fp0 = 3 * beta * u0**2 - 2 * (alpha + a * a) * u0 + 2 * a * b - beta
    if udot0 == 0 and abs(fp0) <= mp.mpf(10) ** (5 - mp.mp.dps) * (abs(beta) + alpha + a * a):  # exactly steady; upright: only φ + ψ is defined
        if 1 - u0 * u0 == 0:
            return mp.mpf(1), mp.mpf(0), w3, (u0, u0)
        return mp.mpf(1), phidot(u0), psidot(u0), (u0, u0)
    cw = [sigma**3 * coeffs[0], sigma**2 * coeffs[1], sigma * coeffs[2], coeffs[3]]  # f(σ w)
    roots = sorted(mp.re(r) for r in mp.polyroots(cw, maxsteps=200, extraprec=200))
    r1, r2, r3 = roots  # f(σ w) ≥ 0 on [w1, w2] ∋ w0, and w3 ≥ 1
    A = abs(beta)
    delta = r2 - r1

    def dt(chi):
        w = r1 + delta * mp.sin(chi) ** 2
        return 2 / mp.sqrt(A * (r3 - w))

    def u_of(chi):
        return sigma * (r1 + delta * mp.sin(chi) ** 2)

    T = 2 * mp.quad(dt, [0, mp.pi / 2])
    tp = tuple(sorted((sigma * r1, sigma * r2)))
    if abs(tp[0]) == 1 or abs(tp[1]) == 1:  # through a pole: φ and ψ jump there (only T)
        return T, None, None, tp
    dphi = 2 * mp.quad(lambda c: phidot(u_of(c)) * dt(c), [0, mp.pi / 2])
    dpsi = 2 * mp.quad(lambda c: psidot(u_of(c)) * dt(c), [0, mp.pi / 2])
    return T, dphi, dpsi, tp


def _advance(mp, state, N, dphi, dpsi):
    """The state N periods later: q → qz(NΔφ) ⊗ q ⊗ qz(NΔψ); ω2 + iω1 and Γ2 + iΓ1 turned by e^{iNΔψ}."""
    w1, w2, w3, G1, G2, G3, q0, q1, q2, q3 = state
    A, B = N * dphi, N * dpsi
    rot = mp.expj(B)
    wz = (w2 + 1j * w1) * rot
    gz = (G2 + 1j * G1) * rot
    ca, sa = mp.cos(A / 2), mp.sin(A / 2)
    cb, sb = mp.cos(B / 2), mp.sin(B / 2)

    def mul(p, r):
        p0, p1, p2, p3 = p
        r0, r1, r2, r3 = r
        return (p0 * r0 - p1 * r1 - p2 * r2 - p3 * r3, p0 * r1 + p1 * r0 + p2 * r3 - p3 * r2,
                p0 * r2 - p1 * r3 + p2 * r0 + p3 * r1, p0 * r3 + p1 * r2 - p2 * r1 + p3 * r0)

    q = mul(mul((ca, 0, 0, sa), (q0, q1, q2, q3)), (cb, 0, 0, sb))
    return [mp.im(wz), mp.re(wz), w3, mp.im(gz), mp.re(gz), G3, *q]


def generate(dps=40, names=None):
    import mpmath as mp

    out = {}
    with mp.workdps(dps):
        for name, case in CASES.items():
            if names and name not in names:
                continue
            T, dphi, dpsi, tp = _quadratures(mp, case)
            steady = tp[0] == tp[1]
            Tf = float(T) if not steady else 0.5
            short = [float(mp.mpf(c) * Tf) for c in ("0.13", "0.5", "1.37")]
            sol = _odefun(mp, case)
            rows = [[float(v) for v in sol(mp.mpf(t))] for t in short]
            longs = []
            if dphi is not None:
                base = mp.mpf("0.3") * (T if not steady else 1)
                for N in (1, 100, 10_000):
                    t_long = float(base + N * T)
                    ts = mp.mpf(t_long) - N * T
                    state = _advance(mp, sol(ts), N, dphi, dpsi)
                    longs.append([t_long, [float(v) for v in state]])
            out[name] = {"case": [*case[:5], list(case[5]), list(case[6])], "period": float(T) if not steady else None,
                         "turning_points": [float(x) for x in tp], "short_t": short, "short": rows, "long": longs}
            print(name, "done", file=sys.stderr, flush=True)
    return out


if __name__ == "__main__":
    data = generate(names=sys.argv[1:] or None)
    DATA.parent.mkdir(exist_ok=True)
    old = json.loads(DATA.read_text()) if DATA.exists() else {}
    old.update(data)
    DATA.write_text(json.dumps(old, indent=1))
