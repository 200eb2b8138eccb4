"""Integrals of motion of a model, proven: ``dH/dt`` along the derived flow is zero exactly, or it is not.

The rate of a candidate ``H(t, state)`` along the flow of :func:`eulersym.model.derive.equations` is
``dH/dt = ∂H/∂t + Σ_x ∂H/∂x · ẋ``. Its zero test is :func:`eulersym.compare.compare` against 0 (exact
simplification and seeded random high-precision points). The state carries two constraints that the flow keeps:
``|Γ|² = 1`` (Γ is the unit upward vertical) and ``|q|² = 1`` (a unit quaternion). A rate that is not zero as it
stands is reduced modulo them — the remainder of the numerator on division by ``γ1² + γ2² + γ3² − 1`` (as a
polynomial in ``γ1``) and by ``q0² + q1² + q2² + q3² − 1`` (in ``q0``): a normal form that is zero exactly when the
rate vanishes on the constraint surface — and the verdict says so. A non-conserved candidate comes with a
counterexample: a state *on* the constraint surface (rational points of the unit spheres) where the rate is not
zero, with the parameters at their defaults.

Candidates (:func:`invariants`), as the model's structure implies them:

- ``E`` — the energy ``½ ωᵀ I ω + V`` (``V`` gravity's ``M g c·Γ`` plus the model's potential; a rotor's
  ``h`` does not enter, ``T = ½ ωᵀ I ω``);
- ``Gamma_norm2`` — ``|Γ|²``, and ``L_dot_Gamma`` — ``(I ω + h)·Γ``, when the state carries Γ;
- ``L2`` — ``|I ω + h|²``, when no potential acts (torque-free, or only the model's torque); with a rotor also
  ``L_body2`` — ``|I ω|²``, the body's own part (not conserved: its rate shows the exchange with the rotor);
- ``L_axis`` — ``(I ω + h)·e`` about a symmetry axis ``e`` of ``I`` (two equal principal moments);
- ``q_norm2`` — ``|q|²``;
- ``K`` — Kovalevskaya's integral, when ``I`` has principal moments ``A = A = 2C`` and the centre of mass lies in
  the equatorial plane (``c·e = 0``, ``e`` the symmetry axis): the literature's form
  ``K = (p² − q² − ν γ₁)² + (2 p q − ν γ₂)²``, ``ν = M g |c| / C``, written in the frame ``e₁ = c/|c|``,
  ``e₃ = e``, ``e₂ = e₃ × e₁`` (``p = ω·e₁``, ``q = ω·e₂``, ``γ_k = Γ·e_k``) — so it holds in whatever axes the
  model uses, not only with ``c`` along x.

- ``Jacobi`` — in a frame that turns uniformly at Ω (``[frame] rate``): ``E − Ω·L`` (``Ω·L = to_body(Ω)·(I ω +
  h)``), the Hamiltonian of the motion relative to the frame, ``T₂ − T₀ + V`` of the Lagrangian in the frame's
  coordinates; conserved when the torques come from a potential fixed in the frame.

On a level set (``on=``)
    Some integrals hold only where others take given values: Goryachev–Chaplygin's ``r (p² + q²) − (M g a/C) p γ₃``
    of a top with ``A = B = 4C`` is conserved on ``L·Γ = 0`` only. ``prove(..., on="L_dot_Gamma = 0")`` names
    integrals of the model (:func:`candidates`, each proven conserved first, so the set is invariant) and their
    values; the rate is reduced modulo the ideal of the constraints and of ``C_i − value_i`` (a Gröbner basis over
    the rational functions of the parameters): a zero normal form proves the candidate conserved on that set. A
    counterexample is a rational state on the set (the constraints solved for a component they are linear in)
    where the rate is not zero.

Examples
--------
>>> import sympy as sp
>>> from eulersym.model.mechanics import Mechanics, OMEGA
>>> c = sp.Symbol("c", positive=True)
>>> damped = Mechanics(name="damped", inertia=sp.ImmutableMatrix(sp.diag(1, 2, 3)), mass=sp.Integer(1),
...                    torque=sp.ImmutableMatrix([-c * w for w in OMEGA]), parameters=((c, 0.1),))
>>> v = invariants(damped)["E"]
>>> v.conserved, v.rate
(False, -c*(omega1**2 + omega2**2 + omega3**2))
"""

