"""Decide whether two symbolic results are equal: exactly, and at random high-precision points.

This is the one comparison engine of the package: ``eulersym.text.check`` proves the text's closed forms with it,
and ``eulersym.verify`` builds its verdicts (parsing, diagnosis of slips) on top of it.

What can be compared: SymPy scalars, matrices (componentwise), ``Eq`` (as lhs − rhs), and lists/tuples of these
(shapes must match). Functions of time such as ``phi(t)`` and their derivatives are frozen into plain symbols
(``phi``, ``phidot``, ``phiddot``) before comparing, so that identities between Euler-angle expressions are tested
at independent random values of angles and rates.

Exact strategies, cheapest first:

1. ``expand`` to zero;
2. trig-polynomial reduction: ``sin x``, ``cos x`` become ``s_x``, ``c_x`` and the numerator is reduced modulo
   ``s_x² + c_x² − 1`` (a Gröbner basis) — decisive and fast for everything built from rotation matrices;
3. ``sympy.simplify``, only for small expressions (a budget on the operation count keeps it bounded).

Numeric: each difference is evaluated with mpmath at ``points`` seeded random points at ``dps`` digits; positive
symbols get positive values. A difference above the tolerance is a counterexample, which proves inequality. Each
difference is first evaluated in one pass in interval arithmetic at ``dps + 20`` digits (:func:`_evaluate_fast`);
only what that pass cannot confirm as agreeing (an interval not inside the tolerance — a large difference, or large
terms cancelling —, NaN, a function it does not know) is evaluated again by SymPy's ``evalf`` at ``dps + 10``
digits from exact rationals, which decides: a difference it certifies to its digits counts whatever the size of the
two sides; one it cannot certify is measured relative to them.

Exact zero tests run in a polynomial ring where the difference is a polynomial in symbols and sines and cosines of
symbols (:func:`_polynomial_zero`: the ring's arithmetic does the expansion), and with SymPy's ``expand`` otherwise.

Examples
--------
>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> r = compare(sp.sin(x)**2, 1 - sp.cos(x)**2)
>>> r.equal, r.exact
(True, True)
>>> print(r.method)
exact (trig-polynomial reduction) + numeric (5 points at 30 digits)
>>> compare(sp.sin(2*x), 2*sp.sin(x)).equal
False
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from typing import Any

import sympy as sp
from sympy.core.function import AppliedUndef

from eulersym.errors import InvalidInput

__all__ = ["Comparison", "compare", "components", "freeze_functions", "zero_exact"]

#: Expressions with more operations than this are not handed to ``sympy.simplify``.
SIMPLIFY_BUDGET = 300


@dataclass(frozen=True)
class Comparison:
    """The verdict of :func:`compare`.

    Attributes
    ----------
    equal : bool
        True when every component agrees (exactly, or numerically when no exact proof was found).
    exact : bool or None
        True when every component's difference was simplified exactly to zero; False when a counterexample
        proves a difference; None when neither was decided exactly.
    numeric : bool
        True when every component agrees at all random points.
    method : str
        How it was shown, in words.
    difference : sympy object
        The (simplified) difference, component by component, in the shape of the inputs.
    counterexample : dict or None
        Symbol → value where the two differ, or None.
    differing : tuple of str
        Labels of the components that differ (``"[0, 1]"`` for a matrix entry, ``"[2]"`` for a list item).
    points, dps, tolerance
        The numeric test: number of points, working digits, and the relative tolerance used.
    """

    equal: bool
    exact: bool | None
    numeric: bool
    method: str
    difference: Any
    counterexample: dict | None = None
    differing: tuple[str, ...] = ()
    points: int = 0
    dps: int = 0
    tolerance: float = 0.0
    details: dict = field(default_factory=dict, compare=False, repr=False)


# ----------------------------------------------------------------------------------------------------------------
# Shapes


def components(obj) -> list[tuple[str, sp.Expr]]:
    """Flatten a comparable object into ``(label, scalar expression)`` pairs.

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> components([sp.Eq(x, 1), sp.Matrix([x, 2])])
    [('[0]', x - 1), ('[1][0]', x), ('[1][1]', 2)]
    """
    out: list[tuple[str, sp.Expr]] = []
    _flatten(obj, "", out)
    return out


def _flatten(obj, label: str, out: list) -> None:
    if isinstance(obj, sp.Equality):
        out.append((label, obj.lhs - obj.rhs))
    elif isinstance(obj, sp.MatrixBase):
        if obj.cols == 1:
            for i in range(obj.rows):
                out.append((f"{label}[{i}]", obj[i, 0]))
        else:
            for i in range(obj.rows):
                for j in range(obj.cols):
                    out.append((f"{label}[{i}, {j}]", obj[i, j]))
    elif isinstance(obj, (list, tuple)):
        for i, item in enumerate(obj):
            _flatten(item, f"{label}[{i}]", out)
    elif isinstance(obj, sp.Basic):
        out.append((label, obj))
    elif isinstance(obj, (int, float)) and not isinstance(obj, bool):
        out.append((label, sp.sympify(obj)))
    else:
        raise InvalidInput("expression", obj, "a SymPy expression, Matrix, Eq, or a list/tuple of them")


def _shape(obj):
    if isinstance(obj, sp.MatrixBase):
        return ("matrix", obj.shape)
    if isinstance(obj, (list, tuple)):
        return ("list", tuple(_shape(o) for o in obj))
    return ("scalar",)


# ----------------------------------------------------------------------------------------------------------------
# Functions of time → symbols


def freeze_functions(expr, names: dict | None = None):
    """Replace functions of one variable and their derivatives by plain real symbols.

    ``phi(t)`` becomes ``phi``, ``Derivative(phi(t), t)`` becomes ``phidot``, the second derivative ``phiddot``,
    higher ones ``phi_d3`` and so on. Returns ``(frozen, mapping)``.

    Examples
    --------
    >>> from eulersym.symbols import phi, t
    >>> frozen, mapping = freeze_functions(phi.diff(t) * phi)
    >>> frozen
    phi*phidot
    """
    mapping: dict = {} if names is None else names
    expr = sp.sympify(expr)
    found = expr.atoms(sp.Derivative, AppliedUndef)
    if not found:  # nothing to freeze (one traversal instead of three)
        return expr, mapping
    derivs = sorted((d for d in found if isinstance(d, sp.Derivative)), key=lambda d: -d.derivative_count)
    for d in derivs:
        if d in mapping:
            continue
        f = d.expr
        if not isinstance(f, AppliedUndef) or len(d.variables) != d.derivative_count:
            continue
        base = f.func.__name__
        n = d.derivative_count
        suffix = {1: "dot", 2: "ddot"}.get(n, f"_d{n}")
        mapping[d] = sp.Symbol(base + suffix, real=True)
    for f in expr.atoms(AppliedUndef):
        if f not in mapping:
            mapping[f] = sp.Symbol(f.func.__name__, real=True)
    return expr.xreplace(mapping), mapping


# ----------------------------------------------------------------------------------------------------------------
# Exact zero tests


def _trig_atoms(expr):
    return [a for a in expr.atoms(sp.sin, sp.cos, sp.tan, sp.cot)]


def _has_denominator(expr) -> bool:
    return any(p.exp.is_negative for p in expr.atoms(sp.Pow) if p.base.free_symbols)


def _trig_polynomial_zero(expr) -> bool | None:
    """True if ``expr`` is zero as a rational function of sin and cos of its (symbol) arguments; None if n/a.

    ``sin x``, ``cos x`` become ring generators ``s_x``, ``c_x`` (lex order, ``s_x`` first) and the numerator is
    divided by ``{s_x² + c_x² − 1}``, which is already a Gröbner basis (the leading terms ``s_x²`` are coprime): the
    remainder is zero exactly when the expression vanishes identically.
    """
    trig = _trig_atoms(expr)
    if any(not a.args[0].is_Symbol for a in trig):
        expr = sp.expand(sp.expand_trig(expr))
        trig = _trig_atoms(expr)
        if any(not a.args[0].is_Symbol for a in trig):
            return None
    if not trig:
        return True if expr == 0 else None
    args = sorted({a.args[0] for a in trig}, key=sp.default_sort_key)
    sub, pairs = {}, []
    for arg in args:
        s, c = sp.Dummy(f"s_{arg}"), sp.Dummy(f"c_{arg}")
        sub.update({sp.sin(arg): s, sp.cos(arg): c, sp.tan(arg): s / c, sp.cot(arg): c / s})
        pairs.append((s, c))
    num = expr.xreplace(sub)
    if _has_denominator(num):
        num = sp.expand(sp.fraction(sp.together(num))[0])
    if num == 0:
        return True
    found = _trig_ring(num, pairs, (sp.QQ, sp.EX))
    if found is None:
        return None
    poly, basis = found
    return poly.rem(basis) == 0


def _trig_ring(num, pairs, domains):
    """``(poly, basis)``: ``num`` as a polynomial (lex order) in the generators of ``pairs`` — ``(s_x, c_x)``, a sine
    and a cosine each, first — and its other symbols, over the first of ``domains`` that holds its coefficients,
    with ``basis = [s_x² + c_x² − 1, …]`` (a Gröbner basis: the leading terms ``s_x²`` are coprime, so
    ``poly.rem(basis)`` is zero exactly when ``num`` vanishes modulo the Pythagorean identities); None when
    ``num`` is not such a polynomial."""
    gens = [g for pair in pairs for g in pair]
    others = sorted(num.free_symbols - set(gens), key=sp.default_sort_key)
    for domain in domains:
        try:
            ring, *xs = sp.ring(gens + others, domain, order="lex")
            poly = ring.from_expr(num)
            break
        except (ValueError, TypeError, sp.polys.polyerrors.PolynomialError, sp.polys.polyerrors.CoercionFailed):
            continue
    else:
        return None
    return poly, [xs[2 * i] ** 2 + xs[2 * i + 1] ** 2 - 1 for i in range(len(pairs))]


def _polynomial_zero(expr) -> str | None:
    """The strategy that proves ``expr`` zero when it is a polynomial with rational coefficients in symbols and the
    sines and cosines of symbols, computed in a polynomial ring (no SymPy ``expand``); None otherwise (not such a
    polynomial, or not zero: the caller's strategies decide).

    ``"expand"`` when the polynomial is zero as it stands, ``"trig-polynomial reduction"`` when it is zero modulo
    ``s_x² + c_x² − 1`` — the same verdicts, by the same algebra, as ``expand`` and :func:`_trig_polynomial_zero`.
    """
    if expr.has(sp.Float):
        return None
    trig = _trig_atoms(expr)
    if any(not isinstance(a, (sp.sin, sp.cos)) or not a.args[0].is_Symbol for a in trig):
        return None
    args = sorted({a.args[0] for a in trig}, key=sp.default_sort_key)
    # sin x, cos x are the ring's generators themselves
    found = _trig_ring(expr, [(sp.sin(arg), sp.cos(arg)) for arg in args], (sp.QQ,))
    if found is None:
        return None
    poly, basis = found
    if not poly:
        return "expand"
    return "trig-polynomial reduction" if basis and not poly.rem(basis) else None


def zero_exact(expr) -> tuple[bool, str]:
    """Try to prove ``expr == 0`` exactly; return ``(proved, strategy)``.

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> zero_exact(sp.cos(x)**2 + sp.sin(x)**2 - 1)
    (True, 'trig-polynomial reduction')
    >>> zero_exact(x + 1)
    (False, '')
    """
    expr = sp.sympify(expr)
    if expr == 0:
        return True, "identical"
    if expr.atoms(AppliedUndef):
        expr, _ = freeze_functions(expr)
    proved = _polynomial_zero(expr)
    if proved:
        return True, proved
    expanded = sp.expand(expr)
    if expanded == 0:
        return True, "expand"
    trig = _trig_polynomial_zero(expanded)
    if trig:
        return True, "trig-polynomial reduction"
    if trig is None and not expanded.free_symbols:
        if sp.nsimplify(expanded) == 0 or sp.simplify(expanded) == 0:
            return True, "simplify"
        return False, ""
    if sp.count_ops(expanded) <= SIMPLIFY_BUDGET and not _clearly_nonzero(expanded):
        if sp.simplify(expanded) == 0:
            return True, "simplify"
    return False, ""


def _clearly_nonzero(expr) -> bool:
    """True when ``expr`` is far from zero (relative to its terms) at one seeded rational point, 30 digits: then no
    simplification can prove it zero, and ``simplify`` (slow, and the import of ``sympy.physics.units``) is not
    tried. Any doubt (a complex, non-finite or failed evaluation, a small value) answers False.

    Examples
    --------
    >>> import sympy as sp
    >>> x = sp.Symbol("x", positive=True)
    >>> _clearly_nonzero(x + 1), _clearly_nonzero(sp.sqrt(x**2) - x)
    (True, False)
    >>> n = sp.Symbol("n", negative=True)
    >>> _clearly_nonzero(sp.sqrt(n**2) + n)  # zero for every negative n: no positive sample may decide it
    False
    """
    symbols = sorted(expr.free_symbols, key=str)
    if any(s.is_integer or s.is_positive is False for s in symbols):  # a positive rational point is outside their domain
        return False
    rng = random.Random(20261123)
    point = {s: sp.Rational(rng.randint(50, 200), 100) for s in symbols}
    terms = sp.Add.make_args(expr)
    try:
        values = [complex(term.xreplace(point).evalf(30)) for term in terms]
    except (TypeError, ValueError, ZeroDivisionError, OverflowError):
        return False
    value, scale = abs(sum(values)), sum(abs(v) for v in values)
    return math.isfinite(scale) and value > 1e-12 * scale


# ----------------------------------------------------------------------------------------------------------------
# Numeric test


def _random_point(symbols, rng: random.Random) -> dict:
    point = {}
    for s in symbols:
        if s.is_positive or s.is_nonnegative:
            value = rng.uniform(0.5, 2.0)
        else:
            value = rng.uniform(-1.5, 1.5)
        point[s] = value
    return point


#: The most digits evalf may work at to certify a difference of large, cancelling terms (a difference of terms of
#: size 10**300 needs ~340).
_MAX_DIGITS = 1000


def _evaluate(expr, point: dict, dps: int, *, certified: bool = False):
    """``expr`` at ``point`` as an mpmath number with ``dps + 10`` digits (NaN when it has no numeric value); with
    ``certified``, ``(value, True)`` when evalf reached that precision (the value's digits are right, however much
    its terms cancelled), ``(value, False)`` otherwise.

    SymPy's evalf is adaptive when the point is given as ``subs`` (exact rationals): a sum whose terms cancel is
    re-evaluated at higher precision, so a small difference of large terms keeps its digits. Where it cannot reach
    the precision asked (an exact zero has no relative precision) the value at the point is taken as it comes.
    """
    import mpmath
    from sympy.core.evalf import PrecisionExhausted

    expr = sp.sympify(expr)
    certain = True
    try:
        value = expr.evalf(dps + 10, subs={s: sp.Rational(repr(v)) for s, v in point.items()}, strict=True,
                           maxn=_MAX_DIGITS)
    except PrecisionExhausted:
        certain = False
        value = expr.xreplace({s: sp.Float(repr(v), dps + 10) for s, v in point.items()}).evalf(dps + 10)
    if not value.is_number or value.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        result, certain = mpmath.mpf("nan"), False
    else:
        with mpmath.workdps(dps + 10):
            re, im = (mpmath.mpf(str(part)) for part in value.as_real_imag())
            result = mpmath.mpc(re, im)
    return (result, certain) if certified else result


class _NotFast(Exception):
    """An expression (or a value on the way) that the fixed-precision evaluator leaves to :func:`_evaluate`."""


#: SymPy functions of one argument → the name of the mpmath function (principal branches, as SymPy's).
_MP_FUNCTIONS = {
    sp.sin: "sin", sp.cos: "cos", sp.tan: "tan", sp.cot: "cot", sp.exp: "exp", sp.log: "log",
    sp.asin: "asin", sp.acos: "acos", sp.atan: "atan", sp.sinh: "sinh", sp.cosh: "cosh", sp.tanh: "tanh",
}


def _evaluate_fast(expr, point: dict, mp):
    """``expr`` at ``point`` in mpmath's interval arithmetic (``mp`` is ``mpmath.iv`` at the caller's precision),
    one pass over the tree with shared subexpressions evaluated once; :class:`_NotFast` for anything it does not
    know (then the adaptive :func:`_evaluate` decides). ``point`` maps each symbol to an interval.

    Fixed precision is not adaptive: a sum of terms of size ``S`` keeps ``S·10**-digits`` of error — which the
    interval carries, so a difference of huge terms gives a wide interval, never a false zero. The caller accepts
    only an interval inside the tolerance; anything else is re-evaluated adaptively (:func:`_evaluate`).
    """
    import mpmath

    memo: dict = {}

    def ev(e):
        value = memo.get(e)
        if value is not None:
            return value
        if e.is_Symbol:
            if e not in point:
                raise _NotFast(e)
            value = point[e]
        elif e.is_Integer:
            value = mp.mpf(int(e))
        elif e.is_Rational:
            value = mp.mpf(int(e.p)) / int(e.q)
        elif e.is_Float:
            value = mp.mpf(mpmath.mpf(e._mpf_))  # the Float's binary value, exactly
        elif e.is_Add:
            value = mp.fsum([ev(a) for a in e.args])
        elif e.is_Mul:
            value = mp.fprod([ev(a) for a in e.args])
        elif e.is_Pow:
            base, exponent = e.args
            if exponent is sp.S.Half:
                value = mp.sqrt(ev(base))
            elif exponent.is_Integer:
                b = ev(base)
                if b == 0 and exponent < 0:
                    raise _NotFast(e)
                value = b ** int(exponent)
            else:
                value = mp.power(ev(base), ev(exponent))
        elif e is sp.pi:
            value = +mp.pi
        elif e is sp.E:
            value = mp.e + 0
        elif type(e) in _MP_FUNCTIONS and len(e.args) == 1 and hasattr(mp, _MP_FUNCTIONS[type(e)]):
            value = getattr(mp, _MP_FUNCTIONS[type(e)])(ev(e.args[0]))
        else:
            raise _NotFast(e)
        memo[e] = value
        return value

    try:
        value = ev(expr)
        with mpmath.workprec(mp.prec):  # the endpoints at the interval's precision
            lo, hi = mpmath.mpf(value.a), mpmath.mpf(value.b)
    except (ZeroDivisionError, ValueError, OverflowError, TypeError, AttributeError) as exc:  # complex, no iv form
        raise _NotFast(expr) from exc
    if not (mpmath.isfinite(lo) and mpmath.isfinite(hi)):
        raise _NotFast(expr)
    return lo, hi


def _proportionality_factor(fa, fb, states) -> sp.Expr | None:
    """The factor k with fb = k·fa when k is free of the state symbols and non-zero; else None."""
    if fa == 0 or fb == 0:
        return None
    k = sp.factor(sp.cancel(sp.together(fb / fa)))
    if k == 0 or k.free_symbols & states or k.has(sp.nan, sp.zoo):
        return None
    return k


def compare(
    a,
    b,
    *,
    points: int = 5,
    dps: int = 30,
    seed: int = 0,
    exact: bool = True,
    up_to_factor: bool = False,
) -> Comparison:
    """Compare two symbolic objects exactly and at random high-precision points.

    Parameters
    ----------
    a, b : SymPy expression, Matrix, Eq, or list/tuple of them
        Same shapes. Equations compare as lhs − rhs.
    points : int, optional
        Number of random points for the numeric test (seeded by ``seed``).
    dps : int, optional
        Decimal digits of the numeric test; expressions are evaluated with ``dps + 10`` digits and a difference
        counts when it exceeds ``10**(5 - dps)`` relative to ``max(1, |a|, |b|)``.
    exact : bool, optional
        Try exact simplification to zero (default). With ``exact=False`` only the numeric test runs.
    up_to_factor : bool, optional
        Compare each component up to a non-zero factor free of the state variables (functions of t, their
        derivatives): the way equations ``lhs = rhs`` are compared. The factors found are in
        ``details["factors"]``.

    Returns
    -------
    Comparison

    Examples
    --------
    >>> import sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> compare(sp.Matrix([[x, y]]), sp.Matrix([[x, y + 1]])).differing
    ('[0, 1]',)
    """
    if points < 1:
        raise InvalidInput("points", points, "an integer >= 1")
    if dps < 15:
        raise InvalidInput("dps", dps, "an integer >= 15 (digits of the numeric evaluation)")
    if _shape(a) != _shape(b):
        raise InvalidInput("b", b, f"an object of the same shape as a ({_shape(a)}), not {_shape(b)}")
    ca, cb = components(a), components(b)
    mapping: dict = {}
    diffs, pairs = [], []
    frozen = []
    for (label, ea), (_, eb) in zip(ca, cb):
        fa, _ = freeze_functions(ea, mapping)
        fb, _ = freeze_functions(eb, mapping)
        frozen.append((label, fa, fb))
    factors: dict[str, sp.Expr] = {}
    states = set(mapping.values())
    known: dict = {}  # difference → zero_exact's verdict, found while looking for factors
    for label, fa, fb in frozen:
        if up_to_factor:
            known[fa - fb] = verdict = zero_exact(fa - fb)
            if not verdict[0]:
                k = _proportionality_factor(fa, fb, states)
                if k is not None and k != 1:
                    factors[label] = k
                    fa = k * fa
        pairs.append((label, fa, fb))
        diffs.append(fa - fb)

    # exact
    strategies: list[str] = []
    exact_ok = [False] * len(diffs)
    simplified = list(diffs)
    if exact:
        for i, d in enumerate(diffs):
            ok, how = known[d] if d in known else zero_exact(d)
            exact_ok[i] = ok
            if ok:
                simplified[i] = sp.Integer(0)
                if how not in strategies:
                    strategies.append(how)
            else:
                simplified[i] = sp.expand(d) if sp.count_ops(d) <= SIMPLIFY_BUDGET else d

    # numeric
    rng = random.Random(seed)
    symbols = sorted(set().union(*(fa.free_symbols | fb.free_symbols for _, fa, fb in pairs)) if pairs else set(),
                     key=sp.default_sort_key)
    tolerance = 10.0 ** (5 - dps)  # relative; evaluation runs at dps + 10 digits
    differing: list[str] = []
    counterexample = None
    import mpmath

    for _ in range(points):
        point = _random_point(symbols, rng)
        iv, saved = mpmath.iv, mpmath.iv.dps
        iv.dps = dps + 20  # the fast path, in intervals: agreement only when the whole interval is within tolerance
        try:
            mp_point = {s: iv.mpf(repr(v)) for s, v in point.items()}
            fast = []
            for d in diffs:
                try:
                    lo, hi = (0, 0) if d == 0 else _evaluate_fast(d, mp_point, iv)
                    fast.append(-tolerance <= lo and hi <= tolerance)
                except _NotFast:
                    fast.append(False)
        finally:
            iv.dps = saved
        for (label, fa, fb), d, agrees in zip(pairs, diffs, fast):
            if d == 0 or agrees:
                continue
            delta, certain = _evaluate(d, point, dps, certified=True)  # evalf keeps cancelling digits
            delta = abs(delta)
            if delta <= tolerance:
                continue
            if certain:  # a difference known to its digits is a difference, however large a and b are
                scale = 1.0
            else:  # a value evalf could not certify: relative to the size of a and b
                va, vb = _evaluate(fa, point, dps), _evaluate(fb, point, dps)
                scale = max(1.0, abs(va), abs(vb))
            if not (delta <= tolerance * scale):  # NaN counts as a difference
                if label not in differing:
                    differing.append(label)
                if counterexample is None:
                    counterexample = {str(s): v for s, v in point.items()}
    numeric_ok = not differing

    if all(exact_ok):
        exact_verdict: bool | None = True
    elif differing:
        exact_verdict = False
    else:
        exact_verdict = None
    # An exact proof is sound; a numeric disagreement with it can only come from evaluation (branch cuts), so the
    # proof decides and the disagreement is reported in the method.
    equal = exact_verdict is True or (numeric_ok and exact_verdict is not False)
    numeric_text = f"numeric ({points} points at {dps} digits)"
    if exact_verdict is True:
        how = ", ".join(strategies) if strategies else "identical"
        method = f"exact ({how}) + {numeric_text}"
        if not numeric_ok:
            method += f" (numeric evaluation disagreed at {', '.join(differing)}: branch cuts?)"
    elif exact_verdict is False:
        method = f"counterexample found by {numeric_text}"
    else:
        method = f"{numeric_text} only; no exact proof found"
    if factors:
        method += "; up to factors " + ", ".join(f"{lab or 'expr'}: {k}" for lab, k in factors.items())
    difference = _reshape(a, simplified)
    return Comparison(
        equal=equal,
        exact=exact_verdict,
        numeric=numeric_ok,
        method=method,
        difference=difference,
        counterexample=counterexample,
        differing=tuple(differing),
        points=points,
        dps=dps,
        tolerance=tolerance,
        details={"frozen": mapping, "factors": factors},
    )


def _reshape(template, flat: list):
    it = iter(flat)

    def build(obj):
        if isinstance(obj, sp.MatrixBase):
            return sp.Matrix(obj.rows, obj.cols, [next(it) for _ in range(obj.rows * obj.cols)])
        if isinstance(obj, (list, tuple)):
            return [build(o) for o in obj]
        return next(it)

    return build(template)
