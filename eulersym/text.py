"""The text's closed forms, typed once, as data — and the check that proves each equal to its derivation.

Every formula of Chapter 4 (§4.1–§4.5 and Examples 4.1–4.3) is an entry of :data:`CLOSED_FORMS`: an id, its section,
the statement in words, the SymPy expression *as printed in the text*, and the derivation it is checked against (a
zero-argument callable into :mod:`eulersym.rotation`, :mod:`~eulersym.kinematics`, :mod:`~eulersym.inertia`,
:mod:`~eulersym.dynamics` or :mod:`~eulersym.top`). Nothing is derived here; the text's expressions are used
only to check.

:func:`check` compares an entry with :func:`eulersym.compare.compare`: exact simplification to zero *and* a numeric
evaluation at seeded random points at 30 digits. An entry whose derivation is not available is ``pending``.

Examples
--------
>>> r = check("4.1.orthogonality")
>>> r.status, r.exact
('equal', True)
>>> print(r.how)
exact (trig-polynomial reduction) + numeric (5 points at 30 digits)
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import dataclass
from typing import Any, Callable

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.symbols import (
    I1, I2, I3, M, N1, N2, N3, eta1, eta2, eta3, g, l, omega0, omega1, omega2, omega3, phi, psi, t, theta,
)

__all__ = [
    "ClosedForm", "CheckResult", "CLOSED_FORMS", "SECTIONS", "check", "check_all", "report", "derivation_printer",
    "cli",
]

#: Sections of the text, in reading order.
SECTIONS = ("4.1", "4.2", "4.3", "4.4", "4.5", "Example 4.1", "Example 4.2", "Example 4.3")


@dataclass(frozen=True)
class ClosedForm:
    """One closed form of the text.

    Attributes
    ----------
    id : str
        Stable identifier, e.g. ``"4.2.omega_body"``.
    section : str
        One of :data:`SECTIONS`.
    statement : str
        The statement in words.
    expression : SymPy object
        The formula as the text prints it (scalar, Matrix, Eq, or a list/tuple of them).
    derivation : str
        The derivation it is checked against, in words (``module.function(args)``).
    up_to_factor : bool
        Equations that the text states up to a non-zero factor (e.g. divided through by a moment).
    """

    id: str
    section: str
    statement: str
    expression: Any
    derivation: str
    _derive: Callable[[], Any]
    up_to_factor: bool = False

    def derived(self):
        """The derived object this entry is checked against (imports the deriving module on first use)."""
        return self._derive()


def _derivation_module(name: str):
    """The module an entry is derived in, imported on first use (so checking one section imports only its own
    modules); each import written out, so that readers and tools see the package's real dependencies."""
    if name == "eulersym.rotation":
        from eulersym import rotation as module
    elif name == "eulersym.kinematics":
        from eulersym import kinematics as module
    elif name == "eulersym.inertia":
        from eulersym import inertia as module
    elif name == "eulersym.dynamics":
        from eulersym import dynamics as module
    elif name == "eulersym.top":
        from eulersym import top as module
    elif name == "eulersym.model.chapter":
        from eulersym.model import chapter as module
    else:
        raise DerivationMissing(f"no module {name}")
    return module


def _call(target: str, *args, **kwargs) -> Callable[[], Any]:
    """A lazy call of ``module:function(*args, **kwargs)``; ``[i]`` after the name picks an item of the result."""
    module_name, _, name = target.partition(":")
    index = None
    if "[" in name:
        name, _, rest = name.partition("[")
        index = int(rest.rstrip("]"))

    def run():
        module = _derivation_module(module_name)
        if not hasattr(module, name):
            raise DerivationMissing(f"{module_name} has no {name}")
        result = getattr(module, name)(*args, **kwargs)
        return result if index is None else result[index]

    return run


class DerivationMissing(LookupError):
    """The derivation an entry is checked against does not exist (yet): the entry is *pending*.

    Only this marks an entry pending; any exception raised while a derivation runs is an *error*.
    """


