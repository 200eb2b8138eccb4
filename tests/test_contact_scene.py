"""Contact and moving-pivot scene files are scenes like any other (``Scene.from_toml``, ``eulersym simulate``): the
bundled ones run; bad input is a named error, exit 2, no traceback, nothing written."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from eulersym.cli import main
from eulersym.errors import EulersymError, InvalidInput
from eulersym.model import Model, contact_scene
from eulersym.model.contact_motion import LiftOff
from eulersym.scene import Scene, model_kernel, simulate

SPHERE = """
name = "ball"
[parameters]
M = 1.0
a = 0.1
[body]
moments = ["2*M*a**2/5", "2*M*a**2/5", "2*M*a**2/5"]
mass = "M"
[contact]
surface = "sphere"
radius = "a"
{contact}
[initial]
omega = {omega}
{initial}
[time]
end = 1.0
points = 11
"""


def _write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def _load(path):
    return Scene.from_toml(contact_scene.bundled().get(path, path))


def test_every_bundled_contact_scene_loads_and_names_its_regime():
    kinds = {name: _load(name).regime for name in contact_scene.bundled()}
    assert kinds == {"chaplygin-ball": "contact", "euler-disk": "contact", "kapitza-pendulum": "model",
                     "rattleback": "contact", "rolling-sphere": "contact", "tippe-top": "contact"}


def test_the_euler_disk_scene_rolls_in_place_and_writes_its_trace_and_normal_force(tmp_path, capsys):
    out = tmp_path / "disk.npz"
    assert main(["simulate", "euler-disk", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "integrate: DOP853" in text and "Newton–Euler" in text and "lift-off" in text
    data = np.load(out)  # the contact outputs are the run's quantities: one column each
    assert np.allclose(data["quantity_N"], 0.4 * 9.81, rtol=1e-9)  # N = M g: Moffatt's steady rolling in place
    assert np.allclose(np.hypot(data["quantity_x_P"], data["quantity_y_P"]), 0.0375 * np.cos(0.3), rtol=1e-9)


def test_the_kapitza_scene_stays_upright(capsys):
    result = simulate(_load("kapitza-pendulum"))
    assert result.gamma[:, 2].min() >= np.cos(0.2) - 1e-9


def test_the_same_scene_is_taken_from_the_kernel_cache_the_second_time(tmp_path, monkeypatch):
    monkeypatch.setenv("EULERSYM_CACHE", str(tmp_path / "cache"))
    model = Model.from_toml(contact_scene.bundled()["rolling-sphere"])
    first, path, emitted = model_kernel.ensure(model, [])
    assert emitted and len(list((tmp_path / "cache" / "models").iterdir())) == 1
    again, path_again, emitted_again = model_kernel.ensure(Model.from_toml(contact_scene.bundled()["rolling-sphere"]), [])
    assert not emitted_again and again.STATE == first.STATE and path_again == path


def test_lift_off_is_a_named_error_at_its_time(tmp_path, capsys):
    """A tippe top spun at 150 rad/s with μ = 0.1 leaves the plane (its normal force reaches 0) near t = 2.41 s."""
    import tomllib

    text = tomllib.loads(open(contact_scene.bundled()["tippe-top"]).read())
    path = _write(tmp_path, open(contact_scene.bundled()["tippe-top"]).read()
                  .replace("mu = 0.3 ", "mu = 0.1 ").replace("omega = [0.0, 0.0, 100.0]", "omega = [0.0, 0.0, 150.0]"))
    assert text["parameters"]["mu"] == 0.3
    with pytest.raises(LiftOff) as info:
        simulate(_load(path))
    assert 2.3 < info.value.t < 2.5 and isinstance(info.value, EulersymError)
    out = tmp_path / "x.npz"
    assert main(["simulate", path, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "left the plane at t = 2.4" in err and "Traceback" not in err and not out.exists()


@pytest.mark.parametrize("contact, omega, initial, key", [
    ("", "[0, 10, 0]", "", None),
    ('radius = 0', "[0, 10, 0]", "", "contact.radius"),
    ('mode = "skating"', "[0, 10, 0]", "", "contact.mode"),
    ('mode = "sliding"\nfriction = "stribeck"', "[0, 10, 0]", "", "contact.friction"),
    ('mode = "sliding"\nfriction = "coulomb"\nmu = 0.3', "[0, 10, 0]", "", "contact.width"),
    ('g = -9.81', "[0, 10, 0]", "", "contact.g"),
    ('colour = "red"', "[0, 10, 0]", "", "contact.colour"),
    ("", "[0, 10]", "", "initial.omega"),
    ("", "[0, 10, 0]", "position = [0, 0, 0.5]", "initial.position"),
    ("", "[0, 10, 0]", "velocity = [3, 0]", "initial.velocity"),
    ('mode = "sliding"\nfriction = "none"', "[0, 10, 0]", "velocity = [1, 0, 0.5]", "initial.velocity"),
    ('mode = "sliding"\nfriction = "none"', "[0, 10, 0]", "velocity = [1, 0, 0]", None),
    ("", "[0, 10, 0]", "quaternion = [0, 0, 0, 0]", "initial.quaternion"),
])
def test_bad_contact_scenes_name_the_key(tmp_path, contact, omega, initial, key):
    text = SPHERE.format(contact=contact, omega=omega, initial=initial).replace("radius = \"a\"\nradius = 0",
                                                                                 "radius = 0")
    if "radius = 0" in contact:
        text = text.replace('radius = "a"\n', "")
    path = _write(tmp_path, text)
    if key is None:
        assert simulate(_load(path)).omega.shape == (11, 3)
        return
    with pytest.raises(InvalidInput) as info:
        simulate(_load(path))
    assert info.value.argument == key


def test_a_contact_on_a_pivoted_body_is_refused(tmp_path, capsys):
    path = _write(tmp_path, SPHERE.format(contact="", omega="[0, 1, 0]", initial="") + "[pivot]\nl = 0.1\n")
    with pytest.raises(InvalidInput) as info:
        _load(path)
    assert info.value.argument == "contact" and "pivot" in str(info.value)
    assert main(["simulate", path]) == 2
    assert "a pivot both hold the body" in capsys.readouterr().err


def test_a_start_that_does_not_press_on_the_plane_is_refused(tmp_path):
    """A tippe top tipped past the horizontal (2.5 rad) and spun about a horizontal axis at 400 rad/s: its centre of
    mass accelerates down faster than g (z = R (1 − α Γ3), z̈ = R α cos θ ω² < −g), N < 0 at once: refused, naming ω."""
    path = _write(tmp_path, open(contact_scene.bundled()["tippe-top"]).read()
                  .replace("omega = [0.0, 0.0, 100.0]", "omega = [400.0, 0.0, 0.0]").replace("angle = 0.1",
                                                                                        "angle = 2.5"))
    with pytest.raises(InvalidInput) as info:
        simulate(_load(path))
    assert info.value.argument == "initial.omega" and "normal force" in str(info.value)


@pytest.mark.parametrize("path, key", [
    ('["0", "0"]', "pivot.path"),
    ('["0", "0", "a*cos(W*t)*omega1"]', "pivot.path[2]"),
    ('["0", "0", "x*t"]', "pivot.path[2]"),
    ('["0", "0", true]', "pivot.path[2]"),
])
def test_a_path_that_is_not_a_function_of_t_alone_is_refused(tmp_path, path, key, capsys):
    text = open(contact_scene.bundled()["kapitza-pendulum"]).read().replace('path = ["0", "0", "a*cos(W*t)"]',
                                                                            f"path = {path}")
    scene = _write(tmp_path, text)
    with pytest.raises(InvalidInput) as info:
        _load(scene)
    assert info.value.argument == key
    assert main(["simulate", scene]) == 2
    assert "Traceback" not in capsys.readouterr().err


@settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.dictionaries(st.sampled_from(contact_scene.CONTACT_KEYS + ("bogus",)),
                       st.one_of(st.none(), st.booleans(), st.integers(-3, 3), st.floats(allow_nan=True),
                                 st.text(max_size=6), st.lists(st.integers(-2, 2), max_size=4)), max_size=5))
def test_reading_any_contact_table_returns_a_checked_table_or_a_named_error(table):
    try:
        checked = contact_scene.read_contact(table)
    except InvalidInput as exc:
        assert exc.argument.startswith("contact")
    else:
        assert checked["surface"] in ("sphere", "ellipsoid", "disk", "paraboloid") and checked["g"] is not None


def test_a_swept_parameter_runs_each_member_on_one_cached_kernel(tmp_path, capsys):
    """Rolling spheres of radii 0.05, 0.1, 0.2 at ω = 10 rad/s: each centre at x = a ω t (v = a ω), one kernel."""
    text = SPHERE.format(contact="", omega="[0, 10, 0]", initial="").replace("a = 0.1", "a = [0.05, 0.1, 0.2]")
    path = _write(tmp_path, text)
    scene = _load(path)
    assert scene.batch == 3 and scene.members()["parameters.a"].tolist() == [0.05, 0.1, 0.2]
    out = tmp_path / "sweep.npz"
    assert main(["simulate", path, "-o", str(out)]) == 0
    data = np.load(out)
    assert data["omega"].shape == (3, 11, 3) and np.allclose(data["sweep_parameters.a"], [0.05, 0.1, 0.2])
    x = data["quantity_x_cm"][:, -1]
    assert np.allclose(x, np.array([0.05, 0.1, 0.2]) * 10 * 1.0, atol=1e-9)
    assert "sweep of 3 members" in capsys.readouterr().out


@pytest.mark.parametrize("value, key", [("[]", "parameters.a"), ('[0.1, "x"]', "parameters.a[1]"),
                                        ("[0.1, nan]", "parameters.a[1]")])
def test_a_bad_sweep_names_the_parameter(tmp_path, value, key):
    path = _write(tmp_path, SPHERE.format(contact="", omega="[0, 10, 0]", initial="").replace("a = 0.1",
                                                                                              f"a = {value}"))
    with pytest.raises(InvalidInput) as info:
        _load(path)
    assert info.value.argument == key


def test_a_file_nested_too_deep_is_a_named_error_here_too(tmp_path):
    path = _write(tmp_path, "[contact]\na = " + "[" * 5000 + "]" * 5000 + "\n")
    with pytest.raises(InvalidInput) as info:
        _load(path)
    assert info.value.argument == "SCENE" and "nested" in str(info.value)


def test_simulate_list_names_every_contact_scene_and_each_name_runs(capsys):
    from eulersym.scene.catalog import bundled as scene_files

    assert main(["simulate", "--list"]) == 0
    text = capsys.readouterr().out
    for name, (description, path) in contact_scene.listing().items():
        assert f"  {name:<22} {description}\n" in text and path in text and description
        assert scene_files()[name] == path and text.count(f"  {name} ") == 1  # in the one catalogue, once
    assert main(["simulate", "tippe-top", "--explain"]) == 0
    assert "tippe-top" in capsys.readouterr().out


def _count_attempts(monkeypatch) -> list:
    """The kernel calls of each run the contact control makes, in order (its ``_attempt`` wrapped)."""
    from eulersym.numerics.methods._contact import ContactDOP853

    made = []
    attempt = ContactDOP853._attempt

    def counted(self, *args, **kwargs):
        run = attempt(self, *args, **kwargs)
        made.append(run.n_rhs_calls)
        return run

    monkeypatch.setattr(ContactDOP853, "_attempt", counted)
    return made


def test_an_accuracy_past_the_rtol_floor_is_not_reached_and_the_calls_are_counted_once(tmp_path, capsys,
                                                                                        monkeypatch):
    """The rattleback at accuracy 1e-13: the tight run is at rtol 1e-14, the floor, so a "refinement" would repeat it
    bit for bit and estimate 0. The run keeps the last honest pair's estimate, warns, exits 3, and its kernel calls
    are the sum of the runs it made (no run counted twice)."""
    from eulersym.errors import AccuracyNotReached

    made = _count_attempts(monkeypatch)
    text = (open(contact_scene.bundled()["rattleback"]).read().replace("end = 10.0", "end = 2.0")
            .replace("points = 201", "points = 11").replace("accuracy = 1e-9", "accuracy = 1e-13"))
    path = _write(tmp_path, text)
    with pytest.warns(AccuracyNotReached, match="was not reached within the contact control's runs") as caught:
        result = simulate(_load(path))
    assert "double precision" not in str(caught[0].message)
    worst = max(float(np.max(v)) for v in result.error.values())
    assert worst > 1e-13  # an honest estimate, not the 0 of a run compared with itself
    assert result.n_rhs_calls == sum(made) and len(made) == 2
    out = tmp_path / "x.npz"
    made.clear()
    assert main(["simulate", path, "-o", str(out)]) == 3 and out.exists()
    assert f"kernel calls: {sum(made)}" in capsys.readouterr().out


def test_a_refined_contact_run_counts_each_run_once(tmp_path, monkeypatch):
    """At accuracy 1e-12 the rattleback is refined once (three runs): its kernel calls are their sum."""
    made = _count_attempts(monkeypatch)
    text = (open(contact_scene.bundled()["rattleback"]).read().replace("end = 10.0", "end = 2.0")
            .replace("points = 201", "points = 11").replace("accuracy = 1e-9", "accuracy = 1e-11"))
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = simulate(_load(_write(tmp_path, text)))
    assert result.n_rhs_calls == sum(made) and len(made) == 3


@pytest.mark.parametrize("contact, swept, key", [
    ("", "a = [0.1, -0.1]", "contact.radius"),
    ('mode = "sliding"\nfriction = "coulomb"\nmu = "c"\nwidth = 0.01', "c = [0.3, -0.2]", "contact.mu"),
    ('mode = "sliding"\nfriction = "coulomb"\nmu = 0.3\nwidth = "c"', "c = [0.01, 0.0]", "contact.width"),
])
def test_contact_dimensions_are_checked_at_every_members_values(tmp_path, capsys, contact, swept, key):
    """A sweep that gives a member a radius −0.1 (or μ < 0, or a zero width) is refused by key, naming the member's
    value — the defaults alone are valid — exit 2, nothing written."""
    name = swept.split(" = ")[0]
    text = SPHERE.format(contact=contact, omega="[0, 10, 0]", initial="")
    text = text.replace("a = 0.1", swept) if name == "a" else text.replace("a = 0.1", f"a = 0.1\n{swept}")
    path = _write(tmp_path, text)
    with pytest.raises(InvalidInput) as info:
        simulate(_load(path))
    assert info.value.argument == key and "member 1" in str(info.value)
    out = tmp_path / "x.npz"
    assert main(["simulate", path, "-o", str(out)]) == 2 and not out.exists()
    assert "member 1" in capsys.readouterr().err


def test_a_contact_sweep_in_chunks_keeps_gamma_as_the_one_pass_does(tmp_path):
    """Rolling spheres of six radii, ``outputs = ["omega"]``: a memory budget that forces chunks gives the one pass's
    Γ (it was None in chunks) and its contact quantities."""
    from eulersym.scene import cost as scene_cost

    text = (SPHERE.format(contact="", omega="[0, 10, 0]", initial='axis = [1, 0, 0]\nangle = 0.3')
            .replace("a = 0.1", "a = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3]") + '[output]\nwant = ["omega"]\n')
    scene = _load(_write(tmp_path, text))
    whole = simulate(scene)
    small = scene_cost.estimate(scene, whole.plan)
    budget = small.output_bytes + small.per_member_working * 2 * scene_cost.threads(whole.plan)
    assert scene_cost.estimate(scene, whole.plan, memory=budget).chunk < scene.batch
    chunked = simulate(scene, memory=budget)
    assert whole.gamma is not None and chunked.gamma is not None
    for name in ("omega", "gamma"):
        assert np.array_equal(getattr(whole, name), getattr(chunked, name)), name
    for name in whole.state_quantities:
        assert np.array_equal(whole.state_quantities[name], chunked.state_quantities[name]), name
    assert whole.notes == chunked.notes and whole.drift == chunked.drift


def test_lift_off_in_a_chunk_names_the_sweeps_member_and_the_earliest_time(tmp_path):
    """Tippe tops at 150 rad/s with μ = 0.02, 0.02, 0.09, 0.1: the last two leave the plane, μ = 0.1 (member 3) first,
    near t = 2.41 s, μ = 0.09 (member 2) near 2.67 s. In chunks of two, the second chunk's members are named 2 and 3
    (not 0 and 1), and the time quoted is member 3's, the earliest — as the one pass says."""
    text = (open(contact_scene.bundled()["tippe-top"]).read().replace("mu = 0.3 ", "mu = [0.02, 0.02, 0.09, 0.1] ")
            .replace("omega = [0.0, 0.0, 100.0]", "omega = [0.0, 0.0, 150.0]").replace("end = 6.0", "end = 3.0")
            .replace("points = 601", "points = 31"))
    from eulersym.scene import cost as scene_cost

    scene = _load(_write(tmp_path, text))
    plan = scene.plan()
    small = scene_cost.estimate(scene, plan)
    budget = small.output_bytes + small.per_member_working * 2 * scene_cost.threads(plan)
    assert scene_cost.estimate(scene, plan, memory=budget).chunk == 2
    said = []
    for memory in (None, budget):
        with pytest.raises(LiftOff) as info:
            simulate(scene, memory=memory)
        said.append(info.value)
    for exc in said:
        assert 2.3 < exc.t < 2.5
        assert exc.members.split(": ", 1)[1].startswith("member 3 (parameters.mu = 0.1) at t = 2.4")
        assert "member 2 (parameters.mu = 0.09) at t = 2.6" in exc.members
        assert "member 0" not in exc.members and "member 1" not in exc.members
    assert said[0].t == said[1].t


