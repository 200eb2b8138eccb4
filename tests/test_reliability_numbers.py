"""One check for numbers, wherever they come from (issue 26 §4): values reached through parameters and sweeps meet
the same bounds as numbers written in place; a parameter inside a turn derives its numbers or is refused by its TOML
key before a proof; parametric quaternions; tensors whose eigenvalues overflow.

Every refusal is an :class:`eulersym.errors.InvalidInput` naming the key (exit 2 from the CLI, no traceback).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from eulersym.errors import InvalidInput
from eulersym.model import Model
from eulersym.model.assemble import refuse_unprovable


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("EULERSYM_CACHE", str(tmp_path / "cache"))


def _eulersym(*args) -> subprocess.CompletedProcess:
    code = "import sys; from eulersym.cli import main; sys.exit(main(sys.argv[1:]))"
    return subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True, text=True,
                          env=dict(os.environ), timeout=120)


def _quaternion_matrix(q) -> np.ndarray:
    """R(q) for a unit q = (w, x, y, z), active (v_model = R v_part): written out here, independently of
    eulersym.rotation."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _at(matrix, value) -> np.ndarray:
    """A one-parameter SymPy matrix at ``value`` (30 digits), as floats."""
    return np.array(matrix.xreplace({x: value for x in matrix.free_symbols}).evalf(30).tolist(), dtype=float)


def _cuboid(**turn) -> dict:
    return {"shape": "cuboid", "mass": 1.0, "a": 1.0, "b": 2.0, "c": 3.0, **turn}


def _cuboid_tensor() -> np.ndarray:  # m (b² + c²) / 12, ... about its centre
    return np.diag([(4 + 9) / 12, (1 + 9) / 12, (1 + 4) / 12])


# ---- a parameter inside a turn -----------------------------------------------------------------------------------

def test_a_parameter_inside_an_angle_builds_its_numbers_and_is_refused_before_a_proof():
    k = 0.3
    model = Model(parameters={"k": k}, body={"parts": [_cuboid(axis=[1, 0, 0], angle="k")]})
    R = _quaternion_matrix([np.cos(k / 2), np.sin(k / 2), 0, 0])
    expected = R @ _cuboid_tensor() @ R.T
    assert np.allclose(model.facts().tensor[0], expected, rtol=0, atol=1e-14)
    symbolic = _at(model.mechanics.inertia, k)
    assert np.allclose(symbolic, expected, rtol=0, atol=1e-14)
    with pytest.raises(InvalidInput) as info:
        refuse_unprovable(model)
    assert info.value.argument == "body.parts[0].orientation.angle" and "cos(k)" in str(info.value)


def test_a_turned_body_whose_kernel_needs_proofs_is_refused_by_key_from_the_cli(tmp_path):
    path = tmp_path / "angle.toml"
    path.write_text(textwrap.dedent("""\
        name = "angle"
        [parameters]
        k = 0.3
        [[body.parts]]
        shape = "cuboid"
        mass = 1.0
        dimensions = { a = 1.0, b = 2.0, c = 3.0 }
        orientation = { axis = [1, 0, 0], angle = "k" }
        [torque]
        body = "-0.1*omega"
        [initial]
        omega = [0.2, 1.0, 0.3]
        [time]
        end = 1.0
        points = 11
        """))
    for args in (("simulate", path), ("derive", "--model", path), ("verify", "--model", path, "--integral", "omega1")):
        run = _eulersym(*args)
        assert run.returncode == 2 and "Traceback" not in run.stderr, (args, run.stderr)
        assert "body.parts[0].orientation.angle='k'" in run.stderr and "PolynomialError" not in run.stderr


def test_a_proof_that_grows_past_its_budget_is_refused_naming_it(monkeypatch):
    from eulersym.model import cli

    monkeypatch.setattr(cli, "BUDGET_SECONDS", 0.5)
    with pytest.raises(Exception) as info:
        cli.verify(["--model", "damped", "--integral", "(gamma1+gamma2+gamma3+q0+q1+q2+q3)^5*(omega1+omega2)^5"])
    assert type(info.value).__name__ == "OverBudget", info.value
    assert "damped" in str(info.value) or "--integral" in str(info.value)


def test_a_turn_rational_in_a_parameter_is_proven():
    model = Model(parameters={"s": 0.5}, body={"parts": [_cuboid(quaternion=[1, 0, 0, "s"])]})
    refuse_unprovable(model)  # nothing to refuse
    R = _quaternion_matrix([1, 0, 0, 0.5])
    assert np.allclose(model.facts().tensor[0], R @ _cuboid_tensor() @ R.T, rtol=0, atol=1e-14)


# ---- parametric quaternions --------------------------------------------------------------------------------------

