"""A rigid body on a horizontal plane — rolling or sliding — by two routes, and the proof that they agree.

State (in the order of the kernels' ``y``): ``omega1..3`` (body components of ω), ``gamma1..3`` (the upward
vertical in body components), ``q0..q3`` (the attitude, scalar first, ``v_space = R(q) v_body``), ``x_cm, y_cm``
(the centre of mass's horizontal position in space) and, sliding, ``vx_cm, vy_cm`` (its horizontal velocity).
The centre of mass's height is not a state: the body touches the plane, so ``z = −r_P(Γ)·Γ``
(:func:`eulersym.model.contact.contact_point`); its rate ``ż = ∂z/∂Γ · Γ̇``. Kinematics:
``Γ̇ = Γ × ω``, ``q̇ = ½ q ⊗ (0, ω)``, ``ṙ_P = (∂r_P/∂Γ) Γ̇``; the space axes ``x̂, ŷ`` in body components are the
first two columns ``X, Y`` of ``A = from_quaternion(q)`` (``r_body = A r_space``).

Forces: gravity ``−M g ẑ`` at the centre of mass; the contact force at the contact point ``P``; the model's torque,
its potential's torque (:func:`eulersym.model.derive.potential_torque`) and the contact's rolling resistance and
spin friction, about the centre of mass. ``L = I ω + h`` (a rotor's constant ``h``).

Route 1 — Newton–Euler with the contact force as a multiplier (:func:`newton_euler`; the kernels use it)
    Rolling: no slip, ``v_P = v_G + ω × r_P = 0``, so ``v_G = r_P × ω`` and (transport theorem, body components)
    ``a_G = ṙ_P × ω + r_P × ω̇ + ω × v_G``. Newton ``M a_G = F − M g Γ`` gives the unknown contact force
    ``F = M a_G + M g Γ``; Euler about the centre of mass ``I ω̇ + ω × L = N + r_P × F`` is then three linear
    equations ``J ω̇ = b`` (``J = I + M (|r_P|² 1 − r_P r_Pᵀ)``, the inertia about the contact point). The normal
    force is ``F·Γ``.
    Sliding: the normal force ``N Γ`` (a multiplier) holds the body on the plane; the friction force ``F_t`` (space,
    horizontal, :class:`eulersym.model.contact.Contact`) acts against the slip ``u = v_G + R(q)(ω × r_P)``.
    Vertical Newton ``M z̈ = N − M g`` with ``z̈`` linear in ``ω̇`` gives ``N``; horizontal Newton
    ``M v̇ = F_t``; Euler ``I ω̇ + ω × L = N_torque + r_P × (N Γ + Aᵀ... F_t)`` (``F_t`` in body components
    ``F_x X + F_y Y``) — again ``J ω̇ = b`` once ``N`` is eliminated.
    ``J ω̇ = b`` is solved as ``ω̇ = adj(J) b / det J`` (the adjugate of a 3×3 matrix, proven for a generic matrix).

Route 2 — Gibbs–Appell with the constraint eliminated (:func:`appell`)
    Quasi-velocities ``u = ω`` (rolling) or ``u = (ω, v_x, v_y)`` (sliding); the velocity of the centre of mass in
    terms of them (the constraint eliminated: ``v_G = r_P × ω`` rolling, ``(v_x, v_y, ż)`` sliding). The Gibbs
    function ``S = ½ M |a_G|² + ½ ω̇ᵀ I ω̇ + ω̇ · (ω × L)`` (the acceleration energy ``½ ∫ |a|² dm`` of the body
    with the terms free of the quasi-accelerations dropped) and the generalised forces from virtual power,
    ``Q_k = Σ F · ∂v/∂u_k`` (gravity at the centre of mass, the torques, the friction at ``P``; the contact's
    constraint force does no virtual work: the partial velocities of ``P`` vanish rolling, and are horizontal
    sliding). Appell's equations ``∂S/∂u̇_k = Q_k``. No contact force is ever formed: the normal force enters only
    through Coulomb friction, ``N = M (g + z̈)``.

The proof (:func:`check`)
    Both routes' equations, written as residuals linear in the accelerations, are shown identical by
    :func:`eulersym.compare.compare` (exact simplification and seeded random 30-digit points); the constraint
    facts they rely on are proven (the partial velocities of the contact point; ``Γ·ṙ_P = 0``); the adjugate solve
    is proven for a generic 3×3 matrix; and the solved right-hand side is checked against Appell's equations
    solved afresh (mpmath, LU) at seeded random points, at 30 digits.

Examples
--------
>>> import sympy as sp
>>> from eulersym.model.contact import Contact, surface
>>> from eulersym.model.mechanics import Mechanics
>>> M, a = sp.Integer(1), sp.Integer(1)
>>> ball = BodyOnPlane(Mechanics(name="ball", inertia=sp.ImmutableMatrix(sp.eye(3) * 2 * M * a**2 / 5), mass=M,
...                              gravity=sp.Rational(981, 100)), Contact(surface("sphere", radius=a)))
>>> newton_euler(ball).names
('omega1', 'omega2', 'omega3', 'gamma1', 'gamma2', 'gamma3', 'q0', 'q1', 'q2', 'q3', 'x_cm', 'y_cm')
>>> check(ball).ok
True
"""

from __future__ import annotations

import functools
import random
from dataclasses import dataclass

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.kinematics import quaternion_rate
from eulersym.model.contact import Contact, contact_point
from eulersym.model.derive import OMEGA_DOT, CheckItem, CheckReport, potential_torque
from eulersym.model.mechanics import GAMMA, OMEGA, Q, Mechanics, t
from eulersym.rotation import from_quaternion

