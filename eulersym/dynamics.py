"""Euler's equations of motion (§4.4), torque-free motion and the Poinsot construction (§4.5.1), and the stability
of steady rotation about a principal axis (Example 4.2, the tennis-racket theorem).

Everything here is derived from two definitions:

* the **rotating-frame relation** ``(dG/dt)_space = (dG/dt)_body + ω × G`` for a vector ``G`` given by its body
  components (:func:`rotating_frame_derivative`);
* **Newton's law for the angular momentum** ``(dL/dt)_space = N`` with ``L = I·ω`` in body components.

Conventions: ``ω = (omega1, omega2, omega3)`` and ``N = (N1, N2, N3)`` are body components (functions of ``t``
and symbols of :mod:`eulersym.symbols`); ``I`` is either three principal moments ``(I1, I2, I3)`` or a symmetric
3×3 tensor in body axes. The heavy body about a fixed pivot uses ``Γ = A ẑ``, the body components of the *upward*
vertical (``r_body = A r_space``), and ``χ``, the body components of the vector from the pivot to the centre of mass.

The Jacobi elliptic functions of the exact torque-free solution are modelled as the SymPy functions :class:`sn`,
:class:`cn`, :class:`dn` of ``(u, m)`` (parameter ``m = k²``) that know only their derivative rules
``sn' = cn dn``, ``cn' = −sn dn``, ``dn' = −m sn cn``, their values at ``u = 0``, ``m = 0`` and ``m = 1``, and
how to evaluate numerically (mpmath). The fast numeric version is ``eulersym.numerics.free_rigid_body_exact``.

Examples
--------
>>> from eulersym.symbols import I1, I2, I3, N1, omega1, omega2, omega3, t
>>> eq1 = euler_equations()[0]
>>> eq1
Eq(I1*Derivative(omega1(t), t) - I2*omega2(t)*omega3(t) + I3*omega2(t)*omega3(t), N1)
>>> from eulersym.compare import compare
>>> text_form = I1*omega1.diff(t) - (I2 - I3)*omega2*omega3 - N1      # §4.4, first equation
>>> compare(eq1.lhs - eq1.rhs, text_form).exact
True
"""

from __future__ import annotations

import functools
import math
import numbers
from dataclasses import dataclass

from eulersym._numpy import np
import sympy as sp

from eulersym import inertia as _inertia
from eulersym.errors import CheckFailed, InvalidInput
from eulersym.symbols import (
    Gamma1,
    Gamma2,
    Gamma3,
    I1,
    I2,
    I3,
    M,
    N1,
    N2,
    N3,
    eta1,
    eta2,
    eta3,
    g,
    l,
    omega0,
    omega1,
    omega2,
    omega3,
    t,
)
from eulersym.validation import is_symbolic, moments, positive
import eulersym.symbols as _symbols

__all__ = [
    "E",
    "L2",
    "SPIN",
    "AMPLITUDE",
    "PHASE",
    "RHO",
    "sn",
    "cn",
    "dn",
    "EllipticSolution",
    "rotating_frame_derivative",
    "euler_equations",
    "euler_poisson_equations",
    "euler_poisson_invariants",
    "symmetric_precession_rate",
    "symmetric_transverse_equation",
    "torque_free_symmetric_solution",
    "linearized_euler_equations",
    "perturbation_coefficient",
    "steady_rotation_stability",
    "intermediate_axis_growth_rate",
    "energy",
    "angular_momentum_squared",
    "energy_ellipsoid",
    "inertia_ellipsoid",
    "invariable_plane_distance",
    "herpolhode_radius_squared",
    "polhode",
    "free_body_elliptic_solution",
    "separatrix_solution",
]

#: The energy of the torque-free body, its kinetic energy (a constant of the motion): :data:`eulersym.symbols.E`.
E = _symbols.E
#: Square of the angular momentum |L|² (a constant of the motion): :data:`eulersym.symbols.L2`.
L2 = _symbols.L2
#: The constant spin ω3 of the torque-free symmetric top (a plain symbol: ``omega3`` itself is a function of t).
SPIN = _symbols.spin
#: Amplitude and phase of the harmonic solution of the torque-free symmetric top.
AMPLITUDE = _symbols.amplitude
PHASE = _symbols.phase
#: Coordinates ρ = ω/√(2T) of Poinsot's inertia ellipsoid (Goldstein §5.6).
RHO = (_symbols.rho1, _symbols.rho2, _symbols.rho3)
_L2_SYMBOL = L2

_OMEGA = sp.ImmutableMatrix([omega1, omega2, omega3])
_ETA = (eta1, eta2, eta3)
_GAMMA = sp.ImmutableMatrix([Gamma1, Gamma2, Gamma3])
_PRINCIPAL = (I1, I2, I3)
_AXES = (1, 2, 3)


# ----------------------------------------------------------------------------------------------------------------
# Jacobi elliptic functions sn, cn, dn of (u | m), known through their derivative rules


class _Jacobi(sp.Function):
    """Base of sn, cn, dn: two arguments ``(u, m)``, numeric evaluation through ``mpmath.ellipfun``."""

    nargs = 2
    _kind = ""

    def _eval_evalf(self, prec):
        u, m = self.args
        if not (u.is_number and m.is_number):
            return None
        import mpmath

        with mpmath.workprec(prec):
            value = mpmath.ellipfun(self._kind, u._to_mpmath(prec), m=m._to_mpmath(prec))
        return sp.Expr._from_mpmath(value, prec)

    def _eval_is_real(self):
        u, m = self.args
        if u.is_real and m.is_real and m.is_nonnegative and (1 - m).is_nonnegative:
            return True
        return None


class sn(_Jacobi):
    """Jacobi's ``sn(u | m)``: ``d sn/du = cn dn``, ``sn(0) = 0``, ``sn(u|0) = sin u``, ``sn(u|1) = tanh u``.

    Examples
    --------
    >>> import sympy as sp
    >>> u, m = sp.symbols("u m")
    >>> sn(u, m).diff(u)
    cn(u, m)*dn(u, m)
    >>> sn(u, 1), sn(0, m)
    (tanh(u), 0)
    >>> round(float(sn(sp.Float(0.5), sp.Float(0.3))), 12)
    0.474215622712
    """

    _kind = "sn"

    @classmethod
    def eval(cls, u, m):
        if u.is_zero:
            return sp.S.Zero
        if m.is_zero:
            return sp.sin(u)
        if (m - 1).is_zero:
            return sp.tanh(u)
        return None

    def fdiff(self, argindex=1):
        if argindex != 1:
            raise sp.ArgumentIndexError(self, argindex)
        u, m = self.args
        return cn(u, m) * dn(u, m)


