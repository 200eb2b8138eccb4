"""Seconds of each derivation and of a cold `eulersym check`, beside SymPy baselines, with ratios.

Run ``eulersym bench derive [--quick] [--csv FILE]``. Every derivation is timed cold: all of eulersym's
``lru_cache`` caches are cleared before each repetition, and the best of ``--repeat`` runs is kept. Baselines, timed in
the same run:

* ω in Euler angles: ``sympy.simplify(−Ȧ Aᵀ)`` (the naive route; skipped with ``--quick``) and
  ``sympy.physics.mechanics`` (``orient_body_fixed`` + ``ang_vel_in``);
* the heavy top's equations of motion: ``sympy.physics.mechanics.LagrangesMethod`` on the same top (RigidBody with
  the same inertia, the same potential);
* a cold ``eulersym check`` in a fresh process, minus the import time of SymPy itself in a fresh process.
"""

from __future__ import annotations

import argparse
import csv
import subprocess
import sys
import time
from typing import Callable

from eulersym.bench.report import ratio_text

__all__ = ["main"]


def _clear_caches() -> None:
    for name, module in list(sys.modules.items()):
        if not name.startswith("eulersym") or module is None:
            continue
        for value in vars(module).values():
            clear = getattr(value, "cache_clear", None)
            if callable(clear):
                clear()


def _best(fn: Callable[[], object], repeat: int, cold: bool = True) -> float:
    best = float("inf")
    for _ in range(repeat):
        if cold:
            _clear_caches()
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def _fresh_process_seconds(code: str) -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)
    return time.perf_counter() - start


def _mechanics_omega():
    from sympy.physics.mechanics import ReferenceFrame

    from eulersym.symbols import phi, psi, theta

    N, B = ReferenceFrame("N"), ReferenceFrame("B")
    B.orient_body_fixed(N, (phi, theta, psi), "zxz")
    return B.ang_vel_in(N).to_matrix(B)


def _simplify_omega():
    import sympy as sp

    from eulersym.rotation import euler_matrix
    from eulersym.symbols import phi, psi, t, theta

    A = euler_matrix(phi, theta, psi)
    return sp.simplify(-A.diff(t) * A.T)


def _mechanics_top():
    from sympy.physics.mechanics import LagrangesMethod, Lagrangian, Point, ReferenceFrame, RigidBody, inertia

    from eulersym.symbols import I1, I3, M, g, l, phi, psi, theta

    N, B = ReferenceFrame("N"), ReferenceFrame("B")
    B.orient_body_fixed(N, (phi, theta, psi), "zxz")
    pivot = Point("O")
    pivot.set_vel(N, 0)
    cm = pivot.locatenew("G", l * B.z)
    cm.v2pt_theory(pivot, N, B)
    top = RigidBody("top", cm, B, M, (inertia(B, I1, I1, I3), pivot))
    top.potential_energy = M * g * l * (B.z & N.z)
    L = Lagrangian(N, top)
    lm = LagrangesMethod(L, [phi, theta, psi])
    return lm.form_lagranges_equations()


