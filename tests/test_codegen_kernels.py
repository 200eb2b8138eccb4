"""The committed kernels of generated/: agreement with their derivations, Jacobians, batches, solve_ivp,
conservation laws, and import without SymPy (from the source tree and from an installed wheel)."""

from __future__ import annotations

import importlib
import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from eulersym.codegen import CATALOGUE, available, build
from eulersym.errors import InvalidInput

ROOT = Path(__file__).resolve().parents[1]
ODE_KERNELS = [n for n in CATALOGUE if n != "kinematics" and available(n)[0]]
METHODS = ["RK45", "DOP853", "Radau", "BDF", "LSODA"]


def _unit(rng, n):
    v = rng.normal(size=n)
    return v / np.linalg.norm(v)


def _point(name, rng):
    """A random state and parameters for an ODE kernel (physical: positive-definite inertia, unit q and Γ)."""
    if name == "euler_principal":
        return rng.normal(size=3), (1.0, 2.0, 2.5, *rng.normal(size=3))
    if name == "euler_full":
        A = rng.normal(size=(3, 3))
        I = A @ A.T + 2 * np.eye(3)
        return rng.normal(size=3), (I[0, 0], I[0, 1], I[0, 2], I[1, 1], I[1, 2], I[2, 2], *rng.normal(size=3))
    if name == "free_body_quaternion":
        return np.concatenate([rng.normal(size=3), _unit(rng, 4)]), (1.0, 2.0, 2.5)
    if name == "heavy_top_euler_angles":
        return (np.array([rng.uniform(-3, 3), rng.uniform(0.4, 2.7), rng.uniform(-3, 3), *rng.normal(size=3)]),
                (1.0, 0.6, 1.2, 9.81, 0.3))
    if name == "heavy_top_euler_poisson":
        return np.concatenate([rng.normal(size=3), _unit(rng, 3), _unit(rng, 4)]), (1.0, 1.6, 2.2, 1.2, 9.81, 0.3)
    raise KeyError(name)


def _module(name):
    return importlib.import_module(f"eulersym.generated.{name}")


def _lambdified(name, function):
    """The derivation's expressions for ``function``, evaluated with mpmath at 30 digits (no CSE, no printer)."""
    spec = next(f for f in build(name).functions if f.name == function)
    symbols = list(spec.symbols)
    f = sp.lambdify(symbols, spec.expressions, modules="mpmath")

    def evaluate(*args):
        flat = []
        for value in args:
            flat.extend(np.atleast_1d(value).tolist())
        return np.array(f(*[sp.Float(v, 30) for v in flat]).tolist(), dtype=float)

    return evaluate


def _close(got, ref, rtol=1e-13):
    got, ref = np.asarray(got, dtype=float), np.asarray(ref, dtype=float)
    scale = np.maximum(np.abs(ref), np.max(np.abs(ref)) * 1e-3 + 1e-300)
    return np.all(np.abs(got - ref) <= rtol * np.maximum(scale, 1e-12))


# ---------------------------------------------------------------------------------------------------------------
# Agreement with the derivation


@pytest.mark.parametrize("name", ODE_KERNELS)
@pytest.mark.parametrize("function", ["rhs", "jac", "invariants"])
def test_kernel_equals_lambdified_derivation(name, function, rng):
    mod = _module(name)
    ref = _lambdified(name, function)
    for _ in range(10):
        y, p = _point(name, rng)
        got = np.array(getattr(mod, function)(0.0, y, *p))
        want = ref(0.0, y, *p).reshape(got.shape)
        assert _close(got, want), (got, want)


def test_kinematics_equals_lambdified_derivation(rng):
    mod = _module("kinematics")
    for _ in range(10):
        angles, rates = rng.uniform(-3, 3, 3), rng.normal(size=3)
        assert _close(mod.attitude_matrix(*angles), _lambdified("kinematics", "attitude_matrix")(*angles).reshape(3, 3))
        assert _close(mod.omega_body(*angles, *rates), _lambdified("kinematics", "omega_body")(*angles, *rates).ravel())


