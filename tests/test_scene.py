"""Tests of eulersym.scene: validation, the pure plan, the runs, sweeps, the command line and bundled scenes."""

from __future__ import annotations

import importlib
import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from eulersym.errors import InvalidInput
from eulersym.scene import OUTPUTS, Plan, Result, Scene, Sweep, bundled, load, simulate
from eulersym.numerics.methods._batched_dop853 import dop853_batched
from eulersym.scene.frames import quaternion_to_rotation, rotate_to_body, rotation_to_quaternion
from eulersym.scene.io import _atomic, save
from eulersym.scene.plan import classify_moments, heavy_top_frame, make_plan

BUNDLED = ("tennis-racket", "symmetric-precession", "heavy-top-nutation", "sleeping-top-above", "sleeping-top-below", "cube-diagonal")


FREE = dict(moments=(1.0, 2.0, 3.0), omega=(0.1, 1.0, 0.2), t_end=5.0, points=101)
TOP = dict(moments=(1.2e-3, 1.2e-3, 4e-4), mass=0.5, l=0.04, euler=(0.0, 0.5, 0.0), omega=(0.0, 0.0, 150.0), t_end=0.3, points=301)


def _euler_rhs(I, N=(0.0, 0.0, 0.0)):
    """Euler's equations written out independently of eulersym (a test oracle): I ω̇ = (Iω) × ω + N."""
    I = np.asarray(I, dtype=float)

    def rhs(t, w):
        return (np.cross(I * w, w) + N) / I

    return rhs


# ---- construction and validation ------------------------------------------------------------------------------


def test_scene_is_frozen_and_normalised():
    import dataclasses
    import pickle

    scene = Scene(**FREE)
    assert scene.moments == (1.0, 2.0, 3.0) and scene.outputs == ("omega", "invariants")
    with pytest.raises(AttributeError):
        scene.t_end = 3.0  # type: ignore[misc]
    assert Scene(**FREE) == scene and hash(Scene(**FREE)) == hash(scene)
    assert dataclasses.replace(scene, t_end=2.0).t_end == 2.0  # replace() re-validates
    with pytest.raises(InvalidInput):
        dataclasses.replace(scene, t_end=-2.0)
    assert pickle.loads(pickle.dumps(scene)) == scene
    assert hash(scene.plan()) == hash(scene.plan())


@pytest.mark.parametrize(
    "kwargs, argument, fragment",
    [
        ({**FREE, "t_edn": 1}, "t_edn", "did you mean 't_end'"),
        ({**FREE, "outputs": ("omega", "atitude")}, "outputs", "did you mean 'attitude'"),
        ({k: v for k, v in FREE.items() if k != "omega"}, "omega", "initial angular velocity"),
        ({k: v for k, v in FREE.items() if k != "t_end"}, "t_end", "end time"),
        ({k: v for k, v in FREE.items() if k != "moments"}, "moments", "a body"),
        ({**FREE, "moments": (1.0, 1.0, 3.0)}, "moments", "I1 + I2 >= I3"),
        ({**FREE, "moments": (1.0, -2.0, 3.0)}, "moments", "positive"),
        ({**FREE, "t_end": 0.0}, "t_end", "t_end > 0"),
        ({**FREE, "t_end": -1.0}, "t_end", "t_end > 0"),
        ({**FREE, "omega": (float("nan"), 1.0, 0.0)}, "omega[0]", "finite"),
        ({**FREE, "omega": (0.0, float("inf"), 0.0)}, "omega[1]", "finite"),
        ({**FREE, "omega": (0.0, 1.0)}, "omega", "3 numbers"),
        ({**FREE, "accuracy": 1e-20}, "accuracy", "between"),
        ({**FREE, "method": "rk4"}, "method", "one of"),
        ({**FREE, "convention": "zzz"}, "convention", "one of"),
        ({**FREE, "points": 1}, "points", "points"),
        ({**FREE, "tensor": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}, "tensor", "only one body"),
        ({**{k: v for k, v in FREE.items() if k != "moments"}, "tensor": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]}, "tensor", "symmetric"),
        ({**{k: v for k, v in FREE.items() if k != "moments"}, "shape": "cube", "mass": 1, "dimensions": {"b": 1}}, "dimensions.b", "one of 'a'"),
        ({**{k: v for k, v in FREE.items() if k != "moments"}, "shape": "cub", "mass": 1}, "shape", "did you mean 'cube'"),
        ({**{k: v for k, v in FREE.items() if k != "moments"}, "shape": "cube", "dimensions": {"a": 1}}, "mass", "mass"),
        ({**FREE, "l": 0.1}, "mass", "M g l"),
        ({**FREE, "axis": (0, 0, 1)}, "angle", "axis and angle"),
        ({**FREE, "quaternion": (0, 0, 0, 0)}, "quaternion", "non-zero"),
        ({**TOP, "moments": (1.2e-3, 1.1e-3, 4e-4), "method": "closed-form"}, "method", "I1 ≠ I2"),
        ({**FREE, "torque": (0, 0, 1), "method": "closed-form"}, "method", "no closed form"),
        ({**FREE, "torque": (0, 0, 1), "method": "splitting"}, "method", "no splitting"),
    ],
)
def test_bad_input_names_the_key(kwargs, argument, fragment):
    with pytest.raises(InvalidInput) as info:
        Scene(**kwargs)
    assert info.value.argument == argument
    assert fragment in str(info.value)


