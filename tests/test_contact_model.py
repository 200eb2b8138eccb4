"""A body on a plane and a pivot that moves as one ``Model`` inside one ``Scene``: ``Model`` reads ``[contact]`` and
``[pivot] path`` itself, the plan chooses ``contact_dop853`` from the methods registry, and the run is one ``Result``
whose quantities are the contact outputs."""

from __future__ import annotations

import numpy as np
import pytest

from eulersym.cli import main
from eulersym.errors import InvalidInput
from eulersym.model import Model
from eulersym.model.contact_motion import LiftOff
from eulersym.scene import Scene, simulate
from eulersym.scene.catalog import bundled

SPHERE = dict(parameters={"M": 1.0, "a": 0.1}, body={"moments": ["2*M*a**2/5"] * 3, "mass": "M"},
              contact={"surface": "sphere", "radius": "a"})


def test_the_tippe_top_model_reads_its_contact_and_proves_its_routes_and_jellett():
    model = Model.from_toml(bundled()["tippe-top"])
    assert model.contact["surface"] == "sphere" and model.contact["mode"] == "sliding"
    assert model.facts().contact and not model.pivoted
    assert model.check().ok  # Newton–Euler with the multiplier = Gibbs–Appell, exactly
    verdicts = model.invariants()
    assert verdicts["Jellett"].conserved and not verdicts["E"].conserved  # sliding friction takes energy
    assert Model.from_dict(model.to_dict()) == model


def test_the_tippe_top_scene_inverts_on_the_one_path_and_agrees_with_the_contact_integrator():
    from eulersym.model.contact_motion import integrate, start

    scene = Scene.from_toml(bundled()["tippe-top"])
    assert scene.regime == "contact"
    plan = scene.plan()
    assert plan.options["engine"] == "contact_dop853" and "contact kernel" in plan.engine
    run = simulate(scene)
    assert run.gamma[0, 2] > 0.99 and run.gamma[-1, 2] < -0.99  # turned over onto its stem
    assert run.drift["Jellett"] < 1e-7
    assert {"x_P", "y_P", "N", "u_x", "u_y", "x_cm", "y_cm", "z_cm"} <= set(run.quantities)
    R, alpha = 0.02, 0.3  # the centre of mass rises from R(1 − α) to R(1 + α)
    assert abs(run.quantities["z_cm"][0] - R * (1 - alpha) * np.cos(0.1) - 0) < 2e-4
    assert abs(run.quantities["z_cm"][-1] - R * (1 + alpha)) < 1e-4
    # the same kernel by the contact integrator directly, at a tight tolerance: within the accuracy asked (×10)
    module = Model.from_toml(bundled()["tippe-top"]).compile()
    q0 = [np.cos(0.05), np.sin(0.05), 0.0, 0.0]
    reference = integrate(module, start(module, omega=(0, 0, 100.0), q=q0), run.t, rtol=1e-12, atol=1e-14)
    scale = np.max(np.abs(reference.y[:, :3]))
    assert np.max(np.abs(run.omega - reference.y[:, :3])) / scale < 10 * scene.accuracy
    assert np.max(np.abs(run.quantities["N"] - reference["N"])) < 1e-6


def test_a_sweep_of_rolling_spheres_is_one_result_each_member_equal_to_its_single_run():
    radii = [0.05, 0.1, 0.2]
    sweep = simulate(Scene(model=Model(**SPHERE), parameters={"a": radii}, omega=(0, 10, 0), t_end=1, points=11))
    assert sweep.quantities["x_cm"].shape == (3, 11)
    assert np.allclose(sweep.quantities["x_cm"][:, -1], np.array(radii) * 10, atol=1e-9)  # v = a ω
    for b, a in enumerate(radii):
        single = simulate(Scene(model=Model(**SPHERE), parameters={"a": a}, omega=(0, 10, 0), t_end=1, points=11))
        assert np.array_equal(single.omega, sweep.omega[b]) and np.array_equal(single.quantities["N"],
                                                                                sweep.quantities["N"][b])


