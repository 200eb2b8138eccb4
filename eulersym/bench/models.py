"""A user's model end to end: Kovalevskaya's top from its TOML — derive, prove, emit, and its kernels' speed.

Every ratio is measured in the same run, against the floors of issue 10:

- **cold**: in a fresh process, Kovalevskaya's top from its TOML file (``eulersym/models/kovalevskaya.toml``):
  derive both routes (Newton–Euler, Lagrange in zxz), prove them equal (:func:`eulersym.model.derive.check`),
  prove its four integrals (E, |Γ|², L·Γ, Kovalevskaya's K) and emit the kernel module — the seconds *beyond*
  SymPy's own import, measured inside the process (median of the runs) ≤ 5 s;
- **scalar**: the generated ``rhs(t, y, *params)`` (one call with an ndarray state, as ``solve_ivp`` passes it)
  within 1.5× of a hand-written Python-float function of the same equations;
- **batched**: ``rhs_batched(t, Y, *params, out=...)`` within 1.5× of hand-written vectorised NumPy;
- **PyDy**: both ≥ 5× faster than ``sympy.physics.mechanics`` (KanesMethod, the same body in zxz Euler angles,
  generalised speeds the body components of ω) + PyDy's ``generate_ode_function`` right-hand side (per state).
  PyDy is the ``bench`` extra; without it the bench says so and skips the row.

The hand-written baselines are typed here on purpose (they are what the floors compare with); the bench checks
that they, and PyDy's ω̇, agree with the generated kernel before timing. Timings are medians of repeats; on a
loaded machine they are noisy, the ratios (measured side by side) less so.

Run ``eulersym bench models [--quick] [--states N]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
import timeit

import numpy as np

__all__ = ["main", "hand_written_rhs", "hand_written_rhs_batched"]

_COLD = r"""
import sys, time
t0 = time.perf_counter()
import sympy
t1 = time.perf_counter()
from eulersym.model import Model, derive, integrals, kernels
model = Model.from_toml(sys.argv[1])
mech = model.mechanics
newton_euler = derive.equations(mech)
lagrange = derive.lagrange_equations(mech, "zxz")
report = derive.check(mech, ["zxz"])
verdicts = integrals.invariants(mech)
four = all(verdicts[name].conserved for name in ("E", "Gamma_norm2", "L_dot_Gamma", "K"))
text = kernels.source(mech, digest=model.digest)
t2 = time.perf_counter()
print(t1 - t0, t2 - t1, report.ok, four, len(text))
"""


def hand_written_rhs(t, y, C, M, a, g):
    """Kovalevskaya's top (I = diag(2C, 2C, C), centre of mass (0, a, 0)) by hand, Python floats.

    ``I ω̇ = (I ω) × ω + M g Γ × c``, ``Γ̇ = Γ × ω``, ``q̇ = ½ q ⊗ (0, ω)``. (A benchmark baseline, typed on
    purpose; :func:`main` checks it against the generated kernel.)

    Examples
    --------
    >>> y = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0])
    >>> [round(x, 9) for x in hand_written_rhs(0.0, y, 1.0, 1.0, 0.1, 9.81)[:3]]
    [-0.4905, -0.0, 0.0]
    """
    w1, w2, w3, G1, G2, G3, q0, q1, q2, q3 = y.tolist()
    mga = M * g * a
    return [(C * w2 * w3 - mga * G3) / (2.0 * C), -0.5 * w1 * w3, mga * G1 / C,
            G2 * w3 - G3 * w2, G3 * w1 - G1 * w3, G1 * w2 - G2 * w1,
            -0.5 * (q1 * w1 + q2 * w2 + q3 * w3), 0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
            0.5 * (q0 * w2 + q3 * w1 - q1 * w3), 0.5 * (q0 * w3 + q1 * w2 - q2 * w1)]


def hand_written_rhs_batched(t, Y, C, M, a, g, out):
    """The same equations by hand in vectorised NumPy, written into ``out`` (rows: the state, batch after).

    Examples
    --------
    >>> Y = np.zeros((10, 2)); Y[2] = 1.0; Y[5] = 1.0; Y[6] = 1.0
    >>> hand_written_rhs_batched(0.0, Y, 1.0, 1.0, 0.1, 9.81, np.empty((10, 2)))[0]
    array([-0.4905, -0.4905])
    """
    w1, w2, w3, G1, G2, G3, q0, q1, q2, q3 = Y
    mga = M * g * a
    out[0] = (C * w2 * w3 - mga * G3) / (2.0 * C)
    out[1] = -0.5 * w1 * w3
    out[2] = mga / C * G1
    out[3] = G2 * w3 - G3 * w2
    out[4] = G3 * w1 - G1 * w3
    out[5] = G1 * w2 - G2 * w1
    out[6] = -0.5 * (q1 * w1 + q2 * w2 + q3 * w3)
    out[7] = 0.5 * (q0 * w1 + q2 * w3 - q3 * w2)
    out[8] = 0.5 * (q0 * w2 + q3 * w1 - q1 * w3)
    out[9] = 0.5 * (q0 * w3 + q1 * w2 - q2 * w1)
    return out


def _side_by_side(funcs, repeat: int, budget: float = 0.05) -> list:
    """Median seconds per call of each function, timed in alternation (a load spike hits both alike)."""
    numbers = []
    for func in funcs:
        t0 = time.perf_counter()
        func()
        numbers.append(max(1, int(budget / max(time.perf_counter() - t0, 1e-7))))
    samples = [[] for _ in funcs]
    for _ in range(repeat):
        for k, func in enumerate(funcs):
            samples[k].append(timeit.timeit(func, number=numbers[k]) / numbers[k])
    return [statistics.median(s) for s in samples]


def _row(name, value, unit, ratio="", floor="", ok=None):
    mark = "" if ok is None else ("ok" if ok else "FAIL")
    print(f"{name:<52} {value:>11.4g} {unit:<3} {ratio:>16} {floor:>9} {mark}")


def _pydy_rhs(backend: str):
    """PyDy's right-hand side of the same body: (rhs(x, t, p), the state map). x = (zxz angles, body ω)."""
    import sympy as sp
    from pydy.codegen.ode_function_generators import generate_ode_function
    from sympy.physics.mechanics import KanesMethod, Point, ReferenceFrame, RigidBody, dynamicsymbols, inertia

    q = dynamicsymbols("q1:4")
    u = dynamicsymbols("u1:4")
    C, M, a, g = sp.symbols("C M a g")
    N, B = ReferenceFrame("N"), ReferenceFrame("B")
    B.orient_body_fixed(N, q, "zxz")
    w = B.ang_vel_in(N)
    kd = [w.dot(B.x) - u[0], w.dot(B.y) - u[1], w.dot(B.z) - u[2]]
    B.set_ang_vel(N, u[0] * B.x + u[1] * B.y + u[2] * B.z)
    O = Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", a * B.y)
    G.v2pt_theory(O, N, B)
    body = RigidBody("body", G, B, M, (inertia(B, 2 * C, 2 * C, C), O))
    kane = KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    kane.kanes_equations([body], [(G, -M * g * N.z)])
    return generate_ode_function(kane.forcing_full, q, u, [C, M, a, g], mass_matrix=kane.mass_matrix_full,
                                 generator=backend)


