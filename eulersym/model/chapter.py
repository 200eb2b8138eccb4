"""The chapter's stability results, derived by the general machinery from the bundled model files alone.

Each function loads a bundled model, finds its steady motions (:func:`eulersym.model.steady.steady_motions`), picks
the family by its structure (never by a typed answer), and returns the quantity in the text's symbols
(:mod:`eulersym.symbols`), for :mod:`eulersym.text` to compare with the closed form typed there:

- :func:`intermediate_axis_growth_rate` — Example 4.2: the permanent rotation of ``torque-free`` that is unstable
  at the model's numbers (the middle axis), the positive root of its reduced characteristic polynomial;
- :func:`steady_precession_rates` — Example 4.3: ``lagrange-top``'s two relative equilibria about its symmetry axis
  (the − and + roots of the solver's quadratic), their precession rates ``φ̇ = (ω + ν e)·Γ``;
- :func:`steady_precession_existence` — the discriminant those roots need ≥ 0;
- :func:`sleeping_top_threshold` — §4.5: the spin-about-the-vertical family with the axis up, its proven
  conditions, and the value of ``s²`` where its classification changes.

The model's parameters are mapped to the text's symbols by name (``I1`` → :data:`eulersym.symbols.I1`, ...), the
family's spin ``s`` to the text's ``ω0`` / ``ω3`` and the tilt to ``θ``.

Examples
--------
>>> intermediate_axis_growth_rate()
omega0*sqrt((I1 - I2)*(I2 - I3))/(sqrt(I1)*sqrt(I3))
"""

from __future__ import annotations

import functools

import sympy as sp

from eulersym import symbols as S

__all__ = ["intermediate_axis_growth_rate", "steady_precession_rates", "steady_precession_existence",
           "sleeping_top_threshold"]


def _families(name: str):
    from eulersym.model.spec import Model
    from eulersym.model.steady import steady_motions
    from eulersym.models import bundled

    return steady_motions(Model.from_toml(bundled()[name]))


def _text_symbols(fam, **extra) -> dict:
    """Model parameter symbols → the text's symbols of the same name; the family's symbols as given."""
    out = {}
    for p in fam.parameters:
        text = getattr(S, p.name, None)
        if isinstance(text, sp.Symbol):
            out[p.name] = text
    named = {s.name: s for s in fam.family}
    mapping = {}
    for p in fam.parameters:
        if p.name in out:
            mapping[p] = out[p.name]
    for name, target in extra.items():
        if name in named:
            mapping[named[name]] = target
    return mapping


@functools.lru_cache(maxsize=1)
def intermediate_axis_growth_rate():
    """Example 4.2's growth rate ``Ω`` from the ``torque-free`` model: of its permanent rotations about a principal
    axis, the one the proven conditions call unstable at the model's numbers; ``Ω`` is the positive root of its
    reduced characteristic polynomial (spin ``s`` → ``ω0``).

    Examples
    --------
    >>> from eulersym.compare import compare
    >>> from eulersym.symbols import I1, I2, I3, omega0
    >>> compare(intermediate_axis_growth_rate(), omega0*sp.sqrt((I3 - I2)*(I2 - I1)/(I1*I3))).equal
    True
    """
    from eulersym.model.stability import LAM

    for fam in _families("torque-free"):
        if fam.kind != "permanent rotation" or len(fam.family) != 1:
            continue
        st = fam.stability()
        if st.classify({fam.family[0].name: 1}) != "unstable":
            continue
        mapping = _text_symbols(fam, s=S.omega0)
        P = sp.expand(st.characteristic_polynomial.xreplace(mapping))
        roots = list(sp.roots(sp.Poly(P, LAM)))  # (sp.solve would import sympy.physics.units)
        defaults = {S.I1: 1, S.I2: 2, S.I3: 3, S.omega0: 1}
        defaults.update({mapping[p]: sp.Rational(str(v)) for p, v in fam._context.mech.parameters if p in mapping})
        growing = [r for r in roots if sp.re(r.xreplace(defaults).evalf()) > 0]
        return growing[0]
    raise LookupError("no unstable permanent rotation in the torque-free model")


