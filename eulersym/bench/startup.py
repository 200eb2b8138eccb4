"""Start-up a user feels: the flagship scene vs a plain SciPy script, kernel import, numba's first call, check, verify.

Whole processes (``sys.executable``), one warm-up each, then ``--runs`` rounds with the commands of a comparison
alternated (A B A B …) so that a drift of the machine's speed hits both; medians are quoted, with the CPU seconds
of the child processes beside the wall seconds (CPU time is what a loaded machine distorts least). Floors (issue 13):

- ``eulersym simulate tennis-racket`` ≥ 3× faster than the plain SciPy script of the same scene (the bundled TOML's
  body, start, times and accuracy; DOP853 through ``solve_ivp``; the same drift and flip count printed), and
  ≤ 1.3× the time of ``python -c "import numpy"`` (issue 23); ``eulersym simulate heavy-top-nutation`` (the Lagrange
  top in closed form, 2001 times, Euler angles and invariants) ≤ 1.5× it — closed-form scenes import neither
  ``scipy.special`` nor ``scipy.integrate`` (checked in the same run);
- importing a generated kernel ≤ 30 ms beyond NumPy's import (timed inside fresh processes);
- numba: the first call of a compiled eulersym loop in a fresh process ≤ 0.3 s once the on-disk cache is warm
  (numba already imported; its own runtime start-up, which imports ``scipy.linalg``, is part of that first call
  and is also shown apart);
- ``eulersym check`` cold ≤ 1.5 s beyond SymPy's import (``python -c "import sympy"``, alternated);
- ``eulersym verify`` of one hand derivation ≤ 0.5 s beyond SymPy's import;
- in process, the exact free-body oracle ``free_rigid_body_exact`` at two output times, warm, a new body each
  call ≤ 200 µs per call (baseline: ``solve_ivp`` DOP853 to the same two times at rtol 1e-10), and its cost per
  output point flat from 10⁴ to 10⁶ points (exponent of time against points ≤ 1.05).

Run ``eulersym bench startup`` (``--runs N``; ``--quick``: 3 rounds; ``--only scenes|kernel|numba|check|oracle``,
repeatable: those parts alone — ``scenes`` needs neither SymPy nor numba, so it also runs in an environment that
holds eulersym's wheel and NumPy and SciPy only).
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

from eulersym.bench.report import floor_line, load_text, ratio_text

__all__ = ["main", "scipy_script"]

PY = sys.executable
#: Child processes run with Python's bytecode cache on, as after a normal install (an environment may turn it off
#: with PYTHONDONTWRITEBYTECODE, and every start would then compile eulersym's sources again).
_ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def scipy_script(scene: str = "tennis-racket") -> str:
    """The plain SciPy script a user would write for a bundled torque-free scene: same body, start, output times,
    accuracy; prints the invariants' drift and the flips of the intermediate axis, like ``eulersym simulate``.

    Examples
    --------
    >>> "DOP853" in scipy_script()
    True
    """
    import tomllib
    from importlib import resources

    with resources.files("eulersym.scenes").joinpath(f"{scene}.toml").open("rb") as fh:
        spec = tomllib.load(fh)
    moments = [float(x) for x in spec["body"]["moments"]]
    omega = [float(x) for x in spec["initial"]["omega"]]
    end, points = float(spec["time"]["end"]), int(spec["time"]["points"])
    rtol = float(spec.get("output", {}).get("accuracy", 1e-10))
    return f"""\
import numpy as np
from scipy.integrate import solve_ivp

I = np.array({moments!r})
w0 = np.array({omega!r})
t = np.linspace(0.0, {end!r}, {points})


def rhs(_, w):
    return [(I[1] - I[2]) / I[0] * w[1] * w[2], (I[2] - I[0]) / I[1] * w[2] * w[0], (I[0] - I[1]) / I[2] * w[0] * w[1]]


sol = solve_ivp(rhs, (0.0, {end!r}), w0, method="DOP853", t_eval=t, rtol={rtol!r}, atol={rtol!r} * 1e-2)
W = sol.y.T
E, L2 = W**2 @ I, W**2 @ I**2
print(f"invariants drift (max relative): energy {{np.max(np.abs(E - E[0])) / E[0]:.2e}}, "
      f"L2 {{np.max(np.abs(L2 - L2[0])) / L2[0]:.2e}}")
axis = int(np.argsort(I)[1])
print(f"omega along the intermediate axis changes sign {{np.count_nonzero(np.diff(np.sign(W[:, axis])))}} times")
"""


def _run(argv, env=None) -> tuple[float, float, str]:
    """(wall s, child CPU s, stdout) of one whole process; a failing command raises with its stderr."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(argv, capture_output=True, text=True, env=_ENV if env is None else env)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(argv[:4])} ... exited {proc.returncode}: {proc.stderr.strip()[-400:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, proc.stdout


