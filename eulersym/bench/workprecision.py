"""Work-precision: error and invariant drift against run time, eulersym's methods vs solve_ivp on the lambdify route.

``eulersym bench workprecision [--quick] [--out DIR] [--repeats N] [--max-seconds S]``

In the style of Hairer–Wanner and SciML's DiffEqDevTools: every method runs at several step sizes or tolerances;
each point is the minimum of several timed runs after a warm-up (runs longer than one second are timed once);
failed runs are recorded with their reason, not dropped. Errors are the maximum absolute error of ω (and Γ for
the top) over the output times, against the exact oracle (validated against 30-digit mpmath) or, for the heavy
top, its closed form (validated against 40-digit mpmath; a tight DOP853 run is reported beside it). Separate columns/panels give
the drift of the invariants (relative energy and L² or |Γ|², L·Γ).

Problems
--------
``free_T100``, ``free_T10000``
    Free body I = (1, 2, 3), ω0 = (1, 0.5, 0.2) (off the separatrix), T = 100 and 10⁴ (10³ with ``--quick``).
``separatrix``
    I = (1, 2, 3), ω0 = (1e-6, 1, 1e-6): 1e-6 off the intermediate axis (m_c ≈ 1e-12), T = 100.
``rigidode``
    Krogh's ``rigidode`` (MATLAB's demo): y1' = y2 y3, y2' = −y1 y3, y3' = −0.51 y1 y2, y(0) = (0, 1, 1),
    T = 12; exact solution (sn, cn, dn)(t | m = 0.51). It is Euler's equations for any moments with I3 > I1 > I2
    after scaling yᵢ = sᵢ ωᵢ; here I = (1.5, 1, 2), s from the coefficients.
``eulr``
    Hairer–Wanner's EULR, *torque-free variant*: I = (0.5, 2, 3) (not a physical body: 0.5 + 2 < 3, allowed),
    y(0) = (1, 0, 0.9), T = 20 (the original adds the torque 0.25 sin²t on y3 for 3π ≤ t ≤ 4π; omitted so that the
    exact oracle is the reference).
``heavy_top``
    I = (1, 1, 2), M g l = 4.905, tilted 0.3 rad, ω0 = (0.5, 0.2, 10), T = 100; with the closed form
    (:func:`eulersym.numerics.heavy_top_exact`, series "closed form": one point, no right-hand side).
``kovalevskaya``, ``full_tensor_rotor`` (:func:`pivoted_problems`)
    The generalised splitting of :mod:`eulersym.numerics.pivoted` (strang, yoshida4, yoshida6; plain Python and
    numba) against DOP853 and RK45 over T = 10³ on Kovalevskaya's top and on a full-tensor top with a rotor;
    reference: the order-6 splitting at a quarter of the smallest step, cross-checked against DOP853 at rtol 1e-13.
    Its summary gives, for each DOP853 run, the cheapest splitting no less accurate, the time ratio (floor ≥ 5×)
    and both energy drifts with their growth after the first 10 % of the span.

The series ``accuracy`` is eulersym asked for an accuracy (a scene with ``method = "DOP853"`` and ``accuracy`` 1e-5 …
1e-11: the control that delivers it, :mod:`eulersym.numerics.methods._accuracy`); it is plotted at its *achieved*
error, the asked value written beside each point, and the CSV's ``asked`` and ``estimated`` columns give what was
asked and what the run estimated (the accuracy bounds ω's error relative to the largest |ω|, the panel plots it
absolute).

Baselines (same run): ``solve_ivp`` RK45, DOP853, LSODA, Radau over right-hand sides obtained the usual way —
SymPy → ``lambdify`` — from :func:`eulersym.dynamics.euler_equations` / ``euler_poisson_equations``.
eulersym's geometric methods run as plain Python (route ``eulersym``) and, when numba is installed (the ``fast``
extra), compiled (route ``numba``; the first, compiling call is the warm-up).
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import time
import types
from dataclasses import dataclass, field

import numpy as np

from eulersym.bench.report import ratio_text

__all__ = ["main", "lambdify_module", "mp_reference_omega", "run_problem", "PROBLEMS", "pivoted_problems",
           "lambdify_pivoted", "run_pivoted_problem", "summarise_pivoted"]


# ----------------------------------------------------------------------------------------------------------------
# The lambdify route (what a user does without eulersym's kernels)
# ----------------------------------------------------------------------------------------------------------------
def lambdify_module(kind: str):
    """A kernel-like module ``rhs(t, y, *params)``, ``jac(...)`` built with SymPy's ``lambdify``.

    ``kind="euler_principal"``: y = ω, params (I1, I2, I3), from ``dynamics.euler_equations`` with zero torque.
    ``kind="heavy_top_euler_poisson"``: y = (ω, Γ, q), params (I1, I2, I3, M, g, l), from
    ``dynamics.euler_poisson_equations`` and ``kinematics.quaternion_rate``.

    Examples
    --------
    >>> mod = lambdify_module("euler_principal")
    >>> [float(v) for v in mod.rhs(0.0, [1.0, 1.0, 1.0], 1.0, 2.0, 3.0)]
    [-1.0, 1.0, -0.3333333333333333]
    """
    import sympy as sp

    from eulersym import dynamics, kinematics
    from eulersym import symbols as S

    W = [S.omega1, S.omega2, S.omega3]
    if kind == "euler_principal":
        eqs = dynamics.euler_equations(torque=(0, 0, 0))
        sol = sp.solve([e.lhs - e.rhs for e in eqs], [w.diff(S.t) for w in W], dict=True)[0]
        rhs = [sol[w.diff(S.t)] for w in W]
        state, params = W, [S.I1, S.I2, S.I3]
    elif kind == "heavy_top_euler_poisson":
        G = [S.Gamma1, S.Gamma2, S.Gamma3]
        Q = [S.q0, S.q1, S.q2, S.q3]
        wdot, gdot = dynamics.euler_poisson_equations()
        qdot = kinematics.quaternion_rate(Q, W)
        rhs = [*wdot, *gdot, *qdot]
        state, params = W + G + Q, [S.I1, S.I2, S.I3, S.M, S.g, S.l]
    else:
        raise ValueError(kind)
    plain = [sp.Symbol(f"y{k}") for k in range(len(state))]
    freeze = dict(zip(state, plain))
    rhs = [sp.sympify(r).xreplace(freeze) for r in rhs]
    jac = sp.Matrix(rhs).jacobian(plain)
    f = sp.lambdify((S.t, plain, params), rhs, "numpy")
    j = sp.lambdify((S.t, plain, params), jac, "numpy")
    return types.SimpleNamespace(
        __name__=kind,
        rhs=lambda t, y, *p: f(t, y, p),
        jac=lambda t, y, *p: j(t, y, p),
    )


def mp_reference_omega(I, w0, ts, dps=40):
    """ω(t) from mpmath's elliptic functions, every constant formed at ``dps`` digits (more when m_c is tiny).

    Independent of :mod:`eulersym.numerics.exact`'s arithmetic: m from mpmath (1 − m_c is exact at this precision),
    u0 from ``mpmath.ellipf`` of the amplitude, sn/cn/dn from ``mpmath.ellipfun``; the (a, b, c) frame chosen by
    the sign of L² − 2E·I_mid as in the module docstring of :mod:`eulersym.numerics.exact`.

    Examples
    --------
    >>> mp_reference_omega((1.0, 2.0, 3.0), (1.0, 0.5, 0.2), [0.0])
    array([[1. , 0.5, 0.2]])
    """
    import mpmath as mp

    with mp.workdps(30):  # the working precision must resolve 1 − m = m_c and the small discriminants
        If = [mp.mpf(float(x)) for x in I]
        w = [mp.mpf(float(x)) for x in w0]
        lsq = sum(If[i] ** 2 * w[i] ** 2 for i in range(3))
        disc = [abs(sum(If[i] * (If[i] - If[k]) * w[i] ** 2 for i in range(3))) / lsq for k in range(3)]
        tiny = min([d for d in disc if d > 0] or [mp.mpf(1)])
        dps = int(dps + max(0, -2 * mp.log10(tiny)))
    with mp.workdps(dps):
        If = [mp.mpf(float(x)) for x in I]
        w = [mp.mpf(float(x)) for x in w0]
        two_e = sum(If[i] * w[i] ** 2 for i in range(3))
        lsq = sum(If[i] ** 2 * w[i] ** 2 for i in range(3))
        lo, mid, hi = sorted(range(3), key=lambda k: If[k])
        idx = (lo, mid, hi) if lsq - two_e * If[mid] >= 0 else (hi, mid, lo)
        a, b, c = idx
        sgn = [1, 1, 1] if (b - a) % 3 == 1 else [1, -1, 1]
        Ia, Ib, Ic = If[a], If[b], If[c]
        wa, wb, wc = sgn[0] * w[a], sgn[1] * w[b], sgn[2] * w[c]
        A = mp.sqrt((two_e * Ic - lsq) / (Ia * (Ic - Ia)))
        C = mp.sqrt((lsq - two_e * Ia) / (Ic * (Ic - Ia))) * mp.sign(wc)
        lam = mp.sqrt((Ic - Ib) * (lsq - two_e * Ia) / (Ia * Ib * Ic))
        B = (Ic - Ia) * C * A / (lam * Ib)
        m = (Ib - Ia) * (two_e * Ic - lsq) / ((Ic - Ib) * (lsq - two_e * Ia))
        u0 = mp.ellipf(mp.atan2(wb / B, wa / A), m)
        out = []
        for tv in ts:
            u = lam * mp.mpf(float(tv)) + u0
            vals = [A * mp.ellipfun("cn", u, m), B * mp.ellipfun("sn", u, m), C * mp.ellipfun("dn", u, m)]
            row = [0.0, 0.0, 0.0]
            for k in range(3):
                row[idx[k]] = float(sgn[k] * vals[k])
            out.append(row)
        return np.array(out)


# ----------------------------------------------------------------------------------------------------------------
# Problems
# ----------------------------------------------------------------------------------------------------------------
@dataclass
class Problem:
    name: str
    kind: str  # "free" or "top"
    I: tuple
    omega0: tuple
    T: float
    n_out: int = 11
    check_body: bool = True
    scale: tuple = (1.0, 1.0, 1.0)  # report y = scale * ω (rigidode)
    top: tuple = ()  # (M, g, l, q0)
    hs: tuple = ()
    rtols: tuple = (1e-6, 1e-8, 1e-10, 1e-12)
    baselines: tuple = ("RK45", "DOP853", "LSODA", "Radau")
    geometric: tuple = ("strang", "yoshida4", "dmv2", "dmv4", "dmv6")
    notes: list = field(default_factory=list)
    #: accuracies asked of eulersym's controlled DOP853 (a scene, ``method = "DOP853"``): the series "accuracy"
    accuracies: tuple = (1e-5, 1e-7, 1e-9, 1e-11)


def _rigidode_scaling():
    I1, I2, I3 = 1.5, 1.0, 2.0
    a1, a2, a3 = (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3
    s3 = math.sqrt(-a1 * a2)
    s1 = -math.sqrt(a2 * a3 / 0.51)
    s2 = math.sqrt(-a1 * a3 / 0.51)
    return (I1, I2, I3), (s1, s2, s3)


def PROBLEMS(quick: bool):
    """The benchmark problems (see the module docstring); ``quick`` shortens T = 10⁴ to 10³ and thins the grids."""
    (Ir, sr) = _rigidode_scaling()
    y0 = (0.0, 1.0, 1.0)
    hs_free = (0.1, 0.05, 0.02) if quick else (0.2, 0.1, 0.05, 0.02, 0.01, 0.005)
    rt = (1e-6, 1e-8, 1e-10) if quick else (1e-6, 1e-8, 1e-10, 1e-12)
    long_T = 1e3 if quick else 1e4
    tilt = 0.3
    return [
        Problem("free_T100", "free", (1.0, 2.0, 3.0), (1.0, 0.5, 0.2), 100.0, hs=hs_free, rtols=rt),
        Problem(
            f"free_T{int(long_T)}",
            "free",
            (1.0, 2.0, 3.0),
            (1.0, 0.5, 0.2),
            long_T,
            hs=(0.1, 0.05) if quick else (0.1, 0.05, 0.02),
            rtols=(1e-10,) if quick else (1e-8, 1e-10, 1e-12),
            baselines=("DOP853",) if quick else ("RK45", "DOP853"),
            geometric=("dmv4", "dmv6"),
        ),
        Problem("separatrix", "free", (1.0, 2.0, 3.0), (1e-6, 1.0, 1e-6), 100.0, hs=hs_free, rtols=rt),
        Problem(
            "rigidode", "free", Ir, tuple(y / s for y, s in zip(y0, sr)), 12.0, scale=sr, hs=hs_free, rtols=rt
        ),
        Problem("eulr", "free", (0.5, 2.0, 3.0), (1.0, 0.0, 0.9), 20.0, check_body=False, hs=hs_free, rtols=rt),
        Problem(
            "heavy_top",
            "top",
            (1.0, 1.0, 2.0),
            (0.5, 0.2, 10.0),
            100.0,
            top=(1.0, 9.81, 0.5, (math.cos(tilt / 2), math.sin(tilt / 2), 0.0, 0.0)),
            hs=(0.02, 0.01, 0.005, 0.002) if quick else (0.02, 0.01, 0.005, 0.002, 0.001),
            rtols=rt,
            geometric=("strang", "yoshida4"),
        ),
    ]


# ----------------------------------------------------------------------------------------------------------------
# Running
# ----------------------------------------------------------------------------------------------------------------
def _timed(fn, repeats):
    """(result, seconds): min of ``repeats`` runs after a warm-up; when the warm-up took longer than 1 s, one timed
    run. The warm-up is never the measurement: it includes numba's compilation (a numba point was once plotted at
    1.6 s for a 0.4 ms run)."""
    t0 = time.perf_counter()
    out = fn()
    first = time.perf_counter() - t0
    best = math.inf
    for _ in range(1 if first > 1.0 else max(1, repeats)):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return out, best


def _free_reference(p: Problem, ts):
    """40-digit mpmath truth: Jacobi functions for rigidode, :func:`mp_reference_omega` otherwise."""
    if p.name == "rigidode":
        import mpmath as mp

        with mp.workdps(40):
            m = mp.mpf(0.51)  # the binary double the ODE uses
            y = [[float(mp.ellipfun(f, mp.mpf(float(x)), m)) for f in ("sn", "cn", "dn")] for x in ts]
        return np.array(y) / np.asarray(p.scale)
    return mp_reference_omega(p.I, p.omega0, ts)


def _invariant_drift(p: Problem, omega, gamma=None):
    from eulersym.numerics import invariants as iv

    if p.kind == "free":
        e = iv.energy(p.I, omega)
        l2 = iv.angular_momentum_squared(p.I, omega)
        return float(np.max(np.abs(e / e[0] - 1))), float(np.max(np.abs(l2 / l2[0] - 1)))
    M, g, l, _ = p.top
    e = iv.heavy_top_energy(p.I, M, g, l, omega, gamma)
    lg = iv.momentum_vertical(p.I, omega, gamma)
    return float(np.max(np.abs(e / e[0] - 1))), float(np.max(np.abs(lg - lg[0]) / max(abs(lg[0]), 1e-300)))


def _heavy_top_closed_form(p: Problem, ts):
    """The symmetric heavy top in closed form (:func:`eulersym.numerics.heavy_top_exact`) as a trajectory-like
    record: no right-hand side is evaluated."""
    from eulersym.numerics import heavy_top_exact

    M, g, l, q0 = p.top
    motion = heavy_top_exact(p.I, M, g, l, p.omega0, q0, ts)
    return types.SimpleNamespace(omega=motion.omega, gamma=motion.gamma, n_rhs_calls=0)


def run_problem(p: Problem, *, repeats=3, max_seconds=60.0, log=print):
    """Run every method of ``p`` at every setting; returns a list of row dicts (CSV columns)."""
    from eulersym.numerics import free_rigid_body_exact, integrate_free_body, integrate_heavy_top, integrate_ivp

    ts = np.linspace(0.0, p.T, p.n_out)
    rows = []
    if p.kind == "free":
        ref = _free_reference(p, ts)
        ref_note = "40-digit mpmath elliptic functions"
        q0 = (1.0, 0.0, 0.0, 0.0)
    else:
        M, g, l, q0 = p.top
        a, b, c, d = q0
        gamma0 = (2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d)
        mod = lambdify_module("heavy_top_euler_poisson")
        params = (*p.I, M, g, l)
        tight = integrate_ivp(mod, [*p.omega0, *gamma0, *q0], ts, params, method="DOP853", rtol=1e-13, atol=1e-14)
        exact = _heavy_top_closed_form(p, ts)  # validated against 40-digit mpmath (tests)
        ref = np.hstack([exact.omega, exact.gamma])
        spread = float(np.max(np.abs(ref - np.hstack([tight.omega, tight.gamma]))))
        ref_note = f"the closed form, heavy_top_exact (DOP853 rtol 1e-13 differs from it by {spread:.1e})"
    log(f"\n== {p.name}: I={p.I} omega0={p.omega0} T={p.T:g}; reference: {ref_note}")
    from eulersym.numerics import _fast

    routes = [("eulersym", False)] + ([("numba", True)] if _fast.available() else [])

    def record(method, route, setting, fn):
        row = dict(problem=p.name, method=method, route=route, setting=setting, time_s="", error="", energy_drift="",
                   invariant_drift="", n_calls="", status="ok", asked="", estimated="")
        try:
            tr, secs = _timed(fn, repeats)
            if isinstance(tr, np.ndarray):  # the oracle
                omega, gamma, calls = tr, None, 0
            else:
                omega, gamma, calls = tr.omega, tr.gamma, tr.n_rhs_calls
            got = omega if p.kind == "free" else np.hstack([omega, gamma])
            err = float(np.max(np.abs((got - ref) * (np.asarray(p.scale) if p.kind == "free" else 1.0))))
            de, dl = _invariant_drift(p, omega, gamma)
            row.update(time_s=f"{secs:.6g}", error=f"{err:.3e}", energy_drift=f"{de:.3e}", invariant_drift=f"{dl:.3e}",
                       n_calls=str(calls))
            if getattr(tr, "accuracy", None) is not None:  # a controlled run: what was asked, what it estimated
                row.update(asked=f"{tr.accuracy:g}", estimated=f"{max(tr.error.values()):.3e}")
        except Exception as exc:  # noqa: BLE001 - a failed run is a data point
            row["status"] = f"failed: {type(exc).__name__}: {exc}"[:200]
        rows.append(row)
        log(f"  {method:<10} {route:<9} {setting:<10} t={row['time_s'] or '-':>10} err={row['error'] or '-':>10} "
            f"dE={row['energy_drift'] or '-':>10} dInv={row['invariant_drift'] or '-':>10} {row['status'] if row['status'] != 'ok' else ''}")
        return row

    if p.kind == "free":
        record("oracle", "eulersym", "exact", lambda: free_rigid_body_exact(p.I, p.omega0, ts, check_body=p.check_body))
        for route, fast in routes:
            for method in p.geometric:
                for h in p.hs:
                    r = record(method, route, f"h={h:g}", lambda m=method, h=h, fast=fast: integrate_free_body(
                        p.I, p.omega0, q0, ts, method=m, h=h, check_body=p.check_body, fast=fast))
                    if r["time_s"] and float(r["time_s"]) > max_seconds:
                        break
        mod = lambdify_module("euler_principal")
        y0, params = list(p.omega0), p.I
    else:
        record("closed form", "eulersym", "exact", lambda: _heavy_top_closed_form(p, ts))
        for route, fast in routes:
            for method in p.geometric:
                for h in p.hs:
                    r = record(method, route, f"h={h:g}", lambda m=method, h=h, fast=fast: integrate_heavy_top(
                        p.I, M, g, l, p.omega0, q0, ts, h=h, method=m, fast=fast))
                    if r["time_s"] and float(r["time_s"]) > max_seconds:
                        break
        y0 = [*p.omega0, *gamma0, *q0]
    if p.check_body:  # the accuracy asked of eulersym (a scene): the achieved error is what the panel plots
        for accuracy in p.accuracies:
            record("accuracy", "eulersym", f"accuracy={accuracy:g}", lambda a=accuracy: _controlled(p, ts, a))
    for method in p.baselines:
        for rtol in p.rtols:
            r = record(method, "lambdify", f"rtol={rtol:g}", lambda m=method, rtol=rtol: integrate_ivp(
                mod, y0, ts, params, method=m, rtol=rtol, atol=rtol * 1e-2))
            if r["time_s"] and float(r["time_s"]) > max_seconds:
                break
    return rows


def _controlled(p: Problem, ts, accuracy):
    """eulersym's DOP853 asked for ``accuracy`` (a scene: the control that delivers it, with its estimate): a
    namespace with ``omega``, ``gamma``, ``n_rhs_calls``, ``accuracy`` and ``error`` (the estimate)."""
    import warnings

    from eulersym.errors import AccuracyNotReached
    from eulersym.scene import Scene, simulate

    body = dict(moments=p.I)
    if p.kind == "top":
        M, g, l, q0 = p.top
        body.update(mass=M, g=g, l=l, quaternion=q0)
    scene = Scene(**body, omega=p.omega0, t_end=float(ts[-1]), points=len(ts), method="DOP853", accuracy=accuracy,
                  outputs=("omega",) if p.kind == "free" else ("omega", "attitude"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyNotReached)  # its estimate says it: the row's 'estimated'
        result = simulate(scene)
    if not np.array_equal(result.t, ts):
        raise RuntimeError("the scene's output times differ from the problem's")
    return types.SimpleNamespace(omega=result.omega, gamma=result.gamma, n_rhs_calls=result.n_rhs_calls,
                                 accuracy=accuracy, error={k: float(v) for k, v in result.error.items()})


def _best(rows, pred):
    ok = [r for r in rows if r["status"] == "ok" and pred(r)]
    return min(ok, key=lambda r: float(r["time_s"])) if ok else None


def summarise(rows, log=print):
    """Print each floor's figure beside its baseline (ratios from the same run).

    For every DOP853 run (the strongest baseline here), the cheapest oracle run and the cheapest geometric run with
    an error no worse than DOP853's, and the time ratio.
    """
    log("\n== summary: eulersym at an error no worse than solve_ivp DOP853 (lambdify route), same run")
    for name in dict.fromkeys(r["problem"] for r in rows):
        pr = [r for r in rows if r["problem"] == name]
        for r in (r for r in pr if r["method"] == "accuracy" and r["status"] == "ok"):
            log(f"  {name}: accuracy asked {r['asked']}: achieved error {float(r['error']):.2e} (estimated "
                f"{float(r['estimated']):.2e}, relative to |ω|), {float(r['time_s']):.3g} s")
        for base in (r for r in pr if r["method"] == "DOP853" and r["status"] == "ok"):
            target = float(base["error"])
            log(f"  {name}: DOP853 {base['setting']}: {float(base['time_s']):.3g} s, error {target:.2e}, "
                f"energy drift {float(base['energy_drift']):.1e}, invariant drift {float(base['invariant_drift']):.1e}")
            for label, pred in (
                ("oracle", lambda r: r["method"] == "oracle"),
                ("closed form", lambda r: r["method"] == "closed form"),
                ("eulersym, accuracy asked", lambda r: r["method"] == "accuracy"),
                ("geometric, pure Python", lambda r: r["route"] == "eulersym"
                 and r["method"] not in ("oracle", "closed form", "accuracy")),
                ("geometric, numba (fast extra)", lambda r: r["route"] == "numba"),
            ):
                best = _best(pr, lambda r, pred=pred: pred(r) and float(r["error"]) <= target)
                if best is None:
                    if any(pred(r) for r in pr):
                        log(f"      {label}: no run reached error {target:.1e}")
                    continue
                what = (f"{label} {best['method']} {best['setting']}" if best["method"] not in ("oracle", "closed form", "accuracy")
                        else f"{label} {best['setting']}" if best["method"] == "accuracy" else label)
                log(f"      {what}: {float(best['time_s']):.3g} s, error "
                    f"{float(best['error']):.2e}, energy drift {float(best['energy_drift']):.1e}, invariant drift "
                    f"{float(best['invariant_drift']):.1e} -> {ratio_text(float(base['time_s']), float(best['time_s']))}")


def _plot(rows, path):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return False
    names = list(dict.fromkeys(r["problem"] for r in rows))
    fig, axes = plt.subplots(2, len(names), figsize=(4 * len(names), 7), squeeze=False)
    series = list(dict.fromkeys((r["method"], r["route"]) for r in rows if r["status"] == "ok"))
    palette = plt.get_cmap("tab20")
    colour = {key: palette(k % 20) for k, key in enumerate(series)}  # the same colour in every panel
    handles = {}
    for j, name in enumerate(names):
        pr = [r for r in rows if r["problem"] == name and r["status"] == "ok"]
        for method, route in dict.fromkeys((r["method"], r["route"]) for r in pr):
            pts = [(float(r["time_s"]), float(r["error"]), float(r["energy_drift"]))
                   for r in pr if (r["method"], r["route"]) == (method, route)]  # in order of refinement
            label = f"{method} ({route})" if route != "eulersym" else method
            x = [max(a, 1e-7) for a, _, _ in pts]
            controlled = method == "accuracy"  # eulersym asked for an accuracy: its achieved error, the asked beside
            if controlled:
                label = "eulersym, accuracy asked (achieved error; the asked value beside)"
            (line,) = axes[0, j].loglog(x, [max(b, 1e-17) for _, b, _ in pts], "D-" if controlled else "o-",
                                        color="black" if controlled else colour[(method, route)],
                                        lw=2 if controlled else 1)
            if controlled:
                for r, xx, (_, b, _) in zip((r for r in pr if r["method"] == "accuracy"), x, pts):
                    axes[0, j].annotate(f"asked {r['asked']}", (xx, max(b, 1e-17)), fontsize=6, xytext=(3, 3),
                                        textcoords="offset points")
            axes[1, j].loglog(x, [max(c, 1e-17) for _, _, c in pts], "o-", color=colour[(method, route)])
            handles[label] = line
        axes[0, j].set_title(name)
        axes[1, j].set_xlabel("run time [s]")
        for ax in axes[:, j]:
            ax.grid(True, which="major", alpha=0.3)
    axes[0, 0].set_ylabel("achieved max |error| of ω [rad/s] (top: and of Γ)")
    axes[1, 0].set_ylabel("relative energy drift")
    fig.tight_layout()
    # the legend outside the panels, to their right, whatever their number; the saved figure grows to hold it
    # (a legend inside the figure's right margin overlapped the last panel when --only kept two)
    fig.legend(list(handles.values()), list(handles), loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=8,
               title="method (route)", title_fontsize=8, frameon=False)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    return True


def main(argv) -> int:
    """``eulersym bench workprecision``: run, write CSV (and PNG with matplotlib), print the summary."""
    ap = argparse.ArgumentParser(prog="eulersym bench workprecision", description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter spans, fewer settings, fewer timed runs")
    ap.add_argument("--out", default=".", help="folder for workprecision.csv / workprecision.png")
    ap.add_argument("--repeats", type=int, default=None, help="timed runs per point after the warm-up")
    ap.add_argument("--max-seconds", type=float, default=None, help="stop refining a method past this run time "
                    "(default 5 s with --quick, 60 s otherwise)")
    ap.add_argument("--only", default=None, help="comma-separated problem names")
    args = ap.parse_args(argv)
    repeats = args.repeats if args.repeats is not None else (3 if args.quick else 5)
    problems = PROBLEMS(args.quick)
    if args.only:
        keep = set(args.only.split(","))
        problems = [p for p in problems if p.name in keep]
    rows = []
    for p in problems:
        limit = args.max_seconds if args.max_seconds is not None else (5.0 if args.quick else 60.0)
        rows.extend(run_problem(p, repeats=repeats, max_seconds=limit))
    pivoted_rows = []  # the generalised splitting (eulersym.numerics.pivoted)
    for p in pivoted_problems(args.quick):
        if not args.only or p.name in set(args.only.split(",")):
            limit = args.max_seconds if args.max_seconds is not None else (5.0 if args.quick else 60.0)
            pivoted_rows.extend(run_pivoted_problem(p, repeats=repeats, max_seconds=limit))
    rows.extend(pivoted_rows)
    os.makedirs(args.out, exist_ok=True)
    csv_path = os.path.join(args.out, "workprecision.csv")
    with open(csv_path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(dict.fromkeys(k for r in rows for k in r)), restval="")
        writer.writeheader()
        writer.writerows(rows)
    summarise([r for r in rows if r not in pivoted_rows])
    summarise_pivoted(pivoted_rows)
    print(f"\nCSV: {csv_path}")
    png = os.path.join(args.out, "workprecision.png")
    print(f"PNG: {png}" if _plot(rows, png) else "PNG: skipped (install the 'plot' extra: matplotlib)")
    return 0


# ----------------------------------------------------------------------------------------------------------------
# Any pivoted body: the generalised splitting (eulersym.numerics.pivoted) against DOP853 over T = 10³
# ----------------------------------------------------------------------------------------------------------------
@dataclass
class PivotedProblem:
    """A pivoted top for :func:`run_pivoted_problem`: tensor about the pivot, M, g, c, rotor, start, span, settings."""

    name: str
    inertia: tuple
    M: float
    g: float
    c: tuple
    rotor: tuple
    omega0: tuple
    q0: tuple
    T: float
    hs: tuple
    rtols: tuple
    methods: tuple = ("strang", "yoshida4", "yoshida6")
    n_out: int = 101


def _turned(axis, angle):
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def pivoted_problems(quick: bool):
    """Kovalevskaya's top (I = diag(2, 2, 1) about the pivot, c = (1, 0, 0), M g = 1) and a full-tensor top with a
    rotor (principal moments (1.5, 2, 2.5) turned by 0.7 rad about (1, 2, 3), c off every axis, M g = 9.81), T = 10³.

    Examples
    --------
    >>> [p.name for p in pivoted_problems(True)]
    ['kovalevskaya', 'full_tensor_rotor']
    """
    R = _turned((1.0, 2.0, 3.0), 0.7)
    kov_hs = (0.05, 0.02, 0.01) if quick else (0.1, 0.05, 0.02, 0.01, 0.005)
    full_hs = (0.02, 0.01, 0.005) if quick else (0.04, 0.02, 0.01, 0.005, 0.0025)
    rt = (1e-6, 1e-8, 1e-10) if quick else (1e-6, 1e-8, 1e-10, 1e-12)
    return [
        PivotedProblem("kovalevskaya", ((2.0, 0.0, 0.0), (0.0, 2.0, 0.0), (0.0, 0.0, 1.0)), 1.0, 1.0, (1.0, 0.0, 0.0),
                       (0.0, 0.0, 0.0), (0.3, 0.1, 1.0), (math.cos(0.3), math.sin(0.3), 0.0, 0.0), 1e3, kov_hs, rt),
        PivotedProblem("full_tensor_rotor", tuple(map(tuple, R @ np.diag([1.5, 2.0, 2.5]) @ R.T)), 1.0, 9.81,
                       tuple(R @ np.array([0.1, -0.2, 0.5])), tuple(R @ np.array([0.3, 0.2, 1.0])), (0.5, -0.3, 4.0),
                       (math.cos(0.2), 0.0, math.sin(0.2), 0.0), 1e3, full_hs, rt),
    ]


def lambdify_pivoted(p: PivotedProblem):
    """The Euler–Poisson right-hand side of ``p`` the usual way: SymPy matrices → ``lambdify``; y = (ω, Γ, q).

    ``I ω̇ = (I ω + h) × ω + M g Γ × c`` (Euler's equations of a gyrostat with the weight's torque), ``Γ̇ = Γ × ω``,
    ``q̇`` from :func:`eulersym.kinematics.quaternion_rate`.

    Examples
    --------
    >>> mod = lambdify_pivoted(pivoted_problems(True)[0])
    >>> [round(float(v), 12) + 0.0 for v in mod.rhs(0.0, [0, 0, 1.0, 0, 0, 1.0, 1.0, 0, 0, 0])[:3]]
    [0.0, 0.5, 0.0]
    """
    import sympy as sp

    from eulersym import kinematics

    y = sp.symbols("y0:10")
    w, G, q = sp.Matrix(y[:3]), sp.Matrix(y[3:6]), list(y[6:])
    I = sp.Matrix(p.inertia)
    h, c = sp.Matrix(p.rotor), sp.Matrix(p.c)
    wdot = I.LUsolve((I * w + h).cross(w) + p.M * p.g * G.cross(c))
    rhs = [*wdot, *G.cross(w), *kinematics.quaternion_rate(q, list(w))]
    f = sp.lambdify((sp.Symbol("t"), y), rhs, "numpy")
    return types.SimpleNamespace(__name__="pivoted_euler_poisson", rhs=lambda t, yy: f(t, yy))


def _pivoted_invariants(p: PivotedProblem, omega, gamma):
    """(max relative energy drift, its growth: whole run over the first 10 %, max |L·Γ| drift / |L|)."""
    from eulersym.numerics.pivoted import pivoted_energy

    I = np.asarray(p.inertia)
    e = pivoted_energy(I, p.M, p.g, p.c, omega, gamma)
    de = np.abs(e - e[0]) / abs(e[0])
    L = omega @ I.T + np.asarray(p.rotor)
    lg = np.sum(L * gamma, axis=1)
    tenth = max(float(de[: len(de) // 10 + 1].max()), 1e-300)
    return float(de.max()), float(de.max()) / tenth, float(np.max(np.abs(lg - lg[0])) / np.linalg.norm(L[0]))


def run_pivoted_problem(p: PivotedProblem, *, repeats=3, max_seconds=60.0, log=print):
    """Every splitting at every step (plain Python and numba) and DOP853/RK45 at every rtol; rows like
    :func:`run_problem`'s, with ``energy_drift`` and ``invariant_drift`` (L·Γ) from the pivoted energy.

    The reference is the order-6 splitting at a quarter of the smallest step (numba), cross-checked against DOP853
    at rtol 1e-13 (the spread is printed).
    """
    from eulersym.numerics import _fast, integrate_ivp
    from eulersym.numerics.pivoted import integrate_pivoted

    ts = np.linspace(0.0, p.T, p.n_out)
    a, b, c, d = p.q0
    gamma0 = (2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d)
    mod = lambdify_pivoted(p)
    y0 = [*p.omega0, *gamma0, *p.q0]
    fast = _fast.available()
    href = min(p.hs) / 4
    ref_tr = integrate_pivoted(p.inertia, p.M, p.g, p.c, p.omega0, p.q0, ts, rotor=p.rotor, method="yoshida6",
                               h=href, fast=fast)
    ref = np.hstack([ref_tr.omega, ref_tr.gamma])
    tight = integrate_ivp(mod, y0, ts, (), method="DOP853", rtol=1e-13, atol=1e-14, layout="omega_gamma_q")
    spread = float(np.max(np.abs(ref - np.hstack([tight.omega, tight.gamma]))))
    log(f"\n== {p.name}: T={p.T:g}; reference: yoshida6 h={href:g} (differs from DOP853 rtol 1e-13 by {spread:.1e})")
    rows = []

    def record(method, route, setting, fn):
        row = dict(problem=p.name, method=method, route=route, setting=setting, time_s="", error="", energy_drift="",
                   invariant_drift="", n_calls="", status="ok", energy_growth="")
        try:
            tr, secs = _timed(fn, repeats)
            err = float(np.max(np.abs(np.hstack([tr.omega, tr.gamma]) - ref)))
            de, growth, dlg = _pivoted_invariants(p, tr.omega, tr.gamma)
            row.update(time_s=f"{secs:.6g}", error=f"{err:.3e}", energy_drift=f"{de:.3e}", invariant_drift=f"{dlg:.3e}",
                       n_calls=str(tr.n_rhs_calls), energy_growth=f"{growth:.3g}")
        except Exception as exc:  # noqa: BLE001 - a failed run is a data point
            row["status"] = f"failed: {type(exc).__name__}: {exc}"[:200]
        rows.append(row)
        log(f"  {method:<16} {route:<9} {setting:<10} t={row['time_s'] or '-':>10} err={row['error'] or '-':>10} "
            f"dE={row['energy_drift'] or '-':>10} (x{row['energy_growth'] or '-'} after the first 10 %) "
            f"d(L.G)={row['invariant_drift'] or '-':>9} {row['status'] if row['status'] != 'ok' else ''}")
        return row

    routes = [("eulersym", False)] + ([("numba", True)] if fast else [])
    for route, fl in routes:
        for method in p.methods:
            for h in p.hs:
                r = record(f"pivoted:{method}", route, f"h={h:g}", lambda m=method, h=h, fl=fl: integrate_pivoted(
                    p.inertia, p.M, p.g, p.c, p.omega0, p.q0, ts, rotor=p.rotor, method=m, h=h, fast=fl))
                if r["time_s"] and float(r["time_s"]) > max_seconds:
                    break
    for method in ("DOP853", "RK45"):
        for rtol in p.rtols:
            r = record(method, "lambdify", f"rtol={rtol:g}", lambda m=method, rtol=rtol: integrate_ivp(
                mod, y0, ts, (), method=m, rtol=rtol, atol=rtol * 1e-2, layout="omega_gamma_q"))
            if r["time_s"] and float(r["time_s"]) > max_seconds:
                break
    return rows


def summarise_pivoted(rows, log=print):
    """The generalised splitting's floor: at each DOP853 error, the cheapest splitting run (per route) that is no
    worse, the time ratio, and the energy drift of both (ratios from the same run)."""
    log("\n== summary: generalised splitting (eulersym.numerics.pivoted) vs solve_ivp DOP853 over T = 10³, same run")
    for name in dict.fromkeys(r["problem"] for r in rows):
        pr = [r for r in rows if r["problem"] == name]
        for base in (r for r in pr if r["method"] == "DOP853" and r["status"] == "ok"):
            target = float(base["error"])
            log(f"  {name}: DOP853 {base['setting']}: {float(base['time_s']):.3g} s, error {target:.2e}, "
                f"energy drift {float(base['energy_drift']):.1e} (x{float(base['energy_growth']):.3g} after the first 10 %)")
            for label, route in (("splitting, pure Python", "eulersym"), ("splitting, numba (fast extra)", "numba")):
                best = _best(pr, lambda r, route=route: r["route"] == route and r["method"].startswith("pivoted:")
                             and float(r["error"]) <= target)
                if best is None:
                    continue
                ratio = float(base["time_s"]) / max(float(best["time_s"]), 1e-9)
                floor = f" (floor 5x: {'PASS' if ratio >= 5 else 'FAIL'})" if route == "numba" else ""
                log(f"      {label} {best['method'][8:]} {best['setting']}: {float(best['time_s']):.3g} s, error "
                    f"{float(best['error']):.2e}, energy drift {float(best['energy_drift']):.1e} (x"
                    f"{float(best['energy_growth']):.3g} after the first 10 %) -> {ratio:.3g}x faster{floor}")