def _precession_families():
    out = {}
    for fam in _families("lagrange-top"):
        if fam.kind == "relative equilibrium" and len(fam.family) == 2 and fam.root:
            out[fam.root] = fam
    return out[-1], out[1]


def steady_precession_rates():
    """Example 4.3's two rates ``(slow, fast)`` from the ``lagrange-top`` model: the precession rates
    ``φ̇ = (ω + ν e)·Γ`` of its two relative equilibria about the symmetry axis, the − and + roots (spin ``s`` →
    ``ω3``, tilt → ``θ``).

    Examples
    --------
    >>> slow, fast = steady_precession_rates()
    >>> fast
    (I3*omega3(t) + sqrt(-4*I1*M*g*l*cos(theta(t)) + I3**2*omega3(t)**2))/(2*I1*cos(theta(t)))
    """
    out = []
    for fam in _precession_families():
        mapping = _text_symbols(fam, s=S.omega3, theta=S.theta)
        out.append(sp.sympify(fam.precession).xreplace(mapping))
    return tuple(out)


def steady_precession_existence():
    """The discriminant the two rates need ≥ 0 (their family's existence condition ``D ≥ 0``), as ``D``.

    Examples
    --------
    >>> steady_precession_existence()
    -4*I1*M*g*l*cos(theta(t)) + I3**2*omega3(t)**2
    """
    slow, fast = _precession_families()
    mapping = _text_symbols(slow, s=S.omega3, theta=S.theta)
    condition = slow.exists
    if not isinstance(condition, sp.GreaterThan) or condition != fast.exists:
        raise LookupError(f"expected one discriminant >= 0 for both roots, got {condition} and {fast.exists}")
    return (condition.lhs - condition.rhs).xreplace(mapping)


def sleeping_top_threshold():
    """§4.5's bound on the spin of the sleeping top from the ``lagrange-top`` model: the family that spins about
    the vertical with its axis up (``Γ = e3``, ``ω = s e3``), its proven conditions, and the value of ``s²`` where the
    classification changes — each candidate root of a boundary factor, tested on both sides at the model's numbers.

    Examples
    --------
    >>> sleeping_top_threshold()
    4*I1*M*g*l/I3**2
    """
    for fam in _families("lagrange-top"):
        state = fam.state
        if fam.kind != "permanent rotation" or sp.sympify(state.get("gamma3")) != 1 or len(fam.family) != 1:
            continue
        s = fam.family[0]
        if sp.sympify(state["omega3"]) != s:
            continue
        st = fam.stability()
        u = sp.Symbol("u", positive=True)
        candidates = set()
        for rel in st.conditions.atoms(sp.core.relational.Relational):
            p = sp.Poly(sp.numer(sp.together(rel.lhs - rel.rhs)), s)
            if p.degree() < 2 or any(m[0] % 2 for m in p.monoms()):
                continue  # a bound on s² is a polynomial in s²
            q = sp.Poly(sum(c * u ** (m[0] // 2) for m, c in p.terms()), u)
            candidates.update(r for r in sp.roots(q) if r != 0)
        defaults = {p: sp.Rational(str(v)) for p, v in fam._context.mech.parameters}
        for c in sorted(candidates, key=sp.default_sort_key):
            value = c.xreplace(defaults)
            if not (value.is_positive):
                continue
            below = st.classify({s.name: float(sp.sqrt(value * sp.Rational(99, 100)))})
            above = st.classify({s.name: float(sp.sqrt(value * sp.Rational(101, 100)))})
            if below == "unstable" and above != "unstable":
                return c.xreplace(_text_symbols(fam))
    raise LookupError("no spin threshold found for the sleeping top")
