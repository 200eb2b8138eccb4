"""Tests of eulersym.codegen's emitter, ad-hoc route, determinism and ``generate --check``.

The per-kernel tests (agreement with the derivation, Jacobians, solve_ivp, import without SymPy) are in
tests/test_codegen_kernels.py.
"""

from __future__ import annotations

import hashlib

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from eulersym.cli import main
from eulersym.codegen import (
    CATALOGUE,
    Argument,
    FunctionSpec,
    ModuleSpec,
    available,
    check_expressions,
    compile_expressions,
    emit_module,
    first_order,
    generate,
)
from eulersym.codegen.emitter import cse_pass, make_printer
from eulersym.errors import InvalidInput


a, b, c, k = sp.symbols("a b c k", real=True)
EXPRS = [k * a * b + sp.sin(a) ** 2 * sp.cos(b), sp.exp(-c) * a / (1 + b**2), sp.sqrt(1 + a**2) - sp.atan2(b, c),
         sp.Rational(1, 3) * a**3 - c**-2 + sp.Float("0.25") * b]


def _reference(exprs, x, kk):
    f = sp.lambdify([a, b, c, k], exprs, modules="mpmath")
    return np.array([float(v) for v in f(*[sp.Float(v, 30) for v in (*x, kk)])])


# ---------------------------------------------------------------------------------------------------------------
# Printer and emitter


def test_printer_tables_and_powers():
    scalar, batched = make_printer("scalar"), make_printer("batched")
    assert scalar.doprint(a**2 * sp.sin(b)) == "(a*a)*sin(b)"
    assert batched.doprint(sp.asin(a)) == "np.arcsin(a)"
    assert scalar.doprint(1 / a) == "1/a"
    assert scalar.doprint(sp.Rational(2, 3) * a) == "(2/3)*a"
    assert scalar.doprint(sp.sqrt(a)) == "sqrt(a)"
    assert scalar.doprint(a ** -3) == "1/(a*a*a)"
    assert eval(scalar.doprint(2 / (a**2 * b)), {"a": 3.0, "b": 5.0}) == pytest.approx(2 / 45)


def test_printer_refuses_unknown_functions_by_name():
    with pytest.raises(InvalidInput, match="besselj"):
        make_printer("scalar").doprint(sp.besselj(0, a))
    with pytest.raises(InvalidInput, match="flavour"):
        make_printer("fortran")
    for expr in (sp.Max(a, b), sp.Min(a, 1), sp.Heaviside(a)):
        with pytest.raises(InvalidInput, match=type(expr).__name__):
            make_printer("batched").doprint(expr)


@pytest.mark.parametrize(
    "expr, name",
    [
        (sp.Function("f")(sp.Symbol("t")), "f\\(t\\)"),
        (sp.Derivative(sp.Function("f")(sp.Symbol("t")), sp.Symbol("t")), "Derivative"),
        (a + sp.Symbol("zeta"), "zeta"),
    ],
)
def test_refuses_leftovers_by_name(expr, name):
    with pytest.raises(InvalidInput, match=name):
        check_expressions([expr], [a])
    with pytest.raises(InvalidInput, match=name):
        compile_expressions([expr], [a])


def test_refuses_vectors():
    from sympy.physics.vector import ReferenceFrame

    N = ReferenceFrame("N")
    with pytest.raises(InvalidInput, match="Vector"):
        check_expressions([a * N.x], [a])


def test_refuses_bad_argument_names():
    with pytest.raises(InvalidInput):
        Argument("out", (a,))
    with pytest.raises(InvalidInput):
        Argument("class", (a,))
    with pytest.raises(InvalidInput, match="reserved for CSE"):
        compile_expressions([sp.Symbol("x0")], [sp.Symbol("x0")])


def test_one_cse_pass_shares_subexpressions_between_functions():
    args = (Argument("y", (a, b), vector=True),)
    f = FunctionSpec("f", args, sp.Matrix([sp.sin(a) * b, sp.sin(a) + 1]))
    j = FunctionSpec("j", args, sp.Matrix([sp.sin(a) * b]).jacobian([a, b]))
    p = cse_pass([f, j])
    assert (sp.Symbol("x0", real=True), sp.sin(a)) in p.replacements
    assert str(p.reduced["j"][0, 1]) == "x0"


# ---------------------------------------------------------------------------------------------------------------
# Ad-hoc route


def test_compile_scalar_matches_high_precision_reference(rng):
    f = compile_expressions(EXPRS, [(a, b, c), k])
    for _ in range(20):
        x, kk = rng.uniform(0.2, 2.0, 3), rng.uniform(-2, 2)
        ref = _reference(EXPRS, x, kk)
        got = np.array(f(x, kk))
        assert np.all(np.abs(got - ref) <= 1e-13 * np.maximum(1.0, np.abs(ref)))
        assert f(list(x), kk) == f(tuple(x), kk) == f(x, kk)


@pytest.mark.parametrize("batch", [(0,), (1,), (7,), (2, 3)])
def test_compile_batched_agrees_with_scalar(rng, batch):
    fs = compile_expressions(EXPRS, [(a, b, c), k])
    fb = compile_expressions(EXPRS, [(a, b, c), k], flavour="batched")
    y = rng.uniform(0.2, 2.0, (3, *batch))
    kk = rng.uniform(-2, 2, batch)
    out = fb(y, kk)
    assert out.shape == (4, *batch)
    for index in np.ndindex(*batch):
        col = (slice(None), *index)
        np.testing.assert_allclose(out[col], fs(y[col], kk[index]), rtol=1e-14, atol=0)
    buffer = np.empty((4, *batch))
    assert fb(y, kk, out=buffer) is buffer
    np.testing.assert_array_equal(buffer, out)


