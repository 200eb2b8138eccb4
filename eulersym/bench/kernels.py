"""Generated kernels vs pydy (or sympy.lambdify), hand-written NumPy, a Python loop; import and generate times.

Every ratio is measured in the same run, against the floors of issue 4:

- scalar heavy-top right-hand side (``heavy_top_euler_angles.rhs``, one call with an ndarray state as
  ``solve_ivp`` passes it) ≥ 8× faster than pydy's ``generate_ode_function`` lambdify backend and no slower
  than its cython backend (pydy and cython are the ``bench`` extra; without them the baseline is
  ``sympy.lambdify(cse=True)`` of the same derivation, and the bench says so);
- batched Euler–Poisson right-hand side over 10⁶ states within 2× of a hand-written vectorised NumPy
  expression of the same equations, and ≥ 500× faster per state than looping the scalar kernel in Python;
- importing a generated module in a fresh process ≤ 30 ms beyond NumPy's import;
- ``eulersym generate`` for the whole catalogue ≤ 10 s (fresh process, into a temporary folder).

Run ``eulersym bench kernels`` (``--states N`` to change the batch, ``--quick`` for a smoke run).
"""

from __future__ import annotations

import argparse
import importlib
import os
import subprocess
import sys
import tempfile
import time
import timeit

import numpy as np

__all__ = ["main", "hand_written_euler_poisson"]


def _best(func, number: int, repeat: int = 5) -> float:
    """Best time per call, in seconds."""
    return min(timeit.repeat(func, number=number, repeat=repeat)) / number


def _per_call(func, budget: float = 0.2) -> float:
    t0 = time.perf_counter()
    func()
    once = max(time.perf_counter() - t0, 1e-7)
    number = max(1, int(budget / once))
    return _best(func, number)


def hand_written_euler_poisson(y, I1, I2, I3, M, g, l, out):
    """The Euler–Poisson heavy top written by hand in vectorised NumPy: the baseline the floors compare with.

    ``I ω̇ = (Iω) × ω + M g l Γ × e3``, ``Γ̇ = Γ × ω``, ``q̇ = ½ q ⊗ (0, ω)``. (A benchmark baseline, typed on
    purpose; the bench checks that it agrees with the generated kernel.)

    Examples
    --------
    >>> from eulersym.generated import heavy_top_euler_poisson as kernel
    >>> y = np.random.default_rng(1).normal(size=(10, 4))
    >>> p = (1.0, 2.0, 3.0, 1.0, 9.81, 0.5)
    >>> np.allclose(hand_written_euler_poisson(y, *p, np.empty((10, 4))), kernel.rhs_batched(0.0, y, *p))
    True
    """
    w1, w2, w3, G1, G2, G3, q0, q1, q2, q3 = y
    mgl = M * g * l
    out[0] = ((I2 - I3) * w2 * w3 + mgl * G2) / I1
    out[1] = ((I3 - I1) * w3 * w1 - mgl * G1) / I2
    out[2] = (I1 - I2) / I3 * w1 * w2
    out[3] = G2 * w3 - G3 * w2
    out[4] = G3 * w1 - G1 * w3
    out[5] = G1 * w2 - G2 * w1
    out[6] = -0.5 * (q1 * w1 + q2 * w2 + q3 * w3)
    out[7] = 0.5 * (q0 * w1 + q2 * w3 - q3 * w2)
    out[8] = 0.5 * (q0 * w2 + q3 * w1 - q1 * w3)
    out[9] = 0.5 * (q0 * w3 + q1 * w2 - q2 * w1)
    return out


# ----------------------------------------------------------------------------------------------------------------
# Baselines for the scalar heavy top


