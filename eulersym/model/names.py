"""The names a model's expressions may use, SymPy-free: what :class:`~eulersym.model.spec.Model` checks at
construction, before any parsing, and what :mod:`eulersym.model.expressions` gives a meaning to.

- ``t``, the time;
- ``omega`` (a vector) and ``omega1``, ``omega2``, ``omega3``: the body components of the angular velocity;
- ``gamma`` and ``gamma1..3``: the upward vertical (space z) in body components;
- ``q0..q3``: the attitude quaternion, scalar first, ``v_space = R(q) v_body``;
- ``inertia``: the model's 3×3 inertia tensor (about the pivot, or the centre of mass of a free body);
- ``pi``; the functions of :data:`FUNCTION_NAMES` (those of :data:`eulersym.parsing.FUNCTIONS` and the vector
  helpers ``cross dot norm to_body to_space``);
- the model's parameters.

Examples
--------
>>> names_in("3*n**2*cross(to_body([cos(n*t), 0, 0]), inertia*omega) + 2e3*k")
['n', 'cross', 'to_body', 'cos', 'n', 't', 'inertia', 'omega', 'k']
>>> "omega2" in STATE_NAMES, "t" in STATE_NAMES
(True, False)
"""

from __future__ import annotations

import keyword
import re

__all__ = [
    "TIME",
    "OMEGA_NAMES",
    "GAMMA_NAMES",
    "Q_NAMES",
    "STATE_NAMES",
    "VECTOR_NAMES",
    "INERTIA",
    "SCALAR_FUNCTIONS",
    "VECTOR_FUNCTIONS",
    "FUNCTION_NAMES",
    "RESERVED",
    "FORBIDDEN",
    "names_in",
]

TIME = "t"
OMEGA_NAMES = ("omega1", "omega2", "omega3")
GAMMA_NAMES = ("gamma1", "gamma2", "gamma3")
Q_NAMES = ("q0", "q1", "q2", "q3")
#: Every state component an expression may name.
STATE_NAMES = (*OMEGA_NAMES, *GAMMA_NAMES, *Q_NAMES)
#: Names of 3-vectors: ``omega`` = [omega1, omega2, omega3], ``gamma`` = [gamma1, gamma2, gamma3].
VECTOR_NAMES = ("omega", "gamma")
INERTIA = "inertia"
#: The scalar functions of the whitelist parser (kept equal to ``eulersym.parsing.FUNCTIONS`` by a test).
SCALAR_FUNCTIONS = (
    "sin", "cos", "tan", "cot", "sec", "csc", "asin", "acos", "atan", "arcsin", "arccos", "arctan", "atan2",
    "sinh", "cosh", "tanh", "sqrt", "exp", "log", "ln", "abs", "sign", "min", "max",
)
#: Vector helpers: ``cross(a, b)``, ``dot(a, b)``, ``norm(a)``, ``to_body(v)`` (space → body components,
#: ``R(q)ᵀ v``), ``to_space(v)`` (body → space, ``R(q) v``).
VECTOR_FUNCTIONS = ("cross", "dot", "norm", "to_body", "to_space")
FUNCTION_NAMES = (*SCALAR_FUNCTIONS, *VECTOR_FUNCTIONS)
#: Names a parameter may not take.
RESERVED = frozenset({TIME, *STATE_NAMES, *VECTOR_NAMES, INERTIA, "pi", *FUNCTION_NAMES})

#: Names the whitelist parser refuses outright (Python keywords and dangerous built-ins; equal to the parser's
#: list, checked by a test).
FORBIDDEN = frozenset(set(keyword.kwlist) - {"lambda"}) | frozenset({
    "eval", "exec", "compile", "open", "getattr", "setattr", "delattr", "globals", "locals", "vars", "input",
    "breakpoint", "print", "exit", "quit", "help", "memoryview", "object", "type", "super", "dir", "os", "sys",
    "subprocess", "builtins",
})

#: A number or a name (group 1); compiled on first use by :mod:`re`'s cache (a scene without formulas never needs it).
_LEXEME = r"(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|([A-Za-z_][A-Za-z0-9_]*)"


def names_in(text: str) -> list[str]:
    """The ASCII names in a formula, in order (numbers such as ``2e3`` are skipped, not read as names).

    Examples
    --------
    >>> names_in("1.5e-3*omega1 + sin(a_2)")
    ['omega1', 'sin', 'a_2']
    """
    return [m.group(1) for m in re.finditer(_LEXEME, text, re.ASCII) if m.group(1)]