__all__ = [
    "KAPPA",
    "POSITION",
    "VELOCITY",
    "V_DOT",
    "BodyOnPlane",
    "ContactEquations",
    "AppellEquations",
    "state_symbols",
    "newton_euler",
    "appell",
    "friction_law",
    "check",
]

#: The centre of mass's horizontal position in space.
POSITION: tuple = sp.symbols("x_cm y_cm", real=True)
#: The centre of mass's horizontal velocity in space (sliding contacts).
VELOCITY: tuple = sp.symbols("vx_cm vy_cm", real=True)
#: Symbols for the rates of :data:`VELOCITY` in the unsolved equations.
V_DOT: tuple = sp.symbols("vx_cmdot vy_cmdot", real=True)

_NUMERIC_POINTS = 5
_DPS = 30


# ----------------------------------------------------------------------------------------------------------------
# The body on the plane


def _default_values(mech: Mechanics) -> dict:
    return {s: sp.Rational(repr(float(v))) for s, v in mech.parameters}


@dataclass(frozen=True)
class BodyOnPlane:
    """A free rigid body touching the horizontal plane ``z = 0`` through a :class:`~eulersym.model.contact.Contact`.

    Parameters
    ----------
    mechanics : Mechanics
        A free body (no pivot): ``inertia`` about the centre of mass (model frame = body frame), ``mass``, the
        model's ``torque``, ``rotor`` and ``potential`` (in ``gamma``, ``q``, ``t`` and the parameters).
    contact : Contact
        The surface near the contact, placed from the centre of mass, and the contact's law.
    gravity : number or sympy.Expr, optional
        ``g`` (default ``mechanics.gravity``); it must be positive.

    Raises
    ------
    eulersym.errors.InvalidInput
        A pivoted body (a pivot and a contact both hold the body), a body without a mass, no gravity, a dimension
        or coefficient that uses a name that is not a parameter, or that is not positive (non-negative for the
        coefficients) at the parameters' values — each naming the key.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.contact import Contact, surface
    >>> from eulersym.model.mechanics import Mechanics
    >>> top = Mechanics(name="top", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1), pivoted=True,
    ...                 centre_of_mass=sp.ImmutableMatrix([0, 0, 1]), gravity=sp.Integer(10))
    >>> BodyOnPlane(top, Contact(surface("sphere", radius=1)))
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: contact='sphere' is not valid: expected a free body: a contact with the plane and a pivot both hold the body (remove [pivot], or the contact)
    """

    mechanics: Mechanics
    contact: Contact
    gravity: object = None

    def __post_init__(self):
        mech = self.mechanics
        if not isinstance(mech, Mechanics):
            raise InvalidInput("mechanics", mech, "an eulersym.model.mechanics.Mechanics (a free body)")
        if not isinstance(self.contact, Contact):
            raise InvalidInput("contact", self.contact, "an eulersym.model.contact.Contact")
        if mech.pivoted:
            raise InvalidInput("contact", self.contact.surface.kind, "a free body: a contact with the plane and a "
                               "pivot both hold the body (remove [pivot], or the contact)")
        g = mech.gravity if self.gravity is None else sp.sympify(self.gravity)
        if isinstance(g, float):  # pragma: no cover - sympify turns floats into Floats
            g = sp.Rational(repr(g))
        if g.is_Float:
            g = sp.Rational(str(g))
        object.__setattr__(self, "gravity", g)
        allowed = set(mech.parameter_symbols)
        defaults = _default_values(mech)
        if sp.sympify(mech.mass) == 0:
            raise InvalidInput("body.mass", 0, "the body's mass: a body on a plane moves its centre of mass")
        for key, value in (("g", g), ("body.mass", mech.mass)):
            extra = sp.sympify(value).free_symbols - allowed
            if extra:
                raise InvalidInput(key, str(value), "numbers and the model's parameters (unknown: "
                                   f"{', '.join(sorted(map(str, extra)))})")
            number = sp.sympify(value).xreplace(defaults)
            if not (number.is_number and number.is_positive):
                raise InvalidInput(key, str(value), "a positive value at the parameters' values (a body rests on the "
                                   "plane under gravity)" if key == "g" else "a positive mass")
        c = self.contact
        s = c.surface
        checks = [(f"contact.{s.key}" + (f"[{k}]" if len(s.dimensions) > 1 else ""), d, "positive")
                  for k, d in enumerate(s.dimensions)]
        checks += [(f"contact.centre[{k}]", x, "any") for k, x in enumerate(s.centre)]
        checks += [("contact.axes", x, "any") for x in s.axes]
        checks += [("contact.mu", c.mu, "non-negative"), ("contact.rolling_resistance", c.rolling_resistance,
                   "non-negative"), ("contact.spin_friction", c.spin_friction, "non-negative")]
        if c.width is not None:
            checks.append(("contact.width", c.width, "positive"))
        for key, value, rule in checks:
            value = sp.sympify(value)
            extra = value.free_symbols - allowed
            if extra:
                raise InvalidInput(key, str(value), "numbers and the model's parameters (unknown: "
                                   f"{', '.join(sorted(map(str, extra)))})")
            number = value.xreplace(defaults)
            if rule == "positive" and not number.is_positive:
                raise InvalidInput(key, str(value), f"a positive value at the parameters' values (it is {number})")
            if rule == "non-negative" and number.is_negative:
                raise InvalidInput(key, str(value), f"a value >= 0 at the parameters' values (it is {number})")
        for key, exprs in (("body.inertia", list(mech.inertia)), ("rotor.h", list(mech.rotor))):
            if any(sp.sympify(e).has(*OMEGA, *GAMMA, *Q, t) for e in exprs):
                raise InvalidInput(key, [str(e) for e in exprs], "constant components (parameters and numbers)")
        if sp.sympify(mech.potential).has(*OMEGA):
            raise InvalidInput("torque.potential", str(mech.potential), "a potential energy in gamma, q, t and the "
                               "parameters (no omega)")

    @property
    def name(self) -> str:
        """The model's name."""
        return self.mechanics.name

    @property
    def sliding(self) -> bool:
        """Whether the contact slides (the state carries the horizontal velocity)."""
        return self.contact.mode == "sliding"

    @property
    def parameters(self) -> tuple:
        """The model's ``(symbol, default)`` pairs, in order."""
        return self.mechanics.parameters


