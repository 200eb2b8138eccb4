"""Stability stress tests: long-run drift, near-separatrix and degenerate bodies, huge spins, the sleeping top.

``eulersym bench stress [--quick] [--steps N]``

Each section prints its figure beside the floor of issue #5 and, where one exists, the baseline measured in the
same run (RK4, solve_ivp DOP853 on the lambdify route, a hand-written NumPy step). ``--quick`` runs 10⁵ instead of
10⁶ steps and smaller suites. The fast subset of the same checks runs in ``tests/test_stress.py``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

__all__ = [
    "main",
    "long_run_drift",
    "oracle_accuracy_suite",
    "near_separatrix",
    "degenerate_bodies",
    "huge_spin_ratios",
    "sleeping_top",
    "oracle_speed",
    "many_bodies",
    "pivoted_long_run",
    "batched_members",
]

I123 = (1.0, 2.0, 3.0)
W_STD = (1.0, 0.5, 0.2)
Q_ID = (1.0, 0.0, 0.0, 0.0)


def long_run_drift(method, n_steps, *, h=0.01, I=I123, omega0=W_STD, samples=200):
    """Drift of the invariants over ``n_steps`` steps of a free-body method, sampled ``samples`` times.

    Returns a dict: ``time_s``; for the first 10 % of the run and for all of it (keys ``*_tenth``, ``*_all``):
    max relative error of L² and energy; and ``q_norm`` / ``orthogonality`` (max over the run; NaN without q).

    Examples
    --------
    >>> r = long_run_drift("strang", 1000)
    >>> bool(r["l2_all"] < 1e-13)
    True
    """
    from eulersym.numerics import integrate_free_body, integrate_ivp, invariants as iv

    T = n_steps * h
    ts = np.linspace(0.0, T, samples + 1)
    t0 = time.perf_counter()
    if method == "DOP853":
        from eulersym.bench.workprecision import lambdify_module

        tr = integrate_ivp(lambdify_module("euler_principal"), list(omega0), ts, I, method="DOP853", rtol=1e-10, atol=1e-12)
    else:
        tr = integrate_free_body(I, omega0, Q_ID, ts, method=method, h=h)
    secs = time.perf_counter() - t0
    e = np.abs(iv.energy(I, tr.omega) / iv.energy(I, tr.omega[:1])[0] - 1)
    l2 = np.abs(iv.angular_momentum_squared(I, tr.omega) / iv.angular_momentum_squared(I, tr.omega[:1])[0] - 1)
    tenth = ts <= T / 10 * (1 + 1e-12)
    out = dict(method=method, steps=n_steps, time_s=secs, energy_tenth=float(e[tenth].max()), energy_all=float(e.max()),
               l2_tenth=float(l2[tenth].max()), l2_all=float(l2.max()), q_norm=math.nan, orthogonality=math.nan)
    if tr.q is not None:
        out["q_norm"] = float(iv.quaternion_norm_error(tr.q).max())
        out["orthogonality"] = float(iv.orthogonality_error(tr.q).max())
    return out


def _physical(I):
    I = np.array(I, dtype=float)
    k = int(np.argmax(I))
    I[k] = min(I[k], I.sum() - I[k])
    return I


def oracle_accuracy_suite(n_cases=24, seed=20261121, t_max=1e4):
    """Max error of :func:`free_rigid_body_exact` relative to |L| against 40-digit mpmath over a random suite.

    Two thirds of the cases start ε ∈ [1e-8.5, 0.1] off the intermediate axis (m_c ~ ε², down to ~1e-17), the rest
    are generic; moments random in [1, 3] (any order, physical). Returns ``(max_error_over_L, min_mc)``.

    Examples
    --------
    >>> err, mc = oracle_accuracy_suite(3, t_max=5.0)
    >>> bool(err < 1e-13)
    True
    """
    from eulersym.bench.workprecision import mp_reference_omega
    from eulersym.numerics import exact, free_rigid_body_exact

    rng = np.random.default_rng(seed)
    worst, mcs = 0.0, []
    for case in range(n_cases):
        I = _physical(rng.uniform(1.0, 3.0, 3))
        if case % 3 == 0:
            w = rng.normal(size=3)
        else:
            eps = {1: 3e-9, 2: 1e-8}.get(case, 10.0 ** -rng.uniform(1, 8.5))
            order = np.argsort(I)
            w = np.zeros(3)
            w[order[1]] = rng.choice([-1.0, 1.0])
            for k in (order[0], order[2]):
                w[k] = eps * rng.uniform(0.5, 2.0) * rng.choice([-1.0, 1.0])
        sol = exact._setup(tuple(I), w)
        mcs.append(getattr(sol, "mc", 1.0))
        ts = rng.uniform(-t_max / 2, t_max, 5)
        err = np.max(np.abs(free_rigid_body_exact(I, w, ts) - mp_reference_omega(I, w, ts)))
        worst = max(worst, err / math.sqrt(np.sum((I * w) ** 2)))
    return worst, min(mcs)


def near_separatrix(eps_list=(1e-2, 1e-4, 1e-6, 1e-8), ts=(1.0, 10.0, 50.0), *, with_dop=True):
    """Starts ε off the intermediate axis of I = (1, 2, 3): oracle vs mpmath, DMV6 and DOP853 (rtol 1e-13) vs oracle.

    Returns a list of dicts (eps, mc, oracle_error, dmv6_error, dop853_error).
    """
    from eulersym.bench.workprecision import lambdify_module, mp_reference_omega
    from eulersym.numerics import exact, free_rigid_body_exact, integrate_free_body, integrate_ivp

    rows = []
    ts = np.array(ts)
    for eps in eps_list:
        w = (eps, 1.0, eps)
        exact_w = free_rigid_body_exact(I123, w, ts)
        row = dict(eps=eps, mc=exact._setup(I123, np.array(w)).mc)
        row["oracle_error"] = float(np.max(np.abs(exact_w - mp_reference_omega(I123, w, ts))))
        tr = integrate_free_body(I123, w, Q_ID, np.concatenate([[0.0], ts]), method="dmv6", h=0.01)
        row["dmv6_error"] = float(np.max(np.abs(tr.omega[1:] - exact_w)))
        if with_dop:
            tr = integrate_ivp(lambdify_module("euler_principal"), list(w), np.concatenate([[0.0], ts]), I123,
                               method="DOP853", rtol=1e-13, atol=1e-15)
            row["dop853_error"] = float(np.max(np.abs(tr.omega[1:] - exact_w)))
        rows.append(row)
    return rows


#: Near-degenerate bodies: almost spherical, almost symmetric, flat (I1 + I2 ≈ I3).
DEGENERATE = {
    "almost spherical": ((1.0, 1.0 + 1e-9, 1.0 + 2e-9), (0.3, 0.5, 0.7)),
    "almost symmetric": ((1.0, 1.0 + 1e-12, 2.0), (0.3, 0.5, 0.7)),
    "flat I1+I2=I3-1e-12": ((1.0, 2.0, 3.0 - 1e-12), (0.3, 0.5, 0.7)),
    "flat I1+I2=I3": ((1.0, 2.0, 3.0), (0.3, 0.5, 0.7)),
}


def degenerate_bodies(ts=(0.5, 5.0, 50.0), steps=10_000):
    """Oracle vs mpmath, and DMV4 L²/energy conservation over ``steps`` steps, for :data:`DEGENERATE` bodies."""
    from eulersym.bench.workprecision import mp_reference_omega
    from eulersym.numerics import free_rigid_body_exact, integrate_free_body, invariants as iv

    rows = []
    ts = np.array(ts)
    for name, (I, w) in DEGENERATE.items():
        err = float(np.max(np.abs(free_rigid_body_exact(I, w, ts) - mp_reference_omega(I, w, ts))))
        tr = integrate_free_body(I, w, Q_ID, np.linspace(0, steps * 0.01, 11), method="dmv4", h=0.01)
        l2 = iv.angular_momentum_squared(I, tr.omega)
        e = iv.energy(I, tr.omega)
        rows.append(dict(body=name, oracle_error=err, l2_drift=float(np.max(np.abs(l2 / l2[0] - 1))),
                         energy_drift=float(np.max(np.abs(e / e[0] - 1)))))
    return rows


def huge_spin_ratios(ratios=(1e3, 1e6, 1e8), steps=2000):
    """ω0 = (1, 1, R)/… on I = (1, 2, 3) and the same R on the intermediate axis: oracle vs mpmath (relative to |ω|)
    and DMV4/Strang with h = 0.01/|ω| (L² drift)."""
    from eulersym.bench.workprecision import mp_reference_omega
    from eulersym.numerics import free_rigid_body_exact, integrate_free_body, invariants as iv

    rows = []
    for R in ratios:
        for label, w in (("fast axis 3", (1.0, 1.0, R)), ("fast axis 2", (1.0, R, 1.0)), ("slow axis 3", (R, R, 1.0))):
            wn = float(np.linalg.norm(w))
            ts = np.array([0.3, 3.0, 30.0]) / wn * 10
            err = float(np.max(np.abs(free_rigid_body_exact(I123, w, ts) - mp_reference_omega(I123, w, ts)))) / wn
            tr = integrate_free_body(I123, w, Q_ID, [0.0, steps * 0.01 / wn], method="dmv4", h=0.01 / wn)
            l2 = iv.angular_momentum_squared(I123, tr.omega)
            rows.append(dict(ratio=R, start=label, oracle_rel_error=err, l2_drift=float(abs(l2[-1] / l2[0] - 1)),
                             finite=bool(np.all(np.isfinite(tr.q)))))
    return rows


def sleeping_top(*, rtol=1e-3):
    """The sleeping top: numeric threshold vs 4MglI1/I3², and starts at θ = 0 and 1e-12 run to T = 100."""
    from eulersym.numerics import integrate_heavy_top, invariants as iv, sleeping_top_threshold_numeric

    I1, I3, M, g, l = 1.0, 2.0, 1.0, 9.81, 0.5
    bound = 4 * M * g * l * I1 / I3**2  # the text's bound, used here only to check
    found = sleeping_top_threshold_numeric(I1, I3, M, g, l, rtol=rtol)
    out = dict(threshold_found=found, threshold_theory=bound, threshold_rel_error=found / bound - 1)
    w3 = 2.0 * math.sqrt(bound)
    for theta in (0.0, 1e-12):
        q0 = (math.cos(theta / 2), math.sin(theta / 2), 0.0, 0.0)
        t0 = time.perf_counter()
        tr = integrate_heavy_top((I1, I1, I3), M, g, l, (0.0, 0.0, w3), q0, np.linspace(0, 100, 1001))
        out[f"theta{theta:g}_calls"] = tr.n_rhs_calls
        out[f"theta{theta:g}_time_s"] = time.perf_counter() - t0
        out[f"theta{theta:g}_max_theta"] = float(np.max(iv.euler_angles(tr.q)[:, 1]))
        out[f"theta{theta:g}_gamma_norm"] = float(np.max(np.abs(iv.vertical_norm_squared(tr.gamma) - 1)))
    return out


def oracle_speed(n=1_000_000, periods=1e4):
    """µs per time point of the oracle (ω; ω and attitude) and the drift of L's space direction over ``periods``."""
    from eulersym.numerics import exact, free_rigid_body_attitude_exact, free_rigid_body_exact

    ts = np.linspace(0.0, 1e3, n)
    free_rigid_body_exact(I123, W_STD, ts[:10])
    best = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        free_rigid_body_exact(I123, W_STD, ts)
        best = min(best, time.perf_counter() - t0)
    t0 = time.perf_counter()
    free_rigid_body_attitude_exact(I123, W_STD, Q_ID, ts)
    att = time.perf_counter() - t0
    sol = exact._setup(I123, np.array(W_STD))
    tl = np.linspace(0.0, periods * 4 * sol.K / sol.lam, 20001)
    om, q = free_rigid_body_attitude_exact(I123, W_STD, Q_ID, tl)
    L = exact._rotate(q, om * np.array(I123))
    L0 = np.array(I123) * np.array(W_STD)
    ang = np.arctan2(np.linalg.norm(np.cross(L, L0), axis=1), L @ L0)
    return dict(us_per_point=best / n * 1e6, us_per_point_attitude=att / n * 1e6, L_direction_rad=float(ang.max()))


