"""30-digit references for the accuracy tests, written here from the physics: Taylor series in mpmath.

Nothing of eulersym is used (no kernel, no integrator, no frame): each motion's equations are typed below on
truncated power series — ``I ω̇ = (I ω + h) × ω + M g Γ × c + N``, ``Γ̇ = Γ × ω``, ``q̇ = ½ q ⊗ (0, ω)`` — and the
solution's Taylor coefficients come from the recurrence ``y_{k+1} = f_k / (k + 1)`` at mp.dps = 40, order 30, with
a step that keeps the tail below 10⁻³⁶ of the state. The states are (ω, Γ, q) in the body frame, q scalar first
with ``v_space = R(q) v_body``, Γ = R(q)ᵀ ẑ.

The references are kept in ``tests/data/accuracy_references.npz`` (``python tests/accuracy_reference.py`` writes it
again, the same numbers); ``tests/test_numerics_accuracy.py`` recomputes one of them live, and compares them with
the bench's independent fixed-point references.
"""

from __future__ import annotations

import math
from pathlib import Path

import mpmath as mp
import numpy as np

DATA = Path(__file__).parent / "data" / "accuracy_references.npz"
DPS = 40
ORDER = 30


# ---- truncated power series ------------------------------------------------------------------------------------
def _mul(a, b, k):
    """Coefficient k of the product of series a and b (lists of mpf, at least k + 1 long)."""
    return mp.fsum(a[j] * b[k - j] for j in range(k + 1))


def _cross_k(a, b, k):
    """Coefficient k of a × b for vectors of series."""
    return [_mul(a[1], b[2], k) - _mul(a[2], b[1], k), _mul(a[2], b[0], k) - _mul(a[0], b[2], k),
            _mul(a[0], b[1], k) - _mul(a[1], b[0], k)]


def _rotation_entry(qq, row, col, m):
    """Coefficient m of R(q)[row][col] (v_space = R v_body) from the series of the products q_i q_j."""
    def a(i, j):
        return qq[(min(i, j), max(i, j))][m]

    R = [[a(0, 0) + a(1, 1) - a(2, 2) - a(3, 3), 2 * (a(1, 2) - a(0, 3)), 2 * (a(1, 3) + a(0, 2))],
         [2 * (a(1, 2) + a(0, 3)), a(0, 0) - a(1, 1) + a(2, 2) - a(3, 3), 2 * (a(2, 3) - a(0, 1))],
         [2 * (a(1, 3) - a(0, 2)), 2 * (a(2, 3) + a(0, 1)), a(0, 0) - a(1, 1) - a(2, 2) + a(3, 3)]]
    return R[row][col]


def _coefficients(motion, y, t0, order):
    """Taylor coefficients (order + 1 per component) of the motion's state at (t0, y), mpf."""
    w = [[y[i]] for i in range(3)]
    G = [[y[3 + i]] for i in range(3)]
    q = [[y[6 + i]] for i in range(4)]
    I, inv, h, mgc, n = motion["I"], motion["inv"], motion["h"], motion["mgc"], motion["orbit"]
    if n:  # the orbit's unit radius in space, (cos n t, sin n t, 0): its series about t0
        c0, s0 = mp.cos(n * t0), mp.sin(n * t0)
        cs = [[c0, -s0, -c0, s0][k % 4] * n ** k / mp.factorial(k) for k in range(order + 1)]
        sn = [[s0, c0, -s0, -c0][k % 4] * n ** k / mp.factorial(k) for k in range(order + 1)]
    L = [[], [], []]
    r = [[], [], []]  # the radius in body components, R(q)ᵀ (cos n t, sin n t, 0)
    Ir = [[], [], []]
    qq = {(i, j): [] for i in range(4) for j in range(i, 4)}
    for k in range(order):
        for i in range(3):
            L[i].append(mp.fsum(I[i][j] * w[j][k] for j in range(3)) + (h[i] if k == 0 else 0))
        torque = _cross_k(L, w, k)  # (I ω + h) × ω
        if any(mgc):  # the weight: M g Γ × c
            torque = [torque[0] + G[1][k] * mgc[2] - G[2][k] * mgc[1],
                      torque[1] + G[2][k] * mgc[0] - G[0][k] * mgc[2],
                      torque[2] + G[0][k] * mgc[1] - G[1][k] * mgc[0]]
        if n:  # the gravity gradient: 3 n² r × (I r)
            for (i, j), series in qq.items():
                series.append(_mul(q[i], q[j], k))
            for i in range(3):
                r[i].append(mp.fsum(_rotation_entry(qq, 0, i, m) * cs[k - m] + _rotation_entry(qq, 1, i, m) * sn[k - m]
                                    for m in range(k + 1)))
            for i in range(3):
                Ir[i].append(mp.fsum(I[i][j] * r[j][k] for j in range(3)))
            gradient = _cross_k(r, Ir, k)
            torque = [torque[i] + 3 * n ** 2 * gradient[i] for i in range(3)]
        wdot = [mp.fsum(inv[i][j] * torque[j] for j in range(3)) for i in range(3)]
        gdot = _cross_k(G, w, k)  # Γ̇ = Γ × ω
        qdot = [-(_mul(q[1], w[0], k) + _mul(q[2], w[1], k) + _mul(q[3], w[2], k)) / 2,  # ½ q ⊗ (0, ω)
                (_mul(q[0], w[0], k) + _mul(q[2], w[2], k) - _mul(q[3], w[1], k)) / 2,
                (_mul(q[0], w[1], k) + _mul(q[3], w[0], k) - _mul(q[1], w[2], k)) / 2,
                (_mul(q[0], w[2], k) + _mul(q[1], w[1], k) - _mul(q[2], w[0], k)) / 2]
        for i in range(3):
            w[i].append(wdot[i] / (k + 1))
            G[i].append(gdot[i] / (k + 1))
        for i in range(4):
            q[i].append(qdot[i] / (k + 1))
    return w + G + q