def state_symbols(body: BodyOnPlane) -> tuple:
    """``(omega1..3, gamma1..3, q0..q3, x_cm, y_cm[, vx_cm, vy_cm])``.

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> len(state_symbols(examples()["tippe-top"]))
    14
    """
    return (*OMEGA, *GAMMA, *Q, *POSITION, *(VELOCITY if body.sliding else ()))


# ----------------------------------------------------------------------------------------------------------------
# Shared kinematics


@dataclass(frozen=True)
class _Kinematics:
    G: sp.Matrix
    w: sp.Matrix
    r: sp.Matrix
    Gdot: sp.Matrix
    rdot: sp.Matrix
    X: sp.Matrix
    Y: sp.Matrix
    height: sp.Expr
    height_rate: sp.Expr
    torque: sp.Matrix
    L: sp.Matrix
    I: sp.Matrix


@functools.lru_cache(maxsize=64)
def _kinematics(body: BodyOnPlane) -> _Kinematics:
    mech, c = body.mechanics, body.contact
    G, w = sp.Matrix(GAMMA), sp.Matrix(OMEGA)
    r = sp.Matrix(contact_point(c.surface))
    Gdot = G.cross(w)  # Γ fixed in space: (dΓ/dt)_body + ω × Γ = 0
    rdot = r.jacobian(list(GAMMA)) * Gdot
    A = from_quaternion(list(Q))  # r_body = A r_space: columns = space axes in body components
    X, Y = A[:, 0], A[:, 1]
    height = -(r.T * G)[0, 0]
    height_rate = sum((sp.diff(height, g) * gd for g, gd in zip(GAMMA, Gdot)), sp.Integer(0))
    spin = (w.T * G)[0, 0]
    torque = (sp.Matrix(mech.torque) + potential_torque(mech.potential)
              - c.rolling_resistance * (w - spin * G) - c.spin_friction * spin * G)
    I = sp.Matrix(mech.inertia)
    L = I * w + sp.Matrix(mech.rotor)
    return _Kinematics(G, w, r, Gdot, rdot, X, Y, height, height_rate, torque, L, I)


#: The friction law's magnitude: ``F_t = −κ u`` (both routes take it as this one symbol, see :func:`friction_law`).
KAPPA = sp.Symbol("kappa_friction", real=True)


def friction_law(body: BodyOnPlane, slip_x, slip_y, normal) -> sp.Expr:
    """``κ`` of the friction force ``F_t = −κ u`` (space, horizontal) for the slip ``u`` and the normal force ``N``:
    ``0`` (none), ``μ`` (viscous), ``μ N / √(|u|² + ε²)`` (Coulomb, regularised).

    Both routes write the friction force as ``−κ u`` with ``κ`` one symbol (:data:`KAPPA`), replaced by this law in
    the solved equations: neither route differentiates ``κ`` (Newton's law and the virtual power only multiply it),
    so their equality for a symbol ``κ`` is their equality for every law.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.contact_examples import examples
    >>> u, N = sp.symbols("u N")
    >>> friction_law(examples()["tippe-top"], u, 0, N)
    N*mu/sqrt(eps**2 + u**2)
    """
    c = body.contact
    if c.friction == "viscous":
        return c.mu
    if c.friction == "coulomb":
        return c.mu * normal / sp.sqrt(slip_x ** 2 + slip_y ** 2 + c.width ** 2)
    return sp.Integer(0)


def _slip(k: _Kinematics) -> tuple:
    """The slip (space, horizontal): ``u = (v_x, v_y) + [R(q) (ω × r_P)]_{x,y}``."""
    spin_part = k.w.cross(k.r)
    return VELOCITY[0] + (k.X.T * spin_part)[0, 0], VELOCITY[1] + (k.Y.T * spin_part)[0, 0]


def _vertical_acceleration(k: _Kinematics, omega_dot) -> sp.Expr:
    """``z̈ = d(ż)/dt`` along ``Γ̇ = Γ × ω`` with ``ω̇`` given: ``∂ż/∂Γ · Γ̇ + ∂ż/∂ω · ω̇``."""
    zd = k.height_rate
    return (sum((sp.diff(zd, g) * gd for g, gd in zip(GAMMA, k.Gdot)), sp.Integer(0))
            + sum((sp.diff(zd, w) * wd for w, wd in zip(OMEGA, omega_dot)), sp.Integer(0)))


# ----------------------------------------------------------------------------------------------------------------
# The linear solve


_J = sp.Matrix(3, 3, sp.symbols("J11 J12 J13 J21 J22 J23 J31 J32 J33", real=True))
_B = sp.Matrix(sp.symbols("b1:4", real=True))


@functools.lru_cache(maxsize=1)
def _generic_solution() -> tuple:
    """``(adj(J) b, det J)`` for a generic 3×3 ``J`` (entries ``J11..J33``) and ``b``: ``J x = b`` is solved by
    ``x = adj(J) b / det J`` (``J adj J = det J · 1``, proven in :func:`check`)."""
    adj = _J.adjugate()
    det = sum((_J[0, j] * adj[j, 0] for j in range(3)), sp.Integer(0))
    return adj * _B, det