class cn(_Jacobi):
    """Jacobi's ``cn(u | m)``: ``d cn/du = −sn dn``, ``cn(0) = 1``, ``cn(u|0) = cos u``, ``cn(u|1) = sech u``.

    Examples
    --------
    >>> import sympy as sp
    >>> u, m = sp.symbols("u m")
    >>> cn(u, m).diff(u)
    -dn(u, m)*sn(u, m)
    >>> cn(u, 0), cn(u, 1)
    (cos(u), sech(u))
    """

    _kind = "cn"

    @classmethod
    def eval(cls, u, m):
        if u.is_zero:
            return sp.S.One
        if m.is_zero:
            return sp.cos(u)
        if (m - 1).is_zero:
            return sp.sech(u)
        return None

    def fdiff(self, argindex=1):
        if argindex != 1:
            raise sp.ArgumentIndexError(self, argindex)
        u, m = self.args
        return -sn(u, m) * dn(u, m)


class dn(_Jacobi):
    """Jacobi's ``dn(u | m)``: ``d dn/du = −m sn cn``, ``dn(0) = 1``, ``dn(u|0) = 1``, ``dn(u|1) = sech u``.

    Examples
    --------
    >>> import sympy as sp
    >>> u, m = sp.symbols("u m")
    >>> dn(u, m).diff(u)
    -m*cn(u, m)*sn(u, m)
    >>> dn(u, 0), dn(u, 1)
    (1, sech(u))
    """

    _kind = "dn"

    @classmethod
    def eval(cls, u, m):
        if u.is_zero or m.is_zero:
            return sp.S.One
        if (m - 1).is_zero:
            return sp.sech(u)
        return None

    def fdiff(self, argindex=1):
        if argindex != 1:
            raise sp.ArgumentIndexError(self, argindex)
        u, m = self.args
        return -m * sn(u, m) * cn(u, m)


# ----------------------------------------------------------------------------------------------------------------
# Input checks


def _vector3(argument: str, value) -> sp.ImmutableMatrix:
    try:
        items = list(value)
    except TypeError:
        raise InvalidInput(argument, value, "three components (a sequence or a 3×1 Matrix)") from None
    if len(items) != 3:
        raise InvalidInput(argument, value, f"three components, got {len(items)}")
    out = []
    for item in items:
        if isinstance(item, bool) or not isinstance(item, (numbers.Number, sp.Basic)):
            raise InvalidInput(argument, value, "three numbers or SymPy expressions")
        item = sp.sympify(item)
        if item.is_real is False or item.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
            raise InvalidInput(argument, value, "three finite real components")
        out.append(item)
    return sp.ImmutableMatrix(out)


def _ndim(value) -> int:
    """``np.ndim`` of ``value`` as an object array; a flat list or tuple of scalars is 1 without NumPy's import."""
    return 1 if _inertia._flat(value) else np.ndim(np.asarray(value, dtype=object))


def _inertia_matrix(I, argument: str = "I") -> sp.ImmutableMatrix:
    """Three principal moments → diag; a 3×3 tensor → itself after checks (symmetric, body-like)."""
    if isinstance(I, sp.MatrixBase) or _ndim(I) == 2:
        try:
            mat = sp.ImmutableMatrix(I)
        except (TypeError, ValueError, sp.SympifyError):
            raise InvalidInput(argument, I, "three principal moments or a symmetric 3×3 inertia tensor") from None
        if mat.shape != (3, 3):
            raise InvalidInput(argument, I, f"a 3×3 inertia tensor, got shape {mat.shape}")
        for i in range(3):
            for j in range(i + 1, 3):
                if sp.expand(mat[i, j] - mat[j, i]) != 0:
                    raise InvalidInput(argument, I, f"a symmetric tensor (I[{i},{j}] != I[{j},{i}])")
        for i in range(3):
            positive(f"{argument}[{i},{i}]", mat[i, i])
        if not mat.free_symbols:
            try:
                principal = np.linalg.eigvalsh(np.array(mat.evalf(), dtype=float))
            except TypeError:
                raise InvalidInput(argument, I, "a real symmetric 3×3 inertia tensor") from None
            moments(argument, tuple(principal))
        return mat
    values = moments(argument, I)
    return sp.ImmutableMatrix(sp.diag(*[sp.sympify(v) for v in values]))


def _principal(I, argument: str = "I") -> tuple:
    return tuple(sp.sympify(v) for v in moments(argument, I))


def _axis(axis) -> int:
    if isinstance(axis, bool) or not isinstance(axis, numbers.Integral) or int(axis) not in _AXES:
        raise InvalidInput("axis", axis, "a principal axis 1, 2 or 3")
    return int(axis)


def _real(argument: str, value):
    if is_symbolic(value):
        if value.is_real is False or value.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
            raise InvalidInput(argument, value, "a finite real number or symbol")
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InvalidInput(argument, value, "a finite real number or symbol")
    if not math.isfinite(float(value)):
        raise InvalidInput(argument, value, "a finite real number or symbol")
    return value


def _solve_linear(expressions, unknowns) -> list:
    """Solve ``expressions = 0``, linear in ``unknowns`` (symbols or derivatives), for the unknowns."""
    A, b = sp.linear_eq_to_matrix(list(expressions), list(unknowns))
    return list(A.LUsolve(b))


# ----------------------------------------------------------------------------------------------------------------
# Euler's equations


def rotating_frame_derivative(G_body, omega=_OMEGA) -> sp.Matrix:
    """Space-frame rate of a vector, in body components: ``(dG/dt)_space = (dG/dt)_body + ω × G`` (§4.4).

    Parameters
    ----------
    G_body : sequence of 3 or 3×1 Matrix
        Body components of ``G`` (functions of ``t`` where they vary).
    omega : sequence of 3 or 3×1 Matrix, optional
        Body components of the angular velocity (default ``omega1, omega2, omega3``).

    Returns
    -------
    sympy.Matrix (3×1)
        Body components of ``(dG/dt)_space``.

    Examples
    --------
    A vector fixed in the body (constant body components) turns with it: its space rate is ``ω × G``.

    >>> from eulersym.symbols import omega3
    >>> rotating_frame_derivative([1, 0, 0], [0, 0, omega3]).T
    Matrix([[0, omega3(t), 0]])
    """
    G = _vector3("G_body", G_body)
    w = _vector3("omega", omega)
    return sp.Matrix(G.applyfunc(lambda c: c.diff(t)) + w.cross(G))  # componentwise (Matrix.diff: array machinery)


@functools.lru_cache(maxsize=64)
def _euler_lhs(inertia: sp.ImmutableMatrix) -> tuple:
    L = _inertia.angular_momentum(inertia, _OMEGA)  # body components of L = I·ω
    return tuple(sp.expand(c) for c in rotating_frame_derivative(L, _OMEGA))


