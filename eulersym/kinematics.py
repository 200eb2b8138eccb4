"""Angular velocity in Euler angles (§4.2.2), derived from the attitude matrix.

Two derivations, shown equal in the tests and by ``eulersym check``:

* **composition** (used for the results, no simplification needed): for the body-fixed sequence "abc",
  ``ω = φ̇ e_a + θ̇ e_b' + ψ̇ e_c''``, each rate about the axis it turns, expressed in body components:
  ``ω_body = P_c(ψ) P_b(θ) e_a φ̇ + P_c(ψ) e_b θ̇ + e_c ψ̇``;
* **the skew matrix** of the definition: with ``r_body = A r_space``, a vector fixed in space moves in the body frame as
  ``ṙ_body = Ȧ Aᵀ r_body = −ω × r_body``, so ``[ω_body]× = −Ȧ Aᵀ`` and ``[ω_space]× = −Aᵀ Ȧ``
  (:func:`angular_velocity_matrix`).

Examples
--------
>>> from eulersym.compare import compare
>>> from eulersym.rotation import skew
>>> compare(skew(omega_body()), angular_velocity_matrix()).exact
True
"""

from __future__ import annotations

import functools

from eulersym._numpy import np
import sympy as sp

from eulersym.errors import CheckFailed, InvalidInput, SingularConfiguration
from eulersym.rotation import _convention, _three, elementary, euler_matrix, quaternion_multiply, to_euler
from eulersym.validation import finite_array
from eulersym.symbols import euler_angles as _EULER_ANGLES, t

__all__ = [
    "euler_angles",
    "omega_body",
    "omega_space",
    "angular_velocity_matrix",
    "euler_rate_matrix",
    "euler_rates",
    "quaternion_rate",
    "space_rate_in_body",
]

_E = {"x": sp.Matrix([1, 0, 0]), "y": sp.Matrix([0, 1, 0]), "z": sp.Matrix([0, 0, 1])}


def euler_angles(A, convention: str = "zxz", *, degrees: bool = False):
    """The Euler angles (φ, θ, ψ) of an attitude matrix ``A`` (``r_body = A @ r_space``): the angles whose
    rates :func:`euler_rates` gives, by :func:`eulersym.rotation.to_euler` (SciPy's ranges; defined at gimbal
    lock with ψ = 0).

    The symbols φ, θ, ψ themselves (functions of t) are :data:`eulersym.symbols.euler_angles`.

    Examples
    --------
    >>> from eulersym.rotation import euler_matrix
    >>> [round(a, 12) for a in euler_angles(euler_matrix(0.1, 0.5, 0.2))]
    [0.1, 0.5, 0.2]
    """
    return to_euler(A, convention, degrees=degrees)


def omega_body(convention: str = "zxz") -> sp.Matrix:
    """Body components of the angular velocity in terms of the Euler angles and their rates.

    ``ω_body = P_c(ψ) P_b(θ) e_a φ̇ + P_c(ψ) e_b θ̇ + e_c ψ̇`` for the passive body-fixed sequence "abc"
    (:func:`eulersym.rotation.euler_matrix`); for the text's "zxz" this is §4.2's three formulas.

    Parameters
    ----------
    convention : str
        One of :data:`eulersym.rotation.CONVENTIONS`.

    Returns
    -------
    sympy.Matrix (3×1) in ``phi, theta, psi`` (functions of t) and their first derivatives.

    Examples
    --------
    >>> omega_body()
    Matrix([
    [ sin(psi(t))*sin(theta(t))*Derivative(phi(t), t) + cos(psi(t))*Derivative(theta(t), t)],
    [-sin(psi(t))*Derivative(theta(t), t) + sin(theta(t))*cos(psi(t))*Derivative(phi(t), t)],
    [                           cos(theta(t))*Derivative(phi(t), t) + Derivative(psi(t), t)]])
    """
    return _omega_body(_convention(convention)).copy()  # the cached matrix stays the caller's to change


@functools.lru_cache(maxsize=32)
def _omega_body(convention: str) -> sp.Matrix:
    a, b, c = convention
    phi, theta, psi = _EULER_ANGLES
    Pc, Pb = elementary(c, psi), elementary(b, theta)
    w = Pc * Pb * _E[a] * phi.diff(t) + Pc * _E[b] * theta.diff(t) + _E[c] * psi.diff(t)
    return w.applyfunc(sp.expand)


def omega_space(convention: str = "zxz") -> sp.Matrix:
    """Space components of the angular velocity: ``ω_space = Aᵀ ω_body``, composed without simplification.

    ``ω_space = e_a φ̇ + P_a(φ)ᵀ e_b θ̇ + P_a(φ)ᵀ P_b(θ)ᵀ e_c ψ̇``.

    Examples
    --------
    >>> omega_space()[2]
    cos(theta(t))*Derivative(psi(t), t) + Derivative(phi(t), t)
    """
    return _omega_space(_convention(convention)).copy()  # the cached matrix stays the caller's to change