def _linear_system(residual: sp.Matrix, unknowns) -> tuple:
    """``(J, b)`` with ``residual = J x − b`` (linear in ``x``)."""
    J = residual.jacobian(list(unknowns))
    b = -residual.xreplace({u: sp.Integer(0) for u in unknowns})
    return J, b


def _solve_named(names, J: sp.Matrix, b: sp.Matrix) -> tuple:
    """``(ω̇, J⁻¹)`` of ``J ω̇ = b`` by the generic adjugate solution, in named intermediates (``J``, ``b`` and the
    determinant named once each)."""
    numerators, det = _generic_solution()
    Jn, bn = names.names("J", J), names.names("b", b)
    values = {**{_J[i, j]: Jn[3 * i + j] for i in range(3) for j in range(3)}, **{_B[i]: bn[i] for i in range(3)}}
    d = names.name("det", det.xreplace(values))
    omega_dot = names.names("wdot", [numerators[i].xreplace(values) / d for i in range(3)])
    inverse = [x.xreplace(values) / d for x in _J.adjugate()]
    return omega_dot, inverse


# ----------------------------------------------------------------------------------------------------------------
# Named intermediates


class _Intermediates:
    """Named intermediate quantities ``s_k = e_k(state, s_1..s_(k−1))``: the equations are built and solved small,
    in these names, then written out in full once (:meth:`resolve`; a subexpression that occurs many times is one
    shared object), differentiated by the chain rule through them (:meth:`derivative`, each derivative named in
    turn), and emitted as they stand (:mod:`eulersym.model.rolling_kernels`: one line each, never a tree of the
    whole). Names are plain symbols ``_<prefix><k>_<label>``, numbered in the order of creation (the same code path
    gives the same names, so the emitted bytes do not depend on the process)."""

    def __init__(self, prefix: str):
        self.prefix = prefix
        self.items: list = []
        self.definition: dict = {}
        self._full: dict = {}
        self._partials: dict = {}

    def copy(self) -> "_Intermediates":
        other = _Intermediates(self.prefix)
        other.items = list(self.items)
        other.definition = dict(self.definition)
        other._full = dict(self._full)
        other._partials = dict(self._partials)
        return other

    def name(self, label: str, expr) -> sp.Expr:
        expr = sp.sympify(expr)
        if expr.is_Atom or (-expr).is_Atom:
            return expr
        symbol = sp.Symbol(f"_{self.prefix}{len(self.items)}_{label}", real=True)
        self.items.append((symbol, expr))
        self.definition[symbol] = expr
        return symbol

    def names(self, label: str, matrix) -> sp.Matrix:
        return sp.Matrix([self.name(f"{label}{k + 1}", e) for k, e in enumerate(matrix)])

    def resolve(self, expr):
        for symbol, e in self.items[len(self._full):]:
            self._full[symbol] = e.xreplace(self._full)
        return expr.xreplace(self._full)

    def _depends(self, expr) -> list:
        return sorted((s for s in expr.free_symbols if s in self.definition), key=lambda s: s.name)

    def derivative(self, expr, variable) -> sp.Expr:
        """``d expr / d variable`` through the intermediates (each intermediate's derivative named once)."""
        out = sp.diff(expr, variable)
        for s in self._depends(expr):
            partial = self._partial(s, variable)
            if partial != 0:
                out += sp.diff(expr, s) * partial
        return out

    def _partial(self, symbol, variable):
        key = (symbol, variable)
        if key not in self._partials:
            value = self.derivative(self.definition[symbol], variable)
            self._partials[key] = self.name(f"d{symbol.name.split('_', 2)[-1]}_{variable}", value)
        return self._partials[key]

    def jacobian(self, exprs, variables, *, resolve: bool = True) -> sp.Matrix:
        """``∂exprs/∂variables`` by the chain rule through the intermediates: in full, or (``resolve=False``) in
        the intermediates."""
        out = sp.Matrix([[self.derivative(e, v) for v in variables] for e in exprs])
        return self.resolve(out) if resolve else out


# ----------------------------------------------------------------------------------------------------------------
# Route 1: Newton–Euler with the contact force as a multiplier