def test_lift_off_in_the_one_path_is_a_named_error_exit_2_nothing_written(tmp_path, capsys):
    text = open(bundled()["tippe-top"]).read().replace("mu = 0.3 ", "mu = 0.1 ").replace("100.0]", "150.0]")
    path = tmp_path / "flying.toml"
    path.write_text(text.replace("end = 6.0", "end = 3.0"))
    with pytest.raises(LiftOff) as info:
        simulate(Scene.from_toml(path))
    assert abs(info.value.t - 2.4105879) < 1e-5
    out = tmp_path / "out.npz"
    assert main(["simulate", str(path), "-o", str(out)]) == 2
    assert "left the plane at t = 2.41" in capsys.readouterr().err and not out.exists()


def test_the_kapitza_pendulum_is_an_ordinary_model_on_the_compiled_dop853():
    scene = Scene.from_toml(bundled()["kapitza-pendulum"])
    assert scene.regime == "model" and scene.model.pivot_path == ("0", "0", "a*cos(W*t)")
    assert scene.plan().options["engine"] == "dop853"
    run = simulate(scene)
    assert run.gamma[:, 2].min() >= np.cos(0.2) - 1e-9  # upright above Kapitza's threshold


@pytest.mark.parametrize("kwargs, key", [
    (dict(SPHERE, contact={"surface": "sphere", "radius": -1}), "contact.radius"),
    (dict(SPHERE, contact={"surface": "sphere", "radius": "b"}), "contact.radius"),
    (dict(SPHERE, contact={"surface": "cube", "radius": 1}), "contact.surface"),
    (dict(SPHERE, pivot={"l": 0.1}), "contact"),
    (dict(SPHERE, quantities={"w": "norm(omega)"}), "quantities"),
    (dict(body={"moments": [1, 1, 0.1], "mass": 1}, pivot={"l": 0.2, "path": ["0", "0", "q0"]}), "pivot.path[2]"),
    (dict(body={"moments": [1, 1, 0.1], "mass": 1}, pivot={"l": 0.2, "path": "t"}), "pivot.path"),
])
def test_bad_contact_and_path_sections_name_the_key(kwargs, key):
    with pytest.raises(InvalidInput) as info:
        Model(**kwargs)
    assert info.value.argument == key


def test_a_position_without_a_contact_is_refused_by_its_key():
    with pytest.raises(InvalidInput) as info:
        Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1, position=(0, 0))
    assert info.value.argument == "position"


def test_a_200_member_tippe_top_spin_sweep_equals_200_single_runs_and_inverts_above_the_threshold():
    """Rauch-Wojciechowski & Rutstam's threshold λ_thres = √(m g R³ I3 α)(1+α)²/√(1+α−γ) on Jellett's λ (∝ the spin
    at one start): 200 spins from 0.5 to 1.7 λ_thres in one sweep; each member equals its own single run to the
    accuracy asked; within 5 s none below 0.8 λ_thres reaches its stem, all above 1.25 do, and the inverted members
    are those above one spin (a single switch)."""
    from eulersym.model.contact_motion import start
    from eulersym.scene import model_kernel

    model = Model.from_toml(bundled()["tippe-top"])
    module = model_kernel.ensure(model, [])[0]
    p = dict(zip(module.PARAMETERS, module.DEFAULTS))
    M, R, alpha, I3, gamma = p["M"], p["R"], p["alpha"], p["I3"], p["gamma_ratio"]
    threshold = np.sqrt(M * 9.81 * R ** 3 * I3 * alpha) * (1 + alpha) ** 2 / np.sqrt(1 + alpha - gamma)
    q = (np.cos(0.05), np.sin(0.05), 0.0, 0.0)  # 0.1 rad about x, as the scene starts
    jellett = module.invariants(0.0, start(module, omega=(0, 0, 1.0), q=q), *module.DEFAULTS)
    spin = threshold / abs(jellett[module.INVARIANTS.index("Jellett")])  # the spin at λ_thres
    factors = np.linspace(0.5, 1.7, 200)
    settings = dict(model=model, axis=(1, 0, 0), angle=0.1, t_end=5.0, points=26, accuracy=1e-6)
    sweep = simulate(Scene(omega=(0, 0, {"start": 0.5 * spin, "stop": 1.7 * spin, "num": 200}), **settings))
    assert sweep.plan.batch == 200 and sweep.plan.options["engine"] == "contact_dop853"
    for b, factor in enumerate(factors):
        single = simulate(Scene(omega=(0, 0, float(factor * spin)), **settings))
        scale = np.max(np.abs(single.omega))
        assert np.max(np.abs(sweep.omega[b] - single.omega)) <= 1e-6 * scale
        assert np.max(np.abs(sweep.gamma[b] - single.gamma)) <= 1e-6
    on_stem = np.all(sweep.gamma[:, -5:, 2] < -0.99, axis=1)
    assert not on_stem[factors < 0.8].any() and on_stem[factors > 1.25].all()
    switch = int(np.argmax(on_stem))
    assert on_stem[switch:].all() and not on_stem[:switch].any()  # one switch, between 0.8 and 1.25 λ_thres