def many_bodies(n=1_000_000):
    """One step of ``n`` free bodies: eulersym's vectorised step (and the generated batched kernel, if present) vs
    a hand-written NumPy step (RK4 on Euler's equations and q̇ = ½ q ⊗ ω, written out by hand here)."""
    from eulersym.numerics import step_free_bodies

    rng = np.random.default_rng(1)
    w = rng.normal(size=(3, n))
    q = rng.normal(size=(4, n))
    q /= np.linalg.norm(q, axis=0)
    I1, I2, I3 = I123
    h = 0.01

    def f(y):  # hand-written NumPy right-hand side
        w1, w2, w3, a, b, c, d = y
        return np.stack([(I2 - I3) / I1 * w2 * w3, (I3 - I1) / I2 * w3 * w1, (I1 - I2) / I3 * w1 * w2,
                         0.5 * (-b * w1 - c * w2 - d * w3), 0.5 * (a * w1 + c * w3 - d * w2),
                         0.5 * (a * w2 - b * w3 + d * w1), 0.5 * (a * w3 + b * w2 - c * w1)])

    def rk4(rhs, y):
        k1 = rhs(y)
        k2 = rhs(y + 0.5 * h * k1)
        k3 = rhs(y + 0.5 * h * k2)
        k4 = rhs(y + h * k3)
        return y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)

    def best_of(fn, k=3):
        best = math.inf
        for _ in range(k):
            t0 = time.perf_counter()
            fn()
            best = min(best, time.perf_counter() - t0)
        return best

    y = np.vstack([w, q])
    out = dict(n=n, hand_rk4_s=best_of(lambda: rk4(f, y)), strang_s=best_of(lambda: step_free_bodies(I123, w, q, h)))
    try:
        from eulersym.generated import free_body_quaternion as kern  # type: ignore

        out["kernel_rk4_s"] = best_of(lambda: rk4(lambda yy: kern.rhs_batched(0.0, yy, I1, I2, I3), y))
    except Exception as exc:  # noqa: BLE001 - not generated yet
        out["kernel_rk4_s"] = f"skipped ({type(exc).__name__}: eulersym.generated.free_body_quaternion)"
    return out