from __future__ import annotations

import functools
import random
from dataclasses import dataclass

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.model.derive import equations, total_potential
from eulersym.model.mechanics import GAMMA, OMEGA, Q, STATE_SYMBOLS, Mechanics, t

__all__ = ["Verdict", "prove", "invariants", "candidates", "symmetry_axis", "kovalevskaya_integral", "level_set"]

_COUNTEREXAMPLE_POINTS = 8


@dataclass(frozen=True)
class Verdict:
    """Whether a candidate is an integral of motion of a model, and how that was shown.

    Attributes
    ----------
    name : str
    expression : sympy.Expr
        The candidate ``H``, in the model's names.
    conserved : bool
        True when ``dH/dt = 0`` along the flow was shown exactly (on the constraint surface if ``constraints``).
    rate : sympy.Expr
        ``dH/dt``, simplified (and reduced modulo the constraints where that was used); 0 when conserved.
    how : str
        How it was shown, in words.
    counterexample : dict or None
        ``{name: float}``: a state (on ``|Γ| = |q| = 1``), the time and the parameters where the rate is not zero.
    exact : bool
        Whether the verdict is exact (False: no exact proof, the rate vanished at every random point).
    constraints : tuple of str
        The constraints used (``"|Gamma|^2 = 1"``, ``"|q|^2 = 1"``), empty if none was needed.

    Examples
    --------
    >>> import sympy as sp
    >>> v = Verdict("H", sp.Integer(1), True, sp.Integer(0), "identical", None, True, ())
    >>> v.line()
    'H: conserved (identical)'
    """

    name: str
    expression: sp.Expr
    conserved: bool
    rate: sp.Expr
    how: str
    counterexample: dict | None
    exact: bool
    constraints: tuple = ()

    def line(self) -> str:
        """One line for a report."""
        if self.conserved:
            return f"{self.name}: conserved ({self.how})"
        return f"{self.name}: NOT conserved, dH/dt = {self.rate} ({self.how})"


# ----------------------------------------------------------------------------------------------------------------
# Exact numbers


def _rational(expr):
    """Floats → the rationals they print as (``9.81`` → ``981/100``), so that exact proofs see exact numbers."""
    expr = sp.sympify(expr)
    floats = expr.atoms(sp.Float)
    if not floats:
        return expr
    return expr.xreplace({f: sp.Rational(str(f)) for f in floats})


@functools.lru_cache(maxsize=64)
def _flow(mech: Mechanics) -> tuple:
    eqs = equations(mech)
    return eqs.state, tuple(_rational(e) for e in eqs.rhs)


# ----------------------------------------------------------------------------------------------------------------
# The rate and its zero test


def _rate(mech: Mechanics, H) -> sp.Expr:
    state, rhs = _flow(mech)
    rate = sp.diff(H, t)
    for x, xdot in zip(state, rhs):
        d = sp.diff(H, x)
        if d != 0:
            rate += d * xdot
    return rate


_TIDY_LIMIT = 200


def _tidy(expr) -> sp.Expr:
    """A readable form of a rate: one fraction, its numerator expanded and factored when small. A rate larger than
    ``_TIDY_LIMIT`` operations is only expanded (so that terms that cancel, such as ω·(ω × L), are gone): putting a
    gravity-gradient rate over one denominator and factoring it costs seconds and reads no better."""
    if sp.count_ops(expr) > _TIDY_LIMIT:
        return sp.expand(expr)
    num, den = sp.fraction(sp.together(sp.expand(expr)))
    num = sp.expand(num)
    if num == 0:
        return sp.Integer(0)
    if sp.count_ops(num) <= 200:
        try:
            num = sp.factor(num)
        except (sp.PolynomialError, NotImplementedError):  # pragma: no cover - factor of exotic coefficients
            num = sp.factor_terms(num)
    else:
        num = sp.factor_terms(num)
    return num / sp.factor(den)


def _reduce(num, symbols) -> sp.Expr:
    """Remainder of ``num`` on division by ``Σ s² − 1``, as a polynomial in the first symbol (monic there)."""
    if not num.has(*symbols):
        return num
    lead = symbols[0]
    try:
        return sp.expand(sp.rem(sp.expand(num), sum(s ** 2 for s in symbols) - 1, lead))
    except (sp.PolynomialError, sp.GeneratorsNeeded):
        return num


