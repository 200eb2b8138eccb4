"""The cheap checks of the batched wrappers (each module's ``_shape`` and ``_batch``, floats and ints not
asked in the overlap test) and the emitted row views change nothing but time: the same bits, the same errors,
the same ``out=`` semantics as the general path (``np.shape`` and ``np.broadcast_shapes`` on every call) and
as one ``out[i, ...]`` subscript per statement."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
import sympy as sp
from hypothesis import event, given, settings
from hypothesis import strategies as st

from eulersym.codegen import CATALOGUE, available, build
from eulersym.codegen.emitter import _emit_into, make_printer
from eulersym.errors import InvalidInput
from eulersym.generated import euler_principal as _runtime  # every module carries the same helpers

KERNELS = [n for n in CATALOGUE if available(n)[0]]
FUNCTIONS = [(name, f) for name in KERNELS for f in build(name).functions]

#: How a scalar argument is passed: each but "bad" broadcasts against a batch of ``n``.
SCALAR_FORMS = ("float", "int", "numpy float", "0-d", "(n,)", "(1,)", "list", "bad")
#: How a vector argument of ``k`` components is passed.
VECTOR_FORMS = ("(k, n)", "(k, 1)", "(k,)", "list", "float32", "fortran", "strided", "bad")


def _general_batch(shapes):
    """The general path: NumPy's broadcasting for every call, its refusal as InvalidInput."""
    try:
        return np.broadcast_shapes(*shapes)
    except ValueError:
        raise InvalidInput("arguments", f"batch shapes {shapes}", "shapes that broadcast together") from None


def _scalar(form, value, n):
    return {"float": value, "int": int(round(value * 3)), "numpy float": np.float64(value), "0-d": np.array(value),
            "(n,)": np.full(n, value), "(1,)": np.array([value]), "list": [value] * n,
            "bad": np.full(n + 1, value)}[form]


def _vector(form, values):
    k, n = values.shape
    return {"(k, n)": values, "(k, 1)": values[:, :1], "(k,)": values[:, 0], "list": values.tolist(),
            "float32": values.astype(np.float32), "fortran": np.asfortranarray(values),
            "strided": np.repeat(values, 2, axis=1)[:, ::2], "bad": np.vstack([values, values[:1]])}[form]


def _outcome(call):
    """Bytes and shape of the result, or the error's type and message."""
    try:
        result = call()
    except Exception as error:  # noqa: BLE001 - compared between the two paths, whatever it is
        return type(error).__name__, str(error)
    return result.shape, result.dtype.str, result.tobytes()


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(FUNCTIONS), st.integers(0, 2**32 - 1), st.integers(1, 9), st.data())
def test_fast_and_general_paths_give_the_same_bits_and_errors(function, seed, n, data):
    name, f = function
    module = importlib.import_module(f"eulersym.generated.{name}")
    kernel = getattr(module, f.name + "_batched")
    rng = np.random.default_rng(seed)
    spoilt = None  # one bad argument in a quarter of the calls
    if data.draw(st.sampled_from([False, False, False, True]), label="spoil"):
        spoilt = data.draw(st.integers(0, len(f.arguments) - 1), label="bad argument")
    args = []
    for i, a in enumerate(f.arguments):
        values = rng.uniform(0.3, 1.4, (len(a.symbols), n))
        forms = ("bad",) if i == spoilt else (VECTOR_FORMS if a.vector else SCALAR_FORMS)[:-1]
        form = data.draw(st.sampled_from(forms), label=a.name)
        args.append(_vector(form, values) if a.vector else _scalar(form, float(values[0, 0]), n))
    out_form = data.draw(st.sampled_from(("none", "none", "fits", "fits", "wrong shape", "float32", "an input")), label="out")
    with pytest.MonkeyPatch.context() as mp:  # the general path: NumPy's checks on every call
        mp.setattr(module, "_shape", np.shape)
        mp.setattr(module, "_batch", _general_batch)
        general = _outcome(lambda: kernel(*args, out=_out(out_form, kernel, args)))
    fast = _outcome(lambda: kernel(*args, out=_out(out_form, kernel, args)))
    assert fast == general
    event("computed" if isinstance(fast[0], tuple) else f"refused: {fast[0]}")


def _out(form, kernel, args):
    """An ``out`` for the call: none, one that fits (its shape from a call without it), a wrong one, an input."""
    if form == "none":
        return None
    try:
        shape = kernel(*args).shape
    except Exception:  # noqa: BLE001 - the call then fails the same way with any out
        shape = (1,)
    if form == "fits":
        return np.full(shape, np.nan)
    if form == "wrong shape":
        return np.empty(shape + (1,))
    if form == "float32":
        return np.empty(shape, dtype=np.float32)
    arrays = [a for a in args if isinstance(a, np.ndarray) and a.dtype == np.float64]
    return arrays[0] if arrays else np.empty(shape)