# ----------------------------------------------------------------------------------------------------------------
# Local symbols of the text's examples (not dynamical variables).
a = sp.Symbol("a", positive=True)  # cube edge (Example 4.1)
x, y, z = sp.symbols("x y z", real=True)
m1, m2 = sp.symbols("m1 m2", positive=True)
x1, y1, z1, x2, y2, z2 = sp.symbols("x1 y1 z1 x2 y2 z2", real=True)
G1, G2, G3 = sp.symbols("G1 G2 G3", cls=sp.Function)
_omega = sp.Matrix([omega1, omega2, omega3])
_dot = sp.Derivative
_c, _s = sp.cos, sp.sin
_phid, _thetad, _psid = phi.diff(t), theta.diff(t), psi.diff(t)
_particles = [(m1, (x1, y1, z1)), (m2, (x2, y2, z2))]


def _Eq(lhs, rhs):  # the text's equations as printed: not evaluated (deciding lhs == rhs costs assumption queries)
    return sp.Eq(lhs, rhs, evaluate=False)


def _text_D(angle):  # §4.2, as printed
    return sp.Matrix([[_c(angle), _s(angle), 0], [-_s(angle), _c(angle), 0], [0, 0, 1]])


def _text_C(angle):
    return sp.Matrix([[1, 0, 0], [0, _c(angle), _s(angle)], [0, -_s(angle), _c(angle)]])


_text_B = _text_D  # the text prints B(ψ) with the same pattern as D(φ)


def _particle_sum(term):
    return sum((term(m, sp.Matrix(r)) for m, r in _particles), sp.zeros(3, 1) if term is not _ke_term else 0)


def _L_term(m, r):
    return m * r.cross(_omega.cross(r))


def _ke_term(m, r):
    v = _omega.cross(r)
    return sp.Rational(1, 2) * m * (v.T * v)[0, 0]


def _tensor_term(m, r):  # the text's moments and products of inertia, one particle
    X, Y, Z = r
    return m * sp.Matrix(
        [[Y**2 + Z**2, -X * Y, -X * Z], [-X * Y, X**2 + Z**2, -Y * Z], [-X * Z, -Y * Z, X**2 + Y**2]]
    )


# derivations that combine two modules' results (kept as small named functions so the table reads)
def _A():
    from eulersym.rotation import euler_matrix

    return euler_matrix(phi, theta, psi)


def _length_squared_after_rotation():
    r = _A() * sp.Matrix([x, y, z])
    return (r.T * r)[0, 0]


def _omega_cross_L():
    from eulersym.inertia import angular_momentum

    return _omega.cross(angular_momentum(sp.diag(I1, I2, I3), _omega))


def _inertia():
    return _derivation_module("eulersym.inertia")


def _corner_cube():
    return _inertia().cube(M, a, origin="corner")


def _first_principal_axis():
    moments, axes = _inertia().principal_axes(_corner_cube())
    v = axes[:, 0]
    return v if sum(v).is_nonnegative else -v


def _corner_cube_times(v):
    return lambda: _corner_cube() * sp.Matrix(v)