def _constrained(mech: Mechanics, rate) -> tuple:
    """``(reduced rate, constraints used)`` modulo |Γ|² = 1 and |q|² = 1 (only those the rate involves)."""
    state, _ = _flow(mech)
    num, den = sp.fraction(sp.together(sp.expand(rate)))
    used = []
    if GAMMA[0] in state and num.has(*GAMMA):
        new = _reduce(num, GAMMA)
        if new != sp.expand(num):
            used.append("|Gamma|^2 = 1")
        num = new
    if num.has(*Q):
        new = _reduce(num, Q)
        if new != sp.expand(num):
            used.append("|q|^2 = 1")
        num = new
    return num / den, tuple(used)


def _unit_point(rng: random.Random, n: int) -> list:
    """A rational point of the unit sphere in R^n (inverse stereographic projection of a random rational point)."""
    u = [sp.Rational(rng.randint(-40, 40), rng.randint(10, 40)) for _ in range(n - 1)]
    s = sum(x ** 2 for x in u)
    return [2 * x / (1 + s) for x in u] + [(s - 1) / (1 + s)]


def _counterexample(mech: Mechanics, rate, seed: int = 0) -> dict | None:
    """A state on |Γ| = |q| = 1, a time and parameters (defaults first) where ``rate`` is not zero.

    The state is rational and the rate is evaluated at 30 digits from the exact substitution, so a value far from
    zero (above 1e-20) proves that the rate is not identically zero on the constraint surface.
    """
    state, _ = _flow(mech)
    if rate == 0:
        return None
    rng = random.Random(seed)
    params = [(s, sp.Rational(str(v))) for s, v in mech.parameters]
    for attempt in range(_COUNTEREXAMPLE_POINTS):
        point = {w: sp.Rational(rng.randint(-30, 30), 10) for w in OMEGA}
        if GAMMA[0] in state:
            point.update(zip(GAMMA, _unit_point(rng, 3)))
        point.update(zip(Q, _unit_point(rng, 4)))
        point[t] = sp.Rational(rng.randint(0, 30), 10)
        if attempt < _COUNTEREXAMPLE_POINTS // 2:
            point.update(params)
        else:
            point.update({s: sp.Rational(rng.randint(5, 20), 10) for s, _ in params})
        value = sp.sympify(rate).xreplace(point)
        if value.free_symbols:
            continue
        low = value.evalf(30)
        if not (low.is_number and low.is_finite and abs(low) > 1e-20):
            continue
        # An exact zero evaluated with transcendental terms leaves a residue that shrinks with the precision; a
        # true value does not: keep the point only if 50 digits agree with 30.
        high = value.evalf(50)
        if abs(high - low) <= 1e-6 * abs(low):
            return {str(k): float(v) for k, v in sorted(point.items(), key=lambda kv: sp.default_sort_key(kv[0]))}
    return None


def _check_candidate(mech: Mechanics, expr) -> sp.Expr:
    if isinstance(expr, sp.MatrixBase) or not isinstance(expr, sp.Expr):
        raise InvalidInput("candidate", expr, "one scalar SymPy expression (a vector is not an integral)")
    allowed = mech.free_symbols_allowed()
    extra = sorted(expr.free_symbols - allowed, key=sp.default_sort_key)
    if extra:
        names = ", ".join(sorted({*STATE_SYMBOLS, "t", *(s.name for s in mech.parameter_symbols)}))
        raise InvalidInput("candidate", str(expr), f"an expression in the model's names only ({names}); "
                           f"unknown: {', '.join(map(str, extra))}")
    if expr.has(sp.Derivative) or expr.atoms(sp.core.function.AppliedUndef):
        raise InvalidInput("candidate", str(expr), "a function of the state, t and the parameters (no derivatives)")
    return expr


