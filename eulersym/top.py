"""The heavy symmetric top with a fixed pivot (§4.5.2–4.5.3, Example 4.3), derived from its Lagrangian.

Model: principal moments about the pivot ``diag(I1, I1, I3)``, mass ``M``, centre of mass a distance ``l`` up the
symmetry axis, gravity ``g``; Euler angles ``φ, θ, ψ`` of the text's zxz convention (``r_body = A r_space``,
``A = B(ψ) C(θ) D(φ)``), so θ is the tilt of the symmetry axis from the upward vertical.

Nothing is typed in: ``T = ½ ωᵀ I ω`` with ω from :func:`eulersym.kinematics.omega_body`, ``V = M g l cos θ``
(height of the centre of mass ``l cos θ``), ``L = T − V``; everything else follows from ``L``.

Symbols (module constants): :data:`P_PHI`, :data:`P_PSI` (the conserved momenta), :data:`ENERGY` (the energy
``E``) and :data:`U` (``u = cos θ``). ``omega3`` of :mod:`eulersym.symbols` stands for the conserved spin
``ω3 = φ̇ cos θ + ψ̇`` where the text uses it.

Examples
--------
>>> from eulersym.compare import compare
>>> from eulersym.symbols import I1, I3, M, g, l, phi, theta, psi, t
>>> phid, thd, psid = (q.diff(t) for q in (phi, theta, psi))
>>> text = (I1*(thd**2 + phid**2*sp.sin(theta)**2)/2 + I3*(phid*sp.cos(theta) + psid)**2/2
...         - M*g*l*sp.cos(theta))                                             # §4.5.2
>>> compare(lagrangian(), text).exact
True
"""

from __future__ import annotations

import functools
import math
import numbers

from eulersym._numpy import np
import sympy as sp

from eulersym.errors import CheckFailed, InvalidInput, SingularConfiguration
from eulersym.inertia import kinetic_energy as _kinetic_energy
from eulersym.kinematics import _reduce_sin_squares, omega_body
from eulersym.symbols import E, I1, I3, M, g, l, omega3, p_phi, p_psi, phi, psi, t, theta, u
from eulersym.validation import is_symbolic, moments, positive

__all__ = [
    "P_PHI",
    "P_PSI",
    "ENERGY",
    "U",
    "lagrangian",
    "equations_of_motion",
    "cyclic_coordinates",
    "conserved_momenta",
    "energy",
    "effective_potential",
    "turning_point_cubic",
    "turning_points",
    "nutation_period",
    "nutation_equation",
    "steady_precession_condition",
    "steady_precession_rates",
    "precession_limits",
    "sleeping_top_threshold",
    "sleeping_top_nutation_frequency",
    "steady_precession_double_root",
]

#: Conserved momenta conjugate to φ and ψ (:mod:`eulersym.symbols`).
P_PHI = p_phi
P_PSI = p_psi
#: The (conserved) total energy E = T + V (:data:`eulersym.symbols.E`, the torque-free body's too).
ENERGY = E
#: u = cos θ.
U = u

_Q = (phi, theta, psi)
_QDOT = tuple(q.diff(t) for q in _Q)
_PARAMETERS = (I1, I3, M, g, l)
_THETA = theta
_OMEGA3 = omega3


@functools.lru_cache(maxsize=1)
def lagrangian() -> sp.Expr:
    """``L = T − V`` of the heavy symmetric top, derived from ω(Euler rates) and the principal inertia.

    ``T = ½ ωᵀ diag(I1, I1, I3) ω`` with ``ω =`` :func:`eulersym.kinematics.omega_body` (zxz); ψ drops out
    (``sin²ψ + cos²ψ = 1``) because ``I2 = I1``. ``V = M g l cos θ``.

    Returns
    -------
    sympy.Expr in ``phi, theta, psi`` (functions of t) and their first derivatives.

    Examples
    --------
    >>> lagrangian()
    I1*sin(theta(t))**2*Derivative(phi(t), t)**2/2 + I1*Derivative(theta(t), t)**2/2 + I3*cos(theta(t))**2*Derivative(phi(t), t)**2/2 + I3*cos(theta(t))*Derivative(phi(t), t)*Derivative(psi(t), t) + I3*Derivative(psi(t), t)**2/2 - M*g*l*cos(theta(t))
    """
    T = _kinetic_energy((I1, I1, I3), omega_body("zxz"))
    T = _reduce_sin_squares(T, (psi,))
    if sp.expand(sp.diff(T, psi)) != 0:
        raise CheckFailed(f"the kinetic energy of a symmetric top should not depend on psi: {T}")
    V = M * g * l * sp.cos(theta)
    return T - V


@functools.lru_cache(maxsize=3)
def _euler_lagrange(k: int) -> sp.Eq:
    """The Euler–Lagrange equation of coordinate ``_Q[k]`` alone (the θ equation needs no other)."""
    q, qd = _Q[k], _QDOT[k]
    return sp.Eq(sp.expand(_partial(qd).diff(t) - _partial(q)), 0, evaluate=False)