@settings(max_examples=40, deadline=None)
@given(
    key=st.sampled_from(["omega", "moments", "euler"]),
    index=st.integers(0, 2),
    bad=st.sampled_from([float("nan"), float("inf"), -float("inf"), "1.0", None, True]),
)
def test_property_any_non_number_is_refused_by_name(key, index, bad):
    kwargs = {**FREE, "euler": (0.1, 0.2, 0.3)}
    vector = list(kwargs[key])
    vector[index] = bad
    kwargs[key] = tuple(vector)
    with pytest.raises(InvalidInput) as info:
        Scene(**kwargs)
    assert info.value.argument.startswith(key)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(0.01, 10.0), min_size=3, max_size=3))
def test_property_moments_accepted_iff_a_body(moments):
    a, b, c = moments
    body = a + b >= c * (1 - 1e-12) and b + c >= a * (1 - 1e-12) and c + a >= b * (1 - 1e-12)
    try:
        Scene(**{**FREE, "moments": tuple(moments)})
        accepted = True
    except InvalidInput as exc:
        accepted = False
        assert exc.argument == "moments"
    assert accepted == body


# ---- TOML ---------------------------------------------------------------------------------------------------


def _write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_toml_round_trip(tmp_path):
    path = _write(tmp_path, """
        name = "demo"
        [body]
        moments = [1, 2, 3]
        [initial]
        omega_space = [0, 1, 0]
        euler = [0.1, 0.2, 0.3]
        [time]
        end = 2
        points = 11
        [output]
        want = ["omega", "attitude"]
        accuracy = 1e-6
    """)
    scene = Scene.from_toml(path)
    assert scene == Scene(name="demo", moments=(1, 2, 3), omega=(0, 1, 0), omega_frame="space", euler=(0.1, 0.2, 0.3),
                          t_end=2, points=11, outputs=("omega", "attitude"), accuracy=1e-6)


@pytest.mark.parametrize(
    "text, argument, fragment",
    [
        ("[body]\nmoments = [1, 2, 3]\n[intial]\nomega = [1, 0, 0]\n", "intial", "did you mean 'initial'"),
        ("[body]\nmoment = [1, 2, 3]\n", "body.moment", "did you mean 'moments'"),
        ("[body]\nmoments = [1, 2, 3]\n[initial]\nomega = [1, 0, 0]\n[time]\nend = -1\n", "time.end", "t_end > 0"),
        ("[body]\nmoments = [1, 2, 3]\n[initial]\nomega = [1, nan, 0]\n[time]\nend = 1\n", "initial.omega[1]", "finite"),
        ("[body]\nmoments = [1, 2, 3]\n[initial]\nomega = [1, 0, 0]\n", "time.end", "end time"),
        ("[body]\nmoments = [1, 2, 3]\nmass = 1\n[pivot]\ng = 9.81\n", "pivot.centre_of_mass", "or l = "),
        ("[body]\nmoments = [1, 2, 3]\n[pivot]\nl = 0.1\n[initial]\nomega = [1, 0, 0]\n[time]\nend = 1\n", "body.mass", "M g l"),
        ("[body]\nmoments = [1, 2, 3\n", "SCENE", "valid TOML"),
    ],
)
def test_toml_bad_input(tmp_path, text, argument, fragment):
    with pytest.raises(InvalidInput) as info:
        Scene.from_toml(_write(tmp_path, text))
    assert info.value.argument == argument, str(info.value)
    assert fragment in str(info.value)


_VALUES = st.one_of(
    st.none(), st.booleans(), st.integers(-3, 5), st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=5),
    st.lists(st.one_of(st.floats(-2, 2), st.integers(-2, 3), st.text(max_size=2)), max_size=4),
    st.dictionaries(st.sampled_from(["start", "stop", "num", "x"]), st.integers(-1, 3), max_size=3),
)


@settings(max_examples=150, deadline=None)
@given(st.dictionaries(
    st.sampled_from(["name", "body", "pivot", "torque", "initial", "time", "output", "extra"]),
    st.one_of(_VALUES, st.dictionaries(
        st.sampled_from(["moments", "tensor", "shape", "mass", "a", "R", "h", "origin", "l", "g", "body", "space",
                         "omega", "omega_space", "euler", "convention", "quaternion", "axis", "angle", "end",
                         "points", "want", "accuracy", "method", "zzz"]),
        _VALUES, max_size=6)),
    max_size=7))
def test_property_any_mapping_gives_a_scene_or_invalid_input(data):
    """Whatever a TOML file holds, the result is a Scene or an InvalidInput that names a key — never another error."""
    try:
        scene = Scene.from_dict(data)
    except InvalidInput as exc:
        assert exc.argument and str(exc)
    else:
        assert isinstance(scene.plan(), Plan)


def test_missing_file_and_unknown_name():
    with pytest.raises(InvalidInput, match="bundled scene"):
        Scene.from_toml("/nonexistent/scene.toml")
    with pytest.raises(InvalidInput, match="did you mean 'tennis-racket'"):
        load("tennis-rackett")


@pytest.mark.parametrize("name", BUNDLED)
def test_bundled_scenes_load_and_plan(name):
    assert name in bundled()
    scene = load(name)
    assert scene.name == name and scene.description
    plan = scene.plan()
    assert isinstance(plan, Plan) and plan.steps
    expected = {"tennis-racket": "torque-free", "symmetric-precession": "torque-free", "cube-diagonal": "torque-free"}
    assert plan.regime == expected.get(name, "heavy top")


