"""One scene, one cost: the estimate, the budgets, the rate bound and the 2**52 rad phase limit of
eulersym.scene.cost, the same for a Python caller of simulate() and for the command line; model sweeps streamed in
chunks; members the heavy top's closed form cannot represent (the upright top's separatrix) integrated, not lost."""

from __future__ import annotations

import math
import pickle
import subprocess
import sys
import textwrap
import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from eulersym.cli import main
from eulersym.errors import InvalidInput
from eulersym.scene import Scene, cost, simulate


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A kernel cache of the test's own."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("EULERSYM_CACHE", str(folder))
    return folder


def _cli_error(capsys, *argv) -> str:
    assert main(["simulate", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def _toml(path, text):
    path.write_text(textwrap.dedent(text))
    return str(path)


def _damped_file(path, name, c, end, points=None, omega="[0.1, 1.0, 0.2]"):
    """A damped body's model file (torque ``-c*omega``, moments (1, 2, 3)): the TOML values as written."""
    lines = [f'name = "{name}"', "[parameters]", f"c = {c}", "[body]", "moments = [1.0, 2.0, 3.0]", "mass = 1.0",
             "[torque]", 'body = "-c*omega"', "[initial]", f"omega = {omega}", "[time]", f"end = {end}"]
    if points is not None:
        lines.append(f"points = {points}")
    path.write_text("\n".join(lines) + "\n")
    return str(path)


# ---- one estimate, one check ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("body, budget", [
    # one member over 1e12 time units: the one-member work budget (1e9 kernel evaluations)
    ("omega = [0, 0, 10]\n[time]\nend = 1e12\n", "work budget of 1e+09"),
    # a sweep of 10^9 members: the memory budget, before anything is allocated
    ("omega = [{start = 0, stop = 1, num = 1000}, {start = 0, stop = 1, num = 1000}, "
     "{start = 20, stop = 40, num = 1000}]\n[time]\nend = 3.0\n", "memory budget"),
    # a sweep of 3 members over 1e12: the sweeps' work budget (5e10)
    ("omega = [0, 0, [10, 11, 12]]\n[time]\nend = 1e12\n", "work budget of 5e+10"),
])
def test_simulate_and_the_command_line_refuse_with_the_same_message(tmp_path, capsys, body, budget):
    path = _toml(tmp_path / "s.toml", "[body]\nmoments = [1.0, 1.5, 2.0]\nmass = 1\n[pivot]\nl = 0.1\n[initial]\n"
                 "euler = [0, 0.5, 0]\n" + body)
    err = _cli_error(capsys, path)
    with pytest.raises(InvalidInput) as info:
        simulate(Scene.from_toml(path))
    assert str(info.value) in err and info.value.argument == "scene"
    for needle in (budget, "What would fit", "it needs about", "rad by t_end"):
        assert needle in err, (needle, err)


def test_the_default_work_budget_is_per_member_count():
    """1e9 kernel evaluations for one member, 5e10 for a sweep: the same scene passes as a sweep of 2 and is refused
    alone once its estimate lies between the two."""
    base = dict(moments=(1.0, 1.5, 2.0), mass=1, l=0.1, euler=(0, 0.5, 0), method="DOP853", points=11)
    single = Scene(**base, omega=(0, 0, 10.0), t_end=1.5e7)
    pair = Scene(**base, omega=(0, 0, [10.0, 10.0]), t_end=1.5e7)
    e = cost.estimate(pair, pair.plan())
    assert cost.ONE_MEMBER_WORK_BUDGET < cost.estimate(single, single.plan()).evaluations < e.evaluations < 5e10
    with pytest.raises(InvalidInput, match="work budget of 1e\\+09"):
        cost.check(single, single.plan())
    assert cost.check(pair, pair.plan()).evaluations == e.evaluations
    assert cost.check(single, single.plan(), work=1e10).members == 1  # the caller's budget wins