def _alternated(commands: dict, runs: int) -> dict:
    """{name: (median wall, median CPU, last stdout)}: one warm-up each, then ``runs`` rounds alternated."""
    samples = {name: [] for name in commands}
    outputs = {}
    for name, argv in commands.items():
        outputs[name] = _run(argv)[2]
    for _ in range(runs):
        for name, argv in commands.items():
            wall, cpu, outputs[name] = _run(argv)
            samples[name].append((wall, cpu))
    return {name: (statistics.median(w for w, _ in s), statistics.median(c for _, c in s), outputs[name])
            for name, s in samples.items()}


def _inner(code: str, runs: int, env=None) -> list[float]:
    """Median of each figure a fresh process prints (space-separated floats), over ``runs`` processes."""
    rows = []
    _run([PY, "-c", code], env=env)  # warm-up (and on-disk caches)
    for _ in range(runs):
        rows.append([float(x) for x in _run([PY, "-c", code], env=env)[2].split()])
    return [statistics.median(col) for col in zip(*rows)]


#: The modules a closed-form scene must not import (a child prints those it did).
_HEAVY_IMPORTS = """\
import sys
from eulersym.scene import load, simulate
for name in ("heavy-top-nutation", "tennis-racket", "sleeping-top-map"):
    simulate(load(name))
print(" ".join(m for m in ("scipy.special", "scipy.integrate", "sympy") if m in sys.modules))
"""

#: The parts ``--only`` may name, in the order they run.
_PARTS = ("scenes", "kernel", "numba", "check", "oracle")

_KERNEL_IMPORT = ("import time; t0 = time.perf_counter(); import numpy; t1 = time.perf_counter(); "
                  "import eulersym.generated.heavy_top_euler_poisson; t2 = time.perf_counter(); print(t1 - t0, t2 - t1)")

_NUMBA_FIRST_CALL = """\
import time
import numpy as np
import numba
import eulersym.generated.euler_principal as kernel
from eulersym.numerics import _fast
{warm}
t0, c0 = time.perf_counter(), time.process_time()
rhs = _fast.batched(kernel, "rhs")
rhs(0.0, np.ones((3, 4)), 1.0, 2.0, 3.0, 0.0, 0.0, 0.0)
print(time.perf_counter() - t0, time.process_time() - c0)
"""

_NUMBA_TRIVIAL = """\
import numba


@numba.njit(cache=True)
def one(x):
    return x + 1.0
"""


def _oracle(runs: int):
    """(median s per call at 2 times with a new body, same for solve_ivp, the cost exponent, {k: s per point}).

    CPU seconds of this process (``time.process_time``): on a loaded machine a run longer than a scheduler slice is
    descheduled, which would inflate long runs' wall time per point and fake a growing cost.
    """
    import numpy as np
    from scipy.integrate import solve_ivp

    from eulersym.numerics.exact import free_rigid_body_exact

    rng = np.random.default_rng(13)
    bodies = [(tuple(np.sort(rng.uniform(1.0, 2.0, 3))), rng.normal(size=3)) for _ in range(200)]
    times = np.array([0.0, 5.0])
    free_rigid_body_exact(*bodies[0], times)
    per_call = []
    for _ in range(max(runs, 3)):
        start = time.process_time()
        for I, w in bodies:
            free_rigid_body_exact(I, w, times)
        per_call.append((time.process_time() - start) / len(bodies))

    def euler(I):
        a, b, c = (I[1] - I[2]) / I[0], (I[2] - I[0]) / I[1], (I[0] - I[1]) / I[2]
        return lambda _, w: [a * w[1] * w[2], b * w[2] * w[0], c * w[0] * w[1]]

    baseline = []
    for _ in range(max(runs, 3)):
        start = time.process_time()
        for I, w in bodies[:20]:
            solve_ivp(euler(I), (0.0, 5.0), w, method="DOP853", t_eval=times, rtol=1e-10, atol=1e-12)
        baseline.append((time.process_time() - start) / 20)
    per_point = {}
    I, w = (1.0, 2.0, 3.0), np.array([1e-3, 1.0, 1e-3])
    for k in (4, 5, 6):
        t = np.linspace(0.0, 1e4, 10**k)
        free_rigid_body_exact(I, w, t)
        samples = []
        for _ in range(max(runs, 3)):
            start = time.process_time()
            free_rigid_body_exact(I, w, t)
            samples.append(time.process_time() - start)
        per_point[k] = statistics.median(samples) / 10**k
    exponent = 1.0 + float(np.log10(per_point[6] / per_point[4])) / 2.0
    return statistics.median(per_call), statistics.median(baseline), exponent, per_point