def _entries() -> list[ClosedForm]:
    E = ClosedForm
    G = sp.Matrix([G1(t), G2(t), G3(t)])
    r = sp.Matrix([x, y, z])
    radicand = I3**2 * omega3**2 - 4 * I1 * M * g * l * _c(theta)  # Example 4.3: the rates are real iff ≥ 0
    root = sp.sqrt(radicand)
    growth_rate = omega0 * sp.sqrt((I3 - I2) * (I2 - I1) / (I1 * I3))
    rates = ((I3 * omega3 - root) / (2 * I1 * _c(theta)), (I3 * omega3 + root) / (2 * I1 * _c(theta)))
    sleeping_bound = 4 * M * g * l * I1 / I3**2
    return [
        # §4.1 -------------------------------------------------------------------------------------------------
        E("4.1.dof", "4.1",
          "Three non-collinear particles: 9 coordinates less 3 distance constraints leave 6 degrees of freedom.",
          sp.Integer(6), "rotation.degrees_of_freedom(3)", _call("eulersym.rotation:degrees_of_freedom", 3)),
        E("4.1.length", "4.1", "A rotation preserves length: r'·r' = r·r with r' = A r.",
          x**2 + y**2 + z**2, "(A r)·(A r) with A = rotation.euler_matrix(φ, θ, ψ)", _length_squared_after_rotation),
        E("4.1.orthogonality", "4.1", "Orthogonality: AᵀA = 1.",
          sp.eye(3), "Aᵀ·A with A = rotation.euler_matrix(φ, θ, ψ)", lambda: _A().T * _A()),
        E("4.1.orthogonality_right", "4.1", "Orthogonality: AAᵀ = 1.",
          sp.eye(3), "A·Aᵀ with A = rotation.euler_matrix(φ, θ, ψ)", lambda: _A() * _A().T),
        E("4.1.proper", "4.1", "Proper rotations have det A = +1 (SO(3)).",
          sp.Integer(1), "det of rotation.euler_matrix(φ, θ, ψ)", lambda: _A().det(method="berkowitz")),
        # §4.2 -------------------------------------------------------------------------------------------------
        E("4.2.D", "4.2", "Precession by φ about the space z-axis.", _text_D(phi),
          "rotation.D(φ) (passive Rodrigues about z)", _call("eulersym.rotation:D", phi)),
        E("4.2.C", "4.2", "Nutation by θ about the line of nodes.", _text_C(theta),
          "rotation.C(θ) (passive Rodrigues about x)", _call("eulersym.rotation:C", theta)),
        E("4.2.B", "4.2", "Spin by ψ about the body z'-axis.", _text_B(psi),
          "rotation.B(ψ) (passive Rodrigues about z)", _call("eulersym.rotation:B", psi)),
        E("4.2.A", "4.2", "A = B(ψ) C(θ) D(φ) transforms space coordinates into body coordinates.",
          _text_B(psi) * _text_C(theta) * _text_D(phi), "rotation.euler_matrix(φ, θ, ψ, 'zxz')", _A),
        E("4.2.omega_body", "4.2", "Body components of ω in Euler angles and their rates.",
          sp.Matrix([
              _phid * _s(theta) * _s(psi) + _thetad * _c(psi),
              _phid * _s(theta) * _c(psi) - _thetad * _s(psi),
              _phid * _c(theta) + _psid,
          ]),
          "kinematics.omega_body('zxz') (composition of the three rotations' rates)",
          _call("eulersym.kinematics:omega_body")),
        E("4.2.euler_theorem", "4.2", "Euler's rotation theorem: every proper rotation has the eigenvalue 1, det(A − 1) = 0.",
          sp.Integer(0), "det(A − 1) with A = rotation.euler_matrix(φ, θ, ψ)",
          lambda: (_A() - sp.eye(3)).det(method="berkowitz")),
        # §4.3 -------------------------------------------------------------------------------------------------
        E("4.3.triple_product", "4.3", "m r × (ω × r) = m [r² ω − (r·ω) r].",
          m1 * ((r.T * r)[0, 0] * _omega - (r.T * _omega)[0, 0] * r),
          "m r × (ω × r) by cross products", lambda: m1 * r.cross(_omega.cross(r))),
        E("4.3.angular_momentum", "4.3", "L = Σ m_i r_i × (ω × r_i) = I ω (two point masses).",
          _particle_sum(_L_term), "inertia.angular_momentum(inertia.point_masses(...), ω)",
          lambda: _inertia().angular_momentum(_inertia().point_masses(_particles), _omega)),
        E("4.3.moments_and_products", "4.3",
          "I_xx = ∫(y² + z²) dm, ..., I_xy = −∫ x y dm, ... (two point masses).",
          _tensor_term(m1, sp.Matrix([x1, y1, z1])) + _tensor_term(m2, sp.Matrix([x2, y2, z2])),
          "inertia.point_masses(...)", _call("eulersym.inertia:point_masses", _particles)),
        E("4.3.kinetic_energy", "4.3", "T = ½ Σ m_i v_i² = ½ ωᵀ I ω (two point masses).",
          sum(_ke_term(m, sp.Matrix(p)) for m, p in _particles),
          "inertia.kinetic_energy(inertia.point_masses(...), ω)",
          lambda: _inertia().kinetic_energy(_inertia().point_masses(_particles), _omega)),
        E("4.3.kinetic_energy_half_omega_L", "4.3", "T = ½ ω·L (two point masses).",
          sp.Rational(1, 2) * (_omega.T * _particle_sum(_L_term))[0, 0],
          "inertia.kinetic_energy(inertia.point_masses(...), ω)",
          lambda: _inertia().kinetic_energy(_inertia().point_masses(_particles), _omega)),
        E("4.3.principal_energy", "4.3", "In principal axes T = ½ I1 ω1² + ½ I2 ω2² + ½ I3 ω3².",
          (I1 * omega1**2 + I2 * omega2**2 + I3 * omega3**2) / 2,
          "inertia.kinetic_energy(diag(I1, I2, I3), ω)",
          _call("eulersym.inertia:kinetic_energy", sp.diag(I1, I2, I3), _omega)),
        E("4.3.principal_momentum", "4.3", "In principal axes L = (I1 ω1, I2 ω2, I3 ω3).",
          sp.Matrix([I1 * omega1, I2 * omega2, I3 * omega3]),
          "inertia.angular_momentum(diag(I1, I2, I3), ω)",
          _call("eulersym.inertia:angular_momentum", sp.diag(I1, I2, I3), _omega)),
        # §4.4 -------------------------------------------------------------------------------------------------
        E("4.4.rotating_frame", "4.4", "(dG/dt)_space = (dG/dt)_body + ω × G, in body components.",
          G.applyfunc(lambda g: g.diff(t)) + sp.Matrix([
              _phid * _s(theta) * _s(psi) + _thetad * _c(psi),
              _phid * _s(theta) * _c(psi) - _thetad * _s(psi),
              _phid * _c(theta) + _psid,
          ]).cross(G),
          "kinematics.space_rate_in_body(G) = A d/dt(Aᵀ G)", _call("eulersym.kinematics:space_rate_in_body", G)),
        E("4.4.omega_cross_L", "4.4", "(ω × L)_1 = ω2 L3 − ω3 L2 = (I3 − I2) ω2 ω3.",
          (I3 - I2) * omega2 * omega3, "first component of ω × inertia.angular_momentum(diag(I1, I2, I3), ω)",
          lambda: _omega_cross_L()[0]),
        E("4.4.euler_equations", "4.4", "Euler's equations: I1 ω̇1 − (I2 − I3) ω2 ω3 = N1 and cyclic.",
          [
              _Eq(I1 * omega1.diff(t) - (I2 - I3) * omega2 * omega3, N1),
              _Eq(I2 * omega2.diff(t) - (I3 - I1) * omega3 * omega1, N2),
              _Eq(I3 * omega3.diff(t) - (I1 - I2) * omega1 * omega2, N3),
          ],
          "dynamics.euler_equations() from (dL/dt)_body + ω × L = N", _call("eulersym.dynamics:euler_equations")),
        # §4.5 -------------------------------------------------------------------------------------------------
        E("4.5.torque_free_symmetric", "4.5", "Torque-free, I1 = I2: I1 ω̇1 = (I1 − I3) ω2 ω3, "
          "I1 ω̇2 = −(I1 − I3) ω1 ω3, I3 ω̇3 = 0.",
          [
              _Eq(I1 * omega1.diff(t), (I1 - I3) * omega2 * omega3),
              _Eq(I1 * omega2.diff(t), -(I1 - I3) * omega1 * omega3),
              _Eq(I3 * omega3.diff(t), 0),
          ],
          "dynamics.euler_equations(I=(I1, I1, I3), torque=(0, 0, 0))",
          _call("eulersym.dynamics:euler_equations", I=(I1, I1, I3), torque=(0, 0, 0))),
        E("4.5.precession_rate", "4.5", "Ω_prec = (I1 − I3)/I1 · ω3.",
          (I1 - I3) / I1 * omega3, "dynamics.symmetric_precession_rate()",
          _call("eulersym.dynamics:symmetric_precession_rate")),
        E("4.5.transverse_oscillator", "4.5", "ω̈1 + Ω_prec² ω1 = 0: ω precesses uniformly about the symmetry axis.",
          _Eq(omega1.diff(t, 2) + ((I1 - I3) / I1 * omega3) ** 2 * omega1, 0),
          "dynamics.symmetric_transverse_equation()", _call("eulersym.dynamics:symmetric_transverse_equation"),
          up_to_factor=True),
        E("4.5.lagrangian", "4.5", "The heavy symmetric top's Lagrangian.",
          sp.Rational(1, 2) * I1 * (_thetad**2 + _phid**2 * _s(theta) ** 2)
          + sp.Rational(1, 2) * I3 * (_phid * _c(theta) + _psid) ** 2 - M * g * l * _c(theta),
          "top.lagrangian() = ½ ωᵀ I ω − M g l cos θ with ω = kinematics.omega_body()",
          _call("eulersym.top:lagrangian")),
        E("4.5.cyclic", "4.5", "φ (precession) and ψ (spin) are cyclic coordinates.", (phi, psi),
          "top.cyclic_coordinates() (∂L/∂q = 0)", _call("eulersym.top:cyclic_coordinates")),
        E("4.5.p_phi", "4.5", "p_φ = I1 φ̇ sin²θ + I3 (φ̇ cos θ + ψ̇) cos θ.",
          I1 * _phid * _s(theta) ** 2 + I3 * (_phid * _c(theta) + _psid) * _c(theta),
          "top.conserved_momenta()[0] = ∂L/∂φ̇", _call("eulersym.top:conserved_momenta[0]")),
        E("4.5.p_psi", "4.5", "p_ψ = I3 (φ̇ cos θ + ψ̇) = I3 ω3.",
          I3 * (_phid * _c(theta) + _psid), "top.conserved_momenta()[1] = ∂L/∂ψ̇",
          _call("eulersym.top:conserved_momenta[1]")),
        E("4.5.sleeping_top", "4.5", "The sleeping top is stable if ω3² ≥ 4 M g l I1 / I3².",
          sleeping_bound, "top.sleeping_top_threshold()", _call("eulersym.top:sleeping_top_threshold")),
        E("4.5.sleeping_top_model", "4.5",
          "The same bound from a model file: the lagrange-top model's spin about the vertical, axis up, "
          "changes from unstable to stable at s² = 4 M g l I1 / I3².",
          sleeping_bound, "model.chapter.sleeping_top_threshold() (the lagrange-top model's equations, shown "
          "steady and linearised there)", _call("eulersym.model.chapter:sleeping_top_threshold")),
        # Example 4.1 ------------------------------------------------------------------------------------------
        E("ex4.1.Ixx", "Example 4.1", "Cube about a corner: I_xx = (2/3) M a².", sp.Rational(2, 3) * M * a**2,
          "inertia.cube(M, a, origin='corner')[0, 0]",
          lambda: _corner_cube()[0, 0]),
        E("ex4.1.Ixy", "Example 4.1", "Cube about a corner: I_xy = −(1/4) M a².", -sp.Rational(1, 4) * M * a**2,
          "inertia.cube(M, a, origin='corner')[0, 1]",
          lambda: _corner_cube()[0, 1]),
        E("ex4.1.tensor", "Example 4.1", "The full corner tensor: 2/3 on the diagonal, −1/4 off it (× M a²).",
          M * a**2 * sp.Matrix([
              [sp.Rational(2, 3), -sp.Rational(1, 4), -sp.Rational(1, 4)],
              [-sp.Rational(1, 4), sp.Rational(2, 3), -sp.Rational(1, 4)],
              [-sp.Rational(1, 4), -sp.Rational(1, 4), sp.Rational(2, 3)],
          ]),
          "inertia.cube(M, a, origin='corner')", _call("eulersym.inertia:cube", M, a, origin="corner")),
        E("ex4.1.principal_moments", "Example 4.1", "Principal moments M a²/6 and 11 M a²/12 (twice).",
          [M * a**2 / 6, sp.Rational(11, 12) * M * a**2, sp.Rational(11, 12) * M * a**2],
          "inertia.principal_axes(cube corner tensor)[0] (ascending)",
          lambda: list(_inertia().principal_axes(_corner_cube())[0])),
        E("ex4.1.first_axis", "Example 4.1", "The axis of M a²/6 points along the space diagonal (1, 1, 1).",
          sp.Matrix([1, 1, 1]) / sp.sqrt(3), "first column of inertia.principal_axes(cube corner tensor)[1]",
          _first_principal_axis),
        E("ex4.1.degenerate_plane", "Example 4.1",
          "Any vector perpendicular to the diagonal, e.g. (1, −1, 0), is a principal axis of 11 M a²/12.",
          sp.Rational(11, 12) * M * a**2 * sp.Matrix([1, -1, 0]), "inertia.cube(M, a, origin='corner') · (1, −1, 0)",
          _corner_cube_times((1, -1, 0))),
        # Example 4.2 ------------------------------------------------------------------------------------------
        E("ex4.2.linearized", "Example 4.2", "About axis 2: I1 η̇1 = (I2 − I3) ω0 η3, η̇2 = 0, I3 η̇3 = (I1 − I2) ω0 η1.",
          [
              _Eq(I1 * eta1.diff(t), (I2 - I3) * omega0 * eta3),
              _Eq(eta2.diff(t), 0),
              _Eq(I3 * eta3.diff(t), (I1 - I2) * omega0 * eta1),
          ],
          "dynamics.linearized_euler_equations(axis=2)", _call("eulersym.dynamics:linearized_euler_equations", 2),
          up_to_factor=True),
        E("ex4.2.coefficient", "Example 4.2", "η̈1 = (I2 − I3)(I1 − I2)/(I1 I3) ω0² η1.",
          (I2 - I3) * (I1 - I2) / (I1 * I3) * omega0**2, "dynamics.perturbation_coefficient(axis=2)",
          _call("eulersym.dynamics:perturbation_coefficient", 2)),
        E("ex4.2.growth_rate", "Example 4.2", "Growth rate Ω = ω0 √[(I3 − I2)(I2 − I1)/(I1 I3)].",
          growth_rate,
          "dynamics.intermediate_axis_growth_rate(I1, I2, I3, ω0)",
          _call("eulersym.dynamics:intermediate_axis_growth_rate", I1, I2, I3, omega0)),
        E("ex4.2.growth_rate_model", "Example 4.2",
          "The same growth rate from the general machinery: the torque-free model's unstable permanent rotation, "
          "the positive root of its reduced characteristic polynomial.",
          growth_rate, "model.chapter.intermediate_axis_growth_rate() (steady motions + stability of the "
          "torque-free model)", _call("eulersym.model.chapter:intermediate_axis_growth_rate")),
        # Example 4.3 ------------------------------------------------------------------------------------------
        E("ex4.3.nutation_equation", "Example 4.3",
          "I1 θ̈ = I1 φ̇² sin θ cos θ − I3 ω3 φ̇ sin θ + M g l sin θ.",
          _Eq(I1 * theta.diff(t, 2),
                I1 * _phid**2 * _s(theta) * _c(theta) - I3 * omega3 * _phid * _s(theta) + M * g * l * _s(theta)),
          "top.nutation_equation() (θ Euler–Lagrange equation, ψ̇ = ω3 − φ̇ cos θ)",
          _call("eulersym.top:nutation_equation")),
        E("ex4.3.quadratic", "Example 4.3", "Steady precession: I1 cos θ φ̇² − I3 ω3 φ̇ + M g l = 0.",
          _Eq(I1 * _c(theta) * _phid**2 - I3 * omega3 * _phid + M * g * l, 0),
          "top.steady_precession_condition()", _call("eulersym.top:steady_precession_condition"), up_to_factor=True),
        E("ex4.3.roots", "Example 4.3", "φ̇ = [I3 ω3 ± √(I3² ω3² − 4 I1 M g l cos θ)] / (2 I1 cos θ) (slow: −, fast: +).",
          rates, "top.steady_precession_rates()", _call("eulersym.top:steady_precession_rates")),
        E("ex4.3.roots_model", "Example 4.3",
          "The same two rates from the general machinery: the lagrange-top model's relative equilibria about its "
          "symmetry axis (Routh), their precession rates φ̇ = (ω + ν e)·Γ.",
          rates, "model.chapter.steady_precession_rates() (steady motions of the lagrange-top model)",
          _call("eulersym.model.chapter:steady_precession_rates")),
        E("ex4.3.existence_model", "Example 4.3",
          "The rates exist (are real) iff I3² ω3² − 4 I1 M g l cos θ ≥ 0: the model's existence condition D ≥ 0.",
          radicand, "model.chapter.steady_precession_existence() (the lagrange-top model's families' existence "
          "condition)", _call("eulersym.model.chapter:steady_precession_existence")),
        E("ex4.3.limits", "Example 4.3", "Large spin: φ̇_slow ≈ M g l/(I3 ω3), φ̇_fast ≈ I3 ω3/(I1 cos θ).",
          (M * g * l / (I3 * omega3), I3 * omega3 / (I1 * _c(theta))), "top.precession_limits()",
          _call("eulersym.top:precession_limits")),
        # The turning-point cubic f(u) = u̇², u = cos θ (issue 11) ---------------------------------------------
        E("4.5.sleeping_top_nutation", "4.5",
          "Small nutations of the sleeping top (double root of f(u) at u = 1): ω_n² = (I3/I1)² (ω3² − 4 M g l I1/I3²), "
          "real iff the text's bound holds.",
          (I3 / I1) ** 2 * (omega3**2 - 4 * M * g * l * I1 / I3**2),
          "top.sleeping_top_nutation_frequency() = −½ f″(1) of top.turning_point_cubic()",
          _call("eulersym.top:sleeping_top_nutation_frequency")),
        E("ex4.3.double_root", "Example 4.3",
          "Steady precession is a double root of the turning-point cubic: f′(cos θ) = 0 is the quadratic "
          "I1 cos θ φ̇² − I3 ω3 φ̇ + M g l = 0.",
          _Eq(I1 * _c(theta) * _phid**2 - I3 * omega3 * _phid + M * g * l, 0),
          "top.steady_precession_double_root() (f(cos θ) = f′(cos θ) = 0 at θ̇ = 0)",
          _call("eulersym.top:steady_precession_double_root"), up_to_factor=True),
    ]


