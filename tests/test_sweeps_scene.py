"""Sweeps through the scene: cost known first, refusals, summaries, chunked streaming, Dask, the sweep engines."""

from __future__ import annotations

import subprocess
import sys
import tracemalloc

import numpy as np
import pytest

from eulersym.errors import InvalidInput
from eulersym.scene import Scene, cli, simulate
from eulersym.scene import cost as scene_cost
from eulersym.numerics import methods
from eulersym.scene.problem import prepare
from eulersym.sweeps import distributed

TOP = dict(moments=(1.2e-3, 1.2e-3, 4.0e-4), mass=0.5, l=0.04, g=9.81, t_end=0.3, points=11, accuracy=1e-6)
ASYMMETRIC = dict(moments=(1.0e-3, 1.4e-3, 6.0e-4), mass=0.5, l=0.04, g=9.81, t_end=0.3, points=7, accuracy=1e-6)


def _map(n_tilt=6, n_spin=7, **kw):
    return Scene(**{**TOP, **kw}, omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": n_spin}),
                 euler=(0.0, {"start": 0.005, "stop": 0.05, "num": n_tilt}, 0.0))


# ---- the cost, before anything is allocated ---------------------------------------------------------------------


def test_a_billion_members_are_refused_by_the_command_line_with_the_estimate(tmp_path, capsys):
    path = tmp_path / "huge.toml"
    path.write_text('[body]\nmoments = [1.0, 1.4, 0.6]\nmass = 0.5\n[pivot]\nl = 0.04\n[initial]\n'
                    'omega = [{start = 0, stop = 1, num = 1000}, {start = 0, stop = 1, num = 1000}, '
                    '{start = 20, stop = 40, num = 1000}]\n[time]\nend = 3.0\n')
    from eulersym.cli import main

    assert main(["simulate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "1000000000 members" in err and "memory budget" in err and "What would fit" in err
    assert "Traceback" not in err


def test_work_beyond_the_budget_is_refused():
    """An asymmetric heavy top over 10^12 time units: refused at once for its kernel evaluations."""
    scene = Scene(**{**ASYMMETRIC, "t_end": 1e12, "points": 101}, omega=(1.0, 0.0, 30.0))
    with pytest.raises(InvalidInput, match="work budget"):
        simulate(scene)
    with pytest.raises(InvalidInput, match="work budget of 10 kernel"):
        simulate(_map(), work=10)


def test_budgets_from_the_scene_file_and_the_command_line(tmp_path, capsys):
    path = tmp_path / "map.toml"
    path.write_text('[body]\nmoments = [1.2e-3, 1.2e-3, 4.0e-4]\nmass = 0.5\n[pivot]\nl = 0.04\n[initial]\n'
                    'euler = [0.0, {start = 0.005, stop = 0.05, num = 4}, 0.0]\n'
                    'omega = [0.0, 0.0, {start = 60.0, stop = 95.0, num = 36}]\n[time]\nend = 3.0\npoints = 301\n'
                    '[output]\nwant = ["omega"]\nmemory = "1 MiB"\n')
    with pytest.raises(InvalidInput, match="memory budget of 1 MiB"):
        cli([str(path)])
    assert cli([str(path), "--explain", "--memory-budget", "3GiB"]) == 0
    out = capsys.readouterr().out
    assert "cost: 144 members × 301 points" in out and "budgets: memory 3 GiB" in out
    with pytest.raises(InvalidInput, match="--memory-budget"):
        cli([str(path), "--memory-budget", "-5"])
    with pytest.raises(InvalidInput, match="--workers"):
        cli([str(path), "--workers", "0"])


def test_the_estimate_is_within_a_factor_of_the_traced_allocations():
    """Peak traced memory of a summary sweep against the plan's estimate (NumPy reports to tracemalloc)."""
    scene = Scene(**TOP, outputs=("summary",), method="DOP853", omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": 40}),
                  euler=(0.0, {"start": 0.3, "stop": 0.6, "num": 30}, 0.0))  # tilted: no sleeping-top derivation (SymPy)
    simulate(scene)  # warm: imports and caches are not the sweep's memory
    estimate = scene_cost.estimate(scene, scene.plan())
    tracemalloc.start()
    try:
        simulate(scene)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert estimate.peak_bytes / 5 < peak < 5 * estimate.peak_bytes, (peak, str(estimate))


# ---- summaries and chunks ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["auto", "DOP853"])
def test_summaries_are_the_reductions_of_the_trajectories(method):
    full = simulate(_map(method=method, outputs=("omega", "invariants")))
    summ = simulate(_map(method=method, outputs=("summary", "invariants")))
    assert summ.omega is None and summ.gamma is None
    for k in range(3):
        assert np.array_equal(summ.summary[f"omega{k + 1}.min"], full.omega[:, :, k].min(axis=1))
        assert np.array_equal(summ.summary[f"omega{k + 1}.max"], full.omega[:, :, k].max(axis=1))
        assert np.array_equal(summ.summary[f"omega{k + 1}.final"], full.omega[:, -1, k])
    g = full.gamma
    tilt = np.arctan2(np.hypot(g[..., 0], g[..., 1]), g[..., 2]).max(axis=1)
    assert np.array_equal(summ.summary["tilt_max"], tilt)
    for name in full.invariants:
        assert summ.drift[name] == full.drift[name]
    assert any("kept per member" in n for n in summ.notes)
    assert any("largest tilt per member" in n for n in summ.notes)


@pytest.mark.parametrize("method", ["auto", "DOP853", "splitting"])
def test_chunked_equals_unchunked_bitwise(method):
    """A memory budget that forces several chunks gives the bits of the single pass (a chunk is a multiple of the
    members a method evaluates together: the closed form's blocks of 1024, DOP853's groups of 4096)."""
    size = dict(n_tilt=30, n_spin=70) if method == "auto" else {}
    scene = _map(method=method, outputs=("omega", "invariants"), **size)
    whole = simulate(scene)
    small = scene_cost.estimate(scene, whole.plan)
    grain = methods.get(whole.plan.options["engine"]).cost.grain
    budget = small.output_bytes + small.per_member_working * max(5, grain) * scene_cost.threads(whole.plan)
    chunked = simulate(scene, memory=budget)
    assert scene_cost.estimate(scene, whole.plan, memory=budget).chunk < scene.batch or method == "DOP853"
    for name in ("omega", "gamma"):
        assert np.array_equal(getattr(whole, name), getattr(chunked, name)), name
    for name in whole.invariants:
        assert np.array_equal(whole.invariants[name], chunked.invariants[name]), name
    assert whole.drift == chunked.drift and whole.notes == chunked.notes


def test_summary_plots_the_map_and_saves_a_row_per_member(tmp_path):
    pytest.importorskip("matplotlib")
    from eulersym.scene.io import plot, save

    r = simulate(_map(outputs=("summary",)))
    plot(r, str(tmp_path / "map.png"))
    assert (tmp_path / "map.png").read_bytes()[:4] == b"\x89PNG"
    save(r, str(tmp_path / "map.csv"))
    lines = (tmp_path / "map.csv").read_text().splitlines()
    head = lines[0].split(",")
    assert head[0] == "member" and set(head[1:3]) == {"omega[2]", "euler[1]"} and len(lines) == 1 + 42
    assert "theta_max_deg" in head and "omega1_min" in head and "gamma3_final" in head
    assert len(set(head)) == len(head) and "tilt_max" not in head and "omega1.final" not in head  # each once
    full = simulate(_map(outputs=("omega",)))  # the same table as the summary of a trajectory run, column for column
    from eulersym.scene.io import summary

    names, rows = summary(r)
    names_full, rows_full = summary(full)
    # theta_max: arccos(min Γ3) in the streamed summary, atan2(|Γ × e3|, Γ3) in the table: equal to round-off
    assert names == names_full and np.allclose(rows, rows_full, rtol=1e-12, atol=0)
    save(r, str(tmp_path / "map.npz"))
    with np.load(tmp_path / "map.npz") as data:
        assert np.array_equal(data["summary_theta_max_deg"], np.degrees(r.summary["tilt_max"]))
        assert np.array_equal(data["summary_omega1_min"], r.summary["omega1.min"])
        assert "summary_tilt_max" not in data and "summary_omega1.final" not in data


# ---- the sweep engines -------------------------------------------------------------------------------------------


def _reference(scene, b):
    """Member ``b`` by solve_ivp DOP853 at rtol 1e-13 (ω, Γ at the output times)."""
    tight = Scene(**{**ASYMMETRIC, "accuracy": 1e-12, "method": "DOP853"}, omega=(1.0, 0.0, [20.0, 40.0]),
                  euler=(0.0, [0.1, 0.6], 0.0))
    problem = prepare(tight, tight.plan())
    traj = methods.get("ivp").run(problem.take(b, b + 1))
    return traj.omega[0], traj.gamma[0]


@pytest.mark.parametrize("method, tolerance", [("auto", 1e-6), ("DOP853", 1e-6), ("splitting", 1e-5)])
def test_sweep_engines_meet_the_accuracy_on_an_asymmetric_top(method, tolerance):
    scene = Scene(**{**ASYMMETRIC, "method": method}, omega=(1.0, 0.0, [20.0, 40.0]), euler=(0.0, [0.1, 0.6], 0.0))
    r = simulate(scene)
    expected = {"auto": "compiled DOP853", "DOP853": "batched DOP853", "splitting": "batched splitting"}[method]
    assert expected in r.plan.engine
    for b in range(4):
        omega, gamma = _reference(scene, b)
        assert np.max(np.abs(r.omega[b] - omega)) / np.max(np.abs(omega)) < tolerance
        assert np.max(np.abs(r.gamma[b] - gamma)) < tolerance


def test_the_compiled_engine_equals_solve_ivp_step_for_step():
    """The per-member DOP853 is scipy's: at the same tolerances a single member takes scipy's steps."""
    from scipy.integrate import solve_ivp

    from eulersym.generated import heavy_top_euler_poisson as kernel
    from eulersym.numerics.methods._members_dop853 import members

    y0 = np.array([[0.0, 0.0, 60.0, 0.0, np.sin(0.05), np.cos(0.05), np.cos(0.025), np.sin(0.025), 0.0, 0.0]])
    p = np.array([[1.2e-3, 1.2e-3, 4e-4, 0.5, 9.81, 0.04]])
    t = np.array([0.0, 0.5])
    out = np.empty((1, 2, 10))
    calls = members(y0, p, t, 1e-9, 1e-12, out)
    sol = solve_ivp(lambda tt, y: kernel.rhs(tt, y, *p[0]), (0.0, 0.5), y0[0], method="DOP853", rtol=1e-9, atol=1e-12)
    assert abs(int(calls[0]) - sol.nfev) <= 13  # scipy counts its start-up evaluations alike, give or take a step
    assert np.max(np.abs(out[0, 1] - sol.y[:, -1])) < 1e-9 * 60


# ---- Dask --------------------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def client():
    c = distributed.local_client(2, processes=False)
    yield c
    distributed.close(c)


@pytest.mark.parametrize("outputs", [("summary",), ("omega", "invariants")])
def test_a_two_worker_cluster_gives_the_in_process_result(client, outputs):
    scene = _map(outputs=outputs)
    here = simulate(scene, memory=scene_cost.estimate(scene, scene.plan()).output_bytes + 2**20)
    there = simulate(scene, client=client)
    for name in here.summary:
        assert np.array_equal(here.summary[name], there.summary[name]), name
    if here.omega is not None:
        assert np.array_equal(here.omega, there.omega) and np.array_equal(here.gamma, there.gamma)
    assert here.drift == there.drift and here.notes == there.notes


def test_the_command_line_runs_on_local_workers(tmp_path):
    """``eulersym simulate FILE --workers 2``: a real 2-process LocalCluster, the report of the in-process run."""
    path = tmp_path / "map.toml"
    path.write_text('[body]\nmoments = [1.2e-3, 1.2e-3, 4.0e-4]\nmass = 0.5\n[pivot]\nl = 0.04\n[initial]\n'
                    'euler = [0.0, [0.01, 0.03], 0.0]\nomega = [0.0, 0.0, [70.0, 80.0, 90.0]]\n[time]\nend = 0.2\n'
                    'points = 5\n[output]\nwant = ["summary"]\n', encoding="utf-8")
    remote = subprocess.run([sys.executable, "-m", "eulersym", "simulate", str(path), "--workers", "2"],
                            capture_output=True, text=True, timeout=300)
    assert remote.returncode == 0, remote.stderr[-2000:]
    here = simulate(Scene.from_toml(path))
    from eulersym.scene.io import report

    strip = lambda text: [line for line in text.splitlines() if not line.startswith("timings")]  # noqa: E731
    assert strip(report(here)) == strip(remote.stdout)[1:]  # after the line naming the scene


_MEASURE = """
import json, sys
from eulersym.scene import Scene, simulate, cost
kind = sys.argv[1]
if kind == "free":
    scene = Scene(moments=(1.0, 2.0, 3.0), omega=({"start": 0.1, "stop": 1.0, "num": 300},
                  {"start": 0.5, "stop": 1.5, "num": 300}, 0.3), t_end=10, points=31, outputs=("omega", "attitude"))
elif kind == "map":
    scene = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, g=9.81, t_end=3, points=31, accuracy=1e-6,
                  outputs=("summary",), omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": 150}),
                  euler=(0.0, {"start": 0.005, "stop": 0.05, "num": 150}, 0.0))
elif kind == "zarr":  # trajectories streamed to a store: the starts prepared a chunk at a time
    scene = Scene(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, g=9.81, t_end=3, points=31, accuracy=1e-6,
                  outputs=("omega",), omega=(0.0, 0.0, {"start": 60.0, "stop": 95.0, "num": 200}),
                  euler=(0.0, {"start": 0.005, "stop": 0.05, "num": 200}, 0.0))
else:
    from eulersym.bench.sweeps import _asymmetric_scene
    scene = _asymmetric_scene(8000, t_end=1.0, outputs=("summary",))
if kind == "zarr":
    import os, tempfile
    from eulersym.scene.io import stream
    from eulersym.sweeps import zarr_store
    path = os.path.join(tempfile.mkdtemp(), "map.zarr")
    with zarr_store.streaming(path):
        e = cost.estimate(scene, scene.plan())
    r = stream(scene, path)
else:
    e = cost.estimate(scene, scene.plan())
    r = simulate(scene)
hwm = [int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmHWM:")][0] * 1024
import resource
kid = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024  # worker processes (the heavy top closed form's chunks)
workers = cost.processes(scene.plan()) if kid and kind != "zarr" else 0
print(json.dumps(dict(peak=hwm, estimate=e.process_bytes, arrays=e.peak_bytes, calls=r.n_rhs_calls,
                      evaluations=e.evaluations, chunk=e.chunk, members=scene.batch, worker=kid, workers=workers)))
"""


@pytest.mark.parametrize("kind", ["free", "map", "zarr", "dop853"])
def test_the_estimate_is_within_one_and_a_half_of_the_measured_peak_and_kernel_calls(kind):
    """A fresh process: its resident peak (VmHWM: interpreter, imports and the run's arrays) against the estimate
    (the arrays, what the budget bounds, plus the baseline it reports beside them), and the kernel calls of an
    integrated sweep against the estimated evaluations; chunks sized to the cache, not to the budget."""
    import json

    out = subprocess.run([sys.executable, "-c", _MEASURE, kind], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    got = json.loads(out.stdout.strip().splitlines()[-1])
    # with worker processes the tree's peak lies between the largest process's and the sum of the process's and each
    # worker's (each counts the pages it shares with the others)
    low = max(got["peak"], got["worker"] if got["workers"] else 0)
    high = got["peak"] + got["workers"] * got["worker"]
    assert got["estimate"] / 1.5 <= high and low <= 1.5 * got["estimate"], got
    assert got["chunk"] < got["members"], got
    if kind == "dop853":
        assert got["evaluations"] / 1.5 <= got["calls"] <= 1.5 * got["evaluations"], got
