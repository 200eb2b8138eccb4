"""Linear stability of a family of steady motions, proven: the characteristic polynomial on the reduced state, the
conditions for spectral (or, with damping, asymptotic) stability as SymPy inequalities, and an energy–Casimir
Lyapunov function where the second variation is definite.

The linearisation
    About a member ``x₀`` of a family, ``δẋ = J δx`` with ``J = ∂f/∂x − ν G`` (``ν`` the family's drift about a
    symmetry axis, ``G`` its generator: the motion is linearised in the frame that turns with it). Every integral
    ``C`` of the model (proven conserved, invariant under the symmetry) gives a left null vector, ``∇C(x₀)ᵀ J = 0``,
    so ``J`` maps into the level set's tangent space ``T`` and acts as zero on the quotient; the orbit of the
    symmetry through ``x₀`` is a right null vector inside ``T``. Hence ``det(λ − J) = λ^(r+g) P(λ)`` with ``r`` the
    rank of the integrals' gradients at ``x₀`` and ``g`` the orbit's dimension: ``P`` is the characteristic
    polynomial of the *reduced* state — on ``|Γ| = 1``, on the level sets of ``L·Γ``, ``|L|²``, the cyclic momentum
    ``L·e`` and the energy, modulo the drift — and its zero roots are no longer the trivial modes of the family.
    (The division is checked: the low coefficients must vanish identically.)

The conditions
    Conservative model (``P`` even, ``P(λ) = Q(λ²)``): spectrally stable iff every root of ``Q`` is real and ≤ 0 —
    ``Q`` of degree 1: its constant ≥ 0; degree 2, ``μ² + bμ + c``: ``b ≥ 0, c ≥ 0, b² − 4c ≥ 0``; degree 3: its
    coefficients and discriminant ≥ 0; higher: coefficients ≥ 0 and Hermite's matrix of power sums positive
    semidefinite (every principal minor ≥ 0). Otherwise (damping) asymptotically stable iff the Hurwitz determinants
    ``Δ_1 … Δ_n`` of the monic ``P`` are all > 0 (Routh–Hurwitz, implemented here: SymPy 1.14 has none).
    Each condition is factored and simplified with what is known of the body (its principal moments and its mass are
    positive): squares and positive factors drop out, a quadratic with a positive leading coefficient and a
    non-positive discriminant is ≥ 0.

Nonlinear stability (energy–Casimir, Arnold)
    For a conservative model, ``H = E − Σ μ_i C_i`` with multipliers making ``x₀`` critical (``∇H(x₀) = 0``); if the
    second variation ``δ²H`` is definite on ``T`` (modulo the orbit), ``H`` is a Lyapunov function: the member is
    stable (modulo the symmetry). Definiteness by Sylvester's criterion on the leading principal minors.

Examples
--------
>>> from eulersym.model.cli import load
>>> from eulersym.model.steady import steady_motions
>>> top = steady_motions(load("lagrange-top")).named("rotation about e3, e3 up")   # the sleeping top
>>> st = top.stability()
>>> st.characteristic_polynomial
I1**2*lam**4 + M**2*g**2*l**2 + lam**2*(-2*I1*M*g*l + I3**2*s**2)
>>> st.conditions
(-2*I1*M*g*l + I3**2*s**2 >= 0) & (Eq(s, 0) | (-4*I1*M*g*l + I3**2*s**2 >= 0))
>>> st.classify({"s": 150.0}), st.classify({"s": 10.0})
('spectrally stable', 'unstable')
"""

from __future__ import annotations

import functools
import itertools
import random
from dataclasses import dataclass

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.model._exact import DRIFT, PSI, THETA, _generator_on_values, _holds, _is_zero, _tidy, _trig
from eulersym.model.mechanics import GAMMA, OMEGA, Q, t

__all__ = ["LAM", "Stability", "Lyapunov", "stability", "hurwitz_conditions", "real_nonpositive_roots",
           "CLASSES"]

#: The eigenvalue symbol of characteristic polynomials.
LAM = sp.Symbol("lam")
#: What :meth:`Stability.classify` answers.
CLASSES = ("unstable", "spectrally stable", "asymptotically stable")


# ----------------------------------------------------------------------------------------------------------------
# Signs: what the body says about its parameters, and conditions simplified with it


def positive_parameters(mech, R=None) -> frozenset:
    """The parameters a body needs positive: those that alone make a principal moment or the mass (``I1``,
    ``2*C``, ``M``). Other parameters (a length, gravity, a rotor's momentum) may take either sign. ``R``: the
    principal axes (columns, model frame) when the tensor is full.

    Examples
    --------
    >>> from eulersym.model.cli import load
    >>> sorted(s.name for s in positive_parameters(load("lagrange-top").mechanics))
    ['I1', 'I3', 'M']
    """
    R = sp.eye(3) if R is None else sp.Matrix(R)
    moments = [(R.T * sp.Matrix(mech.inertia) * R)[k, k] for k in range(3)]
    out = set()
    params = set(mech.parameter_symbols)
    for expr in (*moments, mech.mass):
        expr = sp.sympify(expr)
        syms = expr.free_symbols & params
        if len(syms) == 1:
            p = next(iter(syms))
            ratio = sp.cancel(expr / p)
            if ratio.is_number and ratio > 0:
                out.add(p)
    return frozenset(out)