#: id → :class:`ClosedForm`, in the text's order.
CLOSED_FORMS: dict[str, ClosedForm] = {e.id: e for e in _entries()}


# ----------------------------------------------------------------------------------------------------------------
# Checking


@dataclass(frozen=True)
class CheckResult:
    """The outcome of checking one closed form.

    ``status`` is ``"equal"`` (exact proof and numeric agreement), ``"numeric"`` (numeric agreement only, no
    exact proof found), ``"differs"``, ``"pending"`` (the derivation is not available) or ``"error"`` (the derivation
    raised). ``exact`` is True when the difference was simplified exactly to zero.
    """

    id: str
    section: str
    status: str
    how: str
    seconds: float
    exact: bool | None = None
    derived: Any = None
    comparison: Any = None

    @property
    def ok(self) -> bool:
        return self.status == "equal"


def check(id: str, *, points: int = 5, dps: int = 30, seed: int = 0) -> CheckResult:
    """Derive the quantity behind one closed form and compare it with the text.

    Parameters
    ----------
    id : str
        A key of :data:`CLOSED_FORMS`.
    points, dps, seed
        The numeric test (see :func:`eulersym.compare.compare`).

    Returns
    -------
    CheckResult

    Examples
    --------
    >>> check("4.1.proper").status
    'equal'
    """
    from eulersym.compare import compare

    if id not in CLOSED_FORMS:
        raise InvalidInput("id", id, "an id of eulersym.text.CLOSED_FORMS (see `eulersym check --list`)")
    entry = CLOSED_FORMS[id]
    start = time.perf_counter()
    try:
        derived = entry.derived()
    except DerivationMissing as exc:
        return CheckResult(id, entry.section, "pending", f"derivation not available: {exc}",
                           time.perf_counter() - start)
    except Exception as exc:  # a derivation that raises is a failure of the check, reported, not hidden
        return CheckResult(id, entry.section, "error", f"{type(exc).__name__}: {exc}", time.perf_counter() - start)
    try:
        result = compare(entry.expression, derived, points=points, dps=dps, seed=seed,
                         up_to_factor=entry.up_to_factor)
    except InvalidInput as exc:
        return CheckResult(id, entry.section, "differs", f"not comparable: {exc}", time.perf_counter() - start,
                           derived=derived)
    status = "differs" if not result.equal else ("equal" if result.exact else "numeric")
    return CheckResult(id, entry.section, status, result.method, time.perf_counter() - start, exact=result.exact,
                       derived=derived, comparison=result)