@pytest.mark.parametrize("a", [0.0, 0.4, 2.5])
def test_a_unit_quaternion_of_a_parameter_is_taken_as_written(a):
    model = Model(parameters={"a": a}, body={"parts": [_cuboid(quaternion=["cos(a/2)", 0, 0, "sin(a/2)"])]})
    R = _quaternion_matrix([np.cos(a / 2), 0, 0, np.sin(a / 2)])
    expected = R @ _cuboid_tensor() @ R.T
    assert np.allclose(model.facts().tensor[0], expected, rtol=0, atol=1e-14)
    symbolic = _at(model.mechanics.inertia, a)
    assert np.allclose(symbolic, expected, rtol=0, atol=1e-14)


@pytest.mark.parametrize("quaternion", [[0, 0, 0, "s"], ["s", "s", 0, 0], ["s - 0.5", 0, 0, 0]])
def test_a_quaternion_zero_at_the_defaults_is_refused_by_key(quaternion):
    s = 0.5 if "s - 0.5" in quaternion else 0.0
    with pytest.raises(InvalidInput) as info:
        Model(parameters={"s": s}, body={"parts": [_cuboid(quaternion=quaternion)]}).mechanics
    assert info.value.argument == "body.parts[0].orientation.quaternion" and "non-zero" in str(info.value)


# ---- numbers at the edge of double precision -------------------------------------------------------------------

@pytest.mark.parametrize("tensor", [
    [[1e308, 0, 0], [0, 1e308, 0], [0, 0, 1e308]],
    [[1e308, 1e307, 0], [1e307, 1e308, 0], [0, 0, 1e308]],
    [[1.7e308, 0, 0], [0, 1.7e308, 0], [0, 0, 1e308]],
])
def test_a_tensor_near_the_largest_double_is_validated_without_overflow(tensor):
    from eulersym.validation import inertia_tensor

    assert inertia_tensor("body.tensor", tensor).shape == (3, 3)  # a body; no LinAlgError, no overflow warning


def test_a_tensor_near_the_largest_double_that_is_no_body_is_refused_with_its_moments():
    from eulersym.validation import inertia_tensor

    with pytest.raises(InvalidInput, match=r"positive-definite tensor \(its principal moments are \[0.0, 1e\+308"):
        inertia_tensor("body.tensor", [[1e308, 1e308, 0], [1e308, 1e308, 0], [0, 0, 1e308]])


def test_the_1e308_tensor_is_refused_by_key_from_the_cli(tmp_path):
    path = tmp_path / "t308.toml"
    path.write_text('[body]\ntensor = [[1e308, 0, 0], [0, 1e308, 0], [0, 0, 1e308]]\n'
                    '[initial]\nomega = [0.2, 1.0, 0.3]\n[time]\nend = 1.0\npoints = 11\n')
    run = _eulersym("simulate", path)
    assert run.returncode == 2 and "Traceback" not in run.stderr and "LinAlgError" not in run.stderr, run.stderr
    assert "body.tensor=" in run.stderr


@pytest.mark.parametrize("where", ["parameters", "sweep"])
def test_numbers_through_parameters_meet_the_bounds_of_numbers_in_place(tmp_path, where):
    value = "1e300" if where == "parameters" else "[1.0, 1e300]"
    path = tmp_path / "big.toml"
    path.write_text(f'[parameters]\nI = {value}\n[body]\nmoments = ["I", "I", "I"]\n[torque]\nbody = "-0.1*omega"\n'
                    '[initial]\nomega = [0.2, 1.0, 0.3]\n[time]\nend = 1.0\npoints = 11\n')
    run = _eulersym("simulate", path, "-o", tmp_path / "out.npz")
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
    assert "body.moments=" in run.stderr and "below 1e+75" in run.stderr
    assert not (tmp_path / "out.npz").exists()


# ---- refusals name the TOML key ---------------------------------------------------------------------------------

