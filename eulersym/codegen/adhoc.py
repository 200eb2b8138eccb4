"""The ad-hoc route: compile any list of SymPy expressions into a Python function, with the emitter's CSE.

This is ``sympy.lambdify`` for the user's own expressions, but through the same emitter (one CSE pass, the
same printers, the same shape checks) as the committed kernels in ``generated/``: what you test here is what
``eulersym generate`` would write.

Examples
--------
>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> f = compile_expressions([sp.sin(x) * y, sp.sin(x) + y], [x, y])
>>> f(0.0, 2.0)
[0.0, 2.0]
"""

from __future__ import annotations

import keyword
import math

import sympy as sp
from sympy.core.function import AppliedUndef

from eulersym.codegen.emitter import Argument, FunctionSpec, ModuleSpec, check_expressions, emit_module, local_name
from eulersym.errors import InvalidInput

__all__ = ["compile_expressions", "freeze"]

#: Names the compiled module's namespace uses: a function of that name would shadow them.
_TAKEN = frozenset({"np", "math", "out", "extra", "STATE", "PARAMETERS", "DEFAULTS", "INVARIANTS"}
                   | {n for n in dir(math) if not n.startswith("_")})


def freeze(objects):
    """Map functions of time and their first derivatives to plain real symbols: ``phi(t)`` → ``phi``,
    ``phi'(t)`` → ``phidot``.

    Returns the mapping (only for the ``AppliedUndef`` and ``Derivative`` objects among ``objects``; symbols
    map to themselves).

    Examples
    --------
    >>> from eulersym.symbols import phi, t
    >>> freeze([phi, phi.diff(t)])
    {phi(t): phi, Derivative(phi(t), t): phidot}
    """
    mapping = {}
    for obj in objects:
        if isinstance(obj, sp.Symbol):
            mapping[obj] = obj
        elif isinstance(obj, AppliedUndef):
            mapping[obj] = sp.Symbol(obj.func.__name__, real=True)
        elif (isinstance(obj, sp.Derivative) and isinstance(obj.expr, AppliedUndef)
              and obj.derivative_count == 1):
            mapping[obj] = sp.Symbol(obj.expr.func.__name__ + "dot", real=True)
        else:
            raise InvalidInput("arguments", obj, "symbols, functions of t such as phi(t), or their first derivatives")
    return mapping


def _expression(argument: str, value):
    """One output: a SymPy expression or a plain number (a string is not parsed here)."""
    if isinstance(value, sp.Basic) and not isinstance(value, sp.MatrixBase):
        return value
    if isinstance(value, (str, bytes)):
        raise InvalidInput(argument, value, "a SymPy expression, not a string (strings are not parsed here: "
                                            "eulersym.parsing.parse reads a formula safely)")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InvalidInput(argument, value, "a SymPy expression or a number")
    return sp.sympify(value, strict=True)


def _as_matrix(expressions) -> sp.Matrix:
    if isinstance(expressions, sp.MatrixBase):
        if 0 in expressions.shape:
            raise InvalidInput("expressions", expressions, "at least one expression")
        return sp.Matrix(expressions)
    if isinstance(expressions, (list, tuple)):
        items = list(expressions)
        if not items:
            raise InvalidInput("expressions", expressions, "at least one expression")
        if all(isinstance(e, (list, tuple)) for e in items):
            widths = {len(row) for row in items}
            if len(widths) != 1 or 0 in widths:
                raise InvalidInput("expressions", expressions, "rows of one common, non-zero length (a matrix)")
            return sp.Matrix([[_expression(f"expressions[{i}][{j}]", e) for j, e in enumerate(row)]
                              for i, row in enumerate(items)])
        return sp.Matrix(len(items), 1, [_expression(f"expressions[{i}]", e) for i, e in enumerate(items)])
    if isinstance(expressions, sp.Basic):
        return sp.Matrix([expressions])
    raise InvalidInput("expressions", expressions, "a SymPy expression, a list of them, or a Matrix")


def _check_outputs(matrix: sp.Matrix, allowed: set) -> None:
    """Every output uses the arguments only: a leftover symbol is named with the output that holds it."""
    flat = list(matrix)
    for i, expr in enumerate(flat):
        label = f"expressions[{i}]" if matrix.cols == 1 else f"expressions[{i // matrix.cols}][{i % matrix.cols}]"
        extra = sorted(expr.free_symbols - allowed, key=sp.default_sort_key)
        if extra:
            names = ", ".join(map(str, extra))
            given = ", ".join(sorted(map(str, allowed))) or "none"
            raise InvalidInput(label, str(expr), f"symbols from the arguments only ({given}); {names} "
                                                 f"{'is' if len(extra) == 1 else 'are'} not among them: add "
                                                 f"{'it' if len(extra) == 1 else 'them'} to the arguments or "
                                                 "substitute a value")
        check_expressions([expr], allowed, what=label)


