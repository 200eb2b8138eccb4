"""The helpers every generated NumPy module carries, as source text: written into each module, after its imports.

A generated module is one file that imports NumPy and ``math`` and nothing else: copied anywhere (a plain NumPy
environment without eulersym), it runs. Its helpers are this text, the same in every module:

- the errors: :func:`_error` raises ``eulersym.errors.<kind>(argument, value, expected)`` where eulersym is
  importable (looked up when an error is raised, never at import), else a ``ValueError`` with the same message;
- the batched flavour's shape checks (``_as_vector``, ``_shape``, ``_batch``, ``_prepare_out``) and its blocks of a
  long 1-d batch (``_blocked``, :data:`_BLOCK` columns each).

Every name starts with ``_`` and is refused as an argument or parameter name (:data:`RUNTIME_NAMES`), so no
argument can shadow a helper. Module-level statements are functions and one literal constant only: the module
level of a generated file stays what :func:`eulersym.codegen.emitter.emit_module` writes (tests/test_untrusted_code).

Examples
--------
>>> import numpy as np
>>> namespace = {"np": np}
>>> exec(compile(RUNTIME_SOURCE, "<runtime>", "exec"), namespace)
>>> namespace["_prepare_out"](None, (2,), ((3,), ())).shape
(2, 3)
>>> raise namespace["_error"]("InvalidInput", "y", [1.0], "a sequence of 3 floats")
Traceback (most recent call last):
...
eulersym.errors.InvalidInput: y=[1.0] is not valid: expected a sequence of 3 floats
"""

from __future__ import annotations

import ast

__all__ = ["RUNTIME_SOURCE", "RUNTIME_NAMES"]

RUNTIME_SOURCE = '''\
# ---- The module's own helpers (eulersym.codegen.runtime, the same in every generated module) ----

#: Columns per block of a long 1-d batch: a block's temporaries (a few rows of 128 KiB) stay in cache.
_BLOCK = 16384


def _error(kind, argument, value, expected):
    """The error to raise: ``eulersym.errors.<kind>(argument, value, expected)`` where eulersym is installed, else
    a ValueError with the same message (this module imports nothing from eulersym: it runs with NumPy alone)."""
    try:
        from eulersym import errors
    except ImportError:
        shown = " ".join(repr(value).split())
        if len(shown) > 120:
            shown = shown[:117] + "..."
        return ValueError(f"{argument}={shown} is not valid: expected {expected}")
    return getattr(errors, kind)(argument, value, expected)


def _singular(name, value, expected):
    """The error for a state on the singularity of the coordinates (where the scalar flavour divided by zero)."""
    return _error("SingularConfiguration", name, value, expected)


def _too_many(function, extra, names):
    """The error for surplus positional arguments."""
    order = ", ".join(names)
    return _error("InvalidInput", f"{function} arguments", f"{len(extra)} more than expected",
                  f"exactly {len(names)} positional arguments in the order ({order})")


def _wrong_length(name, value, names):
    """The error for a vector argument of the wrong length (scalar flavour)."""
    order = ", ".join(names)
    return _error("InvalidInput", name, value, f"a sequence of {len(names)} floats in the order ({order})")


def _as_vector(name, value, names):
    """``value`` as a float array of shape ``(len(names), *batch)``; otherwise InvalidInput naming the order."""
    array = np.asarray(value, dtype=float)
    if array.ndim == 0 or array.shape[0] != len(names):
        order = ", ".join(names)
        raise _error("InvalidInput", name, f"array of shape {array.shape}",
                     f"shape ({len(names)}, ...) with rows in the order ({order}), batch after")
    return array


def _shape(value):
    """``np.shape(value)``; a Python float or int (shape ``()``) and an ndarray cost no conversion."""
    kind = type(value)
    if kind is float or kind is int:
        return ()
    if kind is np.ndarray:
        return value.shape
    return np.shape(value)


def _batch(shapes):
    """The batch: ``np.broadcast_shapes(*shapes)``, without its cost when every non-empty shape is the same."""
    batch = ()
    for shape in shapes:
        if shape and shape != batch:
            if batch:  # two different batch shapes: NumPy's rules (and its refusal)
                try:
                    return np.broadcast_shapes(*shapes)
                except ValueError:
                    raise _error("InvalidInput", "arguments", f"batch shapes {shapes}",
                                 "shapes that broadcast together") from None
            batch = shape
    return batch


def _prepare_out(out, head, shapes, inputs=()):
    """A float array of shape ``head + batch`` (batch: the shapes broadcast), ``out`` itself if it fits.

    ``out`` is written in place row by row, so it may not overlap an input array (a Python float or int
    cannot: only the others are asked).
    """
    shape = tuple(head) + tuple(_batch(shapes))
    if out is None:
        return np.empty(shape)
    if not isinstance(out, np.ndarray) or out.shape != shape or out.dtype != np.float64:
        got = f"{type(out).__name__} of shape {getattr(out, 'shape', None)}, dtype {getattr(out, 'dtype', None)}"
        raise _error("InvalidInput", "out", got, f"a float64 ndarray of shape {shape}")
    for array in inputs:
        kind = type(array)
        if kind is not float and kind is not int and np.may_share_memory(out, array):
            raise _error("InvalidInput", "out", "an array overlapping an input",
                         "a separate array (out is written in place)")
    return out


def _blocked(block, out, head, args, vectors):
    """``block(*args, out)`` over slices of a long 1-d batch (``out.shape[head:] == (n,)``), else in one call.

    An argument is sliced when it carries the batch: a vector (``vectors[i]``) of shape ``(k, n)``, a scalar
    argument of shape ``(n,)``; anything else (floats, shape ``(1,)``) broadcasts as it is.
    """
    batch = out.shape[head:]
    if len(batch) != 1 or batch[0] <= 2 * _BLOCK:
        return block(*args, out)
    n = batch[0]
    sliced = [isinstance(a, np.ndarray) and a.ndim == 1 + v and a.shape[-1] == n for a, v in zip(args, vectors)]
    for start in range(0, n, _BLOCK):
        cut = slice(start, start + _BLOCK)
        block(*[a[..., cut] if s else a for a, s in zip(args, sliced)], out[..., cut])
    return out
'''

#: The module-level names the helpers define (an argument of one of these names would shadow it).
RUNTIME_NAMES = frozenset(
    node.targets[0].id if isinstance(node, ast.Assign) else node.name
    for node in ast.parse(RUNTIME_SOURCE).body
    if isinstance(node, (ast.Assign, ast.FunctionDef))
)
