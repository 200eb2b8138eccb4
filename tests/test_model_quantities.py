"""Quantities a user defines (``[quantities]``): derived into the kernel, evaluated along runs, reported, written and
plotted; bad input refused by name; the Euler angles derived for every sequence."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from eulersym.errors import EulersymError, InvalidInput
from eulersym.model import Model
from eulersym.model.cli import load
from eulersym.models import bundled
from eulersym.rotation import CONVENTIONS, euler_matrix, to_euler, to_quaternion
from eulersym.scene import Scene, simulate


def test_damped_energy_decays_at_minus_c_omega_squared():
    """The bundled damped scene outputs its energy E = ½ ωᵀIω; along the run dE/dt = −c |ω|² (the rate the scene's
    description states), checked by the derivative of the output against −c |ω|² from the output ω."""
    scene = Scene.from_toml(bundled()["damped"])
    run = simulate(scene)
    E = run.quantities["energy"]
    c = scene.model.parameters["c"]
    I = np.array(scene.model.normalised["body"]["moments"])
    assert np.allclose(E, 0.5 * np.einsum("ni,i,ni->n", run.omega, I, run.omega), rtol=1e-14, atol=0)
    dt = run.t[1] - run.t[0]
    rate = (E[2:] - E[:-2]) / (2 * dt)  # central differences: O(dt²) = 4e-4 × the rate's second derivative
    expected = -c * np.sum(run.omega[1:-1] ** 2, axis=1)
    assert np.max(np.abs(rate - expected)) < 1e-4 * np.max(np.abs(expected))
    assert E[-1] < 0.2 * E[0]  # it decays


def test_report_columns_npz_and_panel(tmp_path):
    scene = Scene.from_toml(bundled()["damped"])
    run = simulate(scene)
    assert "quantity energy: min" in run.report()
    csv = tmp_path / "out.csv"
    from eulersym.scene.io import figure, save

    save(run, str(csv))
    head = csv.read_text().splitlines()[0].split(",")
    assert "energy" in head
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert np.allclose(table[:, head.index("energy")], run.quantities["energy"], rtol=1e-15)
    npz = tmp_path / "out.npz"
    save(run, str(npz))
    assert np.array_equal(np.load(npz)["quantity_energy"], run.quantities["energy"])
    fig = figure(run)
    assert "energy = E" in [ax.get_title() for ax in fig.axes]


def test_sweep_summary_keeps_each_quantity():
    body = Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"},
                 quantities={"energy": "E"})
    run = simulate(Scene(model=body, parameters={"c": [0.1, 0.2]}, omega=(0, 1, 0), t_end=2, points=21))
    from eulersym.scene.io import summary

    names, rows = summary(run)
    final = rows[:, names.index("energy_final")]
    assert np.allclose(final, np.exp(-np.array([0.1, 0.2]) * 2), rtol=1e-7)  # ω2 = e^{−ct/2} about e2 (I2 = 2)


def test_gyroscope_precession_rate_averages_to_the_slow_root():
    """The gyroscope's output precession rate φ̇ averages, over whole nutations, to the slow root of
    I1 cos θ φ̇² − I3 ω3 φ̇ + M g l = 0 (a fast top, Example 4.3's quadratic), with cos θ the mean of the turning
    points and ω3 the spin — computed here from the body's facts (NumPy), not by eulersym.top."""
    scene = Scene.from_toml(bundled()["gyroscope"])
    run = simulate(scene)
    f = scene.facts
    I1, I3 = f.tensor[0, 0, 0], f.tensor[0, 2, 2]
    Mgl = f.mass[0] * f.g[0] * f.centre_of_mass[0, 2]
    w3 = run.omega[0, 2]
    u = np.cos(np.mean(run.turning_points))
    slow = (I3 * w3 - np.sqrt((I3 * w3) ** 2 - 4 * I1 * u * Mgl)) / (2 * I1 * u)
    rate = run.quantities["precession"]
    gamma3 = run.gamma[:, 2]
    # whole nutation periods: from the first to the last maximum of the tilt's cosine
    peaks = np.flatnonzero((gamma3[1:-1] >= gamma3[:-2]) & (gamma3[1:-1] > gamma3[2:])) + 1
    mean = np.trapezoid(rate[peaks[0]:peaks[-1] + 1], run.t[peaks[0]:peaks[-1] + 1]) / (run.t[peaks[-1]] - run.t[peaks[0]])
    assert abs(mean - slow) < 2e-3 * slow


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_euler_angles_derived_for_every_sequence(convention):
    """φ, θ, ψ of a quantity (derived from A(φ, θ, ψ) and A = R(q)ᵀ) agree with eulersym.rotation.to_euler at
    seeded random attitudes, in SciPy's ranges."""
    from eulersym.model.mechanics import Q
    from eulersym.model.quantities import euler_angles
    import sympy as sp

    rng = np.random.default_rng(20)
    funcs = sp.lambdify(list(Q), list(euler_angles(convention)), "math")
    for _ in range(5):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        A = np.array(euler_matrix(*to_euler(_attitude(q), convention), convention=convention), dtype=float)
        got = np.array(funcs(*q))
        assert np.allclose(euler_matrix(*got, convention=convention), _attitude(q), atol=1e-12)
        assert np.allclose(got, to_euler(A, convention), atol=1e-12)


def _attitude(q):
    from eulersym.rotation import from_quaternion

    return np.array(from_quaternion(q), dtype=float)


def test_quantities_of_the_attitude_need_it_kept():
    body = Model(body={"moments": [1, 2, 3]}, quantities={"tilt": "theta"})
    run = simulate(Scene(model=body, omega=(0, 1, 0), t_end=1, points=3))
    with pytest.raises(InvalidInput, match="attitude"):
        run.quantities
    run = simulate(Scene(model=body, omega=(0, 1, 0), t_end=1, points=3, outputs=("omega", "attitude")))
    # a steady turn about e2 = space y from the identity: the body's e3 tilts from the vertical by θ = t exactly
    assert np.allclose(run.quantities["tilt"], run.t, atol=1e-9)


@pytest.mark.parametrize("table, key, words", [
    ({"x": "omga1"}, "quantities.x", "did you mean 'omega1'"),
    ({"x": "L"}, "quantities.x", "a scalar, not a vector"),
    ({"x": "omega"}, "quantities.x", "a scalar, not a vector"),
    ({"x": ["omega1"]}, "quantities.x", "one scalar expression string"),
    ({"omega1": "E"}, "quantities.omega1", "a name of its own"),
    ({"c": "E"}, "quantities.c", "a name of its own"),
    ({"1x": "E"}, "quantities.1x", "a quantity name"),
    ({"x": "K"}, "quantities.x", "an integral this model has"),
    ({"x": "E", "convention": "zxy2"}, "quantities.convention", "did you mean"),
    ({}, "quantities", "at least one quantity"),
    ({"x": "__import__('os')"}, "quantities.x", None),
])
def test_bad_quantities_are_refused_by_name(table, key, words):
    with pytest.raises(EulersymError) as info:
        Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, quantities=table).compile()
    assert key in str(info.value)
    if words:
        assert words in str(info.value)