def _top_mass_matrix_form():
    """(M, F, q, u, constants) of the Euler-angle top from eulersym.top, for pydy: M(q) u̇ = F(q, u)."""
    import sympy as sp
    from sympy.physics.mechanics import dynamicsymbols

    from eulersym import top
    from eulersym.symbols import I1, I3, M, g, l, phi, psi, t, theta

    q = [phi, theta, psi]
    u = dynamicsymbols("u1:4")
    sub = {qi.diff(t, 2): ui.diff(t) for qi, ui in zip(q, u)}
    sub.update({qi.diff(t): ui for qi, ui in zip(q, u)})
    residuals = [(e.lhs - e.rhs).subs(sub) for e in top.equations_of_motion()]
    Mm, F = sp.linear_eq_to_matrix(residuals, [ui.diff(t) for ui in u])
    return Mm, F, q, u, [I1, I3, M, g, l]


def _scalar_baselines(params, state):
    """{name: callable()} of the baselines available here, and notes."""
    import sympy as sp

    notes = []
    baselines = {}
    Mm, F, q, u, constants = _top_mass_matrix_form()
    try:
        from pydy.codegen.ode_function_generators import generate_ode_function
    except ImportError:
        generate_ode_function = None
        notes.append("pydy is not installed (`pip install eulersym[bench]`): baseline is sympy.lambdify(cse=True)")
    p = np.array(params)
    if generate_ode_function is not None:
        for backend in ("lambdify", "cython"):
            try:
                f = generate_ode_function(F, q, u, constants, mass_matrix=Mm, coordinate_derivatives=sp.Matrix(u),
                                          generator=backend)
            except Exception as exc:  # noqa: BLE001 - a missing compiler must not stop the bench
                notes.append(f"pydy {backend} backend unavailable: {type(exc).__name__}: {exc}")
                continue
            baselines[f"pydy {backend}"] = (lambda f=f: f(state, 0.0, p))
    from eulersym.codegen import build

    spec = build("heavy_top_euler_angles").functions[0]
    lam = sp.lambdify(list(spec.symbols), list(spec.expressions), modules="math", cse=True)
    baselines["sympy.lambdify(cse=True)"] = lambda: lam(0.0, *state, *params)
    return baselines, notes


# ----------------------------------------------------------------------------------------------------------------
# Fresh-process measurements


def _fresh_import(module: str, repeat: int) -> tuple[float, float]:
    """(NumPy import, module import beyond NumPy) in fresh processes, best of ``repeat``, seconds."""
    code = ("import time; t0 = time.perf_counter(); import numpy; t1 = time.perf_counter(); "
            f"import {module}; t2 = time.perf_counter(); print(t1 - t0, t2 - t1)")
    best = (float("inf"), float("inf"))
    for _ in range(repeat):
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
        a, b = map(float, out.split())
        best = (min(best[0], a), min(best[1], b))
    return best


def _fresh_generate() -> float:
    with tempfile.TemporaryDirectory() as d:
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "eulersym", "generate", "--dir", d], check=True,
                       capture_output=True)
        return time.perf_counter() - t0


def _row(name, value, unit, ratio="", floor="", ok=None):
    mark = "" if ok is None else ("ok" if ok else "FAIL")
    print(f"{name:<48} {value:>12.4g} {unit:<4} {ratio:>14} {floor:>16} {mark}")