@functools.lru_cache(maxsize=6)
def _partial(var) -> sp.Expr:
    """``∂L/∂var`` for ``var`` a coordinate ``q(t)`` or a rate ``q̇(t)``, the two independent as the Lagrangian
    calculus takes them: L with q and q̇ frozen into plain symbols, differentiated, thawed (what ``sp.diff(L, var)``
    does, without its substitution of a function by a dummy on every call)."""
    frozen, mapping = _frozen_lagrangian()
    if var not in mapping:  # L does not hold it at all
        return sp.Integer(0)
    return sp.diff(frozen, mapping[var]).xreplace({v: k for k, v in mapping.items()})


@functools.lru_cache(maxsize=1)
def _frozen_lagrangian() -> tuple:
    from eulersym.compare import freeze_functions

    return freeze_functions(lagrangian())


def _equations() -> tuple:
    return tuple(_euler_lagrange(k) for k in range(3))


def equations_of_motion() -> list:
    """The Euler–Lagrange equations ``d/dt ∂L/∂q̇ − ∂L/∂q = 0`` for ``q = φ, θ, ψ`` (in this order).

    Returns
    -------
    list of 3 sympy.Eq (``Eq(expression, 0)``), expanded.

    Examples
    --------
    >>> eqs = equations_of_motion()
    >>> [e.lhs.has(q.diff(t, 2)) for e, q in zip(eqs, (phi, theta, psi))]
    [True, True, True]
    >>> eqs[2]
    Eq(-I3*sin(theta(t))*Derivative(phi(t), t)*Derivative(theta(t), t) + I3*cos(theta(t))*Derivative(phi(t), (t, 2)) + I3*Derivative(psi(t), (t, 2)), 0)
    """
    return list(_equations())


@functools.lru_cache(maxsize=1)
def cyclic_coordinates() -> tuple:
    """The coordinates on which the Lagrangian does not depend (``∂L/∂q = 0``), found, not listed.

    Examples
    --------
    >>> cyclic_coordinates()
    (phi(t), psi(t))
    """
    return tuple(q for q in _Q if sp.expand(_partial(q)) == 0)


@functools.lru_cache(maxsize=1)
def conserved_momenta() -> tuple:
    """``(p_φ, p_ψ) = (∂L/∂φ̇, ∂L/∂ψ̇)``, conserved because φ and ψ are cyclic.

    Returns
    -------
    tuple of sympy.Expr, one per cyclic coordinate (φ then ψ).

    Examples
    --------
    >>> p_phi, p_psi = conserved_momenta()
    >>> sp.factor(p_psi)
    I3*(cos(theta(t))*Derivative(phi(t), t) + Derivative(psi(t), t))
    """
    return tuple(sp.expand(_partial(q.diff(t))) for q in cyclic_coordinates())


@functools.lru_cache(maxsize=1)
def energy() -> sp.Expr:
    """The energy (Jacobi integral) ``E = Σ q̇ ∂L/∂q̇ − L``; here ``T + V`` since T is quadratic in the rates.

    Examples
    --------
    >>> from eulersym.compare import compare
    >>> T_plus_V = lagrangian() + 2*M*g*l*sp.cos(theta)
    >>> compare(energy(), T_plus_V).exact
    True
    """
    return sp.expand(sum(qd * _partial(qd) for qd in _QDOT) - lagrangian())


@functools.lru_cache(maxsize=1)
def _rates_from_momenta() -> dict:
    """φ̇ and ψ̇ in terms of p_φ, p_ψ and θ (the momentum definitions solved; linear)."""
    p_phi, p_psi = conserved_momenta()
    phid, psid = phi.diff(t), psi.diff(t)
    A, b = sp.linear_eq_to_matrix([p_phi - P_PHI, p_psi - P_PSI], [phid, psid])
    det = sp.expand(A.det(method="berkowitz"))  # I1 I3 sin²θ: expansion cancels the cos² terms
    solution = (A.adjugate() * b).applyfunc(sp.expand) / det  # Cramer's rule
    return {phid: sp.factor_terms(solution[0]), psid: sp.factor_terms(solution[1])}