_TOKENS = [*"omegaLEKthpsi123+-*/() ,[]._q", "dot", "norm", "cross", "sin", "atan2", "gamma", "omega", "theta",
           "E", "L", "**", "pi", "to_body"]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=st.lists(st.sampled_from(_TOKENS), max_size=12).map("".join))
def test_fuzz_quantity_text(text):
    """Any text: a quantity is derived, or refused with an eulersym error naming the key; never anything else."""
    from eulersym.model.quantities import expressions

    try:
        (name, expr), = expressions(Model(body={"moments": [1, 2, 3]}, quantities={"x": text}).mechanics)
    except EulersymError as exc:
        assert "quantities" in str(exc)
        return
    assert name == "x" and not getattr(expr, "is_Matrix", False)


@settings(max_examples=30, deadline=None)
@given(rate=st.lists(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.sampled_from(
    ["n", "omega1", "t", "nn", "2*n", "gamma", "[1, 2, 3]", ""])), min_size=0, max_size=4))
def test_fuzz_frame_rate(rate):
    """[frame] rate: three constants (numbers or expressions of the parameters), else an InvalidInput naming
    frame.rate."""
    try:
        Model(parameters={"n": 0.1}, body={"moments": [1, 2, 3]}, frame={"rate": rate})
    except InvalidInput as exc:
        assert "frame.rate" in str(exc)
        return
    assert len(rate) == 3