@dataclass(frozen=True)
class ContactEquations:
    """The first-order equations of a body on a plane, by Newton–Euler with the contact force as a multiplier.

    Attributes
    ----------
    state : tuple of sympy.Symbol
        :func:`state_symbols`.
    rhs : sympy.ImmutableMatrix
        ``d(state)/dt``, one row per state symbol.
    accelerations : tuple of sympy.Symbol
        The unknowns of the unsolved equations: ``omega1dot..3`` (and ``vx_cmdot, vy_cmdot`` sliding).
    residual : sympy.ImmutableMatrix
        The unsolved equations (zero along the motion), linear in :attr:`accelerations`; a sliding contact's
        friction force written ``−κ u`` with ``κ`` the symbol :data:`KAPPA` (:func:`friction_law`).
    contact_point : sympy.ImmutableMatrix
        ``r_P`` from the centre of mass, body components.
    height : sympy.Expr
        ``z`` of the centre of mass: ``−r_P·Γ``.
    velocity : sympy.ImmutableMatrix
        The centre of mass's velocity, space components.
    normal_force : sympy.Expr
        ``N`` along the motion (accelerations solved): lift-off where it reaches 0.
    contact_force : sympy.ImmutableMatrix
        The whole contact force, body components, along the motion.
    slip : sympy.ImmutableMatrix
        The slip velocity of the contact point, space ``(u_x, u_y)`` (zero rolling).
    friction : sympy.Expr
        ``κ`` along the motion (0 rolling).

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> eqs = newton_euler(examples()["rolling-sphere"])
    >>> eqs.accelerations
    (omega1dot, omega2dot, omega3dot)
    """

    state: tuple
    rhs: sp.ImmutableMatrix
    accelerations: tuple
    residual: sp.ImmutableMatrix
    contact_point: sp.ImmutableMatrix
    height: sp.Expr
    velocity: sp.ImmutableMatrix
    normal_force: sp.Expr
    contact_force: sp.ImmutableMatrix
    slip: sp.ImmutableMatrix
    friction: sp.Expr
    _intermediates: object = None
    _compact: tuple = ()

    @property
    def names(self) -> tuple:
        """The state names, in order."""
        return tuple(s.name for s in self.state)

    def rate(self, symbol) -> sp.Expr:
        """``d(symbol)/dt`` for a state symbol."""
        return self.rhs[self.state.index(symbol), 0]

    @property
    def solution(self) -> dict:
        """``{acceleration symbol: its solved expression}``."""
        rates = dict(zip(OMEGA_DOT, self.rhs[:3, 0]))
        if len(self.accelerations) == 5:
            rates.update(zip(V_DOT, self.rhs[12:14, 0]))
        return rates

    def linear_system(self) -> tuple:
        """``(J, b)``, written out: the equations that fix ``ω̇`` are ``J ω̇ = b`` (a sliding contact's normal force
        eliminated), ``J`` 3×3.

        Examples
        --------
        >>> from eulersym.model.contact_examples import examples
        >>> J, b = newton_euler(examples()["rolling-sphere"]).linear_system()
        >>> J.shape, b.shape
        ((3, 3), (3, 1))
        """
        compact = dict(self._compact)
        resolve = self._intermediates.resolve
        return resolve(sp.Matrix(3, 3, list(compact["J"]))), resolve(sp.Matrix(list(compact["b"])))

    def free_rates(self) -> sp.Matrix:
        """``d(state)/dt`` written out with ``ω̇`` left as the symbols ``omega1dot..3`` (linear in them).

        Examples
        --------
        >>> from eulersym.model.contact_examples import examples
        >>> newton_euler(examples()["rolling-sphere"]).free_rates()[0]
        omega1dot
        """
        return self._intermediates.resolve(sp.Matrix(list(dict(self._compact)["free_rows"])))

    def friction_system(self) -> tuple:
        """``(J, b, rates)`` written out with the friction law's ``κ`` one symbol (:data:`KAPPA`, not a function
        of ``ω̇``): ``J ω̇ = b`` and ``d(state)/dt`` with ``ω̇`` as symbols — the flow of every friction law at once
        (the form in which integrals are proven: ``κ`` is never differentiated, so an identity of this flow holds
        for whatever ``κ`` the law gives, Coulomb's through the normal force included). Rolling: no ``κ``.

        Examples
        --------
        >>> from eulersym.model.contact_examples import examples
        >>> J, b, rates = newton_euler(examples()["tippe-top"]).friction_system()
        >>> rates[-1].has(KAPPA), J.has(KAPPA)
        (True, False)
        """
        compact = dict(self._compact)
        resolve = self._intermediates.resolve
        J, b = _linear_system(sp.Matrix(list(compact["kappa_residual"])), OMEGA_DOT)
        return resolve(J), resolve(b), resolve(sp.Matrix(list(compact["kappa_rows"])))

    def free_friction(self) -> sp.Expr:
        """The friction law's ``κ`` written out with ``ω̇`` left as symbols (Coulomb's holds ``N(ω̇)``); 0 rolling.

        Examples
        --------
        >>> from eulersym.model.contact_examples import examples
        >>> newton_euler(examples()["tippe-top"]).free_friction().has(OMEGA_DOT[0])
        True
        """
        return self._intermediates.resolve(sp.sympify(dict(self._compact)["law"][0]))

    def program(self, outputs: dict) -> tuple:
        """``(definitions, outputs)``: named intermediates and the outputs in them, for emission.

        ``outputs`` maps a function name to a list of quantity names: ``rhs``, ``jac`` (∂rhs/∂state),
        ``normal_force``, ``contact_force``, ``slip``, ``friction`` (or SymPy expressions in the state). The Jacobian
        follows the solve: the right-hand side is ``f(y, ω̇(y))`` with ``E(y, ω̇) = J ω̇ − b = 0``, so
        ``df/dy = ∂f/∂y − ∂f/∂ω̇ · J⁻¹ ∂E/∂y`` (``J⁻¹ = adj(J)/det J``, each entry named once). ``definitions``
        are ``(symbol, expression)`` pairs in dependency order, only those the outputs need.

        Examples
        --------
        >>> from eulersym.model.contact_examples import examples
        >>> definitions, outputs = newton_euler(examples()["rolling-sphere"]).program({"rhs": ["rhs"]})
        >>> len(outputs["rhs"])
        12
        """
        compact = dict(self._compact)
        names = self._intermediates.copy()
        state = list(self.state)
        result = {}
        for function, quantities in outputs.items():
            exprs = []
            for quantity in quantities:
                if isinstance(quantity, str) and quantity == "jac":
                    exprs.extend(self._jacobian_compact(names, compact, state))
                elif isinstance(quantity, str):
                    exprs.extend(compact[quantity])
                else:
                    exprs.append(sp.sympify(quantity))
            result[function] = exprs
        needed: set = set()
        stack = [s for exprs in result.values() for e in exprs for s in sp.sympify(e).free_symbols
                 if s in names.definition]
        while stack:
            s = stack.pop()
            if s not in needed:
                needed.add(s)
                stack.extend(x for x in names.definition[s].free_symbols if x in names.definition)
        definitions = tuple((s, e) for s, e in names.items if s in needed)
        return definitions, result

    @staticmethod
    def _jacobian_compact(names, compact, state) -> list:
        inverse = sp.Matrix(3, 3, [names.name(f"Jinv{k + 1}", e) for k, e in enumerate(compact["inverse"])])
        solved = dict(zip(OMEGA_DOT, compact["rhs"][:3]))
        # ∂E/∂y at fixed ω̇, then at the solution (the intermediates before the solve hold no ω̇)
        dE = names.jacobian(list(compact["solve_residual"]), state, resolve=False).xreplace(solved)
        d_omega = sp.Matrix(3, len(state), [names.name(f"dwdot{k}", e) for k, e in enumerate(-inverse * dE)])
        rows = list(compact["free_rows"])
        out = []
        for f in rows:
            through = [names.derivative(f, a) for a in OMEGA_DOT]
            for j, y in enumerate(state):
                value = names.derivative(f, y) + sum((through[k] * d_omega[k, j] for k in range(3)), sp.Integer(0))
                out.append(value.xreplace(solved))
        return out

    def jacobian(self) -> sp.Matrix:
        """``∂rhs/∂state`` written out in full (large: for tests; the kernels emit :meth:`program`'s form).

        Examples
        --------
        >>> from eulersym.model.contact_examples import examples
        >>> newton_euler(examples()["rolling-sphere"]).jacobian().shape
        (12, 12)
        """
        definitions, outputs = self.program({"jac": ["jac"]})
        full: dict = {}
        for s, e in definitions:
            full[s] = e.xreplace(full)
        n = len(self.state)
        return sp.Matrix(n, n, [e.xreplace(full) for e in outputs["jac"]])


