"""Scenes and files (issue 14): hostile scene files, output paths and kills end in exit 2 with one clean line naming
the key, the value and what is valid — or in a correct answer; Euler-angle rates, the template, the CSV and the
plots of the user's surface."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from eulersym.cli import main
from eulersym.errors import InvalidInput
from eulersym.scene import Scene, bundled, simulate
from eulersym.scene.cli import TEMPLATE
from eulersym.scene.io import figure, quantity_label, save, summary_path

TOP = dict(moments=(1.2e-3, 1.2e-3, 4.0e-4), mass=0.5, l=0.04, euler=(0.0, 0.5, 0.0), omega=(0.0, 0.0, 150.0),
           t_end=0.05, points=11)


def _exit_2(capsys, *argv, needles=(), forbidden=("Traceback", "rtol", "array(")):
    start = time.monotonic()
    assert main(["simulate", *argv]) == 2
    err = capsys.readouterr().err
    assert time.monotonic() - start < 60
    assert err.count("\n") == 1 and "is not valid: expected" in err, err
    for word in forbidden:
        assert word not in err, (word, err)
    for needle in needles:
        assert needle in err, (needle, err)
    return err


def _write(path: Path, text: str) -> str:
    path.write_text(textwrap.dedent(text))
    return str(path)


# ----------------------------------------------------------------------------------------------------------------
# files


def test_toml_nested_5000_deep(tmp_path, capsys):
    path = tmp_path / "deep.toml"
    path.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    _exit_2(capsys, str(path), needles=("SCENE=", "nested"))


@pytest.mark.parametrize("flag, target", [("-o", "/proc/out.npz"), ("-o", "/no/such/folder/out.csv"),
                                          ("--plot", "/proc/out.png")])
def test_output_where_nothing_can_be_written_is_refused_before_the_run(capsys, flag, target):
    if not Path("/proc").is_dir() and target.startswith("/proc"):
        pytest.skip("no /proc")
    _exit_2(capsys, "tennis-racket", flag, target, needles=(f"{flag}={target!r}",))


_KILLED_WRITER = """
import sys, time
from eulersym.scene.io import _atomic
def writer(tmp):
    with open(tmp, "wb") as handle:
        handle.write(b"partial" * 1000)
        handle.flush()
    print("WRITING", flush=True)
    time.sleep(600)