def test_sleeping_scenes_straddle_the_threshold():
    """The two sleeping-top scenes sit just above and just below 4MglI1/I3² (bound computed here, independently)."""
    ratios = {}
    for name in ("sleeping-top-above", "sleeping-top-below"):
        s = load(name)
        I1, _, I3 = s.moments
        ratios[name] = s.omega[2] ** 2 / (4 * s.mass * s.g * s.l * I1 / I3**2)
    assert 1.0 < ratios["sleeping-top-above"] < 1.1
    assert 0.9 < ratios["sleeping-top-below"] < 1.0


# ---- the plan (pure) ------------------------------------------------------------------------------------------


def test_classify_moments():
    assert classify_moments((1, 2, 3)) == "asymmetric"
    assert classify_moments((2, 1, 2)) == "symmetric"
    assert classify_moments((3, 3, 3)) == "spherical"
    assert classify_moments([(1, 2, 3), (2, 2, 1)]) == "mixed"


@settings(max_examples=200, deadline=None)
@given(st.tuples(*[st.sampled_from([1.0, 1.0 + 1e-13, 1.0 + 1e-9, 2.0, 0.5, 3.0])] * 3))
def test_classify_one_body_as_rows(m):
    """One body's comparisons on floats agree with the rows' (two equal rows: the array path)."""
    assert classify_moments(m) == classify_moments([m, m])


def test_plan_torque_free_omega_only_is_closed_form_and_skips_top_and_attitude():
    plan = Scene(**{**FREE, "outputs": ("omega",)}).plan()
    assert plan.engine == "closed form: elliptic"
    assert plan.derive == () and plan.kernels == () and plan.propagate == ("omega",)
    skipped = " ".join(s.what for s in plan.skipped)
    assert "heavy top" in skipped and "attitude propagation" in skipped and "integration" in skipped
    assert all(s.reason for s in plan.steps + plan.skipped)


def test_plan_symmetric_and_spherical_closed_forms():
    assert Scene(**{**FREE, "moments": (2, 2, 1)}).plan().engine == "closed form: trigonometric"
    assert Scene(**{**FREE, "moments": (1, 1, 1)}).plan().engine == "closed form: constant"
    plan = Scene(**{**FREE, "moments": (2, 2, 1), "outputs": ("attitude",)}).plan()
    assert plan.propagate == ("omega", "attitude") and plan.options["call"] == "free_rigid_body_attitude_exact"
    assert plan.method == "free_rigid_body_attitude_exact" and plan.options["engine"] == "free_body_exact"


def test_plan_heavy_top_closed_form_or_the_integrator_asked_for():
    for accuracy in (1e-4, 1e-10):  # a symmetric heavy top: the closed form, at any accuracy (issue 11)
        plan = Scene(**TOP, accuracy=accuracy).plan()
        assert plan.engine == "closed form: elliptic (Lagrange top)" and plan.kernels == ()
        assert plan.options["engine"] == "heavy_top_exact"
        assert any(s.what == "integration" for s in plan.skipped)
    tight = Scene(**TOP, accuracy=1e-10, method="DOP853").plan()
    assert tight.engine == "integrate: DOP853 on heavy_top_euler_poisson"
    assert any(s.what == "closed form" and "'DOP853' asked for" in s.reason for s in tight.skipped)
    loose = Scene(**TOP, accuracy=1e-4, method="splitting").plan()
    assert loose.engine.startswith("integrate: splitting")
    asym = Scene(**{**TOP, "moments": (1.2e-3, 1.1e-3, 4e-4)}, accuracy=1e-4).plan()
    assert "DOP853" in asym.engine  # neither the closed form nor the symmetric-top splitting applies
    assert any(s.what == "closed form" and "I1 ≠ I2" in s.reason for s in asym.skipped)
    assert "gamma" in tight.propagate and "attitude" in tight.propagate
    assert any("heavy_top_euler_angles" in s.what for s in tight.skipped)


def test_plan_heavy_top_upright_start_derives_threshold():
    assert "top.sleeping_top_threshold" in Scene(**{**TOP, "euler": (0, 0.01, 0)}).plan().derive
    assert "top.sleeping_top_threshold" not in Scene(**TOP).plan().derive


def test_plan_torque():
    body = Scene(**{**FREE, "torque": (0, 0, 0.1), "outputs": ("omega",)}).plan()
    assert body.regime == "torque" and body.propagate == ("omega",) and body.kernels == ("euler_principal",)
    space = Scene(**{**FREE, "torque": (0, 0, 0.1), "torque_frame": "space", "outputs": ("omega",)}).plan()
    assert space.propagate == ("omega", "attitude") and "free_body_quaternion" in space.kernels
    # invariants of a torqued body: none is conserved, and the plan says so (no silent empty output)
    torqued = Scene(**{**FREE, "torque": (0, 0, 1), "outputs": ("omega", "invariants")}).plan()
    assert any(s.what == "invariants and their drift" and "conserves neither" in s.reason for s in torqued.steps)
    # a polhode needs N = 0: skipped, with the reason
    top = Scene(**TOP, outputs=("omega", "polhode")).plan()
    assert any(s.what == "polhode" and "torque-free" in s.reason for s in top.skipped)