def main(argv: list[str] | None = None) -> int:
    """Run the start-up benchmarks; print each figure with its floor; 0 when every floor is met (1 otherwise).

    Examples
    --------
    >>> main(["--help"])  # doctest: +ELLIPSIS
    usage: eulersym bench startup ...
    0
    """
    parser = argparse.ArgumentParser(prog="eulersym bench startup", description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7, help="alternated rounds, medians quoted (default 7)")
    parser.add_argument("--quick", action="store_true", help="3 rounds (a smoke run)")
    parser.add_argument("--only", choices=_PARTS, action="append", help="run only these parts (repeatable)")
    try:
        args = parser.parse_args(argv or [])
    except SystemExit as exc:
        return int(exc.code or 0)
    runs = 3 if args.quick else max(1, args.runs)
    only = set(args.only or _PARTS)
    floors = []

    def floor(name, measured, limit, met):
        floors.append(met)
        print("  " + floor_line(name, measured, limit, met), flush=True)

    print(f"eulersym bench startup — Python {sys.version.split()[0]}, {runs} alternated rounds, medians; "
          f"{load_text()}")
    if "PYTHONDONTWRITEBYTECODE" in os.environ:
        print("note: PYTHONDONTWRITEBYTECODE is set here; the timed processes run with the bytecode cache on")
    print(f"eulersym is {_installed()}")
    print()

    if "scenes" in only:
        _scenes(runs, floor)
    if "kernel" in only:
        _kernel(runs, floor)
    if "numba" in only:
        _numba(runs, floor)
    if "check" in only:
        _check(runs, floor)
    if "oracle" in only:
        _oracle_floors(runs, floor)

    missed = floors.count(False)
    print(f"\n{'all floors met' if not missed else f'{missed} floor(s) missed'} ({load_text()})")
    return 0 if not missed else 1


def _installed() -> str:
    """How eulersym is installed here: an editable install adds a finder to every start (its .pth file imports
    pathlib, re and urllib, and each eulersym import asks it first); a wheel does not.

    Examples
    --------
    >>> _installed().split()[0] in ("editable", "installed", "run")
    True
    """
    import eulersym

    if any("__editable__" in getattr(finder, "__module__", "") for finder in sys.meta_path):
        return "editable (pip install -e): every process here, `import numpy` too, pays its finder at start-up"
    if "site-packages" in os.path.dirname(eulersym.__file__):
        return f"installed (a wheel) in {os.path.dirname(os.path.dirname(eulersym.__file__))}"
    return f"run from a source tree, {os.path.dirname(os.path.dirname(eulersym.__file__))}"


def _scenes(runs: int, floor) -> None:
    """The flagship scene, the plain SciPy script, NumPy's import; closed-form scenes without heavy imports."""
    with tempfile.TemporaryDirectory() as folder:
        script = os.path.join(folder, "tennis_racket_scipy.py")
        with open(script, "w") as fh:
            fh.write(scipy_script())
        res = _alternated({"eulersym simulate tennis-racket": [PY, "-m", "eulersym", "simulate", "tennis-racket"],
                           "eulersym simulate heavy-top-nutation": [PY, "-m", "eulersym", "simulate",
                                                                    "heavy-top-nutation"],
                           "plain SciPy script (DOP853)": [PY, script],
                           'python -c "import numpy"': [PY, "-c", "import numpy"]}, runs)
    for name, (wall, cpu, _) in res.items():
        print(f"{name:<40} {wall:7.3f} s wall  {cpu:7.3f} s CPU")
    ours = res["eulersym simulate tennis-racket"]
    base = res["plain SciPy script (DOP853)"]
    numpy_t = res['python -c "import numpy"']
    floor("simulate tennis-racket vs the SciPy script", ratio_text(base[0], ours[0]), "≥ 3× faster",
          base[0] / ours[0] >= 3)
    floor("simulate tennis-racket over `import numpy`", f"{ours[0] / numpy_t[0]:.2f}× (CPU {ours[1] / numpy_t[1]:.2f}×)",
          "≤ 1.3×", ours[0] / numpy_t[0] <= 1.3)
    top = res["eulersym simulate heavy-top-nutation"]
    floor("simulate heavy-top-nutation over `import numpy`", f"{top[0] / numpy_t[0]:.2f}× (CPU {top[1] / numpy_t[1]:.2f}×)",
          "≤ 1.5×", top[0] / numpy_t[0] <= 1.5)
    heavy = _run([PY, "-c", _HEAVY_IMPORTS])[2].split()
    floor("closed-form scenes without heavy imports", ", ".join(heavy) or "none of scipy.special, scipy.integrate",
          "none", not heavy)