def prove(mech: Mechanics, expr, *, name: str | None = None, seed: int = 0, on=None) -> Verdict:
    """Whether ``expr`` is conserved along the model's flow: ``dH/dt`` derived, tested for zero, and simplified.

    Parameters
    ----------
    mech : Mechanics or eulersym.model.Model
    expr : sympy.Expr or str
        The candidate, in the model's names (``omega1..3``, ``gamma1..3``, ``q0..q3``, ``t``, parameters; a
        string is read by the whitelist parser, with ``omega``, ``gamma``, ``inertia``, ``dot``, ...). A
        candidate in ``gamma`` for a model whose state has no Γ uses ``Γ = A(q) ẑ``, the vertical of the attitude.
    name : str
        For the report (default: the string given, else ``"H"``).
    seed : int
        Seeds the numeric test and the search for a counterexample.
    on : str or mapping, optional
        A level set of the model's integrals: ``"L_dot_Gamma = 0"`` (several joined by commas), or
        ``{"L_dot_Gamma": 0}``; values are numbers or expressions of the parameters (see :func:`level_set`).

    Returns
    -------
    Verdict

    Raises
    ------
    eulersym.errors.InvalidInput
        A candidate with a name the model does not know, a vector, or a derivative.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics, OMEGA
    >>> free = Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.diag(1, 2, 3)), mass=sp.Integer(1))
    >>> w1, w2, w3 = OMEGA
    >>> prove(free, w1**2 + 4*w2**2 + 9*w3**2).conserved
    True
    >>> v = prove(free, w3)
    >>> v.conserved, v.rate, v.counterexample is not None
    (False, -omega1*omega2/3, True)

    Goryachev–Chaplygin's integral, on the level set ``L·Γ = 0`` only:

    >>> from eulersym.model.cli import load
    >>> top = load("top-goryachev-chaplygin")
    >>> gc = "omega3*(omega1**2 + omega2**2) - M*g*a/C*omega1*gamma3"
    >>> prove(top, gc).conserved, prove(top, gc, on="L_dot_Gamma = 0").conserved
    (False, True)
    """
    from eulersym.compare import compare

    mech = _as_mechanics(mech)
    if isinstance(expr, str):
        from eulersym.model.expressions import parse

        name = expr if name is None else name
        expr = parse(expr, mech, argument="candidate", shape="scalar")
    name = "H" if name is None else name
    expr = _check_candidate(mech, sp.sympify(expr))
    if on is not None:
        return _prove_on(mech, expr, level_set(mech, on), name=name, seed=seed)
    state, _ = _flow(mech)
    notes = []
    H = _rational(expr)
    if H.has(*GAMMA) and GAMMA[0] not in state:
        from eulersym.rotation import from_quaternion

        vertical = from_quaternion(list(Q)) * sp.Matrix([0, 0, 1])
        H = H.xreplace(dict(zip(GAMMA, vertical)))
        notes.append("gamma written as A(q) z (the state carries no vertical)")
    rate = _rate(mech, H)
    # Refute first (cheap): an exact rational state on |Γ| = |q| = 1 where the rate is not zero is a proof.
    cx = _counterexample(mech, rate, seed)
    if cx is not None:
        surface = " on the constraint surface |Gamma| = |q| = 1" if GAMMA[0] in state else " (with |q| = 1)"
        how = f"dH/dt is not zero: exact evaluation at a rational state{surface}"
        return Verdict(name, expr, False, _tidy(rate), "; ".join([how, *notes]), cx, True)
    # One fraction: the rate is zero exactly when its numerator is (denominators are the tensor's determinant and
    # the parameters' expressions of the model, non-zero for a body).
    first = compare(sp.fraction(sp.together(rate))[0], sp.Integer(0), seed=seed)
    if first.exact is True:
        return Verdict(name, expr, True, sp.Integer(0), "; ".join([first.method, *notes]), None, True)
    reduced, constraints = _constrained(mech, rate)
    if constraints:
        second = compare(reduced, sp.Integer(0), seed=seed)
        if second.exact is True:
            how = (f"{second.method}, on the constraint surface {', '.join(constraints)} (the rate's numerator "
                   "reduced modulo the constraints: remainder zero)")
            return Verdict(name, expr, True, sp.Integer(0), "; ".join([how, *notes]), None, True, constraints)
        rate, first = reduced, second
    if first.exact is False:
        how = f"dH/dt is not zero: {first.method}"
        return Verdict(name, expr, False, _tidy(rate), "; ".join([how, *notes]), first.counterexample, True,
                       constraints)
    how = f"undecided: {first.method}; not claimed conserved"
    return Verdict(name, expr, False, _tidy(rate), "; ".join([how, *notes]), None, False, constraints)