def _positive_view(expr, positive):
    """``expr`` with the positive parameters replaced by positive dummies (SymPy's assumptions then see them)."""
    sub = {p: sp.Dummy(p.name, positive=True) for p in positive}
    return expr.xreplace(sub), sub


def _is_positive(expr, positive) -> bool:
    view, _ = _positive_view(sp.sympify(expr), positive)
    return view.is_positive is True


def _factor_sign(f, positive, deep: bool = True) -> tuple:
    """``(sign, strict)`` of a factor when it is known — a positive parameter's expression ``(+1, True)``, its
    negative ``(-1, True)``, ``1 ± cos x`` ``(+1, False)``, ``cos x − 1`` ``(-1, False)``, a manifestly
    non-negative quadratic form ``(+1, False)`` — else ``(0, False)``."""
    if _is_positive(f, positive):
        return 1, True
    if _is_positive(-f, positive):
        return -1, True
    if deep and f.free_symbols:
        if _is_nonnegative(f, positive, depth=1):
            return 1, False
        if _is_nonnegative(-f, positive, depth=1):
            return -1, False
    for trig in f.atoms(sp.cos, sp.sin):
        for sign in (1, -1):
            for offset in (1, -1):
                if _is_zero(f - sign * (trig + offset)):
                    return (sign if offset == 1 else -sign), False
    view, _ = _positive_view(f, positive)
    if view.is_nonnegative is True:
        return 1, False
    if view.is_nonpositive is True:
        return -1, False
    return 0, False


def _is_nonnegative(expr, positive, depth: int = 0) -> bool:
    """Manifestly ≥ 0: every factor of known sign with an even count of negative ones (squares count as
    non-negative), or a quadratic ``a v² + b v + c`` in one of its symbols (or in a square ``v²``) with ``a ≥ 0``,
    ``c ≥ 0`` and ``4ac − b² ≥ 0`` (each shown the same way)."""
    expr = sp.expand(sp.sympify(expr))
    if expr.is_number:
        return bool(expr >= 0)
    content, factors = sp.factor_list(expr)
    sign = 1 if content > 0 else -1
    known = True
    for f, k in factors:
        if k % 2 == 0:
            continue
        fs, _ = _factor_sign(f, positive, deep=False)
        if fs == 0:
            known = False
            break
        sign *= fs
    if known:
        return sign > 0
    if depth >= 3:
        return False
    generators = sorted(expr.free_symbols, key=str) + sorted(expr.atoms(sp.cos, sp.sin), key=str)
    for v in generators:
        for even in (False, True):
            p = _as_poly(expr, v, even=even)
            if p is None or p.degree() != 2:
                continue
            a, b, c = p.all_coeffs()
            if (_is_nonnegative(a, positive, depth + 1) and _is_nonnegative(c, positive, depth + 1)
                    and _is_nonnegative(sp.expand(4 * a * c - b ** 2), positive, depth + 1)):
                return True
    return False


