"""Input checks at the package's boundary, shared by every layer (SymPy-free).

Each function returns the validated value or raises an :mod:`eulersym.errors` exception whose message names the
argument, the value and what is valid. SymPy objects are checked by duck typing (``.is_positive``, ``.is_real``)
so that this module never imports SymPy.

Examples
--------
>>> moments("I", (1.0, 2.0, 3.0))
(1.0, 2.0, 3.0)
>>> moments("I", (1.0, 1.0, 3.0))
Traceback (most recent call last):
...
eulersym.errors.InvalidInput: I=(1.0, 1.0, 3.0) is not valid: expected principal moments of a body: positive and I1 + I2 >= I3, I2 + I3 >= I1, I3 + I1 >= I2 (here I1 + I2 = 2 < I3 = 3)
"""

from __future__ import annotations

import builtins
import keyword
import math
import numbers
from typing import Any, Iterable, Sequence

from eulersym._numpy import np

from eulersym.errors import InvalidInput

__all__ = ["positive", "moments", "inertia_tensor", "finite_array", "choice", "is_symbolic", "GENERATED_CODE_NAMES",
           "docstring_text", "comment_text", "TRIANGLE_SLACK"]

#: Names that generated code uses at module level or calls (Python's keywords and built-ins, ``math``'s names, the
#: modules and the functions and tables a generated module defines): a parameter or argument that took one would
#: shadow what the code calls (``float``, ``isinstance``, ``fabs``, ``rhs_flat``), so they are refused by name.
GENERATED_CODE_NAMES = frozenset(
    set(keyword.kwlist) | set(dir(builtins)) | set(dir(math))
    | {"np", "numpy", "jax", "jnp", "math", "out", "extra", "shape", "row", "InvalidInput", "body", "STATE", "PARAMETERS",
       "DEFAULTS", "INVARIANTS", "FLAGS", "QUANTITIES"}
    | {f + s for f in ("rhs", "jac", "invariants", "quantities") for s in ("", "_flat", "_batched", "_loop")}
)


def docstring_text(text: str) -> str:
    r"""``text`` made safe inside a generated module's triple-quoted (non-raw) docstring: backslashes, double
    quotes and control characters escaped, so no text can close the docstring or change what follows; the
    docstring's value is ``text``.

    Examples
    --------
    >>> q = '"' * 3
    >>> print(docstring_text("x" + q + " + str(1) + " + q))
    x\"\"\" + str(1) + \"\"\"
    >>> import ast
    >>> hostile = "a" + q + "b" + chr(92)          # closes the docstring, then escapes its end
    >>> ast.literal_eval(q + docstring_text(hostile) + q) == hostile
    True
    """
    if not isinstance(text, str):
        raise InvalidInput("text", text, "a string")
    return comment_text(text.replace("\\", "\\\\").replace('"', '\\"'))


def comment_text(text: str) -> str:
    r"""``text`` made safe on one ``#`` comment line of a generated module: every character Python may read as a
    line break (and every other control character) written as its escape, so nothing leaves the comment.

    Examples
    --------
    >>> print(comment_text("model x\nimport os"))
    model x\nimport os
    """
    if not isinstance(text, str):
        raise InvalidInput("text", text, "a string")
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in text)


#: Relative slack allowed on the triangle inequalities of floating-point moments (a flat body has I1 + I2 = I3).
TRIANGLE_SLACK = 1e-12


def is_symbolic(value: Any) -> bool:
    """True for SymPy objects (anything with ``free_symbols`` that is not a plain number).

    Examples
    --------
    >>> is_symbolic(1.0)
    False
    """
    return hasattr(value, "free_symbols") and hasattr(value, "is_positive")


def _as_float(argument: str, value: Any, expected: str) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InvalidInput(argument, value, expected)
    out = float(value)
    if not math.isfinite(out):
        raise InvalidInput(argument, value, expected)
    return out


def positive(argument: str, value: Any):
    """Return ``value`` if it is (or may be, for symbols) a finite positive number.

    SymPy objects pass unless SymPy can prove them non-positive (``is_positive is False``) or they are not real.

    Examples
    --------
    >>> positive("M", 2)
    2
    >>> positive("M", 0.0)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: M=0.0 is not valid: expected a finite positive number
    """
    expected = "a finite positive number"
    if is_symbolic(value):
        if value.is_positive is False or value.is_real is False or _nonfinite(value):
            raise InvalidInput(argument, value, expected)
        return value
    if _as_float(argument, value, expected) <= 0:
        raise InvalidInput(argument, value, expected)
    return value


def _nonfinite(value) -> bool:  # SymPy: oo, zoo, nan
    return any(str(a) in ("oo", "-oo", "zoo", "nan") for a in getattr(value, "atoms", lambda: ())())