def test_the_command_line_aliases_are_the_one_estimate():
    from eulersym.scene.cli import WORK_LIMIT, _refuse_endless, work_estimate
    from eulersym.scene.spec import load, rate_bound

    scene = load("sleeping-top-map")
    assert WORK_LIMIT == cost.ONE_MEMBER_WORK_BUDGET and rate_bound is cost.rate_bound
    assert work_estimate(scene) == cost.estimate(scene, scene.plan())
    endless = Scene(moments=(1.0, 1.5, 2.0), mass=1, l=0.1, euler=(0, 0.5, 0), omega=(0, 0, 10.0), t_end=1e12)
    with pytest.raises(InvalidInput) as a:
        _refuse_endless(endless)
    with pytest.raises(InvalidInput) as b:
        simulate(endless)
    assert str(a.value) == str(b.value)


def test_explain_prints_the_one_estimate(tmp_path, capsys):
    path = _toml(tmp_path / "s.toml", "[body]\nmoments = [1.0, 1.5, 2.0]\n[initial]\n"
                 "omega = [0.1, [1.0, 2.0], 0.2]\n[time]\nend = 2.0\npoints = 21\n")
    assert main(["simulate", path, "--explain", "--memory-budget", "1 GiB"]) == 0
    out = capsys.readouterr().out
    scene = Scene.from_toml(path)
    assert cost.describe(cost.estimate(scene, scene.plan(), memory=2**30), 2**30, 5e10) in out
    assert out.count("cost:") == 1


# ---- the one rate bound ------------------------------------------------------------------------------------------


_finite = st.floats(-1e3, 1e3, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(w=st.lists(st.lists(_finite, min_size=1, max_size=3), min_size=3, max_size=3),
       moments=st.tuples(st.floats(0.1, 10.0), st.floats(0.1, 10.0), st.floats(0.05, 0.95)), pivot=st.booleans(),
       l=st.floats(0.01, 1.0), mass=st.floats(0.1, 10.0))
def test_the_rate_bound_bounds_every_members_spin_and_pendulum(w, moments, pivot, l, mass):
    i1, i2, f = moments
    moments = (i1, i2, abs(i1 - i2) + f * (i1 + i2 - abs(i1 - i2)))  # a body's: the triangle inequalities
    omega = tuple(c[0] if len(c) == 1 else list(c) for c in w)
    kw = dict(mass=mass, l=l, euler=(0, 0.5, 0)) if pivot else {}
    scene = Scene(moments=moments, omega=omega, t_end=1.0, **kw)
    rate = cost.rate_bound(scene)
    members = scene.members()
    spins = np.linalg.norm(np.stack([members.get(f"omega[{k}]", np.full(scene.batch, float(w[k][0])))
                                     for k in range(3)], axis=1), axis=1)
    assert np.all(spins <= rate * (1 + 1e-12))
    if pivot:
        assert math.sqrt(mass * 9.81 * l / min(moments)) <= rate * (1 + 1e-12)


@settings(max_examples=80, deadline=None)
@given(text=st.text(max_size=12) | st.from_regex(r"\s*[0-9.eE+-]{1,8}\s*[kKmMgGtTiIbB]{0,3}\s*", fullmatch=True))
def test_budgets_from_any_text_are_parsed_or_refused_naming_the_argument(text):
    scene = Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1)
    for kw, argument in (("memory", "--memory-budget"), ("work", "--work-budget")):
        try:
            mem, wk = cost.budgets(scene, **{kw: text})
        except InvalidInput as exc:
            assert exc.argument == argument and exc.value == text
        else:
            assert mem > 0 and wk > 0 and math.isfinite(wk)


def test_a_torque_adds_what_it_can_spin_up_by_the_end():
    scene = Scene(moments=(2.0, 2.0, 2.0), omega=(0, 0, 1.0), torque=(0, 0, 4.0), t_end=3.0, outputs=("omega",))
    assert cost.rate_bound(scene) == 1.0 + 4.0 * 3.0 / 2.0
    r = simulate(scene)
    assert np.max(np.linalg.norm(r.omega, axis=1)) <= cost.rate_bound(scene) * (1 + 1e-12)


# ---- model scenes: the phase limit, refusals before deriving, --explain -------------------------------------------


