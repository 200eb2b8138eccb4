"""The C target (issue 25 §2, §4): every committed C file and a model's compile with ``gcc -std=c99 -pedantic -Wall
-Wextra -Wconversion -Werror`` (and its headers as C++), load through ``ctypes`` and agree with the NumPy kernels at
random states — within 4 ulp in double, 1e-6 relative in float; the exact free-body propagator agrees with the NumPy
oracle within 1e-14·|ω| for t up to 10⁶; the splitting step gives the bits of the Python loop.

Everything is compiled once per session (one gcc call, a few seconds)."""

from __future__ import annotations

import ctypes
import importlib
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from eulersym.bench.kernels import c_compiler, compile_c
from eulersym.codegen import CATALOGUE, available, build
from eulersym.codegen.c import c_name
from eulersym.codegen.emitter import cse_pass
from eulersym.model import Model, kernels
from eulersym.models import bundled
from eulersym.numerics import free_rigid_body_exact
from eulersym.numerics import pivoted as P

ROOT = Path(__file__).resolve().parents[1]
C_DIR = ROOT / "generated" / "c"
ODE = [n for n in CATALOGUE if n != "kinematics" and available(n)[0]]
MODEL = "kovalevskaya"


@pytest.fixture(scope="session")
def library(tmp_path_factory):
    """One shared library of every committed C file and Kovalevskaya's model, compiled with the strict flags."""
    tmp = tmp_path_factory.mktemp("c")
    model = Model.from_toml(bundled()[MODEL])
    for file, text in kernels.files(model.mechanics, "c", digest=model.digest).items():
        (tmp / file).write_text(text)
    sources = sorted(C_DIR.glob("*.c")) + [tmp / f"{MODEL}.c"]
    lib = ctypes.CDLL(compile_c(sources, tmp / "libkernels.so", include=(C_DIR, tmp)))
    return lib, model, tmp


def _module(name, model):
    return model.compile() if name == MODEL else importlib.import_module(f"eulersym.generated.{name}")


def _struct(names, real):
    return type("params", (ctypes.Structure,), {"_fields_": [(c_name(n), real) for n in names]})


def _bind(lib, name, function, real):
    suffix = "" if real is ctypes.c_double else "_f"
    f = getattr(lib, f"{name}_{function}{suffix}")
    f.restype = ctypes.c_int
    return f


def _call(lib, module, name, function, t, y, params, real):
    """``name_function[_f](t, y, &p, out)`` through ctypes: (status, out as float64)."""
    n = len(module.STATE)
    size = {"rhs": n, "jac": n * n, "invariants": len(module.INVARIANTS)}[function]
    Y = (real * len(y))(*y)
    p = _struct(module.PARAMETERS, real)(*params)
    out = (real * size)()
    status = _bind(lib, name, function, real)(real(t), Y, ctypes.byref(p), out)
    return status, np.array(out[:], dtype=float)


def _states(module, rng, n):
    """Random states and parameters near the module's DEFAULTS (θ away from 0 and π for the Euler angles)."""
    k = len(module.STATE)
    for _ in range(n):
        y = rng.uniform(-1.5, 1.5, k)
        if "theta" in module.STATE:
            y[module.STATE.index("theta")] = rng.uniform(0.3, 2.8)
        d = np.array(module.DEFAULTS)
        params = d * rng.uniform(0.8, 1.25, d.size) + np.where(d == 0.0, rng.uniform(-0.5, 0.5, d.size), 0.0)
        yield y, tuple(params.tolist())


# ---------------------------------------------------------------------------------------------------------------
# The strict flags, C++ and byte-reproducibility