def moments(argument: str, values: Any, *, body: bool = True, shown: Any = None):
    """Validate principal moments of inertia: three of them, or one row of three per member.

    The one check of a body's moments in eulersym (a model's, a scene's keywords and every member of a sweep, the
    numerics' inputs): positive, and — for a body — the triangle inequalities.

    Parameters
    ----------
    argument : str
        Name used in the error message.
    values : iterable of 3 numbers or SymPy expressions, or an array of shape (..., 3)
        One body's moments, or a row of them per member (floats: checked all at once with NumPy).
    body : bool, optional
        Also require the triangle inequalities that every physical body satisfies:
        I1 + I2 ≥ I3, I2 + I3 ≥ I1, I3 + I1 ≥ I2 (floats with a relative slack of ``TRIANGLE_SLACK``).
    shown : optional
        The value the message shows (default ``values``), e.g. what the user wrote before a sweep was expanded.

    Returns
    -------
    tuple or ndarray
        The moments, unchanged (an array of rows is returned as given).

    Examples
    --------
    >>> moments("I", [2, 2, 1])
    (2, 2, 1)
    >>> moments("I", [1, -2, 3], body=False)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: I=[1, -2, 3] is not valid: expected three positive principal moments (I2=-2 is not)
    >>> import numpy as np
    >>> moments("moments", np.array([[1.0, 2.0, 3.0], [1.0, 2.0, 3.5]]))
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: moments=[[1.0, 2.0, 3.0], [1.0, 2.0, 3.5]] is not valid: expected principal moments of a body: positive and I1 + I2 >= I3, I2 + I3 >= I1, I3 + I1 >= I2 (here I1 + I2 = 3 < I3 = 3.5, member 1)
    """
    shown = values if shown is None else shown
    if hasattr(shown, "tolist") and hasattr(shown, "dtype"):  # an array (duck-typed: NumPy is not imported here)
        shown = shown.tolist()
    if hasattr(values, "dtype") and getattr(values, "ndim", 0) >= 1 and values.dtype.kind in "fiu":
        return _moment_rows(argument, values, body, shown)
    try:
        items = tuple(values)
    except TypeError:
        raise InvalidInput(argument, shown, "three principal moments (I1, I2, I3)") from None
    if len(items) != 3:
        raise InvalidInput(argument, shown, f"three principal moments (I1, I2, I3), got {len(items)} values")
    for k, value in enumerate(items, start=1):
        try:
            positive(f"{argument}[{k - 1}]", value)
        except InvalidInput:
            raise InvalidInput(argument, shown, f"three positive principal moments (I{k}={value!r} is not)") from None
    if not body or any(is_symbolic(v) and v.free_symbols for v in items):
        return items
    floats = [float(v) for v in items]  # one body: plain floats (the symbolic layers import no NumPy)
    scale = max(floats) * TRIANGLE_SLACK
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        if floats[i] + floats[j] < floats[k] - scale:
            raise InvalidInput(argument, shown, _TRIANGLE + f" (here I{i + 1} + I{j + 1} = {items[i] + items[j]:g} < "
                                                            f"I{k + 1} = {items[k]:g})")
    return items


_TRIANGLE = "principal moments of a body: positive and I1 + I2 >= I3, I2 + I3 >= I1, I3 + I1 >= I2"


def _moment_rows(argument: str, rows, body: bool, shown: Any, items: tuple | None = None):
    """:func:`moments` on an array of rows (..., 3); ``items``: the one row as the caller wrote it (for the message)."""
    m = np.asarray(rows, dtype=float)
    if m.shape[-1:] != (3,):
        raise InvalidInput(argument, shown, f"three principal moments (I1, I2, I3) per member, got shape {m.shape}")
    flat = m.reshape(-1, 3)
    bad = ~np.isfinite(flat) | (flat <= 0)
    if bad.any():
        member, k = (int(i) for i in np.argwhere(bad)[0])
        where = f", member {member}" if len(flat) > 1 else ""
        raise InvalidInput(argument, shown, f"three positive principal moments (I{k + 1}={flat[member, k]!r} is not"
                                            f"{where})")
    if not body:
        return rows
    scale = np.max(flat, axis=1) * TRIANGLE_SLACK
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        broken = flat[:, i] + flat[:, j] < flat[:, k] - scale
        if broken.any():
            member = int(np.argmax(broken))
            row = items if items is not None and len(flat) == 1 else flat[member].tolist()
            where = f", member {member}" if len(flat) > 1 else ""
            raise InvalidInput(argument, shown, _TRIANGLE + f" (here I{i + 1} + I{j + 1} = {row[i] + row[j]:g} < "
                                                            f"I{k + 1} = {row[k]:g}{where})")
    return rows