# ---- the generalised splitting (eulersym.numerics.pivoted / batched) --------------------------------------------
def pivoted_long_run(name, method, n_steps, *, h=0.01, samples=1000, fast=None):
    """Energy, |Γ|², L·Γ and |q| over ``n_steps`` steps of the generalised splitting on a workprecision top.

    ``name``: "kovalevskaya" or "full_tensor_rotor" (:func:`eulersym.bench.workprecision.pivoted_problems`).
    Returns a dict: ``time_s``, ``energy_tenth`` / ``energy_all`` (max relative energy error over the first 10 % /
    the whole run), ``gamma_norm`` (max ||Γ|² − 1|), ``l_gamma`` (max |L·Γ − L0·Γ0| / |L0|), ``q_norm``.

    Examples
    --------
    >>> r = pivoted_long_run("kovalevskaya", "strang", 1000, samples=10)
    >>> bool(r["gamma_norm"] <= 1e-13 and r["l_gamma"] <= 1e-13)
    True
    """
    from eulersym.bench.workprecision import pivoted_problems
    from eulersym.numerics.pivoted import integrate_pivoted, pivoted_energy

    p = {q.name: q for q in pivoted_problems(True)}[name]
    ts = np.linspace(0.0, n_steps * h, samples + 1)
    t0 = time.perf_counter()
    tr = integrate_pivoted(p.inertia, p.M, p.g, p.c, p.omega0, p.q0, ts, rotor=p.rotor, method=method, h=h, fast=fast)
    secs = time.perf_counter() - t0
    I = np.asarray(p.inertia)
    e = pivoted_energy(I, p.M, p.g, p.c, tr.omega, tr.gamma)
    de = np.abs(e / e[0] - 1)
    L = tr.omega @ I.T + np.asarray(p.rotor)
    lg = np.sum(L * tr.gamma, axis=1)
    tenth = ts <= ts[-1] / 10 * (1 + 1e-12)
    return dict(time_s=secs, energy_tenth=float(de[tenth].max()), energy_all=float(de.max()),
                gamma_norm=float(np.max(np.abs(np.sum(tr.gamma ** 2, axis=1) - 1))),
                l_gamma=float(np.max(np.abs(lg - lg[0])) / np.linalg.norm(L[0])),
                q_norm=float(np.max(np.abs(np.sum(tr.q ** 2, axis=1) - 1))))