def test_plan_shape_takes_the_committed_closed_form_and_resolves():
    """A named shape's tensor is the closed form eulersym.inertia derived, committed: nothing to derive at run time;
    the plan knows the body at once (about its corner, no pivot: held there, weightless)."""
    scene = Scene(shape="cube", mass=1, dimensions={"a": 1}, origin="corner", omega=(1, 1, 1), t_end=1)
    plan = scene.plan()
    assert plan.derive == () and plan.body == "symmetric" and plan.engine == "closed form: trigonometric"
    assert [s.what for s in plan.steps[:2]] == ["inertia tensor of the cube", "principal axes"]
    assert sorted(make_plan(scene).steps, key=str) == sorted(plan.steps, key=str)


def test_plan_gravity_without_pivot_is_torque_free():
    assert Scene(**FREE, mass=1.0, g=9.81).regime == "torque-free"
    assert Scene(**{**TOP, "l": 0.0}).regime == "torque-free"
    assert Scene(**{**TOP, "g": 0.0}).regime == "torque-free"


def test_heavy_top_frame_diagonalises_about_e3(rng):
    a = rng.uniform(0, np.pi)
    Rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    tensor = Rz @ np.diag([2.0, 3.0, 4.0]) @ Rz.T
    moments, P = heavy_top_frame(tensor)
    assert np.allclose(P.T @ tensor @ P, np.diag(moments), atol=1e-14)
    assert sorted(moments[:2]) == pytest.approx([2.0, 3.0]) and moments[2] == pytest.approx(4.0)
    assert np.linalg.det(P) == pytest.approx(1.0)
    with pytest.raises(InvalidInput, match="I13 = I23 = 0"):
        heavy_top_frame([[2, 0, 0.5], [0, 2, 0], [0.5, 0, 1]])


@settings(max_examples=60, deadline=None)
@given(
    moments=st.sampled_from([(1.0, 2.0, 3.0), (2.0, 2.0, 1.0), (1.0, 1.0, 1.0)]),
    outputs=st.lists(st.sampled_from(OUTPUTS), min_size=1, max_size=5, unique=True),
    heavy=st.booleans(),
    accuracy=st.sampled_from([1e-4, 1e-8, 1e-12]),
)
def test_property_plan_is_consistent(moments, outputs, heavy, accuracy):
    """Every plan gives a reason for each step; a torque-free plan never touches the top and propagates the
    attitude exactly when an output needs it; a heavy top has its closed form exactly when it is symmetric."""
    kwargs = {**FREE, "moments": moments, "outputs": tuple(outputs), "accuracy": accuracy}
    if heavy:
        kwargs.update(mass=1.0, l=0.1)
    plan = Scene(**kwargs).plan()
    if heavy and "polhode" in outputs:
        assert any(s.what == "polhode" for s in plan.skipped)
    assert all(step.reason for step in plan.steps + plan.skipped)
    if heavy:
        symmetric = moments[0] == moments[1]
        assert plan.regime == "heavy top" and plan.engine.startswith("closed form") == symmetric
        assert plan.kernels == (() if symmetric else ("heavy_top_euler_poisson",))
    else:
        wants = bool({"attitude", "euler_angles"} & set(outputs))
        assert plan.engine.startswith("closed form") and plan.kernels == ()
        assert ("attitude" in plan.propagate) == wants
        assert not any(d.startswith("top.") for d in plan.derive)


# ---- sweeps -----------------------------------------------------------------------------------------------------


def test_sweep_grid_and_ranges():
    scene = Scene(**{**TOP, "omega": (0, 0, {"start": 60, "stop": 90, "num": 4}), "euler": (0, [0.01, 0.02], 0)})
    assert scene.batch == 8
    members = scene.members()
    assert members["omega[2]"].tolist() == [60, 70, 80, 90, 60, 70, 80, 90]
    assert members["euler[1]"].tolist() == [0.01] * 4 + [0.02] * 4
    assert "sweep of 8 members" in str(scene.plan())
    with pytest.raises(InvalidInput, match="did you mean 'stop'"):
        Sweep.of("omega[2]", {"start": 1, "stpo": 2, "num": 3})
    with pytest.raises(InvalidInput, match="cannot be swept"):
        Scene(**{**FREE, "t_end": [1, 2]})


def test_sweep_validates_every_member():
    with pytest.raises(InvalidInput):
        Scene(**{**FREE, "moments": (1.0, 2.0, [2.5, 3.5])})  # 1 + 2 < 3.5


# ---- pure numeric helpers -------------------------------------------------------------------------------------


def test_dop853_batched_matches_solve_ivp(rng):
    """Harmonic oscillators with different frequencies in one pass agree with solve_ivp DOP853 and the exact cos."""
    w = rng.uniform(0.5, 3.0, size=5)
    y0 = np.vstack([np.ones(5), np.zeros(5)])
    t = np.linspace(0, 10, 51)
    Y, calls = dop853_batched(lambda tt, y, w2: np.vstack([y[1], -w2 * y[0]]), y0, t, params=(w**2,), rtol=1e-10, atol=1e-12, chunk=2)
    assert Y.shape == (51, 2, 5) and calls > 0
    assert np.max(np.abs(Y[:, 0, :] - np.cos(np.outer(t, w)))) < 1e-8
    ref = solve_ivp(lambda tt, y: [y[1], -w[0] ** 2 * y[0]], (0, 10), [1, 0], method="DOP853", t_eval=t, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(ref.y[0] - Y[:, 0, 0])) < 1e-8