GYROSTAT = """
name = "fast-rotor"
[parameters]
h = 2.0
[body]
moments = [1.0, 2.0, 3.0]
mass = 10.0
[rotor]
h = [0.0, 0.0, "h"]
[initial]
omega = [0.0, 0.0, 1.0]
[time]
end = {end}
points = 11
[output]
want = ["omega"]
"""


def test_a_model_scene_beyond_2_52_rad_is_refused_before_deriving(tmp_path, cache, capsys):
    """The spin alone turns it 2**53 rad: refused naming the end time as the file writes it, when the scene is read
    (nothing derived: the cache stays empty)."""
    path = _toml(tmp_path / "spin.toml", GYROSTAT.format(end=2.0 ** 53))
    err = _cli_error(capsys, path)
    assert "time.end=" in err and "2**52 rad" in err and "phase" in err
    assert not cache.exists() or not any(cache.rglob("*.py"))


def test_a_model_scene_beyond_2_52_rad_by_its_rotor_is_refused_from_its_facts(tmp_path, cache):
    """Spin 1 × 2e15 < 2**52 rad, but the rotor's |h| / I_min = 2 adds 4e15: the model's facts (NumPy, nothing
    derived) know it when the scene is read."""
    with pytest.raises(InvalidInput) as info:
        Scene.from_toml(_toml(tmp_path / "rotor.toml", GYROSTAT.format(end=2e15)))
    assert info.value.argument == "time.end" and "|ω| ≈ 3 ×" in str(info.value)
    assert not cache.exists() or not any(cache.rglob("*.py"))
    small = Scene.from_toml(_toml(tmp_path / "ok.toml", GYROSTAT.format(end=2.0)))
    assert cost.rate_bound(small) == 3.0
    assert np.all(np.isfinite(simulate(small).omega))


def test_a_model_sweep_too_big_is_refused_before_deriving_or_allocating(tmp_path, cache):
    sweep = "{start = 0, stop = 1, num = 1000}"
    path = _damped_file(tmp_path / "huge.toml", "huge-damped", "{start = 0.0, stop = 1.0, num = 1000}", "3.0",
                        omega=f"[{sweep}, {sweep}, 0.2]")
    scene = Scene.from_toml(path)
    tracemalloc.start()
    try:
        with pytest.raises(InvalidInput, match="memory budget") as info:
            simulate(scene)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 50 * 2**20, peak
    assert "1000000000 members" in str(info.value)
    assert not cache.exists() or not any(cache.rglob("*.py"))  # nothing derived


def test_an_endless_torqued_model_is_refused_before_deriving(tmp_path, cache, capsys):
    """A torque that names the state means the model's own kernel is integrated (its facts say so): 1e12 time units
    are refused for their work before anything is derived."""
    path = _damped_file(tmp_path / "endless.toml", 'endless-damped', '0.1', '1e12')
    err = _cli_error(capsys, path)
    assert "work budget of 1e+09" in err and "scene=" in err
    assert not cache.exists() or not any(cache.rglob("*.py"))


def test_explain_of_an_uncached_model_says_what_it_will_do_without_sympy(tmp_path, cache):
    path = _damped_file(tmp_path / "damped.toml", 'damped', '[0.1, 0.2, 0.3]', '2.0', points=11)
    code = ("import sys\nfrom eulersym.cli import main\n"
            f"assert main(['simulate', {path!r}, '--explain']) == 0\n"
            "print('sympy imported:', 'sympy' in sys.modules)")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                         env={**__import__("os").environ, "EULERSYM_CACHE": str(cache)})
    assert run.returncode == 0, run.stderr
    out = run.stdout
    assert "sympy imported: False" in out
    assert "the model's equations of motion" in out and str(cache) in out  # what is derived, where it goes
    assert "3 members in one vectorised pass" in out and "its state, once emitted" in out and "a torque" in out
    assert out.count("cost:") == 1
    assert not cache.exists() or not any(cache.rglob("*.py"))  # nothing derived
    simulate(Scene.from_toml(path))  # now cached: --explain names the kernel's state too
    assert main(["simulate", path, "--explain"]) == 0