def _as_mechanics(mech, argument: str = "mech") -> Mechanics:
    """A model's :class:`Mechanics` (``mech`` itself, or a ``Model``'s)."""
    if isinstance(mech, Mechanics):
        return mech
    inner = getattr(mech, "mechanics", None)
    if isinstance(inner, Mechanics):
        return inner
    raise InvalidInput(argument, mech, "an eulersym.model.Model or its Mechanics")


# ----------------------------------------------------------------------------------------------------------------
# Level sets


def level_set(mech, on) -> tuple:
    """The level set named by ``on``: ``((name, H, value), ...)`` with each ``H`` an integral of the model, proven
    conserved (so the set is invariant), and ``value`` a number or an expression of the parameters.

    Parameters
    ----------
    mech : Mechanics or Model
    on : str or mapping
        ``"L_dot_Gamma = 0"``, ``"L_dot_Gamma = 0, E = 2*M*g*a"``, or ``{"L_dot_Gamma": 0}``; names from
        :func:`candidates`.

    Raises
    ------
    eulersym.errors.InvalidInput
        An unknown name (did-you-mean), a name whose integral is not conserved (its level set is not invariant),
        a malformed entry, or a value that is not an expression of the parameters.

    Examples
    --------
    >>> from eulersym.model.cli import load
    >>> [(n, str(v)) for n, _, v in level_set(load("kovalevskaya"), "L_dot_Gamma = 0")]
    [('L_dot_Gamma', '0')]
    >>> level_set(load("kovalevskaya"), "L_dot_Gama = 0")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: on='L_dot_Gama' is not valid: expected an integral of the model: E, Gamma_norm2, L_dot_Gamma, L_axis, q_norm2, K (did you mean 'L_dot_Gamma'?)
    """
    import difflib

    from eulersym.parsing import parse as parse_formula

    mech = _as_mechanics(mech)
    if isinstance(on, str):
        entries = []
        for part in on.split(","):
            if not part.strip():
                continue
            if part.count("=") != 1:
                raise InvalidInput("on", part.strip(), "NAME = VALUE, e.g. 'L_dot_Gamma = 0' (several joined by "
                                   "commas)")
            key, value = (x.strip() for x in part.split("="))
            entries.append((key, value))
    elif isinstance(on, dict):
        entries = list(on.items())
    else:
        raise InvalidInput("on", on, "a string 'NAME = VALUE, ...' or a mapping {name: value}")
    if not entries:
        raise InvalidInput("on", on, "at least one integral and its value, e.g. 'L_dot_Gamma = 0'")
    known = candidates(mech)
    verdicts = invariants(mech)
    params = {s.name: s for s in mech.parameter_symbols}
    out = []
    for key, value in entries:
        if key not in known:
            close = difflib.get_close_matches(str(key), list(known), n=1, cutoff=0.5)
            raise InvalidInput("on", key, "an integral of the model: " + ", ".join(known)
                               + (f" (did you mean {close[0]!r}?)" if close else ""))
        if not verdicts[key].conserved:
            raise InvalidInput("on", key, f"an integral the model conserves ({key} is not: dH/dt = "
                               f"{verdicts[key].rate}), so that its level set is invariant")
        if isinstance(value, str):
            value = parse_formula(value, names=dict(params), strict=True, argument=f"on.{key}")
        elif isinstance(value, bool) or not isinstance(value, (int, float, sp.Basic)):
            raise InvalidInput(f"on.{key}", value, "a number or an expression of the parameters")
        value = sp.sympify(value)
        extra = value.free_symbols - set(mech.parameter_symbols)
        if extra or isinstance(value, sp.MatrixBase):
            raise InvalidInput(f"on.{key}", str(value), "a number or an expression of the parameters ("
                               + (", ".join(params) or "none") + ")")
        if value.is_number and not value.is_finite:
            raise InvalidInput(f"on.{key}", str(value), "a finite value")
        out.append((key, known[key], value))
    return tuple(out)