_atomic(sys.argv[1], writer)
"""


def test_kill_9_while_writing_leaves_no_lasting_temporary(tmp_path):
    target = tmp_path / "out.npz"
    child = subprocess.Popen([sys.executable, "-c", _KILLED_WRITER, str(target)], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "WRITING", child.stderr.read()
        os.kill(child.pid, signal.SIGKILL)
        child.wait(timeout=30)
    finally:
        if child.poll() is None:
            child.kill()
    left = [p.name for p in tmp_path.iterdir()]
    assert len(left) == 1 and left[0].startswith(".out.npz.eulersym-tmp-") and not target.exists()
    assert main(["simulate", "tennis-racket", "-o", str(target)]) == 0  # the next write cleans up
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.npz"]
    assert set(np.load(target).files) >= {"t", "omega"}


def test_explain_with_outputs_says_it_writes_nothing(tmp_path, capsys):
    out, png = tmp_path / "x.csv", tmp_path / "x.png"
    assert main(["simulate", "tennis-racket", "--explain", "-o", str(out), "--plot", str(png)]) == 0
    text = capsys.readouterr().out
    assert "nothing was written" in text and str(out) in text and str(png) in text
    assert not out.exists() and not png.exists()


def test_memory_error_is_clean(monkeypatch, capsys):
    C = sys.modules["eulersym.scene.cli"]  # the module (the package exports a function of that name)

    def exhausted(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(C, "simulate", exhausted)
    _exit_2(capsys, "tennis-racket", needles=("fits in memory",))


# ----------------------------------------------------------------------------------------------------------------
# numbers double precision cannot carry, and runs that would not end


@pytest.mark.parametrize("body, initial, extra, key", [
    ("moments = [1e300, 2e300, 3e300]", "omega = [0.1, 1, 0]", "", "body.moments"),
    ("moments = [1, 2, 3]", "omega = [1e200, 1e200, 0]", "", "initial.omega"),
    ("moments = [1, 2, 3]", "omega = [1e300, 1e300, 0]", "", "initial.omega"),
    ("moments = [1, 1, 2]\nmass = 1e300", "euler = [0, 0.5, 0]\nomega = [0, 0, 10]", "[pivot]\nl = 0.1\n",
     "body.mass"),
    ("moments = [1, 2, 3]", "omega = [0.1, 1, 0]", "[torque]\nbody = [1e300, 0, 0]\n", "torque.body"),
    ("moments = [1, 2, 3]", "omega = [1e9, 0, 0]", "", "time.end"),
])
def test_huge_numbers_are_refused_with_their_cause(tmp_path, capsys, body, initial, extra, key):
    path = tmp_path / "huge.toml"
    path.write_text(f"[body]\n{body}\n{extra}[initial]\n{initial}\n[time]\nend = 1e7\npoints = 11\n"
                    "[output]\nwant = [\"omega\"]\n")
    err = _exit_2(capsys, str(path), needles=(f"{key}=",))
    assert "double" in err


def test_large_but_carried_numbers_still_run():
    r = simulate(Scene(moments=(1e20, 2e20, 3e20), omega=(1e10, 1e12, 0.0), t_end=1e-9, points=5))
    assert np.all(np.isfinite(r.omega)) and r.drift["energy"] < 1e-12


def test_an_endless_heavy_top_is_refused_with_an_estimate(tmp_path, capsys):
    path = _write(tmp_path / "endless.toml", """
        [body]
        moments = [1, 1.5, 2]
        mass = 1
        [pivot]
        l = 0.1
        [initial]
        euler = [0, 0.5, 0]
        omega = [0, 0, 10]
        [time]
        end = 1e12
    """)
    err = _exit_2(capsys, path, needles=("scene=", "work budget", "kernel evaluations"))
    assert "rad by t_end" in err
    from eulersym.scene.spec import load

    with pytest.raises(InvalidInput) as info:  # a Python caller gets the one refusal the command line prints
        simulate(load(path))
    assert str(info.value) in err


def test_the_bundled_scenes_pass_the_work_guard():
    from eulersym.scene.cli import WORK_LIMIT, work_estimate
    from eulersym.scene.spec import load

    for name in bundled():
        assert work_estimate(load(name)).evaluations < WORK_LIMIT / 100, name


def test_a_sweep_too_big_for_memory_is_refused_before_allocating(tmp_path, capsys):
    path = _write(tmp_path / "big.toml", """
        [body]
        moments = [1, 2, 3]
        [initial]
        omega = [0.1, 1, {start = 0, stop = 1, num = 1000}]
        [time]
        end = 1
        points = 10000000
    """)
    _exit_2(capsys, path, needles=("memory", "1000 members × 10000000 points"))


# ----------------------------------------------------------------------------------------------------------------
# a shape on a pivot


CONE = {"body": {"shape": "cone", "mass": 1.0, "R": 0.05, "h": 0.2}, "initial": {"euler": [0, 0.5, 0],
        "omega": [0, 0, 100]}, "time": {"end": 0.01, "points": 3}, "output": {"want": ["omega"]}}


def _cone(origin, pivot):
    return {**CONE, "body": {**CONE["body"], "origin": origin}, "pivot": pivot}


def test_a_cone_on_its_apex_takes_l_from_its_shape():
    scene = Scene.from_dict(_cone("apex", {"g": 9.81}))
    h = sp.Symbol("h", positive=True)
    assert scene.regime == "heavy top" and abs(scene.l - float((3 * h / 4).subs(h, 0.2))) < 1e-15
    assert Scene.from_dict(_cone("apex", {"l": 0.15})).l == pytest.approx(0.15)


@pytest.mark.parametrize("origin, l, says", [("apex", 0.05, "l = 0.15"), ("center", 0.05, "l = 0")])
def test_a_contradicting_l_is_refused(tmp_path, origin, l, says):
    with pytest.raises(InvalidInput) as info:
        Scene.from_dict(_cone(origin, {"l": l}))
    assert info.value.argument == "pivot.l" and says in str(info.value)


def test_a_cube_on_its_corner_is_a_heavy_top_about_the_space_diagonal():
    """The centre of mass off body axis 3 but on a principal axis through the pivot (the cube's space diagonal, the
    axis of its moment M a²/6 about the corner): the heavy top's frame turns e3 onto it — and the cube is symmetric
    about it, so Lagrange's closed form applies; it agrees with DOP853 on the same frame."""
    data = {**CONE, "body": {"shape": "cube", "mass": 1.0, "a": 0.1, "origin": "corner"}, "pivot": {"g": 9.81},
            "time": {"end": 0.2, "points": 5}}
    scene = Scene.from_dict(data)
    plan = scene.plan()
    assert scene.regime == "heavy top" and plan.engine == "closed form: elliptic (Lagrange top)"
    exact = simulate(scene)
    assert np.allclose(exact.axes[:, 2], np.ones(3) / np.sqrt(3), atol=1e-15)
    integrated = simulate(Scene.from_dict({**data, "output": {"want": ["omega"], "method": "DOP853",
                                                              "accuracy": 1e-11}}))
    assert np.max(np.abs(exact.omega - integrated.omega)) < 1e-8 * 100


