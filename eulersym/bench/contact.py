"""Bodies on a plane: the tippe top from its TOML cold (both routes, integrals, kernel), and its kernel against a
hand-written batched NumPy right-hand side of the same equations.

Floors (issue 22), each measured in the same run as its reference:

1. the tippe top from ``eulersym/scenes/contact/tippe-top.toml``: both routes derived and proven equal
   (:func:`eulersym.model.rolling.check`), its integrals proven (:func:`eulersym.model.rolling_integrals.invariants`)
   and its kernel emitted (:func:`eulersym.model.rolling_kernels.source`), in a fresh process, **≤ 10 s beyond
   SymPy's import** (timed in the same process and subtracted);
2. its generated ``rhs_batched`` **within 1.5×** of :func:`hand_rhs` — the gliding tippe top's equations written
   by hand in NumPy (below), batched over columns — on the same states (medians of repeats; the two agree to
   1e-12 first).

3. the tippe top's inversion (from 0.1 rad, 100 rad/s, the first second, 101 output times as the bundled scene
   has them) by the engine of ``eulersym simulate``'s path for contact scenes —
   :func:`eulersym.model.contact_motion.integrate` on the generated kernel: eulersym's compiled DOP853
   (:mod:`eulersym.numerics.methods._dop853`) with the normal force checked for lift-off at least once a step, and
   the states, contact outputs and invariants at the output times — **≥ 5× faster** than the same body from
   ``sympy.physics.mechanics.KanesMethod`` (z-x-z Euler angles,
   ω and the centre of mass's horizontal velocity as speeds) with PyDy's generated right-hand side (its Cython
   generator, else lambdify) in ``solve_ivp``, each at the loosest tolerance whose error at the end, against a
   reference at rtol 1e-13, is ≤ 1e-8 (relative, on ω, Γ and the velocity). Both use *viscous* friction
   ``F = −μ u`` (μ = 1.2 N s/m): KanesMethod does not give the normal force a Coulomb law needs without auxiliary
   speeds, so the comparison is made on a law both can state. The same path on its fallback without numba
   (solve_ivp with the kernel's lift-off event) is timed and printed beside it, and so is the whole of
   :func:`eulersym.scene.simulate` (plan, cached kernel, the method ``contact_dop853`` with its global-error
   estimate — two or three runs —, the contact outputs and invariants), against the same floor.

A sweep of tippe-top spins (200 members; 50 with ``--quick``) is timed as one sweep and as as many single runs, both
through :func:`eulersym.scene.simulate` (no floor: the figure the issue asks for).

The hand-written equations (body components; ``r = R (α e3 − Γ)`` the contact point from the centre of mass,
``X, Y`` the space axes ``x̂, ŷ`` in body components, the rows of ``R(q)``): the height ``z = R (1 − α Γ3)``, so
``z̈ = −R α (c + k·ω̇)`` with ``c = ((Γ × ω) × ω)_3`` and ``k = e3 × Γ``; the slip ``u`` is the horizontal part of
``v_G + R(q)(ω × r)``, ``v_G = v_x x̂ + v_y ŷ + ż ẑ``; Coulomb ``F = N f``, ``f = −μ u/√(|u|² + ε²)``; the normal
force ``N = M (g + z̈)``; Euler ``I ω̇ + ω × I ω = N w``, ``w = r × (Γ + f_x X + f_y Y)``: a rank-one system
``(I + M R α w kᵀ) ω̇ = M (g − R α c) w − ω × I ω`` solved by Sherman–Morrison; ``v̇ = N f / M``.

Examples
--------
>>> main(["--help"])  # doctest: +ELLIPSIS
usage: eulersym bench contact ...
0
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time

import numpy as np

__all__ = ["main", "hand_rhs"]

_COLD = r"""
import json, os, tempfile, time
os.environ["EULERSYM_CACHE"] = tempfile.mkdtemp()
t0 = time.perf_counter()
import sympy
t1, c1 = time.perf_counter(), time.process_time()
from eulersym.model import Model
from eulersym.model.rolling_kernels import source
from eulersym.scene import bundled
model = Model.from_toml(bundled()["tippe-top"])
report = model.check()
proven = {n: bool(v.conserved) for n, v in model.invariants().items()}
text = source(model.body_on_plane)
t2, c2 = time.perf_counter(), time.process_time()
print(json.dumps({"sympy": t1 - t0, "work": t2 - t1, "cpu": c2 - c1, "ok": bool(report.ok), "proven": proven,
                  "lines": text.count(chr(10))}))