def test_dop853_batched_empty_batch():
    Y, _ = dop853_batched(lambda tt, y: -y, np.zeros((2, 0)), np.array([0.0, 1.0]), rtol=1e-8, atol=1e-10)
    assert Y.shape == (2, 2, 0)


def test_quaternion_helpers_agree_with_scipy(rng):
    rot = Rotation.random(20, random_state=np.random.default_rng(7))
    q = rotation_to_quaternion(rot)
    assert np.all(q[:, 0] >= 0) and np.allclose(np.linalg.norm(q, axis=1), 1)
    assert np.allclose(quaternion_to_rotation(q).as_matrix(), rot.as_matrix(), atol=1e-14)
    v = rng.normal(size=(3, 20))
    expected = np.einsum("bji,jb->ib", rot.as_matrix(), v)  # R(q)ᵀ v per column
    assert np.allclose(rotate_to_body(q.T, v), expected, atol=1e-13)


def test_progress_bar_only_when_enabled():
    import io

    from eulersym.scene.progress import Progress

    quiet, loud = io.StringIO(), io.StringIO()
    for stream, enabled in ((quiet, False), (loud, True)):
        bar = Progress("demo", enabled=enabled, stream=stream)
        bar.fraction(0.5)
        bar.fraction(1.0)
        bar.done()
    assert quiet.getvalue() == "" and "100.0%" in loud.getvalue()


def test_atomic_write_leaves_nothing_on_error(tmp_path):
    target = tmp_path / "out.npz"

    def failing(tmp):
        with open(tmp, "w") as handle:
            handle.write("partial")
        raise RuntimeError("boom")

    with pytest.raises(RuntimeError):
        _atomic(str(target), failing)
    assert list(tmp_path.iterdir()) == []


# ---- the command line (pure paths) ---------------------------------------------------------------------------


def _main(*argv):
    from eulersym.cli import main

    return main(["simulate", *argv])


def test_cli_list_and_explain(capsys):
    assert _main("--list") == 0
    out = capsys.readouterr().out
    for name in BUNDLED:
        assert name in out
    assert _main("tennis-racket", "--explain") == 0
    out = capsys.readouterr().out
    assert "closed form" in out and "skip" in out and "heavy top" in out


def test_cli_bad_input_exits_2_and_writes_nothing(tmp_path, capsys):
    bad = _write(tmp_path, "[body]\nmoments = [1, 1, 3]\n[initial]\nomega = [1, 0, 0]\n[time]\nend = 1\n")
    out = tmp_path / "out.npz"
    assert _main(str(bad), "-o", str(out)) == 2
    assert "body.moments" in capsys.readouterr().err
    assert _main("no-such-scene") == 2
    assert _main("tennis-racket", "-o", str(tmp_path / "out.txt")) == 2
    assert _main("tennis-racket", "-o", str(tmp_path / "missing" / "out.npz")) == 2
    assert _main("tennis-racket", "--bogus") == 2
    assert _main() == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]


def test_cli_plot_without_matplotlib_says_so(tmp_path, capsys, monkeypatch):
    real_find_spec = importlib.util.find_spec  # matplotlib is installed (the test extra): hide it from the check
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a, **k: None if name.split(".")[0] == "matplotlib" else real_find_spec(name, *a, **k))
    assert _main("tennis-racket", "--plot", str(tmp_path / "p.png")) == 2
    assert "eulersym[plot]" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


# ---- runs (need numerics and kernels) --------------------------------------------------------------------------


def test_torque_free_omega_only_matches_independent_integration_and_propagates_no_attitude(monkeypatch):
    numerics = importlib.import_module("eulersym.numerics")

    def forbidden(*args, **kwargs):
        raise AssertionError("an ω-only scene must not propagate the attitude")

    monkeypatch.setattr(numerics, "free_rigid_body_attitude_exact", forbidden)
    scene = Scene(**{**FREE, "outputs": ("omega", "invariants")})
    result = simulate(scene)
    assert isinstance(result, Result)
    assert result.attitude is None and result.propagated == ("omega",) and result.n_rhs_calls == 0
    assert result.derivations == ()
    ref = solve_ivp(_euler_rhs(FREE["moments"]), (0, FREE["t_end"]), FREE["omega"], t_eval=result.t, rtol=1e-12, atol=1e-14, method="DOP853")
    assert np.max(np.abs(result.omega - ref.y.T)) < 1e-9
    assert result.drift["energy"] < 1e-12 and result.drift["L2"] < 1e-12


def test_asked_for_dop853_agrees_with_the_closed_form():
    exact = simulate(Scene(**{**FREE, "outputs": ("omega",)}))
    ivp = simulate(Scene(**{**FREE, "outputs": ("omega",), "method": "DOP853", "accuracy": 1e-11}))
    assert ivp.plan.engine == "integrate: DOP853 on euler_principal" and ivp.n_rhs_calls > 0
    assert np.max(np.abs(ivp.omega - exact.omega)) < 1e-8
    swept = simulate(Scene(**{**FREE, "omega": (0.1, [1.0, 1.5], 0.2), "outputs": ("omega",), "method": "DOP853", "accuracy": 1e-11}))
    assert swept.plan.engine == "integrate: batched DOP853 on euler_principal"
    assert np.max(np.abs(swept.omega[0] - exact.omega)) < 1e-8