def check_all(section: str | None = None, **kwargs) -> list[CheckResult]:
    """Check every closed form (of one section, if given), in the text's order.

    Examples
    --------
    >>> all(r.ok for r in check_all("4.1"))
    True
    """
    if section is not None and section not in SECTIONS:
        raise InvalidInput("section", section, "one of " + ", ".join(repr(s) for s in SECTIONS))
    return [check(i, **kwargs) for i, e in CLOSED_FORMS.items() if section is None or e.section == section]


def _format(obj, latex: bool) -> str:
    if latex:
        if isinstance(obj, (list, tuple)):
            return r",\quad ".join(sp.latex(o) for o in obj)
        return sp.latex(obj)
    if isinstance(obj, (list, tuple)):
        return "; ".join(_format(o, False) for o in obj)
    return sp.sstr(obj) if not isinstance(obj, sp.MatrixBase) else sp.sstr(obj.tolist())


def report(section: str, *, latex: bool = False, file=None) -> list[CheckResult]:
    """Print each closed form of ``section`` beside its derivation, and the verdict; return the results.

    Examples
    --------
    >>> results = report("4.1")  # doctest: +ELLIPSIS
    §4.1
    ...
    """
    file = file or sys.stdout
    results = check_all(section)
    title = section if section.startswith("Example") else f"§{section}"
    print(title, file=file)
    for res in results:
        entry = CLOSED_FORMS[res.id]
        print(f"\n[{res.id}] {entry.statement}", file=file)
        print(f"  text:    {_format(entry.expression, latex)}", file=file)
        if res.derived is not None:
            print(f"  derived: {_format(res.derived, latex)}   <- {entry.derivation}", file=file)
        print(f"  verdict: {res.status.upper()} — {res.how}", file=file)
    return results


