"""The symbolic content of a model — what every derivation needs, and nothing of the file it came from.

:class:`Mechanics` is the one object that connects the two halves of :mod:`eulersym.model`: the *specification*
(``Model``, TOML, parameters, parts, a pivot, torque strings — validated, SymPy-free where it can be) builds it;
the *derivations* (Newton–Euler and Lagrange routes, integrals of motion, kernels) take it and nothing else.

State names (plain real SymPy symbols, defined once here): ``omega1..3`` (body components of ω), ``gamma1..3``
(the upward vertical, space z, in body components), ``q0..q3`` (the attitude quaternion, scalar first,
``v_space = R(q) v_body``) and the time ``t`` (:data:`eulersym.symbols.t`). Torques and potentials are written in
these names and the model's parameter symbols only.

Examples
--------
>>> import sympy as sp
>>> from eulersym.model.mechanics import Mechanics, OMEGA
>>> a = sp.Symbol("a", real=True)
>>> m = Mechanics(name="kovalevskaya", inertia=sp.ImmutableMatrix(sp.diag(2, 2, 1)), mass=sp.Integer(1),
...               centre_of_mass=sp.ImmutableMatrix([a, 0, 0]), gravity=sp.Float(9.81), pivoted=True,
...               parameters=((a, 1.0),))
>>> m.free_symbols_allowed() >= {a, *OMEGA}
True
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from eulersym.symbols import STATE_GAMMA, STATE_OMEGA, STATE_Q, t

__all__ = ["Mechanics", "OMEGA", "GAMMA", "Q", "t", "STATE_SYMBOLS"]

#: Body components of the angular velocity (:data:`eulersym.symbols.STATE_OMEGA`).
OMEGA: tuple[sp.Symbol, sp.Symbol, sp.Symbol] = STATE_OMEGA
#: The upward vertical (space z) in body components (:data:`eulersym.symbols.STATE_GAMMA`).
GAMMA: tuple[sp.Symbol, sp.Symbol, sp.Symbol] = STATE_GAMMA
#: The attitude quaternion, scalar first, ``v_space = R(q) v_body`` (:data:`eulersym.symbols.STATE_Q`).
Q: tuple[sp.Symbol, sp.Symbol, sp.Symbol, sp.Symbol] = STATE_Q
#: Every state name an expression may use, by name.
STATE_SYMBOLS: dict[str, sp.Symbol] = {s.name: s for s in (*OMEGA, *GAMMA, *Q)}

_ZERO3 = sp.ImmutableMatrix([0, 0, 0])


@dataclass(frozen=True)
class Mechanics:
    """A rigid body's mechanics, symbolic: the input of every model derivation.

    Parameters
    ----------
    name : str
        For headers and reports.
    inertia : 3×3 ImmutableMatrix
        The inertia tensor in the model frame, about the pivot for a pivoted body, about the centre of mass for a
        free one (symmetric, positive definite for every admissible parameter value).
    mass : sympy.Expr
        Total mass M.
    centre_of_mass : 3×1 ImmutableMatrix
        From the pivot, model (body) frame; zeros for a free body.
    gravity : sympy.Expr
        g; acts only through a pivot (``0`` for a free body).
    pivoted : bool
        Whether the body turns about a fixed pivot.
    torque : 3×1 ImmutableMatrix
        Every torque other than gravity and ``potential``, in body components (space torques already mapped with
        ``to_body``), in the names of this module and the parameters.
    rotor : 3×1 ImmutableMatrix
        The constant angular momentum h of an internal rotor, body components (L = I ω + h).
    potential : sympy.Expr
        A potential energy other than gravity's, in ``gamma1..3`` / ``q0..3`` and the parameters (0 if none).
    parameters : tuple of (Symbol, float)
        The model's parameters with their default values, in the order the file gives them (the order generated
        functions take them).
    frame : 3×1 ImmutableMatrix
        The angular velocity ``Ω`` of the reference frame (its own components, constant: the frame turns uniformly);
        zeros for an inertial frame. ``ω`` stays the body's angular velocity relative to inertial space (body
        components); ``q``, ``Γ``, ``to_body``/``to_space`` refer to the frame.
    quantities : tuple of (str, str)
        Quantities the user defines (name, expression text), emitted into the kernel
        (:mod:`eulersym.model.quantities`).
    convention : str
        The Euler-angle sequence of ``phi``, ``theta``, ``psi`` in :attr:`quantities`.
    """

    name: str
    inertia: sp.ImmutableMatrix
    mass: sp.Expr
    centre_of_mass: sp.ImmutableMatrix = _ZERO3
    gravity: sp.Expr = sp.Integer(0)
    pivoted: bool = False
    torque: sp.ImmutableMatrix = _ZERO3
    rotor: sp.ImmutableMatrix = _ZERO3
    potential: sp.Expr = sp.Integer(0)
    parameters: tuple = field(default=())
    frame: sp.ImmutableMatrix = _ZERO3
    quantities: tuple = field(default=())
    convention: str = "zxz"

    @property
    def turning(self) -> bool:
        """Whether the reference frame turns (``Ω ≠ 0``)."""
        return any(sp.sympify(e) != 0 for e in self.frame)

    @property
    def parameter_symbols(self) -> tuple:
        """The parameter symbols, in order."""
        return tuple(s for s, _ in self.parameters)

    @property
    def defaults(self) -> dict:
        """``{symbol: default value}``."""
        return {s: v for s, v in self.parameters}

    def free_symbols_allowed(self) -> set:
        """Every symbol an expression of this model may contain: state names, ``t`` and the parameters."""
        return {*STATE_SYMBOLS.values(), t, *self.parameter_symbols}
