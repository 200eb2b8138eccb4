"""The chapter's stability results, derived by the general machinery from the bundled model files alone.

Each function loads a bundled model, finds its steady motions (:func:`eulersym.model.steady.steady_motions`), picks
the family by its structure (never by a typed answer) — or, for the sleeping top, linearises the model's equations
about the motion the text names — and returns the quantity in the text's symbols
(:mod:`eulersym.symbols`), for :mod:`eulersym.text` to compare with the closed form typed there:

- :func:`intermediate_axis_growth_rate` — Example 4.2: the permanent rotation of ``torque-free`` that is unstable
  at the model's numbers (the middle axis), the positive root of its reduced characteristic polynomial;
- :func:`steady_precession_rates` — Example 4.3: ``lagrange-top``'s two relative equilibria about its symmetry axis
  (the − and + roots of the solver's quadratic), their precession rates ``φ̇ = (ω + ν e)·Γ``;
- :func:`steady_precession_existence` — the discriminant those roots need ≥ 0;
- :func:`sleeping_top_threshold` — §4.5: spin about the vertical with the axis up, shown steady by
  ``lagrange-top``'s own equations, linearised there, and the value of ``s²`` where its spectrum leaves the
  imaginary axis (the sleeping motion alone: no other family is solved for).

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
    """§4.5's bound on the spin of the sleeping top from the ``lagrange-top`` model's own equations of motion.

    The sleeping top spins about the vertical with its axis up: ``ω = s e3``, ``Γ = e3``. That state is shown to be
    steady (the model's rates vanish there exactly), its linearisation ``J`` is taken, and the characteristic
    polynomial of ``J``, its zero modes (the level sets of the integrals) divided out, is a polynomial in
    ``μ = λ²``: the spectrum lies on the imaginary axis exactly while its roots in ``μ`` are real and ≤ 0, so the
    classification can change only where its discriminant or its constant term vanishes. Each positive root in
    ``s²`` of those factors is tested on both sides (the eigenvalues of ``J`` at the model's numbers, 30 digits);
    the bound is the one with unstable motions below and none above. Only the sleeping family is derived (the
    other steady motions of the model are :func:`eulersym.model.steady.steady_motions`'s; Example 4.3's entries
    use them).

    Examples
    --------
    >>> sleeping_top_threshold()
    4*I1*M*g*l/I3**2
    """
    import mpmath

    from eulersym.model.mechanics import GAMMA, OMEGA
    from eulersym.model.spec import Model
    from eulersym.models import bundled

    model = Model.from_toml(bundled()["lagrange-top"])
    eqs = model.equations()
    x = [*OMEGA, *GAMMA]
    f = sp.Matrix([eqs.rhs[eqs.state.index(v)] for v in x])
    s = sp.Symbol("s", real=True)
    sleeping = dict(zip(x, (0, 0, s, 0, 0, 1)))  # the motion the text names, not its bound
    if any(sp.cancel(e) != 0 for e in f.xreplace(sleeping)):
        raise LookupError("spin about the vertical, axis up, is not a steady motion of the lagrange-top model")
    J = f.jacobian(x).xreplace(sleeping)
    lam, mu, u = sp.symbols("lam mu u")
    p = sp.Poly(sp.numer(sp.together(J.charpoly(lam).as_expr())), lam)
    zero_modes = min(m[0] for m in p.monoms())
    coeffs = p.all_coeffs()[: len(p.all_coeffs()) - zero_modes]  # highest power first, λ^zero_modes divided out
    if any(sp.expand(c) != 0 for c in coeffs[1::2]):
        raise LookupError("the sleeping top's characteristic polynomial is not even in λ")
    in_mu = sp.Poly(coeffs[::2], mu)
    candidates = set()
    for boundary in (sp.discriminant(in_mu), in_mu.all_coeffs()[-1]):
        for factor, _ in sp.factor_list(boundary)[1]:
            q = sp.Poly(factor, s)
            if q.degree() >= 2 and not any(m[0] % 2 for m in q.monoms()):  # a polynomial in s²: a bound on s²
                q = sp.Poly(sum(c * u ** (m[0] // 2) for m, c in q.terms()), u)
                candidates.update(r for r in sp.roots(q) if r != 0)
    numbers = {p: sp.Rational(str(v)) for p, v in model.mechanics.parameters}

    def unstable(s2) -> bool:
        with mpmath.workdps(30):
            A = mpmath.matrix(J.xreplace({**numbers, s: sp.sqrt(s2)}).evalf(30).tolist())
            eigenvalues = mpmath.eig(A, left=False, right=False)
            return max(mpmath.re(e) for e in eigenvalues) > mpmath.mpf(10) ** -20 * max(map(abs, eigenvalues))

    for c in sorted(candidates, key=sp.default_sort_key):
        value = c.xreplace(numbers)
        if value.is_positive and unstable(value * sp.Rational(99, 100)) and not unstable(value * sp.Rational(101, 100)):
            return c.xreplace({p: getattr(S, p.name) for p in model.mechanics.parameter_symbols
                               if isinstance(getattr(S, p.name, None), sp.Symbol)})
    raise LookupError("no spin threshold found for the sleeping top")