@pytest.mark.parametrize("method", ["splitting", "RK45", "Radau", "LSODA"])
def test_every_asked_for_method_meets_the_accuracy(method):
    exact = simulate(Scene(**FREE))
    r = simulate(Scene(**FREE, method=method, accuracy=1e-9))
    assert method in r.plan.engine or "splitting" in r.plan.engine
    assert np.max(np.abs(r.omega - exact.omega)) / np.max(np.abs(exact.omega)) < 1e-9
    assert r.drift["energy"] < 1e-8


def test_symmetric_closed_form_precesses_at_the_derived_rate():
    """ω⊥ turns at Ω = (I1 − I3)/I1 ω3: checked by the phase of ω1 + iω2 (the rate is recomputed here)."""
    I1, I3, w3 = 2.0, 1.0, 5.0
    result = simulate(Scene(moments=(I1, I1, I3), omega=(0.3, 0.0, w3), t_end=2.0, points=201, outputs=("omega",)))
    phase = np.unwrap(np.angle(result.omega[:, 0] + 1j * result.omega[:, 1]))
    slope = np.polyfit(result.t, phase, 1)[0]
    assert slope == pytest.approx(-(I1 - I3) / I1 * w3, rel=1e-10)
    assert np.allclose(result.omega[:, 2], w3, rtol=1e-13)


def test_attitude_outputs_and_euler_angles():
    scene = Scene(moments=(2.0, 2.0, 1.0), omega=(0.3, 0.0, 5.0), euler=(0.2, 0.5, 0.1), t_end=3.0, points=61,
                  outputs=("omega", "attitude", "euler_angles", "invariants"))
    r = simulate(scene)
    assert r.attitude.shape == (61, 4) and r.euler_angles.shape == (61, 3)
    assert np.allclose(np.linalg.norm(r.attitude, axis=1), 1, atol=1e-12)
    # the first attitude is the scene's start: A = R(q).T equals scipy's ZXZ matrix transposed
    assert np.allclose(quaternion_to_rotation(r.attitude[0]).as_matrix(), Rotation.from_euler("ZXZ", [0.2, 0.5, 0.1]).as_matrix(), atol=1e-12)
    assert np.allclose(r.euler_angles[0], [0.2, 0.5, 0.1], atol=1e-12)
    # the angles and the quaternions describe the same rotations
    back = Rotation.from_euler("ZXZ", r.euler_angles).as_matrix()
    assert np.allclose(back, quaternion_to_rotation(r.attitude).as_matrix(), atol=1e-10)
    assert r.drift["L_space_deviation"] < 1e-10
    # the convention agrees with eulersym.rotation's A = B(psi) C(theta) D(phi)
    from eulersym.rotation import euler_matrix

    A = np.array(euler_matrix(0.2, 0.5, 0.1), dtype=float)
    assert np.allclose(A, quaternion_to_rotation(r.attitude[0]).as_matrix().T, atol=1e-12)


def test_omega_in_space_components():
    rot = Rotation.from_euler("ZXZ", [0.3, 0.4, 0.5])
    w_space = np.array([0.2, -0.1, 1.0])
    a = simulate(Scene(moments=(1, 2, 3), omega=tuple(w_space), omega_frame="space", euler=(0.3, 0.4, 0.5), t_end=1, points=5, outputs=("omega",)))
    assert np.allclose(a.omega[0], rot.inv().apply(w_space), atol=1e-14)


def _subprocess(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=120)


def test_torque_free_run_imports_no_sympy_and_nothing_of_the_top():
    proc = _subprocess("""
        import sys
        sys.modules['sympy'] = None  # any import of SymPy now fails
        from eulersym.scene import Scene, simulate
        r = simulate(Scene(moments=(1.0, 2.0, 3.0), omega=(0.01, 1.0, 0.01), t_end=10.0, outputs=('omega', 'invariants')))
        assert r.derivations == (), r.derivations
        assert 'eulersym.top' not in sys.modules and 'eulersym.dynamics' not in sys.modules
        print('ok', r.omega.shape)
        # a tilted heavy top and a torqued body need no derivation either: no SymPy
        top = simulate(Scene(moments=(1.0, 1.0, 0.5), mass=1.0, l=0.1, euler=(0, 0.5, 0), omega=(0, 0, 20.0),
                             t_end=0.2, points=11, outputs=('omega', 'attitude', 'invariants')))
        torqued = simulate(Scene(moments=(1, 2, 3), torque=(0, 0, 1), torque_frame='space', omega=(0, 0, 1), t_end=1,
                                 points=11, outputs=('omega', 'attitude')))
        assert top.derivations == () and torqued.derivations == ()
        print('ok too')
    """)
    assert proc.returncode == 0, proc.stderr
    assert "ok (1001, 3)" in proc.stdout and "ok too" in proc.stdout