def inertia_tensor(argument: str, tensors: Any, *, shown: Any = None) -> np.ndarray:
    """Validate inertia tensors of bodies: a (3, 3) array, or one per member (..., 3, 3) — symmetric, positive
    definite, and their principal moments (the eigenvalues) those of a body (:func:`moments`).

    Examples
    --------
    >>> inertia_tensor("tensor", [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]]).shape
    (3, 3)
    >>> inertia_tensor("tensor", [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]])
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: tensor=[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]] is not valid: expected the tensor of a body: its principal moments [1.0, 1.0, 3.0] must satisfy I1 + I2 >= I3 (the triangle inequality)
    """
    shown = tensors if shown is None else shown
    if hasattr(shown, "tolist") and hasattr(shown, "dtype"):
        shown = shown.tolist()
    T = np.asarray(tensors, dtype=float)
    if T.shape[-2:] != (3, 3):
        raise InvalidInput(argument, shown, "a 3×3 symmetric inertia tensor")
    flat = T.reshape(-1, 3, 3)
    if not np.all(np.isfinite(flat)):
        raise InvalidInput(argument, shown, "a tensor of finite numbers")
    scale = np.max(np.abs(flat), axis=(1, 2))
    asym = np.max(np.abs(flat - flat.transpose(0, 2, 1)), axis=(1, 2)) > 1e-12 * scale
    if asym.any():
        member = int(np.argmax(asym))
        i, j = (int(x) for x in np.unravel_index(np.argmax(np.abs(flat[member] - flat[member].T)), (3, 3)))
        raise InvalidInput(argument, shown, f"a symmetric tensor: {argument}[{i}][{j}] = {flat[member, i, j]:g} but "
                                            f"{argument}[{j}][{i}] = {flat[member, j, i]:g}")
    eig = np.linalg.eigvalsh((flat + flat.transpose(0, 2, 1)) / 2)
    where = lambda member: f" (member {member})" if len(flat) > 1 else ""  # noqa: E731
    low = eig[:, 0] <= 1e-14 * np.where(scale > 0, scale, 1.0)
    if low.any():
        member = int(np.argmax(low))
        raise InvalidInput(argument, shown, f"a positive-definite tensor (its principal moments are "
                                            f"{[float(f'{e:.6g}') for e in eig[member]]}{where(member)})")
    broken = eig[:, 0] + eig[:, 1] < eig[:, 2] * (1 - TRIANGLE_SLACK)
    if broken.any():
        member = int(np.argmax(broken))
        raise InvalidInput(argument, shown, f"the tensor of a body: its principal moments "
                                            f"{[float(f'{e:.6g}') for e in eig[member]]} must satisfy I1 + I2 >= I3 "
                                            f"(the triangle inequality){where(member)}")
    return T


def finite_array(argument: str, value: Any, shape: Sequence[int | None] | None = None) -> np.ndarray:
    """Return ``value`` as a float64 array after checking it is finite and (optionally) of ``shape``.

    ``shape`` entries may be ``None`` for "any length".

    Examples
    --------
    >>> finite_array("omega0", [1, 2, 3], shape=(3,))
    array([1., 2., 3.])
    >>> finite_array("omega0", [1, float("nan"), 3], shape=(3,))
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: omega0=[1, nan, 3] is not valid: expected finite numbers (no NaN or infinity)
    >>> finite_array("angle", ["30", 0, 0])
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: angle=['30', 0, 0] is not valid: expected an array of real numbers, not text (a string is never converted to a number)
    """
    try:
        raw = np.asarray(value)
        text = raw.dtype.kind in "SU" or (raw.dtype.kind == "O" and any(isinstance(x, (str, bytes)) for x in raw.flat))
    except (TypeError, ValueError):
        text = False
    if text:  # "30" is text, never 30 radians: numbers are read by parsers that say so, not by float()
        raise InvalidInput(argument, value, "an array of real numbers, not text (a string is never converted to a number)")
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInput(argument, value, "an array of real numbers") from None
    if shape is not None:
        ok = arr.ndim == len(shape) and all(s is None or s == n for s, n in zip(shape, arr.shape))
        if not ok:
            want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
            raise InvalidInput(argument, value, f"an array of shape {want}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InvalidInput(argument, value, "finite numbers (no NaN or infinity)")
    return arr


def choice(argument: str, value: Any, valid: Iterable[str]):
    """Return ``value`` if it is one of ``valid``.

    Examples
    --------
    >>> choice("origin", "corner", ("center", "corner"))
    'corner'
    >>> choice("origin", "edge", ("center", "corner"))
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: origin='edge' is not valid: expected one of 'center', 'corner'
    """
    valid = tuple(valid)
    if not isinstance(value, str) or value not in valid:
        raise InvalidInput(argument, value, "one of " + ", ".join(repr(v) for v in valid))
    return value