def euler_equations(I=_PRINCIPAL, torque=(N1, N2, N3)) -> list:
    """Euler's equations of motion, derived from ``(dL/dt)_body + ω × L = N`` with ``L = I·ω``.

    Newton's law ``(dL/dt)_space = N`` in the body frame, with the rotating-frame relation
    (:func:`rotating_frame_derivative`). For principal axes the result is §4.4's
    ``I1 ω̇1 − (I2 − I3) ω2 ω3 = N1`` and cyclic permutations.

    Parameters
    ----------
    I : sequence of 3, or 3×3 Matrix, optional
        Principal moments ``(I1, I2, I3)`` (default: the symbols), or a full symmetric inertia tensor in body axes.
        Moments must be positive and satisfy the triangle inequalities.
    torque : sequence of 3, optional
        Body components of the external torque (default ``N1, N2, N3``).

    Returns
    -------
    list of 3 sympy.Eq
        ``Eq(lhs_k, N_k)`` with ``lhs_k`` the k-th body component of ``(dL/dt)_body + ω × L`` (expanded).

    Raises
    ------
    eulersym.errors.InvalidInput
        Non-positive or triangle-violating moments, a non-symmetric tensor, or a torque without 3 components.

    Examples
    --------
    >>> for eq in euler_equations(torque=(0, 0, 0)):
    ...     print(eq)
    Eq(I1*Derivative(omega1(t), t) - I2*omega2(t)*omega3(t) + I3*omega2(t)*omega3(t), 0)
    Eq(I1*omega1(t)*omega3(t) + I2*Derivative(omega2(t), t) - I3*omega1(t)*omega3(t), 0)
    Eq(-I1*omega1(t)*omega2(t) + I2*omega1(t)*omega2(t) + I3*Derivative(omega3(t), t), 0)
    """
    inertia = _inertia_matrix(I)
    N = _vector3("torque", torque)
    lhs = _euler_lhs(inertia)
    return [sp.Eq(lhs[k], N[k], evaluate=False) for k in range(3)]


@functools.lru_cache(maxsize=16)
def _euler_poisson(inertia: sp.ImmutableMatrix, chi: sp.ImmutableMatrix) -> tuple:
    weight = -M * g * _GAMMA  # body components of the weight −M g ẑ (Γ = A ẑ is the upward vertical)
    torque = chi.cross(weight)  # N = χ × (−M g Γ) = M g Γ × χ
    eqs = euler_equations(inertia, torque)
    omega_dot = _solve_linear([e.lhs - e.rhs for e in eqs], [w.diff(t) for w in _OMEGA])
    # Γ is fixed in space: (dΓ/dt)_space = (dΓ/dt)_body + ω × Γ = 0.
    fixed = rotating_frame_derivative(_GAMMA, _OMEGA)
    gamma_dot = _solve_linear(list(fixed), [G.diff(t) for G in _GAMMA])
    return (
        sp.ImmutableMatrix([sp.together(sp.expand(x)) for x in omega_dot]),
        sp.ImmutableMatrix([sp.expand(x) for x in gamma_dot]),
    )


def euler_poisson_equations(I=_PRINCIPAL, com=(0, 0, l)) -> tuple:
    """The heavy body about a fixed pivot in the non-singular Euler–Poisson form: ``(ω̇, Γ̇)``.

    Derived, not typed: the weight ``−M g ẑ`` has body components ``−M g Γ`` where ``Γ = A ẑ`` are the body
    components of the upward vertical (``Gamma1..3``); its torque about the pivot is ``N = χ × (−M g Γ) = M g Γ × χ``
    with ``χ`` the pivot → centre-of-mass vector in body axes. Euler's equations with this torque give
    ``I ω̇ = I ω × ω + M g Γ × χ``; ``ẑ`` is fixed in space, so the rotating-frame relation gives
    ``0 = Γ̇ + ω × Γ``, i.e. ``Γ̇ = Γ × ω``. Invariants: ``E = ½ ωᵀIω + M g χ·Γ``, ``|Γ|² = 1``, ``(Iω)·Γ``.

    Parameters
    ----------
    I : sequence of 3 or 3×3 Matrix, optional
        Moments (or tensor) about the pivot, in body axes.
    com : sequence of 3, optional
        ``χ``, body components of the centre of mass relative to the pivot (default ``(0, 0, l)``).

    Returns
    -------
    (omega_dot, Gamma_dot) : two sympy.Matrix (3×1)
        Right-hand sides in ``omega1..3`` and ``Gamma1..3``.

    Examples
    --------
    >>> wdot, Gdot = euler_poisson_equations()
    >>> wdot.T
    Matrix([[(I2*omega2(t)*omega3(t) - I3*omega2(t)*omega3(t) + M*g*l*Gamma2(t))/I1, (-I1*omega1(t)*omega3(t) + I3*omega1(t)*omega3(t) - M*g*l*Gamma1(t))/I2, (I1 - I2)*omega1(t)*omega2(t)/I3]])
    >>> Gdot.T
    Matrix([[Gamma2(t)*omega3(t) - Gamma3(t)*omega2(t), -Gamma1(t)*omega3(t) + Gamma3(t)*omega1(t), Gamma1(t)*omega2(t) - Gamma2(t)*omega1(t)]])
    """
    omega_dot, gamma_dot = _euler_poisson(_inertia_matrix(I), _vector3("com", com))
    return sp.Matrix(omega_dot), sp.Matrix(gamma_dot)


def euler_poisson_invariants(I=_PRINCIPAL, com=(0, 0, l)) -> tuple:
    """The conserved quantities of :func:`euler_poisson_equations`: ``(E, |Γ|², L·Γ)``.

    ``E = T + V`` with ``T`` from :func:`energy` and ``V = M g (χ·Γ)`` the height of the centre of mass (``Γ`` is the
    upward vertical in body components, ``χ`` the pivot → centre-of-mass vector); ``L = I ω`` from
    :func:`eulersym.inertia.angular_momentum`. ``|Γ|²`` is conserved because ``Γ̇ = Γ × ω ⟂ Γ``, ``L·Γ`` (the vertical
    component of L) because the gravity torque is horizontal.

    Examples
    --------
    >>> E, gamma2, L_gamma = euler_poisson_invariants()
    >>> sp.expand(E - energy())
    M*g*l*Gamma3(t)
    """
    inertia_matrix = _inertia_matrix(I)
    chi = sp.Matrix(_vector3("com", com))
    gamma = sp.Matrix([Gamma1, Gamma2, Gamma3])
    omega = sp.Matrix(_OMEGA)
    E = energy(inertia_matrix, omega) + M * g * (chi.T * gamma)[0, 0]
    L = _inertia.angular_momentum(inertia_matrix, omega)
    return E, (gamma.T * gamma)[0, 0], sp.expand((L.T * gamma)[0, 0])


# ----------------------------------------------------------------------------------------------------------------
# Torque-free symmetric body


@functools.lru_cache(maxsize=1)
def symmetric_precession_rate() -> sp.Expr:
    """The precession rate of ω about the symmetry axis of a torque-free symmetric body (§4.5.1).

    From :func:`euler_equations` with ``I2 = I1`` and ``N = 0``: the third equation gives ``I3 ω̇3 = 0`` (ω3 is
    constant), the first ``ω̇1 = Ω ω2`` with ``Ω = ω̇1/ω2`` read off, and the second is then ``ω̇2 = −Ω ω1``.

    Returns
    -------
    sympy.Expr
        ``Ω_prec = (I1 − I3)/I1 · ω3``, in ``I1, I3`` and ``omega3`` (a function of t, constant on the motion).

    Examples
    --------
    >>> symmetric_precession_rate()
    (I1 - I3)*omega3(t)/I1
    """
    eqs = euler_equations((I1, I1, I3), (0, 0, 0))
    rates = _solve_linear([e.lhs - e.rhs for e in eqs], [w.diff(t) for w in _OMEGA])
    if rates[2] != 0:
        raise CheckFailed(f"torque-free symmetric body: expected ω̇3 = 0, derived {rates[2]}")
    rate = sp.factor(rates[0] / omega2)
    if sp.expand(rates[1] + rate * omega1) != 0:
        raise CheckFailed("torque-free symmetric body: ω̇2 = −Ω ω1 does not follow")
    return rate