def _prove_on(mech: Mechanics, expr, level, *, name: str, seed: int) -> Verdict:
    """``dH/dt`` reduced modulo the constraints and ``C_i − value_i`` (Gröbner basis over QQ(parameters))."""
    from eulersym.compare import compare

    state, _ = _flow(mech)
    H = _rational(expr)
    rate = _rate(mech, H)
    num, den = sp.fraction(sp.together(sp.expand(rate)))
    num = sp.expand(num)
    gens = [s for s in state if s in (*OMEGA, *GAMMA, *Q)]
    ideal = []
    used = []
    if GAMMA[0] in state:
        ideal.append(sum(g ** 2 for g in GAMMA) - 1)
        used.append("|Gamma|^2 = 1")
    ideal.append(sum(q ** 2 for q in Q) - 1)
    used.append("|q|^2 = 1")
    for key, C, value in level:
        ideal.append(sp.numer(sp.together(_rational(C) - _rational(value))))
        used.append(f"{key} = {value}")
    params = sorted((num.free_symbols | set().union(*[p.free_symbols for p in ideal])) - set(gens) - {t},
                    key=str)
    if num.has(t) or any(p.has(t) for p in ideal):
        gens = gens + [t]
        params = [p for p in params if p is not t]
    domain = sp.QQ.frac_field(*params) if params else sp.QQ
    surface = ", ".join(used)
    G = sp.groebner(ideal, *gens, order="grevlex", domain=domain)
    remainder = sp.expand(G.reduce(num)[1]) if num != 0 else sp.Integer(0)
    if remainder == 0:
        how = (f"exact (Gröbner normal form), on the level set {surface} (the rate's numerator reduced modulo the "
               "ideal of the set: remainder zero)")
        return Verdict(name, expr, True, sp.Integer(0), how, None, True, tuple(used))
    cx = _counterexample_on(mech, remainder / den, ideal, gens, level, seed)
    shown = _tidy(remainder / den)
    if cx is not None:
        how = f"dH/dt is not zero on the level set {surface}: exact evaluation at a rational state on it"
        return Verdict(name, expr, False, shown, how, cx, True, tuple(used))
    check = compare(remainder, sp.Integer(0), seed=seed)
    how = (f"dH/dt reduced modulo the level set {surface} is not zero ({check.method}); no rational state on the "
           "set was found for a counterexample")
    return Verdict(name, expr, False, shown, how, None, check.exact is False, tuple(used))


def _counterexample_on(mech, rate, ideal, gens, level, seed: int) -> dict | None:
    """A rational state on the level set (each constraint solved for a component it is linear in) where ``rate``
    is not zero; parameters at their defaults, then at random values."""
    rng = random.Random(seed)
    defaults = [(s, sp.Rational(str(v))) for s, v in mech.parameters]
    state, _ = _flow(mech)
    for attempt in range(2 * _COUNTEREXAMPLE_POINTS):
        point = dict(defaults) if attempt < _COUNTEREXAMPLE_POINTS else {
            s: sp.Rational(rng.randint(5, 20), 10) for s, _ in defaults}
        point.update({w: sp.Rational(rng.randint(-30, 30), 10) for w in OMEGA})
        if GAMMA[0] in state:
            point.update(zip(GAMMA, _unit_point(rng, 3)))
        point.update(zip(Q, _unit_point(rng, 4)))
        point[t] = sp.Rational(rng.randint(0, 30), 10)
        ok = True
        for key, C, value in level:
            relation = sp.expand(_rational(C) - _rational(value))
            for w in (*OMEGA[::-1], *Q):
                if w not in state:
                    continue
                p = sp.Poly(relation, w)
                if p.degree() == 1:
                    others = {k: v for k, v in point.items() if k is not w}
                    a, b = (c.xreplace(others) for c in p.all_coeffs())
                    if a != 0:
                        point[w] = -b / a
                        break
            else:
                ok = False
        if not ok or any(sp.expand(p.xreplace(point)) != 0 for p in ideal):
            continue
        value = sp.sympify(rate).xreplace(point)
        if value.free_symbols:
            continue
        low = value.evalf(30)
        if low.is_number and low.is_finite and abs(low) > 1e-20:
            return {str(k): float(v) for k, v in sorted(point.items(), key=lambda kv: sp.default_sort_key(kv[0]))}
    return None


# ----------------------------------------------------------------------------------------------------------------
# Structure: symmetry axis, Kovalevskaya's case


def _rational_coefficients(x, symbols) -> bool:
    """Whether ``x`` is a ratio of polynomials in ``symbols`` with rational coefficients (no cos(3/10), no √2)."""
    for part in sp.fraction(sp.together(x)):
        coeffs = sp.Poly(part, *symbols).coeffs() if symbols else [part]
        if not all(c.is_Rational for c in coeffs):
            return False
    return True