def test_the_contact_trace_is_the_figure_chosen_for_a_body_on_a_plane_and_draws_the_runs_quantities(tmp_path):
    pytest.importorskip("matplotlib")
    from eulersym.figures import fitting, plot
    from eulersym.figures.contact_trace import figure

    run = simulate(Scene(model=Model(**SPHERE), omega=(0, 10, 0), t_end=1, points=11))
    assert fitting(run) == ["panels", "contact-trace"]
    fig = figure(run)
    above, force = fig.axes[:2]
    x_P, y_P = above.get_lines()[0].get_data()
    assert np.array_equal(x_P, run.quantities["x_P"]) and np.array_equal(y_P, run.quantities["y_P"])
    assert np.allclose(force.get_lines()[0].get_ydata(), 9.81)  # N = M g: a sphere rolling on a straight line
    paths = plot(run, str(tmp_path / "ball.png"))
    assert [p.rsplit("/", 1)[1] for p in paths] == ["ball.png", "ball.contact-trace.png"]
    assert open(paths[1], "rb").read(4) == b"\x89PNG"


@pytest.mark.parametrize("argv", [
    ["derive", "--model", "{path}"],
    ["verify", "--model", "{path}", "--integral", "dot(omega, inertia*omega)"],
    ["generate", "--model", "{path}", "--target", "c", "--dir", "{dir}"],
])
def test_the_free_body_commands_refuse_a_body_on_a_plane_by_its_key(argv, tmp_path, capsys):
    """derive/verify/generate --model derive the free or pivoted body's equations: on a contact body they would
    answer for another body (the Chaplygin ball's ω·Iω is not conserved while it rolls) — refused, exit 2."""
    path = bundled()["chaplygin-ball"]
    assert main([a.format(path=path, dir=tmp_path) for a in argv]) == 2
    err = capsys.readouterr().err
    assert "--model='chaplygin-ball'" in err and "[contact]" in err and "Traceback" not in err
    assert not any(tmp_path.iterdir())
    assert not Model.from_toml(path).prove("dot(omega, inertia*omega)").conserved  # the model itself answers right


def test_a_contact_model_answers_for_its_own_body_or_refuses_by_name():
    model = Model(**SPHERE)
    assert [s.name for s in model.equations().state] == list(model.compile().STATE)  # Newton–Euler with the contact
    with pytest.raises(InvalidInput) as info:
        model.lagrangian()  # nonholonomic: no Lagrangian answers for it
    assert info.value.argument == "model" and "[contact]" in str(info.value)