@functools.lru_cache(maxsize=1)
def symmetric_transverse_equation() -> sp.Eq:
    """``ω̈1 + Ω_prec² ω1 = 0``: the torque-free symmetric body's ω1 is a harmonic oscillator (§4.5.1).

    Derived by differentiating ``ω̇1`` (from :func:`euler_equations` with ``I2 = I1``, ``N = 0``) once more and
    substituting ``ω̇2`` and ``ω̇3 = 0`` from the same equations.

    Returns
    -------
    sympy.Eq
        ``Eq(ω̈1 + Ω² ω1, 0)`` with ``Ω = (I1 − I3)/I1 · ω3``.

    Examples
    --------
    >>> symmetric_transverse_equation()
    Eq(Derivative(omega1(t), (t, 2)) + (I1 - I3)**2*omega1(t)*omega3(t)**2/I1**2, 0)
    """
    eqs = euler_equations((I1, I1, I3), (0, 0, 0))
    derivatives = [w.diff(t) for w in _OMEGA]
    rates = dict(zip(derivatives, _solve_linear([e.lhs - e.rhs for e in eqs], derivatives)))
    second = sp.expand(rates[derivatives[0]].diff(t).xreplace(rates))
    restoring = sp.factor(-second / omega1)
    if restoring.has(omega2, *derivatives):
        raise CheckFailed(f"ω̈1 is not proportional to ω1: {second}")
    return sp.Eq(omega1.diff(t, 2) + restoring * omega1, 0, evaluate=False)


def torque_free_symmetric_solution(amplitude=AMPLITUDE, phase=PHASE, spin=SPIN) -> tuple:
    """The harmonic solution ``ω1 = A cos(Ω t + δ)``, ``ω2 = −A sin(Ω t + δ)``, ``ω3 = const`` (§4.5.1).

    Derived: with ``w = ω1 + i ω2`` Euler's equations (``I2 = I1``, ``N = 0``) become ``ẇ = k w`` with
    ``k = −i Ω_prec`` (computed as ``ẇ/w``), so ``w = A e^{k t − i δ}``; its real and imaginary parts are returned.
    ω precesses about the body symmetry axis at ``Ω_prec = (I1 − I3)/I1 · ω3`` — clockwise seen from +e3 when
    ``Ω_prec > 0`` (prolate body, ``I3 < I1``, with ``ω3 > 0``).

    Parameters
    ----------
    amplitude : real, optional
        ``A = sqrt(ω1² + ω2²)`` (default the symbol ``A``).
    phase : real, optional
        ``δ`` (default the symbol ``delta``).
    spin : real, optional
        The constant ``ω3`` (default the plain symbol ``omega_3``, see :data:`SPIN`).

    Returns
    -------
    (omega1, omega2, omega3) : tuple of sympy.Expr, functions of ``t``.

    Examples
    --------
    >>> w1, w2, w3 = torque_free_symmetric_solution()
    >>> w1
    A*cos(delta + omega_3*t*(I1 - I3)/I1)
    >>> w2
    -A*sin(delta + omega_3*t*(I1 - I3)/I1)
    """
    for name, value in (("amplitude", amplitude), ("phase", phase), ("spin", spin)):
        _real(name, value)
    rate = symmetric_precession_rate().xreplace({omega3: SPIN})
    eqs = euler_equations((I1, I1, I3), (0, 0, 0))
    rates = _solve_linear([e.lhs - e.rhs for e in eqs], [w.diff(t) for w in _OMEGA])
    rates = [r.xreplace({omega3: SPIN}) for r in rates]
    w = omega1 + sp.I * omega2
    k = sp.cancel((rates[0] + sp.I * rates[1]) / w)
    if k.has(omega1, omega2):
        raise CheckFailed(f"ẇ/w = {k} is not a constant")
    # w = A e^{i α(t)} with α = (k/i) t − δ real: ω1 = Re w = A cos α, ω2 = Im w = A sin α.
    A, alpha = sp.Dummy("A", real=True), sp.Dummy("alpha", real=True)
    solution = sp.expand_complex(A * sp.exp(sp.I * alpha))
    angle = sp.factor(k / sp.I) * t - sp.sympify(phase)
    if sp.expand(angle + rate * t + phase) != 0:
        raise CheckFailed(f"the phase {angle} does not advance at the rate −Ω_prec = {-rate}")
    back = {A: sp.sympify(amplitude), alpha: angle}
    w1, w2 = (part(solution).xreplace(back).xreplace({SPIN: sp.sympify(spin)}) for part in (sp.re, sp.im))
    return w1, w2, sp.sympify(spin)


# ----------------------------------------------------------------------------------------------------------------
# Example 4.2: stability of steady rotation about a principal axis


@functools.lru_cache(maxsize=3)
def _linearized(axis: int) -> tuple:
    eqs = euler_equations(_PRINCIPAL, (0, 0, 0))
    eps = sp.Dummy("epsilon")
    steady = [omega0 if k == axis else 0 for k in _AXES]
    replace = {}
    for k in range(3):
        replace[_OMEGA[k].diff(t)] = eps * _ETA[k].diff(t)
        replace[_OMEGA[k]] = steady[k] + eps * _ETA[k]
    out = []
    for k, eq in enumerate(eqs):
        residual = sp.expand((eq.lhs - eq.rhs).xreplace(replace))
        if residual.coeff(eps, 0) != 0:
            raise CheckFailed(f"steady rotation about axis {axis} does not solve equation {k + 1}")
        first = residual.coeff(eps, 1)  # drop second order in η
        lhs = _PRINCIPAL[k] * _ETA[k].diff(t)
        rhs = sp.factor(sp.expand(lhs - first))
        if rhs.has(sp.Derivative):
            raise CheckFailed(f"linearised equation {k + 1} is not solved for η̇{k + 1}")
        out.append(sp.Eq(lhs, rhs, evaluate=False))
    return tuple(out)


