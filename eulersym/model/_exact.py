"""Exact helpers of the steady-motion solver and the stability analysis: zero tests that know
``sin² θ + cos² θ = 1``, the trigonometric normal form, conditions decided at numbers, the rotation generator.

Private to :mod:`eulersym.model.steady` and :mod:`eulersym.model.stability` (both import it; it imports neither).

Examples
--------
>>> _is_zero(sp.sin(THETA)**2 + sp.cos(THETA)**2 - 1)
True
>>> _holds(sp.Symbol("x") > 1, {sp.Symbol("x"): 2})
True
"""

from __future__ import annotations

import sympy as sp

from eulersym.model.mechanics import GAMMA

__all__ = ["DRIFT", "THETA", "PSI"]

#: The drift rate ν of a relative equilibrium about a symmetry axis: ``x(t) = R_e(ν t) x₀`` in body components.
DRIFT = sp.Symbol("nu", real=True)
#: The tilt of a family's vertical: ``Γ·e = cos θ`` (``e`` the symmetry axis, or e3).
THETA = sp.Symbol("theta", real=True)
#: The second angle when the vertical is free on the whole sphere: ``Γ = (sin θ sin ψ, sin θ cos ψ, cos θ)``.
PSI = sp.Symbol("psi", real=True)


def _holds(condition, point) -> bool | None:
    """Whether a condition holds at exact numbers (None when it cannot be decided, e.g. exactly on a boundary of
    transcendental numbers)."""
    value = sp.sympify(condition).xreplace(point)
    if value in (sp.true, sp.false):
        return bool(value)
    try:
        return bool(_decide(value))
    except TypeError:
        return None


def _decide(value):
    """A relational of numbers decided at 30 digits (SymPy leaves some, with radicals, unevaluated)."""
    if isinstance(value, sp.And):
        return all(_decide(a) for a in value.args)
    if isinstance(value, sp.Or):
        return any(_decide(a) for a in value.args)
    if isinstance(value, sp.Not):
        return not _decide(value.args[0])
    if value in (sp.true, sp.false):
        return bool(value)
    if isinstance(value, sp.core.relational.Relational):
        diff = (value.lhs - value.rhs).evalf(30)
        if not diff.is_number or not diff.is_real:
            raise TypeError(f"undecidable: {value}")
        op = value.rel_op
        return {"==": diff == 0, "!=": diff != 0, ">=": diff >= 0, ">": diff > 0, "<=": diff <= 0,
                "<": diff < 0}[op]
    raise TypeError(f"undecidable: {value}")


def _is_zero(expr) -> bool:
    """Exactly zero: the numerator expanded, with ``sin² θ = 1 − cos² θ`` (a polynomial in cos θ plus sin θ times
    one is zero only when both are)."""
    num = sp.expand(sp.numer(sp.together(sp.expand(expr))))
    return num == 0 or (num.has(THETA) and _trig(num) == 0)


def _generator_on_values(x, values, e) -> list:
    e = sp.Matrix(e)
    out = []
    for k in range(0, 6 if GAMMA[0] in x else 3, 3):
        out += list(e.cross(sp.Matrix(values[k:k + 3])))
    return out + [sp.Integer(0)] * (len(x) - len(out))


def _trig(expr):
    """Powers of sin θ above the first written with cos θ (``sin² = 1 − cos²``): one normal form."""
    if not expr.has(THETA):
        return expr
    s, c = sp.sin(THETA), sp.cos(THETA)
    expr = sp.expand(expr)
    return sp.expand(expr.replace(lambda e: e.is_Pow and e.base == s and e.exp.is_Integer and e.exp >= 2,
                                  lambda e: s ** (e.exp % 2) * (1 - c ** 2) ** (e.exp // 2)))


def _tidy(expr):
    expr = sp.sympify(expr)
    if expr.is_number:
        return sp.nsimplify(expr) if expr.has(sp.Float) else expr
    num, den = sp.fraction(sp.cancel(sp.together(_trig(sp.expand(expr)))))
    num, den = _trig(sp.expand(num)), _trig(sp.expand(den))
    if num.has(sp.sqrt) or den.has(sp.Pow):
        return sp.factor_terms(num) / sp.factor_terms(den)
    return sp.factor(num) / sp.factor(den)