def _cold(path: str, runs: int) -> list:
    out = []
    for _ in range(runs):
        result = subprocess.run([sys.executable, "-c", _COLD, path], capture_output=True, text=True)
        if result.returncode != 0:
            raise RuntimeError(f"the cold run failed: {result.stderr.strip()[-500:]}")
        sympy_s, work_s, ok, four, size = result.stdout.split()
        out.append((float(sympy_s), float(work_s), ok == "True", four == "True", int(size)))
    return out


def main(argv: list[str] | None = None) -> int:
    """Run the model benchmarks and print each figure with its floor; 0 when every floor is met, else 1.

    Examples
    --------
    >>> callable(main)
    True
    """
    from eulersym.model import Model, kernels
    from eulersym.models import bundled
    from eulersym.rotation import euler_matrix, to_quaternion

    parser = argparse.ArgumentParser(prog="eulersym bench models", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one cold run, 10^4 states, no cython (smoke run)")
    parser.add_argument("--states", type=int, default=100_000, help="batch size (default 10^5)")
    args = parser.parse_args(argv or [])
    n_states = 10_000 if args.quick else args.states
    repeat = 5 if args.quick else 15
    failures = 0
    path = str(bundled()["kovalevskaya"])
    print(f"eulersym bench models — Kovalevskaya's top from {os.path.basename(path)}; Python "
          f"{sys.version.split()[0]}, NumPy {np.__version__}, {os.cpu_count()} CPUs (medians; noisy on a shared "
          "machine)\n")
    print(f"{'measurement':<52} {'value':>11} {'':<3} {'ratio':>16} {'floor':>9}")

    # 1. Cold: derive both routes, prove equal, prove four integrals, emit.
    runs = _cold(path, 1 if args.quick else 3)
    sympy_s = statistics.median(r[0] for r in runs)
    work_s = statistics.median(r[1] for r in runs)
    proven = all(r[2] and r[3] for r in runs)
    ok = work_s <= 5.0 and proven
    failures += not ok
    _row(f"import sympy (fresh process, median of {len(runs)})", sympy_s, "s")
    _row("  derive 2 routes + prove equal + 4 integrals + emit", work_s, "s", "beyond SymPy", "≤ 5 s", ok)
    if not proven:
        print("  note: a proof FAILED in the cold run")

    # 2. Scalar rhs vs hand-written Python floats.
    model = Model.from_toml(path)
    kernel = kernels.compile(model.mechanics)
    params = kernel.DEFAULTS
    angles = (0.3, 1.0, 0.4)
    A = np.array(euler_matrix(*angles), dtype=float)
    y = np.concatenate([[0.5, -0.3, 2.0], A[:, 2], to_quaternion(A)])
    agree = np.allclose(kernel.rhs(0.0, y, *params), hand_written_rhs(0.0, y, *params), rtol=1e-13, atol=1e-14)
    ours, hand = _side_by_side([lambda: kernel.rhs(0.0, y, *params), lambda: hand_written_rhs(0.0, y, *params)],
                               repeat)
    ratio = ours / hand
    ok = ratio <= 1.5 and agree
    failures += not ok
    print()
    _row("generated rhs (scalar, 1 call, ndarray state)", ours * 1e6, "µs")
    _row("  hand-written Python floats" + ("" if agree else " (DISAGREES)"), hand * 1e6, "µs",
         f"{ratio:.2f}× of it", "≤ 1.5×", ok)

    # 3. Batched rhs vs hand-written NumPy.
    rng = np.random.default_rng(0)
    Y = rng.normal(size=(10, n_states))
    out, out_hand = np.empty_like(Y), np.empty_like(Y)
    ours_b, hand_b = _side_by_side([lambda: kernel.rhs_batched(0.0, Y, *params, out=out),
                                    lambda: hand_written_rhs_batched(0.0, Y, *params, out_hand)], repeat)
    agree = np.allclose(out, out_hand, rtol=1e-12, atol=1e-12)
    ratio = ours_b / hand_b
    ok = ratio <= 1.5 and agree
    failures += not ok
    print()
    _row(f"generated rhs_batched ({n_states} states, out=)", ours_b * 1e3, "ms")
    _row("  hand-written vectorised NumPy" + ("" if agree else " (DISAGREES)"), hand_b * 1e3, "ms",
         f"{ratio:.2f}× of it", "≤ 1.5×", ok)

    # 4. sympy.physics.mechanics + PyDy.
    print()
    try:
        import pydy  # noqa: F401
    except ImportError:
        print("sympy.physics.mechanics + PyDy: skipped — pydy is not installed (`pip install eulersym[bench]`)")
    else:
        x = np.array([*angles, 0.5, -0.3, 2.0])
        for backend in ("lambdify",) if args.quick else ("lambdify", "cython"):
            try:
                t0 = time.perf_counter()
                f = _pydy_rhs(backend)
                build = time.perf_counter() - t0
            except Exception as exc:  # noqa: BLE001 - a missing compiler must not stop the bench
                print(f"PyDy {backend}: unavailable ({type(exc).__name__}: {exc})")
                continue
            p = np.array(params)
            theirs = np.asarray(f(x, 0.0, p), dtype=float)
            agree = np.allclose(theirs[3:], kernel.rhs(0.0, y, *params)[:3], rtol=1e-10, atol=1e-12)
            (pydy_t,) = _side_by_side([lambda: f(x, 0.0, p)], repeat)
            scalar_ratio = pydy_t / ours
            batched_ratio = pydy_t / (ours_b / n_states)
            ok_s, ok_b = scalar_ratio >= 5 and agree, batched_ratio >= 5 and agree
            failures += (not ok_s) + (not ok_b)
            _row(f"PyDy {backend} rhs (1 call; built in {build:.1f} s)" + ("" if agree else " (DISAGREES)"),
                 pydy_t * 1e6, "µs")
            _row("  generated scalar rhs, faster by", scalar_ratio, "×", "", "≥ 5×", ok_s)
            _row("  generated batched rhs per state, faster by", batched_ratio, "×", "", "≥ 5×", ok_b)
    print(f"\n{'all floors met' if not failures else f'{failures} floor(s) missed'}")
    return 0 if not failures else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(sys.argv[1:]))
