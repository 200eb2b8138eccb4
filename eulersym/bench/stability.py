"""Steady motions and stability: the lagrange-top's families and proven conditions cold, Kovalevskaya's rotations
classified, and a stability map from the proven conditions against eigenvalues at every point (NumPy).

Three floors (issue 20), each measured here in the same run as its reference:

1. ``lagrange-top``: its steady motions and their proven conditions, in a fresh process, **≤ 3 s beyond SymPy's
   import** (the process's own ``import sympy`` is timed in the same process and subtracted);
2. ``kovalevskaya``: its permanent rotations, members at five rates and each member classified, in a fresh process,
   **≤ 5 s** beyond SymPy's import;
3. a **400 × 400** stability map of the sleeping top over (spin, l) from the proven conditions, **≥ 50× faster** than
   the eigenvalues of the linearisation at every point with ``numpy.linalg.eigvals`` (both compiled first; medians of
   three), and **agreeing at every point off the boundary**.

Examples
--------
>>> main(["--help"])  # doctest: +ELLIPSIS
usage: eulersym bench stability ...
0
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time

__all__ = ["main"]

_COLD = r"""
import json, time
t0 = time.perf_counter()
import sympy
t1 = time.perf_counter()
from eulersym.model.cli import load
from eulersym.model.steady import steady_motions
{body}
t2 = time.perf_counter()
print(json.dumps({{"sympy": t1 - t0, "work": t2 - t1, "detail": detail}}))
"""

_LAGRANGE = """
families = steady_motions(load("lagrange-top"))
detail = [[f.name, str(f.stability().conditions)[:60]] for f in families]
"""

_KOVALEVSKAYA = """
families = steady_motions(load("kovalevskaya"))
detail = []
for f in families:
    st = f.stability()
    for s in (0.5, 1.0, 2.0, 4.0, 8.0):
        if f.members({"s": s}):
            detail.append([f.name, s, st.classify({"s": s})])
"""


def _cold(body: str) -> dict:
    code = _COLD.format(body=body)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr.strip().splitlines()[-1] if proc.stderr else "failed")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _map(n: int, repeat: int):
    import numpy as np

    from eulersym.model.cli import load
    from eulersym.model.stability_map import (
        StabilityMap, agreement, compile_condition_map, compile_jacobian, eigenvalue_classes,
    )
    from eulersym.model.steady import steady_motions

    fam = steady_motions(load("lagrange-top")).named("rotation about e3, e3 up")
    st = fam.stability()
    X, Y = np.meshgrid(np.linspace(0.0, 200.0, n), np.linspace(-0.02, 0.05, n))
    proven = compile_condition_map(st, "s", "l")
    jacobian = compile_jacobian(st, "s", "l")
    proven(X[:2, :2], Y[:2, :2])
    eigenvalue_classes(st, jacobian(X[:2, :2], Y[:2, :2]))
    ours, theirs = [], []
    for _ in range(repeat):
        start = time.perf_counter()
        classes, margin = proven(X, Y)
        ours.append(time.perf_counter() - start)
        start = time.perf_counter()
        numeric = eigenvalue_classes(st, jacobian(X, Y))
        theirs.append(time.perf_counter() - start)
    pm = StabilityMap(("s", X[0]), ("l", Y[:, 0]), classes, margin)
    nm = StabilityMap(("s", X[0]), ("l", Y[:, 0]), numeric, None)
    return statistics.median(ours), statistics.median(theirs), agreement(pm, nm)


def main(argv) -> int:
    """``eulersym bench stability [--quick] [--size N] [--repeat R]``: the three floors of the module docstring."""
    from eulersym.bench.report import floor_line, load_text, ratio_text

    parser = argparse.ArgumentParser(prog="eulersym bench stability", description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=400, help="map points per side (default 400)")
    parser.add_argument("--repeat", type=int, default=3, help="timed repetitions of the map (median)")
    parser.add_argument("--quick", action="store_true", help="a 100 × 100 map, one repetition")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    if args.quick:
        args.size, args.repeat = 100, 1
    print(f"eulersym bench stability ({load_text()})")
    ok = True
    lagrange = _cold(_LAGRANGE)
    line = floor_line("lagrange-top: steady motions + proven conditions, cold, beyond SymPy's import",
                      f"{lagrange['work']:.2f} s (SymPy's import {lagrange['sympy']:.2f} s)", "≤ 3 s",
                      lagrange["work"] <= 3.0)
    print(line)
    print(f"  {len(lagrange['detail'])} families: " + "; ".join(name for name, _ in lagrange["detail"]))
    ok &= lagrange["work"] <= 3.0
    kova = _cold(_KOVALEVSKAYA)
    print(floor_line("kovalevskaya: permanent rotations, members at 5 rates, each classified, cold",
                     f"{kova['work']:.2f} s", "≤ 5 s", kova["work"] <= 5.0))
    print(f"  {len(kova['detail'])} members classified: "
          + ", ".join(f"{c} (s = {s:g})" for _, s, c in kova["detail"][:6]) + (" …" if len(kova["detail"]) > 6 else ""))
    ok &= kova["work"] <= 5.0
    ours, theirs, (agree, compared, boundary) = _map(args.size, max(1, args.repeat))
    ratio = theirs / ours if ours > 0 else float("inf")
    print(f"sleeping-top map {args.size} × {args.size} over (s, l): proven conditions {ours * 1e3:.2f} ms, "
          f"eigenvalues at every point {theirs * 1e3:.0f} ms — {ratio_text(theirs, ours)}")
    print(floor_line("map from the proven conditions vs NumPy eigenvalues", f"{ratio:.0f}×", "≥ 50×", ratio >= 50))
    print(floor_line("agreement off the boundary", f"{agree} of {compared} ({boundary} boundary points skipped)",
                     "all", agree == compared))
    ok &= ratio >= 50 and agree == compared
    return 0 if ok else 1