def test_explain_of_a_cached_model_names_its_engine(tmp_path, cache, capsys):
    path = _damped_file(tmp_path / "damped.toml", 'damped', '0.1', '2.0', points=11)
    simulate(Scene.from_toml(path))
    assert main(["simulate", path, "--explain"]) == 0
    out = capsys.readouterr().out
    assert "DOP853 on model damped (omega1, omega2, omega3, q0" in out and "cached for digest" in out


# ---- model sweeps in chunks --------------------------------------------------------------------------------------


def _damped(n, **output):
    c = {"start": 0.0, "stop": 0.5, "num": n} if n > 1 else 0.0
    return Scene.from_dict({
        "name": "damped", "parameters": {"c": c},
        "body": {"moments": [1.0, 2.0, 3.0]}, "torque": {"body": "-c*omega"},
        "initial": {"omega": [0.1, 1.0, 0.2], "euler": [0.1, 0.2, 0.3]},
        "time": {"end": 1.0, "points": 5},
        "output": {"want": ["omega", "attitude", "invariants"], "accuracy": 1e-6, **output}})


def _chunked_budget(scene, plan, members_per_chunk):
    e = cost.estimate(scene, plan)
    budget = e.output_bytes + e.per_member_working * members_per_chunk * cost.threads(plan)
    assert cost.check(scene, plan, memory=budget).chunk < scene.batch
    return budget


def _same(a, b):
    for name in ("omega", "attitude", "gamma", "euler_angles"):
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None and y is None) or np.array_equal(x, y), name
    assert a.invariants.keys() == b.invariants.keys()
    for name in a.invariants:
        assert np.array_equal(a.invariants[name], b.invariants[name]), name
    assert a.drift == b.drift and a.notes == b.notes


def test_a_chunked_model_sweep_equals_the_single_pass_member_for_member(cache):
    """The model's own kernel by batched DOP853 (members step in groups of 4096): 2 chunks = 1 pass, bit for bit."""
    scene = _damped(4096 + 7)
    whole = simulate(scene)
    assert whole.plan.engine == "integrate: batched DOP853 on model damped"
    chunked = simulate(scene, memory=_chunked_budget(scene, whole.plan, 4096))
    _same(whole, chunked)
    one = simulate(_damped(1))
    assert np.max(np.abs(chunked.omega[0] - one.omega)) < 1e-5  # member 0 (c = 0) is the single run


def _lagrange(*want, spins=None):
    from importlib import resources

    base = Scene.from_toml(str(resources.files("eulersym.models") / "lagrange-top.toml")).model.to_dict()
    spin = 150.0 if spins is None else {"start": 120.0, "stop": 150.0, "num": spins}
    return Scene.from_dict({**base, "parameters": {**base["parameters"], "l": [0.02, 0.03, 0.04, 0.05], "M": [0.4, 0.5]},
                            "initial": {"euler": [0.0, 0.5, 0.0], "omega": [0.0, 0.0, spin]},
                            "time": {"end": 0.2, "points": 21}, "output": {"want": list(want)}})


def test_a_chunked_heavy_top_model_sweep_equals_the_single_pass(cache):
    """A Lagrange top written as a model takes the closed form in its frame: chunks of one block of members (the
    closed form's grain, 1024), same bits; its summaries are the reductions of the trajectories."""
    scene = _lagrange("omega", "euler_angles", "invariants", spins=300)
    whole = simulate(scene)
    assert whole.plan.engine.startswith("closed form") and whole.omega.shape == (2400, 21, 3)
    grain = cost.method_cost(whole.plan).grain
    _same(whole, simulate(scene, memory=_chunked_budget(scene, whole.plan, grain)))
    scene = _lagrange("omega", "euler_angles", "invariants")
    whole = simulate(scene)
    summary = simulate(_lagrange("summary", "omega"))
    assert summary.omega is None
    assert np.array_equal(summary.summary["omega3.max"], whole.omega[:, :, 2].max(axis=1))
    assert np.array_equal(summary.summary["gamma3.final"], whole.gamma[:, -1, 2])


