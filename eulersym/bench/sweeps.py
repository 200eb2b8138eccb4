"""Sweeps at scale: closed forms against their NumPy floor, a 10⁶-member map in bounded memory, 10⁷ members to Zarr,
the compiled sweep against its lower bound, the plan's default against DOP853, refusals, Dask workers.

Each figure beside its floor (issues 12, 23), measured in the same run:

0. **Closed forms against their floor.** A free-body sweep (I = (1, 2, 3)) and the sleeping-top map's Lagrange
   tops, ``--members`` members (default 10⁵), 31 output times, ω out: ``simulate``'s CPU time per member against a
   vectorised NumPy floor of the same work the bench builds (:mod:`eulersym.bench._floors`: constants, phase and
   Landen in plain double; for the top, ω by the textbook's ψ with SciPy's compiled Carlson integrals at every
   time — cos θ alone, less work, is printed beside it), medians of alternating runs. Floor: ≤ 3×.
1. **Map.** The sleeping top's stability map, ``--tilts`` × ``--spins`` members (default 1000 × 1000), T = 3, 31
   output times, in a fresh process whose peak resident memory (``VmHWM``, the whole process) is read at its end:
   with ``want = ["summary"]`` (floor: peak ≤ 400 MB) and with ω kept (``map-omega``; floors: ≤ 15 s and peak ≤
   the output + 300 MB). Sampled members are run again as single scenes: their largest tilt and final ω agree with
   the map's to the accuracy asked. ``zarr`` (only when named): ``--zarr-members`` (default 10⁷) streamed to a Zarr
   store (floor: peak ≤ 1 GB), read back with xarray.
1b. **Lower bound.** The asymmetric sweep (summaries) against its kernel calls × the CPU-ns a call costs in the bare
   compiled loop, over the cores used. Floor: ≤ 2×.
2. **Default against DOP853.** An asymmetric heavy top (no closed form), ``--members`` members (default 10⁵), by the
   plan's default and by ``method = "DOP853"``, median times of alternating runs; both errors on sampled members
   against a single solve_ivp DOP853 run at rtol 1e-12. Floors: the default ≥ 5× faster, its error ≤ the accuracy
   asked (DOP853's is printed beside it). Every member is also compared with the sweep run at accuracy 1e-10: the
   share beyond the accuracy asked, median, p99 and largest error of each engine (an asymmetric heavy top is
   sensitive: a few members' global errors are many times the tolerance, for both engines).
3. **Refusal.** ``eulersym simulate`` of a 10⁹-member sweep in a fresh process: exit 2 with the estimate. Floors:
   < 1 s and < 100 MB (the whole command, interpreter start included).
4. **Dask.** The asymmetric sweep of (2) on a local cluster of 1 and of 2 worker processes: results identical to
   the in-process run; floor: 2 workers ≥ 1.8× the throughput of one, on a free machine (2 cores, shared: noisy).

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
import json, os, threading, time
start = time.perf_counter()
pss_peak = [0]
def _pss(pid):
    try:
        with open(f"/proc/{{pid}}/smaps_rollup") as f:
            return sum(int(l.split()[1]) for l in f if l.startswith("Pss:"))
    except OSError:
        return 0
def _sample(stop):  # the process and its worker processes: proportional set sizes, summed, every 500 ms
    me = os.getpid()
    while not stop.wait(0.5):
        kids = []
        for task in os.listdir(f"/proc/{{me}}/task"):
            try:
                kids += open(f"/proc/{{me}}/task/{{task}}/children").read().split()
            except OSError:
                pass
        pss_peak[0] = max(pss_peak[0], _pss(me) + sum(_pss(int(k)) for k in kids))
stop = threading.Event()
threading.Thread(target=_sample, args=(stop,), daemon=True).start()
import numpy as np
from eulersym.scene import Scene, simulate
from eulersym.scene import cost
scene = Scene(name="sleeping-top-map-bench", **{body!r}, t_end={t_end!r}, points={points!r}, accuracy={accuracy!r},
              outputs={want!r}, memory={memory!r}, omega=(0.0, 0.0, {{"start": 60.0, "stop": 95.0, "num": {spins}}}),
              euler=(0.0, {{"start": 0.005, "stop": 0.05, "num": {tilts}}}, 0.0))
store = {store!r}
if store:
    from eulersym.sweeps import zarr_store
    with zarr_store.streaming(store):
        estimate = cost.estimate(scene, scene.plan())
    from eulersym.scene.io import stream
    r = stream(scene, store, memory={memory!r})
else:
    estimate = cost.estimate(scene, scene.plan())
    r = simulate(scene)
seconds = time.perf_counter() - start
stop.set()
picks = {picks!r}
hwm = [int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmHWM:")][0]
import resource, os
use = resource.getrusage(resource.RUSAGE_SELF)
kids = resource.getrusage(resource.RUSAGE_CHILDREN)  # the worker processes of a closed form's chunks (if any)
workers = cost.processes(r.plan) if r.plan.batch > 1 and not store else 1
workers = workers if kids.ru_maxrss else 0
if r.summary:
    tilt_max = [float(r.summary["tilt_max"][b]) for b in picks]
    final = [[float(r.summary[f"omega{{k}}.final"][b]) for k in (1, 2, 3)] for b in picks]
elif store:
    import xarray
    ds = xarray.open_zarr(store)
    g = ds["gamma"].isel(member=picks).values
    tilt_max = [float(v) for v in np.arctan2(np.hypot(g[..., 0], g[..., 1]), g[..., 2]).max(axis=1)]
    final = ds["omega"].isel(member=picks, time=-1).values.tolist()
else:
    g = r.gamma[picks]
    tilt_max = [float(v) for v in np.arctan2(np.hypot(g[..., 0], g[..., 1]), g[..., 2]).max(axis=1)]
    final = r.omega[picks, -1].tolist()
print(json.dumps(dict(seconds=seconds, cpu=use.ru_utime + use.ru_stime + kids.ru_utime + kids.ru_stime,
    load=os.getloadavg()[0], motion=r.timings.get("motion", 0.0), peak_kib=hwm + workers * kids.ru_maxrss,
    parent_kib=hwm, workers=workers, pss_kib=pss_peak[0], worker_kib=kids.ru_maxrss, engine=r.plan.engine, output_bytes=estimate.output_bytes,
    estimate_bytes=estimate.process_bytes, members=r.plan.batch, tilt=[float(r.sweep["euler[1]"][b]) for b in picks],
    spin=[float(r.sweep["omega[2]"][b]) for b in picks], tilt_max=tilt_max, omega_final=final)))
"""