@functools.lru_cache(maxsize=64)
def newton_euler(body: BodyOnPlane) -> ContactEquations:
    """Route 1: Newton–Euler about the centre of mass with the contact force as a multiplier (module docstring).

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> eqs = newton_euler(examples()["tippe-top"])
    >>> eqs.names[-4:]
    ('x_cm', 'y_cm', 'vx_cm', 'vy_cm')
    """
    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane")
    k = _kinematics(body)
    M, g = body.mechanics.mass, body.gravity
    wd = sp.Matrix(OMEGA_DOT)
    w, G = k.w, k.G
    quaternion = list(quaternion_rate(list(Q), list(OMEGA)))
    names = _Intermediates("ne")
    r = names.names("r", k.r)
    L = names.names("L", k.L)
    torque = names.names("N", k.torque)
    state = state_symbols(body)
    if not body.sliding:
        rdot = names.names("rdot", k.rdot)
        v = names.names("v", r.cross(w))  # v_P = v_G + ω × r_P = 0
        a = rdot.cross(w) + r.cross(wd) + w.cross(v)
        F = M * a + M * g * G  # Newton: M a_G = F − M g Γ
        residual = k.I * wd + w.cross(L) - torque - r.cross(F)
        J, b = _linear_system(residual, OMEGA_DOT)
        omega_dot, inverse = _solve_named(names, J, b)
        solved = dict(zip(OMEGA_DOT, omega_dot))
        velocity = [(k.X.T * v)[0, 0], (k.Y.T * v)[0, 0], k.height_rate]
        rows = [*omega_dot, *k.Gdot, *quaternion, velocity[0], velocity[1]]
        free_rows = [*OMEGA_DOT, *rows[3:]]
        solve_residual = residual
        force = F.xreplace(solved)
        normal = (G.T * force)[0, 0]
        slip = [sp.Integer(0), sp.Integer(0)]
        kappa = law = sp.Integer(0)
        full_residual = residual
        kappa_rows = free_rows
    else:
        # The normal force from the vertical Newton equation M z̈ = N − M g (z̈ linear in ω̇), friction against the
        # slip; κ = friction_law(...) may hold N, hence ω̇.
        zd = k.height_rate
        z_dd0 = names.name("zdd0", sum((sp.diff(zd, x) * xd for x, xd in zip(GAMMA, k.Gdot)), sp.Integer(0)))
        z_dw = names.names("zdw", [sp.diff(zd, x) for x in OMEGA])
        N = M * (g + z_dd0 + (z_dw.T * wd)[0, 0])
        X, Y = names.names("X", k.X), names.names("Y", k.Y)
        spin_part = w.cross(r)
        ux = names.name("ux", VELOCITY[0] + (X.T * spin_part)[0, 0])
        uy = names.name("uy", VELOCITY[1] + (Y.T * spin_part)[0, 0])
        law = friction_law(body, ux, uy, N)
        slip_force = X * ux + Y * uy  # the slip in body components (horizontal)
        vd = sp.Matrix(V_DOT)

        def equations(kappa):
            F_body = -kappa * slip_force
            return sp.Matrix([*(k.I * wd + w.cross(L) - torque - r.cross(N * G + F_body)),
                              M * vd[0] + kappa * ux, M * vd[1] + kappa * uy])

        residual = equations(law)
        solve_residual = residual[:3, 0]
        J, b = _linear_system(solve_residual, OMEGA_DOT)
        omega_dot, inverse = _solve_named(names, J, b)
        solved = dict(zip(OMEGA_DOT, omega_dot))
        normal = names.name("normal", N.xreplace(solved))
        kappa = names.name("kappa", law.xreplace(solved))
        v_dot = [-kappa * ux / M, -kappa * uy / M]
        rows = [*omega_dot, *k.Gdot, *quaternion, *VELOCITY, *v_dot]
        free_rows = [*OMEGA_DOT, *rows[3:12], -law * ux / M, -law * uy / M]
        force = normal * G - kappa * slip_force
        velocity = [*VELOCITY, k.height_rate]
        slip = [ux, uy]
        full_residual = equations(KAPPA)
        kappa_rows = [*free_rows[:12], -KAPPA * ux / M, -KAPPA * uy / M]
    compact = (("rhs", tuple(rows)), ("normal_force", (normal,)), ("contact_force", tuple(force)),
               ("slip", tuple(slip)), ("friction", (kappa,)), ("free_rows", tuple(free_rows)),
               ("solve_residual", tuple(solve_residual)), ("inverse", tuple(inverse)),
               ("velocity", tuple(velocity)), ("J", tuple(J)), ("b", tuple(b)), ("law", (law,)),
               ("kappa_residual", tuple(full_residual[:3, 0])), ("kappa_rows", tuple(kappa_rows)))
    resolve = names.resolve
    return ContactEquations(
        state, sp.ImmutableMatrix(resolve(sp.Matrix(rows))), tuple(OMEGA_DOT) + (tuple(V_DOT) if body.sliding else ()),
        sp.ImmutableMatrix(resolve(full_residual)), sp.ImmutableMatrix(k.r), k.height,
        sp.ImmutableMatrix(resolve(sp.Matrix(velocity))), resolve(sp.sympify(normal)), sp.ImmutableMatrix(resolve(force)),
        sp.ImmutableMatrix(resolve(sp.Matrix(slip))), resolve(sp.sympify(kappa)), names, compact)


