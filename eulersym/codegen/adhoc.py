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

import sympy as sp
from sympy.core.function import AppliedUndef

from eulersym.codegen.emitter import Argument, FunctionSpec, ModuleSpec, emit_module, local_name
from eulersym.codegen.runtime import RUNTIME_SOURCE
from eulersym.errors import InvalidInput

__all__ = ["compile_expressions", "freeze"]


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


def _as_matrix(expressions) -> sp.Matrix:
    if isinstance(expressions, sp.MatrixBase):
        return sp.Matrix(expressions)
    if isinstance(expressions, (list, tuple)):
        items = list(expressions)
        if items and all(isinstance(e, (list, tuple)) for e in items):
            return sp.Matrix(items)
        return sp.Matrix(len(items), 1, [sp.sympify(e, strict=True) if not isinstance(e, sp.Basic) else e
                                         for e in items])
    if isinstance(expressions, sp.Basic):
        return sp.Matrix([expressions])
    raise InvalidInput("expressions", expressions, "a SymPy expression, a list of them, or a Matrix")


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
    eulersym.errors.InvalidInput: f.f='b' is not valid: expected no free symbols other than the arguments (a)
    """
    if flavour not in ("scalar", "batched"):
        raise InvalidInput("flavour", flavour, "'scalar' or 'batched'")
    if not isinstance(name, str) or not name.isidentifier():
        raise InvalidInput("name", name, "a Python identifier")
    matrix = _as_matrix(expressions)
    groups = [tuple(a) if isinstance(a, (list, tuple)) else (a,) for a in arguments]
    vectors = [isinstance(a, (list, tuple)) for a in arguments]
    mapping = freeze([s for group in groups for s in group])
    replace = {k: v for k, v in mapping.items() if k is not v}
    if replace:
        matrix = matrix.xreplace(replace)
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
    source = emit_module(module, versions={"eulersym": "ad hoc", "sympy": sp.__version__}, runtime_import="")
    namespace: dict = {}
    exec(compile(RUNTIME_SOURCE, "<eulersym runtime>", "exec"), namespace)  # our own fixed text
    exec(compile(source, f"<eulersym.codegen {name}>", "exec"), namespace)  # text we just emitted
    func = namespace[name if flavour == "scalar" else name + "_batched"]
    func.source = source
    return func