def test_a_streamed_contact_sweep_keeps_its_contact_outputs_the_one_pass_bits():
    """Summaries and Dask chunks carry the contact point, normal force and height as the one pass does (they were
    dropped on the streamed paths before the lead wired ``scene.chunked``)."""
    from eulersym.sweeps import distributed

    radii = list(np.linspace(0.05, 0.2, 12))

    def scene(**kwargs):
        return Scene(model=Model(**SPHERE), parameters={"a": radii}, omega=(0, 10, 0), t_end=1, points=11, **kwargs)

    one = simulate(scene())
    summary = simulate(scene(outputs=("omega", "summary")))
    assert np.array_equal(summary.summary["N.max"], one.quantities["N"].max(axis=1))
    assert np.array_equal(summary.summary["x_cm.final"], one.quantities["x_cm"][:, -1])
    assert not any("contact outputs" in note for note in summary.notes)
    client = distributed.local_client(2, processes=False)
    try:
        there = simulate(scene(), client=client)
    finally:
        distributed.close(client)
    assert set(there.quantities) == set(one.quantities)
    assert all(np.array_equal(there.quantities[k], one.quantities[k]) for k in one.quantities)


def test_generate_model_writes_a_body_on_a_plane_its_contact_kernel_and_checks_it(tmp_path, capsys):
    """``eulersym generate --model`` on a model with [contact] writes the contact kernel (the bytes of
    ``Model.generate``), and ``--check`` passes on it and fails (exit 1) once it is stale."""
    import importlib.util

    path = bundled()["rolling-sphere"]
    assert main(["generate", "--model", path, "--dir", str(tmp_path)]) == 0
    written = tmp_path / "rolling_sphere.py"
    assert capsys.readouterr().out.strip() == f"wrote {written}"
    assert main(["generate", "--model", path, "--dir", str(tmp_path), "--check"]) == 0
    spec = importlib.util.spec_from_file_location("rolling_sphere_kernel", written)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert list(module.STATE) == list(Model.from_toml(path).compile().STATE) and hasattr(module, "lift_off")
    written.write_text(written.read_text() + "# edited\n")
    assert main(["generate", "--model", path, "--dir", str(tmp_path), "--check"]) == 1
    assert "stale" in capsys.readouterr().err


def test_a_contact_sweep_streamed_to_zarr_and_a_run_saved_to_zarr_hold_the_contact_outputs(tmp_path):
    """``-o out.zarr``: the contact point, N and the height are ``quantity_<name>`` arrays over (member, time), streamed
    chunk by chunk or written from memory, equal to the one pass's (they were dropped from stores before)."""
    import xarray

    from eulersym.scene import cost as scene_cost
    from eulersym.scene.io import save, stream
    from eulersym.sweeps import zarr_store

    radii = list(np.linspace(0.05, 0.2, 12))

    def scene(a=radii):
        return Scene(model=Model(**SPHERE), parameters={"a": a}, omega=(0, 10, 0), t_end=1, points=11)

    one = simulate(scene())
    target = str(tmp_path / "streamed.zarr")
    with zarr_store.streaming(target):  # a budget that forces chunks of two members
        small = scene_cost.estimate(scene(), one.plan)
        budget = small.output_bytes + small.per_member_working * 2 * scene_cost.threads(one.plan)
        assert scene_cost.estimate(scene(), one.plan, memory=budget).chunk < len(radii)
    stream(scene(), target, memory=budget)
    save(one, str(tmp_path / "saved.zarr"))
    single = simulate(scene(0.1))
    save(single, str(tmp_path / "single.zarr"))
    for name in ("streamed", "saved"):
        ds = xarray.open_zarr(str(tmp_path / f"{name}.zarr"))
        for key, values in one.quantities.items():
            assert ds[f"quantity_{key}"].dims == ("member", "time")
            assert np.array_equal(ds[f"quantity_{key}"].values, values), (name, key)
    ds = xarray.open_zarr(str(tmp_path / "single.zarr"))
    assert np.array_equal(ds["quantity_N"].values[0], single.quantities["N"])
