"""Sweeps at scale: a 10⁶-member map in bounded memory, the plan's default against DOP853, refusals, Dask workers.

Four figures, each beside its floor (issue 12), measured in the same run:

1. **Map.** The sleeping top's stability map, ``--tilts`` × ``--spins`` members (default 1000 × 1000), T = 3, 31
   output times, ``want = ["summary"]``, ``memory = "1 GiB"`` (the budget that sizes the chunks), run by ``eulersym.scene.simulate`` in a fresh process whose peak resident
   memory (``VmHWM``) is read at its end. Floors: ≤ 60 s and ≤ 1.5 GB. Sampled members are run again as single
   scenes: their largest tilt and final ω agree with the map's summaries to the accuracy asked.
2. **Default against DOP853.** An asymmetric heavy top (no closed form), ``--members`` members (default 10⁵), by the
   plan's default and by ``method = "DOP853"``, median times of alternating runs; both errors on sampled members
   against a single solve_ivp DOP853 run at rtol 1e-12. Floors: the default ≥ 5× faster, its error ≤ the accuracy
   asked (DOP853's is printed beside it). Every member is also compared with the sweep run at accuracy 1e-10: the
   share beyond the accuracy asked, median, p99 and largest error of each engine (an asymmetric heavy top is
   sensitive: a few members' global errors are many times the tolerance, for both engines).
3. **Refusal.** ``eulersym simulate`` of a 10⁹-member sweep in a fresh process: exit 2 with the estimate. Floors:
   < 1 s and < 100 MB (the whole command, interpreter start included).
4. **Dask.** The asymmetric sweep of (2) on a local cluster of 1 and of 2 worker processes: results identical to
   the in-process run; floor: 2 workers ≥ 1.6× the throughput of one (this machine has 2 cores, shared: noisy).

``--quick`` runs small sizes (a smoke test; floors are reported, not enforced). Exit 1 if a floor is missed.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from eulersym.bench.report import load_text, ratio_text

__all__ = ["main", "bench_map", "bench_default_vs_dop853", "bench_refusal", "bench_dask"]

#: The bundled sleeping top (eulersym/scenes/sleeping-top-map.toml): the map's body.
SLEEPING_TOP = dict(moments=(1.2e-3, 1.2e-3, 4.0e-4), mass=0.5, l=0.04, g=9.81)
#: An asymmetric heavy top (three distinct moments about the pivot): no closed form.
ASYMMETRIC_TOP = dict(moments=(1.0e-3, 1.4e-3, 6.0e-4), mass=0.5, l=0.04, g=9.81)


def _peak_kib() -> int:
    """This process's peak resident memory (``VmHWM``, KiB), which unlike ``ru_maxrss`` starts afresh at exec."""
    with open("/proc/self/status") as handle:
        for line in handle:
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    return -1


def _in_fresh_process(code: str, timeout: float = 900.0) -> dict:
    """Run ``code`` (which prints one JSON line last) in a fresh interpreter; its dict."""
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout, env=env)
    lines = [line for line in proc.stdout.splitlines() if line.startswith("{")]
    if proc.returncode != 0 or not lines:
        raise RuntimeError(f"benchmark subprocess failed ({proc.returncode}): {proc.stderr[-2000:]}")
    return json.loads(lines[-1])


_MAP_CODE = """
import json, time
start = time.perf_counter()
import numpy as np
from eulersym.scene import Scene, simulate
scene = Scene(name="sleeping-top-map-bench", **{body!r}, t_end={t_end!r}, points={points!r}, accuracy={accuracy!r},
              outputs=("summary",), memory={memory!r}, omega=(0.0, 0.0, {{"start": 60.0, "stop": 95.0, "num": {spins}}}),
              euler=(0.0, {{"start": 0.005, "stop": 0.05, "num": {tilts}}}, 0.0))
r = simulate(scene)
seconds = time.perf_counter() - start
picks = {picks!r}
hwm = [int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmHWM:")][0]
import resource, os
use = resource.getrusage(resource.RUSAGE_SELF)
print(json.dumps(dict(seconds=seconds, cpu=use.ru_utime + use.ru_stime, load=os.getloadavg()[0],
    motion=r.timings.get("motion", 0.0), peak_kib=hwm, engine=r.plan.engine,
    members=r.plan.batch, tilt=[float(r.sweep["euler[1]"][b]) for b in picks],
    spin=[float(r.sweep["omega[2]"][b]) for b in picks], tilt_max=[float(r.summary["tilt_max"][b]) for b in picks],
    omega_final=[[float(r.summary[f"omega{{k}}.final"][b]) for k in (1, 2, 3)] for b in picks])))
"""


