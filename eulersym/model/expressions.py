"""A model's formulas — torques, potentials, numbers written as expressions — read by the whitelist parser.

:func:`parse` reads a string with :func:`eulersym.parsing.parse` (never ``eval``) in the names of
:mod:`eulersym.model.names`, with a meaning for each: ``t``; ``omega``, ``omega1..3``; ``gamma``,
``gamma1..3``; ``q0..q3`` (the symbols of :mod:`eulersym.model.mechanics`); ``inertia``; the model's parameters;
``pi``; the parser's functions; and the vector helpers ``cross``, ``dot``, ``norm``, ``to_body``, ``to_space``.
A list ``[a, b, c]`` is a vector. Names are strict: any other name is refused with a did-you-mean.

Convention: ``q`` is the attitude quaternion, scalar first, and ``v_space = R(q) v_body``;
``to_body(v) = R(q)ᵀ v`` gives the body components of a vector whose space components are ``v``, and
``to_space(v) = R(q) v``. ``R(q)`` is the polynomial form of the rotation of a unit quaternion
(:func:`eulersym.rotation.from_quaternion` gives ``A = R(q)ᵀ``).

Examples
--------
A satellite's gravity-gradient torque on a circular orbit of rate ``n``:

>>> import sympy as sp
>>> ns = namespace({"n": sp.Symbol("n", real=True)}, inertia=sp.diag(1, 2, 3))
>>> N = parse("3*n**2*cross(to_body([cos(n*t), sin(n*t), 0]), inertia*to_body([cos(n*t), sin(n*t), 0]))",
...           ns, argument="torque.body", shape="vector")
>>> N.shape
(3, 1)
>>> parse("omega1 + omga2", ns, argument="torque.body")
Traceback (most recent call last):
...
eulersym.errors.InvalidInput: torque.body='omga2' is not valid: expected a known name: ... (did you mean 'omega2'?)
"""

from __future__ import annotations

from typing import Mapping

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.model import names as N
from eulersym.model.mechanics import GAMMA, OMEGA, Q, Mechanics, t
from eulersym.parsing import check_expansion, parse as _parse
from eulersym.rotation import from_quaternion

__all__ = ["parse", "namespace", "to_body", "to_space", "VECTOR_FUNCTIONS", "SHAPES"]

#: The shapes :func:`parse` can require.
SHAPES = ("scalar", "vector", "any")


def _attitude() -> sp.ImmutableMatrix:
    """A = R(q)ᵀ, ``r_body = A r_space``, in the state symbols q0..q3 (polynomial: q is a unit quaternion)."""
    return sp.ImmutableMatrix(from_quaternion(list(Q)))


_A = _attitude()


def to_body(v) -> sp.ImmutableMatrix:
    """Body components of a vector given by its space components: ``R(q)ᵀ v``, in q0..q3.

    Examples
    --------
    The vertical of a body turned by a quarter turn about space x (q = (cos π/4, sin π/4, 0, 0)):

    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Q
    >>> at = dict(zip(Q, (sp.sqrt(2) / 2, sp.sqrt(2) / 2, 0, 0)))
    >>> to_body([0, 0, 1]).xreplace(at).T
    Matrix([[0, 1, 0]])
    """
    return sp.ImmutableMatrix(_A * sp.Matrix(v))


def to_space(v) -> sp.ImmutableMatrix:
    """Space components of a vector given by its body components: ``R(q) v``, in q0..q3.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Q
    >>> at = dict(zip(Q, (sp.Rational(1, 2),) * 4))   # a third of a turn about (1, 1, 1)
    >>> to_space([1, 0, 0]).xreplace(at).T
    Matrix([[0, 1, 0]])
    """
    return sp.ImmutableMatrix(_A.T * sp.Matrix(v))


def _cross(a, b):
    return sp.ImmutableMatrix(sp.Matrix(a).cross(sp.Matrix(b)))


def _dot(a, b):
    return sp.Matrix(a).dot(sp.Matrix(b))


def _norm(a):
    return sp.sqrt(sp.Matrix(a).dot(sp.Matrix(a)))


#: name → (function, argument kinds), for :func:`eulersym.parsing.parse`'s ``functions=``.
VECTOR_FUNCTIONS = {
    "cross": (_cross, ("vector", "vector")),
    "dot": (_dot, ("vector", "vector")),
    "norm": (_norm, ("vector",)),
    "to_body": (to_body, ("vector",)),
    "to_space": (to_space, ("vector",)),
}


