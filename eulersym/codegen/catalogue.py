"""The kernel catalogue: module name → the derivation it comes from, its inputs in order, and its outputs.

Nothing here is typed physics: each entry calls a derivation of :mod:`eulersym.dynamics`, :mod:`eulersym.top`,
:mod:`eulersym.kinematics` or :mod:`eulersym.rotation`, freezes its functions of time into state symbols,
solves for the highest derivatives where needed (:func:`first_order`), and differentiates for the Jacobian.

State and parameter orders (fixed by the project's contracts):

==========================  ==============================================  ======================================
module                      y                                               params
==========================  ==============================================  ======================================
``euler_principal``         (omega1, omega2, omega3)                        (I1, I2, I3, N1, N2, N3)
``euler_full``              (omega1, omega2, omega3)                        (I11, I12, I13, I22, I23, I33, N1, N2, N3)
``free_body_quaternion``    (omega1, omega2, omega3, q0, q1, q2, q3)        (I1, I2, I3)
``heavy_top_euler_angles``  (phi, theta, psi, phidot, thetadot, psidot)     (I1, I3, M, g, l)
``heavy_top_euler_poisson`` (omega1..3, Gamma1..3, q0..q3)                  (I1, I2, I3, M, g, l)
``kinematics``              attitude_matrix(phi, theta, psi), omega_body(phi, theta, psi, phidot, thetadot, psidot)
==========================  ==============================================  ======================================

Each ODE entry also names a body to start from (``DEFAULTS``: the moments of a body with I1 : I2 : I3 = 1 : 2 : 3,
or the symmetric top I1 = I2 = 1, I3 = 0.5, M = 1, g = 9.81, l = 0.1; no torque): example inputs, not results.

An entry whose derivation is not importable (a module or function not yet in the package) stays registered but
is *unavailable*: :func:`available` says why, and ``eulersym generate`` skips it with that message.

Examples
--------
>>> list(CATALOGUE)[:2]
['euler_principal', 'euler_full']
>>> CATALOGUE["kinematics"].requires
('eulersym.rotation:euler_matrix', 'eulersym.kinematics:omega_body')
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Callable

import sympy as sp

from eulersym import dynamics, kinematics, rotation
from eulersym import symbols as S
from eulersym import top as top_module
from eulersym.codegen.emitter import Argument, FunctionSpec, ModuleSpec
from eulersym.errors import InvalidInput

__all__ = ["Kernel", "CATALOGUE", "available", "build", "first_order", "frozen_symbols", "freeze_state"]


@dataclass(frozen=True)
class Kernel:
    """A catalogue entry.

    Attributes
    ----------
    name : str
        The module name in ``eulersym.generated``.
    source : str
        The derivation, as written in the generated file's header.
    requires : tuple of str
        ``"module:function"`` names the derivation calls (all must import for the entry to be available).
    build : callable
        ``build() -> ModuleSpec`` (pure; cached by :func:`build`).

    Examples
    --------
    >>> CATALOGUE["euler_principal"].source
    'eulersym.dynamics.euler_equations'
    """

    name: str
    source: str
    requires: tuple
    build: Callable[[], ModuleSpec]


# ----------------------------------------------------------------------------------------------------------------
# Freezing functions of time into plain symbols


def _real(name: str) -> sp.Symbol:
    return sp.Symbol(name, real=True)


def frozen_symbols(functions) -> dict:
    """``{f(t): f, f'(t): fdot, f''(t): fddot}`` for each function of time, as real symbols named after it.

    Examples
    --------
    >>> from eulersym.symbols import phi
    >>> m = frozen_symbols([phi])
    >>> [str(v) for v in m.values()]
    ['phiddot', 'phidot', 'phi']
    """
    mapping = {}
    for f in functions:
        name = f.func.__name__
        mapping[f.diff(S.t, 2)] = _real(name + "ddot")
        mapping[f.diff(S.t)] = _real(name + "dot")
        mapping[f] = _real(name)
    return mapping


def freeze_state(expr, mapping: dict):
    """Replace functions of time and their derivatives by symbols (``xreplace``: a derivative matches first).

    Examples
    --------
    >>> from eulersym.symbols import phi, t
    >>> freeze_state(phi.diff(t) * phi, frozen_symbols([phi]))
    phi*phidot
    """
    if isinstance(expr, (list, tuple)):
        return [freeze_state(e, mapping) for e in expr]
    return sp.sympify(expr).xreplace(mapping)


def _residual(eq):
    return eq.lhs - eq.rhs if isinstance(eq, sp.Equality) else sp.sympify(eq)


_CANCEL_LIMIT = 300


def first_order(equations, unknowns) -> sp.Matrix:
    """Solve equations linear in ``unknowns`` (the highest derivatives, as symbols) for them: ``M x = F``.

    A diagonal mass matrix is inverted entry by entry (and each entry ``cancel``-ed). Otherwise the LU solution is
    kept in its nested form, or replaced by its ``cancel``-ed form where that is cheaper: the candidate with
    fewer operations after CSE wins (for a full 3×3 inertia tensor the nested form is 4× smaller). Above
    ``_CANCEL_LIMIT`` operations the nested form is kept without trying (``cancel`` would cost seconds).

    Parameters
    ----------
    equations : list of sympy.Eq or expressions (= 0)
        Already frozen: the unknowns appear as symbols.
    unknowns : list of sympy.Symbol

    Examples
    --------
    >>> import sympy as sp
    >>> a, b, x, y = sp.symbols("a b x y")
    >>> first_order([sp.Eq(a * x + y, 1), sp.Eq(b * y, 2)], [x, y]).T
    Matrix([[(1 - 2/b)/a, 2/b]])
    """
    residuals = [_residual(e) for e in equations]
    try:
        M, F = sp.linear_eq_to_matrix(residuals, list(unknowns))
    except (ValueError, sp.polys.polyerrors.PolynomialError):
        raise InvalidInput("equations", residuals, f"equations linear in {list(unknowns)}") from None
    if M.is_diagonal():
        if any(M[i, i] == 0 for i in range(M.rows)):
            raise InvalidInput("equations", equations, "a non-singular mass matrix")
        return sp.Matrix([sp.cancel(F[i] / M[i, i]) for i in range(M.rows)])
    nested = M.LUsolve(F)
    if sp.count_ops(nested) > _CANCEL_LIMIT:
        return nested
    cancelled = nested.applyfunc(lambda e: sp.factor_terms(sp.cancel(sp.together(e))))
    size = [sp.count_ops(sp.cse(list(x), order="canonical")) for x in (nested, cancelled)]
    return cancelled if size[1] <= size[0] else nested


# ----------------------------------------------------------------------------------------------------------------
# The state symbols (plain real symbols; names are the local names in the generated code)

_OMEGA = frozen_symbols(S.omega_symbols)
_GAMMA = frozen_symbols((S.Gamma1, S.Gamma2, S.Gamma3))
_QUAT = frozen_symbols((S.q0, S.q1, S.q2, S.q3))
_ANGLES = frozen_symbols(S.euler_angles)

OMEGA = tuple(_OMEGA[f] for f in S.omega_symbols)
OMEGA_DOT = tuple(_OMEGA[f.diff(S.t)] for f in S.omega_symbols)
GAMMA = tuple(_GAMMA[f] for f in (S.Gamma1, S.Gamma2, S.Gamma3))
QUAT = tuple(_QUAT[f] for f in (S.q0, S.q1, S.q2, S.q3))
ANGLES = tuple(_ANGLES[f] for f in S.euler_angles)
RATES = tuple(_ANGLES[f.diff(S.t)] for f in S.euler_angles)
ACCELERATIONS = tuple(_ANGLES[f.diff(S.t, 2)] for f in S.euler_angles)
FULL_INERTIA = tuple(_real(n) for n in ("I11", "I12", "I13", "I22", "I23", "I33"))
_ALL = {**_OMEGA, **_GAMMA, **_QUAT, **_ANGLES}


def _full_tensor():
    I11, I12, I13, I22, I23, I33 = FULL_INERTIA
    return sp.Matrix([[I11, I12, I13], [I12, I22, I23], [I13, I23, I33]])


#: The derivation modules the catalogue draws on, by name (imported as themselves, so the graph shows them).
_DERIVATIONS = {"eulersym.dynamics": dynamics, "eulersym.kinematics": kinematics, "eulersym.rotation": rotation,
                "eulersym.top": top_module}


def _call(target: str):
    module, name = target.split(":")
    return getattr(_DERIVATIONS[module], name)


def _ode(name, description, source, state, params, rhs, invariants=None, invariant_names=(), notes=(), singular=(),
         defaults=()):
    """A ModuleSpec with rhs, jac (and invariants) of (t, y, *params); ``defaults``: a body to start from (the
    module's ``DEFAULTS``, one float per parameter)."""
    args = (Argument("t", (S.t,), doc="time"),
            Argument("y", tuple(state), vector=True, doc="state"),
            *(Argument(p.name, (p,)) for p in params))
    rhs = sp.Matrix(rhs)
    names = tuple(f"d{s.name}/dt" for s in state)
    functions = [FunctionSpec("rhs", args, rhs, "the right-hand side dy/dt", names),
                 FunctionSpec("jac", args, rhs.jacobian(list(state)),
                              "the Jacobian d(rhs)/dy, derived symbolically; row i = d(dy_i/dt)/dy")]
    if invariants is not None:
        functions.append(FunctionSpec("invariants", args, sp.Matrix(invariants),
                                      "the invariants " + ", ".join(invariant_names), tuple(invariant_names)))
    return ModuleSpec(name, description, source, tuple(functions), tuple(notes), tuple(singular),
                      tuple(float(v) for v in defaults))


def _freeze_all(exprs):
    return sp.Matrix([freeze_state(e, _ALL) for e in exprs])


def _euler_rhs(I, torque):
    eqs = _call("eulersym.dynamics:euler_equations")(I, torque)
    return first_order([freeze_state(_residual(e), _OMEGA) for e in eqs], OMEGA_DOT)


def _euler_invariants(I):
    energy = _call("eulersym.dynamics:energy")
    l2 = _call("eulersym.dynamics:angular_momentum_squared")
    omega = sp.Matrix(S.omega_symbols)
    return _freeze_all([energy(I, omega), l2(I, omega)])


# ----------------------------------------------------------------------------------------------------------------
# Builders


def _build_euler_principal() -> ModuleSpec:
    I = tuple(S.moments)
    return _ode(
        "euler_principal",
        "Euler's equations in principal axes with a body torque: I ω̇ = (I ω) × ω + N, I = diag(I1, I2, I3).",
        "eulersym.dynamics.euler_equations(I=(I1, I2, I3), torque=(N1, N2, N3)) solved for d(omega)/dt",
        OMEGA, (*S.moments, *S.torques), _euler_rhs(I, tuple(S.torques)),
        _euler_invariants(I), ("E", "L2"),
        ("Invariants: E = ½ ω·Iω and L² = |Iω|² (conserved only without torque).",),
        defaults=(1.0, 2.0, 3.0, 0.0, 0.0, 0.0),
    )


def _build_euler_full() -> ModuleSpec:
    I = _full_tensor()
    return _ode(
        "euler_full",
        "Euler's equations with a full (symmetric) inertia tensor and a body torque: I ω̇ = (I ω) × ω + N, "
        "I = [[I11, I12, I13], [I12, I22, I23], [I13, I23, I33]] (the tensor's entries, body axes).",
        "eulersym.dynamics.euler_equations(I=<full symmetric tensor>, torque=(N1, N2, N3)) solved for d(omega)/dt",
        OMEGA, (*FULL_INERTIA, *S.torques), _euler_rhs(I, tuple(S.torques)),
        _euler_invariants(I), ("E", "L2"),
        ("Invariants: E = ½ ω·Iω and L² = |Iω|² (conserved only without torque).",),
        defaults=(1.0, 0.0, 0.0, 2.0, 0.0, 3.0, 0.0, 0.0, 0.0),
    )


def _quaternion_rhs():
    rate = _call("eulersym.kinematics:quaternion_rate")([S.q0, S.q1, S.q2, S.q3], list(S.omega_symbols))
    return _freeze_all(list(rate))


def _build_free_body_quaternion() -> ModuleSpec:
    omega_dot = _euler_rhs(tuple(S.moments), (0, 0, 0))
    q_dot = _quaternion_rhs()
    invariants = list(_euler_invariants(tuple(S.moments))) + [sum(q ** 2 for q in QUAT)]
    return _ode(
        "free_body_quaternion",
        "The torque-free rigid body with its attitude as a unit quaternion (scalar first): Euler's equations "
        "I ω̇ = (I ω) × ω and q̇ = ½ q ⊗ (0, ω_body).",
        "eulersym.dynamics.euler_equations(I=(I1, I2, I3), torque=(0, 0, 0)) and "
        "eulersym.kinematics.quaternion_rate(q, omega)",
        (*OMEGA, *QUAT), S.moments, list(omega_dot) + list(q_dot), invariants, ("E", "L2", "q_norm2"),
        defaults=(1.0, 2.0, 3.0),
    )


def _build_heavy_top_euler_angles() -> ModuleSpec:
    top = top_module
    eqs = [freeze_state(_residual(e), _ANGLES) for e in top.equations_of_motion()]
    accelerations = first_order(eqs, ACCELERATIONS)
    p_phi, p_psi = top.conserved_momenta()
    invariants = _freeze_all([top.energy(), p_phi, p_psi])
    params = (S.I1, S.I3, S.M, S.g, S.l)
    return _ode(
        "heavy_top_euler_angles",
        "The heavy symmetric top with a fixed pivot in Euler angles (zxz): Lagrange's equations in first-order "
        "form, y = (φ, θ, ψ, φ̇, θ̇, ψ̇). Singular at sin θ = 0: there the scalar flavour raises "
        "eulersym.errors.SingularConfiguration (the batched flavour gives inf or nan; the flat one divides by zero).",
        "eulersym.top.equations_of_motion() solved for the second derivatives (mass matrix); "
        "invariants eulersym.top.energy(), eulersym.top.conserved_momenta()",
        (*ANGLES, *RATES), params, list(RATES) + list(accelerations), invariants, ("E", "p_phi", "p_psi"),
        singular=("theta", "sin(theta) == 0",
                  "sin(theta) != 0 (theta strictly between 0 and pi, modulo pi): the Euler-angle equations are "
                  "singular at theta = 0 and pi (the sleeping top); use heavy_top_euler_poisson there"),
        defaults=(1.0, 0.5, 1.0, 9.81, 0.1),
    )


def _build_heavy_top_euler_poisson() -> ModuleSpec:
    omega_dot, gamma_dot = dynamics.euler_poisson_equations()
    frozen = {**_OMEGA, **_GAMMA}
    rates = [freeze_state(e, frozen) for m in (omega_dot, gamma_dot) for e in m]
    q_dot = _quaternion_rhs()
    energy, gamma_norm2, l_dot_gamma = dynamics.euler_poisson_invariants()
    invariants = _freeze_all([energy, gamma_norm2, l_dot_gamma, sum(q ** 2 for q in (S.q0, S.q1, S.q2, S.q3))])
    return _ode(
        "heavy_top_euler_poisson",
        "The heavy top in the non-singular Euler–Poisson form, centre of mass at l·e3 in the body: "
        "I ω̇ = (I ω) × ω + M g l Γ × e3, Γ̇ = Γ × ω (Γ: the upward vertical in body components), with the "
        "attitude quaternion q̇ = ½ q ⊗ (0, ω). Invariants: E = ½ ω·Iω + M g l Γ3, |Γ|², L·Γ = (Iω)·Γ, |q|².",
        "eulersym.dynamics.euler_poisson_equations() (omega_dot, Gamma_dot) and "
        "eulersym.kinematics.quaternion_rate(q, omega)",
        (*OMEGA, *GAMMA, *QUAT), (*S.moments, S.M, S.g, S.l), list(rates) + list(q_dot), invariants,
        ("E", "Gamma_norm2", "L_dot_Gamma", "q_norm2"),
        defaults=(1.0, 1.0, 0.5, 1.0, 9.81, 0.1),
    )


def _build_kinematics() -> ModuleSpec:
    A = _call("eulersym.rotation:euler_matrix")(S.phi, S.theta, S.psi)
    w = _call("eulersym.kinematics:omega_body")()
    angle_args = tuple(Argument(s.name, (s,)) for s in ANGLES)
    rate_args = tuple(Argument(s.name, (s,)) for s in RATES)
    return ModuleSpec(
        "kinematics",
        "Kinematics of the zxz Euler angles (passive, the text's convention): the attitude matrix "
        "A = B(ψ) C(θ) D(φ), r_body = A @ r_space, and the body angular velocity ω from the angles and rates.",
        "eulersym.rotation.euler_matrix(phi, theta, psi) and eulersym.kinematics.omega_body()",
        (FunctionSpec("attitude_matrix", angle_args, _freeze_all(A).reshape(3, 3),
                      "A (3×3), r_body = A @ r_space"),
         FunctionSpec("omega_body", angle_args + rate_args, _freeze_all(list(w)),
                      "ω in body components", ("omega1", "omega2", "omega3"))),
    )


#: name → Kernel, in a fixed order.
CATALOGUE: dict[str, Kernel] = {
    k.name: k
    for k in (
        Kernel("euler_principal", "eulersym.dynamics.euler_equations",
               ("eulersym.dynamics:euler_equations", "eulersym.dynamics:energy",
                "eulersym.dynamics:angular_momentum_squared"), _build_euler_principal),
        Kernel("euler_full", "eulersym.dynamics.euler_equations",
               ("eulersym.dynamics:euler_equations", "eulersym.dynamics:energy",
                "eulersym.dynamics:angular_momentum_squared"), _build_euler_full),
        Kernel("free_body_quaternion", "eulersym.dynamics.euler_equations + eulersym.kinematics.quaternion_rate",
               ("eulersym.dynamics:euler_equations", "eulersym.dynamics:energy",
                "eulersym.dynamics:angular_momentum_squared", "eulersym.kinematics:quaternion_rate"),
               _build_free_body_quaternion),
        Kernel("heavy_top_euler_angles", "eulersym.top.equations_of_motion",
               ("eulersym.top:equations_of_motion", "eulersym.top:energy", "eulersym.top:conserved_momenta"),
               _build_heavy_top_euler_angles),
        Kernel("heavy_top_euler_poisson", "eulersym.dynamics.euler_poisson_equations",
               ("eulersym.dynamics:euler_poisson_equations", "eulersym.dynamics:energy",
                "eulersym.kinematics:quaternion_rate"), _build_heavy_top_euler_poisson),
        Kernel("kinematics", "eulersym.rotation.euler_matrix + eulersym.kinematics.omega_body",
               ("eulersym.rotation:euler_matrix", "eulersym.kinematics:omega_body"), _build_kinematics),
    )
}


def available(name: str) -> tuple[bool, str]:
    """Whether a catalogue entry's derivation can be imported, and if not, why.

    Examples
    --------
    >>> available("kinematics")
    (True, '')
    >>> available("nope")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: name='nope' is not valid: expected one of euler_principal, euler_full, free_body_quaternion, heavy_top_euler_angles, heavy_top_euler_poisson, kinematics
    """
    if name not in CATALOGUE:
        raise InvalidInput("name", name, "one of " + ", ".join(CATALOGUE))
    for target in CATALOGUE[name].requires:
        module, func = target.split(":")
        mod = _DERIVATIONS.get(module)
        if mod is None or not hasattr(mod, func):
            return False, f"its derivation {module}.{func} is not available (not defined yet)"
    return True, ""


@functools.lru_cache(maxsize=None)
def build(name: str) -> ModuleSpec:
    """The ModuleSpec of a catalogue entry (derived once per process).

    Examples
    --------
    >>> build("kinematics").function_names
    ('attitude_matrix', 'omega_body')
    """
    ok, why = available(name)
    if not ok:
        raise InvalidInput("name", name, f"an available kernel: {why}")
    return CATALOGUE[name].build()