def bench_map(tilts: int = 1000, spins: int = 1000, *, t_end: float = 3.0, points: int = 31, accuracy: float = 1e-6,
              samples: int = 5, memory: str = "1 GiB") -> dict:
    """The sleeping-top map of ``tilts × spins`` members (summaries) in a fresh process: time, peak memory, and
    sampled members against single runs."""
    from eulersym.scene import Scene, simulate

    members = tilts * spins
    picks = sorted({int(b) for b in np.linspace(0, members - 1, samples)})
    code = _MAP_CODE.format(body=SLEEPING_TOP, t_end=t_end, points=points, accuracy=accuracy, tilts=tilts,
                            spins=spins, picks=picks, memory=memory)
    got = _in_fresh_process(code)
    worst_tilt = worst_omega = 0.0
    for k in range(len(picks)):
        single = simulate(Scene(**SLEEPING_TOP, t_end=t_end, points=points, accuracy=accuracy,
                                outputs=("omega",), omega=(0.0, 0.0, got["spin"][k]), euler=(0.0, got["tilt"][k], 0.0)))
        theta = np.arccos(np.clip(single.gamma[:, 2], -1.0, 1.0))
        worst_tilt = max(worst_tilt, abs(float(theta.max()) - got["tilt_max"][k]) / max(float(theta.max()), 1e-300))
        worst_omega = max(worst_omega, float(np.max(np.abs(single.omega[-1] - np.asarray(got["omega_final"][k])))) / got["spin"][k])
    return {
        "case": f"sleeping-top map: {tilts} tilts × {spins} spins = {members} members, T = {t_end:g}, {points} output "
                f"times, accuracy {accuracy:g}, want = [\"summary\"]",
        "engine": got["engine"],
        "seconds": got["seconds"],
        "cpu": got["cpu"],
        "load": got["load"],
        "peak_bytes": got["peak_kib"] * 1024,
        "tilt_error": worst_tilt,
        "omega_error": worst_omega,
        "accuracy": accuracy,
        "members": members,
    }