def test_scalar_returns_a_new_list_every_call():
    f = compile_expressions(EXPRS, [(a, b, c), k])
    y = np.array([0.5, 0.6, 0.7])
    first = f(y, 1.0)
    second = f(y + 1, 1.0)
    assert first is not second and first != second
    fb = compile_expressions(EXPRS, [(a, b, c), k], flavour="batched")
    first = fb(y[:, None], 1.0)
    assert fb(y[:, None] + 1, 1.0) is not first


def test_bad_shapes_name_the_expected_order():
    f = compile_expressions(EXPRS, [(a, b, c), k])
    with pytest.raises(InvalidInput, match=r"order \(a, b, c\)"):
        f(np.ones(4), 1.0)
    with pytest.raises(InvalidInput, match=r"order \(a, b, c\)"):
        f([1.0, 2.0], 1.0)
    fb = compile_expressions(EXPRS, [(a, b, c), k], flavour="batched")
    with pytest.raises(InvalidInput, match=r"shape \(3, \.\.\.\) with rows in the order \(a, b, c\)"):
        fb(np.ones((2, 5)), 1.0)
    with pytest.raises(InvalidInput, match="broadcast"):
        fb(np.ones((3, 5)), np.ones(4))
    with pytest.raises(InvalidInput, match="out"):
        fb(np.ones((3, 5)), 1.0, out=np.empty((4, 4)))
    with pytest.raises(TypeError):
        f(np.ones(3))  # missing k: Python names it


def test_compile_accepts_functions_of_time():
    from eulersym.symbols import phi, t

    f = compile_expressions([phi * phi.diff(t)], [phi, phi.diff(t)])
    assert f(2.0, 3.0) == [6.0]
    assert "def f(phi, phidot, *extra)" in f.source


def test_matrix_output_is_nested():
    f = compile_expressions(sp.Matrix([[a, b], [a * b, 1]]), [a, b])
    assert f(2.0, 3.0) == [[2.0, 3.0], [6.0, 1.0]]
    fb = compile_expressions(sp.Matrix([[a, b], [a * b, 1]]), [a, b], flavour="batched")
    assert fb(np.array([2.0, 1.0]), 3.0).shape == (2, 2, 2)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-5, 5, allow_nan=False), min_size=3, max_size=3), st.floats(0.5, 3))
def test_scalar_and_batched_agree_property(x, kk):
    exprs = [a * b - c * k, sp.cos(a * k) + b**2, a**4 * k - b * c]
    fs = _COMPILED.setdefault("s", compile_expressions(exprs, [(a, b, c), k]))
    fb = _COMPILED.setdefault("b", compile_expressions(exprs, [(a, b, c), k], flavour="batched"))
    np.testing.assert_allclose(fb(np.array(x)[:, None], kk)[:, 0], fs(x, kk), rtol=1e-15, atol=1e-15)


_COMPILED: dict = {}


def test_first_order_solves_a_mass_matrix():
    x, y = sp.symbols("x y")
    sol = first_order([sp.Eq(a * x + b * y, c), sp.Eq(b * x + a * y, k)], [x, y])
    assert sp.simplify(a * sol[0] + b * sol[1] - c) == 0
    assert sp.simplify(b * sol[0] + a * sol[1] - k) == 0
    with pytest.raises(InvalidInput, match="linear"):
        first_order([x * y - 1, x - y], [x, y])


# ---------------------------------------------------------------------------------------------------------------
# generate (the whole-catalogue checks are in tests/test_codegen_sync.py)


def test_generate_writes_into_a_fresh_folder(tmp_path):
    paths = generate(tmp_path / "out", names=["kinematics"])
    assert sorted(p.name for p in paths) == ["kinematics.py"]
    assert main(["generate", "--dir", str(tmp_path / "out"), "no_such_kernel"]) == 2


def test_catalogue_entries_are_registered_in_contract_order():
    assert list(CATALOGUE) == ["euler_principal", "euler_full", "free_body_quaternion", "heavy_top_euler_angles",
                               "heavy_top_euler_poisson", "kinematics"]
    for name in CATALOGUE:
        ok, why = available(name)
        assert ok or "not available" in why


def test_emit_module_header_names_source_versions_hash_and_order():
    spec = ModuleSpec("demo", "A demo.", "by hand", (FunctionSpec("f", (Argument("a", (a,)),), sp.Matrix([a])),))
    src = emit_module(spec, versions={"eulersym": "9.9", "sympy": "8.8"})
    head = src.splitlines()[:6]
    assert head[1] == "# Source derivation: by hand"
    assert head[2] == "# eulersym version: 9.9" and head[3] == "# SymPy version: 8.8"
    assert head[4].startswith("# Input hash: sha256:") and head[5] == "# Arguments: f(a)"
    assert hashlib.sha256(src.encode()).hexdigest() == hashlib.sha256(
        emit_module(spec, versions={"eulersym": "9.9", "sympy": "8.8"}).encode()).hexdigest()