@functools.lru_cache(maxsize=1)
def effective_potential() -> sp.Expr:
    """The effective potential of the nutation: ``E = ½ I1 θ̇² + V_eff(θ)``.

    Derived by solving the definitions of :data:`P_PHI`, :data:`P_PSI` for φ̇, ψ̇ and substituting in
    :func:`energy`; ``V_eff`` is everything but the ``½ I1 θ̇²`` term. Its form:
    ``V_eff(θ) = (p_φ − p_ψ cos θ)²/(2 I1 sin² θ) + p_ψ²/(2 I3) + M g l cos θ`` (the constant ``p_ψ²/(2 I3)``
    included; Goldstein's ``E'`` subtracts it).

    Examples
    --------
    >>> from eulersym.compare import compare
    >>> c = sp.cos(theta)
    >>> form = (P_PHI - P_PSI*c)**2/(2*I1*sp.sin(theta)**2) + P_PSI**2/(2*I3) + M*g*l*c
    >>> compare(effective_potential(), form).exact
    True
    """
    E = energy().xreplace(_rates_from_momenta())
    thd = theta.diff(t)
    E = sp.expand(E)
    kinetic = E.coeff(thd, 2) * thd**2
    if sp.expand(kinetic - I1 * thd**2 / 2) != 0:
        raise CheckFailed(f"the θ̇ term of the energy is not ½ I1 θ̇²: {kinetic}")
    rest = sp.expand(E - kinetic)  # E is expanded: the θ̇² terms cancel as they are added
    if rest.has(thd):
        raise CheckFailed("the effective potential depends on θ̇")
    groups: dict = {}  # group the terms by their power of sin θ, and factor each group (display only)
    for term in sp.Add.make_args(rest):
        groups.setdefault(term.as_coeff_exponent(sp.sin(theta))[1], []).append(term)
    return sp.Add(*(sp.factor(sp.Add(*terms)) if power != 0 else sp.Add(*terms) for power, terms in groups.items()))


@functools.lru_cache(maxsize=1)
def turning_point_cubic() -> sp.Expr:
    """``f(u) = u̇²`` with ``u = cos θ``: the cubic whose roots in [−1, 1] are the turning points ``cos θ1,2``.

    Derived from ``E = ½ I1 θ̇² + V_eff(θ)`` and ``u̇ = −sin θ θ̇``: ``u̇² = (1 − u²) · 2 (E − V_eff)/I1``, which is
    polynomial (cubic) in u. In terms of the energy ``E`` (:data:`ENERGY`) and the momenta
    (:data:`P_PHI`, :data:`P_PSI`):
    ``f(u) = (1 − u²)(2E/I1 − p_ψ²/(I1 I3) − 2 M g l u/I1) − (p_φ − p_ψ u)²/I1²``, i.e. Goldstein's
    ``(1 − u²)(α − β u) − (b − a u)²`` with ``α = (2E − p_ψ²/I3)/I1``, ``β = 2 M g l/I1``, ``a = p_ψ/I1``,
    ``b = p_φ/I1``.

    Returns
    -------
    sympy.Expr, a polynomial of degree 3 in :data:`U` with leading coefficient ``β = 2 M g l/I1 > 0``.

    Examples
    --------
    >>> sp.Poly(turning_point_cubic(), U).degree()
    3
    >>> sp.Poly(turning_point_cubic(), U).LC()
    2*M*g*l/I1
    """
    V = effective_potential()
    udot2 = sp.expand(sp.sin(theta) ** 2 * 2 * (ENERGY - V) / I1)
    udot2 = _reduce_sin_squares(udot2, (theta,)).xreplace({sp.cos(theta): U})
    f = udot2 if udot2.is_polynomial(U) else sp.expand(sp.cancel(udot2))  # sin²θ cancels as it stands
    if f.has(theta) or not f.is_polynomial(U) or max(term.as_powers_dict().get(U, 0)
                                                     for term in sp.Add.make_args(f)) != 3:
        raise CheckFailed(f"u̇² is not a cubic in u: {f}")
    return f


@functools.lru_cache(maxsize=1)
def _cubic_coefficients():
    coefficients = sp.Poly(turning_point_cubic(), U).all_coeffs()
    return sp.lambdify((ENERGY, P_PHI, P_PSI, *_PARAMETERS), coefficients, modules="math")


def _top_numbers(E, p_phi, p_psi, I1_, I3_, M_, g_, l_) -> tuple:
    for name, value in (("E", E), ("p_phi", p_phi), ("p_psi", p_psi)):
        if isinstance(value, bool) or not isinstance(value, numbers.Real) \
                or not math.isfinite(float(value)):
            raise InvalidInput(name, value, "a finite real number")
    moments("I", (I1_, I1_, I3_))
    for name, value in (("I1", I1_), ("I3", I3_), ("M", M_), ("g", g_), ("l", l_)):
        positive(name, value)
        if is_symbolic(value):
            raise InvalidInput(name, value, "a number (use turning_point_cubic() for symbolic work)")
    return tuple(float(v) for v in (E, p_phi, p_psi, I1_, I3_, M_, g_, l_))


def _cubic_value(c, u) -> float:
    return float(((c[0] * u + c[1]) * u + c[2]) * u + c[3])


def _noise(c, u) -> float:
    """A bound on the rounding error of evaluating the cubic at u (and of its coefficients)."""
    au = abs(u)
    return 16 * np.finfo(float).eps * float(((abs(c[0]) * au + abs(c[1])) * au + abs(c[2])) * au + abs(c[3]))


def _stable_quadratic(A, B, C) -> list:
    """Real roots of A x² + B x + C (A ≠ 0) without cancellation; a double root once."""
    disc = B * B - 4 * A * C
    if disc < 0:
        return []
    q = -0.5 * (B + math.copysign(math.sqrt(disc), B))
    if q == 0:
        return [0.0]
    return sorted({q / A, C / q})