@pytest.mark.parametrize("value", ["sqrt(-1)", "2*sqrt(-1)*k", "k + sqrt(-4)"])
def test_an_imaginary_number_is_refused_by_its_key(value):
    with pytest.raises(InvalidInput) as info:
        Model(parameters={"k": 1.0}, body={"moments": [1, value, 3]}).facts()
    assert info.value.argument == "body.moments[1]" and "imaginary unit" in str(info.value)


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_refusals_of_mutated_models_name_a_toml_key():
    """A seeded mutation of valid models, key by key, with hostile values: every refusal names a key of the model
    file (the audit found `expression=`, `function='sign'`, `name='np'`), and nothing else escapes."""
    import copy
    import random
    import re

    from eulersym.errors import EulersymError

    rng = random.Random(26)
    sections = {"name", "description", "parameters", "body", "pivot", "torque", "rotor"}
    values = [0, -1, 1e300, 1e-300, float("nan"), "k", "omega", "omega1", "gamma", "abs(omega1)", "sign(k)",
              "max(k, 1)", "inertia", "t", "q0", "k^70", "[1, 2, 3]", "cos(k)", [1, 2], [1, 2, 3],
              [[1, 0, 0], [0, 1, 0], [0, 0, 1]], {}, {"a": 1}, True, None, "", "x", "1/0", "np", "sqrt(-1)", "log(k)"]
    bases = [
        dict(parameters={"k": 0.5}, body={"moments": [1, 2, 3]}, torque={"body": "-k*omega"}),
        dict(parameters={"k": 0.5}, body={"moments": [1, 1, 2], "mass": 1}, pivot={"l": 0.1}),
        dict(parameters={"k": 0.5}, body={"shape": "cuboid", "mass": 1, "a": 1, "b": 2, "c": 3}),
        dict(parameters={"k": 0.5}, body={"parts": [{"shape": "sphere", "mass": 1, "R": 0.1, "position": [0, 0, 0.1]},
                                                    {"shape": "point", "mass": "k", "position": [0.1, 0, 0]}]}),
        dict(parameters={"k": 0.5}, body={"tensor": [[2, 0.1, 0], [0.1, 2, 0], [0, 0, 3]]}, rotor={"h": [0, 0, "k"]}),
    ]

    def paths(d, prefix=()):
        items = d.items() if isinstance(d, dict) else enumerate(d) if isinstance(d, list) else ()
        for k, v in items:
            yield prefix + (k,)
            yield from paths(v, prefix + (k,))

    for _ in range(120):
        data = copy.deepcopy(rng.choice(bases))
        path = rng.choice(list(paths(data)))
        target = data
        for k in path[:-1]:
            target = target[k]
        target[path[-1]] = rng.choice(values)
        try:
            model = Model(**data)
            model.facts()
            model.mechanics
        except InvalidInput as exc:
            assert re.split(r"[.\[]", exc.argument)[0] in sections, (path, str(exc))
        except EulersymError:
            pass


@pytest.mark.parametrize("where", ["initial.omega[0]", "parameters.k", "body.moments[2]"])
def test_a_sweep_of_a_billion_values_is_refused_before_any_array(where):
    from eulersym.scene import Scene

    data = {"parameters": {"k": 0.5}, "body": {"moments": [1, 2, 3]}, "torque": {"body": "-k*omega"},
            "initial": {"omega": [0.2, 1.0, 0.3]}, "time": {"end": 1.0, "points": 11}}
    big = {"start": 1.0, "stop": 2.0, "num": 10**9}  # 7.45 GiB as an array: a MemoryError, or the OOM killer
    if where == "initial.omega[0]":
        data["initial"]["omega"][0] = big
    elif where == "parameters.k":
        data["parameters"]["k"] = big
    else:
        data["body"]["moments"][2] = big
    with pytest.raises(InvalidInput, match=r"\.num=1000000000 is not valid: expected at most 1,000,000 values"):
        Scene.from_dict(data)


# ---- a right-hand side that leaves its domain -------------------------------------------------------------------

@pytest.mark.parametrize("torque, error", [("c*log(omega1 - 1)", "ValueError: math domain error"),
                                           ("c*exp(1000*omega2)", "OverflowError: math range error")])
def test_a_single_run_whose_kernel_leaves_its_domain_ends_in_a_named_error(tmp_path, torque, error):
    path = tmp_path / "domain.toml"
    path.write_text(f'[parameters]\nc = 0.1\n[body]\nmoments = [1.0, 2.0, 3.0]\n[torque]\nbody = ["{torque}", 0, 0]\n'
                    '[initial]\nomega = [0.2, 1.0, 0.3]\n[time]\nend = 1.0\npoints = 11\n')
    run = _eulersym("simulate", path, "-o", tmp_path / "out.npz")
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
    assert "could not get the motion" in run.stderr, run.stderr
    # named either by the Python kernel's own error (with its line) or by the compiled integrator that met the
    # non-finite value first — both say the right-hand side left its domain or the finite numbers
    assert error in run.stderr or "right-hand side left the finite numbers" in run.stderr, run.stderr
    assert "domain" in run.stderr
    assert not (tmp_path / "out.npz").exists()


def test_an_error_outside_the_kernel_is_not_disguised():
    from eulersym.scene.cli import _left_its_domain

    try:
        raise ValueError("a bug elsewhere")
    except ValueError as exc:
        assert _left_its_domain(exc, "auto") is exc


def test_a_sweep_whose_members_leave_their_domain_writes_no_nan(tmp_path):
    path = tmp_path / "sweep.toml"
    path.write_text('[parameters]\nc = [0.1, 0.2, 0.3]\n[body]\nmoments = [1.0, 2.0, 3.0]\n[torque]\n'
                    'body = ["c*log(omega1)", 0, 0]\n[initial]\nomega = [-0.2, 1.0, 0.3]\n[time]\nend = 1.0\n'
                    'points = 11\n')
    run = _eulersym("simulate", path, "-o", tmp_path / "out.csv")
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
    assert "3 of 3 members" in run.stderr and "0, 1, 2" in run.stderr, run.stderr  # every member named, no NaN written
    assert not (tmp_path / "out.csv").exists() and not (tmp_path / "out.summary.csv").exists()