def reference(motion: dict, y0, times) -> np.ndarray:
    """The motion's state (ω, Γ, q) at ``times`` (floats, increasing from the start), as floats (len(times), 10)."""
    with mp.workdps(DPS):
        I = [[mp.mpf(float(x)) for x in row] for row in motion["inertia"]]
        inv = mp.inverse(mp.matrix(I))
        m = {"I": I, "inv": [[inv[i, j] for j in range(3)] for i in range(3)],
             "h": [mp.mpf(float(x)) for x in motion.get("rotor", (0, 0, 0))],
             "mgc": [mp.mpf(float(motion.get("mg", 0.0))) * mp.mpf(float(x)) for x in motion.get("centre", (0, 0, 0))],
             "orbit": mp.mpf(float(motion.get("orbit", 0.0)))}
        y = [mp.mpf(float(v)) for v in y0]
        now = mp.mpf(float(times[0]))
        out = [[float(v) for v in y]]
        tol = mp.mpf(10) ** (-36)
        for target in times[1:]:
            target = mp.mpf(float(target))
            while now < target:
                c = _coefficients(m, y, now, ORDER)
                scale = max(max(abs(v) for v in y), 1)
                rate = max(max((abs(ci[k]) / scale) ** (mp.mpf(1) / k) for k in (ORDER - 1, ORDER) if ci[k] != 0)
                           if any(ci[k] != 0 for k in (ORDER - 1, ORDER)) else 0 for ci in c)
                step = target - now if rate == 0 else min(target - now, 0.8 * tol ** (mp.mpf(1) / ORDER) / rate)
                y = [mp.fsum(ci[k] * step ** k for k in range(ORDER + 1)) for ci in c]
                now += step
            out.append([float(v) for v in y])
        return np.array(out)


def _q(phi, theta, psi):
    """zxz angles → the unit quaternion (v_space = R v_body, R = R_z(φ) R_x(θ) R_z(ψ)), floats."""
    def about(axis, angle):
        q = [math.cos(angle / 2), 0.0, 0.0, 0.0]
        q[axis] = math.sin(angle / 2)
        return q

    def times(p, r):
        return [p[0] * r[0] - p[1] * r[1] - p[2] * r[2] - p[3] * r[3],
                p[0] * r[1] + p[1] * r[0] + p[2] * r[3] - p[3] * r[2],
                p[0] * r[2] - p[1] * r[3] + p[2] * r[0] + p[3] * r[1],
                p[0] * r[3] + p[1] * r[2] - p[2] * r[1] + p[3] * r[0]]

    return tuple(times(times(about(3, phi), about(1, theta)), about(3, psi)))