def test_kinematics_matches_scipy_rotation(rng):
    from scipy.spatial.transform import Rotation

    mod = _module("kinematics")
    angles = rng.uniform(-3, 3, (3, 5))
    A = mod.attitude_matrix_batched(*angles)
    for k in range(5):
        ref = Rotation.from_euler("ZXZ", angles[:, k]).as_matrix().T
        np.testing.assert_allclose(A[:, :, k], ref, atol=1e-14)


def test_omega_body_is_the_rotation_rate_of_A(rng):
    """Independent check: [ω]× = −Ȧ Aᵀ with Ȧ from central differences of the generated A."""
    mod = _module("kinematics")
    angles, rates = rng.uniform(0.3, 2.5, 3), rng.normal(size=3)
    h = 1e-6
    A = np.array(mod.attitude_matrix(*angles))
    Adot = (np.array(mod.attitude_matrix(*(angles + h * rates))) - np.array(mod.attitude_matrix(*(angles - h * rates)))) / (2 * h)
    W = -Adot @ A.T
    np.testing.assert_allclose([W[2, 1], W[0, 2], W[1, 0]], mod.omega_body(*angles, *rates), atol=1e-8)


@pytest.mark.parametrize("name", ODE_KERNELS)
def test_jacobian_matches_central_differences(name, rng):
    mod = _module(name)
    y, p = _point(name, rng)
    J = np.array(mod.jac(0.0, y, *p))
    n = len(y)
    assert J.shape == (n, n)
    for j in range(n):
        h = 1e-6 * max(1.0, abs(y[j]))
        e = np.zeros(n)
        e[j] = h
        column = (np.array(mod.rhs(0.0, y + e, *p)) - np.array(mod.rhs(0.0, y - e, *p))) / (2 * h)
        np.testing.assert_allclose(J[:, j], column, rtol=1e-6, atol=1e-7)


# ---------------------------------------------------------------------------------------------------------------
# Flavours, batches, bad input


@pytest.mark.parametrize("name", ODE_KERNELS)
@pytest.mark.parametrize("size", [0, 1, 9])
def test_batched_agrees_with_scalar(name, size, rng):
    mod = _module(name)
    points = [_point(name, rng) for _ in range(max(size, 1))][:size]
    p = _point(name, rng)[1]
    n = len(_point(name, rng)[0])
    Y = np.array([y for y, _ in points]).T.reshape(n, size)
    for function in ("rhs", "jac", "invariants"):
        batched = getattr(mod, function + "_batched")(0.0, Y, *p)
        scalar = [np.array(getattr(mod, function)(0.0, Y[:, k], *p)) for k in range(size)]
        assert batched.shape[-1] == size
        for k in range(size):
            np.testing.assert_allclose(batched[..., k], scalar[k], rtol=1e-14, atol=1e-14)
        out = np.empty_like(batched)
        assert getattr(mod, function + "_batched")(0.0, Y, *p, out=out) is out
        np.testing.assert_array_equal(out, batched)