def main(argv: list[str] | None = None) -> int:
    """Run the kernel benchmarks and print each ratio with its floor; return 0 (1 if a floor is missed).

    Examples
    --------
    >>> callable(main)
    True
    """
    parser = argparse.ArgumentParser(prog="eulersym bench kernels", description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=1_000_000, help="batch size (default 10^6)")
    parser.add_argument("--quick", action="store_true", help="smaller batch and fewer repeats (smoke run)")
    args = parser.parse_args(argv or [])
    n_states = 10_000 if args.quick else args.states
    repeat = 2 if args.quick else 5
    failures = 0

    print(f"eulersym bench kernels — Python {sys.version.split()[0]}, NumPy {np.__version__}, "
          f"{os.cpu_count()} CPUs\n")
    print(f"{'measurement':<48} {'value':>12} {'':<4} {'ratio':>14} {'floor':>16}")

    # 1. Scalar heavy top (Euler angles), one call with an ndarray state.
    from eulersym.codegen import available

    if available("heavy_top_euler_angles")[0]:
        top = importlib.import_module("eulersym.generated.heavy_top_euler_angles")
        params = (1.0, 0.6, 1.2, 9.81, 0.3)
        state = np.array([0.1, 0.9, 0.2, 0.5, 0.3, 12.0])
        ours = _per_call(lambda: top.rhs(0.0, state, *params))
        _row("heavy_top_euler_angles.rhs (scalar, 1 call)", ours * 1e6, "µs")
        baselines, notes = _scalar_baselines(params, state)
        for name, call in baselines.items():
            ref = np.asarray(call(), dtype=float).ravel()
            agree = np.allclose(ref, top.rhs(0.0, state, *params), rtol=1e-12, atol=1e-12)
            t = _per_call(call)
            ratio = t / ours
            if name == "pydy lambdify":
                floor, ok = "≥ 8×", ratio >= 8
            elif name == "pydy cython":
                floor, ok = "≥ 1×", ratio >= 1
            else:
                floor, ok = "(info)", None
            failures += ok is False
            _row(f"  {name}" + ("" if agree else " (DISAGREES)"), t * 1e6, "µs", f"{ratio:.1f}× slower", floor, ok)
        ours_array = _per_call(lambda: np.array(top.rhs(0.0, state, *params)))
        _row("  rhs wrapped in np.array (info)", ours_array * 1e6, "µs")
        for note in notes:
            print(f"  note: {note}")
    else:
        print("heavy_top_euler_angles is unavailable (eulersym.top missing): scalar floor not measured")

    # 2. Batched Euler–Poisson over n states.
    ep = importlib.import_module("eulersym.generated.heavy_top_euler_poisson")
    rng = np.random.default_rng(0)
    p = (1.0, 1.6, 2.2, 1.2, 9.81, 0.3)
    Y = rng.normal(size=(10, n_states))
    out = np.empty_like(Y)
    out_hand = np.empty_like(Y)
    ours = _best(lambda: ep.rhs_batched(0.0, Y, *p, out=out), 1, repeat)
    hand = _best(lambda: hand_written_euler_poisson(Y, *p, out_hand), 1, repeat)
    agree = np.allclose(out, out_hand, rtol=1e-12, atol=1e-12)
    print()
    _row(f"heavy_top_euler_poisson.rhs_batched ({n_states} states)", ours * 1e3, "ms")
    ratio = ours / hand
    failures += ratio > 2
    _row("  hand-written NumPy" + ("" if agree else " (DISAGREES)"), hand * 1e3, "ms",
         f"{ratio:.2f}× of it", "≤ 2×", ratio <= 2)
    loop_n = 2000 if args.quick else 20000
    columns = [Y[:, k].copy() for k in range(loop_n)]
    loop = _best(lambda: [ep.rhs(0.0, c, *p) for c in columns], 1, max(2, repeat // 2)) / loop_n
    per_state = ours / n_states
    speedup = loop / per_state
    failures += speedup < 500
    _row("  Python loop of the scalar rhs, per state", loop * 1e9, "ns", f"{speedup:.0f}× per state", "≥ 500×",
         speedup >= 500)
    _row("  (hand-written NumPy vs the same loop: NumPy's ceiling)", loop / (hand / n_states), "×")

    # 3. Import time beyond NumPy, fresh process.
    numpy_t, module_t = _fresh_import("eulersym.generated.heavy_top_euler_poisson", repeat)
    print()
    failures += module_t > 0.030
    _row("import numpy (fresh process)", numpy_t * 1e3, "ms")
    _row("  import a generated module beyond NumPy", module_t * 1e3, "ms", "", "≤ 30 ms", module_t <= 0.030)

    # 4. eulersym generate for the whole catalogue.
    gen = _fresh_generate()
    failures += gen > 10
    _row("eulersym generate (whole catalogue, fresh)", gen, "s", "", "≤ 10 s", gen <= 10)
    print(f"\n{'all floors met' if not failures else f'{failures} floor(s) missed'}")
    return 0 if not failures else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(sys.argv[1:]))
