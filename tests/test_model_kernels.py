"""eulersym.model.kernels: a model's emitted module — contract, reproducibility, SymPy-free import, flavours agree."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import model_bodies as B
from eulersym.errors import InvalidInput
from eulersym.model import derive, integrals, kernels
from eulersym.model.mechanics import Mechanics

ROOT = Path(__file__).resolve().parents[1]
TESTS = Path(__file__).resolve().parent
BODIES = ("lagrange_top", "kovalevskaya", "heavy_asymmetric", "gyrostat", "damped", "spin_up", "satellite")


def _state(kernel, rng, batch=()):
    n = len(kernel.STATE)
    y = rng.normal(size=(n, *batch))
    if "gamma1" in kernel.STATE:
        y[3:6] /= np.linalg.norm(y[3:6], axis=0)
    y[-4:] /= np.linalg.norm(y[-4:], axis=0)
    return y


def _lambdified(mech):
    eqs = derive.equations(mech)
    args = [B.t, list(eqs.state), *mech.parameter_symbols]
    rhs = sp.lambdify(args, list(eqs.rhs), modules="math")
    jac = sp.lambdify(args, sp.Matrix(eqs.rhs).jacobian(list(eqs.state)).tolist(), modules="math")
    return rhs, jac


@pytest.mark.parametrize("body", BODIES)
def test_scalar_batched_and_lambdify_agree(body, rng):
    mech = getattr(B, body)()
    kernel = kernels.compile(mech)
    rhs_ref, jac_ref = _lambdified(mech)
    params = kernel.DEFAULTS
    for _ in range(3):
        y = _state(kernel, rng)
        t = float(rng.uniform(0, 5))
        assert np.allclose(kernel.rhs(t, y, *params), rhs_ref(t, list(y), *params), rtol=1e-13, atol=1e-13)
        assert np.allclose(kernel.jac(t, y, *params), jac_ref(t, list(y), *params), rtol=1e-13, atol=1e-13)
    for size in (0, 1, 17):
        Y = _state(kernel, rng, (size,))
        T = rng.uniform(0, 5, size=size)
        out = kernel.rhs_batched(T, Y, *params)
        assert out.shape == (len(kernel.STATE), size)
        ref = np.array([kernel.rhs(T[j], Y[:, j], *params) for j in range(size)]).T.reshape(out.shape)
        assert np.allclose(out, ref, rtol=1e-13, atol=1e-14)
        inv = kernel.invariants_batched(T, Y, *params, out=np.empty((len(kernel.INVARIANTS), size)))
        ref = np.array([kernel.invariants(T[j], Y[:, j], *params) for j in range(size)]).T.reshape(inv.shape)
        assert np.allclose(inv, ref, rtol=1e-13, atol=1e-14)


def test_parameters_broadcast_over_the_batch(rng):
    kernel = kernels.compile(B.damped())
    Y = _state(kernel, rng, (5,))
    c = np.linspace(0.0, 1.0, 5)
    out = kernel.rhs_batched(0.0, Y, c)
    for j in range(5):
        assert np.allclose(out[:, j], kernel.rhs(0.0, Y[:, j], c[j]))


def test_jacobian_matches_central_differences(rng):
    kernel = kernels.compile(B.heavy_asymmetric())
    y = _state(kernel, rng)
    J = np.array(kernel.jac(0.3, y, *kernel.DEFAULTS))
    eps = 1e-6
    for j in range(len(y)):
        e = np.zeros_like(y)
        e[j] = eps
        column = (np.array(kernel.rhs(0.3, y + e, *kernel.DEFAULTS)) - np.array(kernel.rhs(0.3, y - e, *kernel.DEFAULTS)))
        assert np.allclose(J[:, j], column / (2 * eps), atol=1e-7)


def test_contract_constants():
    kernel = kernels.compile(B.kovalevskaya())
    assert kernel.STATE == ("omega1", "omega2", "omega3", "gamma1", "gamma2", "gamma3", "q0", "q1", "q2", "q3")
    assert kernel.PARAMETERS == ("I3", "M", "a", "g") and kernel.DEFAULTS == (1.0, 1.0, 1.0, 9.81)
    assert kernel.INVARIANTS == ("E", "Gamma_norm2", "L_dot_Gamma", "q_norm2", "K")
    assert kernel.INVARIANTS == tuple(n for n, v in integrals.invariants(B.kovalevskaya()).items() if v.conserved)
    assert kernel.FLAGS == {"pivoted": True, "gravity": True, "torque": False, "potential": False, "rotor": False,
                            "time": False}
    assert kernels.compile(B.satellite()).FLAGS["time"] is True
    assert kernels.compile(B.heavy_asymmetric()).FLAGS["rotor"] is True
    body = kernel.body(0.5, 2.0, 0.1, 9.8)
    assert body == [2.0, 0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 9.8]
    assert all(isinstance(x, float) for x in body)
    with pytest.raises(InvalidInput, match="positional"):
        kernel.body(1, 2, 3, 4, 5)


def test_invariants_of_the_kernel_are_the_proven_expressions(rng):
    mech = B.lagrange_top()
    kernel = kernels.compile(mech)
    verdicts = integrals.invariants(mech)
    y = _state(kernel, rng)
    values = kernel.invariants(0.0, y, *kernel.DEFAULTS)
    point = {**dict(zip(derive.equations(mech).state, y)), **{s: v for s, v in mech.parameters}}
    for name, value in zip(kernel.INVARIANTS, values):
        assert abs(float(verdicts[name].expression.xreplace(point)) - value) < 1e-12


_RENDER = """
import hashlib, sys
sys.path.insert(0, {tests!r})
import model_bodies as B
from eulersym.model import kernels
for body in {bodies!r}:
    print(body, hashlib.sha256(kernels.source(getattr(B, body)(), digest="ab" * 32).encode()).hexdigest())