@pytest.mark.parametrize("name", ODE_KERNELS)
def test_parameters_broadcast_over_the_batch(name, rng):
    mod = _module(name)
    (y1, p1), (y2, p2) = _point(name, rng), _point(name, rng)
    Y = np.stack([y1, y2], axis=1)
    P = [np.array([a, b]) for a, b in zip(p1, p2)]
    out = mod.rhs_batched(0.0, Y, *P)
    np.testing.assert_allclose(out[:, 0], mod.rhs(0.0, y1, *p1), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(out[:, 1], mod.rhs(0.0, y2, *p2), rtol=1e-14, atol=1e-14)


@pytest.mark.parametrize("name", ODE_KERNELS)
def test_wrong_state_length_names_the_order(name, rng):
    mod = _module(name)
    y, p = _point(name, rng)
    order = ", ".join(build(name).functions[0].arguments[1].names)
    with pytest.raises(InvalidInput, match=rf"order \({order}\)"):
        mod.rhs(0.0, np.append(y, 1.0), *p)
    with pytest.raises(InvalidInput, match=rf"order \({order}\)"):
        mod.rhs(0.0, list(y[:-1]), *p)
    with pytest.raises(InvalidInput, match=rf"order \({order}\)"):
        mod.rhs_batched(0.0, np.ones((len(y) + 1, 4)), *p)
    with pytest.raises(TypeError, match="missing"):
        mod.rhs(0.0, y, *p[:-1])
    names = ", ".join(a.name for a in build(name).functions[0].arguments)
    with pytest.raises(InvalidInput, match=rf"order \({names}\)"):
        mod.rhs(0.0, y, *p, 1.0)
    with pytest.raises(InvalidInput, match=rf"order \({names}\)"):
        mod.rhs_batched(0.0, y[:, None], *p, 1.0)
    with pytest.raises(InvalidInput, match="out"):
        mod.rhs_batched(0.0, np.ones((len(y), 4)), *p, out=np.empty((len(y), 5)))
    Y = np.ones((len(y), 4))
    with pytest.raises(InvalidInput, match="overlapping"):
        mod.rhs_batched(0.0, Y, *p, out=Y)


def test_heavy_top_in_euler_angles_refuses_the_singular_attitude_loudly():
    mod = _module("heavy_top_euler_angles")
    from eulersym.errors import SingularConfiguration

    for theta in (0.0, -0.0):
        with pytest.raises(SingularConfiguration, match=r"theta=-?0\.0 is not valid: expected sin\(theta\) != 0"):
            mod.rhs(0.0, [0.0, theta, 0.0, 1.0, 0.0, 1.0], 1.0, 0.5, 1.0, 9.81, 0.3)
        with pytest.raises(SingularConfiguration, match="heavy_top_euler_poisson"):
            mod.jac(0.0, [0.0, theta, 0.0, 1.0, 0.0, 1.0], 1.0, 0.5, 1.0, 9.81, 0.3)
    with pytest.raises(ZeroDivisionError):  # I1 = 0 is not the attitude's fault: not blamed on theta
        mod.rhs(0.0, [0.0, 0.5, 0.0, 1.0, 0.0, 1.0], 0.0, 0.5, 1.0, 9.81, 0.3)


@pytest.mark.parametrize("name", ODE_KERNELS)
def test_scalar_rhs_never_reuses_its_result(name, rng):
    mod = _module(name)
    y, p = _point(name, rng)
    first = mod.rhs(0.0, y, *p)
    kept = list(first)
    second = mod.rhs(0.0, y * 1.1, *p)
    assert first is not second and first == kept
    a = mod.rhs_batched(0.0, y[:, None], *p)
    b = mod.rhs_batched(0.0, 1.1 * y[:, None], *p)
    assert a is not b and not np.shares_memory(a, b)


# ---------------------------------------------------------------------------------------------------------------
# solve_ivp and conservation laws


def _reference_solution(name, y0, p, T):
    """DOP853 at tight tolerance over the derivation lambdified with NumPy (no generated code)."""
    spec = build(name).functions[0]
    f = sp.lambdify(list(spec.symbols), list(spec.expressions), modules="numpy", cse=True)
    sol = solve_ivp(lambda t, y: f(t, *y, *p), (0, T), y0, method="DOP853", rtol=1e-12, atol=1e-12)
    return sol.y[:, -1]


@pytest.mark.parametrize("name", ODE_KERNELS)
def test_every_scipy_method_agrees_with_the_reference(name, rng):
    mod = _module(name)
    y0, p = _point(name, rng)
    if name == "heavy_top_euler_angles":
        y0[1] = 1.0  # stay away from sin θ = 0 over the interval
    T = 1.0
    ref = _reference_solution(name, y0, p, T)
    for method in METHODS:
        kwargs = {"jac": mod.jac} if method in ("Radau", "BDF", "LSODA") else {}
        sol = solve_ivp(mod.rhs, (0, T), y0, method=method, args=p, rtol=1e-9, atol=1e-11, **kwargs)
        assert sol.success, (method, sol.message)
        np.testing.assert_allclose(sol.y[:, -1], ref, rtol=1e-5, atol=1e-6, err_msg=method)


def test_a_buffer_reusing_rhs_would_be_caught():
    """Negative control (issue item 5): returning one reused buffer, as PyDy's kernels do, breaks BDF."""
    mod = _module("heavy_top_euler_angles")
    p, y0 = (1.0, 0.6, 1.2, 9.81, 0.3), np.array([0.1, 1.0, 0.2, 0.5, 0.3, 12.0])
    ref = _reference_solution("heavy_top_euler_angles", y0, p, 1.0)
    buffer = np.empty(6)

    def reusing(t, y, *params):
        buffer[:] = mod.rhs(t, y, *params)
        return buffer

    bad = solve_ivp(reusing, (0, 1), y0, method="BDF", args=p, rtol=1e-9, atol=1e-11).y[:, -1]
    good = solve_ivp(mod.rhs, (0, 1), y0, method="BDF", args=p, rtol=1e-9, atol=1e-11).y[:, -1]
    assert not np.allclose(bad, ref, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(good, ref, rtol=1e-5, atol=1e-6)


def test_vectorized_solve_ivp_uses_the_batched_flavour(rng):
    mod = _module(ODE_KERNELS[0])
    y0, p = _point(ODE_KERNELS[0], rng)
    a = solve_ivp(mod.rhs_batched, (0, 1), y0, method="BDF", args=p, vectorized=True, rtol=1e-9, atol=1e-11)
    b = solve_ivp(mod.rhs, (0, 1), y0, method="BDF", args=p, rtol=1e-9, atol=1e-11)
    np.testing.assert_allclose(a.y[:, -1], b.y[:, -1], rtol=1e-6, atol=1e-8)


CONSERVED = {  # which invariants are conserved (torque-free / heavy top)
    "euler_principal": [0, 1],
    "euler_full": [0, 1],
    "free_body_quaternion": [0, 1, 2],
    "heavy_top_euler_angles": [0, 1, 2],
    "heavy_top_euler_poisson": [0, 1, 2, 3],
}


@pytest.mark.parametrize("name", ODE_KERNELS)
def test_invariants_are_conserved_along_the_flow(name, rng):
    mod = _module(name)
    y0, p = _point(name, rng)
    if name in ("euler_principal", "euler_full"):
        p = (*p[:-3], 0.0, 0.0, 0.0)  # torque-free
    if name == "heavy_top_euler_angles":
        y0[1] = 1.0
    sol = solve_ivp(mod.rhs, (0, 2.0), y0, method="DOP853", args=p, rtol=1e-12, atol=1e-12, dense_output=True)
    inv = mod.invariants_batched(0.0, sol.y, *p)
    for k in CONSERVED[name]:
        np.testing.assert_allclose(inv[k], inv[k, 0], rtol=1e-8, atol=1e-9)


_finite = st.floats(-10, 10, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(_finite, min_size=10, max_size=10), st.lists(st.floats(0.5, 3.0), min_size=3, max_size=3))
def test_rates_of_the_invariants_vanish_identically(values, moments):
    """At any state (not only on the unit sphere): d|q|²/dt = 2 q·q̇ = 0, d|Γ|²/dt = 0, d(L·Γ)/dt = 0 and dE/dt = 0
    for the Euler–Poisson top; d|q|²/dt = 0, dE/dt = ω·Iω̇ = 0, dL²/dt = 0 for the free body."""
    I = np.array(moments)
    w, G, q = np.array(values[:3]), np.array(values[3:6]), np.array(values[6:10])
    Mgl = 1.2 * 9.81 * 0.3
    ep = _module("heavy_top_euler_poisson")
    rates = np.array(ep.rhs(0.0, np.concatenate([w, G, q]), *I, 1.2, 9.81, 0.3))
    wd, Gd, qd = rates[:3], rates[3:6], rates[6:]
    scale = 1 + np.sum(np.abs(values)) ** 3
    assert abs(q @ qd) <= 1e-12 * scale and abs(G @ Gd) <= 1e-12 * scale
    assert abs((I * wd) @ G + (I * w) @ Gd) <= 1e-12 * scale  # d(L·Γ)/dt
    assert abs((I * w) @ wd + Mgl * Gd[2]) <= 1e-12 * scale  # dE/dt
    fb = _module("free_body_quaternion")
    rates = np.array(fb.rhs(0.0, np.concatenate([w, q]), *I))
    assert abs((I * w) @ rates[:3]) <= 1e-12 * scale and abs((I * I * w) @ rates[:3]) <= 1e-12 * scale
    assert abs(q @ rates[3:]) <= 1e-12 * scale


def _derivation_residuals(name):
    """(equations frozen to symbols, state symbols, rate symbols, parameter symbols) straight from the derivation."""
    from eulersym import dynamics, top
    from eulersym.codegen import catalogue as C
    from eulersym.symbols import I1, I3, M, g, l, moments, torques

    if name == "euler_principal":
        eqs, mapping, rates, params = dynamics.euler_equations(), C._OMEGA, C.OMEGA_DOT, (*moments, *torques)
    elif name == "euler_full":
        eqs, mapping = dynamics.euler_equations(C._full_tensor(), torques), C._OMEGA
        rates, params = C.OMEGA_DOT, (*C.FULL_INERTIA, *torques)
    else:
        eqs, mapping, rates, params = top.equations_of_motion(), C._ANGLES, C.ACCELERATIONS, (I1, I3, M, g, l)
    state = C.OMEGA if name.startswith("euler") else (*C.ANGLES, *C.RATES)
    return [C.freeze_state(C._residual(e), mapping) for e in eqs], state, rates, params


@pytest.mark.parametrize("name", ["euler_principal", "euler_full", "heavy_top_euler_angles"])
def test_derivation_equations_hold_at_the_kernel_rates(name, rng):
    """Independent of the first-order solve: the derivation's own equations vanish at (y, rhs(y))."""
    mod = _module(name)
    residuals, state, rates, params = _derivation_residuals(name)
    for _ in range(3):
        y, p = _point(name, rng)
        dy = mod.rhs(0.0, y, *p)
        values = dict(zip((*state, *rates, *params), (*y, *dy[-len(rates):], *p)))
        values = {k: sp.Float(v, 30) for k, v in values.items()}
        for residual in residuals:
            assert abs(float(residual.xreplace(values))) < 1e-12


# ---------------------------------------------------------------------------------------------------------------
# Import without SymPy


_NO_SYMPY = """
import sys
sys.modules["sympy"] = None
import numpy as np
import eulersym.generated.{name} as m
assert "sympy" not in [k for k, v in sys.modules.items() if v is not None and k.split(".")[0] == "sympy"]
print(m.__file__)
print(m.{function})
"""


def _call_line(name):
    if name == "kinematics":
        return "attitude_matrix(0.1, 0.2, 0.3)"
    y, p = _point(name, np.random.default_rng(0))
    return f"rhs(0.0, {list(map(float, y))}, *{tuple(map(float, p))})"


def _no_sympy_script():
    return "".join(_NO_SYMPY.format(name=name, function=_call_line(name)) for name in [*ODE_KERNELS, "kinematics"])


def test_generated_modules_import_and_run_without_sympy():
    out = subprocess.run([sys.executable, "-c", _no_sympy_script()], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0, out.stderr


def test_generated_modules_run_without_sympy_from_an_installed_wheel(tmp_path):
    wheels, target, elsewhere, source = tmp_path / "wheels", tmp_path / "site", tmp_path / "cwd", tmp_path / "src"
    elsewhere.mkdir()
    # Build from a copy, so that setuptools' build/ folder never lands in the working tree.
    shutil.copytree(ROOT, source, ignore=shutil.ignore_patterns(".git", ".venv", "build", "*.egg-info", "__pycache__",
                                                                 ".hypothesis", ".benchmarks", "out*"))
    pip = [sys.executable, "-m", "pip", "-q"]
    isolation = [] if importlib.util.find_spec("setuptools") is None else ["--no-build-isolation"]
    subprocess.run([*pip, "wheel", "--no-deps", *isolation, "-w", str(wheels), str(source)],
                   check=True, capture_output=True, cwd=tmp_path)
    wheel = next(wheels.glob("eulersym-*.whl"))
    subprocess.run([*pip, "install", "--no-deps", "--target", str(target), str(wheel)], check=True,
                   capture_output=True)
    script = _no_sympy_script() + "\nimport eulersym\nprint(eulersym.__file__)\n"
    env = {**os.environ, "PYTHONPATH": str(target)}
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=elsewhere, env=env)
    assert out.returncode == 0, out.stderr
    files = [line for line in out.stdout.splitlines() if line.endswith(".py")]
    assert files and all(line.startswith(str(target)) for line in files), out.stdout