def linearized_euler_equations(axis: int = 2) -> list:
    """Euler's torque-free equations linearised about steady rotation ``ω0`` on a principal axis (Example 4.2).

    Derived by substituting ``ω = ω0 e_axis + ε η`` into :func:`euler_equations` (``N = 0``), checking that the
    order ``ε⁰`` vanishes (steady rotation is a solution) and keeping the order ``ε¹``.

    Parameters
    ----------
    axis : {1, 2, 3}
        The principal axis of the steady rotation.

    Returns
    -------
    list of 3 sympy.Eq
        ``Eq(I_k η̇_k, rhs_k)`` in ``eta1..3`` (functions of t), ``I1..3`` and ``omega0``.

    Raises
    ------
    eulersym.errors.InvalidInput
        ``axis`` not in {1, 2, 3}.

    Examples
    --------
    Example 4.2, step 2 (rotation about the intermediate axis 2):

    >>> for eq in linearized_euler_equations(2):
    ...     print(eq)
    Eq(I1*Derivative(eta1(t), t), omega0*(I2 - I3)*eta3(t))
    Eq(I2*Derivative(eta2(t), t), 0)
    Eq(I3*Derivative(eta3(t), t), omega0*(I1 - I2)*eta1(t))
    """
    return list(_linearized(_axis(axis)))


@functools.lru_cache(maxsize=3)
def _perturbation_coefficient(axis: int) -> sp.Expr:
    eqs = _linearized(axis)
    rates = {_ETA[k].diff(t): eqs[k].rhs / _PRINCIPAL[k] for k in range(3)}
    coefficients = []
    for i in (k for k in range(3) if k != axis - 1):
        second = sp.expand(rates[_ETA[i].diff(t)].diff(t).xreplace(rates))  # η̈_i, then η̇_j eliminated
        coefficient = second.coeff(_ETA[i])  # η̈_i = k η_i: k is η_i's coefficient and nothing is left over
        if coefficient.has(*_ETA) or sp.expand(second - coefficient * _ETA[i]) != 0:
            raise CheckFailed(f"η̈{i + 1} is not proportional to η{i + 1}: {second}")
        coefficient = sp.factor(coefficient)
        coefficients.append(coefficient)
    if sp.expand(coefficients[0] - coefficients[1]) != 0:
        raise CheckFailed("the two transverse perturbations obey different equations")
    return coefficients[0]


def perturbation_coefficient(axis: int = 2) -> sp.Expr:
    """The coefficient ``k`` of ``η̈_i = k η_i`` for both transverse perturbations (Example 4.2, step 3).

    Derived by differentiating the linearised equation of one transverse component and substituting the other's.
    ``k > 0``: exponential growth (unstable); ``k < 0``: oscillation at ``sqrt(−k)``.

    Parameters
    ----------
    axis : {1, 2, 3}

    Returns
    -------
    sympy.Expr
        For axis 2: ``(I2 − I3)(I1 − I2)/(I1 I3) · ω0²``.

    Examples
    --------
    >>> perturbation_coefficient(2)
    omega0**2*(I1 - I2)*(I2 - I3)/(I1*I3)
    """
    return _perturbation_coefficient(_axis(axis))


@functools.lru_cache(maxsize=3)
def _jacobian(axis: int) -> sp.ImmutableMatrix:
    eqs = _linearized(axis)
    rates = [eqs[k].rhs / _PRINCIPAL[k] for k in range(3)]
    return sp.ImmutableMatrix(sp.Matrix(rates).jacobian(sp.Matrix(_ETA)))


@functools.lru_cache(maxsize=3)
def _jacobian_function(axis: int):
    return sp.lambdify((I1, I2, I3, omega0), _jacobian(axis), modules="numpy")


def steady_rotation_stability(I=_PRINCIPAL, axis: int = 2, omega0=_symbols.omega0):
    """Eigenvalues of the linearised torque-free Euler equations about steady rotation on a principal axis.

    ``η̇ = J η`` with ``J`` the Jacobian of :func:`linearized_euler_equations` (solved for ``η̇``). Its eigenvalues
    are ``0`` (the perturbation along the axis) and ``±sqrt(k)`` with ``k`` = :func:`perturbation_coefficient`:
    a positive real eigenvalue means exponential growth (unstable), an imaginary pair means oscillation.

    Parameters
    ----------
    I : sequence of 3
        Principal moments (positive, triangle inequalities).
    axis : {1, 2, 3}
    omega0 : real
        The steady spin ω0 (any real number or symbol).

    Returns
    -------
    list of sympy.Expr (with multiplicity) for symbolic input; numpy.ndarray of complex, sorted by real then
    imaginary part, when every input is a number.

    Examples
    --------
    >>> steady_rotation_stability((1.0, 2.0, 3.0), 2, 1.0)
    array([-0.57735027+0.j,  0.        +0.j,  0.57735027+0.j])
    >>> steady_rotation_stability(axis=2)
    [0, -omega0*sqrt((I1 - I2)*(I2 - I3))/(sqrt(I1)*sqrt(I3)), omega0*sqrt((I1 - I2)*(I2 - I3))/(sqrt(I1)*sqrt(I3))]
    """
    axis = _axis(axis)
    values = moments("I", I)
    _real("omega0", omega0)
    if not any(is_symbolic(v) for v in (*values, omega0)):
        J = np.asarray(_jacobian_function(axis)(*(float(v) for v in values), float(omega0)), dtype=float)
        eig = np.linalg.eigvals(J).astype(complex)
        eig = np.where(np.abs(eig.imag) < 1e-14 * max(1.0, np.abs(eig).max()), eig.real + 0j, eig)
        return eig[np.lexsort((eig.imag, eig.real))]
    J = sp.Matrix(_jacobian(axis)).xreplace(
        {I1: sp.sympify(values[0]), I2: sp.sympify(values[1]), I3: sp.sympify(values[2]), _symbols.omega0: omega0}
    )
    out = []
    for value, multiplicity in J.eigenvals().items():
        out.extend([value] * multiplicity)
    return sorted(out, key=sp.default_sort_key)


def intermediate_axis_growth_rate(I1=_symbols.I1, I2=_symbols.I2, I3=_symbols.I3, omega0=_symbols.omega0):
    """Exponential growth rate Ω of a perturbation of steady rotation about the intermediate axis (Example 4.2).

    The positive real eigenvalue of :func:`steady_rotation_stability` on axis 2, ``Ω = sqrt(λ²)``:
    ``Ω = |ω0| sqrt((I3 − I2)(I2 − I1)/(I1 I3))``.

    Parameters
    ----------
    I1, I2, I3 : positive
        Principal moments with axis 2 intermediate: ``I1 < I2 < I3`` or ``I1 > I2 > I3``. Symbols are assumed to be
        so ordered (an ordering SymPy can disprove raises).
    omega0 : real, non-zero
        The steady spin.

    Returns
    -------
    sympy.Expr for symbolic input, float for numbers.

    Raises
    ------
    eulersym.errors.InvalidInput
        Axis 2 not intermediate, moments invalid, or ``omega0 = 0`` (no growth to speak of).

    Examples
    --------
    >>> intermediate_axis_growth_rate()
    omega0*sqrt((I1 - I2)*(I2 - I3))/(sqrt(I1)*sqrt(I3))
    >>> round(intermediate_axis_growth_rate(1.0, 2.0, 3.0, 1.0), 12)   # sqrt(1/3)
    0.57735026919
    """
    values = moments("I", (I1, I2, I3))
    _real("omega0", omega0)
    if (omega0.is_zero if is_symbolic(omega0) else float(omega0) == 0):
        raise InvalidInput("omega0", omega0, "a non-zero steady spin")
    a, b, c = (sp.sympify(v) for v in values)
    ordered = sp.expand((b - a) * (c - b))
    if ordered.is_positive is False or ordered.is_zero:
        raise InvalidInput(
            "I", values, "moments with axis 2 intermediate: I1 < I2 < I3 or I1 > I2 > I3 (strictly)"
        )
    eig = steady_rotation_stability(values, 2, omega0)
    if not isinstance(eig, list):  # numeric moments: an ndarray of eigenvalues
        rate = eig[np.argmax(eig.real)]
        if rate.real <= 0 or abs(rate.imag) > 1e-12 * abs(rate):
            raise CheckFailed(f"no positive real eigenvalue on the intermediate axis: {eig}")
        return float(rate.real)
    nonzero = [e for e in eig if e != 0]
    if len(nonzero) != 2 or sp.expand(nonzero[0] ** 2 - nonzero[1] ** 2) != 0:
        raise CheckFailed(f"unexpected eigenvalues {eig}")
    return sp.sqrt(sp.factor(sp.expand(nonzero[0] ** 2)))


