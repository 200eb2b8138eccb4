"""The JAX backend: a kernel module's functions in ``jax.numpy``, ready for ``jax.jit``, ``jax.vmap`` and ``jax.grad``.

The same :func:`~eulersym.codegen.emitter.cse_pass` and printer methods as the NumPy module; the leaves call
``jnp.<name>`` (:data:`JAX_FUNCTIONS`). Each function is straight-line code on its arguments — no Python branch or
loop on a value, no in-place update, no NumPy call — so every JAX transformation applies. Shapes are read (static
under ``jit``) to refuse a state of the wrong length with a ``ValueError`` that names the order.

A module ``name`` written by ``eulersym generate --target jax`` has, for an ODE kernel::

    rhs(t, y, *params)         -> (n,) + batch        y of shape (n,) or (n, *batch): state first, batch after
    jac(t, y, *params)         -> (n, n) + batch      derived symbolically (tests: equal to jax.jacfwd(rhs))
    invariants(t, y, *params)  -> (k,) + batch
    rhs_batched, jac_batched, invariants_batched      the same functions under the NumPy module's names

and the NumPy module's contract (``STATE``, ``PARAMETERS``, ``DEFAULTS``, ``INVARIANTS``). Every operation is
elementwise, so a batch after the state's axis broadcasts (``rhs_batched(t, Y)`` equals ``jax.vmap(rhs)`` over the
columns of ``Y``) and the parameters may carry the batch too. The module imports ``jax.numpy`` and nothing of
eulersym; JAX computes in ``float32`` unless ``jax.config.update("jax_enable_x64", True)`` runs first.

Examples
--------
>>> import sympy as sp
>>> x = sp.Symbol("x", real=True)
>>> make_printer().doprint(sp.cos(x) + x**2 * sp.sqrt(x + 1))
'(x*x)*jnp.sqrt(x + 1) + jnp.cos(x)'
"""

from __future__ import annotations

import textwrap

import sympy as sp

from eulersym.codegen import emitter as E
from eulersym.errors import InvalidInput
from eulersym.validation import comment_text, docstring_text

__all__ = ["JAX_EMITTER_VERSION", "JAX_FUNCTIONS", "JAX_RESERVED", "emit_jax", "make_printer"]

#: Bumped whenever the emitted text changes for the same input (it is written in the header).
JAX_EMITTER_VERSION = "1"

#: SymPy function name → ``jax.numpy`` function (called as ``jnp.<name>``).
JAX_FUNCTIONS: dict[str, str] = {
    "sin": "sin", "cos": "cos", "tan": "tan", "asin": "arcsin", "acos": "arccos", "atan": "arctan",
    "atan2": "arctan2", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "asinh": "arcsinh",
    "acosh": "arccosh", "atanh": "arctanh", "exp": "exp", "log": "log", "sqrt": "sqrt", "Abs": "abs",
    "floor": "floor", "ceiling": "ceil",
}

#: Names the JAX module uses beyond the NumPy module's (an argument of such a name would shadow it).
JAX_RESERVED = frozenset({"jax", "jnp", "_stack", "_unpack"})

_Q = '"' * 3

_HELPERS = '''\
def _unpack(name, value, names):
    """The rows of a state ``value`` of shape ``(len(names), *batch)`` (shapes are static under ``jax.jit``)."""
    value = jnp.asarray(value)
    if value.ndim == 0 or value.shape[0] != len(names):
        raise ValueError(f"{name}=array of shape {value.shape} is not valid: expected shape ({len(names)}, ...) "
                         f"with rows in the order ({', '.join(names)}), batch after")
    return tuple(value[k] for k in range(len(names)))


def _stack(entries, shape=None):
    """``entries`` (arrays and numbers of broadcasting shapes) stacked on a new first axis; with ``shape`` (rows,
    columns), that axis made two (a matrix, row by row)."""
    out = jnp.stack(jnp.broadcast_arrays(*entries))
    return out if shape is None else out.reshape(shape + out.shape[1:])'''


def make_printer() -> E._Printer:
    """The JAX printer: the NumPy printer's methods with ``jnp.<name>`` for functions.

    Examples
    --------
    >>> import sympy as sp
    >>> make_printer().doprint(sp.Abs(sp.Symbol("x")))
    'jnp.abs(x)'
    """
    return E._Printer(JAX_FUNCTIONS, "jnp.")


def _check_names(spec: E.ModuleSpec) -> None:
    for f in spec.functions:
        for a in f.arguments:
            for name in (a.name, *a.names):
                if name in JAX_RESERVED:
                    raise InvalidInput("argument name", name, "a name other than jax, jnp, _stack and _unpack (the "
                                                              "JAX module calls them): rename the parameter")