def test_a_plot_refusal_comes_before_o_writes_anything(tmp_path, capsys):
    """(a) A contact sweep kept as summaries has no figure to draw: ``--plot`` is refused, naming why the map does not
    fit (no ``--figure='map'`` the user never gave), and ``-o`` is not written. (b) ``--figure contact-trace`` on a
    torque-free scene is refused before it runs: nothing written."""
    text = (SPHERE.format(contact="", omega="[0, 10, 0]", initial="").replace("a = 0.1", "a = [0.05, 0.1]")
            + '[output]\nwant = ["summary"]\n')
    path = _write(tmp_path, text)
    out, png = tmp_path / "s.npz", tmp_path / "s.png"
    assert main(["simulate", path, "-o", str(out), "--plot", str(png)]) == 2
    err = capsys.readouterr().err
    assert "--plot=" in err and "--figure='map'" not in err and "map: ball kept per-member summaries" in err
    assert not out.exists() and not png.exists()
    out, png = tmp_path / "t.npz", tmp_path / "t.png"
    assert main(["simulate", "tennis-racket", "-o", str(out), "--plot", str(png), "--figure", "contact-trace"]) == 2
    captured = capsys.readouterr()
    assert "for a body on a plane" in captured.err and "scene 'tennis-racket'" not in captured.out
    assert not out.exists() and not png.exists()