@functools.lru_cache(maxsize=32)
def _omega_space(convention: str) -> sp.Matrix:
    a, b, c = convention
    phi, theta, psi = _EULER_ANGLES
    PaT, PbT = elementary(a, phi).T, elementary(b, theta).T
    w = _E[a] * phi.diff(t) + PaT * _E[b] * theta.diff(t) + PaT * PbT * _E[c] * psi.diff(t)
    return w.applyfunc(sp.expand)


def angular_velocity_matrix(convention: str = "zxz", frame: str = "body") -> sp.Matrix:
    """The skew matrix of the definition: ``−Ȧ Aᵀ`` (frame="body") or ``−Aᵀ Ȧ`` (frame="space"), unsimplified.

    Its entries equal ``skew(omega_body())`` (resp. ``skew(omega_space())``) once sin² + cos² = 1 is used; the
    equality is proven in the tests and by ``eulersym check`` (entry ``4.2.omega_skew``).

    Examples
    --------
    >>> W = angular_velocity_matrix()
    >>> W.shape
    (3, 3)
    """
    if frame not in ("body", "space"):
        raise InvalidInput("frame", frame, "'body' or 'space'")
    A = euler_matrix(*_EULER_ANGLES, convention=convention)
    Adot = A.diff(t)
    W = -Adot * A.T if frame == "body" else -A.T * Adot
    return W.applyfunc(sp.expand)


def euler_rate_matrix(convention: str = "zxz") -> sp.Matrix:
    """The matrix J(φ, θ, ψ) with ``ω_body = J · (φ̇, θ̇, ψ̇)``, and its determinant's zero set is the singularity.

    Examples
    --------
    >>> sp.trigsimp(euler_rate_matrix().det())
    -sin(theta(t))
    """
    return _euler_rate_matrix(_convention(convention)).copy()  # the cached matrix stays the caller's to change


@functools.lru_cache(maxsize=32)
def _euler_rate_matrix(convention: str) -> sp.Matrix:
    rates = [q.diff(t) for q in _EULER_ANGLES]
    return _omega_body(convention).jacobian(rates)


def euler_rates(omega_body, angles, convention: str = "zxz"):
    """Invert ``ω_body = J(angles) · rates`` for the Euler-angle rates (φ̇, θ̇, ψ̇).

    Parameters
    ----------
    omega_body : sequence of 3 (numbers or SymPy expressions)
        Body components of ω.
    angles : sequence of 3 (φ, θ, ψ), numbers or SymPy expressions
    convention : str

    Returns
    -------
    tuple of 3: floats for numeric input, SymPy expressions otherwise.

    Raises
    ------
    SingularConfiguration
        At the coordinate singularity (sin θ = 0 for "zxz"; cos θ = 0 for Tait–Bryan sequences), where the rates are
        not determined by ω; numerically when |det J| < 1e-12. Use quaternions there.

    Examples
    --------
    >>> euler_rates([0.0, 0.0, 1.0], [0.1, 0.5, 0.2])  # doctest: +ELLIPSIS
    (0.0, 0.0, 1.0)
    >>> euler_rates([0, 0, 1], [0.0, 0.0, 0.0])
    Traceback (most recent call last):
    ...
    eulersym.errors.SingularConfiguration: angles=[0.0, 0.0, 0.0] is not valid: expected a non-singular attitude for 'zxz' (det J = 0 here; J is singular where sin(theta) = 0): integrate with quaternions there
    """
    J = euler_rate_matrix(convention)
    syms = list(_EULER_ANGLES)
    angles = _three("angles", angles)
    omega_body = _three("omega_body", omega_body)
    where = _singular_set(convention)
    numeric = all(not isinstance(v, sp.Basic) for v in [*angles, *omega_body])
    if numeric:
        angles = finite_array("angles", angles, shape=(3,)).tolist()
        omega_body = finite_array("omega_body", omega_body, shape=(3,)).tolist()
        f = _rate_matrix_function(convention)
        Jn = np.asarray(f(*[float(a) for a in angles]), dtype=float)
        det = np.linalg.det(Jn)
        if not abs(det) >= 1e-12:
            raise SingularConfiguration(
                "angles", list(angles),
                f"a non-singular attitude for {convention!r} (det J = {det:.3g} here; J is singular where {where}): "
                "integrate with quaternions there",
            )
        rates = np.linalg.solve(Jn, np.asarray(omega_body, dtype=float))
        return tuple(float(r) for r in rates)
    Jv = J.xreplace(dict(zip(syms, [sp.sympify(a) for a in angles])))
    det = sp.trigsimp(Jv.det())
    if det == 0:
        raise SingularConfiguration(
            "angles", list(angles), f"a non-singular attitude for {convention!r} (J is singular where {where})"
        )
    rates = Jv.LUsolve(sp.Matrix(omega_body))
    return tuple(sp.trigsimp(sp.simplify(r)) for r in rates)