def batched_members(n, *, steps=1000, h=0.01, repeats=3):
    """Seconds for ``n`` random pivoted tops × ``steps`` Strang steps: NumPy, numba serial, numba ``parallel=True``.

    Returns a dict with ``numpy_s`` (None when n > 10⁴: too slow to matter), ``serial_s``, ``parallel_s`` (medians
    of ``repeats`` after a warm-up) and ``max_difference`` between the paths.

    Examples
    --------
    >>> r = batched_members(4, steps=10, repeats=1)
    >>> bool(r["max_difference"] < 1e-12)
    True
    """
    from eulersym.numerics.batched import integrate_pivoted_batch

    rng = np.random.default_rng(12)
    A = np.linalg.qr(rng.normal(size=(n, 3, 3)))[0]
    A = A * np.sign(np.linalg.det(A))[:, None, None]
    m = rng.uniform(1.0, 2.0, (n, 3))
    I = np.einsum("bij,bj,bkj->bik", A, m, A)
    q0 = rng.normal(size=(n, 4))
    q0 /= np.linalg.norm(q0, axis=1, keepdims=True)
    args = (I, 1.0, 9.81, rng.normal(size=(n, 3)) * 0.3, rng.normal(size=(n, 3)), q0, [0.0, steps * h])

    def median_time(**kw):
        integrate_pivoted_batch(*args, method="strang", h=h, **kw)  # warm-up (compiles on first use)
        times, out = [], None
        for _ in range(repeats):
            t0 = time.perf_counter()
            out = integrate_pivoted_batch(*args, method="strang", h=h, **kw)
            times.append(time.perf_counter() - t0)
        return float(np.median(times)), out

    serial_s, a = median_time(fast=True, parallel=False)
    parallel_s, b = median_time(fast=True, parallel=True)
    diff = float(np.max(np.abs(a.omega - b.omega), initial=0.0))
    numpy_s = None
    if n <= 10_000:
        numpy_s, c = median_time(fast=False)
        diff = max(diff, float(np.max(np.abs(a.omega - c.omega), initial=0.0)))
    return dict(n=n, steps=steps, numpy_s=numpy_s, serial_s=serial_s, parallel_s=parallel_s, max_difference=diff)