def test_cli_bad_quantity_exits_2(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text('[body]\nmoments = [1, 2, 3]\n[quantities]\nx = "omga1"\n')
    proc = subprocess.run([sys.executable, "-m", "eulersym", "derive", "--model", str(path)], capture_output=True,
                          text=True)
    assert proc.returncode == 2
    assert "quantities.x" in proc.stderr and "Traceback" not in proc.stderr


def test_model_round_trip_and_digest():
    m = load("damped")
    assert Model.from_dict(m.to_dict()) == m
    plain = Model(parameters={"c": 0.05}, body={"moments": [1, 2, 3]})
    assert "quantities" not in plain.to_dict() and "frame" not in plain.normalised


# ---- the scene's own quantities: Scene(quantities=...) and [output] quantities ----------------------------------------
def test_a_scene_adds_its_own_quantities_to_its_model(tmp_path):
    """``[output] quantities`` in a scene file (and ``Scene(quantities=...)``) reach the model's kernel: the report,
    the CSV columns, and the values themselves (the kinetic energy against ½ ωᵀIω computed here)."""
    import numpy as np

    from eulersym.scene import Scene, simulate

    path = tmp_path / "spin-down.toml"
    path.write_text('name = "spin-down"\n[body]\nmoments = [1.0, 2.0, 3.0]\n[torque]\nbody = "-0.2*omega"\n'
                    '[initial]\nomega = [0.1, 1.0, 0.1]\n[time]\nend = 2.0\npoints = 11\n'
                    '[output]\nquantities = { energy = { expression = "E", unit = "J" }, spin = "norm(omega)" }\n')
    scene = Scene.from_toml(path)
    result = simulate(scene)
    omega = result.omega
    assert np.allclose(result.quantities["energy"], 0.5 * (omega ** 2 * [1.0, 2.0, 3.0]).sum(axis=1), rtol=1e-13)
    assert np.allclose(result.quantities["spin"], np.linalg.norm(omega, axis=1), rtol=1e-13)
    assert "quantity energy:" in result.report() and "(J)" in result.report()
    keyword = Scene(model=scene.model, omega=(0.1, 1.0, 0.1), t_end=2.0, points=11, quantities={"tilt": "theta"},
                    outputs=("omega", "attitude"))
    assert "energy" in dict(keyword.model.to_dict()["quantities"]) and "tilt" in keyword.model.to_dict()["quantities"]


@pytest.mark.parametrize("quantities, key", [({"spin": "omega"}, "quantities.spin"),
                                             ({"x": "omegaa1"}, "quantities.x"),
                                             (3, "quantities")])
def test_a_scene_quantity_that_is_not_one_is_refused_by_key(quantities, key):
    from eulersym.scene import Scene, simulate

    with pytest.raises(InvalidInput) as info:  # names at construction; a vector where a scalar belongs at derivation
        simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1.0, 0.1), t_end=1, points=3, quantities=quantities)).quantities
    assert info.value.argument == key, info.value


def test_a_scene_keeps_the_meaning_of_its_models_angle_quantities():
    """The model's own phi/theta/psi keep their convention when a scene adds quantities; a table asking another is
    refused by key; an empty table adds nothing."""
    from eulersym.model import Model
    from eulersym.scene import Scene

    model = Model(body={"moments": [1, 2, 3]}, quantities={"yaw": "phi", "convention": "zyx"})
    scene = Scene(model=model, omega=(0.1, 1.0, 0.1), t_end=1, quantities={"tilt": "theta"})
    q = scene.model.to_dict()["quantities"]
    assert q["convention"] == "zyx" and q["yaw"] == "phi" and q["tilt"] == "theta"
    with pytest.raises(InvalidInput) as info:
        Scene(model=model, omega=(0.1, 1.0, 0.1), t_end=1, quantities={"tilt": "theta", "convention": "zxz"})
    assert info.value.argument == "quantities.convention"
    assert Scene(model=model, omega=(0.1, 1.0, 0.1), t_end=1, quantities={}).model == model