# ----------------------------------------------------------------------------------------------------------------
# Route 2: Gibbs–Appell


@dataclass(frozen=True)
class AppellEquations:
    """Route 2: Appell's equations ``∂S/∂u̇_k − Q_k = 0`` of a body on a plane.

    Attributes
    ----------
    speeds : tuple of sympy.Symbol
        The quasi-velocities ``u``: ``omega1..3`` (and ``vx_cm, vy_cm`` sliding).
    accelerations : tuple of sympy.Symbol
        Their rates, the unknowns.
    gibbs : sympy.Expr
        ``S = ½ M |a_G|² + ½ ω̇ᵀ I ω̇ + ω̇·(ω × L)``.
    forces : sympy.ImmutableMatrix
        The generalised forces ``Q_k``.
    residual : sympy.ImmutableMatrix
        ``∂S/∂u̇_k − Q_k``.
    contact_partials : sympy.ImmutableMatrix
        ``∂v_P/∂u_k`` (columns; space components): zero rolling, horizontal sliding.

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> appell(examples()["rolling-sphere"]).speeds
    (omega1, omega2, omega3)
    """

    speeds: tuple
    accelerations: tuple
    gibbs: sp.Expr
    forces: sp.ImmutableMatrix
    residual: sp.ImmutableMatrix
    contact_partials: sp.ImmutableMatrix


@functools.lru_cache(maxsize=64)
def appell(body: BodyOnPlane) -> AppellEquations:
    """Route 2: the Gibbs–Appell equations with the constraint eliminated (module docstring).

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> appell(examples()["tippe-top"]).accelerations
    (omega1dot, omega2dot, omega3dot, vx_cmdot, vy_cmdot)
    """
    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane")
    k = _kinematics(body)
    M, g = body.mechanics.mass, body.gravity
    w, G, r = k.w, k.G, k.r
    wd = sp.Matrix(OMEGA_DOT)
    S_rotation = (wd.T * k.I * wd)[0, 0] / 2 + (wd.T * w.cross(k.L))[0, 0]
    if not body.sliding:
        speeds, accelerations = tuple(OMEGA), tuple(OMEGA_DOT)
        v_G = r.cross(w)  # the constraint eliminated: v_P = 0
        a_G = k.rdot.cross(w) + r.cross(wd) + w.cross(v_G)  # body components of the acceleration
        S = M * (a_G.T * a_G)[0, 0] / 2 + S_rotation
        v_P = v_G + w.cross(r)
        partial_G = v_G.jacobian(list(speeds))
        partial_P = v_P.jacobian(list(speeds))
        gravity = -M * g * G
        Qs = [(gravity.T * partial_G[:, j])[0, 0] + k.torque[j] for j in range(3)]
        partials = sp.ImmutableMatrix(partial_P)
    else:
        speeds, accelerations = (*OMEGA, *VELOCITY), (*OMEGA_DOT, *V_DOT)
        z_ddot = _vertical_acceleration(k, OMEGA_DOT)
        S = M * (V_DOT[0] ** 2 + V_DOT[1] ** 2 + z_ddot ** 2) / 2 + S_rotation
        v_G = sp.Matrix([*VELOCITY, k.height_rate])  # space components; ż from the contact
        ux, uy = _slip(k)
        v_P = sp.Matrix([ux, uy, k.height_rate + (G.T * w.cross(r))[0, 0]])  # space: R(q)(ω × r)·ẑ = Γ·(ω × r)
        Fx, Fy = -KAPPA * ux, -KAPPA * uy  # κ = friction_law(...): Coulomb's takes N = M (g + z̈)
        friction = sp.Matrix([Fx, Fy, 0])
        gravity = sp.Matrix([0, 0, -M * g])
        partial_G = v_G.jacobian(list(speeds))
        partial_P = v_P.jacobian(list(speeds))
        torque = [*k.torque, 0, 0]
        Qs = [(gravity.T * partial_G[:, j])[0, 0] + (friction.T * partial_P[:, j])[0, 0] + torque[j]
              for j in range(5)]
        partials = sp.ImmutableMatrix(partial_P)
    residual = sp.Matrix([sp.diff(S, a) for a in accelerations]) - sp.Matrix(Qs)
    return AppellEquations(speeds, accelerations, S, sp.ImmutableMatrix(Qs), sp.ImmutableMatrix(residual), partials)