def bench_map(tilts: int = 1000, spins: int = 1000, *, t_end: float = 3.0, points: int = 31, accuracy: float = 1e-6,
              samples: int = 5, memory: str = "1 GiB", want=("summary",), store: str | None = None) -> dict:
    """The sleeping-top map of ``tilts × spins`` members in a fresh process — summaries, or trajectories kept in
    memory (``want = ("omega",)``), or streamed to the Zarr store ``store`` — its time, CPU (the process and its
    worker processes), peak memory (VmHWM of the process plus, where its chunks ran on worker processes, their number
    times the largest worker's peak resident set: an upper bound, since each counts the pages it shares), and sampled
    members against single runs."""
    from eulersym.scene import Scene, simulate

    members = tilts * spins
    picks = sorted({int(b) for b in np.linspace(0, members - 1, samples)})
    code = _MAP_CODE.format(body=SLEEPING_TOP, t_end=t_end, points=points, accuracy=accuracy, tilts=tilts,
                            spins=spins, picks=picks, memory=memory, want=tuple(want), store=store)
    got = _in_fresh_process(code)
    worst_tilt = worst_omega = 0.0
    for k in range(len(picks)):
        single = simulate(Scene(**SLEEPING_TOP, t_end=t_end, points=points, accuracy=accuracy,
                                outputs=("omega",), omega=(0.0, 0.0, got["spin"][k]), euler=(0.0, got["tilt"][k], 0.0)))
        theta = np.arccos(np.clip(single.gamma[:, 2], -1.0, 1.0))
        worst_tilt = max(worst_tilt, abs(float(theta.max()) - got["tilt_max"][k]) / max(float(theta.max()), 1e-300))
        worst_omega = max(worst_omega, float(np.max(np.abs(single.omega[-1] - np.asarray(got["omega_final"][k])))) / got["spin"][k])
    what = ", ".join(f'"{w}"' for w in want) + (f", streamed to {os.path.basename(store)}" if store else "")
    return {
        "case": f"sleeping-top map: {tilts} tilts × {spins} spins = {members} members, T = {t_end:g}, {points} output "
                f"times, accuracy {accuracy:g}, want = [{what}]",
        "output_bytes": got["output_bytes"],
        "estimate_bytes": got["estimate_bytes"],
        "engine": got["engine"],
        "seconds": got["seconds"],
        "cpu": got["cpu"],
        "load": got["load"],
        "peak_bytes": got["peak_kib"] * 1024,
        "workers": got["workers"],
        "parent_bytes": got["parent_kib"] * 1024,
        "worker_bytes": got["worker_kib"] * 1024,
        "pss_bytes": got["pss_kib"] * 1024,
        # what the memory floors read: with worker processes, the proportional set sizes summed (sampled)
        "floor_bytes": (got["pss_kib"] if got["workers"] else got["peak_kib"]) * 1024,
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


def _cpu(fn):
    """CPU seconds of ``fn()`` in this process and in the worker processes it started and waited for (a closed form's
    chunks, :func:`eulersym.sweeps.chunks.pooled`), and its result."""
    start, kids = time.process_time(), os.times()
    out = fn()
    done = os.times()
    workers = done.children_user - kids.children_user + done.children_system - kids.children_system
    return time.process_time() - start + workers, out


def bench_closed_form(members: int = 100_000, *, points: int = 31, repeats: int = 3) -> dict:
    """A closed-form sweep's CPU time per member (``simulate``: the free body, I = (1, 2, 3), and the sleeping-top
    map's Lagrange top, ``points`` output times, ω out) against the vectorised NumPy floor of the same work the bench
    builds (:mod:`eulersym.bench._floors`: constants, phase and Landen in plain double, chunks of 4096), medians of
    alternating runs in one process; the floor checked to agree with the sweep (the same work)."""
    from eulersym.bench._floors import free_body_floor, heavy_top_floor, heavy_top_omega_floor
    from eulersym.numerics.heavy_top_exact import euler_to_quaternion
    from eulersym.scene import Scene, simulate

    side = max(2, int(round(np.sqrt(members))))
    rows = {}
    free = Scene(name="free-body-sweep", moments=(1.0, 2.0, 3.0), t_end=10.0, points=points, outputs=("omega",),
                 omega=({"start": 0.1, "stop": 1.0, "num": side}, {"start": 0.5, "stop": 1.5, "num": side}, 0.3))
    top = Scene(name="sleeping-top-map", **SLEEPING_TOP, t_end=3.0, points=points, accuracy=1e-6, outputs=("omega",),
                omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": side}),
                euler=(0.0, {"start": 0.005, "stop": 0.05, "num": side}, 0.0))
    for name, scene in (("free body", free), ("Lagrange top", top)):
        simulate(scene)  # warm: imports
        result = simulate(scene)
        B, t = scene.batch, result.t
        if name == "free body":
            I = np.tile([1.0, 2.0, 3.0], (B, 1))
            w = np.stack([result.sweep["omega[0]"], result.sweep["omega[1]"], np.full(B, 0.3)], axis=1)

            def floor(I=I, w=w, t=t):
                return np.concatenate([free_body_floor(I[k:k + 4096], w[k:k + 4096], t) for k in range(0, B, 4096)])

            check = float(np.max(np.abs(floor() - result.omega)))
        else:
            I1, I3 = np.full(B, SLEEPING_TOP["moments"][0]), np.full(B, SLEEPING_TOP["moments"][2])
            mgl = np.full(B, SLEEPING_TOP["mass"] * SLEEPING_TOP["g"] * SLEEPING_TOP["l"])
            w = np.stack([np.zeros(B), np.zeros(B), result.sweep["omega[2]"]], axis=1)
            q = euler_to_quaternion(np.stack([np.zeros(B), result.sweep["euler[1]"], np.zeros(B)], axis=1))

            def blocks(fn, I1=I1, I3=I3, mgl=mgl, w=w, q=q, t=t):
                return np.concatenate([fn(I1[k:k + 4096], I3[k:k + 4096], mgl[k:k + 4096], w[k:k + 4096],
                                          q[k:k + 4096], t) for k in range(0, B, 4096)])

            def floor():  # ω, the sweep's own output: ψ needs the third-kind integrals at every time
                return blocks(heavy_top_omega_floor)

            def cos_theta():  # what the floor used to be: less work (no ψ), informational
                return blocks(heavy_top_floor)

            scale = np.abs(result.omega).max(axis=(1, 2))
            differ = np.abs(floor() - result.omega).max(axis=(1, 2)) / scale
            check = float(np.nanmax(differ))
            median = float(np.nanmedian(differ))
        ours, base, less = [], [], []
        for _ in range(max(1, repeats)):
            ours.append(_cpu(lambda scene=scene: simulate(scene))[0])
            base.append(_cpu(floor)[0])
            if name != "free body":
                less.append(_cpu(cos_theta)[0])
        rows[name] = {"members": B, "ours_us": 1e6 * float(np.median(ours)) / B,
                      "floor_us": 1e6 * float(np.median(base)) / B, "agree": check, "engine": result.plan.engine}
        if less:
            rows[name]["cos_theta_us"] = 1e6 * float(np.median(less)) / B
            rows[name]["agree_median"] = median
        rows[name]["ratio"] = rows[name]["ours_us"] / rows[name]["floor_us"]
    return rows


def bench_bound(members: int = 100_000, *, accuracy: float = 1e-6) -> dict:
    """The asymmetric heavy-top sweep (summaries) against its lower bound: its kernel calls × the CPU nanoseconds one
    call costs inside the compiled DOP853 loop itself (the bare loop on a sample of the members, outside the scene),
    over the cores it uses."""
    from eulersym.numerics.methods._members_dop853 import members as compiled
    from eulersym.scene import simulate
    from eulersym.scene.problem import prepare

    scene = _asymmetric_scene(members, accuracy=accuracy, outputs=("summary",))
    simulate(_asymmetric_scene(256, accuracy=accuracy, outputs=("summary",)))  # warm: numba's cache, imports
    start, cpu_start = time.perf_counter(), time.process_time()
    result = simulate(scene)
    wall, cpu_sweep = time.perf_counter() - start, time.process_time() - cpu_start
    plan = scene.plan()
    problem = prepare(scene, plan).take(0, min(20_000, scene.batch))
    y0 = np.ascontiguousarray(np.concatenate([problem.omega0, problem.gamma0, problem.q0], axis=1))
    params = np.ascontiguousarray(np.stack([problem.moments[:, 0], problem.moments[:, 1], problem.moments[:, 2],
                                            problem.mass, problem.g, problem.l], axis=1))
    out = np.empty((problem.batch, len(problem.t), 10))
    cpu, calls = _cpu(lambda: compiled(y0, params, problem.t, problem.rtol, problem.atol, out))
    ns = 1e9 * cpu / float(np.sum(calls))
    cores = min(os.cpu_count() or 1, 2)
    bound = result.n_rhs_calls * ns * 1e-9 / cores
    return {"members": scene.batch, "wall": wall, "calls": result.n_rhs_calls, "ns_per_call": ns, "cores": cores,
            "bound": bound, "ratio": wall / bound, "engine": result.plan.engine, "cpu": cpu_sweep,
            "cpu_ratio": cpu_sweep / (bound * cores), "load": os.getloadavg()[0]}


def main(argv) -> int:
    """Run the four benchmarks; print each figure beside its floor. Exit 1 if a floor is missed."""
    p = argparse.ArgumentParser(prog="eulersym bench sweeps", description=__doc__.splitlines()[0])
    p.add_argument("--tilts", type=int, default=1000, help="map: tilts (default 1000)")
    p.add_argument("--spins", type=int, default=1000, help="map: spins (default 1000)")
    p.add_argument("--members", type=int, default=100_000, help="asymmetric sweep and Dask: members (default 10⁵)")
    p.add_argument("--only", choices=("closed-form", "map", "map-omega", "zarr", "bound", "dop853", "refusal", "dask"),
                   action="append", help="run only these (repeatable; zarr is not run unless named)")
    p.add_argument("--zarr-members", type=int, default=10_000_000,
                   help="zarr: members of the map streamed to a Zarr store (default 10⁷: ~15 GB of ω and Γ on disk)")
    p.add_argument("--zarr-dir", default=None, help="zarr: the folder the store goes in (default: a temporary one)")
    p.add_argument("--repeats", type=int, default=None,
                   help="default against DOP853: alternating runs, medians reported (default 3; 5 with --quick)")
    p.add_argument("--quick", action="store_true", help="small sizes (a smoke test; floors reported, not enforced)")
    args = p.parse_args(list(argv))
    if args.quick:
        args.tilts, args.spins, args.members, args.zarr_members = 50, 40, 4000, 20_000
    only = set(args.only or ("closed-form", "map", "map-omega", "bound", "dop853", "refusal", "dask"))
    ok = True

    def verdict(passed: bool) -> str:
        nonlocal ok
        ok &= passed or args.quick
        return "met" if passed else "MISSED"

    print("eulersym bench sweeps" + (" --quick" if args.quick else "") + f" ({load_text()}; wall times are noisy under load)")
    if "closed-form" in only:
        rows = bench_closed_form(args.members)
        for name, r in rows.items():
            print(f"closed-form sweep, {name}: {r['members']} members × 31 times, ω out ({r['engine']})\n"
                  f"  simulate {r['ours_us']:.2f} CPU-µs a member, vectorised NumPy floor of the same work "
                  f"{r['floor_us']:.2f} (medians of 3 alternating): {r['ratio']:.2f}× the floor (floor ≤ 3×: "
                  f"{verdict(r['ratio'] <= 3)})")
            if name == "free body":
                print(f"  the floor's ω against the sweep's: {r['agree']:.1e} (the same function, in plain double)")
            else:
                print(f"  the floor: ω by the textbook's ψ (Carlson's R_F, R_J at every time: SciPy's compiled "
                      f"elliprf/elliprj), constants in plain double; its ω against the sweep's, relative: largest "
                      f"{r['agree']:.1e}, median {r['agree_median']:.1e} (the floor's own error: its constants in "
                      f"plain double)\n  cos θ alone (less work: no ψ; not a floor of ω) "
                      f"{r['cos_theta_us']:.2f} CPU-µs a member")
    def whose(r) -> str:
        if not r["workers"]:
            return "the whole process"
        return (f"the process {r['parent_bytes'] / 1e6:.0f} MB + {r['workers']} worker processes × "
                f"{r['worker_bytes'] / 1e6:.0f} MB, each counting the pages it shares; their proportional set sizes "
                f"summed, sampled every 500 ms: {r['pss_bytes'] / 1e6:.0f} MB, what the floor reads")

    if "map" in only:
        r = bench_map(args.tilts, args.spins, memory="2 GiB")
        mb = r["floor_bytes"] / 1e6
        print(f"{r['case']}\n  engine: {r['engine']}\n  {r['seconds']:.1f} s ({r['cpu']:.1f} CPU-s, load average "
              f"{r['load']:.1f} on 2 cores), peak {mb:.0f} MB ({whose(r)}) (floor ≤ 400 MB: {verdict(mb <= 400)}; "
              f"estimated {r['estimate_bytes'] / 1e6:.0f} MB)\n"
              f"  sampled members against single runs: largest tilt {r['tilt_error']:.1e}, final ω {r['omega_error']:.1e} "
              f"(relative; accuracy {r['accuracy']:g}: {verdict(max(r['tilt_error'], r['omega_error']) <= 10 * r['accuracy'])})")
    if "map-omega" in only:
        r = bench_map(args.tilts, args.spins, memory="4 GiB", want=("omega",))
        out_mb, mb = r["output_bytes"] / 1e6, r["floor_bytes"] / 1e6
        print(f"{r['case']}\n  engine: {r['engine']}\n  {r['seconds']:.1f} s (floor ≤ 15 s: {verdict(r['seconds'] <= 15)}; "
              f"{r['cpu']:.1f} CPU-s, load average {r['load']:.1f} on 2 cores), peak {mb:.0f} MB ({whose(r)}) for an output of "
              f"{out_mb:.0f} MB (ω and Γ) (floor ≤ output + 300 MB: {verdict(mb <= out_mb + 300)}; estimated "
              f"{r['estimate_bytes'] / 1e6:.0f} MB)\n  sampled members against single runs: largest tilt "
              f"{r['tilt_error']:.1e}, final ω {r['omega_error']:.1e}")
    if "zarr" in (args.only or ()):
        side = int(round(np.sqrt(args.zarr_members)))
        folder = args.zarr_dir or tempfile.mkdtemp(prefix="eulersym-bench-")
        store = os.path.join(folder, "map.zarr")
        try:
            r = bench_map(side, side, memory="1 GiB", want=("omega",), store=store)
            size = sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(store) for f in fs)
        finally:
            if args.zarr_dir is None:
                import shutil

                shutil.rmtree(folder, ignore_errors=True)
        mb = r["peak_bytes"] / 1e6
        print(f"{r['case']}\n  {r['seconds']:.0f} s ({r['cpu']:.0f} CPU-s, load average {r['load']:.1f}), "
              f"{size / 1e9:.1f} GB written, peak {mb:.0f} MB (floor ≤ 1 GB: {verdict(mb <= 1000)}); sampled members "
              f"read back against single runs: final ω {r['omega_error']:.1e}")
    if "bound" in only:
        r = bench_bound(args.members)
        print(f"asymmetric heavy top, {r['members']} members (summaries), {r['engine']}\n  {r['wall']:.2f} s wall, "
              f"{r['calls']:.3g} kernel calls × {r['ns_per_call']:.1f} CPU-ns a call in the bare compiled loop / "
              f"{r['cores']} cores = lower bound {r['bound']:.2f} s: {r['ratio']:.2f}× the bound "
              f"(floor ≤ 2×: {verdict(r['ratio'] <= 2)}); CPU {r['cpu']:.2f} s against {r['bound'] * r['cores']:.2f} "
              f"CPU-s of kernel calls: {r['cpu_ratio']:.2f}× (what the wall ratio would be on free cores; load "
              f"average {r['load']:.1f} on {os.cpu_count()} CPUs)")
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
              f"(floor ≥ 1.8×, on a free machine: {verdict(r['ratio'] >= 1.8)}); identical to in-process: "
              f"{verdict(r['identical'])}"
              + ("" if r["identical"] else f" (entries that differ, by summary: {r['differ']})"))
    return 0 if ok else 1