def _verdict(ok):
    return "PASS" if ok else "FAIL"


def main(argv) -> int:
    """``eulersym bench stress``: run every section and print figures beside the floors."""
    ap = argparse.ArgumentParser(prog="eulersym bench stress", description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="10⁵ steps and smaller suites")
    ap.add_argument("--steps", type=int, default=None, help="steps of the long runs (default 10⁶, 10⁵ with --quick)")
    args = ap.parse_args(argv)
    n = args.steps or (100_000 if args.quick else 1_000_000)

    print(f"== long runs: free body I={I123}, omega0={W_STD}, h=0.01, {n} steps (figures: first 10% | whole run)")
    drift = {}
    for method in ("strang", "yoshida4", "dmv4", "dmv6", "rk4", "DOP853"):
        r = drift[method] = long_run_drift(method, n)
        print(f"  {method:<8} {r['time_s']:7.2f} s  |L|² {r['l2_tenth']:.1e} | {r['l2_all']:.1e}   energy "
              f"{r['energy_tenth']:.1e} | {r['energy_all']:.1e} (x{r['energy_all'] / max(r['energy_tenth'], 1e-300):.2f})"
              f"   |q|-1 {r['q_norm']:.1e}  RᵀR-1 {r['orthogonality']:.1e}")
    for method in ("strang", "yoshida4", "dmv4", "dmv6"):
        r = drift[method]
        grow = r["energy_all"] / max(r["energy_tenth"], 1e-300)
        roundoff = r["energy_all"] <= 1e-12
        note = " (energy error at round-off, a √n random walk: Brouwer's law)" if roundoff and grow >= 2 else ""
        print(f"  floor {method}: |L|² ≤ 1e-12: {r['l2_all']:.1e} {_verdict(r['l2_all'] <= 1e-12)}; energy growth "
              f"< 2x over the last 90%: x{grow:.2f} {_verdict(grow < 2 or roundoff)}{note}")
    for method in ("rk4", "DOP853"):
        r = drift[method]
        print(f"  baseline {method}: energy drift grows x{r['energy_all'] / max(r['energy_tenth'], 1e-300):.1f}, "
              f"|L|² drift {r['l2_all']:.1e}")

    print("\n== oracle accuracy vs 40-digit mpmath (random suite, m_c down to ~1e-17)")
    err, mc = oracle_accuracy_suite(12 if args.quick else 48)
    print(f"  max error / |L| = {err:.2e} (floor 1e-13: {_verdict(err <= 1e-13)}); smallest m_c = {mc:.1e}")
    sp = oracle_speed(200_000 if args.quick else 1_000_000)
    print(f"  speed: {sp['us_per_point']:.3f} µs per time point for ω (floor 2: {_verdict(sp['us_per_point'] <= 2)}), "
          f"{sp['us_per_point_attitude']:.3f} µs with the attitude")
    print(f"  space direction of L over 1e4 periods: {sp['L_direction_rad']:.1e} rad "
          f"(floor 1e-14: {_verdict(sp['L_direction_rad'] <= 1e-14)})")

    print("\n== near-separatrix starts (I = (1,2,3), ω0 = (ε, 1, ε); errors max over t = 1, 10, 50)")
    for r in near_separatrix():
        print(f"  ε={r['eps']:.0e} m_c={r['mc']:.1e}: oracle vs mpmath {r['oracle_error']:.1e}; dmv6 h=0.01 "
              f"{r['dmv6_error']:.1e}; DOP853 rtol 1e-13 {r['dop853_error']:.1e}")

    print("\n== near-degenerate inertia (oracle vs mpmath at t = 0.5, 5, 50; dmv4 over 1e4 steps)")
    for r in degenerate_bodies():
        print(f"  {r['body']:<22} oracle {r['oracle_error']:.1e}  dmv4 |L|² {r['l2_drift']:.1e} energy {r['energy_drift']:.1e}")

    print("\n== huge spin ratios (I = (1,2,3); oracle error relative to |ω|; dmv4 with h = 0.01/|ω|)")
    for r in huge_spin_ratios():
        print(f"  R={r['ratio']:.0e} {r['start']:<12} oracle {r['oracle_rel_error']:.1e}  dmv4 |L|² "
              f"{r['l2_drift']:.1e} finite={r['finite']}")

    print("\n== sleeping top (I = (1,1,2), M g l = 4.905)")
    s = sleeping_top()
    print(f"  threshold located at ω3² = {s['threshold_found']:.5g} vs 4MglI1/I3² = {s['threshold_theory']:.5g}: "
          f"{100 * s['threshold_rel_error']:+.2f} % (floor ±1 %: {_verdict(abs(s['threshold_rel_error']) <= 0.01)})")
    for th in ("0", "1e-12"):
        calls = s[f"theta{th}_calls"]
        print(f"  θ0 = {th}: T = 100 in {s[f'theta{th}_time_s']:.2f} s with {calls} kernel calls (floor 1e4: "
              f"{_verdict(calls <= 10_000)}); max θ {s[f'theta{th}_max_theta']:.1e}; ||Γ|²-1| {s[f'theta{th}_gamma_norm']:.1e}")

    print("\n== many bodies: one step")
    m = many_bodies(200_000 if args.quick else 1_000_000)
    print(f"  {m['n']} bodies: hand-written NumPy RK4 step {m['hand_rk4_s'] * 1e3:.1f} ms; eulersym Strang step "
          f"{m['strang_s'] * 1e3:.1f} ms (ratio {m['strang_s'] / m['hand_rk4_s']:.2f})")
    if isinstance(m["kernel_rk4_s"], float):
        ratio = m["kernel_rk4_s"] / m["hand_rk4_s"]
        print(f"  RK4 step on the generated batched kernel {m['kernel_rk4_s'] * 1e3:.1f} ms: ratio {ratio:.2f} "
              f"(floor ≤ 3: {_verdict(ratio <= 3)})")
    else:
        print(f"  batched-kernel RK4: {m['kernel_rk4_s']}")

    print(f"\n== generalised splitting (eulersym.numerics.pivoted), {n} steps, h = 0.01 (first 10% | whole run)")
    for name in ("kovalevskaya", "full_tensor_rotor"):
        for method in ("strang", "yoshida4"):
            r = pivoted_long_run(name, method, n)
            grow = r["energy_all"] / max(r["energy_tenth"], 1e-300)
            ok = r["gamma_norm"] <= 1e-13 and r["l_gamma"] <= 1e-13
            print(f"  {name:<18} {method:<8} {r['time_s']:6.2f} s  energy {r['energy_tenth']:.2e} | {r['energy_all']:.2e} "
                  f"(x{grow:.2f}: {_verdict(grow < 2)} no secular growth)  ||Γ|²-1| {r['gamma_norm']:.1e}  "
                  f"|ΔL·Γ|/|L| {r['l_gamma']:.1e} (floor 1e-13: {_verdict(ok)})  ||q|²-1| {r['q_norm']:.1e}")

    print("\n== batched splitting: random pivoted tops, 10⁶ member-steps of Strang each (medians of 3; the machine is "
          "shared: noisy)")
    for members in ((1_000, 10_000) if args.quick else (1_000, 10_000, 100_000)):
        b = batched_members(members, steps=max(1, 1_000_000 // members))
        numpy = f"NumPy {b['numpy_s']:.2f} s, " if b["numpy_s"] is not None else ""
        print(f"  {members:>7} members × {b['steps']} steps: {numpy}numba serial {b['serial_s']:.2f} s, numba parallel {b['parallel_s']:.2f} s "
              f"(parallel/serial speed-up x{b['serial_s'] / b['parallel_s']:.2f}); paths agree to {b['max_difference']:.0e}")
    return 0