def _diag(a, b, c):
    return ((a, 0.0, 0.0), (0.0, b, 0.0), (0.0, 0.0, c))


def start(motion: dict) -> list:
    """(ω, Γ, q) at the start in floats: q normalised as a scene normalises it, Γ = R(q)ᵀ ẑ."""
    q = [float(x) for x in motion["quaternion"]]
    norm = math.sqrt(sum(x * x for x in q))
    q = [x / norm for x in q]
    a, b, c, d = q
    return [*map(float, motion["omega"]), 2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d, *q]


#: The tests' motions: short spans of the bench's five, and edges (a separatrix, fast and slow spins).
MOTIONS = {
    "asymmetric-top": dict(inertia=_diag(1.0, 1.3, 0.6), mg=9.81, centre=(0.0, 0.0, 0.2), omega=(0.5, 0.3, 8.0),
                           quaternion=_q(0.0, 0.5, 0.0), t_end=4.0),
    "kovalevskaya": dict(inertia=_diag(2.0, 2.0, 1.0), mg=9.81, centre=(0.1 * math.cos(0.7), 0.1 * math.sin(0.7), 0.0),
                         omega=(0.5, -0.3, 2.0), quaternion=_q(0.0, 1.0, 0.3), t_end=10.0),
    "gyrostat": dict(inertia=_diag(1.0, 2.0, 3.0), rotor=(0.3, 0.5, 0.7), omega=(0.1, 1.0, 0.2),
                     quaternion=(1.0, 0.0, 0.0, 0.0), t_end=10.0),
    "satellite": dict(inertia=_diag(1.0, 2.0, 2.5), orbit=0.1, omega=(0.01, 0.005, 0.102),
                      quaternion=(1.0, 0.0, 0.0, 0.0), t_end=60.0),
    "separatrix": dict(inertia=_diag(1.0, 2.0, 3.0), omega=(1e-4, 1.0, 1e-4), quaternion=(1.0, 0.0, 0.0, 0.0),
                       t_end=20.0),
    "asymmetric-top-7": dict(inertia=_diag(1.0, 1.3, 0.6), mg=9.81, centre=(0.0, 0.0, 0.2), omega=(0.5, 0.3, 7.0),
                             quaternion=_q(0.0, 0.5, 0.0), t_end=4.0),
    "asymmetric-top-9": dict(inertia=_diag(1.0, 1.3, 0.6), mg=9.81, centre=(0.0, 0.0, 0.2), omega=(0.5, 0.3, 9.0),
                             quaternion=_q(0.0, 0.5, 0.0), t_end=4.0),
    "lagrange": dict(inertia=_diag(1.0, 1.0, 0.5), mg=9.81, centre=(0.0, 0.0, 0.1), omega=(0.3, 0.1, 20.0),
                     quaternion=_q(0.0, 0.5, 0.0), t_end=2.0),
    "fast": dict(inertia=_diag(1.0, 1.5, 2.0), mg=9.81, centre=(0.0, 0.0, 0.1), omega=(3.0, -2.0, 200.0),
                 quaternion=_q(0.2, 0.4, 0.0), t_end=0.5),
    # a member of the sweeps bench's asymmetric top (ω3 = linspace(20, 40, 200)[57], θ = linspace(0.1, 0.6, 50)[3]):
    # at rtol 1e-7 and 1e-8 its error is the same — the control must go on, not call it round-off
    "fast-sensitive": dict(inertia=_diag(1e-3, 1.4e-3, 6e-4), mg=0.5 * 9.81, centre=(0.0, 0.0, 0.04),
                           omega=(1.0, 0.0, 25.728643216080403), quaternion=_q(0.0, 0.1306122448979592, 0.0),
                           t_end=2.0),
    "slow": dict(inertia=_diag(2e-3, 3e-3, 5e-3), omega=(1e-3, 2e-4, 3e-4), quaternion=_q(0.1, 0.2, 0.3),
                 t_end=2000.0),
}
POINTS = 11


def times(name: str) -> np.ndarray:
    return np.linspace(0.0, MOTIONS[name]["t_end"], POINTS)


def write() -> None:
    data = {}
    for name, motion in MOTIONS.items():
        data[name] = reference(motion, start(motion), times(name))
        print(name, flush=True)
    DATA.parent.mkdir(exist_ok=True)
    np.savez(DATA, **data)


if __name__ == "__main__":
    write()