def test_every_committed_c_file_compiles_with_the_strict_flags_and_its_headers_as_cplusplus(library, tmp_path):
    _, _, tmp = library  # the session's compile used -std=c99 -pedantic -Wall -Wextra -Wconversion -Werror
    headers = sorted(C_DIR.glob("*.h")) + [tmp / f"{MODEL}.h"]
    source = tmp_path / "all.cpp"
    source.write_text("".join(f'#include "{h.name}"\n' for h in headers) + "int main() { return 0; }\n")
    cxx = Path(c_compiler()).with_name("g++")
    if not cxx.exists():
        cxx = Path(c_compiler())
    run = subprocess.run([str(cxx), "-x", "c++", "-std=c++11", "-Wall", "-Wextra", "-pedantic", "-Werror",
                          f"-I{C_DIR}", f"-I{tmp}", "-fsyntax-only", str(source)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


#: What the object code may call: <math.h>, and the copies and fused sin/cos the compiler itself emits.
_CALLS = {"sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh",
          "exp", "log", "sqrt", "fabs", "floor", "ceil", "erf", "erfc", "tgamma", "lgamma", "pow", "fmod", "fmax",
          "frexp", "ldexp", "nearbyint", "sincos", "memcpy", "memset", "__stack_chk_fail"}


def test_the_c_files_are_reentrant_no_malloc_no_globals(tmp_path):
    """The object code of every file (the model's too) holds functions and read-only constants only (nm: no data,
    no bss, nothing writable) and calls nothing but the C library's mathematics (no malloc, no I/O)."""
    sources = sorted(C_DIR.glob("*.c"))
    for source in sources:
        obj = tmp_path / (source.stem + ".o")
        subprocess.run([c_compiler(), "-std=c99", "-O2", "-c", str(source), "-o", str(obj)], check=True)
        symbols = [line.split() for line in subprocess.run(["nm", str(obj)], capture_output=True, text=True,
                                                           check=True).stdout.splitlines()]
        kinds = {parts[-2] for parts in symbols}
        assert kinds <= {"T", "t", "R", "r", "U"}, (source.name, kinds)  # no D/d/B/b/C: no state
        calls = {parts[-1] for parts in symbols if parts[-2] == "U"}
        calls = {c[:-1] if c.endswith("f") and c[:-1] in _CALLS else c for c in calls}
        assert calls <= _CALLS, (source.name, calls - _CALLS)


# ---------------------------------------------------------------------------------------------------------------
# The kernels against NumPy


_DERIVATIVE = {sp.sin: sp.cos, sp.cos: lambda g: -sp.sin(g), sp.exp: sp.exp, sp.log: lambda g: 1 / g,
               sp.atan: lambda g: 1 / (1 + g * g), sp.tan: lambda g: 1 + sp.tan(g) ** 2}


def _magnitude(expr, env):
    """``(value, M)`` of ``expr`` in double, with M the first-order bound of its rounding error in units of the unit
    roundoff (the running error analysis of Wilkinson/Higham §3.3): every operation adds |its result|, and errors
    of its operands propagate with their weights. ``env`` holds the inputs (M = 0: the reference sees the same
    float inputs) and the CSE symbols already evaluated. |float − exact| ≲ 2⁻²⁴ M; M = O(|f|) where nothing cancels."""
    if expr.is_Number or expr.is_NumberSymbol:
        return float(expr), 0.0
    if expr.is_Symbol:
        return env[expr]
    parts = [_magnitude(a, env) for a in expr.args]
    if expr.is_Add:
        v = math.fsum(p[0] for p in parts)
        return v, sum(p[1] for p in parts) + (len(parts) - 1) * abs(v)
    if expr.is_Mul:
        v = math.prod(p[0] for p in parts)
        spread = sum(m * math.prod(abs(q[0]) for j, q in enumerate(parts) if j != i) for i, (_, m) in enumerate(parts))
        return v, spread + (len(parts) - 1) * abs(v)
    if expr.is_Pow:
        (b, mb), (x, _) = parts
        v = b ** x
        return v, abs(x) * abs(b) ** (x - 1) * mb + (abs(x) if float(x).is_integer() else 1.0) * abs(v)
    (g, mg), = parts
    v = float(expr.func(g))
    slope = float(_DERIVATIVE[expr.func](sp.Float(g))) if expr.func in _DERIVATIVE else float(
        sp.diff(expr.func(sp.Symbol("u")), sp.Symbol("u")).subs(sp.Symbol("u"), g))
    return v, abs(slope) * mg + abs(v)


def _magnitudes(spec, function, values):
    """M of every output of ``function`` at ``values`` (symbol → float), along the C's own CSE program."""
    cse = cse_pass(spec.functions)
    reduced = cse.reduced[function]
    env = {s: (float(v), 0.0) for s, v in values.items()}
    for symbol, e in cse.needed(list(reduced)):
        env[symbol] = _magnitude(e, env)
    return np.array([_magnitude(e, env)[1] for e in reduced])


def _spec(name, model):
    return kernels.module_spec(model.mechanics) if name == MODEL else build(name)


@pytest.mark.parametrize("name", [*ODE, MODEL])
def test_c_double_within_4_ulp_and_float_within_1e_6_of_the_magnitude(library, name):
    """double: ≤ 4 ulp of the NumPy kernel (the same operations: in practice the same bits). float: ≤ 1e-6 relative
    to M, the magnitude of the evaluation (see :func:`_magnitude`) — not to |f| itself, which float cannot promise
    where terms cancel (a torque against the gyroscopic term: 1.2e-5 of |f| measured for euler_full's rhs)."""
    lib, model, _ = library
    module = _module(name, model)
    spec = _spec(name, model)
    rng = np.random.default_rng(sum(map(ord, name)))
    worst = 0.0
    for y, params in _states(module, rng, 12):
        for function in ("rhs", "jac", "invariants"):
            ref = np.ravel(np.asarray(getattr(module, function)(0.3, y, *params), dtype=float))
            status, got = _call(lib, module, name, function, 0.3, y, params, ctypes.c_double)
            assert status == 0
            ulp = np.abs(got - ref) / np.spacing(np.abs(ref))
            assert np.all(ulp <= 4), (function, np.max(ulp))
            y32 = np.float32(y).astype(float)
            p32 = tuple(np.float32(params).astype(float).tolist())
            ref32 = np.ravel(np.asarray(getattr(module, function)(0.3, y32, *p32), dtype=float))
            status, got32 = _call(lib, module, name, function, 0.3, y32, p32, ctypes.c_float)
            assert status == 0
            f = next(f for f in spec.functions if f.name == function)
            M = _magnitudes(spec, function, dict(zip(f.symbols, (0.3, *y32, *p32))))
            assert np.all(np.abs(got32 - ref32) <= 1e-6 * M), (function, np.max(np.abs(got32 - ref32) / M))
            worst = max(worst, float(np.max(np.abs(got32 - ref32) / (2.0**-24 * np.maximum(M, 1e-300)))))
    assert worst <= 1.0  # measured: within the first-order bound itself (≤ 0.8 unit roundoffs of M)


@pytest.mark.parametrize("name", [*ODE, MODEL])
def test_default_params_are_the_modules_defaults_and_out_may_be_y(library, name):
    lib, model, _ = library
    module = _module(name, model)
    for real in (ctypes.c_double, ctypes.c_float):
        suffix = "" if real is ctypes.c_double else "_f"
        f = getattr(lib, f"{name}_default_params{suffix}")
        f.restype = _struct(module.PARAMETERS, real)
        p = f()
        assert [getattr(p, c_name(n)) for n in module.PARAMETERS] == pytest.approx(module.DEFAULTS, rel=1e-7)
    y = np.random.default_rng(3).uniform(0.3, 1.2, len(module.STATE))
    _, separate = _call(lib, module, name, "rhs", 0.0, y, module.DEFAULTS, ctypes.c_double)
    Y = (ctypes.c_double * len(y))(*y)
    p = _struct(module.PARAMETERS, ctypes.c_double)(*module.DEFAULTS)
    assert _bind(lib, name, "rhs", ctypes.c_double)(ctypes.c_double(0.0), Y, ctypes.byref(p), Y) == 0
    assert np.array(Y[:]).tobytes() == separate.tobytes()  # every input read before the first output is written


@pytest.mark.parametrize("name", [*ODE, MODEL])
def test_the_batched_flavour_equals_the_numpy_batched_and_the_per_state_calls(library, name):
    """n states laid out as NumPy's batches (state first): the bits of the per-state calls in double and in float
    (the same statements; so within 4 ulp of the NumPy kernel, whose batched flavour orders its in-place operations
    otherwise: close to it), n = 0 writes nothing."""
    lib, model, _ = library
    module = _module(name, model)
    states = list(_states(module, np.random.default_rng(9), 5))
    params = states[0][1]
    Y = np.ascontiguousarray(np.stack([y for y, _ in states], axis=1))
    for function in ("rhs", "jac", "invariants"):
        for real, dtype in ((ctypes.c_double, np.float64), (ctypes.c_float, np.float32)):
            suffix = "" if real is ctypes.c_double else "_f"
            f = getattr(lib, f"{name}_{function}_batched{suffix}")
            f.argtypes = [ctypes.c_size_t, real, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
            y = Y.astype(dtype)
            per_state = np.stack([_call(lib, module, name, function, 0.3, y[:, i].astype(float), params, real)[1]
                                  for i in range(y.shape[1])], axis=1)
            out = np.full(per_state.shape, np.nan, dtype=dtype)
            p = _struct(module.PARAMETERS, real)(*params)
            assert f(y.shape[1], 0.3, y.ctypes.data, ctypes.byref(p), out.ctypes.data) == 0
            assert out.astype(float).tobytes() == per_state.tobytes()
            if real is ctypes.c_double:
                ref = getattr(module, function + "_batched")(0.3, Y, *params).reshape(out.shape)
                np.testing.assert_allclose(out, ref, rtol=1e-13, atol=1e-13 * np.max(np.abs(ref)))
            empty = np.full(3, 7.0, dtype=dtype)
            assert f(0, 0.3, y.ctypes.data, ctypes.byref(p), empty.ctypes.data) == 0 and np.all(empty == 7.0)


def test_the_singular_euler_angle_top_returns_1_at_sin_theta_0(library):
    lib, model, _ = library
    module = _module("heavy_top_euler_angles", model)
    y = [0.1, 0.0, 0.2, 0.3, 0.4, 5.0]  # sin θ = 0: a division by zero
    for real in (ctypes.c_double, ctypes.c_float):
        assert _call(lib, module, "heavy_top_euler_angles", "rhs", 0.0, y, module.DEFAULTS, real)[0] == 1
    Y = np.array([y, [0.1, 0.7, 0.2, 0.3, 0.4, 5.0]]).T.copy()  # one of the two states singular
    f = lib.heavy_top_euler_angles_rhs_batched
    f.argtypes = [ctypes.c_size_t, ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
    p = _struct(module.PARAMETERS, ctypes.c_double)(*module.DEFAULTS)
    out = np.empty_like(Y)
    assert f(2, 0.0, Y.ctypes.data, ctypes.byref(p), out.ctypes.data) == 1
    assert np.all(np.isfinite(out[:, 1]))
    y = [0.1, 0.7, 0.2, 0.3, 0.4, 5.0]
    assert _call(lib, module, "heavy_top_euler_angles", "rhs", 0.0, y, module.DEFAULTS, ctypes.c_double)[0] == 0


def test_kinematics_in_c_equals_numpy(library):
    lib, _, _ = library
    from eulersym.generated import kinematics as k

    rng = np.random.default_rng(11)
    A = lib.kinematics_attitude_matrix
    W = lib.kinematics_omega_body
    for _ in range(20):
        angles = rng.uniform(-3, 3, 3)
        rates = rng.normal(size=3)
        out = (ctypes.c_double * 9)()
        assert A(*map(ctypes.c_double, angles), out) == 0
        np.testing.assert_array_max_ulp(np.array(out[:]), np.ravel(k.attitude_matrix(*angles)), 4)
        out = (ctypes.c_double * 3)()
        assert W(*map(ctypes.c_double, [*angles, *rates]), out) == 0
        np.testing.assert_array_max_ulp(np.array(out[:]), np.array(k.omega_body(*angles, *rates)), 4)


# ---------------------------------------------------------------------------------------------------------------
# The free body's exact propagator


def _c_omega(lib, I, w0, times):
    body = ctypes.create_string_buffer(8192)  # larger than eulersym_free_body: the caller's memory
    status = lib.eulersym_free_body_init(body, (ctypes.c_double * 3)(*I), (ctypes.c_double * 3)(*w0))
    if status:
        return status, None
    out = np.empty((len(times), 3))
    w = (ctypes.c_double * 3)()
    for k, t in enumerate(times):
        assert lib.eulersym_free_body_omega(body, ctypes.c_double(t), w) == 0
        out[k] = w[:]
    return 0, out


def _bodies(rng):
    """Random bodies and starts, and the special ones: symmetric, spherical, steady, near and on the separatrix,
    huge and tiny spins."""
    for _ in range(60):
        yield rng.uniform(0.3, 3.0, 3), rng.normal(size=3)
    yield (1.0, 1.0, 2.0), (0.3, -0.2, 1.5)
    yield (2.0, 1.0, 2.0), (0.3, -0.2, 1.5)
    yield (1.5, 1.5, 1.5), (0.3, -0.2, 1.5)
    yield (1.0, 2.0, 3.0), (0.0, 2.0, 0.0)
    yield (1.0, 2.0, 3.0), (1.0, 0.0, 0.0)
    yield (1.0, 2.0, 3.0), (1e-3, 1.0, 1e-3)
    yield (1.0, 2.0, 4.0), (1.0, 0.0, 0.25)  # D_mid = 0 exactly: the separatrix (tanh, sech)
    yield (1.0, 2.0, 4.0), (1.0, 1e-9, 0.25 + 2.0**-40)  # m_c ~ 1e-11
    yield (1.0, 2.0, 3.0), (3e25, -1e25, 2e25)
    yield (1.0, 2.0, 3.0), (3e-25, -1e-25, 2e-25)


def test_the_c_free_body_equals_the_numpy_oracle_within_1e_14_omega_up_to_t_1e6(library):
    lib, _, _ = library
    rng = np.random.default_rng(25)
    worst = 0.0
    for I, w0 in _bodies(rng):
        times = np.concatenate([[0.0, -2.5], rng.uniform(0, 10, 3), rng.uniform(0, 1e6, 4), [1e6]])
        ref = free_rigid_body_exact(I, w0, times, check_body=False)
        status, got = _c_omega(lib, I, w0, times)
        assert status == 0
        error = float(np.max(np.abs(got - ref)) / np.linalg.norm(w0))
        worst = max(worst, error)
        assert error <= 1e-14, (I, w0, error)
        # independent of the oracle: the start, and the energy and |L|² conserved to round-off at every time
        assert np.max(np.abs(got[0] - w0)) <= 2e-15 * np.linalg.norm(w0)
        I = np.asarray(I)
        for invariant in (np.sum(I * got**2, axis=1), np.sum((I * got) ** 2, axis=1)):
            assert np.max(np.abs(invariant / invariant[0] - 1.0)) <= 1e-14
    assert worst < 1e-14


def test_the_c_free_body_refuses_bad_input(library):
    lib, _, _ = library
    for I, w0 in [((0.0, 1.0, 2.0), (1, 2, 3)), ((1.0, -1.0, 2.0), (1, 2, 3)), ((1.0, np.inf, 2.0), (1, 2, 3)),
                  ((1.0, 2.0, 3.0), (np.nan, 2, 3)), ((np.nan, 2.0, 3.0), (1, 2, 3))]:
        assert _c_omega(lib, I, w0, [0.0])[0] == 1


# ---------------------------------------------------------------------------------------------------------------
# The pivoted body's splitting step


@pytest.mark.parametrize("method", P.PIVOTED_METHODS)
@pytest.mark.parametrize("free_flow", ["axes", "symmetric"])
def test_the_c_splitting_step_gives_the_bits_of_the_python_loop(library, method, free_flow):
    lib, _, _ = library
    rng = np.random.default_rng(7)
    if free_flow == "axes":
        inertia, rotor, c = rng.uniform(0.6, 1.4, 3), rng.normal(size=3) * 0.2, rng.normal(size=3) * 0.3
    else:
        inertia, rotor, c = (1.0, 1.0, 0.6), (0.0, 0.0, 0.3), (0.0, 0.0, 0.5)
    q0 = rng.normal(size=4)
    state, par, _, _ = P._prepare(np.diag(inertia), 1.0, 9.81, c, rng.normal(size=3) * 3, q0 / np.linalg.norm(q0),
                                  rotor, free_flow, batch=1)
    p = tuple(float(x) for x in par[:, 0])
    kind = P._FREE_FLOWS.index(free_flow)
    reference = P._run_pivoted(state[:, 0], [200], [0.01], P.COMPOSITIONS[method], p, kind)[-1]
    s = (ctypes.c_double * 10)(*state[:, 0])
    parameters = (ctypes.c_double * 10)(*p)  # the struct: 1/I (3), rotor (3), M g c (3), L·Γ
    for _ in range(200):
        assert lib.eulersym_pivoted_step(s, ctypes.c_double(0.01), parameters, P.PIVOTED_METHODS.index(method),
                                         kind) == 0
    assert np.array(s[:]).tobytes() == reference.tobytes()


def test_the_c_splitting_step_refuses_an_unknown_method(library):
    lib, _, _ = library
    s = (ctypes.c_double * 10)(0, 0, 1, 0, 0, 1, 1, 0, 0, 0)
    before = s[:]
    parameters = (ctypes.c_double * 10)(1, 1, 1, 0, 0, 0, 0, 0, 1, 1)
    assert lib.eulersym_pivoted_step(s, ctypes.c_double(0.1), parameters, 3, 0) == 1
    assert lib.eulersym_pivoted_step(s, ctypes.c_double(0.1), parameters, 0, 2) == 1
    assert s[:] == before


# ---------------------------------------------------------------------------------------------------------------
# The README's C program


def test_the_readmes_c_program_compiles_strictly_and_prints_what_the_readme_shows(tmp_path):
    import re

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    match = re.search(r"```c\n(.*?)```\s*```text\n(.*?)```", text, re.S)
    assert match is not None
    program, shown = match.groups()
    (tmp_path / "top.c").write_text(program)
    binary = compile_c([tmp_path / "top.c", C_DIR / "heavy_top_euler_poisson.c", C_DIR / "eulersym_free_body.c"],
                       tmp_path / "top", shared=False, include=(C_DIR,))
    run = subprocess.run([binary], capture_output=True, text=True, check=True)
    assert run.stdout == shown
    omega = [float(x) for x in shown.splitlines()[1].split("=")[1].split()]
    np.testing.assert_allclose(omega, free_rigid_body_exact((1.0, 2.0, 3.0), (1.0, 0.5, 0.2), [1e6])[0],
                               rtol=0, atol=1e-12)  # the oracle, to the 12 digits printed