def _bisect_root(c, lo, hi, flo) -> float:
    """The root of the cubic in [lo, hi] where it changes sign (``flo``: its sign at lo, exact at a pole):
    bisection to the last bit (monotone segment)."""
    for _ in range(2000):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        fm = _cubic_value(c, mid)
        if fm == 0:
            return mid
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return lo if abs(_cubic_value(c, lo)) <= abs(_cubic_value(c, hi)) else hi


def _turning_roots(values, c):
    """The roots of the cubic on [−1, 1] that bound the motion, exact at double roots.

    The cubic is monotone between its critical points (roots of f′, a quadratic), so each simple root is found by
    bisection to the last bit; at a critical point where |f| is below the rounding noise the root is double and is
    returned as the critical point itself (to round-off), not by a solver that loses half the digits. A pole
    ``u = ±1`` is a root exactly when ``p_φ = ±p_ψ`` (``f(±1) = −(p_φ ∓ p_ψ)²/I1²``).
    """
    E, p_phi, p_psi, I1_ = values[:4]
    crit = [u for u in _stable_quadratic(3 * c[0], 2 * c[1], c[2]) if -1.0 < u < 1.0]
    knots = [-1.0, *crit, 1.0]
    fvals = [_cubic_value(c, u) for u in knots]
    # at the poles the value is known exactly, f(±1) = −(p_φ ∓ p_ψ)²/I1² ≤ 0 (the polynomial's rounding is not)
    fvals[0] = -(((p_phi + p_psi) / I1_) ** 2)
    fvals[-1] = -(((p_phi - p_psi) / I1_) ** 2)
    roots = []  # (u, double?)
    for k, (u, fu) in enumerate(zip(knots, fvals)):
        is_crit = 0 < k < len(knots) - 1
        if fu == 0.0 or (is_crit and abs(fu) <= _noise(c, u)):
            roots.append((u, is_crit or _double_at_pole(c, u)))
            fvals[k] = 0.0
    for a, b, fa, fb in zip(knots, knots[1:], fvals, fvals[1:]):
        if fa != 0.0 and fb != 0.0 and (fa > 0) != (fb > 0):
            roots.append((_bisect_root(c, a, b, fa), False))
    roots.sort()
    return roots, knots, fvals


def _double_at_pole(c, u) -> bool:
    """Whether the root at the pole u = ±1 is double: f′(u) within its rounding noise of zero."""
    d = (3 * c[0] * u + 2 * c[1]) * u + c[2]
    noise = 16 * np.finfo(float).eps * (3 * abs(c[0]) + 2 * abs(c[1]) + abs(c[2]))
    return abs(d) <= noise


def _roots(values) -> tuple:
    """(coefficients, the turning roots on [−1, 1] with their multiplicity flags, the third root)."""
    coefficients = np.array(_cubic_coefficients()(*values), dtype=float)
    roots, _, _ = _turning_roots(values, coefficients)
    return coefficients, roots


def turning_points(E, p_phi, p_psi, I1, I3, M, g, l) -> tuple:
    """The turning points of the nutation: the roots ``u1 ≤ u2`` of :func:`turning_point_cubic` in [−1, 1].

    The nutation angle oscillates between ``θ1 = arccos u2`` and ``θ2 = arccos u1``; ``f(u) ≥ 0`` between the
    roots. (``f(±1) = −(p_φ ∓ p_ψ)²/I1² ≤ 0`` and ``f → +∞`` as ``u → ∞``, so the third root is ≥ 1.) A double root
    (steady precession, the sleeping top) is returned as ``(u, u)`` to round-off: the roots are bracketed by the
    critical points of the cubic and a pole ``u = ±1`` is a root exactly when ``p_φ = ±p_ψ``, so no digits are lost
    to a generic cubic solver.

    Parameters
    ----------
    E, p_phi, p_psi : float
        Energy and the two conserved momenta (see :func:`conserved_momenta`).
    I1, I3, M, g, l : float
        Positive; moments about the pivot.

    Returns
    -------
    (u1, u2) : tuple of float, ``-1 <= u1 <= u2 <= 1``.

    Raises
    ------
    eulersym.errors.InvalidInput
        Bad parameters, or no motion is possible (no interval of [−1, 1] with ``f ≥ 0``).

    Examples
    --------
    A top released at rest in ``θ̇`` at θ = 60° (u = 0.5), spinning fast:

    >>> I1_, I3_, M_, g_, l_ = 1.0, 0.5, 1.0, 9.81, 0.1
    >>> u0, w3, phid = 0.5, 40.0, 0.0
    >>> p_psi = I3_*w3; p_phi = p_psi*u0 + I1_*(1 - u0**2)*phid
    >>> E = p_psi**2/(2*I3_) + M_*g_*l_*u0
    >>> u1, u2 = turning_points(E, p_phi, p_psi, I1_, I3_, M_, g_, l_)
    >>> round(u2, 12), round(u1, 6)
    (0.5, 0.496303)

    The stable sleeping top: a double root at u = 1, exactly.

    >>> p = I3_ * w3
    >>> turning_points(p**2/(2*I3_) + M_*g_*l_, p, p, I1_, I3_, M_, g_, l_)
    (1.0, 1.0)
    """
    values = _top_numbers(E, p_phi, p_psi, I1, I3, M, g, l)
    coefficients, roots = _roots(values)

    def f(u):
        return _cubic_value(coefficients, u)

    for (a, da), (b, db) in zip(roots, roots[1:]):
        if b > a and f(0.5 * (a + b)) > 0:
            return (float(a), float(b))
    doubles = [u for u, dbl in roots if dbl]
    if doubles:
        poles = [u for u in doubles if abs(u) == 1.0]  # a pole that is a root is exact; prefer it
        u = poles[0] if poles else min(doubles, key=lambda v: abs(f(v)))
        return (float(u), float(u))
    raise InvalidInput(
        "E", E, "an energy at or above the minimum of the effective potential for these momenta "
        "(f(u) = u̇² is negative everywhere on [-1, 1]: no motion is possible)"
    )