def test_a_streamed_model_sweep_holds_its_outputs_and_a_chunk(cache):
    """Peak traced memory of a model sweep in 3 chunks: near the estimate (outputs + the chunks in flight), well
    below what the single pass would hold."""
    scene = _damped(3 * 4096, want=["summary"])
    simulate(_damped(5, want=["summary"]))  # the kernel, imports: not the sweep's memory
    plan = scene.plan()
    budget = _chunked_budget(scene, plan, 4096)
    e = cost.check(scene, plan, memory=budget)
    whole = cost.estimate(scene, plan, chunk=scene.batch)
    tracemalloc.start()
    try:
        result = simulate(scene, memory=budget)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert e.chunk == 4096 and result.summary["omega1.final"].shape == (scene.batch,)
    assert e.peak_bytes / 3 < peak < 3 * e.peak_bytes, (peak, str(e))
    assert peak < whole.peak_bytes / 2, (peak, str(whole))


def test_a_model_kernel_travels_by_its_path(cache):
    from eulersym.scene import model_kernel

    scene = _damped(3)
    simulate(scene)
    module, path, emitted = model_kernel.ensure(scene.model, [])
    kernel = model_kernel.kernel(scene.model, module, path, emitted, scene.parameter_values(), scene.batch)
    back = pickle.loads(pickle.dumps(kernel.take(1, 3)))
    assert not emitted and back.module is kernel.module and back.params[0].tolist() == kernel.params[0][1:].tolist()


def test_a_model_sweep_on_dask_workers_is_the_in_process_one(cache):
    pytest.importorskip("distributed")
    from eulersym.sweeps import distributed

    scene = _damped(6)
    local = simulate(scene)
    client = distributed.local_client(2, processes=False)
    try:
        remote = simulate(scene, client=client)
    finally:
        distributed.close(client)
    assert np.array_equal(local.omega, remote.omega) and np.array_equal(local.gamma, remote.gamma)


# ---- the heavy top's closed form and the upright top's separatrix --------------------------------------------------


def _euler_poisson(I1, I3, mgl):
    def rhs(t, y):
        w, g = y[:3], y[3:6]
        I = np.array([I1, I1, I3])
        torque = mgl * np.cross(g, [0.0, 0.0, 1.0])
        return np.concatenate([(np.cross(I * w, w) + torque) / I, np.cross(g, w)])

    return rhs


@pytest.mark.parametrize("outputs", [("omega", "invariants"), ("summary",)])
def test_a_sweep_member_on_the_separatrix_is_integrated_and_reported(outputs):
    """Upright, below the sleeping threshold, ω⊥ = 1e-80: the closed form has no period there (m_c < 1e-150). The
    sweep completes, the member comes from DOP853 (checked against the test's own Euler–Poisson integration), the
    others keep the closed form bit for bit, and the report names the member and why."""
    kw = dict(moments=(1.0, 1.0, 1.0), mass=1.0, l=0.3, g=9.81, euler=(0.0, 0.0, 0.0), t_end=2.0, points=9,
              accuracy=1e-10, outputs=outputs)
    swept = simulate(Scene(**kw, omega=([0.5, 1e-80, 0.3], 0.0, 3.0)))
    note = [n for n in swept.notes if "singular for the closed form" in n]
    assert len(note) == 1 and "1 of 3 members (member 1)" in note[0] and "separatrix" in note[0]  # today's closed
    assert "DOP853" in note[0]  # form refuses it (eulersym.numerics.heavy_top_exact: m_c below 1e-150)
    if "summary" in outputs:
        assert all(np.all(np.isfinite(v)) for v in swept.summary.values())
        return
    assert np.all(np.isfinite(swept.omega)) and np.all(np.isfinite(swept.gamma))
    for k, w1 in ((0, 0.5), (2, 0.3)):
        alone = simulate(Scene(**kw, omega=(w1, 0.0, 3.0)))
        assert np.array_equal(swept.omega[k], alone.omega) and not any("singular" in n for n in alone.notes)
    ref = solve_ivp(_euler_poisson(1.0, 1.0, 9.81 * 0.3), (0, 2.0), [1e-80, 0, 3.0, 0, 0, 1.0], t_eval=swept.t,
                    method="DOP853", rtol=1e-12, atol=1e-95)
    assert np.allclose(swept.omega[1], ref.y[:3].T, rtol=1e-8, atol=1e-90)
    assert np.allclose(swept.gamma[1], ref.y[3:].T, rtol=1e-8, atol=1e-12)
    assert swept.drift["energy"] < 1e-8