# ----------------------------------------------------------------------------------------------------------------
# Poinsot construction


def energy(I=_PRINCIPAL, omega=_OMEGA) -> sp.Expr:
    """Rotational kinetic energy ``T = ½ ωᵀ I ω`` (body components; :func:`eulersym.inertia.kinetic_energy`, expanded).

    Examples
    --------
    >>> energy()
    I1*omega1(t)**2/2 + I2*omega2(t)**2/2 + I3*omega3(t)**2/2
    """
    return sp.expand(_inertia.kinetic_energy(_inertia_matrix(I), _vector3("omega", omega)))


def angular_momentum_squared(I=_PRINCIPAL, omega=_OMEGA) -> sp.Expr:
    """``|L|² = (Iω)·(Iω)`` (body components).

    Examples
    --------
    >>> angular_momentum_squared()
    I1**2*omega1(t)**2 + I2**2*omega2(t)**2 + I3**2*omega3(t)**2
    """
    L = _inertia.angular_momentum(_inertia_matrix(I), _vector3("omega", omega))
    return sp.expand(L.dot(L))


def energy_ellipsoid(I=_PRINCIPAL, E=E) -> sp.Eq:
    """The energy ellipsoid in ω-space: ``½ ωᵀ I ω = E``; ω(t) of the free body stays on it.

    Examples
    --------
    >>> energy_ellipsoid()
    Eq(I1*omega1(t)**2/2 + I2*omega2(t)**2/2 + I3*omega3(t)**2/2, E)
    """
    return sp.Eq(energy(I), positive("E", E), evaluate=False)


def inertia_ellipsoid(I=_PRINCIPAL, rho=RHO) -> sp.Eq:
    """Poinsot's inertia ellipsoid ``ρᵀ I ρ = 1`` (Goldstein §5.6), with ``ρ = ω/√(2T)``.

    With ``ρ = ω/√(2E)`` this is :func:`energy_ellipsoid` divided by ``E``: the same surface, scaled.

    Examples
    --------
    >>> inertia_ellipsoid()
    Eq(I1*rho1**2 + I2*rho2**2 + I3*rho3**2, 1)
    """
    return sp.Eq(2 * energy(I, rho), 1, evaluate=False)


def invariable_plane_distance(I=_PRINCIPAL, omega=_OMEGA, *, scale: str = "omega") -> sp.Expr:
    """Distance from the centre to the invariable plane, derived from the tangent plane of the ellipsoid.

    The plane tangent to the energy ellipsoid at ω has normal ``∇_ω T = I ω = L`` (fixed in space): the
    invariable plane. Its distance from the centre is ``ω·L/|L| = 2T/|L|`` (``scale="omega"``: the energy
    ellipsoid in ω-space); for Goldstein's inertia ellipsoid in ``ρ = ω/√(2T)`` it is ``√(2T)/|L|``
    (``scale="rho"``). Both are constant on the motion: the ellipsoid rolls on a fixed plane.

    Parameters
    ----------
    I : sequence of 3 or 3×3 Matrix
    omega : sequence of 3
    scale : {"omega", "rho"}

    Returns
    -------
    sympy.Expr in ω.

    Examples
    --------
    >>> d = invariable_plane_distance()
    >>> from eulersym.compare import compare
    >>> compare(d, 2*energy()/sp.sqrt(angular_momentum_squared())).exact
    True
    """
    if scale not in ("omega", "rho"):
        raise InvalidInput("scale", scale, "'omega' (energy ellipsoid) or 'rho' (Goldstein's inertia ellipsoid)")
    w = sp.Matrix(_vector3("omega", omega))
    T = energy(I, w)
    normal = sp.Matrix([sp.diff(T, x) for x in w]) if all(x.is_Symbol or x.is_Function for x in w) else None
    if normal is None:  # numbers given: differentiate at symbols, then substitute
        dummies = sp.Matrix(sp.symbols("w1:4", real=True))
        normal = sp.Matrix([sp.diff(energy(I, dummies), x) for x in dummies]).xreplace(dict(zip(dummies, w)))
    distance = sp.expand(w.dot(normal)) / sp.sqrt(sp.expand(normal.dot(normal)))
    if scale == "rho":
        distance = distance / sp.sqrt(2 * T)
    return distance


def herpolhode_radius_squared(I=_PRINCIPAL, omega=_OMEGA) -> sp.Expr:
    """Squared distance of ω's tip from the foot of the perpendicular on the invariable plane (the herpolhode).

    ω = (its component along L̂) + (its component in the plane); the first is the constant
    :func:`invariable_plane_distance` ``d = 2T/|L|``, so the herpolhode — the curve the tip of ω traces on the fixed
    invariable plane — has radius ``r`` with ``r² = |ω|² − d²``. It varies only through ``|ω|²`` along the motion,
    between the extremes of ``|ω|²`` on the polhode: the herpolhode stays in an annulus.

    Examples
    --------
    >>> from eulersym.compare import compare
    >>> r2 = herpolhode_radius_squared()
    >>> w2 = sum(w**2 for w in _OMEGA)
    >>> compare(r2 + invariable_plane_distance()**2, w2).exact
    True
    """
    w = sp.Matrix(_vector3("omega", omega))
    return sp.expand(w.dot(w)) - invariable_plane_distance(I, w) ** 2