def namespace(parameters: Mapping[str, sp.Basic] = (), *, inertia=None, state: bool = True,
              omega: bool = True, time: bool = True) -> dict:
    """The names of a model's expressions, each with its SymPy meaning.

    Parameters
    ----------
    parameters : mapping name → Symbol (or expression)
    inertia : 3×3 matrix, optional
        The meaning of ``inertia`` (absent when None).
    state : bool
        Include the state names (``omega``, ``gamma``, ``q`` and their components).
    omega : bool
        Include ``omega`` and ``omega1..3`` (a potential energy must not depend on them).
    time : bool
        Include ``t``.

    Examples
    --------
    >>> sorted(namespace({"a": 1}, state=False, time=False))
    ['a']
    >>> namespace()["gamma"].T
    Matrix([[gamma1, gamma2, gamma3]])
    """
    ns: dict = {}
    if time:
        ns[N.TIME] = t
    if state:
        ns.update({s.name: s for s in (*GAMMA, *Q)})
        ns["gamma"] = sp.ImmutableMatrix(GAMMA)
        if omega:
            ns.update({s.name: s for s in OMEGA})
            ns["omega"] = sp.ImmutableMatrix(OMEGA)
    if inertia is not None:
        ns[N.INERTIA] = sp.ImmutableMatrix(inertia)
    for name, value in dict(parameters).items():
        if name in N.RESERVED:
            raise InvalidInput(f"parameters.{name}", value, "a name that is not one of the model's own names "
                               "(t, omega, gamma, q0..q3, inertia, pi, the functions)")
        ns[name] = sp.sympify(value) if not isinstance(value, sp.Basic) else value
    return ns


def mechanics_namespace(mech: Mechanics) -> dict:
    """Every name an expression about ``mech`` may use: state, ``t``, ``inertia``, the parameters.

    Examples
    --------
    >>> from eulersym.model.mechanics import Mechanics
    >>> m = Mechanics(name="m", inertia=sp.ImmutableMatrix(sp.diag(1, 2, 3)), mass=sp.Integer(1))
    >>> mechanics_namespace(m)["inertia"][2, 2]
    3
    """
    return namespace({s.name: s for s in mech.parameter_symbols}, inertia=mech.inertia)


def parse(text, mech_or_namespace, *, argument: str, shape: str = "scalar"):
    """Read a model expression with the whitelist parser, in a model's names.

    Parameters
    ----------
    text : str
        The formula (``"3*n**2*cross(to_body(e), inertia*to_body(e))"``, ``"-c*omega"``, ``"[0, 0, N0]"``).
    mech_or_namespace : Mechanics or mapping
        A :class:`~eulersym.model.mechanics.Mechanics` (its state names, ``t``, ``inertia`` and parameters), or
        a namespace mapping name → SymPy object (see :func:`namespace`).
    argument : str
        The name of the input in messages (the TOML key: ``torque.body``).
    shape : {"scalar", "vector", "any"}
        What the formula must give: a scalar, a 3×1 vector, or either.

    Returns
    -------
    sympy.Expr or 3×1 sympy.ImmutableMatrix

    Raises
    ------
    InvalidInput
        An unknown name (with a did-you-mean), a vector where a scalar belongs or the reverse, an equation, a
        malformed formula; :class:`~eulersym.errors.UnsafeExpression` for anything beyond plain math, or beyond
        :data:`eulersym.parsing.MAX_EXPANDED_TERMS` terms once multiplied out (the exact proofs expand it).

    Examples
    --------
    >>> from eulersym.model.mechanics import Mechanics
    >>> c = sp.Symbol("c", real=True)
    >>> m = Mechanics(name="damped", inertia=sp.ImmutableMatrix(sp.diag(1, 2, 3)), mass=sp.Integer(1),
    ...               parameters=((c, 0.1),))
    >>> parse("-c*omega", m, argument="torque.body", shape="vector").T
    Matrix([[-c*omega1, -c*omega2, -c*omega3]])
    >>> parse("omega", m, argument="torque.potential")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: torque.potential='omega' is not valid: expected a scalar, not a vector
    """
    if shape not in SHAPES:
        raise InvalidInput("shape", shape, "one of " + ", ".join(SHAPES))
    ns = mechanics_namespace(mech_or_namespace) if isinstance(mech_or_namespace, Mechanics) \
        else dict(mech_or_namespace)
    value = _parse(text, argument=argument, names=ns, functions=VECTOR_FUNCTIONS, strict=True)
    check_expansion(value, argument, text)  # the exact proofs expand it: refuse what would not end
    if isinstance(value, (list, sp.Equality)):
        raise InvalidInput(argument, text, f"an expression (a {shape}), not an equation")
    if isinstance(value, sp.MatrixBase):
        if shape == "any" and value.shape == (3, 3):
            return sp.ImmutableMatrix(value)
        wanted = "a vector (3 components)" if shape != "scalar" else "a scalar"
        if value.shape not in ((3, 1), (1, 3)):
            raise InvalidInput(argument, text, f"{wanted}, not a {value.shape[0]}×{value.shape[1]} matrix")
        if shape == "scalar":
            raise InvalidInput(argument, text, "a scalar, not a vector")
        return sp.ImmutableMatrix(value.reshape(3, 1))
    if shape == "vector":
        raise InvalidInput(argument, text, "a vector (3 components: [x, y, z] or a vector expression), "
                           "not a scalar")
    return value