def nutation_period(E, p_phi, p_psi, I1, I3, M, g, l) -> float:
    """Period of the nutation ``θ1 → θ2 → θ1``: ``2 ∫_{u1}^{u2} du / sqrt(f(u))``, via the complete elliptic K.

    With ``f(u) = β (u − u1)(u − u2)(u − u3)``, ``u1 ≤ u2 ≤ u3`` (β the leading coefficient of
    :func:`turning_point_cubic`), the substitution ``u = u1 + (u2 − u1) sin² χ`` gives
    ``period = 4 K(m) / sqrt(β (u3 − u1))`` with ``m = (u2 − u1)/(u3 − u1)``. At ``u1 = u2`` (steady precession)
    it is the period of small nutations.

    Parameters
    ----------
    E, p_phi, p_psi, I1, I3, M, g, l : float
        As in :func:`turning_points`.

    Returns
    -------
    float (seconds, in the units of the inputs)

    Examples
    --------
    >>> I1_, I3_, M_, g_, l_ = 1.0, 0.5, 1.0, 9.81, 0.1
    >>> p_psi = 0.5*40.0; p_phi = p_psi*0.5
    >>> E = p_psi**2/(2*I3_) + M_*g_*l_*0.5
    >>> round(nutation_period(E, p_phi, p_psi, I1_, I3_, M_, g_, l_), 6)   # ≈ 2π I1/(I3 ω3) for a fast top
    0.314928
    """
    from scipy.special import ellipk

    values = _top_numbers(E, p_phi, p_psi, I1, I3, M, g, l)
    u1, u2 = turning_points(E, p_phi, p_psi, I1, I3, M, g, l)
    coefficients, _ = _roots(values)
    beta = coefficients[0]
    u3 = float(-coefficients[1] / beta - u1 - u2)  # the sum of the roots
    if not u3 >= u2:
        raise CheckFailed(f"the third root of the cubic ({u3}) should lie above u2 = {u2}")
    if u3 - u1 <= 0:
        raise SingularConfiguration("E", E, "a motion whose three turning-point roots are not all equal")
    m = (u2 - u1) / (u3 - u1)
    return float(4 * ellipk(m) / math.sqrt(beta * (u3 - u1)))


@functools.lru_cache(maxsize=1)
def nutation_equation() -> sp.Eq:
    """The θ equation of motion, ``I1 θ̈ = …``, with ψ̇ eliminated for the conserved spin ``ω3 = φ̇ cos θ + ψ̇``.

    From the θ Euler–Lagrange equation (:func:`equations_of_motion`) solved for ``I1 θ̈``, then
    ``ψ̇ → omega3 − φ̇ cos θ``. Example 4.3, step 1.

    Examples
    --------
    >>> nutation_equation()
    Eq(I1*Derivative(theta(t), (t, 2)), I1*sin(theta(t))*cos(theta(t))*Derivative(phi(t), t)**2 - I3*omega3(t)*sin(theta(t))*Derivative(phi(t), t) + M*g*l*sin(theta(t)))
    """
    eq = _euler_lagrange(1)
    thdd = theta.diff(t, 2)
    coefficient = sp.expand(eq.lhs).coeff(thdd)
    rest = sp.expand(eq.lhs - coefficient * thdd)
    if coefficient != I1 or rest.has(thdd):
        raise CheckFailed(f"the θ equation is not I1 θ̈ + (terms without θ̈): {eq}")
    rhs = -rest.xreplace({psi.diff(t): omega3 - phi.diff(t) * sp.cos(theta)})
    return sp.Eq(I1 * thdd, sp.expand(rhs), evaluate=False)