@pytest.mark.parametrize("overlap", ["view of y", "memoryview of out", "0-d view of out", "a row of out"])
def test_out_overlapping_any_input_is_refused_floats_are_not_asked(overlap):
    from eulersym.generated import heavy_top_euler_poisson as kernel

    y = np.linspace(0.1, 1.0, 30).reshape(10, 3)
    out = np.empty((4, 3))
    params = [1.0, 1, 0.5, 2.0, 9.81, 0.3]  # a float and an int: no memory to share
    assert kernel.invariants_batched(0.0, y, *params, out=out) is out
    if overlap == "view of y":
        out, y = y[:4], y
    elif overlap == "memoryview of out":
        params[0] = memoryview(out[1])  # not an ndarray, yet its memory is out's: still asked
    elif overlap == "0-d view of out":
        params[0] = out[0, 0, ...]
    else:
        params[0] = out[1]
    with pytest.raises(InvalidInput, match="overlapping"):
        kernel.invariants_batched(0.0, y, *params, out=out)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.lists(st.integers(0, 3), max_size=3).map(tuple), min_size=1, max_size=8))
def test_batch_is_numpys_broadcast_shape_or_its_refusal(shapes):
    try:
        expected = np.broadcast_shapes(*shapes)
    except ValueError:
        with pytest.raises(InvalidInput, match="arguments"):
            _runtime._batch(shapes)
    else:
        assert _runtime._batch(shapes) == expected
        assert type(_runtime._batch(shapes)) is tuple


@pytest.mark.parametrize("value", [1.5, 2, True, np.float64(1.0), np.array(2.0), np.ones((2, 3)), [1.0, 2.0],
                                   [[1.0], [2.0]], (), "text", None, np.ones((2, 3))[:, ::2]])
def test_shape_is_numpys_shape(value):
    assert _runtime._shape(value) == np.shape(value)


# ---------------------------------------------------------------------------------------------------------------
# Emitted rows: a view named once per row is the same arithmetic as a subscript per statement

a, b, k = sp.symbols("a b k", real=True)
_ATOMS = st.sampled_from([a, b, k, a**2, b**2, 1 / b, a * b, sp.Rational(1, 3), sp.Float("0.5"), -k])
_TERMS = st.lists(_ATOMS, min_size=1, max_size=3).map(lambda xs: sp.Mul(*xs))
_EXPRESSIONS = st.lists(_TERMS, min_size=1, max_size=4).map(lambda xs: sp.Add(*xs))


@settings(max_examples=150, deadline=None)
@given(_EXPRESSIONS, st.integers(0, 2**32 - 1))
def test_a_row_view_writes_the_same_bits_as_subscripts(expr, seed):
    printer, arrays = make_printer("batched"), {a, b}
    rng = np.random.default_rng(seed)
    namespace = {"np": np, "a": rng.uniform(0.5, 2, 7), "b": rng.uniform(0.5, 2, 7), "k": float(rng.uniform(0.5, 2))}
    subscripts = _emit_into(expr, "out[1, ...]", printer, arrays)
    view = ["row = out[1, ...]"] + _emit_into(expr, "row", printer, arrays)
    results = []
    for lines in (subscripts, view):
        namespace["out"] = np.full((2, 7), np.nan)
        exec(compile("\n".join(lines), "<emitted>", "exec"), namespace)  # our own emitted text
        results.append(namespace["out"].tobytes())
    assert results[0] == results[1]
    values = namespace["a"], namespace["b"], namespace["k"]
    expected = sp.lambdify([a, b, k], expr, "numpy")(*values)
    # Terms may cancel: the rounding error is relative to the sum of the terms' sizes, not to their sum.
    scale = sum(np.abs(sp.lambdify([a, b, k], term, "numpy")(*values)) for term in sp.Add.make_args(expr))
    assert np.all(np.abs(namespace["out"][1] - expected) <= 1e-13 * np.broadcast_to(scale, (7,)))
    assert np.isnan(namespace["out"][0]).all()  # the other row untouched


@pytest.mark.parametrize(("expr", "reference"), [
    (a**2, lambda a, b: a * a),
    (a**2 + b, lambda a, b: np.add(a * a, b)),
    (a**2 / b, lambda a, b: np.divide(a * a, b)),
    (3 * a**2, lambda a, b: np.multiply(a * a, 3)),
    (a**2 + b**2, lambda a, b: np.add(a * a, b * b)),
])
def test_a_square_written_into_its_row_is_the_product_as_printed(expr, reference):
    """``np.multiply(x, x, out=row)`` replaced ``row[...] = (x*x)``: the same product, bit for bit."""
    rng = np.random.default_rng(7)
    namespace = {"np": np, "a": rng.uniform(-2, 2, 9), "b": rng.uniform(0.5, 2, 9), "out": np.empty((1, 9))}
    lines = ["row = out[0, ...]"] + _emit_into(expr, "row", make_printer("batched"), {a, b})
    assert any(line.startswith("np.multiply(") and ", out=row)" in line for line in lines), lines
    exec(compile("\n".join(lines), "<emitted>", "exec"), namespace)  # our own emitted text
    assert namespace["out"][0].tobytes() == reference(namespace["a"], namespace["b"]).tobytes()