def test_heavy_top_conserves_invariants_and_nutates():
    r = simulate(Scene(**TOP, outputs=("omega", "euler_angles", "invariants"), accuracy=1e-10))
    assert r.plan.regime == "heavy top" and "gamma" in r.propagated
    # not near upright: no threshold; θ(t) asked: the turning points, the roots the closed form solved (no SymPy)
    assert r.plan.engine.startswith("closed form") and r.derivations == ()
    for name in ("energy", "gamma_norm2", "L_dot_gamma"):
        assert r.drift[name] < 1e-7, (name, r.drift[name])
    theta = r.euler_angles[:, 1]
    assert theta.min() == pytest.approx(0.5, abs=1e-6)  # released at rest in θ: θ1 is the start
    assert theta.max() > 0.5 + 1e-3  # and it nutates down to θ2
    assert np.allclose(np.cos(theta), r.gamma[:, 2], atol=1e-8)  # Γ3 = cos θ
    # the integrated θ(t) touches the turning points derived from the effective potential
    theta1, theta2 = r.turning_points
    assert theta1 == pytest.approx(theta.min(), abs=1e-6) and theta2 == pytest.approx(theta.max(), abs=1e-5)
    # the closed form's roots are eulersym.top's (the cubic's roots bracketed by its critical points, bisected)
    from eulersym.scene import symbolic

    record = []
    by_top = symbolic.turning_points(r.moments, TOP["mass"], 9.81, TOP["l"], r.omega[0], r.gamma[0], r.attitude[0], record)
    assert record == ["top.turning_points"] and np.allclose(r.turning_points, by_top, rtol=0, atol=1e-12)


def test_heavy_top_turning_points_integrated_are_derived():
    """An integrating plan has no closed form's roots: the turning points are derived by eulersym.top, and agree."""
    r = simulate(Scene(**TOP, outputs=("omega", "euler_angles"), accuracy=1e-10, method="DOP853"))
    closed = simulate(Scene(**TOP, outputs=("omega", "euler_angles"), accuracy=1e-10))
    assert "DOP853" in r.plan.engine and r.derivations == ("top.turning_points",) and "turning" not in r.plan.options
    assert closed.plan.options["turning"] == "closed form" and "turning points θ1, θ2" in str(closed.plan)
    # the Euler angles: the closed form's own (zxz), the integrator's from its quaternion
    assert "from the closed form's θ and φ ± ψ" in str(closed.plan) and "from the quaternion" not in str(closed.plan)
    assert "from the quaternion" in str(r.plan)
    zyz = simulate(Scene(**{**TOP, "euler": (0.0, 0.5, 0.0)}, convention="zyz", outputs=("euler_angles",), accuracy=1e-10))
    assert zyz.plan.engine.startswith("closed form") and "from the quaternion" in str(zyz.plan)
    assert np.allclose(r.turning_points, closed.turning_points, rtol=0, atol=1e-12)


def test_heavy_top_splitting_agrees_with_dop853():
    a = simulate(Scene(**TOP, outputs=("omega",), accuracy=1e-4, method="splitting"))
    b = simulate(Scene(**TOP, outputs=("omega",), accuracy=1e-10, method="DOP853"))
    assert a.plan.engine.startswith("integrate: splitting") and "DOP853" in b.plan.engine
    scale = np.max(np.abs(b.omega))
    assert np.max(np.abs(a.omega - b.omega)) / scale < 1e-2


def test_sleeping_tops_above_stay_and_below_fall():
    above = simulate(load("sleeping-top-above"))
    below = simulate(load("sleeping-top-below"))
    tilt = lambda r: np.degrees(np.arccos(np.clip(r.gamma[:, 2], -1, 1))).max()  # noqa: E731
    assert tilt(above) < 10 and tilt(below) > 15
    assert "top.sleeping_top_threshold" in above.derivations
    assert any("above" in n for n in above.notes) and any("below" in n for n in below.notes)


def test_sweep_equals_looped_single_runs():
    base = {**TOP, "t_end": 0.2, "points": 21, "accuracy": 1e-9, "outputs": ("omega",), "method": "DOP853"}
    sweep = simulate(Scene(**{**base, "omega": (0, 0, [100.0, 150.0]), "euler": (0, [0.3, 0.5], 0)}))
    assert sweep.omega.shape == (4, 21, 3) and "DOP853" in sweep.plan.engine  # batched, or compiled per member
    for b in range(4):
        w3, th = sweep.sweep["omega[2]"][b], sweep.sweep["euler[1]"][b]
        single = simulate(Scene(**{**base, "omega": (0, 0, w3), "euler": (0, th, 0)}))
        assert np.max(np.abs(single.omega - sweep.omega[b])) / w3 < 1e-6


def test_body_torque_spins_up_linearly_and_space_torque_follows_attitude():
    r = simulate(Scene(moments=(1, 1, 2), omega=(0, 0, 1), torque=(0, 0, 0.5), t_end=2, points=21, outputs=("omega",)))
    assert np.allclose(r.omega[:, 2], 1 + 0.25 * r.t, rtol=1e-7)  # I3 ω̇3 = N3 with ω1 = ω2 = 0
    assert r.attitude is None and r.propagated == ("omega",)
    s = simulate(Scene(moments=(1, 2, 2.5), omega=(0.1, 0.2, 0.3), torque=(0, 0, 0.2), torque_frame="space",
                       t_end=2, points=41, outputs=("omega", "attitude"), accuracy=1e-10))
    # independent truth: in space, dL/dt = N, so L_space(t) = L_space(0) + N t
    L_space = quaternion_to_rotation(s.attitude).apply(s.omega * np.array([1, 2, 2.5]))
    assert np.allclose(L_space - L_space[0], np.outer(s.t, [0, 0, 0.2]), atol=1e-7)