def _ordered_about(values, energy_value, l2_value, about):
    """Pick the axis the polhode encircles; axis 2 must be intermediate for these formulas."""
    a, b, c = values
    numeric = not any(is_symbolic(v) and v.free_symbols for v in (a, b, c, energy_value, l2_value))
    if numeric:
        if not (a < b < c or a > b > c):
            raise InvalidInput("I", values, "moments with axis 2 intermediate (I1 < I2 < I3 or I1 > I2 > I3)")
        lo, hi = sorted((2 * energy_value * a, 2 * energy_value * c))
        if not lo <= l2_value <= hi:
            raise InvalidInput("L2", l2_value, f"a value in [2 E I_min, 2 E I_max] = [{float(lo):g}, {float(hi):g}]")
        side = l2_value - 2 * energy_value * b
        if side == 0:
            raise InvalidInput("L2", l2_value, "L2 != 2 E I2 (that is the separatrix: use separatrix_solution)")
        encircled = 3 if (side > 0) == (c > a) else 1
        if about is not None and about != encircled:
            raise InvalidInput("about", about, f"{encircled}: with these E and L2 the polhode encircles axis "
                               f"{encircled} (L2 {'>' if side > 0 else '<'} 2 E I2)")
        about = encircled
    if about is None:
        about = 3
    if isinstance(about, bool) or about not in (1, 3):
        raise InvalidInput("about", about, "1 or 3 (polhodes encircle the axes of extreme moment, not axis 2)")
    return about


def polhode(I=_PRINCIPAL, E=E, L2=L2, *, about=None, parameter=None, sign: int = 1):
    """A polhode, parametrised: the intersection of the energy ellipsoid and the L-sphere in ω-space.

    Derived: with ``W_i = ω_i²`` the two invariants are linear, ``Σ I_i W_i = 2E`` and ``Σ I_i² W_i = L²``.
    Eliminating ``W_k`` (k = ``about``) gives ``Σ_{i≠k} I_i (I_k − I_i) W_i = 2 E I_k − L²``, an ellipse in the
    two other components: ``ω_j = R_j cos s`` (j the other extreme axis) and ``ω_2 = R_2 sin s``; ``ω_k`` then
    follows from the energy (``sign`` picks its branch). The polhode encircles axis 3 when ``L² > 2 E I2`` and
    axis 1 when ``L² < 2 E I2`` (for ``I1 < I2 < I3``).

    Parameters
    ----------
    I : sequence of 3
        Principal moments with axis 2 intermediate (symbols are assumed ``I1 < I2 < I3``).
    E, L2 : positive
        The energy and ``L²`` (defaults the symbols :data:`E`, :data:`L2`).
    about : {1, 3}, optional
        The axis encircled; deduced from the numbers when omitted (symbols: 3).
    parameter : Symbol, optional
        The curve parameter ``s`` (default a real symbol ``s``).
    sign : {1, -1}
        Branch of ``ω_about``.

    Returns
    -------
    sympy.Matrix (3×1): ω(s).

    Examples
    --------
    >>> w = polhode()
    >>> w[0], w[1]
    (sqrt(-(2*E*I3 - L2)/(I1 - I3))*cos(s)/sqrt(I1), sqrt(-(2*E*I3 - L2)/(I2 - I3))*sin(s)/sqrt(I2))
    >>> w[2]
    sqrt((I1 - I2)*(2*E*I3 - L2)*sin(s)**2/(I3*(I1 - I3)*(I2 - I3)) + (2*E*I1 - L2)/(I3*(I1 - I3)))
    >>> from eulersym.compare import compare
    >>> compare([energy(omega=w), angular_momentum_squared(omega=w)], [E, L2]).equal
    True
    """
    values = _principal(I)
    energy_value, l2_value = sp.sympify(positive("E", E)), sp.sympify(positive("L2", L2))
    if sign not in (1, -1):
        raise InvalidInput("sign", sign, "+1 or -1")
    about = _ordered_about(values, energy_value, l2_value, about)
    s = parameter if parameter is not None else sp.Symbol("s", real=True)
    k = about - 1
    W = sp.symbols("W1:4")
    invariants = [sum(values[i] * W[i] for i in range(3)) - 2 * energy_value,
                  sum(values[i] ** 2 * W[i] for i in range(3)) - l2_value]
    ellipse = sp.expand(values[k] * invariants[0] - invariants[1])  # W_k eliminated
    if ellipse.has(W[k]):
        raise CheckFailed("W_k was not eliminated")
    others = [i for i in range(3) if i != k]
    level = -ellipse.subs({W[i]: 0 for i in others})  # = 2 E I_k − L²
    radius = {i: sp.sqrt(sp.factor(level / ellipse.coeff(W[i]))) for i in others}
    curve = {others[0] if others[0] != 1 else others[1]: sp.cos(s), 1: sp.sin(s)}
    w = [None, None, None]
    for i in others:
        w[i] = radius[i] * curve[i]
    Wk = _solve_linear([invariants[0].subs({W[i]: w[i] ** 2 for i in others})], [W[k]])[0]
    Wk = sp.expand(Wk).subs(sp.cos(s) ** 2, 1 - sp.sin(s) ** 2)  # one trigonometric function left
    parts = sp.collect(sp.expand(Wk), sp.sin(s), evaluate=False)
    w[k] = sign * sp.sqrt(sp.Add(*(sp.factor(c) * p for p, c in parts.items())))
    return sp.Matrix(w)


@dataclass(frozen=True)
class EllipticSolution:
    """ω(t) of the free asymmetric body in Jacobi elliptic functions, with its derived constants.

    Attributes
    ----------
    omega : sympy.ImmutableMatrix (3×1)
        ``(a cn, b sn, c dn)(λ t | m)`` when the polhode encircles axis 3, ``(a dn, b sn, c cn)(λ t | m)`` when it
        encircles axis 1.
    amplitudes : tuple (a, b, c)
    rate : λ
    parameter : m (= k², in [0, 1) on a polhode, 1 on the separatrix)
    about : int
        The axis the polhode encircles (1 or 3).
    """

    omega: sp.ImmutableMatrix
    amplitudes: tuple
    rate: sp.Expr
    parameter: sp.Expr
    about: int


def _coefficient(residual, functions) -> sp.Expr:
    """``residual = c · (product of two Jacobi functions)`` → ``c``."""
    residual = sp.expand(residual)
    atoms = residual.atoms(*functions)
    monomial = sp.Mul(*atoms)
    coefficient = sp.expand(sp.cancel(residual / monomial))
    if coefficient.has(*functions):
        raise CheckFailed(f"residual {residual} is not a single product of Jacobi functions")
    return coefficient