def symmetry_axis(inertia) -> tuple | None:
    """``(e, A, C)`` when the tensor has two equal principal moments ``A`` and a distinct one ``C`` about ``e``.

    Diagonal tensors are read directly; a full tensor through its characteristic polynomial: a double root
    ``A`` (``gcd(p, p′)`` of degree 1) makes ``I − A·1 = (C − A) e eᵀ`` of rank one, and ``e`` is any non-zero
    column. A spherical tensor (three equal moments) has no distinguished axis: None. So is a tensor whose entries
    are not rational functions of the parameters (transcendental constants, e.g. a part turned by Euler angles): the
    exact test would not finish.

    Examples
    --------
    >>> import sympy as sp
    >>> symmetry_axis(sp.diag(2, 2, 1))
    (Matrix([
    [0],
    [0],
    [1]]), 2, 1)
    >>> symmetry_axis(sp.Matrix([[3, 1, 0], [1, 3, 0], [0, 0, 2]]))[0].T   # moments 2, 2, 4
    Matrix([[1, 1, 0]])
    >>> symmetry_axis(sp.diag(1, 2, 3)) is None
    True
    """
    I = sp.Matrix(_rational(sp.ImmutableMatrix(inertia)))
    if I.is_diagonal():
        d = [I[k, k] for k in range(3)]
        for k in range(3):
            i, j = [m for m in range(3) if m != k]
            if sp.expand(d[i] - d[j]) == 0 and sp.expand(d[k] - d[i]) != 0:
                e = sp.zeros(3, 1)
                e[k] = 1
                return e, d[i], d[k]
        return None
    symbols = sorted(I.free_symbols, key=str)
    if not all(_rational_coefficients(x, symbols) for x in I):
        # Transcendental constants (a part turned by Euler angles: cos(3/10), ...) admit no exact double-root test in
        # bounded time (the gcd below does not return); such a body is offered no symmetry-axis momentum.
        return None
    p = I.charpoly()
    g = sp.gcd(p, p.diff())
    if g.degree() != 1:
        return None
    A = sp.cancel(-g.all_coeffs()[1] / g.all_coeffs()[0])
    B = (I - A * sp.eye(3)).applyfunc(lambda x: sp.factor(sp.expand(x)))
    for j in range(3):
        column = B[:, j]
        if any(x != 0 for x in column):
            C = sp.expand(I.trace() - 2 * A)
            return column, A, C
    return None  # pragma: no cover - a rank-one B has a non-zero column


def _dot(a, b) -> sp.Expr:
    return (sp.Matrix(a).T * sp.Matrix(b))[0, 0]


def kovalevskaya_integral(mech: Mechanics) -> sp.Expr | None:
    """Kovalevskaya's integral in the model's axes, or None when the model is not in her case.

    Her case: a pivoted heavy body, no other torque and no rotor, principal moments ``A = A = 2C`` about the pivot
    and the centre of mass ``c ≠ 0`` in the equatorial plane (``c·e = 0``). The literature writes, with ``c`` along
    the first axis and ``e`` the third, ``K = (p² − q² − ν γ₁)² + (2 p q − ν γ₂)²``, ``ν = M g |c| / C`` and γ the
    upward vertical (the complex form: ``ξ = (p + i q)² − ν (γ₁ + i γ₂)`` obeys ``ξ̇ = −i r ξ``). Rotated into the
    model's axes: ``p = ω·u/|u|``, ``q = ω·v/|u|``, ``γ₁ = Γ·u/|u|``, ``γ₂ = Γ·v/|u|`` with ``u = c``,
    ``v = ê × u``, so ``K = ((ω·u)² − (ω·v)²)/|u|² − (M g/C) Γ·u)² + (2 (ω·u)(ω·v)/|u|² − (M g/C) Γ·v)²``.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> m = Mechanics(name="k", inertia=sp.ImmutableMatrix(sp.diag(2, 2, 1)), mass=sp.Integer(1),
    ...               centre_of_mass=sp.ImmutableMatrix([1, 0, 0]), gravity=sp.Integer(1), pivoted=True)
    >>> sp.expand(kovalevskaya_integral(m)).coeff(sp.Symbol("gamma1", real=True), 2)
    1
    """
    if not (mech.pivoted and mech.gravity != 0) or mech.potential != 0:
        return None
    if any(e != 0 for e in mech.torque) or any(e != 0 for e in mech.rotor):
        return None
    c = sp.Matrix(_rational(mech.centre_of_mass))
    if all(x == 0 for x in c):
        return None
    axis = symmetry_axis(mech.inertia)
    if axis is None:
        return None
    e, A, C = axis
    if sp.expand(A - 2 * C) != 0 or sp.expand(_dot(c, e)) != 0:
        return None
    e_hat = e / sp.sqrt(_dot(e, e))
    u, v = c, e_hat.cross(c)
    w, G = sp.Matrix(OMEGA), sp.Matrix(GAMMA)
    u2 = _dot(u, u)
    k = _rational(mech.mass * mech.gravity) / C
    wu, wv = _dot(w, u), _dot(w, v)
    real = sp.cancel(sp.expand((wu ** 2 - wv ** 2) / u2)) - sp.expand(k * _dot(G, u))
    imag = sp.cancel(sp.expand(2 * wu * wv / u2)) - sp.expand(k * _dot(G, v))
    return real ** 2 + imag ** 2