def test_full_tensor_maps_frames(rng):
    """A tensor Q diag(I) Qᵀ with ω and attitude in its body frame gives Q times the principal-frame answer."""
    Q = Rotation.random(random_state=np.random.default_rng(3)).as_matrix()
    I = np.array([1.0, 2.0, 3.0])
    w = rng.normal(size=3)
    tensor = Q @ np.diag(I) @ Q.T
    r = simulate(Scene(tensor=tensor.tolist(), omega=tuple(w), t_end=2, points=21, outputs=("omega", "attitude")))
    assert r.derivations == ()  # the principal axes by NumPy (eulersym.scene.regime.principal_axes)
    P = r.axes
    assert np.allclose(P.T @ tensor @ P, np.diag(r.moments), atol=1e-12)
    ref = simulate(Scene(moments=tuple(r.moments), omega=tuple(P.T @ w), quaternion=tuple(rotation_to_quaternion(Rotation.from_matrix(P))),
                         t_end=2, points=21, outputs=("omega", "attitude")))
    assert np.allclose(r.omega, ref.omega @ P.T, atol=1e-12)
    # the body's attitude: R_body = R_principal Pᵀ
    R_body = quaternion_to_rotation(r.attitude).as_matrix()
    assert np.allclose(R_body, quaternion_to_rotation(ref.attitude).as_matrix() @ P.T, atol=1e-12)


def test_full_tensor_with_a_body_torque_maps_the_torque():
    Q = Rotation.random(random_state=np.random.default_rng(5)).as_matrix()
    tensor = Q @ np.diag([1.0, 2.0, 2.5]) @ Q.T
    N, w = np.array([0.1, -0.2, 0.3]), np.array([0.3, 0.1, -0.2])
    r = simulate(Scene(tensor=tensor.tolist(), torque=tuple(N), omega=tuple(w), t_end=2, points=11, outputs=("omega",), accuracy=1e-11))
    ref = solve_ivp(lambda t, y: np.linalg.solve(tensor, np.cross(tensor @ y, y) + N), (0, 2), w, t_eval=r.t, rtol=1e-12, atol=1e-14)
    assert np.allclose(r.omega, ref.y.T, atol=1e-8)


def test_cube_diagonal_takes_its_tensor_and_keeps_omega_on_the_diagonal():
    r = simulate(load("cube-diagonal"))
    assert r.derivations == ()  # the cube's tensor: the committed closed form of eulersym.inertia's derivation
    assert not any(d.startswith("top.") for d in r.derivations)
    assert np.allclose(sorted(r.moments), [1 / 6, 11 / 12, 11 / 12], rtol=1e-12)
    k = int(np.argmin(r.moments))
    assert np.allclose(np.abs(r.axes[:, k]), np.ones(3) / np.sqrt(3), atol=1e-12)
    assert np.allclose(r.omega, [2.0, 2.0, 2.0], atol=1e-10)  # spin about a principal axis: steady
    assert r.plan.engine == "closed form: trigonometric"


@pytest.mark.parametrize("name", BUNDLED)
def test_bundled_scenes_run(name):
    r = simulate(load(name))
    assert np.all(np.isfinite(r.omega)) and "timings" in r.report()


def test_cli_writes_npz_and_csv(tmp_path, capsys):
    npz, csv = tmp_path / "out.npz", tmp_path / "out.csv"
    assert _main("tennis-racket", "-o", str(npz)) == 0
    assert "drift" in capsys.readouterr().out
    data = np.load(npz)
    assert data["omega"].shape == (2001, 3) and "invariant_energy" in data
    assert _main("tennis-racket", "-o", str(csv)) == 0
    head = csv.read_text().splitlines()[0]
    assert head == "t,omega1,omega2,omega3,polhode1,polhode2,polhode3,energy,L2"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv", "out.npz"]


def test_cli_plot_writes_png(tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "racket.png"
    assert _main("tennis-racket", "--plot", str(path)) == 0
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert oct(path.stat().st_mode & 0o777) != oct(0o600)


def test_sweep_csv_has_member_columns(tmp_path):
    r = simulate(Scene(**{**TOP, "t_end": 0.05, "points": 3, "omega": (0, 0, [100.0, 120.0]), "outputs": ("omega",), "accuracy": 1e-6}))
    path = tmp_path / "sweep.csv"
    save(r, str(path))
    lines = path.read_text().splitlines()
    assert lines[0] == "member,omega[2],t,omega1,omega2,omega3,gamma1,gamma2,gamma3" and len(lines) == 1 + 2 * 3


def test_outputs_constant_lists_the_contract():
    assert OUTPUTS == ("omega", "attitude", "euler_angles", "invariants", "polhode", "summary")
    assert math.isclose(Scene(**FREE).times[-1], FREE["t_end"])


@settings(max_examples=100, deadline=None)
@given(st.sampled_from(["ZXZ", "zxz", "XYZ", "zyx", "ZYZ"]), st.lists(st.floats(-7, 7), min_size=3, max_size=3))
def test_frames_one_euler_rotation_as_the_rows(seq, angles):
    """One rotation from Euler angles (products on floats) is the rows' (products on arrays), to round-off."""
    from eulersym.scene.frames import Rotation as Frames

    one = Frames.from_euler(seq, angles).as_quat()
    rows = Frames.from_euler(seq, [angles, angles]).as_quat()
    assert np.allclose(rows, one, rtol=0, atol=4e-16)
    assert np.allclose(Frames.from_euler(seq, angles).as_matrix(), Rotation.from_euler(seq, angles).as_matrix(), atol=1e-14)