def derivation_printer(description: str, argv: list[str] | None = None):
    """Options and a printer for the literate scripts in ``derivations/``.

    Parses ``--latex`` from ``argv`` and returns ``(args, show)`` where ``show(label, expr)`` prints one derived
    result, as plain text or LaTeX.

    Examples
    --------
    >>> args, show = derivation_printer("demo", ["--latex"])
    >>> show("D(φ)[0, 0]", sp.cos(phi))
    D(φ)[0, 0]:
        \\cos{\\left(\\phi{\\left(t \\right)} \\right)}
    """
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--latex", action="store_true", help="print results as LaTeX")
    args = parser.parse_args(argv)

    def show(label: str, expr) -> None:
        print(f"{label}:\n    {_format(expr, args.latex)}")

    return args, show


def cli(argv: list[str]) -> int:
    """``eulersym check [--section S] [--list] [--strict]``: prove the text; exit 1 if any entry fails."""
    parser = argparse.ArgumentParser(prog="eulersym check", description="Derive every closed form of the text "
                                     "and prove it equal (exact simplification + 30-digit random points).")
    parser.add_argument("--section", choices=SECTIONS, help="only this section")
    parser.add_argument("--id", action="append", help="only this entry (repeatable)")
    parser.add_argument("--list", action="store_true", help="list the entries and exit")
    parser.add_argument("--strict", action="store_true", help="treat pending and numeric-only entries as failures")
    args = parser.parse_args(argv)
    if args.list:
        for e in CLOSED_FORMS.values():
            print(f"{e.id:<32} {e.section:<12} {e.statement}")
        return 0
    start = time.perf_counter()
    ids = args.id or [i for i, e in CLOSED_FORMS.items() if args.section in (None, e.section)]
    width = max(len(i) for i in ids)
    print(f"{'id':<{width}}  {'section':<11}  {'status':<7}  {'seconds':>7}  how shown")
    results = []
    for i in ids:
        res = check(i)
        results.append(res)
        print(f"{res.id:<{width}}  {res.section:<11}  {res.status:<7}  {res.seconds:7.3f}  {res.how}", flush=True)
    counts = {s: sum(r.status == s for r in results) for s in ("equal", "numeric", "differs", "pending", "error")}
    total = time.perf_counter() - start
    print(f"\n{counts['equal']} equal, {counts['numeric']} numeric only, {counts['differs']} differ, {counts['pending']} pending, "
          f"{counts['error']} errors — {len(results)} closed forms in {total:.2f} s")
    failed = counts["differs"] + counts["error"] + (counts["pending"] + counts["numeric"] if args.strict else 0)
    return 1 if failed else 0