def compile_expressions(expressions, arguments, *, flavour: str = "scalar", name: str = "f"):
    """Compile SymPy expressions into a function of ``arguments`` (one CSE pass, ``math`` or NumPy).

    Parameters
    ----------
    expressions : sympy.Expr, list of sympy.Expr, list of lists, or sympy.Matrix
        The outputs. A list (or a column) gives a flat output, a Matrix of several columns a nested one.
    arguments : sequence
        In signature order. Each item is a symbol (a scalar argument), a function of time such as ``phi(t)``
        or its first derivative (frozen to ``phi``/``phidot``), or a tuple of those (a vector argument, named
        ``y`` — ``y0, y1, ...`` if there are several — and unpacked in the given order).
    flavour : {"scalar", "batched"}
        ``"scalar"``: Python floats and ``math``, returns a new list on every call. ``"batched"``: NumPy, vector
        arguments of shape ``(n, *batch)``, scalars broadcast, optional ``out=``; returns an array.
    name : str
        The function's name (a Python identifier).

    Returns
    -------
    function
        With the emitted source in its ``source`` attribute.

    Raises
    ------
    eulersym.errors.InvalidInput
        A leftover free symbol, ``Derivative``, undefined function or ``Vector``, named; a bad flavour.

    Examples
    --------
    >>> import numpy as np
    >>> import sympy as sp
    >>> a, b, k = sp.symbols("a b k")
    >>> f = compile_expressions([k * a * b, a + b], [(a, b), k], flavour="batched")
    >>> f(np.array([[1.0, 2.0], [3.0, 4.0]]), 2.0)
    array([[ 6., 16.],
           [ 4.,  6.]])
    >>> compile_expressions([a + b], [a])
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: expressions[0]='a + b' is not valid: expected symbols from the arguments only (a); b is not among them: add it to the arguments or substitute a value
    """
    if flavour not in ("scalar", "batched"):
        raise InvalidInput("flavour", flavour, "'scalar' or 'batched'")
    if (not isinstance(name, str) or not name.isidentifier() or keyword.iskeyword(name) or name.startswith("_")
            or name in _TAKEN):
        raise InvalidInput("name", name, "a Python identifier that is not a keyword, does not start with '_' and "
                                         "is not a name the compiled code uses (np, math's functions)")
    matrix = _as_matrix(expressions)
    if isinstance(arguments, (str, bytes)) or not isinstance(arguments, (list, tuple)):
        raise InvalidInput("arguments", arguments, "a list of symbols (or tuples of symbols for vectors), in "
                                                   "signature order")
    groups = [tuple(a) if isinstance(a, (list, tuple)) else (a,) for a in arguments]
    vectors = [isinstance(a, (list, tuple)) for a in arguments]
    mapping = freeze([s for group in groups for s in group])
    replace = {k: v for k, v in mapping.items() if k is not v}
    if replace:
        matrix = matrix.xreplace(replace)
    symbols_in_order = [mapping[s] for group in groups for s in group]
    if len(set(symbols_in_order)) != len(symbols_in_order):
        repeated = sorted({str(x) for x in symbols_in_order if symbols_in_order.count(x) > 1})
        raise InvalidInput("arguments", [str(x) for x in symbols_in_order],
                           f"each symbol once ({', '.join(repeated)} given more than once)")
    _check_outputs(matrix, set(symbols_in_order))
    n_vectors = sum(vectors)
    specs = []
    k = 0
    for group, is_vector in zip(groups, vectors):
        symbols = tuple(mapping[s] for s in group)
        if is_vector:
            arg_name = "y" if n_vectors == 1 else f"y{k}"
            k += 1
            specs.append(Argument(arg_name, symbols, vector=True))
        else:
            specs.append(Argument(local_name(symbols[0]), symbols))
    function = FunctionSpec(name, tuple(specs), matrix)
    module = ModuleSpec(name, f"Compiled on the fly by eulersym.codegen.compile_expressions ({name}).",
                        "compile_expressions", (function,))
    source = emit_module(module, versions={"eulersym": "ad hoc", "sympy": sp.__version__})
    namespace: dict = {}
    exec(compile(source, f"<eulersym.codegen {name}>", "exec"), namespace)  # text we just emitted
    func = namespace[name if flavour == "scalar" else name + "_batched"]
    func.source = source
    return func