def _function(f: E.FunctionSpec, cse: E.CsePass) -> str:
    printer = make_printer()
    reduced = cse.reduced[f.name]
    needed = cse.needed(list(reduced))
    args = ", ".join(a.name for a in f.arguments)
    shape = f"({f.out_shape[0]},)" if len(f.out_shape) == 1 else repr(f.out_shape)
    doc = [_Q + f"{f.name}({args}) -> array of shape {shape} + batch"
           + (f", rows ({docstring_text(', '.join(map(str, f.output_names)))})" if f.output_names else ""), ""]
    if f.doc:
        doc += ["    " + docstring_text(f.doc), ""]
    doc += ["    Arguments, in order (a vector: components first, batch after; scalars broadcast):"]
    doc += ["    " + line for line in E._order_doc(f)] + ["    " + _Q]
    body = []
    for a in f.arguments:
        if a.vector:
            trailing = "," if len(a.names) == 1 else ""
            body.append(f"{', '.join(a.names)}{trailing} = _unpack({a.name!r}, {a.name}, {a.names!r})")
        elif a.names[0] != a.name:
            body.append(f"{a.names[0]} = {a.name}")
    body += [f"{printer.doprint(sym)} = {printer.doprint(expr)}" for sym, expr in needed]
    if len(f.out_shape) == 1:
        body.append("return _stack([" + ", ".join(E._constant(printer, e) for e in reduced) + "])")
    else:
        entries = ", ".join(E._constant(printer, e) for e in reduced)
        body.append(f"return _stack([{entries}], {f.out_shape!r})")
    lines = [f"def {f.name}({args}):", "    " + doc[0], *doc[1:], *("    " + line for line in body)]
    return "\n".join(line.rstrip() for line in lines)


def _alias(f: E.FunctionSpec) -> str:
    args = ", ".join(a.name for a in f.arguments)
    return "\n".join([f"def {f.name}_batched({args}):",
                      f"    {_Q}``{f.name}`` under the NumPy module's name: ``{f.name}`` takes a batch after the "
                      f"state's axis already.{_Q}",
                      f"    return {f.name}({args})"])


def emit_jax(spec: E.ModuleSpec, *, versions: dict | None = None, header: tuple = ()) -> str:
    """The source of a module's JAX kernels (deterministic text; imports ``jax.numpy`` only).

    Parameters
    ----------
    spec : ModuleSpec
        What to emit (the same spec the NumPy emitter takes).
    versions : dict, optional
        ``{"eulersym": ..., "sympy": ...}`` for the header (defaults to the installed versions).
    header : tuple of str
        More header lines (escaped), such as a model's digest.

    Examples
    --------
    >>> import sympy as sp
    >>> t, a, k = sp.symbols("t a k", real=True)
    >>> args = (E.Argument("t", (t,)), E.Argument("y", (a,), vector=True), E.Argument("k", (k,)))
    >>> spec = E.ModuleSpec("decay", "Decay.", "hand", (E.FunctionSpec("rhs", args, sp.Matrix([-k * a])),),
    ...                     defaults=(0.5,))
    >>> source = emit_jax(spec, versions={"eulersym": "0", "sympy": "0"})
    >>> print(source[source.index("def rhs("):source.index("def rhs_batched(")].split(_Q)[-1].strip())
    a, = _unpack('y', y, ('a',))
        return _stack([-a*k])
    """
    E.check_module(spec)
    _check_names(spec)
    if versions is None:
        from eulersym import __version__

        versions = {"eulersym": __version__, "sympy": sp.__version__}
    cse = E.cse_pass(spec.functions)
    lines = [
        "# Generated by `eulersym generate --target jax` from eulersym.codegen.jax. Do not edit: regenerate.",
        f"# Source derivation: {comment_text(spec.source)}",
        f"# eulersym version: {comment_text(versions['eulersym'])}",
        f"# SymPy version: {comment_text(versions['sympy'])}",
        f"# Input hash: sha256:{E.input_hash(spec)}",
        f"# JAX emitter version: {JAX_EMITTER_VERSION}",
        *(f"# {comment_text(line)}" for line in header),
    ]
    description = textwrap.fill(docstring_text(spec.description.strip()), width=100, break_on_hyphens=False,
                                break_long_words=False).split("\n")
    doc = [_Q + description[0], *description[1:], "",
           "Functions (jax.numpy throughout, straight-line code: jax.jit, jax.vmap, jax.grad and jax.jacfwd apply;",
           "each also as ``<name>_batched``, the same function):", ""]
    for f in spec.functions:
        doc.append(f"- ``{f.name}({E._signature(f)})`` → {E._outputs_doc(f)}"
                   + (f": {docstring_text(f.doc)}" if f.doc else ""))
    doc += ["", "A vector takes the shape ``(n,)`` or ``(n, *batch)`` (components first, batch after) and every",
            "operation is elementwise, so batches broadcast, the parameters' included. JAX computes in float32",
            "unless ``jax.config.update(\"jax_enable_x64\", True)`` runs first. A singular state gives inf or nan",
            "(no check: a check would branch on a traced value)."]
    for note in spec.notes:
        doc += ["", *textwrap.fill(docstring_text(note), width=100, break_on_hyphens=False,
                                   break_long_words=False).split("\n")]
    doc.append(_Q)
    names = [f.name + suffix for suffix in ("", "_batched") for f in spec.functions]
    names += ["STATE", "PARAMETERS", "DEFAULTS", "INVARIANTS"]
    parts = lines + doc + ["", "import jax.numpy as jnp", "", f"__all__ = {names!r}", ""] + E.contract_lines(spec)
    parts += ["", "", _HELPERS]
    for f in spec.functions:
        parts += ["", "", _function(f, cse)]
    for f in spec.functions:
        parts += ["", "", _alias(f)]
    return "\n".join(parts).rstrip("\n") + "\n"