def test_a_single_start_on_the_separatrix_is_integrated_too():
    r = simulate(Scene(moments=(1.0, 1.0, 1.0), mass=1.0, l=0.3, euler=(0.0, 0.0, 0.0), omega=(1e-100, 0.0, 3.0),
                       t_end=1.0, points=5))
    assert np.all(np.isfinite(r.omega)) and any("1 of 1 members (member 0)" in n for n in r.notes)
    assert r.n_rhs_calls > 0 and np.allclose(r.omega[:, 2], 3.0)


def test_a_chunked_sweep_reports_the_singular_members_of_every_chunk():
    kw = dict(moments=(1.0, 1.0, 1.0), mass=1.0, l=0.3, euler=(0.0, 0.0, 0.0), t_end=1.0, points=5)
    spins = np.linspace(0.1, 0.5, 2100)
    spins[[1, 1500]] = 1e-80, 1e-90  # one in each chunk of 1024 (the closed form's grain)
    scene = Scene(**kw, omega=(spins.tolist(), 0.0, 3.0))
    whole = simulate(scene)
    e = cost.estimate(scene, whole.plan)
    grain = cost.method_cost(whole.plan).grain
    budget = e.output_bytes + e.per_member_working * grain * cost.threads(whole.plan)
    assert cost.estimate(scene, whole.plan, memory=budget).chunk < scene.batch
    chunked = simulate(scene, memory=budget)
    assert np.array_equal(whole.omega, chunked.omega) and whole.notes == chunked.notes
    assert any("2 of 2100 members (members 1, 1500)" in n for n in whole.notes)
    # the estimate of the members integrated instead, 0 for those of the closed form: the same in every chunk
    assert set(whole.error) >= {"omega"} and np.flatnonzero(whole.error["omega"]).tolist() == [1, 1500]
    assert whole.error.keys() == chunked.error.keys()
    assert all(np.array_equal(whole.error[k], chunked.error[k]) for k in whole.error)


def test_only_the_members_the_closed_form_refuses_are_integrated(monkeypatch):
    """The mechanism, whatever the closed form refuses: an engine that refuses members with ω1 = 0.25 (as the
    heavy top's does at the separatrix) leaves those to DOP853, the others bit for bit its own, in order."""
    from eulersym.errors import SingularConfiguration
    from eulersym.numerics.methods import LagrangeTopClosedForm

    original = LagrangeTopClosedForm.run

    def picky(self, problem, *, progress=None):
        if np.any(problem.omega0[:, 0] == 0.25):
            raise SingularConfiguration("omega0", problem.omega0.tolist(), "a start the closed form can represent")
        return original(self, problem, progress=progress)

    kw = dict(moments=(1.0, 1.0, 0.5), mass=1.0, l=0.1, euler=(0.0, 0.4, 0.0), t_end=0.5, points=6, accuracy=1e-10)
    values = [0.1, 0.25, 0.2, 0.3, 0.25, 0.0, 0.25]
    scene = Scene(**kw, omega=(values, 0.0, 20.0))
    clean = simulate(scene)
    assert not any("singular" in n for n in clean.notes) and clean.n_rhs_calls == 0
    monkeypatch.setattr(LagrangeTopClosedForm, "run", picky)
    mixed = simulate(scene)  # (chunks are multiples of the closed form's blocks of 1024 members: the test above)
    for r in (mixed,):
        assert any("3 of 7 members (members 1, 4, 6)" in n for n in r.notes) and r.n_rhs_calls > 0
        for k, w1 in enumerate(values):
            if w1 == 0.25:  # DOP853 at rtol 1e-11 against the exact motion
                assert np.allclose(r.omega[k], clean.omega[k], rtol=0, atol=1e-8) and not np.array_equal(
                    r.omega[k], clean.omega[k])
            else:
                assert np.array_equal(r.omega[k], clean.omega[k]) and np.array_equal(r.gamma[k], clean.gamma[k])