def _kernel(runs: int, floor) -> None:
    """A generated kernel's import beyond NumPy's, inside fresh processes."""
    numpy_in, kernel_in = _inner(_KERNEL_IMPORT, runs)
    print(f"\nimport numpy (inside a fresh process)    {numpy_in * 1e3:7.1f} ms")
    floor("import a generated kernel beyond NumPy", f"{kernel_in * 1e3:.1f} ms", "≤ 30 ms", kernel_in <= 0.030)



def _numba(runs: int, floor) -> None:
    """numba's first call in a fresh process with a warm on-disk cache."""
    from eulersym.numerics import _fast

    print()
    if _fast.available():
        with tempfile.TemporaryDirectory() as folder:
            with open(os.path.join(folder, "eulersym_bench_trivial.py"), "w") as fh:
                fh.write(_NUMBA_TRIVIAL)
            env = dict(_ENV, PYTHONPATH=os.pathsep.join([folder, os.environ.get("PYTHONPATH", "")]))
            first, first_cpu = _inner(_NUMBA_FIRST_CALL.format(warm=""), runs, env=env)
            warm = "from eulersym_bench_trivial import one\none(1.0)  # numba's own runtime start-up"
            ours_only, ours_cpu = _inner(_NUMBA_FIRST_CALL.format(warm=warm), runs, env=env)
        print(f"numba first call: numba's runtime start-up  {max(first - ours_only, 0.0) * 1e3:7.1f} ms  "
              f"(CPU {max(first_cpu - ours_cpu, 0.0) * 1e3:.0f} ms; imports scipy.linalg; paid by any numba program)")
        print(f"numba first call: eulersym's cached loop    {ours_only * 1e3:7.1f} ms  (CPU {ours_cpu * 1e3:.0f} ms; "
              "loaded from the disk cache)")
        floor("numba first call in a fresh process, warm cache", f"{first:.3f} s (CPU {first_cpu:.3f} s)", "≤ 0.3 s",
              first <= 0.3)
    else:
        print("numba is not installed (the fast extra): its first call is not measured")


def _check(runs: int, floor) -> None:
    """``eulersym check`` and ``eulersym verify`` beyond SymPy's import."""
    verify = [PY, "-m", "eulersym", "verify", "(I1 - I3)/I1*omega3", "--against", "symmetric_precession_rate"]
    res = _alternated({"eulersym check": [PY, "-m", "eulersym", "check"],
                       "eulersym verify (one hand derivation)": verify,
                       'python -c "import sympy"': [PY, "-c", "import sympy"]}, runs)
    print()
    for name, (wall, cpu, _) in res.items():
        print(f"{name:<40} {wall:7.3f} s wall  {cpu:7.3f} s CPU")
    sympy_t = res['python -c "import sympy"']
    check = res["eulersym check"][0] - sympy_t[0]
    floor("eulersym check beyond SymPy's import", f"{check:.2f} s (CPU {res['eulersym check'][1] - sympy_t[1]:.2f} s)",
          "≤ 1.5 s", check <= 1.5)
    ver = res["eulersym verify (one hand derivation)"]
    floor("eulersym verify beyond SymPy's import", f"{ver[0] - sympy_t[0]:.2f} s (CPU {ver[1] - sympy_t[1]:.2f} s)",
          "≤ 0.5 s", ver[0] - sympy_t[0] <= 0.5)



def _oracle_floors(runs: int, floor) -> None:
    """The exact free-body oracle, in process."""
    print()
    per_call, baseline, exponent, per_point = _oracle(runs)
    print(f"free_rigid_body_exact, 2 times, new body    {per_call * 1e6:7.1f} µs CPU per call (median)")
    print(f"solve_ivp DOP853 to the same 2 times        {baseline * 1e6:7.1f} µs CPU per call (median)  "
          f"→ {ratio_text(baseline, per_call)}")
    floor("free_rigid_body_exact per call (2 times, new body)", f"{per_call * 1e6:.0f} µs", "≤ 200 µs",
          per_call <= 200e-6)
    print("  per output point: " + ", ".join(f"10^{k}: {v * 1e9:.0f} ns" for k, v in per_point.items()))
    floor("free_rigid_body_exact cost exponent, 10⁴ → 10⁶ points", f"{exponent:.3f}", "≤ 1.05", exponent <= 1.05)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main(sys.argv[1:]))