def _rows(quick: bool, repeat: int) -> list[tuple[str, float, str, float | None]]:
    from eulersym import dynamics, inertia, kinematics, rotation, text, top
    from eulersym.symbols import M, phi, psi, theta

    a = text.a
    rows: list[tuple[str, float, str, float | None]] = []

    def add(name, fn, baseline_name="", baseline=None):
        ours = _best(fn, repeat)
        base = _best(baseline, max(1, repeat // 2), cold=False) if baseline is not None else None
        rows.append((name, ours, baseline_name, base))

    add("rotation.euler_matrix (zxz)", lambda: rotation.euler_matrix(phi, theta, psi))
    add("kinematics.omega_body (zxz)", kinematics.omega_body, "sympy.physics.mechanics ang_vel_in", _mechanics_omega)
    if not quick:
        rows.append(("kinematics.omega_body (zxz)", _best(kinematics.omega_body, repeat),
                     "sympy.simplify(-Adot A^T)", _best(_simplify_omega, 1, cold=False)))
    add("kinematics.omega_body, all 12 sequences",
        lambda: [kinematics.omega_body(c) for c in rotation.CONVENTIONS])
    add("inertia.cube (corner)", lambda: inertia.cube(M, a, origin="corner"))
    add("inertia.principal_axes (cube corner)", lambda: inertia.principal_axes(inertia.cube(M, a, origin="corner")))
    add("inertia.sphere, cylinder, cone, ellipsoid", lambda: (
        inertia.sphere(M, a), inertia.cylinder(M, a, 2 * a), inertia.cone(M, a, 2 * a),
        inertia.ellipsoid(M, a, 2 * a, 3 * a)))
    add("dynamics.euler_equations", dynamics.euler_equations)
    add("top.lagrangian", top.lagrangian)
    add("top.equations_of_motion", top.equations_of_motion, "mechanics LagrangesMethod (same top)", _mechanics_top)
    add("top.sleeping_top_threshold", top.sleeping_top_threshold)
    add("top.precession_limits", top.precession_limits)
    for section in text.SECTIONS:
        add(f"check {section} (in process, cold)", lambda s=section: text.check_all(s))
    return rows


def main(argv: list[str]) -> int:
    """Run the benchmark; print a table and the cold-check figure."""
    parser = argparse.ArgumentParser(prog="eulersym bench derive", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="skip the slow sympy.simplify baseline")
    parser.add_argument("--repeat", type=int, default=3, help="repetitions; the best is kept (default 3)")
    parser.add_argument("--csv", help="also write the rows to this CSV file")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        from eulersym.errors import InvalidInput

        raise InvalidInput("--repeat", args.repeat, "an integer >= 1")

    sympy_import = min(_fresh_process_seconds("import sympy") for _ in range(3))
    cold_check = min(_fresh_process_seconds("from eulersym.cli import main; main(['check'])") for _ in range(2))
    foundation = min(_fresh_process_seconds(
        "from eulersym import text\nfor s in ('4.1', '4.2', '4.3', 'Example 4.1'): text.check_all(s)") for _ in range(2))
    import sympy  # noqa: F401 — in this process too, so the rows below time eulersym beyond it
    rows = _rows(args.quick, args.repeat)

    width = max(len(r[0]) for r in rows)
    print(f"{'derivation':<{width}}  {'eulersym s':>10}  {'baseline s':>10}  {'ratio':>14}  baseline")
    for name, ours, base_name, base in rows:
        if base is None:
            print(f"{name:<{width}}  {ours:10.4f}")
        else:
            print(f"{name:<{width}}  {ours:10.4f}  {base:10.4f}  {ratio_text(base, ours):>14}  {base_name}")
    print(f"\ncold `eulersym check` (fresh process): {cold_check:.2f} s; `import sympy` alone: {sympy_import:.2f} s; "
          f"beyond SymPy's import: {cold_check - sympy_import:.2f} s")
    print(f"cold check of §4.1–4.3 and Example 4.1 (fresh process): {foundation:.2f} s; beyond SymPy's import: "
          f"{foundation - sympy_import:.2f} s")
    print("ratio = baseline seconds / eulersym seconds")
    if args.csv:
        with open(args.csv, "w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(["derivation", "eulersym_s", "baseline", "baseline_s", "ratio"])
            for name, ours, base_name, base in rows:
                writer.writerow([name, f"{ours:.6f}", base_name, "" if base is None else f"{base:.6f}",
                                 "" if base is None else f"{base / ours:.3f}"])
            writer.writerow(["cold eulersym check beyond sympy import", f"{cold_check - sympy_import:.6f}", "", "", ""])
            writer.writerow(["cold check 4.1-4.3 + Example 4.1 beyond sympy import",
                             f"{foundation - sympy_import:.6f}", "", "", ""])
    return 0