# ----------------------------------------------------------------------------------------------------------------
# The proof


def _point(symbols, rng: random.Random, defaults: dict) -> dict:
    """A random rational state on ``|q| = 1`` with ``Γ = A(q) ẑ`` (the physical manifold), random rates, and the
    parameters near their values."""
    from eulersym.model.integrals import _unit_point

    point = {}
    q = _unit_point(rng, 4)
    point.update(zip(Q, q))
    A = from_quaternion(q)
    point.update(zip(GAMMA, A[:, 2]))
    for s in symbols:
        if s in point:
            continue
        if s in defaults:
            point[s] = defaults[s] * sp.Rational(rng.randint(80, 120), 100)
        else:
            point[s] = sp.Rational(rng.randint(-30, 30), 10)
    return point


def _numeric(exprs, dps: int):
    """A function ``point → [values]`` that evaluates ``exprs`` at ``dps`` digits through one CSE pass (so that a
    large expression with shared parts costs its distinct parts, not its tree)."""
    replacements, reduced = sp.cse(list(exprs), order="canonical")

    def evaluate(point: dict) -> list:
        values = {s: sp.Float(v.evalf(dps + 10), dps + 10) if not isinstance(v, sp.Float) else v
                  for s, v in point.items()}
        for symbol, e in replacements:
            values[symbol] = e.xreplace(values).evalf(dps + 10)
        return [e.xreplace(values).evalf(dps + 10) for e in reduced]

    return evaluate


def _solved_agree(body: BodyOnPlane, seed: int = 0) -> tuple[bool, str]:
    """Route 1's solved right-hand side against Appell's equations solved afresh (mpmath LU) at random points."""
    import mpmath

    eqs = newton_euler(body)
    route2 = appell(body)
    residual = sp.Matrix(route2.residual)
    if body.sliding:
        k = _kinematics(body)
        ux, uy = _slip(k)
        N = body.mechanics.mass * (body.gravity + _vertical_acceleration(k, OMEGA_DOT))
        residual = residual.xreplace({KAPPA: friction_law(body, ux, uy, N)})
    J2, b2 = _linear_system(residual, route2.accelerations)
    rates = [eqs.rhs[k, 0] for k in range(3)] + ([eqs.rhs[12, 0], eqs.rhs[13, 0]] if body.sliding else [])
    ours = _numeric(rates, _DPS)
    theirs = _numeric([*J2, *b2], _DPS)
    symbols = sorted(set().union(*(e.free_symbols for e in (*J2, *b2, *rates))), key=sp.default_sort_key)
    rng = random.Random(seed)
    defaults = _default_values(body.mechanics)
    worst = 0.0
    n = len(rates)
    with mpmath.workdps(_DPS + 10):
        for _ in range(_NUMERIC_POINTS):
            point = _point(symbols, rng, defaults)
            values = [mpmath.mpf(str(v)) for v in theirs(point)]
            A = mpmath.matrix([[values[i * n + j] for j in range(n)] for i in range(n)])
            x = mpmath.lu_solve(A, mpmath.matrix(values[n * n:]))
            for i, e in enumerate(ours(point)):
                value = mpmath.mpf(str(e))
                worst = max(worst, float(abs(value - x[i]) / max(1, abs(x[i]), abs(value))))
    ok = worst <= 10.0 ** (5 - _DPS)
    return ok, (f"numeric ({_NUMERIC_POINTS} points at {_DPS} digits on |q| = 1, Γ = A(q) ẑ; max relative "
                f"difference {worst:.1e})")


def check(body: BodyOnPlane, *, seed: int = 0) -> CheckReport:
    """Prove the two routes equal, and the facts they rely on (see the module docstring).

    Returns
    -------
    eulersym.model.derive.CheckReport

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> print(check(examples()["chaplygin-ball"]))  # doctest: +ELLIPSIS
    model chaplygin-ball: all identities hold
      ok    Γ·dr_P/dt = 0 (the contact point slides along the tangent plane): exact (...)
    ...
    """
    from eulersym.compare import compare

    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane")
    k = _kinematics(body)
    route1 = newton_euler(body)
    route2 = appell(body)
    items = []
    r = compare((k.G.T * k.rdot)[0, 0], sp.Integer(0), seed=seed)
    items.append(CheckItem("Γ·dr_P/dt = 0 (the contact point slides along the tangent plane)", "", r.equal,
                           r.method))
    if body.sliding:
        r = compare(list(route2.contact_partials[2, :]), [0] * route2.contact_partials.cols, seed=seed)
        items.append(CheckItem("∂v_P/∂u is horizontal (the normal force does no virtual work)", "", r.equal,
                               r.method))
    else:
        r = compare(route2.contact_partials, sp.zeros(3, 3), seed=seed)
        items.append(CheckItem("∂v_P/∂ω = 0 (no slip: the contact force does no virtual work)", "", r.equal,
                               r.method))
    r = compare(list(route1.residual), list(route2.residual), seed=seed)
    items.append(CheckItem("Newton–Euler (contact force eliminated) = Gibbs–Appell", "", r.equal, r.method))
    numerators, det = _generic_solution()
    r = compare(_J * numerators, det * _B, seed=seed)
    items.append(CheckItem("J·adj(J)·b = det(J)·b (the solve, for a generic 3×3 J)", "", r.equal, r.method))
    ok, how = _solved_agree(body, seed)
    items.append(CheckItem("solved right-hand side = Appell's equations solved afresh (LU)", "", ok, how))
    return CheckReport(body.name, tuple(items))