def _asymmetric_scene(members: int, *, method: str = "auto", t_end: float = 2.0, points: int = 11,
                      accuracy: float = 1e-6, outputs=("omega",)):
    from eulersym.scene import Scene

    n_tilt = max(1, int(round(np.sqrt(members / 4))))
    n_spin = max(1, members // n_tilt)
    return Scene(name="asymmetric-heavy-top-sweep", **ASYMMETRIC_TOP, t_end=t_end, points=points, accuracy=accuracy,
                 method=method, outputs=outputs, omega=(1.0, 0.0, {"start": 20.0, "stop": 40.0, "num": n_spin}),
                 euler=(0.0, {"start": 0.1, "stop": 0.6, "num": n_tilt}, 0.0))


def _reference(scene, b: int, result) -> np.ndarray:
    """Member ``b`` by a single solve_ivp DOP853 run at rtol 1e-12 (ω at the output times)."""
    from eulersym.scene import Scene, simulate

    import dataclasses

    kwargs = {f.name: getattr(scene, f.name) for f in dataclasses.fields(scene) if f.init}
    kwargs.update(omega=(1.0, 0.0, float(result.sweep["omega[2]"][b])),
                  euler=(0.0, float(result.sweep["euler[1]"][b]), 0.0), method="DOP853", accuracy=1e-13)
    for key in ("dimensions",):
        if kwargs.get(key) is not None:
            kwargs[key] = dict(kwargs[key])
    return simulate(Scene(**kwargs)).omega


#: The whole sweep's reference: the plan's default at this accuracy (rtol 2e-13).
_WHOLE_SWEEP_ACCURACY = 1e-10


def bench_default_vs_dop853(members: int = 100_000, *, samples: int = 4, accuracy: float = 1e-6,
                            repeats: int = 3) -> dict:
    """An asymmetric heavy-top sweep by the plan's default and by DOP853: median times of ``repeats`` alternating
    runs (this machine is shared: one run of either can be slowed by a neighbour) and errors on sampled members."""
    from eulersym.scene import simulate

    fast_scene = _asymmetric_scene(members, accuracy=accuracy)
    slow_scene = _asymmetric_scene(members, method="DOP853", accuracy=accuracy)
    simulate(_asymmetric_scene(64, accuracy=accuracy))  # warm-up: imports, compiled kernels
    simulate(_asymmetric_scene(64, method="DOP853", accuracy=accuracy))
    fast_times, slow_times, fast_cpu, slow_cpu = [], [], [], []
    for _ in range(max(1, repeats)):
        start, cpu = time.perf_counter(), time.process_time()
        fast = simulate(fast_scene)
        fast_times.append(time.perf_counter() - start)
        fast_cpu.append(time.process_time() - cpu)
        start, cpu = time.perf_counter(), time.process_time()
        slow = simulate(slow_scene)
        slow_times.append(time.perf_counter() - start)
        slow_cpu.append(time.process_time() - cpu)
    t_fast, t_slow = float(np.median(fast_times)), float(np.median(slow_times))
    picks = sorted({int(b) for b in np.linspace(0, fast_scene.batch - 1, samples)})
    # every member: the same sweep by the plan's default at accuracy 1e-10 (checked on the samples against scipy)
    whole = simulate(_asymmetric_scene(members, accuracy=_WHOLE_SWEEP_ACCURACY)).omega
    whole_scale = np.max(np.abs(whole), axis=(1, 2))
    err_fast = err_slow = err_whole = 0.0
    for b in picks:
        ref = _reference(fast_scene, b, fast)
        scale = float(np.max(np.abs(ref)))
        err_fast = max(err_fast, float(np.max(np.abs(fast.omega[b] - ref))) / scale)
        err_slow = max(err_slow, float(np.max(np.abs(slow.omega[b] - ref))) / scale)
        err_whole = max(err_whole, float(np.max(np.abs(whole[b] - ref))) / scale)

    def spread(omega):
        e = np.max(np.abs(omega - whole), axis=(1, 2)) / whole_scale
        return {"beyond": float(np.mean(e > accuracy)), "p99": float(np.quantile(e, 0.99)), "max": float(e.max()),
                "median": float(np.median(e))}
    return {
        "case": f"asymmetric heavy top, {fast_scene.batch} members, T = {fast_scene.t_end:g}, accuracy {accuracy:g}",
        "members": fast_scene.batch,
        "engine": fast.plan.engine,
        "baseline_engine": slow.plan.engine,
        "seconds": t_fast,
        "baseline_seconds": t_slow,
        "ratio": t_slow / t_fast,
        "error": err_fast,
        "baseline_error": err_slow,
        "accuracy": accuracy,
        "calls": int(fast.n_rhs_calls),
        "cpu": float(np.median(fast_cpu)),
        "baseline_cpu": float(np.median(slow_cpu)),
        "repeats": len(fast_times),
        "samples": len(picks),
        "whole": {"default": spread(fast.omega), "DOP853": spread(slow.omega), "reference_error": err_whole},
    }


_REFUSAL_TOML = """name = "too-big"
[body]
moments = [1.0e-3, 1.4e-3, 6.0e-4]
mass = 0.5
[pivot]
l = 0.04
[initial]
omega = [{{start = 0.0, stop = 1.0, num = 1000}}, {{start = 0.0, stop = 1.0, num = 1000}}, {{start = 20.0, stop = 40.0, num = 1000}}]
[time]
end = {t_end}
points = 1001
"""

_REFUSAL_CODE = """
import json, sys, time, io, contextlib
start = time.perf_counter()
from eulersym.cli import main
err = io.StringIO()
with contextlib.redirect_stderr(err):
    rc = main(["simulate", {path!r}])
seconds = time.perf_counter() - start
hwm = [int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmHWM:")][0]
import resource
use = resource.getrusage(resource.RUSAGE_SELF)
print(json.dumps(dict(rc=rc, seconds=seconds, cpu=use.ru_utime + use.ru_stime, peak_kib=hwm,
                      message=err.getvalue().strip())))
"""


def bench_refusal(t_end: float = 3.0) -> dict:
    """``eulersym simulate`` of a 10⁹-member sweep in a fresh process: exit status, time, peak memory, message."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "too-big.toml")
        with open(path, "w") as handle:
            handle.write(_REFUSAL_TOML.format(t_end=t_end))
        wall = time.perf_counter()
        got = _in_fresh_process(_REFUSAL_CODE.format(path=path))
        wall = time.perf_counter() - wall
    got.update(wall=wall, case="a 1000 × 1000 × 1000 sweep (10⁹ members, 1001 points)")
    return got


def bench_dask(members: int = 100_000, *, accuracy: float = 1e-6) -> dict:
    """The asymmetric sweep in-process, on 1 and on 2 local worker processes: identical results, throughputs."""
    from eulersym.scene import simulate
    from eulersym.sweeps import distributed

    scene = _asymmetric_scene(members, accuracy=accuracy, outputs=("summary",))
    small = _asymmetric_scene(256, accuracy=accuracy, outputs=("summary",))
    local = simulate(scene)
    times = {}
    for n in (1, 2):
        client = distributed.local_client(n)
        try:
            simulate(small, client=client)  # warm-up: worker imports, compiled kernels
            start = time.perf_counter()
            got = simulate(scene, client=client)
            times[n] = time.perf_counter() - start
        finally:
            distributed.close(client)
        differ = {k: int(np.count_nonzero(np.asarray(local.summary[k]) != np.asarray(got.summary[k])))
                  for k in local.summary if not np.array_equal(local.summary[k], got.summary[k])}
        same = not differ
        if not same:
            differ["workers"] = n
            break
    return {
        "case": f"Dask LocalCluster, {scene.batch} members (asymmetric heavy top, summaries)",
        "one_worker_seconds": times.get(1, float("nan")),
        "two_worker_seconds": times.get(2, float("nan")),
        "ratio": times.get(1, float("nan")) / times.get(2, float("nan")),
        "identical": bool(same),
        "differ": differ,  # summary → how many entries differ from the in-process run (empty when identical)
        "engine": local.plan.engine,
    }


def main(argv) -> int:
    """Run the four benchmarks; print each figure beside its floor. Exit 1 if a floor is missed."""
    p = argparse.ArgumentParser(prog="eulersym bench sweeps", description=__doc__.splitlines()[0])
    p.add_argument("--tilts", type=int, default=1000, help="map: tilts (default 1000)")
    p.add_argument("--spins", type=int, default=1000, help="map: spins (default 1000)")
    p.add_argument("--members", type=int, default=100_000, help="asymmetric sweep and Dask: members (default 10⁵)")
    p.add_argument("--only", choices=("map", "dop853", "refusal", "dask"), action="append",
                   help="run only these (repeatable)")
    p.add_argument("--repeats", type=int, default=None,
                   help="default against DOP853: alternating runs, medians reported (default 3; 5 with --quick)")
    p.add_argument("--quick", action="store_true", help="small sizes (a smoke test; floors reported, not enforced)")
    args = p.parse_args(list(argv))
    if args.quick:
        args.tilts, args.spins, args.members = 50, 40, 4000
    only = set(args.only or ("map", "dop853", "refusal", "dask"))
    ok = True

    def verdict(passed: bool) -> str:
        nonlocal ok
        ok &= passed or args.quick
        return "met" if passed else "MISSED"

    print("eulersym bench sweeps" + (" --quick" if args.quick else "") + f" ({load_text()}; wall times are noisy under load)")
    if "map" in only:
        r = bench_map(args.tilts, args.spins)
        gb = r["peak_bytes"] / 1e9
        print(f"{r['case']}\n  engine: {r['engine']}\n  {r['seconds']:.1f} s (floor ≤ 60 s: {verdict(r['seconds'] <= 60)}; "
              f"{r['cpu']:.1f} CPU-s, load average {r['load']:.1f} on 2 cores), "
              f"peak {gb:.2f} GB (floor ≤ 1.5 GB: {verdict(gb <= 1.5)})\n"
              f"  sampled members against single runs: largest tilt {r['tilt_error']:.1e}, final ω {r['omega_error']:.1e} "
              f"(relative; accuracy {r['accuracy']:g}: {verdict(max(r['tilt_error'], r['omega_error']) <= 10 * r['accuracy'])})")
    if "dop853" in only:
        r = bench_default_vs_dop853(args.members, repeats=args.repeats or (5 if args.quick else 3))
        print(f"{r['case']}\n  default: {r['engine']}  {r['seconds']:.2f} s   DOP853: {r['baseline_engine']}  "
              f"{r['baseline_seconds']:.2f} s   (medians of {r['repeats']} alternating runs)   "
              f"{ratio_text(r['baseline_seconds'], r['seconds'])} (floor ≥ 5×: {verdict(r['ratio'] >= 5)})\n"
              f"  CPU time (all threads): default {r['cpu']:.2f} s, DOP853 {r['baseline_cpu']:.2f} s (the default's 2 "
              f"threads need both cores: under load its wall time suffers first); kernel calls per member: default "
              f"{r['calls'] / max(r['members'], 1):.0f} ({1e9 * r['cpu'] / max(r['calls'], 1):.0f} CPU-ns each, "
              f"simulate's overhead included)\n"
              f"  max relative ω error of {r['samples']} sampled members against rtol 1e-12: default {r['error']:.1e} "
              f"(≤ accuracy {r['accuracy']:g}: {verdict(r['error'] <= r['accuracy'])}), DOP853 {r['baseline_error']:.1e}")
        w = r["whole"]
        line = lambda d: (f"{100 * d['beyond']:.1f} % beyond {r['accuracy']:g}, median {d['median']:.1e}, "  # noqa: E731
                          f"p99 {d['p99']:.1e}, max {d['max']:.1e}")
        same = all(w["default"][k] <= w["DOP853"][k] for k in ("beyond", "median", "p99"))
        print(f"  every member against the sweep at accuracy {_WHOLE_SWEEP_ACCURACY:g} (itself within "
              f"{w['reference_error']:.1e} of the samples' rtol 1e-12 runs):\n    default {line(w['default'])}\n"
              f"    DOP853  {line(w['DOP853'])}\n  the default at least as accurate as DOP853 over the whole sweep "
              f"(share beyond, median, p99): {verdict(same)}\n  ({load_text()} at the end)")
    if "refusal" in only:
        r = bench_refusal()
        print(f"refusal: {r['case']}\n  exit {r['rc']} in {r['seconds']:.2f} s, {r['cpu']:.2f} CPU-s, imports included "
              f"(whole command {r['wall']:.2f} s; floor < 1 s: {verdict(r['rc'] == 2 and r['seconds'] < 1)}), peak {r['peak_kib'] / 1024:.0f} MiB (floor < 100 MB: "
              f"{verdict(r['peak_kib'] * 1024 < 100e6)})\n  {r['message'][:400]}")
    if "dask" in only:
        r = bench_dask(args.members)
        print(f"{r['case']}\n  engine: {r['engine']}\n  1 worker {r['one_worker_seconds']:.2f} s, 2 workers "
              f"{r['two_worker_seconds']:.2f} s: throughput {r['ratio']:.2f}× one worker's "
              f"(floor ≥ 1.6×: {verdict(r['ratio'] >= 1.6)}); identical to in-process: {verdict(r['identical'])}"
              + ("" if r["identical"] else f" (entries that differ, by summary: {r['differ']})"))
    return 0 if ok else 1