def _theta_value(theta_value):
    if theta_value is theta:
        return theta
    if is_symbolic(theta_value):
        value = theta_value
        if value.is_real is False:
            raise InvalidInput("theta", theta_value, "a real angle")
        if sp.sin(value).is_zero:
            raise SingularConfiguration("theta", theta_value, "sin(theta) != 0 (the steady-precession balance is "
                                        "divided by sin(theta); at theta = 0 or pi see sleeping_top_threshold)")
        return value
    if isinstance(theta_value, bool) or not isinstance(theta_value, numbers.Real) \
            or not math.isfinite(float(theta_value)):
        raise InvalidInput("theta", theta_value, "a finite real angle")
    if abs(math.sin(float(theta_value))) < 1e-12:
        raise SingularConfiguration("theta", theta_value, "sin(theta) != 0 (the steady-precession balance is "
                                    "divided by sin(theta); at theta = 0 or pi see sleeping_top_threshold)")
    return sp.Float(theta_value) if isinstance(theta_value, float) else sp.sympify(theta_value)


def steady_precession_condition(theta=theta) -> sp.Eq:
    """Steady precession (θ̇ = θ̈ = 0): the quadratic in φ̇, from :func:`nutation_equation` divided by ``sin θ``.

    Parameters
    ----------
    theta : angle, optional
        The fixed tilt (default the symbol θ(t)); ``sin θ = 0`` is refused.

    Returns
    -------
    sympy.Eq
        ``Eq(I1 cos θ φ̇² − I3 ω3 φ̇ + M g l, 0)`` (Example 4.3, step 2), with φ̇ as ``Derivative(phi(t), t)``.

    Raises
    ------
    eulersym.errors.SingularConfiguration
        ``sin θ = 0``: the division is not allowed (the vertical top is treated by
        :func:`sleeping_top_threshold`).

    Examples
    --------
    >>> steady_precession_condition()
    Eq(I1*cos(theta(t))*Derivative(phi(t), t)**2 - I3*omega3(t)*Derivative(phi(t), t) + M*g*l, 0)
    """
    value = _theta_value(theta)
    eq = nutation_equation()
    steady = {_THETA.diff(t, 2): 0, _THETA.diff(t): 0}
    balance = eq.rhs.xreplace(steady) - eq.lhs.xreplace(steady)
    quadratic = sp.expand(balance / sp.sin(_THETA))
    if quadratic.has(sp.sin(_THETA)):
        raise CheckFailed(f"the balance is not divisible by sin(theta): {balance}")
    if value is not _THETA:
        quadratic = quadratic.xreplace({_THETA: value})
    return sp.Eq(quadratic, 0, evaluate=False)


def steady_precession_rates(theta=theta) -> tuple:
    """The two exact steady-precession rates φ̇ (slow, fast): the roots of :func:`steady_precession_condition`.

    ``φ̇ = (I3 ω3 ∓ sqrt(I3² ω3² − 4 I1 M g l cos θ)) / (2 I1 cos θ)``; slow takes the minus sign (for
    ``ω3 > 0``, ``cos θ > 0``). Real only when ``I3² ω3² ≥ 4 I1 M g l cos θ``.

    Parameters
    ----------
    theta : angle, optional
        ``sin θ = 0`` is refused; ``cos θ = 0`` too (the quadratic degenerates: only ``φ̇ = M g l/(I3 ω3)``).

    Returns
    -------
    (slow, fast) : tuple of sympy.Expr in ``omega3`` (a function of t, constant on the motion).

    Examples
    --------
    >>> slow, fast = steady_precession_rates()
    >>> slow
    (I3*omega3(t) - sqrt(-4*I1*M*g*l*cos(theta(t)) + I3**2*omega3(t)**2))/(2*I1*cos(theta(t)))
    """
    value = _theta_value(theta)
    cosine = sp.cos(value)
    if value is not _THETA and (cosine.is_zero or (cosine.is_number and abs(float(cosine)) < 1e-12)):
        raise SingularConfiguration("theta", theta, "cos(theta) != 0 (at theta = pi/2 the quadratic degenerates "
                                    "to the single root M g l/(I3 omega3))")
    q = steady_precession_condition(value).lhs
    x = sp.Dummy("x")
    a, b, c = sp.Poly(q.xreplace({phi.diff(t): x}), x).all_coeffs()
    root = sp.sqrt(sp.expand(b**2 - 4 * a * c))
    return ((-b - root) / (2 * a), (-b + root) / (2 * a))


def precession_limits(theta=theta, omega3=omega3) -> tuple:
    """Leading terms (slow, fast) of the steady-precession rates for a fast top, by series in ``1/ω3``.

    ``ω3 = 1/ε`` with a positive helper ε (a fast top spins with ``ω3 > 0``); the leading term of each root of
    :func:`steady_precession_rates` as ε → 0 is mapped back (``ε → 1/ω3``): slow ``M g l/(I3 ω3)``
    (= torque/L, the gyroscopic precession), fast ``I3 ω3/(I1 cos θ)``.

    Parameters
    ----------
    theta : angle, optional
        As in :func:`steady_precession_rates`.
    omega3 : optional
        A value for the spin to put in the limits (default: keep the symbol ``omega3(t)``); zero is refused.

    Raises
    ------
    eulersym.errors.InvalidInput
        ``omega3 = 0`` (the slow limit divides by the spin).

    Examples
    --------
    >>> precession_limits()
    (M*g*l/(I3*omega3(t)), I3*omega3(t)/(I1*cos(theta(t))))
    """
    spin = omega3
    if spin is not _OMEGA3:
        if isinstance(spin, bool) or not isinstance(spin, (numbers.Real, sp.Basic)):
            raise InvalidInput("omega3", spin, "a non-zero real spin")
        if sp.sympify(spin).is_zero or (not is_symbolic(spin) and float(spin) == 0):
            raise InvalidInput("omega3", spin, "a non-zero spin (the slow precession M g l/(I3 omega3) divides by it)")
    leads = _precession_limits(_theta_value(theta))
    if spin is _OMEGA3:
        return leads
    return tuple(lead.xreplace({_OMEGA3: sp.sympify(spin)}) for lead in leads)


