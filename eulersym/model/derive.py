"""A model's equations of motion by two routes — Newton–Euler in the body frame and Lagrange in Euler angles — and
the proof that they agree.

Newton–Euler (:func:`equations`, the route the kernels use)
    ``L = I ω + h`` (``h`` the constant angular momentum of an internal rotor, body components) and Newton's law
    in the body frame, ``(dL/dt)_body + ω × L = N``; ``I`` and ``h`` are constant in the body, so
    ``I ω̇ = N − ω × (I ω + h)``. ``N`` is the model's torque plus the torque of its potential energy
    ``V = M g c·Γ`` (gravity through the pivot: ``c`` the centre of mass from the pivot, ``Γ`` the upward vertical in
    body components, so ``c·Γ`` is the height of the centre of mass) ``+ potential``. The torque of a potential is
    derived by virtual work: a virtual turn ``δθ`` (body components) moves the state ``x = (Γ, q)`` by
    ``δx = (∂ẋ/∂ω) δθ``, and ``N·δθ = −δV`` gives ``N = −(∂ẋ/∂ω)ᵀ ∂V/∂x``; for ``Γ̇ = Γ × ω`` this is
    ``N = Γ × ∂V/∂Γ``, for gravity ``M g Γ × c``. Kinematics: ``Γ`` is fixed in space, so
    ``(dΓ/dt)_body + ω × Γ = 0``, i.e. ``Γ̇ = Γ × ω``; the quaternion ``q̇ = ½ q ⊗ (0, ω)``
    (:func:`eulersym.kinematics.quaternion_rate`).

Lagrange (:func:`lagrangian`, for models whose torques all come from potentials)
    ``L = ½ ωᵀ I ω + h·ω − V`` with ``ω`` from :func:`eulersym.kinematics.omega_body` in any of the 12
    conventions, ``Γ = A ẑ`` the third column of the passive attitude matrix ``A`` (``r_body = A r_space``,
    :func:`eulersym.rotation.euler_matrix`), and the quaternion of the angles composed from the three elementary
    half-angle quaternions, ``q = q_a(φ) ⊗ q_b(θ) ⊗ q_c(ψ)`` for the sequence "abc".

The proof (:func:`check`)
    With ``ω = J(angles) · rates`` (``J`` = :func:`eulersym.kinematics.euler_rate_matrix`), Lagrange's equations
    ``d/dt ∂L/∂q̇ − ∂L/∂q`` must equal ``Jᵀ (I ω̇ + ω × L − N)`` — the Newton–Euler residual mapped through
    ``ω(φ, θ, ψ, rates)`` — identically. Since ``J`` is invertible away from the coordinate singularity, this
    proves the two routes give the same motion. The kinematic relations (``Γ̇ = Γ × ω``, ``q̇ = ½ q ⊗ (0, ω)``,
    ``A = from_quaternion(q)``) are proven along the same map. For the chapter's heavy symmetric top the model's
    equations are also proven equal to :mod:`eulersym.top`'s Lagrangian and equations and to
    :func:`eulersym.dynamics.euler_poisson_equations`. Every comparison is :func:`eulersym.compare.compare`
    (exact simplification to zero and seeded random high-precision points).

Examples
--------
>>> import sympy as sp
>>> from eulersym.model.mechanics import Mechanics
>>> I1, I3, M, g, l = sp.symbols("I1 I3 M g l", positive=True)
>>> top = Mechanics(name="top", inertia=sp.ImmutableMatrix(sp.diag(I1, I1, I3)), mass=M,
...                 centre_of_mass=sp.ImmutableMatrix([0, 0, l]), gravity=g, pivoted=True)
>>> eqs = equations(top)
>>> [s.name for s in eqs.state]
['omega1', 'omega2', 'omega3', 'gamma1', 'gamma2', 'gamma3', 'q0', 'q1', 'q2', 'q3']
>>> eqs.rhs[2]
0
>>> check(top, conventions=["zxz"]).ok
True
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.kinematics import euler_rate_matrix, omega_body, quaternion_rate
from eulersym.model.mechanics import GAMMA, OMEGA, Q, Mechanics, t
from eulersym.rotation import CONVENTIONS, _convention, euler_matrix, from_quaternion
from eulersym.symbols import euler_angles

__all__ = [
    "Equations",
    "CheckItem",
    "CheckReport",
    "OMEGA_DOT",
    "equations",
    "state_symbols",
    "uses_gamma",
    "total_potential",
    "potential_torque",
    "lagrangian",
    "lagrange_equations",
    "angle_map",
    "is_chapter_top",
    "check",
]

#: Symbols for the rates ``dω/dt`` in the Newton–Euler equations (``Equations.euler``).
OMEGA_DOT: tuple = sp.symbols("omega1dot omega2dot omega3dot", real=True)

_ZERO3 = sp.ImmutableMatrix([0, 0, 0])
_EZ = sp.Matrix([0, 0, 1])


@dataclass(frozen=True)
class Equations:
    """A model's first-order equations of motion, derived by Newton–Euler in the body frame.

    Attributes
    ----------
    state : tuple of sympy.Symbol
        ``omega1..3``, ``gamma1..3`` (when the state carries the vertical, :func:`uses_gamma`), ``q0..q3``.
    rhs : sympy.ImmutableMatrix
        ``d(state)/dt``, one row per state symbol, in the model's names.
    euler : tuple of 3 sympy.Eq
        ``Eq((I ω̇ + ω × (I ω + h))_k, N_k)`` with ``ω̇`` as :data:`OMEGA_DOT`.
    torque : sympy.ImmutableMatrix
        ``N``, body components: the model's torque plus the torque of the potential.
    potential : sympy.Expr
        ``V``: gravity's ``M g c·Γ`` (pivoted bodies) plus the model's potential.
    angular_momentum : sympy.ImmutableMatrix
        ``L = I ω + h``.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> eqs = equations(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.diag(1, 2, 3)), mass=sp.Integer(1)))
    >>> eqs.names[:3], eqs.omega_dot.T
    (('omega1', 'omega2', 'omega3'), Matrix([[-omega2*omega3, omega1*omega3, -omega1*omega2/3]]))
    """

    state: tuple
    rhs: sp.ImmutableMatrix
    euler: tuple
    torque: sp.ImmutableMatrix
    potential: sp.Expr
    angular_momentum: sp.ImmutableMatrix

    @property
    def names(self) -> tuple:
        """The state names, in order."""
        return tuple(s.name for s in self.state)

    @property
    def omega_dot(self) -> sp.ImmutableMatrix:
        """``dω/dt`` (the first three rows of :attr:`rhs`)."""
        return sp.ImmutableMatrix(self.rhs[:3, 0])

    def rate(self, symbol) -> sp.Expr:
        """``d(symbol)/dt`` for a state symbol.

        Examples
        --------
        >>> import sympy as sp
        >>> from eulersym.model.mechanics import Mechanics, Q
        >>> eqs = equations(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1)))
        >>> eqs.rate(Q[0])
        -omega1*q1/2 - omega2*q2/2 - omega3*q3/2
        """
        return self.rhs[self.state.index(symbol), 0]


# ----------------------------------------------------------------------------------------------------------------
# Structure


def _expressions(mech: Mechanics) -> list:
    return [*mech.torque, mech.potential, *mech.rotor, *mech.inertia, mech.mass, *mech.centre_of_mass, mech.gravity]


def uses_gamma(mech: Mechanics) -> bool:
    """Whether the state carries the vertical ``gamma1..3``: gravity through a pivot, or an expression uses it.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> uses_gamma(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1)))
    False
    """
    if mech.pivoted and mech.gravity != 0:
        return True
    return any(sp.sympify(e).has(*GAMMA) for e in (*mech.torque, mech.potential))


def state_symbols(mech: Mechanics) -> tuple:
    """``(omega1..3, [gamma1..3,] q0..q3)``: the contract's STATE rule.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> len(state_symbols(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1))))
    7
    """
    return (*OMEGA, *(GAMMA if uses_gamma(mech) else ()), *Q)


def total_potential(mech: Mechanics) -> sp.Expr:
    """``V = M g c·Γ + potential`` (gravity only for a pivoted body; ``c·Γ`` is the centre of mass's height).

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> M, g, a = sp.symbols("M g a", positive=True)
    >>> total_potential(Mechanics(name="k", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=M, gravity=g,
    ...                           centre_of_mass=sp.ImmutableMatrix([a, 0, 0]), pivoted=True))
    M*a*g*gamma1
    """
    V = sp.sympify(mech.potential)
    if V.has(*OMEGA):
        raise InvalidInput("potential", str(V), "a potential energy in gamma1..3, q0..q3, t and the parameters "
                           "(no omega: a velocity-dependent effect is a torque)")
    if mech.pivoted and mech.gravity != 0:
        c = sp.Matrix(mech.centre_of_mass)
        V = V + mech.mass * mech.gravity * (c.T * sp.Matrix(GAMMA))[0, 0]
    return V


@functools.lru_cache(maxsize=64)
def _quaternion_kinematics() -> sp.ImmutableMatrix:
    return sp.ImmutableMatrix(quaternion_rate(list(Q), list(OMEGA)))


def _gamma_kinematics() -> sp.Matrix:
    # Γ (the upward vertical) is fixed in space: (dΓ/dt)_body + ω × Γ = 0.
    return -sp.Matrix(OMEGA).cross(sp.Matrix(GAMMA))


def _frame_gamma_terms(mech: Mechanics) -> sp.Matrix:
    """``−Γ × to_body(Ω)``: Γ (the frame's up) is fixed in the frame, which turns at Ω relative to inertial space, so
    ``(dΓ/dt)_body + (ω − R(q)ᵀ Ω) × Γ = 0``; zero for an inertial frame (and for Ω along the frame's up)."""
    if not mech.turning:
        return sp.zeros(3, 1)
    from eulersym.model.expressions import to_body

    return (-sp.Matrix(GAMMA).cross(sp.Matrix(to_body(mech.frame)))).applyfunc(sp.expand)


def _frame_quaternion_terms(mech: Mechanics) -> sp.Matrix:
    """``−½ (0, Ω) ⊗ q``: the attitude relative to a frame turning at Ω (frame components) changes at
    ``q̇ = ½ q ⊗ (0, ω) − ½ (0, Ω) ⊗ q`` (for a unit q this is ``½ q ⊗ (0, ω − R(q)ᵀ Ω)``)."""
    if not mech.turning:
        return sp.zeros(4, 1)
    from eulersym.quaternion import hamilton

    product = hamilton((sp.Integer(0), *mech.frame), tuple(Q))
    return sp.Matrix([-sp.expand(c) / 2 for c in product])


def potential_torque(V) -> sp.Matrix:
    """The torque of a potential energy ``V(Γ, q, t)``, by virtual work: ``N = −(∂ẋ/∂ω)ᵀ ∂V/∂x``, ``x = (Γ, q)``.

    For ``Γ̇ = Γ × ω`` this is ``N = Γ × ∂V/∂Γ``; for ``q̇ = ½ q ⊗ (0, ω)``, ``N_k = −½ ∂V/∂q · (q ⊗ e_k)``.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import GAMMA
    >>> k = sp.Symbol("k")
    >>> potential_torque(k * GAMMA[2]).T   # Γ × (k ẑ_body)
    Matrix([[gamma2*k, -gamma1*k, 0]])
    """
    V = sp.sympify(V)
    N = sp.zeros(3, 1)
    blocks = ((GAMMA, _gamma_kinematics()), (Q, sp.Matrix(_quaternion_kinematics())))
    for symbols, rate in blocks:
        if not V.has(*symbols):
            continue
        grad = sp.Matrix([sp.diff(V, s) for s in symbols])
        N -= rate.jacobian(list(OMEGA)).T * grad
    return N.applyfunc(sp.expand)


def _inverse(I: sp.Matrix) -> sp.Matrix:
    if I.is_diagonal():
        return sp.diag(*[1 / I[k, k] for k in range(3)])
    det = sp.factor(sp.expand(I.det()))
    if det == 0:
        raise InvalidInput("inertia", I.tolist(), "a non-singular (positive definite) inertia tensor")
    return I.adjugate().applyfunc(sp.expand) / det


@functools.lru_cache(maxsize=64)
def equations(mech: Mechanics) -> Equations:
    """The first-order equations of motion of a model, by Newton–Euler in the body frame (see the module docstring).

    Parameters
    ----------
    mech : Mechanics

    Returns
    -------
    Equations

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics, OMEGA
    >>> c = sp.Symbol("c", positive=True)
    >>> damped = Mechanics(name="damped", inertia=sp.ImmutableMatrix(sp.diag(1, 2, 3)), mass=sp.Integer(1),
    ...                    torque=sp.ImmutableMatrix([-c * w for w in OMEGA]), parameters=((c, 0.1),))
    >>> equations(damped).euler[0]
    Eq(omega1dot + omega2*omega3, -c*omega1)
    """
    if not isinstance(mech, Mechanics):
        raise InvalidInput("mech", mech, "an eulersym.model.mechanics.Mechanics")
    I = sp.Matrix(mech.inertia)
    h = sp.Matrix(mech.rotor)
    constants = (("rotor", list(h)), ("inertia", list(I)), ("mass", [mech.mass]),
                 ("centre_of_mass", list(mech.centre_of_mass)), ("gravity", [mech.gravity]))
    for name, value in constants:
        if any(sp.sympify(e).has(*OMEGA, *GAMMA, *Q, t) for e in value):
            raise InvalidInput(name, [str(e) for e in value], "constant components (parameters and numbers only)")
    w = sp.Matrix(OMEGA)
    L = I * w + h
    V = total_potential(mech)
    N = sp.Matrix(mech.torque) + potential_torque(V)
    lhs = I * sp.Matrix(OMEGA_DOT) + w.cross(L)
    euler = tuple(sp.Eq(sp.expand(lhs[k]), N[k], evaluate=False) for k in range(3))
    # I ω̇ = N − ω × L, solved with I⁻¹ (diagonal: entry by entry). The torque keeps the structure it was written
    # with (a gravity-gradient torque expanded is twenty times larger); ω × L is expanded.
    residual = N - w.cross(L).applyfunc(sp.expand)
    inverse = _inverse(I)
    omega_dot = [sp.Add(*[inverse[k, j] * residual[j] for j in range(3) if inverse[k, j] != 0])
                 for k in range(3)]
    rows = list(omega_dot)
    if uses_gamma(mech):
        rows += list(_gamma_kinematics() + _frame_gamma_terms(mech))
    rows += list(sp.Matrix(_quaternion_kinematics()) + _frame_quaternion_terms(mech))
    state = state_symbols(mech)
    return Equations(state, sp.ImmutableMatrix(rows), euler, sp.ImmutableMatrix(N), V, sp.ImmutableMatrix(L))


# ----------------------------------------------------------------------------------------------------------------
# Lagrange


def _require_conservative(mech: Mechanics) -> None:
    if any(sp.sympify(e) != 0 for e in mech.torque):
        raise InvalidInput(
            "torque", [str(e) for e in mech.torque],
            "no torque other than that of a potential for the Lagrangian route (a torque that is not the gradient "
            "of a potential, such as damping or a prescribed N(t), has no Lagrangian L = T − V; write it as "
            "[torque] potential = \"...\" if it is conservative)")


_UNIT = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}


@functools.lru_cache(maxsize=16)
def _angle_map(convention: str) -> tuple:
    from eulersym.quaternion import hamilton  # NumPy-backed module: imported only where the Lagrangian needs it

    phi, theta, psi = euler_angles
    w = omega_body(convention)
    A = euler_matrix(phi, theta, psi, convention=convention)
    gamma = A * _EZ  # body components of space z: r_body = A r_space
    # The body's orientation R = Aᵀ = R_a(φ) R_b(θ) R_c(ψ) (active), composed from half-angle quaternions.
    q = (sp.Integer(1), sp.Integer(0), sp.Integer(0), sp.Integer(0))
    for axis, angle in zip(convention, (phi, theta, psi)):
        e = _UNIT[axis]
        factor = (sp.cos(angle / 2), *(sp.sin(angle / 2) * k for k in e))
        q = tuple(sp.expand(c) for c in hamilton(q, factor))
    mapping = {**dict(zip(OMEGA, w)), **dict(zip(GAMMA, gamma)), **dict(zip(Q, q))}
    return mapping, w, gamma, sp.Matrix(q), A


def angle_map(convention: str = "zxz") -> dict:
    """``{omega_k: ω_k(angles, rates), gamma_k: (A ẑ)_k, q_k: q_k(angles)}`` for one of the 12 conventions.

    Angles and rates are :data:`eulersym.symbols.euler_angles` (functions of ``t``) and their derivatives.

    Examples
    --------
    >>> from eulersym.model.mechanics import GAMMA
    >>> angle_map("zxz")[GAMMA[2]]
    cos(theta(t))
    """
    return dict(_angle_map(_convention(convention))[0])


def lagrangian(mech: Mechanics, convention: str = "zxz") -> sp.Expr:
    """``L = ½ ωᵀ I ω + h·ω − V`` in Euler angles of ``convention`` (functions of ``t`` and their rates).

    Parameters
    ----------
    mech : Mechanics
        Every torque must come from a potential (gravity through the pivot, ``potential``).
    convention : str
        One of :data:`eulersym.rotation.CONVENTIONS`.

    Raises
    ------
    eulersym.errors.InvalidInput
        A model with a torque that is not a potential's (no Lagrangian L = T − V), or a bad convention.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> from eulersym.compare import compare
    >>> from eulersym import top
    >>> from eulersym.symbols import I1, I3, M, g, l
    >>> m = Mechanics(name="top", inertia=sp.ImmutableMatrix(sp.diag(I1, I1, I3)), mass=M,
    ...               centre_of_mass=sp.ImmutableMatrix([0, 0, l]), gravity=g, pivoted=True)
    >>> compare(lagrangian(m), top.lagrangian()).exact
    True
    """
    if not isinstance(mech, Mechanics):
        raise InvalidInput("mech", mech, "an eulersym.model.mechanics.Mechanics")
    convention = _convention(convention)
    _require_conservative(mech)
    mapping = _frame_map(mech, convention)[0]
    w = sp.Matrix(OMEGA)
    I = sp.Matrix(mech.inertia)
    T = (w.T * I * w)[0, 0] / 2 + (sp.Matrix(mech.rotor).T * w)[0, 0]
    return sp.expand(T.xreplace(mapping)) - total_potential(mech).xreplace(mapping)


def lagrange_equations(mech: Mechanics, convention: str = "zxz") -> list:
    """Lagrange's equations ``d/dt ∂L/∂q̇ − ∂L/∂q = 0`` for ``q = φ, θ, ψ`` of :func:`lagrangian`.

    Returns
    -------
    list of 3 sympy.Eq (``Eq(expression, 0)``).

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> from eulersym.symbols import psi, t
    >>> m = Mechanics(name="sym", inertia=sp.ImmutableMatrix(sp.diag(1, 1, 2)), mass=sp.Integer(1))
    >>> lagrange_equations(m)[2].lhs.has(psi.diff(t, 2))
    True
    """
    return list(_lagrange_equations(mech, _convention(convention)))


@functools.lru_cache(maxsize=64)
def _lagrange_equations(mech: Mechanics, convention: str) -> tuple:
    L = lagrangian(mech, convention)
    # Differentiate with the angles and rates frozen into plain symbols (cheaper than functions of t), the time
    # derivative by the chain rule: d/dt f(q, q̇, t) = Σ ∂f/∂q_i q̇_i + ∂f/∂q̇_i q̈_i + ∂f/∂t.
    q = [sp.Dummy(a.func.__name__, real=True) for a in euler_angles]
    qd = [sp.Dummy(a.func.__name__ + "dot", real=True) for a in euler_angles]
    qdd = [sp.Dummy(a.func.__name__ + "ddot", real=True) for a in euler_angles]
    freeze = {**{a.diff(t): s for a, s in zip(euler_angles, qd)}, **dict(zip(euler_angles, q))}
    thaw = {**dict(zip(q, euler_angles)), **{s: a.diff(t) for a, s in zip(euler_angles, qd)},
            **{s: a.diff(t, 2) for a, s in zip(euler_angles, qdd)}}
    frozen = L.xreplace(freeze)
    out = []
    for j in range(3):
        p = sp.diff(frozen, qd[j])
        rate = sp.diff(p, t) + sum(sp.diff(p, q[i]) * qd[i] + sp.diff(p, qd[i]) * qdd[i] for i in range(3))
        expr = sp.expand(rate - sp.diff(frozen, q[j]))
        out.append(sp.Eq(expr.xreplace(thaw), 0, evaluate=False))
    return tuple(out)


def _frame_map(mech: Mechanics, convention: str) -> tuple:
    """:func:`_angle_map` for angles relative to the model's frame: ``ω = J(angles)·rates + A(angles) Ω`` (the
    frame's own turn, Ω in frame components, mapped to the body by ``r_body = A r_frame``); Γ and q unchanged (they
    refer to the frame)."""
    mapping, w, gamma, q, A = _angle_map(convention)
    if not mech.turning:
        return mapping, w, gamma, q, A
    w = (w + A * sp.Matrix(mech.frame)).applyfunc(sp.expand)
    return {**mapping, **dict(zip(OMEGA, w))}, w, gamma, q, A


def _newton_euler_in_angles(mech: Mechanics, convention: str) -> sp.Matrix:
    """``Jᵀ (I ω̇ + ω × L − N)``: the Newton–Euler residual mapped through ω(φ, θ, ψ, rates)."""
    mapping, w, _, _, _ = _frame_map(mech, convention)
    eqs = equations(mech)
    residual = sp.Matrix([e.lhs - e.rhs for e in eqs.euler])
    mapping = {**mapping, **dict(zip(OMEGA_DOT, w.diff(t)))}
    mapped = residual.xreplace(mapping)
    return (euler_rate_matrix(convention).T * mapped).applyfunc(sp.expand)


# ----------------------------------------------------------------------------------------------------------------
# Proof


@dataclass(frozen=True)
class CheckItem:
    """One proven (or refuted) identity of :func:`check`.

    Examples
    --------
    >>> CheckItem("demo", "zxz", True, "exact (expand)").line()
    'ok    [zxz] demo: exact (expand)'
    """

    name: str
    convention: str
    equal: bool
    method: str

    def line(self) -> str:
        """One line for a report."""
        where = f"[{self.convention}] " if self.convention else ""
        return f"{'ok' if self.equal else 'FAIL':<5} {where}{self.name}: {self.method}"


@dataclass(frozen=True)
class CheckReport:
    """What :func:`check` proved: one :class:`CheckItem` per identity; ``ok`` when all hold.

    Examples
    --------
    >>> CheckReport("demo", (CheckItem("x", "", True, "identical"),)).ok
    True
    """

    model: str
    items: tuple

    @property
    def ok(self) -> bool:
        """Whether every identity was shown."""
        return all(item.equal for item in self.items)

    def __str__(self) -> str:
        return "\n".join([f"model {self.model}: {'all identities hold' if self.ok else 'FAILED'}"]
                         + ["  " + item.line() for item in self.items])


def _half_angles(a, b):
    """Freeze functions of t (shared names) and write each angle as twice a half angle, so that the half-angle
    quaternion's sines and cosines become polynomial generators for the compare engine's exact reduction."""
    from eulersym.compare import freeze_functions

    mapping: dict = {}
    fa, _ = freeze_functions(sp.Matrix(a) if isinstance(a, (list, tuple)) else a, mapping)
    fb, _ = freeze_functions(sp.Matrix(b) if isinstance(b, (list, tuple)) else b, mapping)
    halves = {}
    for f in euler_angles:
        s = mapping.get(f)
        if s is not None:
            halves[s] = 2 * sp.Symbol(s.name + "_half", real=True)
    return fa.xreplace(halves), fb.xreplace(halves)


def _compare(a, b, *, half: bool = False):
    from eulersym.compare import compare

    if half:
        a, b = _half_angles(a, b)
    return compare(a, b)


def is_chapter_top(mech: Mechanics) -> bool:
    """Whether ``mech`` is the chapter's heavy symmetric top: ``I = diag(I1, I1, I3)`` about the pivot, the centre
    of mass on the symmetry axis ``(0, 0, l)``, gravity, no other torque, no rotor.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> is_chapter_top(Mechanics(name="top", inertia=sp.ImmutableMatrix(sp.diag(2, 2, 1)), mass=sp.Integer(1),
    ...                centre_of_mass=sp.ImmutableMatrix([0, 0, 1]), gravity=sp.Integer(10), pivoted=True))
    True
    """
    I, c = mech.inertia, mech.centre_of_mass
    return bool(
        mech.pivoted and mech.gravity != 0 and I.is_diagonal() and sp.expand(I[0, 0] - I[1, 1]) == 0
        and c[0] == 0 and c[1] == 0 and c[2] != 0
        and all(e == 0 for e in mech.torque) and all(e == 0 for e in mech.rotor) and mech.potential == 0
    )


def _chapter_top_items(mech: Mechanics) -> list:
    from eulersym import dynamics, top
    from eulersym import symbols as S

    I, c = mech.inertia, mech.centre_of_mass
    values = {S.I1: I[0, 0], S.I2: I[1, 1], S.I3: I[2, 2], S.M: mech.mass, S.g: mech.gravity, S.l: c[2]}
    items = []
    r = _compare(lagrangian(mech, "zxz"), top.lagrangian().xreplace(values))
    items.append(CheckItem("Lagrangian = eulersym.top.lagrangian()", "zxz", r.equal, r.method))
    ours = [e.lhs for e in lagrange_equations(mech, "zxz")]
    theirs = [e.lhs.xreplace(values) for e in top.equations_of_motion()]
    r = _compare(ours, theirs)
    items.append(CheckItem("Lagrange's equations = eulersym.top.equations_of_motion()", "zxz", r.equal, r.method))
    omega_dot, gamma_dot = dynamics.euler_poisson_equations()
    frozen = {**dict(zip(S.omega_symbols, OMEGA)), **dict(zip((S.Gamma1, S.Gamma2, S.Gamma3), GAMMA))}
    theirs = [e.xreplace(values).xreplace(frozen) for e in (*omega_dot, *gamma_dot)]
    r = _compare(list(equations(mech).rhs[:6, 0]), theirs)
    items.append(CheckItem("Newton–Euler = eulersym.dynamics.euler_poisson_equations()", "", r.equal, r.method))
    return items


def check(mech: Mechanics, conventions=None) -> CheckReport:
    """Prove that Lagrange's equations, mapped through ω(φ, θ, ψ, rates), equal the Newton–Euler equations.

    For each convention: Lagrange's equations ``= Jᵀ (I ω̇ + ω × L − N)`` identically; the kinematics along the
    angle map that the Lagrangian relies on (``Γ̇ = Γ × ω`` with ``Γ = A ẑ`` when the state carries Γ;
    ``q̇ = ½ q ⊗ (0, ω)`` and ``from_quaternion(q) = A`` for the composed quaternion when an expression uses q). Models with a torque that is not a potential's have no Lagrangian: only the kinematics
    are checked and an item says why. For the chapter's top, also the identities with :mod:`eulersym.top` and
    :func:`eulersym.dynamics.euler_poisson_equations`.

    Parameters
    ----------
    mech : Mechanics
    conventions : sequence of str, optional
        Default ``("zxz",)``, the text's; ``"all"`` for all 12 of :data:`eulersym.rotation.CONVENTIONS`.

    Returns
    -------
    CheckReport

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> a = sp.Symbol("a", positive=True)
    >>> kovalevskaya = Mechanics(name="kovalevskaya", inertia=sp.ImmutableMatrix(sp.diag(2, 2, 1)),
    ...     mass=sp.Integer(1), centre_of_mass=sp.ImmutableMatrix([a, 0, 0]), gravity=sp.Float(9.81), pivoted=True)
    >>> print(check(kovalevskaya, ["xyz"]))  # doctest: +ELLIPSIS
    model kovalevskaya: all identities hold
      ok    [xyz] Lagrange's equations = Jᵀ·(Newton–Euler): exact (...) + numeric (5 points at 30 digits)
    ...
    """
    if not isinstance(mech, Mechanics):
        raise InvalidInput("mech", mech, "an eulersym.model.mechanics.Mechanics")
    if conventions is None:
        conventions = ("zxz",)
    elif conventions == "all":
        conventions = CONVENTIONS
    elif isinstance(conventions, str):
        conventions = (conventions,)
    conventions = tuple(_convention(c) for c in conventions)
    if not conventions:
        raise InvalidInput("conventions", conventions, "at least one of " + ", ".join(CONVENTIONS))
    items = []
    conservative = all(sp.sympify(e) == 0 for e in mech.torque)
    has_q = sp.sympify(mech.potential).has(*Q)
    for convention in conventions:
        if conservative:
            ours = [e.lhs for e in lagrange_equations(mech, convention)]
            theirs = list(_newton_euler_in_angles(mech, convention))
            r = _compare(ours, theirs, half=has_q)
            items.append(CheckItem("Lagrange's equations = Jᵀ·(Newton–Euler)", convention, r.equal, r.method))
        else:
            items.append(CheckItem("Lagrangian route", convention, True,
                                   "not applicable: a torque that is not a potential's has no Lagrangian"))
        mapping, w, gamma, q, A = _frame_map(mech, convention)
        turning = mech.turning
        if uses_gamma(mech):  # the derived kinematics (frame terms included), along the angle map
            rows = equations(mech).rhs[3:6, 0]
            r = _compare(list(gamma.diff(t)), [e.xreplace(mapping) for e in rows], half=turning)
            items.append(CheckItem("Γ = A ẑ satisfies Γ̇ = Γ × ω" + (" − Γ × A Ω (turning frame)" if turning else ""),
                                   convention, r.equal, r.method))
        if has_q or turning:  # the Lagrangian uses q(angles) only through a potential in q (or the frame's turn)
            rows = equations(mech).rhs[-4:, 0]
            r = _compare(list(q.diff(t)), [e.xreplace(mapping) for e in rows], half=True)
            items.append(CheckItem("q(angles) satisfies q̇ = ½ q ⊗ (0, ω)" + (" − ½ (0, Ω) ⊗ q (turning frame)"
                                   if turning else ""), convention, r.equal, r.method))
            r = _compare(from_quaternion(list(q)), A, half=True)
            items.append(CheckItem("from_quaternion(q(angles)) = A(angles)", convention, r.equal, r.method))
    if is_chapter_top(mech):
        items += _chapter_top_items(mech)
    return CheckReport(mech.name, tuple(items))