def test_a_disk_lying_flat_is_refused_by_name(tmp_path, capsys):
    """Euler's disk left at the default attitude lies flat (its axis vertical): its rim does not touch at one point.
    Refused at the start, naming the attitude — not a ZeroDivisionError inside the kernel — exit 2, nothing written."""
    text = "\n".join(line for line in open(contact_scene.bundled()["euler-disk"]).read().splitlines()
                     if not line.startswith(("axis = ", "angle = ")))
    path = _write(tmp_path, text)
    with pytest.raises(InvalidInput) as info:
        simulate(_load(path))
    assert info.value.argument == "initial.q" and "the disk lies flat" in str(info.value)
    out = tmp_path / "x.npz"
    assert main(["simulate", path, "-o", str(out)]) == 2 and not out.exists()
    assert "rim down" in capsys.readouterr().err


@pytest.mark.parametrize("sliding", [False, True])
def test_the_estimate_counts_the_contact_outputs(tmp_path, sliding):
    """The estimated output of a contact sweep holds what the run keeps: ω, Γ and the 6 contact quantities (8 when
    it slides), measured on the one pass's arrays — at least that, within 1.5×."""
    from eulersym.scene import cost as scene_cost

    contact = 'mode = "sliding"\nfriction = "coulomb"\nmu = 0.3\nwidth = 0.05' if sliding else ""
    text = (SPHERE.format(contact=contact, omega="[0, 10, 0]", initial="").replace("a = 0.1", "a = [0.05, 0.1, 0.2]")
            + '[output]\nwant = ["omega"]\n')
    scene = _load(_write(tmp_path, text))
    result = simulate(scene)
    kept = result.omega.nbytes + result.gamma.nbytes + sum(v.nbytes for v in result.state_quantities.values())
    assert len(result.state_quantities) == (8 if sliding else 6)
    estimated = scene_cost.estimate(scene, result.plan).output_bytes
    assert kept <= estimated <= 1.5 * kept, (kept, estimated)