"""


def test_bytes_do_not_depend_on_pythonhashseed():
    code = _RENDER.format(tests=str(TESTS), bodies=("kovalevskaya", "heavy_asymmetric", "damped"))
    runs = [subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env={**os.environ, "PYTHONHASHSEED": seed}) for seed in ("0", "4242")]
    outputs = [run.communicate() for run in runs]
    assert all(run.returncode == 0 for run in runs), [err for _, err in outputs]
    assert outputs[0][0] == outputs[1][0] and len(outputs[0][0].splitlines()) == 3


_BLOCKED = """
import sys, importlib.util
sys.modules["sympy"] = None
spec = importlib.util.spec_from_file_location("kov", {path!r})
module = importlib.util.module_from_spec(spec)
spec.loader.exec_module(module)
assert not [k for k, v in sys.modules.items() if v is not None and k.split(".")[0] in ("sympy", "mpmath")]
print(module.rhs(0.0, [0.1, 0.2, 0.3, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0], *module.DEFAULTS)[1])
"""


def test_generated_file_imports_without_sympy_and_checks(tmp_path):
    mech = B.kovalevskaya()
    path = kernels.generate(mech, tmp_path, digest="cd" * 32)
    assert path == tmp_path / "kovalevskaya.py"
    text = path.read_text()
    assert "# Model digest: sha256:" + "cd" * 32 in text and text.startswith("# Generated by `eulersym generate`")
    result = subprocess.run([sys.executable, "-c", _BLOCKED.format(path=str(path))], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    reference = kernels.compile(mech).rhs(0.0, [0.1, 0.2, 0.3, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0], *(1.0, 1.0, 1.0, 9.81))
    assert float(result.stdout) == reference[1]
    # --check: ok as written; a hand edit, a missing file and another model fail
    assert kernels.check(mech, tmp_path, digest="cd" * 32).ok
    assert not kernels.check(mech, tmp_path).ok  # the digest line differs
    path.write_text(text.replace("return", "return ", 1))
    assert not kernels.check(mech, tmp_path, digest="cd" * 32).ok
    assert not kernels.check(B.lagrange_top(), tmp_path).ok


def test_check_across_sympy_versions_compares_the_header(tmp_path):
    mech = B.damped()
    path = kernels.generate(mech, tmp_path)
    text = path.read_text()
    other = text.replace(f"# SymPy version: {sp.__version__}", "# SymPy version: 0.0.1").replace("x0", "z0")
    path.write_text(other)
    report = kernels.check(mech, tmp_path)
    assert report.ok and "code not compared" in report.notes[0]
    path.write_text(other.replace("# Input hash: sha256:", "# Input hash: sha256:0"))
    assert not kernels.check(mech, tmp_path).ok


def test_generated_equals_compiled(tmp_path, rng):
    mech = B.heavy_asymmetric()
    path = kernels.generate(mech, tmp_path, name="general_body")
    spec = importlib.util.spec_from_file_location("general_body", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    kernel = kernels.compile(mech)
    y = _state(kernel, rng)
    assert module.rhs(0.1, y, *module.DEFAULTS) == kernel.rhs(0.1, y, *kernel.DEFAULTS)


def test_bad_input(tmp_path):
    x = sp.Symbol("y", positive=True)
    clash = Mechanics(name="clash", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1),
                      torque=sp.ImmutableMatrix([x, 0, 0]), parameters=((x, 1.0),))
    with pytest.raises(InvalidInput, match="parameter name other than"):
        kernels.source(clash)
    with pytest.raises(InvalidInput, match="identifier"):
        kernels.generate(B.damped(), tmp_path, name="no good")
    with pytest.raises(InvalidInput, match="hex digest"):
        kernels.source(B.damped(), digest="xyz")
    (tmp_path / "file").write_text("")
    with pytest.raises(InvalidInput, match="folder"):
        kernels.generate(B.damped(), tmp_path / "file")
    assert kernels.module_name(B.spin_up()) == "spin_up"


def test_bench_models_quick_runs_end_to_end(capsys):
    """`eulersym bench models --quick` runs (its figures are not asserted: timings are not tests)."""
    from eulersym.bench import available
    from eulersym.bench.models import main

    assert "models" in available()
    assert main(["--quick"]) in (0, 1)
    out = capsys.readouterr().out
    assert "beyond SymPy" in out and "hand-written vectorised NumPy" in out and "DISAGREES" not in out
    assert "PyDy lambdify" in out  # the test extra installs PyDy: CI runs the peer's row