def _as_poly(expr, v, even: bool = False):
    """``expr`` as a polynomial in ``v`` (``even``: in ``v²``, when only even powers occur), or None."""
    try:
        p = sp.Poly(expr, v)
    except sp.PolynomialError:
        return None
    if any(c.has(v) for c in p.all_coeffs()):
        return None
    if not even:
        return p
    terms = p.terms()
    if any(m[0] % 2 for m, _ in terms):
        return None
    w = sp.Dummy("w")
    return sp.Poly(sum(c * w ** (m[0] // 2) for m, c in terms), w)


def _sign_condition(expr, positive, *, strict: bool):
    """``expr ≥ 0`` (``strict``: ``> 0``) simplified: factors of known sign dropped (their zeros kept as
    alternatives, or excluded), squares turned into the alternative ``f = 0`` (or the requirement ``f ≠ 0``), a
    remainder that is manifestly ≥ 0 made True. The remaining factors stay factored."""
    expr = sp.sympify(expr)
    if expr.is_number:
        value = expr.evalf(30)
        return sp.true if (value > 0 or (not strict and value == 0)) else sp.false
    num, den = sp.fraction(sp.together(expr))
    sign = 1
    residual = []
    zeros, nonzeros = [], []
    for part, is_den in ((num, False), (den, True)):
        content, factors = sp.factor_list(sp.expand(part))
        if content < 0:
            sign = -sign
        for f, k in factors:
            fs, always = _factor_sign(f, positive)
            if fs:
                if k % 2:
                    sign *= fs
                if not always and not is_den:
                    (nonzeros if strict else zeros).append(f)
                continue
            if k % 2 == 0:
                if not is_den:
                    (nonzeros if strict else zeros).append(_drop_positive(f, positive))
                continue
            residual.append(f)
    core = sp.Mul(*residual)
    if sign < 0:
        core = -core if len(residual) != 1 else sp.expand(-core)
    if not residual:
        base = sp.true if sign > 0 else sp.false
        if not strict and sign < 0:
            base = sp.false
    elif not strict and _is_nonnegative(sp.expand(sign * sp.Mul(*residual)), positive):
        base = sp.true
    elif strict and _is_nonnegative(sp.expand(-sign * sp.Mul(*residual)), positive):
        base = sp.false
    else:
        base = sp.StrictGreaterThan(core, 0) if strict else sp.GreaterThan(core, 0)
    if strict:
        return sp.And(base, *[sp.Ne(z, 0) for z in nonzeros])
    if base is sp.true:
        return sp.true
    return sp.Or(base, *[sp.Eq(z, 0) for z in zeros])


def _drop_positive(f, positive):
    content, factors = sp.factor_list(f)
    out = sp.Integer(1)
    for g, k in factors:
        if not _is_positive(g, positive):
            out *= g ** k
    return out


# ----------------------------------------------------------------------------------------------------------------
# Polynomials: real non-positive roots (conservative) and Hurwitz (asymptotic)


def _monic(coefficients) -> list:
    cs = [sp.sympify(c) for c in coefficients]
    if not cs or cs[0] != 1:
        raise InvalidInput("coefficients", cs, "a monic polynomial's coefficients, leading 1 first")
    return cs


def real_nonpositive_roots(coefficients, positive=frozenset()):
    """The condition that a monic polynomial ``μⁿ + c₁ μⁿ⁻¹ + … + cₙ`` has only real roots ≤ 0.

    Parameters
    ----------
    coefficients : sequence
        ``[1, c1, ..., cn]`` (SymPy expressions).
    positive : set of Symbol
        Symbols known positive (for simplification).

    Examples
    --------
    >>> b, c = sp.symbols("b c", real=True)
    >>> real_nonpositive_roots([1, b, c])
    (b >= 0) & (c >= 0) & (b**2 - 4*c >= 0)
    """
    cs = _monic(coefficients)
    n = len(cs) - 1
    if n == 0:
        return sp.true
    conds = [_sign_condition(c, positive, strict=False) for c in cs[1:]]
    if n >= 2:
        mu = sp.Dummy("mu")
        poly = sp.Poly(sum(c * mu ** (n - k) for k, c in enumerate(cs)), mu)
        if n <= 3:
            conds.append(_sign_condition(sp.discriminant(poly), positive, strict=False))
        else:
            H = _hermite_matrix(poly)
            for size in range(1, n + 1):
                for rows in itertools.combinations(range(n), size):
                    minor = _det(H.extract(list(rows), list(rows)))
                    conds.append(_sign_condition(minor, positive, strict=False))
    return sp.And(*conds)


def _hermite_matrix(poly):
    """Hermite's matrix ``H_jk = p_{j+k}`` of the power sums of the roots (Newton's identities): positive
    semidefinite iff every root is real."""
    n = poly.degree()
    a = poly.all_coeffs()  # monic
    p = [sp.Integer(n)]
    for k in range(1, 2 * n - 1):
        s = -k * a[k] if k <= n else sp.Integer(0)
        for i in range(1, k):
            if i <= n:
                s -= a[i] * p[k - i]
        p.append(sp.expand(s))
    return sp.Matrix(n, n, lambda j, k: p[j + k])


def hurwitz_conditions(coefficients, positive=frozenset()):
    """Routh–Hurwitz: every root of the monic ``λⁿ + a₁ λⁿ⁻¹ + … + aₙ`` has a negative real part iff the leading
    principal minors ``Δ_k`` of the Hurwitz matrix ``H_ij = a_{2j−i}`` (``a₀ = 1``, ``a_k = 0`` outside ``0..n``)
    are all positive.

    Examples
    --------
    >>> a1, a2, a3 = sp.symbols("a1 a2 a3", real=True)
    >>> hurwitz_conditions([1, a1, a2, a3])
    (a1 > 0) & (a3 > 0) & (a1*a2 - a3 > 0)
    """
    cs = _monic(coefficients)
    n = len(cs) - 1
    if n == 0:
        return sp.true

    def a(k):
        return cs[k] if 0 <= k <= n else sp.Integer(0)

    H = sp.Matrix(n, n, lambda i, j: a(2 * (j + 1) - (i + 1)))
    conds = []
    for k in range(1, n + 1):
        minor = _det(H[:k, :k])
        if k == n and n > 1:
            # Δ_n = a_n Δ_{n-1}: with Δ_{n-1} > 0 the last condition is a_n > 0
            conds.append(_sign_condition(cs[n], positive, strict=True))
        else:
            conds.append(_sign_condition(minor, positive, strict=True))
    return sp.And(*conds)


# ----------------------------------------------------------------------------------------------------------------
# The result


@dataclass(eq=False)
class Lyapunov:
    """An energy–Casimir Lyapunov function of a family and where it proves nonlinear stability.

    Attributes
    ----------
    function : sympy.Expr
        ``H = E − Σ μ_i C_i`` in the state names, the multipliers written out (functions of the family symbols).
    multipliers : dict
        Integral name → ``μ_i``.
    minors : tuple
        Sylvester's leading principal minors of ``δ²H`` on the level set's tangent space, modulo the orbit.
    condition : sympy Boolean
        ``δ²H`` definite (all minors > 0, or alternating): the member is stable (modulo the symmetry).
    free : tuple of Symbol
        Multipliers the member leaves free (``kappa1``…) that ``condition`` still holds: stable where it holds for
        some value of them. Empty when none, or when they were eliminated exactly.
    """

    function: object
    multipliers: dict
    minors: tuple
    condition: object
    free: tuple = ()


class Stability:
    """The linear stability of a family of steady motions (see the module docstring).

    Attributes
    ----------
    family : Family
    characteristic_polynomial : sympy.Expr
        ``P(λ)`` in ``lam`` on the reduced state (the family's trivial zero modes removed), its leading coefficient
        cleared of a monomial denominator; its roots are the reduced linearisation's eigenvalues.
    conditions : sympy Boolean
        Where the family is spectrally stable (conservative model) or asymptotically stable (``dissipative``).
    dissipative : bool
        True when ``P`` is not even in λ (damping): ``conditions`` are Hurwitz's.
    reduced : str
        What was divided out of ``det(λ − J)``, in words.
    chart : tuple or None
        ``(u, expression)`` when the family's formulas carry a root (a quadratic's): ``readable()`` writes ``P`` and
        the conditions with the state component ``u`` standing for it — rational, and shorter.
    lyapunov : Lyapunov or None
        An energy–Casimir function and its condition, where one proves nonlinear stability (computed on first use).
    """

    def __init__(self, family, polynomial, conditions, dissipative, reduced, coefficients, chart, readable,
                 lyapunov_inputs, jacobian=None, removed: int = 0):
        self.family = family
        self._jacobian_public = jacobian
        self._removed = removed
        self._polynomial = polynomial
        self.conditions = conditions
        self.dissipative = dissipative
        self.reduced = reduced
        self.chart = chart
        self._coefficients = tuple(coefficients)
        self._readable = readable
        self._lyapunov_inputs = lyapunov_inputs

    def __repr__(self) -> str:
        return f"Stability({self.family.name!r}, conditions={self.conditions})"

    @functools.cached_property
    def characteristic_polynomial(self):
        """``P(λ)`` (see the class docstring); written out on first use."""
        if self._polynomial is None and self._coefficients:
            self._polynomial = _pretty_poly(self._coefficients)
        return self._polynomial

    @functools.cached_property
    def lyapunov(self):
        """The energy–Casimir Lyapunov function (:class:`Lyapunov`) or None (see the module docstring)."""
        if self._lyapunov_inputs is None:
            return None
        return _lyapunov(*self._lyapunov_inputs)

    def readable(self) -> tuple:
        """``(P, conditions, where)``: in the chart (``where = "u = expression"``) when there is one, else the
        public forms and ``""``.

        Examples
        --------
        >>> from eulersym.model.cli import load
        >>> from eulersym.model.steady import steady_motions
        >>> P, conditions, where = steady_motions(load("lagrange-top"))[2].stability().readable()
        >>> conditions, where.split(" = ")[0]
        (True, 'omega2')
        """
        if self._readable is None:
            self._readable = (self.characteristic_polynomial, self.conditions, "")
        return self._readable

    def _point(self, values) -> dict:
        fam = self.family
        point = fam.values(values)
        if not fam.members(values):
            raise InvalidInput("values", dict(values or {}), f"numbers where {fam.name!r} exists "
                               f"({fam.exists}{', ' + ', '.join(map(str, fam.where)) if fam.where else ''})")
        return point

    def eigenvalues(self, values=None):
        """The roots of the reduced characteristic polynomial at numbers (30 digits), as a complex array sorted by
        real part, then imaginary part.

        Examples
        --------
        >>> from eulersym.model.cli import load
        >>> from eulersym.model.steady import steady_motions
        >>> st = steady_motions(load("torque-free")).named("rotation about e2").stability()
        >>> st.eigenvalues({"s": 1.0}).round(6)          # ±ω0 √((I3 − I2)(I2 − I1)/(I1 I3)) = ±1/√8
        array([-0.353553+0.j,  0.353553+0.j])
        """
        import mpmath
        import numpy as np

        point = self._point(values)
        coeffs = [sp.sympify(c).xreplace(point).evalf(40) for c in self._coefficients]
        if len(coeffs) <= 1:
            return np.zeros(0, dtype=complex)
        with mpmath.workdps(40):
            roots = mpmath.polyroots([mpmath.mpmathify(complex(c)) if not c.is_real else mpmath.mpf(str(c))
                                      for c in coeffs], maxsteps=400, extraprec=80)
        out = np.array([complex(r) for r in roots], dtype=complex)
        out.real[np.abs(out.real) < 1e-25 * (1 + np.abs(out))] = 0.0
        return out[np.lexsort((out.imag, out.real))]

    def classify(self, values=None) -> str:
        """``"unstable"``, ``"spectrally stable"`` or ``"asymptotically stable"`` at numbers, from the proven
        conditions (a damped member outside Hurwitz's conditions is spectrally stable when no root has a
        positive real part, which its eigenvalues decide).

        Examples
        --------
        >>> from eulersym.model.cli import load
        >>> from eulersym.model.steady import steady_motions
        >>> [f.stability().classify({"s": 1.0}) for f in steady_motions(load("torque-free"))]
        ['spectrally stable', 'unstable', 'spectrally stable']
        """
        point = self._point(values)
        holds = _holds(self.conditions, point)
        if not self.dissipative:
            return "spectrally stable" if holds else "unstable"
        if holds:
            return "asymptotically stable"
        roots = self.eigenvalues(values)
        scale = 1.0 + (max(abs(roots)) if len(roots) else 0.0)
        return "spectrally stable" if (len(roots) == 0 or max(roots.real) <= 1e-20 * scale) else "unstable"


# ----------------------------------------------------------------------------------------------------------------
# The computation


def _integrals(ctx, symmetries):
    """The model's proven integrals on the reduced state, invariant under the symmetries used: ``{name: H}``."""
    from eulersym.model.integrals import invariants

    out = {}
    x = list(ctx.x)
    for name, verdict in invariants(ctx.mech).items():
        if not verdict.conserved:
            continue
        H = sp.sympify(verdict.expression)
        from eulersym.model.integrals import _rational

        H = _rational(H)
        if H.has(t) or (H.has(*Q) and Q[0] not in x) or (H.has(*GAMMA) and GAMMA[0] not in x):
            continue
        grad = [sp.diff(H, s) for s in x]
        ok = True
        for e in symmetries:
            Gx = _generator_on_values(x, x, e)
            if not _is_zero(sum(g * v for g, v in zip(grad, Gx))):
                ok = False
        if ok and any(g != 0 for g in grad):
            out[name] = H
    return out


def _numeric_rank(rows, point, dps: int = 40) -> int:
    """The rank of a matrix of expressions at a point, from the eigenvalues of ``M Mᴴ`` at ``dps`` digits (an
    eigenvalue below ``10^(−dps/2)`` of the largest counts as zero)."""
    import mpmath

    if not rows:
        return 0
    with mpmath.workdps(dps):
        M = mpmath.matrix([[mpmath.mpmathify(complex(sp.sympify(e).xreplace(point).evalf(dps))) for e in row]
                           for row in rows])
        ev = mpmath.eighe(M * M.H, eigvals_only=True)
        big = max(abs(v) for v in ev)
        if big == 0:
            return 0
        return sum(1 for v in ev if abs(v) > big * mpmath.mpf(10) ** (-(dps // 2)))


def _random_family_point(fam, chart_symbols, rng, tries: int = 50):
    """A random real member's exact point: parameters at random positive-ish values near their defaults and the
    family's (chart) symbols random, where the family exists."""
    mech = fam._context.mech
    for _ in range(tries):
        point = {}
        for s, v in mech.parameters:
            v = sp.Rational(str(v))
            point[s] = v * sp.Rational(rng.randint(70, 130), 100) if v != 0 else sp.Rational(rng.randint(1, 9), 10)
        for s in chart_symbols:
            if s in (THETA, PSI):
                point[s] = sp.Rational(rng.randint(5, 300), 100)
            else:
                point[s] = sp.Rational(rng.randint(-400, 400), 37) or sp.Rational(1, 3)
        ok = True
        for cond in (fam.exists, *fam.where):
            if _holds(cond, point) is False:
                ok = False
        if fam._chart is not None:
            u = fam._chart[0]
            # the chart point must be real: the root it stands for is real where the relation has real roots
            ok = ok and True
        if ok:
            return point
    return None


class _NumericStability(Stability):
    """The stability of a family without a closed form: decided member by member, at numbers, from the
    eigenvalues of the linearisation at the member (30 digits), the trivial zero modes (the integrals' level sets)
    removed. ``characteristic_polynomial`` and ``conditions`` are None: there is no closed form to state them in."""

    def _member(self, values):
        fam = self.family
        values = dict(values or {})
        chosen = {k: values.pop(k) for k in list(values) if k in fam.state}
        members = fam.members(values)
        if not members:
            raise InvalidInput("values", dict(values), f"numbers where {fam.name!r} has a member")
        if chosen:
            def distance(m):
                return sum((m[k] - float(v)) ** 2 for k, v in chosen.items())
            return min(members, key=distance), values
        if len(members) > 1:
            raise InvalidInput("values", dict(values), f"the state of one of the {len(members)} members of "
                               f"{fam.name!r} at these numbers (e.g. omega2=...): "
                               + "; ".join(", ".join(f"{k} = {v:.6g}" for k, v in m.items()) for m in members))
        return members[0], values

    def _spectrum(self, values, *, floats: bool = False):
        """``(point, x, eigenvalues)``: the member's point, the state and the eigenvalues of ``∂f/∂x`` there at 30
        digits (``floats``: the family's own values taken as 30-digit floats too)."""
        import mpmath

        member, rest = self._member(values)
        fam = self.family
        ctx = fam._context
        point = fam.values(rest)
        if floats:
            point = {k: sp.Float(v, 30) for k, v in point.items()}
        point.update({sp.Symbol(k, real=True): sp.Float(v, 30) for k, v in member.items()})
        x = list(ctx.x)
        J = sp.Matrix(ctx.f).jacobian(x).xreplace(point).evalf(30)
        with mpmath.workdps(30):
            ev = mpmath.eig(mpmath.matrix([[complex(e) for e in row] for row in J.tolist()]), left=False,
                            right=False)
        return point, x, [complex(v) for v in ev]

    def eigenvalues(self, values=None):
        import numpy as np

        point, x, ev = self._spectrum(values)
        ev = sorted(ev, key=abs)
        ctx = self.family._context
        integrals = _integrals(ctx, [])
        grads = [[sp.diff(H, s).xreplace(point) for s in x] for H in integrals.values()]
        r = _numeric_rank(grads, {}) if grads else 0
        out = np.array(ev[r:], dtype=complex)
        return out[np.lexsort((out.imag, out.real))]

    def classify(self, values=None) -> str:
        roots = self.eigenvalues(values)
        return _verdict(roots, 1e-12 * (1.0 + (max(abs(roots)) if len(roots) else 0.0)))


def _verdict(roots, tol: float) -> str:
    """The class of a linearisation from its eigenvalues (trivial zero modes already dropped): the largest real part
    below ``−tol`` asymptotically stable, within ``±tol`` spectrally stable, above it unstable."""
    top = max(roots.real) if len(roots) else 0.0
    if top < -tol:
        return "asymptotically stable"
    return "spectrally stable" if top <= tol else "unstable"


def _numeric_stability(fam) -> Stability:
    return _NumericStability(fam, None, None, True, "numeric: the integrals' zero modes removed at each member",
                             (), None, (None, None, ""), None)


def stability(fam) -> Stability:
    """The stability of a family (see the module docstring): characteristic polynomial, conditions, Lyapunov.

    Parameters
    ----------
    fam : Family
        From :func:`eulersym.model.steady.steady_motions`.

    Examples
    --------
    >>> from eulersym.model.cli import load
    >>> from eulersym.model.steady import steady_motions
    >>> st = steady_motions(load("torque-free")).named("rotation about e2").stability()
    >>> st.characteristic_polynomial
    I1*I3*lam**2 - s**2*(I1 - I2)*(I2 - I3)
    >>> st.conditions
    Eq(s, 0) | (-(I1 - I2)*(I2 - I3) >= 0)
    """
    if not (hasattr(fam, "_context") and hasattr(fam, "closed_form")):
        raise InvalidInput("family", fam, "a Family from eulersym.model.steady.steady_motions")
    return _stability(fam)


@functools.lru_cache(maxsize=64)
def _stability(fam) -> Stability:
    linearise = getattr(fam._context, "linearise", None)
    if linearise is not None:  # a body on a plane: its contact equations (eulersym.model.rolling_steady)
        return linearise(fam)
    if not fam.closed_form:
        return _numeric_stability(fam)
    ctx = fam._context
    mech = ctx.mech
    x = list(ctx.x)
    positive = positive_parameters(mech, ctx.R)
    axes = [sp.Matrix(axis) for _, axis, _ in ctx.symmetries]
    fixed_point = False
    if axes and not fam.drift:
        # a member the symmetry fixes (ω and Γ along e) is steady in every frame turning about e: it is linearised
        # in the one that does not turn with its spin (ν = −ω·e), the text's frame for the sleeping top; the real
        # parts of the spectrum do not depend on the choice
        orbit = _generator_on_values(x, [sp.sympify(fam.state[s.name]) for s in x], axes[0])
        fixed_point = all(_is_zero(e) for e in orbit)
        if not fixed_point:
            axes = []
    # the rates in the frame turning with the family
    F = list(ctx.f)
    if axes:
        Gx = _generator_on_values(x, x, axes[0])
        F = [fi - DRIFT * gi for fi, gi in zip(F, Gx)]
    J = sp.Matrix(F).jacobian(x)
    # the point: the chart's rational state where there is one, else the state itself
    if fam._chart is not None:
        u, eliminated, value, chart_state = fam._chart
        point = {s: chart_state[s] for s in x}
        point[DRIFT] = chart_state.get(DRIFT, sp.Integer(0))
        chart_symbols = [u if s == eliminated else s for s in fam.family]
        back = {u: fam.state[u.name]}
    else:
        point = {s: sp.sympify(fam.state[s.name]) for s in x}
        drift = next(iter(fam.drift.values())) if fam.drift else sp.Integer(0)
        if fixed_point:
            drift = -_tidy(sum(point[w] * e for w, e in zip(OMEGA, axes[0])))
        point[DRIFT] = drift
        chart_symbols = list(fam.family)
        back = {}
    key = (id(ctx), tuple(sorted((str(k), sp.srepr(v)) for k, v in point.items())), len(axes))
    analysis = _ANALYSES.get(key)
    if analysis is None:
        analysis = _analyse(fam, J, point, x, axes, chart_symbols, positive)
        _ANALYSES[key] = analysis
    coeffs, k, notes, even, cond_chart, integrals, J0 = analysis
    lyapunov_inputs = (fam, integrals, point, positive, axes, back, x) if (even and "E" in integrals) else None
    conditions = cond_chart.xreplace(back) if back else cond_chart
    public_coeffs = tuple(c.xreplace(back) for c in coeffs) if back else tuple(coeffs)
    chart = None
    readable = None
    if back:
        (u, value), = back.items()
        chart = (u, value)
        readable = (_pretty_poly(coeffs), cond_chart, f"{u} = {value}")
    jacobian = J0.xreplace(back) if back else J0
    return Stability(fam, None, conditions, not even, "; ".join(notes), public_coeffs, chart, readable,
                     lyapunov_inputs, jacobian, k)


#: Analyses shared by families with the same point (the two roots of one chart): key → results.
_ANALYSES: dict = {}


def _analyse(fam, J, point, x, axes, chart_symbols, positive):
    """The characteristic polynomial at a point, its trivial zero modes divided out, and the conditions."""
    ctx = fam._context
    J0 = J.xreplace(point).applyfunc(_cancel)
    N = len(x)
    # sin θ and cos θ as plain symbols for the characteristic polynomial (a rational-function domain: fast), then
    # back, with sin² θ = 1 − cos² θ
    trig = sorted(J0.atoms(sp.sin, sp.cos), key=str)
    plain = {f: sp.Dummy(f.func.__name__) for f in trig}
    back = {d: f for f, d in plain.items()}
    full = [_cancel(c.xreplace(back)) for c in J0.xreplace(plain).charpoly(LAM).all_coeffs()]
    # the trivial zero modes: integrals' gradients (left) and the orbit (right)
    rng = random.Random(5)
    integrals = _integrals(ctx, axes)
    sample = _random_family_point(fam, chart_symbols, rng)
    notes = []
    k = 0
    if sample is not None:
        grads = [[sp.diff(H, s).xreplace(point) for s in x] for H in integrals.values()]
        r = _numeric_rank(grads, sample)
        g = 0
        if axes:
            orbit = [e.xreplace(point) for e in _generator_on_values(x, x, axes[0])]
            g = 1 if any(abs(complex(sp.sympify(e).xreplace(sample).evalf(30))) > 1e-25 for e in orbit) else 0
        k = r + g
        low = full[::-1][:k]
        vanish = 0
        for c in low:
            if _vanishes(c, fam, chart_symbols, rng):
                vanish += 1
            else:
                break
        if vanish < k:
            notes.append(f"expected λ^{k} from the integrals and the orbit, found λ^{vanish}")
            k = vanish
        names = ", ".join(integrals) or "none"
        notes.append(f"λ^{k} divided out: the level sets of {names}" + (" and the orbit of the symmetry" if g else ""))
    coeffs = [_factor(c) for c in full[:N - k + 1]]
    n = len(coeffs) - 1
    odd = [coeffs[i] for i in range(1, n + 1, 2)]
    even = all(_vanishes(c, fam, chart_symbols, rng) for c in odd)
    if even:
        cond_chart = real_nonpositive_roots([coeffs[i] for i in range(0, n + 1, 2)], positive)
    else:
        cond_chart = hurwitz_conditions(coeffs, positive)
    return coeffs, k, notes, even, cond_chart, integrals, J0


def _cancel(expr):
    """One fraction, cancelled, with ``sin² θ = 1 − cos² θ`` (cheap: no factoring)."""
    expr = sp.sympify(expr)
    if expr.is_number:
        return expr
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    if num.has(THETA) or den.has(THETA):
        num, den = _trig(sp.expand(num)), _trig(sp.expand(den))
        return sp.cancel(num / den)
    return num / den


def _factor(expr):
    expr = sp.sympify(expr)
    if expr.is_number or expr.has(sp.sqrt):
        return expr
    return sp.factor(expr)


def _det(M):
    """A small symbolic determinant through SymPy's domain matrices (no expression simplification on the way)."""
    if M.shape[0] == 0:
        return sp.Integer(1)
    from sympy.polys.matrices import DomainMatrix

    dM = DomainMatrix.from_Matrix(M)
    return dM.domain.to_sympy(dM.det())


def _pretty_poly(coeffs):
    """``Σ c_i λ^(n−i)`` times a common monomial denominator of the coefficients (``I1**2*lam**4 + …``)."""
    n = len(coeffs) - 1
    common = sp.Integer(1)
    dens = [sp.denom(sp.together(c)) for c in coeffs if not c.has(sp.sqrt)]
    d = functools.reduce(sp.lcm, dens) if dens else sp.Integer(1)
    if d != 1 and len(sp.Add.make_args(sp.expand(d))) == 1:
        common = d
    terms = []
    for c in coeffs:
        c = c * common
        terms.append(sp.factor(sp.cancel(c)) if not c.has(sp.sqrt) else sp.radsimp(sp.cancel(c)))
    return sp.Add(*[c * LAM ** (n - i) for i, c in enumerate(terms)])


def _vanishes(expr, fam, symbols, rng) -> bool:
    expr = sp.sympify(expr)
    if expr == 0:
        return True
    if _is_zero(expr):
        return True
    for _ in range(3):
        point = _random_family_point(fam, symbols, rng)
        if point is None:
            return False
        v = expr.xreplace(point).evalf(30)
        if not v.is_number or abs(complex(v)) > 1e-20:
            return False
    return True


def _lyapunov(fam, integrals, point, positive, axes, back, x):
    """Energy–Casimir: multipliers, the second variation on the level set modulo the orbit, Sylvester. Multipliers
    left free by dependent gradients (a member where the integrals' gradients are dependent, such as the sleeping
    top) are kept as ``kappa``: the member is stable if *some* choice makes ``δ²H`` definite, and a single free
    multiplier is eliminated exactly (a quadratic requirement ``q(κ) > 0`` holds for some κ iff its leading
    coefficient is positive or its discriminant is)."""
    names = [n for n in integrals if n != "E"]
    E = integrals["E"]
    Cs = [integrals[n] for n in names]
    mus = sp.symbols(f"mu0:{len(Cs)}")
    H = E - sum(m * C for m, C in zip(mus, Cs))
    grad = [sp.diff(H, s).xreplace(point) for s in x]
    A = sp.Matrix([[sp.diff(g, m) for m in mus] for g in grad])
    rhs = sp.Matrix([-g.xreplace({m: 0 for m in mus}) for g in grad])
    values = _solve_linear(A, rhs)
    if values is None:
        return None
    free = sorted(set().union(*[sp.sympify(v).free_symbols for v in values]) & set(mus), key=str)
    kappas = sp.symbols(f"kappa1:{len(free) + 1}", real=True) if free else ()
    rename = dict(zip(free, kappas))
    sol = {m: _tidy(sp.sympify(v).xreplace(rename)) for m, v in zip(mus, values)}
    Hs = sp.hessian(H.xreplace(sol), x).xreplace(point).applyfunc(_cancel)
    rows = [[_tidy(sp.diff(C, s).xreplace(point)) for s in x] for C in Cs]
    if axes:
        orbit = [_tidy(e.xreplace(point)) for e in _generator_on_values(x, x, axes[0])]
        if any(not _is_zero(e) for e in orbit):
            rows.append(orbit)
    A = sp.Matrix(rows) if rows else sp.zeros(0, len(x))
    basis = (A.nullspace(simplify=_tidy, iszerofunc=_is_zero) if rows
             else [sp.eye(len(x))[:, i] for i in range(len(x))])
    if not basis:
        return None
    B = sp.Matrix.hstack(*basis)
    Rm = (B.T * Hs * B).applyfunc(_cancel)
    n = Rm.shape[0]
    minors = tuple(_factor(_cancel(_det(Rm[:k, :k]))) for k in range(1, n + 1))
    branches = []
    for signs in ([1] * n, [(-1) ** (k + 1) for k in range(n)]):
        branches.append(_definite(minors, signs, kappas, positive))
    condition = sp.Or(*branches)
    if condition is sp.false:
        return None
    kappas = tuple(k for k in kappas if condition.has(k))
    function = H.xreplace(sol)
    if back:
        function = function.xreplace(back)
        condition = condition.xreplace(back)
        minors = tuple(m.xreplace(back) for m in minors)
    return Lyapunov(function, {n: sol[m] for n, m in zip(names, mus)}, minors, condition, tuple(kappas))


def _solve_linear(A, b):
    """A solution of ``A μ = b`` (free unknowns left as themselves), by Gauss–Jordan with an exact zero test that
    knows ``sin² θ + cos² θ = 1``; None when inconsistent."""
    n = A.shape[1]
    aug = A.row_join(b)
    R, pivots = aug.rref(iszerofunc=_is_zero, simplify=_tidy)
    if n in pivots:
        return None
    unknowns = sp.symbols(f"mu0:{n}")
    values = list(unknowns)
    for row, col in enumerate(pivots):
        values[col] = _tidy(R[row, n] - sum(R[row, j] * unknowns[j] for j in range(n) if j not in pivots))
    return values


def _definite(minors, signs, kappas, positive):
    """``sign_k · Δ_k > 0`` for every k, with a single free multiplier κ eliminated where the requirements that
    involve it reduce to one quadratic (or linear) polynomial in κ."""
    fixed, on_kappa = [], []
    for m, sg in zip(minors, signs):
        cond = _sign_condition(sg * m, positive, strict=True)
        if kappas and cond.has(*kappas):
            on_kappa.append(sp.expand(sg * m))
        else:
            fixed.append(cond)
    if not on_kappa:
        return sp.And(*fixed)
    if len(kappas) == 1:
        kappa = kappas[0]
        essential = []
        for m in on_kappa:
            content, factors = sp.factor_list(m)
            sign = 1 if content > 0 else -1
            for f, k in factors:
                fs, _ = _factor_sign(f, positive)
                if fs:
                    sign *= fs ** k
                elif k % 2 == 1:
                    essential.append((f, sign))
                    sign = 1
                elif not f.has(kappa):
                    fixed.append(sp.Ne(f, 0))
        qs = [(f, sg) for f, sg in essential if f.has(kappa)]
        rest = [(f, sg) for f, sg in essential if not f.has(kappa)]
        same = qs and all(_is_zero(f - qs[0][0]) or _is_zero(f + qs[0][0]) for f, _ in qs)
        if same:
            q0 = qs[0][0]
            sigmas = {sg * (1 if _is_zero(f - q0) else -1) for f, sg in qs}
            if len(sigmas) == 1:
                sigma = sigmas.pop()
                p = sp.Poly(sigma * q0, kappa)
                for f, sg in rest:
                    fixed.append(_sign_condition(sg * f, positive, strict=True))
                if p.degree() == 1:
                    return sp.And(*fixed)
                if p.degree() == 2:
                    a, b, c = p.all_coeffs()
                    exists = sp.Or(_sign_condition(a, positive, strict=True),
                                   _sign_condition(b ** 2 - 4 * a * c, positive, strict=True))
                    return sp.And(*fixed, exists)
    # not eliminated: the condition keeps κ (stable if it holds for some κ)
    return sp.And(*fixed, *[_sign_condition(m, positive, strict=True) for m in on_kappa])


class _FrameStability(_NumericStability):
    """The stability of an equilibrium in a turning frame found at numbers (off the frame's axes): the eigenvalues
    of ``∂f/∂x`` at the member (30 digits) with the zero modes of the redundant state (``|q|``, ``|Γ|`` and ``Γ``
    against ``A(q) ẑ``: numerically zero, below 1e-10 of the largest) dropped."""

    def eigenvalues(self, values=None):
        import numpy as np

        _, _, ev = self._spectrum(values, floats=True)
        scale = max([1e-300] + [abs(v) for v in ev])
        out = np.array([v for v in ev if abs(v) > 1e-10 * scale], dtype=complex)
        return out[np.lexsort((out.imag, out.real))]

    def classify(self, values=None) -> str:
        roots = self.eigenvalues(values)
        return _verdict(roots, 1e-9 * (max(abs(roots)) if len(roots) else 1.0))


def _frame_stability(fam) -> Stability:
    return _FrameStability(fam, None, None, True, "numeric: the redundant state's zero modes removed at the member",
                           (), None, (None, None, ""), None)