# ----------------------------------------------------------------------------------------------------------------
# The candidates


def candidates(mech: Mechanics) -> dict:
    """``{name: expression}``: the integrals the model's structure suggests (see the module docstring).

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> list(candidates(Mechanics(name="free", inertia=sp.ImmutableMatrix(sp.diag(1, 1, 2)), mass=sp.Integer(1))))
    ['E', 'L2', 'L_axis', 'q_norm2']
    """
    if not isinstance(mech, Mechanics):
        raise InvalidInput("mech", mech, "an eulersym.model.mechanics.Mechanics")
    eqs = equations(mech)
    w = sp.Matrix(OMEGA)
    I = sp.Matrix(mech.inertia)
    L = sp.Matrix(eqs.angular_momentum)
    V = total_potential(mech)
    out = {"E": sp.expand((w.T * I * w)[0, 0] / 2 + V)}
    if GAMMA[0] in eqs.state:
        G = sp.Matrix(GAMMA)
        out["Gamma_norm2"] = _dot(G, G)
        out["L_dot_Gamma"] = sp.expand(_dot(L, G))
    if V == 0:
        out["L2"] = sp.expand(_dot(L, L))
        if any(e != 0 for e in mech.rotor):  # the body's own part, I ω, is not conserved with a rotor
            Iw = I * w
            out["L_body2"] = sp.expand(_dot(Iw, Iw))
    axis = symmetry_axis(mech.inertia)
    if axis is not None:
        out["L_axis"] = sp.expand(_dot(L, axis[0]))
    out["q_norm2"] = sum(q ** 2 for q in Q)
    K = kovalevskaya_integral(mech)
    if K is not None:
        out["K"] = K
    if mech.turning:  # the Jacobi-like integral of a uniformly turning frame: E − Ω·L (the frame's own Hamiltonian)
        from eulersym.model.expressions import to_body

        out["Jacobi"] = sp.expand(out["E"] - _dot(to_body(mech.frame), L))
    return out


@functools.lru_cache(maxsize=32)
def _invariants(mech: Mechanics) -> tuple:
    return tuple((name, prove(mech, expr, name=name)) for name, expr in candidates(mech).items())


def invariants(mech: Mechanics) -> dict:
    """``{name: Verdict}`` for every candidate of :func:`candidates`, each proven or refuted.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> a = sp.Symbol("a", positive=True)
    >>> kovalevskaya = Mechanics(name="kovalevskaya", inertia=sp.ImmutableMatrix(sp.diag(2, 2, 1)),
    ...     mass=sp.Integer(1), centre_of_mass=sp.ImmutableMatrix([a, 0, 0]), gravity=sp.Integer(10), pivoted=True,
    ...     parameters=((a, 0.5),))
    >>> {name: v.conserved for name, v in invariants(kovalevskaya).items()}
    {'E': True, 'Gamma_norm2': True, 'L_dot_Gamma': True, 'L_axis': False, 'q_norm2': True, 'K': True}
    """
    if not isinstance(mech, Mechanics):
        raise InvalidInput("mech", mech, "an eulersym.model.mechanics.Mechanics")
    return dict(_invariants(mech))