@functools.lru_cache(maxsize=16)
def _elliptic(values: tuple, energy_value, l2_value, about: int) -> EllipticSolution:
    a, b, c, lam, m = (sp.Dummy(n, positive=True) for n in ("a", "b", "c", "lambda", "m"))
    u = lam * t
    shape = (cn, sn, dn) if about == 3 else (dn, sn, cn)
    ansatz = [amp * f(u, m) for amp, f in zip((a, b, c), shape)]
    replace = {}
    for k in range(3):
        replace[_OMEGA[k].diff(t)] = ansatz[k].diff(t)
        replace[_OMEGA[k]] = ansatz[k]
    eqs = euler_equations(values, (0, 0, 0))
    conditions = [_coefficient((e.lhs - e.rhs).xreplace(replace), (sn, cn, dn)) for e in eqs]
    # Initial values ω(0) = (a, 0, c) carry the invariants: solve 2E and L² for a², c².
    start = [x.subs(t, 0) for x in ansatz]
    A2, C2 = sp.symbols("A2 C2")
    squares = {a: sp.sqrt(A2), c: sp.sqrt(C2)}
    sq = _solve_linear(
        [2 * energy(values, start).xreplace(squares) - 2 * energy_value,
         angular_momentum_squared(values, start).xreplace(squares) - l2_value],
        [A2, C2],
    )
    a_sq, c_sq = (sp.factor(x) for x in sq)
    # b from the condition linear in b without m (the ω2 equation), then λ² from the other m-free one, then m.
    free_of_m = [cnd for cnd in conditions if not cnd.has(m)]
    with_m = [cnd for cnd in conditions if cnd.has(m)]
    if len(free_of_m) != 2 or len(with_m) != 1:
        raise CheckFailed(f"unexpected structure of the conditions {conditions}")
    b_eq = next(cnd for cnd in free_of_m if sp.degree(cnd, lam) == 1 and sp.degree(cnd, b) == 1
                and sp.expand(cnd).coeff(b).has(lam))
    b_value = sp.solve(b_eq, b)[0]
    other = next(cnd for cnd in free_of_m if cnd is not b_eq)
    numerator = sp.expand(sp.numer(sp.together(other.subs(b, b_value))))
    poly = sp.Poly(numerator, lam)
    if set(poly.monoms()) - {(2,), (0,)}:
        raise CheckFailed(f"λ is not fixed by λ² alone: {numerator}")
    lam_sq = -poly.coeff_monomial(1) / poly.coeff_monomial(lam**2)
    m_value = sp.solve(with_m[0].subs(b, b_value), m)[0]
    values_sq = {a: sp.sqrt(a_sq), c: sp.sqrt(c_sq)}
    lam_sq = sp.factor(sp.expand(lam_sq.xreplace({a: sp.sqrt(a_sq), c: sp.sqrt(c_sq)})))
    rate = sp.sqrt(lam_sq)
    b_final = sp.sqrt(sp.factor(sp.expand((b_value**2).xreplace({lam: rate}).xreplace(values_sq))))
    m_final = sp.factor(sp.expand((m_value.subs(b, b_value) if m_value.has(b) else m_value)
                                  .xreplace({lam: rate}).xreplace(values_sq)))
    amplitudes = (sp.sqrt(a_sq), b_final, sp.sqrt(c_sq))
    omega = sp.ImmutableMatrix([amp * f(rate * t, m_final) for amp, f in zip(amplitudes, shape)])
    return EllipticSolution(omega=omega, amplitudes=amplitudes, rate=rate, parameter=m_final, about=about)


def free_body_elliptic_solution(I=_PRINCIPAL, E=E, L2=L2, *, about=None) -> EllipticSolution:
    """The exact ω(t) of the torque-free asymmetric body, derived in Jacobi elliptic functions.

    Ansatz ``ω = (a cn, b sn, c dn)(λ t | m)`` when the polhode encircles axis 3 (``L² > 2 E I2`` for
    ``I1 < I2 < I3``) or ``(a dn, b sn, c cn)(λ t | m)`` when it encircles axis 1 (``L² < 2 E I2``), with ``t = 0``
    where ``ω2 = 0``. Substituting into :func:`euler_equations` with the derivative rules of sn, cn, dn turns each
    equation into (constant) × (two Jacobi functions), so three algebraic conditions; with the invariants at
    ``t = 0``, ``2E = I1 a² + I3 c²`` and ``L² = I1² a² + I3² c²``, they fix ``a, c`` (from the invariants), ``b``
    (the ω2 equation), ``λ²`` (the other m-free equation) and ``m`` (the remaining one); ``λ > 0`` is chosen.

    For ``about=3``: ``a² = (2EI3 − L²)/(I1(I3 − I1))``, ``c² = (L² − 2EI1)/(I3(I3 − I1))``,
    ``λ² = (I3 − I2)(L² − 2EI1)/(I1 I2 I3)``, ``m = (I2 − I1)(2EI3 − L²)/((I3 − I2)(L² − 2EI1))`` (as in Landau
    & Lifshitz §37); ``about=1`` exchanges the roles of axes 1 and 3. The separatrix ``L² = 2 E I2`` is the limit
    ``m → 1`` (:func:`separatrix_solution`).

    Parameters
    ----------
    I : sequence of 3
        Principal moments with axis 2 intermediate (symbols assumed ``I1 < I2 < I3``).
    E, L2 : positive
        Energy and squared angular momentum (defaults the symbols :data:`E`, :data:`L2`).
    about : {1, 3}, optional
        Deduced from numbers when omitted (symbols: 3).

    Returns
    -------
    EllipticSolution

    Examples
    --------
    >>> sol = free_body_elliptic_solution()
    >>> sol.parameter
    -(I1 - I2)*(2*E*I3 - L2)/((I2 - I3)*(2*E*I1 - L2))
    >>> sol.omega[1]
    sqrt(-(2*E*I3 - L2)/(I2 - I3))*sn(t*sqrt((I2 - I3)*(2*E*I1 - L2))/(sqrt(I1)*sqrt(I2)*sqrt(I3)), -(I1 - I2)*(2*E*I3 - L2)/((I2 - I3)*(2*E*I1 - L2)))/sqrt(I2)
    """
    values = _principal(I)
    energy_value, l2_value = sp.sympify(positive("E", E)), sp.sympify(positive("L2", L2))
    about = _ordered_about(values, energy_value, l2_value, about)
    return _elliptic(values, energy_value, l2_value, about)


def separatrix_solution(I=_PRINCIPAL, E=E) -> EllipticSolution:
    """The separatrix ``L² = 2 E I2`` as the limit ``m → 1`` of :func:`free_body_elliptic_solution`.

    At ``L² = 2 E I2`` the derived parameter ``m`` reduces to 1, and ``sn → tanh``, ``cn, dn → sech``: the body
    leaves the intermediate axis asymptotically, ``ω2 → ±b`` as ``t → ±∞`` (both polhode families meet here).

    Examples
    --------
    >>> sol = separatrix_solution()
    >>> sol.parameter
    1
    >>> sol.omega[1]
    sqrt(2)*sqrt(E)*tanh(t*sqrt((I2 - I3)*(2*E*I1 - 2*E*I2))/(sqrt(I1)*sqrt(I2)*sqrt(I3)))/sqrt(I2)
    """
    values = _principal(I)
    energy_value = sp.sympify(positive("E", E))
    general = free_body_elliptic_solution(values, energy_value, _L2_SYMBOL, about=3)
    limit = {_L2_SYMBOL: 2 * energy_value * values[1]}
    m = sp.factor(sp.cancel(general.parameter.xreplace(limit)))
    if m != 1:
        raise CheckFailed(f"the separatrix should be m = 1, derived m = {m}")
    amplitudes = tuple(sp.factor(x.xreplace(limit)) for x in general.amplitudes)
    rate = general.rate.xreplace(limit)
    omega = sp.ImmutableMatrix([amp * f(rate * t, m) for amp, f in zip(amplitudes, (cn, sn, dn))])
    return EllipticSolution(omega=omega, amplitudes=amplitudes, rate=rate, parameter=m, about=3)