# ----------------------------------------------------------------------------------------------------------------
# initial Euler-angle rates


@pytest.mark.parametrize("convention", ["zxz", "xyx", "yzy", "zyz", "xzx", "yxy", "xyz", "yzx", "zxy", "xzy", "zyx",
                                        "yxz"])
def test_euler_rates_use_the_derived_kinematics(convention, rng):
    from eulersym.kinematics import omega_body
    from eulersym.scene.rates import omega_body as numeric
    from eulersym.symbols import phi, psi, t, theta

    w = omega_body(convention)
    for angles, rates in zip(rng.uniform(-3, 3, (5, 3)), rng.uniform(-5, 5, (5, 3))):
        subs = {phi.diff(t): rates[0], theta.diff(t): rates[1], psi.diff(t): rates[2]}
        subs.update({phi: angles[0], theta: angles[1], psi: angles[2]})
        exact = [float(c.subs(subs)) for c in w]
        np.testing.assert_allclose(numeric(angles, rates, convention), exact, atol=1e-12)


def test_a_scene_started_with_euler_rates_needs_no_sympy():
    code = textwrap.dedent("""
        import sys
        from eulersym.scene import Scene, simulate
        s = Scene(moments=(2, 2, 1), euler=(0.1, 0.5, 0.2), euler_rates=(0.0, 0.0, 3.0), t_end=1, points=3)
        r = simulate(s)
        print(s.omega, "sympy" in sys.modules)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "(0.0, 0.0, 3.0) False"


def test_euler_rates_from_toml_and_bad_combinations(tmp_path):
    base = {"body": {"moments": [1, 2, 3]}, "time": {"end": 1}}
    scene = Scene.from_dict({**base, "initial": {"euler": [0.3, 0.8, 0.1], "euler_rates": [1.0, 0.5, 2.0]}})
    from eulersym.generated import kinematics

    assert scene.omega == pytest.approx(tuple(kinematics.omega_body(0.3, 0.8, 0.1, 1.0, 0.5, 2.0)))
    for initial, says in [({"euler_rates": [1, 0, 0]}, "Euler angles too"),
                          ({"euler": [0, 1, 0], "euler_rates": [1, 0, 0], "omega": [1, 0, 0]}, "not both"),
                          ({"euler": [0, [0.5, 1.0], 0], "euler_rates": [1, 0, 0]}, "not swept"),
                          ({"euler": [0, 1, 0], "euler_rates": [1, 0]}, "3 numbers")]:
        with pytest.raises(InvalidInput, match=says) as info:
            Scene.from_dict({**base, "initial": initial})
        assert info.value.argument.startswith("initial.")


# ----------------------------------------------------------------------------------------------------------------
# template and list


def test_template_loads_and_names_every_key(tmp_path, capsys):
    from eulersym.scene.spec import _TOML_LAYOUT

    assert main(["simulate", "--template"]) == 0
    text = capsys.readouterr().out
    assert text == TEMPLATE
    path = tmp_path / "template.toml"
    path.write_text(text)
    scene = Scene.from_toml(path)
    assert scene.regime == "heavy top" and scene.name == "my-top"
    for section, keys in _TOML_LAYOUT.items():
        for key in keys:
            assert f"{key} =" in text or f"{key} = " in text, (section, key)
    assert main(["simulate", str(path), "--explain"]) == 0


def test_list_gives_each_bundled_scene_path(capsys):
    assert main(["simulate", "--list"]) == 0
    text = capsys.readouterr().out
    for name, path in bundled().items():
        assert name in text and path in text and Path(path).is_file()


# ----------------------------------------------------------------------------------------------------------------
# CSV


def test_heavy_top_csv_keeps_the_vertical(tmp_path):
    r = simulate(Scene(**TOP, outputs=("omega",)))
    path = tmp_path / "top.csv"
    assert save(r, str(path)) == [str(path)]
    head = path.read_text().splitlines()[0].split(",")
    assert head[-3:] == ["gamma1", "gamma2", "gamma3"]
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[0, -1], np.cos(0.5), atol=1e-12)  # Γ3 = cos θ
    np.testing.assert_allclose(np.linalg.norm(table[:, -3:], axis=1), 1.0, atol=1e-8)


def test_sweep_csv_has_a_per_member_summary_beside_it(tmp_path):
    r = simulate(Scene(**{**TOP, "omega": (0, 0, [100.0, 120.0, 140.0]), "outputs": ("omega", "invariants"),
                          "accuracy": 1e-6}))
    path = tmp_path / "sweep.csv"
    written = save(r, str(path))
    assert written == [str(path), summary_path(str(path))]
    lines = Path(written[1]).read_text().splitlines()
    head = lines[0].split(",")
    assert head[:2] == ["member", "omega[2]"] and "theta_max_deg" in head and "drift_energy" in head
    rows = np.loadtxt(written[1], delimiter=",", skiprows=1)
    assert rows.shape[0] == 3 and rows[:, 1].tolist() == [100.0, 120.0, 140.0]
    tilt = np.degrees(np.arccos(np.clip(r.gamma[..., 2], -1, 1))).max(axis=1)
    np.testing.assert_allclose(rows[:, head.index("theta_max_deg")], tilt)
    npz = tmp_path / "sweep.npz"
    save(r, str(npz))
    assert "summary_theta_max_deg" in np.load(npz).files


# ----------------------------------------------------------------------------------------------------------------
# plots


def test_quantity_labels():
    assert quantity_label("euler[1]") == "θ0 (rad)"
    assert quantity_label("omega[2]") == "ω3 (rad/s)"
    assert quantity_label("mass") == "M (kg)" and quantity_label("dimensions.h") == "h (m)"
    assert quantity_label("nonsense[3]") == "nonsense[3]"


def _axes_read(fig):
    import matplotlib

    fig.canvas.draw()
    for ax in fig.axes:
        if ax.get_label() == "<colorbar>":
            assert ax.get_ylabel(), "colorbar without a label"
            continue
        assert ax.get_xlabel() and ax.get_ylabel(), (ax.get_title(), ax.get_xlabel(), ax.get_ylabel())
        if hasattr(ax, "get_zlabel"):
            assert ax.get_zlabel()
        labels = [ax.get_xlabel(), ax.get_ylabel()]
        assert any("(" in text for text in labels), labels  # units
        for axis in (ax.xaxis, ax.yaxis):
            offset = axis.get_offset_text().get_text()
            assert not offset.startswith("+") and not offset.startswith("−") or "e" in offset, offset
    matplotlib.pyplot.close(fig)


@pytest.mark.parametrize("name", sorted(bundled()))
def test_every_bundled_scene_plots_with_labelled_axes(name):
    pytest.importorskip("matplotlib")
    from eulersym.figures import figure as draw, fitting
    from eulersym.scene.spec import load

    scene = load(name)
    result = simulate(scene)
    names = fitting(result)
    fig = figure(result)  # the time panels
    titles = " ".join(ax.get_title() for ax in fig.axes)
    if "euler_angles" in scene.outputs:
        assert "Euler angles" in titles or "Euler angle (degrees)" in {ax.get_ylabel() for ax in fig.axes}
    if scene.regime == "heavy top":
        assert "tilt" in titles and ("axis-path" in names or scene.batch > 1)
    if "polhode" in scene.outputs:
        assert "polhodes" in names
    _axes_read(fig)  # and closes it
    if scene.batch > 1 and len(scene.sweeps) == 2 and scene.regime == "heavy top":
        fig = draw(result, "map")
        labels = {ax.get_xlabel() for ax in fig.axes} | {ax.get_ylabel() for ax in fig.axes}
        assert "θ0 (degrees)" in labels and "ω3 (rad/s)" in labels and not any("[" in x for x in labels)
        import matplotlib.pyplot

        matplotlib.pyplot.close(fig)


def test_a_constant_line_is_not_hidden_by_an_offset():
    pytest.importorskip("matplotlib")
    r = simulate(Scene(moments=(2.0, 2.0, 2.0), omega=(0.0, 0.0, 2.0), t_end=1, points=11, outputs=("omega",)))
    fig = figure(r)
    ax = fig.axes[0]
    fig.canvas.draw()
    low, high = ax.get_ylim()
    assert high - low > 0.1 and ax.yaxis.get_offset_text().get_text() == ""


def test_a_missing_dimension_is_named_where_it_goes(tmp_path, capsys):
    path = _write(tmp_path / "cyl.toml", """
        [body]
        shape = "cylinder"
        mass = 1
        R = 0.05
        [initial]
        omega = [0, 0, 100]
        [time]
        end = 1
    """)
    _exit_2(capsys, path, needles=("body.h=None", "needs R, h"), forbidden=("dimensions.",))


def test_an_array_value_is_shown_on_one_line():
    err = InvalidInput("u", np.arange(40.0).reshape(8, 5) * 1e281, "finite arguments")
    assert "\n" not in str(err) and str(err).startswith("u=array([[") and len(str(err)) < 200


def _bundled_models():
    from importlib import resources

    folder = resources.files("eulersym.models")
    return sorted(str(p) for p in folder.iterdir() if p.name.endswith(".toml"))


@pytest.mark.parametrize("path", _bundled_models(), ids=lambda p: Path(p).stem)
def test_model_scenes_pass_the_work_guard(path):
    from eulersym.scene.cli import WORK_LIMIT, _refuse_endless, work_estimate
    from eulersym.scene.spec import load

    scene = load(path)
    assert work_estimate(scene).evaluations < WORK_LIMIT
    _refuse_endless(scene)  # no refusal, no crash


def test_an_endless_model_scene_is_refused(tmp_path, capsys):
    """Kovalevskaya's top is integrated (no closed form): over 10¹² time units it is refused with the estimate."""
    text = Path(next(p for p in _bundled_models() if p.endswith("kovalevskaya.toml"))).read_text()
    path = tmp_path / "endless-model.toml"
    assert "\nend = 20.0\n" in text
    path.write_text(text.replace("\nend = 20.0\n", "\nend = 1e12\n", 1))
    _exit_2(capsys, str(path), needles=("work budget",))


def test_a_user_work_budget_is_honoured(tmp_path, capsys):
    path = tmp_path / "long.toml"
    path.write_text("[body]\nmoments = [1, 1.5, 2]\nmass = 1\n[pivot]\nl = 0.1\n[initial]\neuler = [0, 0.5, 0]\n"
                    "omega = [0, 0, 10]\n[time]\nend = 1e5\npoints = 11\n[output]\nwant = [\"omega\"]\n")
    _exit_2(capsys, str(path), "--work-budget", "1e6", needles=("work budget",))


def test_a_model_scene_plots_the_vertical_and_keeps_it_in_the_csv(tmp_path):
    pytest.importorskip("matplotlib")
    from eulersym.scene.spec import load

    result = simulate(load(next(p for p in _bundled_models() if p.endswith("lagrange-top.toml"))))
    fig = figure(result)
    assert any("tilt" in ax.get_title() for ax in fig.axes)
    _axes_read(fig)
    path = tmp_path / "model.csv"
    save(result, str(path))
    assert "gamma3" in path.read_text().splitlines()[0].split(",")