@functools.lru_cache(maxsize=32)
def _precession_limits(value) -> tuple:
    """The leading terms of :func:`precession_limits` for one θ (a pure derivation, cached).

    With ``ω3 = 1/ε`` (ε > 0) each rate holds ``√R`` with ``R ~ I3²/ε²``; written ``√(ε² R)/ε`` (exact for ε > 0),
    ``h(ε) = ε · rate`` is analytic at ε = 0 (``ε² R → I3² > 0``), so the rate's leading term is ``h_k ε^(k−1)`` for
    the first non-zero Taylor coefficient ``h_k = h⁽ᵏ⁾(0)/k!`` of h — the Laurent series of the rate, term by term
    until one survives.
    """
    eps = sp.Symbol("epsilon", positive=True)
    cosine = sp.cos(value)
    frozen = {} if cosine.is_number else {cosine: sp.Dummy("c", real=True)}
    thaw = {v: k for k, v in frozen.items()}
    out = []
    for rate in steady_precession_rates(value):
        expr = rate.xreplace({_OMEGA3: 1 / eps}).xreplace(frozen)
        roots = {p: sp.sqrt(sp.expand(eps**2 * p.base)) / eps
                 for p in expr.atoms(sp.Pow) if p.exp == sp.S.Half and p.base.has(eps)}
        h = sp.expand(expr.xreplace(roots) * eps)
        for k in range(_LAURENT_TERMS):
            coefficient = sp.cancel(h.diff(eps, k).xreplace({eps: 0}) / math.factorial(k))
            if coefficient.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
                raise CheckFailed(f"ε·rate is not analytic at ε = 0: {h}")
            if coefficient != 0:
                break
        else:
            raise CheckFailed(f"no non-zero term of ε·rate up to order {_LAURENT_TERMS - 1}: {h}")
        out.append(sp.factor(coefficient * eps ** (k - 1)).xreplace(thaw).xreplace({eps: 1 / _OMEGA3}))
    return tuple(out)


#: How many Taylor coefficients of ε·rate :func:`_precession_limits` tries (the slow rate needs three: 0, 0, M g l/I3).
_LAURENT_TERMS = 6


@functools.lru_cache(maxsize=1)
def _upright_cubic() -> tuple:
    """(w, f): the cubic of the top spinning upright with spin w (θ = 0, θ̇ = 0, φ̇ + ψ̇ = w); u = 1 is a double root."""
    w = sp.Symbol("w", positive=True)  # the spin about the vertical: φ̇ + ψ̇ at θ = 0
    rest = {theta.diff(t): 0, psi.diff(t): w - phi.diff(t)}
    p_phi, p_psi = (sp.expand(p.xreplace(rest).xreplace({theta: 0})) for p in conserved_momenta())
    e_upright = sp.expand(energy().xreplace(rest).xreplace({theta: 0}))
    upright = {P_PHI: p_phi, P_PSI: p_psi, ENERGY: e_upright}
    f = sp.expand(turning_point_cubic().xreplace(upright))
    if sp.expand(f.xreplace({U: 1})) != 0 or sp.expand(sp.diff(f, U).xreplace({U: 1})) != 0:
        raise CheckFailed(f"u = 1 is not a double root for the upright top: {f}")
    return w, f


@functools.lru_cache(maxsize=1)
def sleeping_top_nutation_frequency() -> sp.Expr:
    """The squared angular frequency of small nutations of the sleeping top, from the double root of f at u = 1.

    Near a double root ``u_d`` of :func:`turning_point_cubic` a slightly disturbed top has
    ``ü = ½ f′(u) ≈ ½ f″(u_d) (u − u_d)``, so ``u`` oscillates at ``ω_n² = −½ f″(u_d)``. For the upright top
    (``p_φ = p_ψ = I3 ω3``, ``E = I3 ω3²/2 + M g l``; see :func:`sleeping_top_threshold`):
    ``ω_n² = (I3² ω3² − 4 I1 M g l)/I1²``, positive exactly above the threshold; it is also the limit of
    :func:`nutation_period` (``2π/ω_n``) as the top goes to sleep.

    Returns
    -------
    sympy.Expr in ``omega3`` (the spin, a function of t, constant on the motion).

    Examples
    --------
    >>> sp.factor(sleeping_top_nutation_frequency())
    -(4*I1*M*g*l - I3**2*omega3(t)**2)/I1**2
    """
    w, f = _upright_cubic()
    return sp.expand(-sp.diff(f, U, 2).xreplace({U: 1}) / 2).xreplace({w: _OMEGA3})