def _singular_set(convention: str) -> str:
    a, b, c = _convention(convention)
    return "sin(theta) = 0" if a == c else "cos(theta) = 0"


@functools.lru_cache(maxsize=32)
def _rate_matrix_function(convention: str):
    J = euler_rate_matrix(convention)
    return sp.lambdify(list(_EULER_ANGLES), J, modules="numpy")


def quaternion_rate(q, omega_body):
    """Rate of the attitude quaternion: ``q̇ = ½ q ⊗ (0, ω_body)``.

    From composition: over dt the body turns by ω dt about its own axes, ``q(t + dt) = q(t) ⊗ (1, ½ ω dt)``. Scalar
    first; q describes the body's orientation (:func:`eulersym.rotation.from_quaternion`).

    Examples
    --------
    >>> quaternion_rate([1.0, 0, 0, 0], [0, 0, 2.0])
    array([0., 0., 0., 1.])
    """
    q = _three("q", q, 4)
    omega_body = _three("omega_body", omega_body)
    if all(not isinstance(v, sp.Basic) for v in [*q, *omega_body]):
        finite_array("omega_body", omega_body, shape=(3,))
    w = quaternion_multiply(q, [0, *omega_body])
    return w / 2


def space_rate_in_body(G_body, convention: str = "zxz") -> sp.Matrix:
    """Body components of the space-frame rate of a vector: ``A · d/dt (Aᵀ G_body)``.

    Differentiates the space components ``G_space = Aᵀ G_body`` and maps the result back to the body frame; §4.4's
    operator relation ``(dG/dt)_space = (dG/dt)_body + ω × G`` is this, once ω is recognised (``eulersym check``
    entry ``4.4.rotating_frame``). By the product rule ``A d/dt(Aᵀ G) = A Aᵀ Ġ + A Ȧᵀ G``; with
    ``A = F1 F2 F3`` (the three elementary rotations, each orthogonal) ``A Aᵀ = 1`` and
    ``A Ȧᵀ = Σ_k P_k (F_k Ḟ_kᵀ) P_kᵀ`` with ``P_k = F1 ⋯ F_(k−1)`` (:func:`_rotating_frame_matrix`): short
    products, each reduced with ``sin² + cos² = 1`` as it is formed, instead of one long expansion.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.compare import compare
    >>> G = sp.Matrix(sp.symbols("G1:4"))  # a vector fixed in the body
    >>> compare(space_rate_in_body(G), omega_body().cross(G)).equal
    True
    """
    G = sp.Matrix(G_body)
    if G.shape != (3, 1):
        raise InvalidInput("G_body", G_body, "a 3-vector of body components")
    W = _rotating_frame_matrix(_convention(convention))
    return (G.applyfunc(lambda g: g.diff(t)) + W * G).applyfunc(sp.expand)


def _reduce_sin_squares(expr, angles) -> sp.Expr:
    """Expand and write even powers of ``sin(a)`` through ``cos(a)`` (``sin² = 1 − cos²``), then expand: the
    normal form of a polynomial in sin and cos modulo ``sin² + cos² − 1`` (sin of degree ≤ 1), so an identity
    reduces to 0."""
    expr = sp.expand(expr)
    sines = {sp.sin(a): a for a in angles}
    powers = {p: p.base ** (p.exp % 2) * (1 - sp.cos(sines[p.base]) ** 2) ** (p.exp // 2)
              for p in expr.atoms(sp.Pow) if p.base in sines and p.exp.is_Integer and p.exp >= 2}
    return sp.expand(expr.xreplace(powers)) if powers else expr


@functools.lru_cache(maxsize=32)
def _rotating_frame_matrix(convention: str) -> sp.Matrix:
    """``A Ȧᵀ`` for ``A = F1 F2 F3 = P_c(ψ) P_b(θ) P_a(φ)``, term by term of the product rule.

    ``Ȧᵀ = Σ_k F3ᵀ ⋯ Ḟ_kᵀ ⋯ F1ᵀ`` and ``F_j F_jᵀ = 1`` (checked for each factor) leave
    ``A Ȧᵀ = Σ_k P_k (F_k Ḟ_kᵀ) P_kᵀ``, ``P_k = F1 ⋯ F_(k−1)``; every product is reduced in the angles it holds.
    """
    a, b, c = convention
    phi, theta, psi = _EULER_ANGLES
    W, P, held = sp.zeros(3, 3), sp.eye(3), []
    for axis, angle in ((c, psi), (b, theta), (a, phi)):
        F = elementary(axis, angle)
        held.append(angle)
        if (F * F.T).applyfunc(lambda e: _reduce_sin_squares(e, (angle,))) != sp.eye(3):
            raise CheckFailed(f"the elementary rotation about {axis} is not orthogonal: {F}")
        S = (F * F.applyfunc(lambda e: e.diff(t)).T).applyfunc(lambda e: _reduce_sin_squares(e, (angle,)))
        W += (P * S * P.T).applyfunc(lambda e: _reduce_sin_squares(e, held))
        P = P * F
    return W