"""


def hand_rhs(t, y, M, R, alpha, I3, gamma_ratio, mu, eps, g=9.81):
    """The gliding tippe top's right-hand side written by hand (module docstring), batched: ``y`` of shape
    ``(14, n)`` in the order ``ω, Γ, q, x, y, v_x, v_y``; returns ``dy/dt`` of the same shape.

    Examples
    --------
    >>> y = np.zeros((14, 1)); y[2] = 100.0; y[5] = 1.0; y[6] = 1.0
    >>> float(hand_rhs(0.0, y, 0.02, 0.02, 0.3, 3.2e-6, 0.95, 0.3, 0.05, 9.81)[2, 0])   # upright: ω̇3 = 0
    0.0
    """
    w1, w2, w3, G1, G2, G3, q0, q1, q2, q3, _, _, vx, vy = y
    I = np.array([gamma_ratio * I3, gamma_ratio * I3, I3])
    w = np.array([w1, w2, w3])
    G = np.array([G1, G2, G3])
    Gdot = np.cross(G, w, axis=0)
    r = R * (np.array([0.0, 0.0, alpha])[:, None] - G)
    # space axes x̂, ŷ in body components: the rows of R(q)
    X = np.array([1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)])
    Y = np.array([2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)])
    wr = np.cross(w, r, axis=0)  # ω × r, body components
    ux = vx + np.sum(X * wr, axis=0)
    uy = vy + np.sum(Y * wr, axis=0)
    scale = -mu / np.sqrt(ux * ux + uy * uy + eps * eps)
    fx, fy = scale * ux, scale * uy
    wvec = np.cross(r, G + fx * X + fy * Y, axis=0)
    c = np.cross(Gdot, w, axis=0)[2]
    k = np.array([-G2, G1, np.zeros_like(G1)])
    Iw = I[:, None] * w
    b = M * (g - R * alpha * c) * wvec - np.cross(w, Iw, axis=0)
    Ib = b / I[:, None]
    Iwv = wvec / I[:, None]
    s = M * R * alpha
    wdot = Ib - s * Iwv * np.sum(k * Ib, axis=0) / (1 + s * np.sum(k * Iwv, axis=0))
    N = M * (g - R * alpha * (c + np.sum(k * wdot, axis=0)))
    qdot = 0.5 * np.array([-q1 * w1 - q2 * w2 - q3 * w3, q0 * w1 + q2 * w3 - q3 * w2,
                           q0 * w2 + q3 * w1 - q1 * w3, q0 * w3 + q1 * w2 - q2 * w1])
    return np.concatenate([wdot, Gdot, qdot, [vx, vy], [N * fx / M, N * fy / M]])


def _states(n: int, seed: int = 20261126) -> np.ndarray:
    rng = np.random.default_rng(seed)
    q = rng.normal(size=(4, n))
    q /= np.linalg.norm(q, axis=0)
    q0, q1, q2, q3 = q
    G = np.array([2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3])
    w = rng.normal(size=(3, n)) * 30
    return np.concatenate([w, G, q, rng.normal(size=(2, n)), rng.normal(size=(2, n)) * 0.1])


def _bundled(name: str) -> str:
    from eulersym.scene import bundled

    return bundled()[name]


def _kernel(path: str):
    """The model kernel of the model in ``path``, from the kernel cache (derived and stored on a miss)."""
    from eulersym.model import Model
    from eulersym.scene import model_kernel

    return model_kernel.ensure(Model.from_toml(path), [])[0]


def _cold() -> dict:
    proc = subprocess.run([sys.executable, "-c", _COLD], capture_output=True, text=True, timeout=600)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr.strip().splitlines()[-1] if proc.stderr else "failed")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _kernel_vs_hand(n: int, repeat: int) -> tuple:
    module = _kernel(_bundled("tippe-top"))
    params = tuple(module.DEFAULTS)
    y = _states(n)
    ours = module.rhs_batched(0.0, y, *params)
    theirs = hand_rhs(0.0, y, *params)
    error = float(np.max(np.abs(ours - theirs) / (1 + np.abs(theirs))))
    times_ours, times_hand = [], []
    out = np.empty_like(y)
    for _ in range(repeat):
        start = time.perf_counter()
        module.rhs_batched(0.0, y, *params, out=out)
        times_ours.append(time.perf_counter() - start)
        start = time.perf_counter()
        hand_rhs(0.0, y, *params)
        times_hand.append(time.perf_counter() - start)
    return statistics.median(times_ours), statistics.median(times_hand), error


def main(argv) -> int:
    """``eulersym bench contact [--quick] [--batch N] [--repeat R]``: the floors of the module docstring."""
    from eulersym.bench.report import floor_line, load_text, ratio_text

    parser = argparse.ArgumentParser(prog="eulersym bench contact", description=__doc__.splitlines()[0])
    parser.add_argument("--batch", type=int, default=100_000, help="states per batched call (default 100000)")
    parser.add_argument("--repeat", type=int, default=7, help="timed repetitions (median)")
    parser.add_argument("--quick", action="store_true", help="10000 states, three repetitions")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    if args.quick:
        args.batch, args.repeat = 10_000, 3
    print(f"eulersym bench contact ({load_text()})")
    cold = _cold()
    ok = cold["work"] <= 10.0 and cold["ok"]
    print(floor_line("tippe top from TOML: both routes proven equal, integrals proven, kernel emitted, cold, beyond "
                     "SymPy's import", f"{cold['work']:.2f} s wall, {cold['cpu']:.2f} s CPU (SymPy's import {cold['sympy']:.2f} s)", "≤ 10 s",
                     ok))
    print(f"  routes equal: {cold['ok']}; integrals: " + ", ".join(f"{n} {'conserved' if c else 'not conserved'}"
                                                                    for n, c in cold["proven"].items())
          + f"; kernel {cold['lines']} lines")
    ours, hand, error = _kernel_vs_hand(args.batch, max(1, args.repeat))
    ratio = ours / hand if hand > 0 else float("inf")
    print(f"rhs_batched on {args.batch} states: generated {ours * 1e3:.2f} ms, hand-written NumPy {hand * 1e3:.2f} ms "
          f"— {ratio_text(hand, ours)}; largest difference {error:.1e} (relative to 1 + |rate|)")
    print(floor_line("generated rhs_batched vs hand-written NumPy", f"{ratio:.2f}×", "≤ 1.5×", ratio <= 1.5))
    ok &= ratio <= 1.5 and error < 1e-10
    ours, theirs, detail = _against_kane(quick=args.quick)
    ratio = theirs / ours if ours > 0 else float("inf")
    print(f"tippe top inversion (viscous, {detail['end']:g} s) at achieved error ≤ 1e-8: eulersym simulate's path (compiled "
          f"DOP853, lift-off checked) {ours * 1e3:.2f} ms ({detail['ours']}), KanesMethod + PyDy "
          f"{detail['generator']} in solve_ivp {theirs * 1e3:.1f} ms ({detail['theirs']}) — "
          f"{ratio_text(theirs, ours)}; PyDy's rhs agrees to {detail['agree']:.1e}; Kane derivation "
          f"{detail['kane_s']:.1f} s, PyDy generation {detail['pydy_s']:.1f} s")
    print(floor_line("eulersym simulate tippe-top's path (compiled DOP853 + lift-off check) vs KanesMethod + PyDy "
                     "in solve_ivp, same achieved error", f"{ratio:.0f}×", "≥ 5×", ratio >= 5))
    fallback = detail["fallback_s"]
    print(f"  the same path without numba (solve_ivp with the lift-off event): {fallback * 1e3:.1f} ms "
          f"({detail['fallback']}) — {ratio_text(theirs, fallback)}")
    scene_s = detail["scene_s"]
    whole = theirs / scene_s if scene_s > 0 else float("inf")
    print(f"  the whole of eulersym.scene.simulate (plan, cached kernel, contact_dop853 with its error estimate, "
          f"contact outputs, invariants): {scene_s * 1e3:.2f} ms ({detail['scene']}) — {ratio_text(theirs, scene_s)}")
    print(floor_line("eulersym.scene.simulate on the tippe top vs KanesMethod + PyDy in solve_ivp, same achieved "
                     "error", f"{whole:.1f}×", "≥ 5×", whole >= 5))
    ok &= ratio >= 5
    members = 50 if args.quick else 200
    batched, singles, worst = _sweep(members, 5.0)
    print(f"tippe-top spin sweep, {members} members (40–130 rad/s, 5 s, accuracy 1e-6): one sweep {batched:.2f} s, "
          f"{members} single runs {singles:.2f} s — {ratio_text(singles, batched)}; largest difference "
          f"{worst:.1e} (relative)")
    return 0 if ok else 1


_VISCOUS = {"M": 0.02, "R": 0.02, "alpha": 0.3, "I3": 3.2e-6, "gamma_ratio": 0.95, "mu": 1.2, "g": 9.81}


def _kane():
    """The viscous gliding tippe top by sympy.physics.mechanics' KanesMethod, and PyDy's right-hand side of it."""
    import sympy as sp
    import sympy.physics.mechanics as me
    from pydy.codegen.ode_function_generators import generate_ode_function

    start = time.perf_counter()
    q1, q2, q3, x, y = me.dynamicsymbols("q1 q2 q3 x y")
    u1, u2, u3, u4, u5 = me.dynamicsymbols("u1:6")
    M, R, alpha, I3, ratio, mu, g = sp.symbols("M R alpha I3 gamma_ratio mu g")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Body", [q1, q2, q3], "313")
    w = B.ang_vel_in(N)
    kd = [w.dot(B.x) - u1, w.dot(B.y) - u2, w.dot(B.z) - u3, x.diff() - u4, y.diff() - u5]
    B.set_ang_vel(N, u1 * B.x + u2 * B.y + u3 * B.z)
    rates = sp.solve(kd, [q1.diff(), q2.diff(), q3.diff(), x.diff(), y.diff()], dict=True)[0]
    z = R * (1 - alpha * B.z.dot(N.z))
    G = me.Point("O").locatenew("G", x * N.x + y * N.y + z * N.z)
    G.set_vel(N, u4 * N.x + u5 * N.y + z.diff(me.dynamicsymbols._t).subs(rates) * N.z)
    P = G.locatenew("P", R * alpha * B.z - R * N.z)
    P.v2pt_theory(G, N, B)
    friction = -mu * (P.vel(N).dot(N.x) * N.x + P.vel(N).dot(N.y) * N.y)
    body = me.RigidBody("top", G, B, M, (me.inertia(B, ratio * I3, ratio * I3, I3), G))
    kane = me.KanesMethod(N, q_ind=[q1, q2, q3, x, y], u_ind=[u1, u2, u3, u4, u5], kd_eqs=kd)
    kane.kanes_equations([body], [(G, -M * g * N.z), (P, friction)])
    kane_s = time.perf_counter() - start
    start = time.perf_counter()
    constants = [M, R, alpha, I3, ratio, mu, g]
    try:
        rhs = generate_ode_function(kane.forcing_full, [q1, q2, q3, x, y], [u1, u2, u3, u4, u5], constants,
                                    mass_matrix=kane.mass_matrix_full, generator="cython")
        generator = "cython"
    except Exception:  # noqa: BLE001 - no compiler: PyDy's pure-Python generator
        rhs = generate_ode_function(kane.forcing_full, [q1, q2, q3, x, y], [u1, u2, u3, u4, u5], constants,
                                    mass_matrix=kane.mass_matrix_full, generator="lambdify")
        generator = "lambdify"
    pydy_s = time.perf_counter() - start
    return rhs, generator, kane_s, pydy_s


def _euler_state(phi, theta, psi, omega):
    """eulersym's state (ω, Γ, q, x, y, v_x, v_y) at z-x-z angles: Γ = (sin θ sin ψ, sin θ cos ψ, cos θ), q of
    R = D(φ)ᵀ C(θ)ᵀ B(ψ)ᵀ (v_space = R v_body), scalar first."""
    from eulersym.attitude import Attitude

    q = Attitude.from_euler((phi, theta, psi), "zxz").as_quaternion()
    gamma = [np.sin(theta) * np.sin(psi), np.sin(theta) * np.cos(psi), np.cos(theta)]
    return np.concatenate([omega, gamma, q, [0.0, 0.0, 0.0, 0.0]])


def _simulate_path(text: str, angles, omega, end: float, points: int):
    """``run(accuracy)``: the whole of ``eulersym.scene.simulate`` on the model of ``text`` — plan, the cached kernel,
    the method ``contact_dop853`` with its error estimate, the contact outputs and invariants — returning the final
    (ω, Γ) as a state-shaped row (the rest zero) for :func:`_compare_scene`."""
    import tomllib

    from eulersym.model import Model
    from eulersym.scene import Scene, simulate

    data = tomllib.loads(text)
    model = Model.from_dict({k: v for k, v in data.items() if k not in ("initial", "time", "output")})

    def run(accuracy):
        result = simulate(Scene(model=model, euler=angles, omega=tuple(omega), t_end=end, points=points,
                                accuracy=accuracy, outputs=("omega", "invariants")))
        return np.concatenate([result.omega[-1], result.gamma[-1]])
    return run


def _compare_scene(y, ref):  # ω and Γ, relative (the scene reports the velocity as x_cm, y_cm only)
    picks = np.r_[0:6]
    return float(np.max(np.abs(y[:6] - ref[picks])) / np.max(np.abs(ref[picks])))


def _sweep(members: int, end: float) -> tuple:
    """(seconds of one sweep of ``members`` tippe-top spins, seconds of the same members as single runs, the largest
    difference): both through ``eulersym.scene.simulate`` at accuracy 1e-6, the kernel cached and compiled first."""
    from eulersym.model import Model
    from eulersym.scene import Scene, bundled, simulate

    model = Model.from_toml(bundled()["tippe-top"])
    settings = dict(model=model, axis=(1, 0, 0), angle=0.1, t_end=end, points=26, accuracy=1e-6)
    spins = np.linspace(40.0, 130.0, members)
    simulate(Scene(omega=(0, 0, {"start": 40.0, "stop": 130.0, "num": 2}), **settings))  # numba's compilations
    simulate(Scene(omega=(0, 0, 40.0), **settings))
    start = time.perf_counter()
    sweep = simulate(Scene(omega=(0, 0, {"start": 40.0, "stop": 130.0, "num": members}), **settings))
    batched = time.perf_counter() - start
    start = time.perf_counter()
    worst = 0.0
    for b, spin in enumerate(spins):
        single = simulate(Scene(omega=(0, 0, float(spin)), **settings))
        worst = max(worst, float(np.max(np.abs(single.omega - sweep.omega[b])) / np.max(np.abs(single.omega))))
    return batched, time.perf_counter() - start, worst


def _loosest(run, reference, tolerances, error_of):
    """The fastest run (median of three) among tolerances whose error against reference is ≤ 1e-8."""
    best = None
    for rtol in tolerances:
        y = run(rtol)
        error = error_of(y, reference)
        if error <= 1e-8:
            times = []
            for _ in range(3):
                start = time.perf_counter()
                run(rtol)
                times.append(time.perf_counter() - start)
            best = (statistics.median(times), f"rtol {rtol:g}, error {error:.1e}")
            break
    return best or (float("inf"), "no tolerance reached 1e-8")


def _against_kane(quick: bool = False) -> tuple:
    import os
    import tempfile

    from scipy.integrate import solve_ivp

    from eulersym.model.contact_motion import integrate

    with open(_bundled("tippe-top"), encoding="utf-8") as f:
        text = f.read()
    text = text.replace('friction = "coulomb"', 'friction = "viscous"').replace('width = "eps"\n', "")
    text = text.replace("mu = 0.3 ", "mu = 1.2 ").replace("eps = 0.05 ", "# eps = 0.05 ")
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "tippe-top-viscous.toml")
        with open(path, "w") as f:
            f.write(text)
        module = _kernel(path)
    path_text = text
    params = tuple(module.DEFAULTS)
    if dict(zip(module.PARAMETERS, params)) != {k: v for k, v in _VISCOUS.items() if k != "g"}:
        raise RuntimeError(f"the viscous tippe top's parameters are {dict(zip(module.PARAMETERS, params))}")
    rhs, generator, kane_s, pydy_s = _kane()
    constants = np.array(list(_VISCOUS.values()))
    angles, omega = (0.3, 0.1, 0.7), np.array([0.0, 0.0, 100.0])
    y0 = _euler_state(*angles, omega)
    x0 = np.concatenate([angles, [0.0, 0.0], omega, [0.0, 0.0]])
    ours0, theirs0 = module.rhs(0.0, y0, *params), rhs(x0, 0.0, constants)
    agree = float(np.max(np.abs(np.concatenate([ours0[0:3] - theirs0[5:8], ours0[12:14] - theirs0[8:10]]))
                         / (1 + np.abs(theirs0[5:10]))))
    end = 0.5 if quick else 1.0
    times = np.linspace(0.0, end, 1 + int(round(100 * end)))

    def scene_path(compiled):
        def run(rtol):  # the engine of eulersym simulate's path for a contact scene, on the same kernel
            return integrate(module, y0, times, params=params, rtol=rtol, atol=rtol * 1e-2, compiled=compiled).y[-1]
        return run

    ours = scene_path(None)

    def theirs(rtol):
        return solve_ivp(lambda t, x: rhs(x, t, constants), (0.0, end), x0, method="DOP853", rtol=rtol,
                         atol=rtol * 1e-2).y[:, -1]

    def compare_ours(y, ref):  # ω, Γ and the velocity, relative
        picks = np.r_[0:6, 12:14]
        return float(np.max(np.abs(y[picks] - ref[picks])) / np.max(np.abs(ref[picks])))

    def compare_theirs(x, ref):
        phi, theta, psi = x[0:3]
        gamma = np.array([np.sin(theta) * np.sin(psi), np.sin(theta) * np.cos(psi), np.cos(theta)])
        mine = np.concatenate([x[5:8], gamma, x[8:10]])
        picks = np.r_[0:6, 12:14]
        return float(np.max(np.abs(mine - ref[picks])) / np.max(np.abs(ref[picks])))

    reference = integrate(module, y0, times, params=params, rtol=1e-13, atol=1e-15, compiled=False).y[-1]
    scene_s, scene_text = _loosest(_simulate_path(path_text, angles, omega, end, times.size), reference,
                                   [10.0 ** -k for k in range(5, 13)], _compare_scene)
    tolerances = [10.0 ** -k for k in range(6, 14)]
    ours(1e-6)  # compiled once (numba), outside the timing, as PyDy's generation is
    ours_s, ours_text = _loosest(ours, reference, tolerances, compare_ours)
    theirs_s, theirs_text = _loosest(theirs, reference, tolerances, compare_theirs)
    fallback_s, fallback_text = _loosest(scene_path(False), reference, tolerances, compare_ours)
    return ours_s, theirs_s, {"ours": ours_text, "theirs": theirs_text, "generator": generator, "agree": agree,
                              "scene_s": scene_s, "scene": scene_text.replace("rtol", "accuracy"),
                              "kane_s": kane_s, "pydy_s": pydy_s, "fallback_s": fallback_s, "fallback": fallback_text,
                              "end": end}