@functools.lru_cache(maxsize=1)
def steady_precession_double_root() -> sp.Eq:
    """Steady precession as a double root of the cubic: ``f(cos θ) = f′(cos θ) = 0`` at θ̇ = 0.

    With θ̇ = 0, precession rate φ̇ and spin ``ω3 = φ̇ cos θ + ψ̇``, :func:`conserved_momenta` and :func:`energy`
    give ``p_φ, p_ψ, E``; then ``f(cos θ) = 0`` identically (θ̇ = 0 is a turning point) and the motion stays at
    ``θ`` iff the root is double, ``f′(cos θ) = 0``. Divided by the non-zero ``−2 sin²θ/I1`` this is the
    steady-precession quadratic in φ̇ — found here from the turning-point cubic, independently of
    :func:`steady_precession_condition`, which balances the θ equation of motion.

    Returns
    -------
    sympy.Eq ``Eq(expression, 0)`` with φ̇ as ``Derivative(phi(t), t)``.

    Examples
    --------
    >>> steady_precession_double_root()
    Eq(I1*cos(theta(t))*Derivative(phi(t), t)**2 - I3*omega3(t)*Derivative(phi(t), t) + M*g*l, 0)
    """
    phid = phi.diff(t)
    rest = {theta.diff(t): 0, psi.diff(t): _OMEGA3 - phid * sp.cos(theta)}
    p_phi, p_psi = (sp.expand(p.xreplace(rest)) for p in conserved_momenta())
    e_steady = sp.expand(energy().xreplace(rest))
    f = turning_point_cubic().xreplace({P_PHI: p_phi, P_PSI: p_psi, ENERGY: e_steady})
    at = {U: sp.cos(theta)}
    value = _reduce_sin_squares(f.xreplace(at), (theta,))
    if sp.simplify(value) != 0:
        raise CheckFailed(f"θ̇ = 0 is not a root of the cubic: f(cos θ) = {value}")
    slope = _reduce_sin_squares(sp.diff(f, U).xreplace(at), (theta,))
    reduced = sp.expand(sp.cancel(slope / (-2 * (1 - sp.cos(theta) ** 2) / I1)))
    if reduced.has(sp.sin(theta)) or sp.Poly(reduced, phid).degree() != 2:
        raise CheckFailed(f"f′(cos θ) is not sin²θ times a quadratic in φ̇: {slope}")
    return sp.Eq(reduced, 0, evaluate=False)


@functools.lru_cache(maxsize=1)
def sleeping_top_threshold() -> sp.Expr:
    """The bound on ω3² above which the vertical ("sleeping") top is stable, derived from a double root of f(u).

    For the top spinning upright (θ = 0, θ̇ = 0, φ̇ + ψ̇ = ω3), :func:`conserved_momenta` and :func:`energy` give
    ``p_φ = p_ψ = I3 ω3`` and ``E = I3 ω3²/2 + M g l``. Then
    ``u = 1`` is a double root of :func:`turning_point_cubic`, ``f(u) = (1 − u)² · β (u − u3)``, with the third root
    ``u3 = I3² ω3²/(2 I1 M g l) − 1``. Stable iff the motion cannot leave ``u = 1``, i.e. ``u3 ≥ 1``:
    ``ω3² ≥ 4 M g l I1/I3²``.

    At equality ``u3 = 1`` is a triple root: ``f(u) = −β (1 − u)³ ≤ 0``, so the exactly upright top still cannot
    move, but the linearised nutation frequency vanishes (marginal stability); the text counts it as stable
    (``≥``). Any loss of spin below the bound makes ``u3 < 1`` and the top starts to wobble (it "wakes").

    Returns
    -------
    sympy.Expr: ``4 M g l I1/I3²``.

    Examples
    --------
    >>> sleeping_top_threshold()
    4*I1*M*g*l/I3**2
    """
    w, f = _upright_cubic()
    rest, remainder = sp.div(sp.Poly(f, U), sp.Poly((1 - U) ** 2, U))  # f/(1 − u)²: linear in u, its root is u3
    if not remainder.is_zero:
        raise CheckFailed(f"(1 − u)² does not divide the upright cubic {f}")
    if rest.degree() != 1:
        raise CheckFailed(f"unexpected third root(s) of {rest.as_expr()}")
    c1, c0 = rest.all_coeffs()
    u3 = sp.cancel(-c0 / c1)
    W = sp.Dummy("W", positive=True)  # ω3² (u3 holds ω3 only squared): u3 = 1 is linear in it
    condition = sp.numer(sp.together(u3 - 1)).subs(w**2, W)
    if condition.has(w) or sp.Poly(condition, W).degree() != 1:
        raise CheckFailed(f"unexpected threshold condition {condition}")
    k1, k0 = sp.Poly(condition, W).all_coeffs()
    return sp.factor(-k0 / k1)
