"""Steady motions of a body on a plane, and their stability from the contact equations (never the free body's).

The reduced state (body components; the attitude about the vertical and the position are ignorable)
    Rolling: ``x = (ω, Γ)`` and ``ẋ = f(x)`` the rows ``ω̇, Γ̇`` of :func:`eulersym.model.rolling.newton_euler`
    (they hold neither ``q`` nor the position while no torque depends on them).
    Sliding: ``x = (ω, Γ, V)``, ``V = X v_x + Y v_y`` the centre of mass's horizontal velocity in body components
    (``V·Γ = 0``). The slip is ``u = V + ω × r_P + ż Γ`` (horizontal: the contact point has no vertical velocity),
    and the kernel's equations read, in body components,

    ``I ω̇ + ω × L = N_torque + r_P × (N Γ − κ u)``, ``N = M (g + z̈)``, ``Γ̇ = Γ × ω``,
    ``V̇ = −κ u / M + V × ω``

    (``κ`` the friction law, :func:`eulersym.model.rolling.friction_law`; a vector whose space components change
    at ``v̇`` changes in the body at ``A v̇ + V × ω``). The tests prove these rows equal to the kernel's at seeded
    states.

Steady motions (:func:`steady_motions`)
    As for a body with a fixed point (:mod:`eulersym.model.steady`): the equilibria of ``f(x) = ν G x``, ``G``
    turning every body vector (``ω``, ``Γ``, ``V``) about a symmetry axis ``e`` of the contact equations (proven:
    ``Df·Gx = G f`` exactly). A sliding body's steady motions are those with zero slip (``u = 0``: no friction
    acts, the motion keeps whatever energy it has): ``V = −(ω × r_P + ż Γ)`` and ``V × ω = ν e × V``.
    A disk's contact point ``r_P = −a (Γ1, Γ2, 0)/√(Γ1² + Γ2²)`` holds a square root. The gauge (the body turned
    about ``e3`` until ``Γ1 = 0``) leaves ``√(Γ2²) = σ Γ2``; the half-turn about ``e3`` maps ``Γ2 → −Γ2``, so
    the branch ``σ = +1`` is every motion once, and its solutions with ``Γ2 ≤ 0`` (the wrong branch of the root)
    are filtered out (``Γ2 > 0`` is part of each family's ``exists``). The solver sees the root replaced by
    ``ρ = Γ2 + Γ1²/(2 Γ2)``, equal to it with its first and second derivatives at ``Γ1 = 0``, so that the
    linearisation there is exact.

Stability (:meth:`eulersym.model.steady.Family.stability`)
    ``J = ∂f/∂x − ν G`` at a member (sliding: ``ω̇`` implicit, ``∂ω̇/∂x = −(∂E/∂ω̇)⁻¹ ∂E/∂x`` of the Newton–Euler
    residual ``E``); ``det(λ − J) = λ^k P(λ)`` where the ``k`` lowest coefficients vanish identically on the
    family (the level sets of ``|Γ|²``, ``V·Γ``, the integrals, and the orbit of the symmetry); then, as in
    :mod:`eulersym.model.stability`, ``P`` even: spectral stability, else Hurwitz's conditions (asymptotic).

Examples
--------
>>> from eulersym.model.contact_examples import examples
>>> families = steady_motions(examples()["euler-disk"])
>>> [f.name for f in families]  # doctest: +NORMALIZE_WHITESPACE
['spinning on the rim about a vertical diameter', 'rolling in a straight line',
 'rolling in place (Moffatt) (- root)', 'rolling in place (Moffatt) (+ root)',
 'steady circular rolling (numeric members)']
>>> families.named("rolling in a straight line").stability().conditions       # Kane's v² ≥ g a / 3
3*a*s**2 - g >= 0
"""

from __future__ import annotations

import functools
import random
import time
from dataclasses import dataclass, replace

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.model._exact import DRIFT, _is_zero, _tidy
from eulersym.model.mechanics import GAMMA, OMEGA, Q
from eulersym.model.rolling import BodyOnPlane, _kinematics, friction_law, newton_euler
from eulersym.model.steady import (DEFAULT_BUDGET, Family, SteadyMotions, _Context, _equivariant, _rational,
                                   _solve)
from eulersym.model.stability import (LAM, Stability, _cancel, _factor, _vanishes, _verdict,
                                      hurwitz_conditions, positive_parameters, real_nonpositive_roots)

__all__ = ["VELOCITY_BODY", "steady_motions", "reduced_rates"]

#: The centre of mass's horizontal velocity in body components (a sliding body's reduced state).
VELOCITY_BODY: tuple = sp.symbols("V1 V2 V3", real=True)
_OMEGA_DOT = sp.symbols("omega1dot omega2dot omega3dot", real=True)


# ----------------------------------------------------------------------------------------------------------------
# The reduced equations


@dataclass(frozen=True, eq=False)
class _Reduced:
    """A body's reduced contact equations: ``x``, the residual ``E(x, ω̇) = 0`` that fixes ``ω̇`` and the rates
    ``ẋ(x, ω̇)`` (rolling: the kernel's rows, ``ω̇`` explicit), the slip-free velocity ``V(ω, Γ)``."""

    body: BodyOnPlane
    x: tuple
    rates: tuple          # in x and ω̇ (sliding) or x alone (rolling: explicit)
    residual: tuple       # E(x, ω̇), sliding only
    slip_free: tuple      # V = −(ω × r_P + ż Γ), sliding only
    roots: tuple          # bases b whose b**(k/2) the rows hold (a disk: Γ1² + Γ2²)


def _sliding_parts(body: BodyOnPlane):
    k = _kinematics(body)
    mech = body.mechanics
    M, g = mech.mass, body.gravity
    w, G, r = k.w, k.G, k.r
    wd = sp.Matrix(_OMEGA_DOT)
    V = sp.Matrix(VELOCITY_BODY)
    u = V + w.cross(r) + k.height_rate * G
    zd = k.height_rate
    zdd = (sum((sp.diff(zd, x) * xd for x, xd in zip(GAMMA, k.Gdot)), sp.Integer(0))
           + sum((sp.diff(zd, x) * xd for x, xd in zip(OMEGA, wd)), sp.Integer(0)))
    N = M * (g + zdd)
    size = sp.sqrt(sum(c ** 2 for c in u))
    kappa = friction_law(body, size, 0, N)
    residual = k.I * wd + w.cross(k.L) - k.torque - r.cross(N * G - kappa * u)
    rates = [*wd, *k.Gdot, *(-kappa * u / M + V.cross(w))]
    slip_free = -(w.cross(r) + k.height_rate * G)
    return tuple(residual), tuple(rates), tuple(slip_free)


@functools.lru_cache(maxsize=16)
def _reduced(body: BodyOnPlane) -> _Reduced:
    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane")
    if body.sliding:
        residual, rates, slip_free = _sliding_parts(body)
        x = (*OMEGA, *GAMMA, *VELOCITY_BODY)
        exprs = [*residual, *rates]
    else:
        eqs = newton_euler(body)
        rates = tuple(eqs.rhs[:6])
        residual, slip_free = (), ()
        x = (*OMEGA, *GAMMA)
        exprs = list(rates)
    from eulersym.model.contact import contact_point

    del exprs
    roots = sorted({p.base for p in sp.Matrix(contact_point(body.contact.surface)).atoms(sp.Pow)
                    if not p.exp.is_Integer and p.base.has(*GAMMA)}, key=sp.default_sort_key)
    return _Reduced(body, x, tuple(rates), residual, slip_free, tuple(roots))


def reduced_rates(body: BodyOnPlane) -> tuple:
    """``(x, ẋ)``: a body's reduced state and its rates, in body components (module docstring); a sliding body's
    ``ω̇`` solved (at numbers, prefer :func:`eulersym.model.rolling.newton_euler`'s kernels).

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> x, rates = reduced_rates(examples()["rolling-sphere"])
    >>> [str(s) for s in x], [sp.cancel(r) for r in rates[:3]]      # Landau §38: ω constant in the body too
    (['omega1', 'omega2', 'omega3', 'gamma1', 'gamma2', 'gamma3'], [0, 0, 0])
    """
    red = _reduced(body)
    if not red.residual:
        return red.x, tuple(red.rates)
    E = sp.Matrix(red.residual)
    J = E.jacobian(list(_OMEGA_DOT))
    b = -E.xreplace({a: 0 for a in _OMEGA_DOT})
    solved = dict(zip(_OMEGA_DOT, J.LUsolve(b)))
    return red.x, tuple(sp.sympify(e).xreplace(solved) for e in red.rates)


def _local(expr, roots):
    """``expr`` with each ``(Γ1² + Γ2²)^(k/2)`` written ``ρ^k``, ``ρ = Γ2 + Γ1²/(2 Γ2)`` (the root's value and its
    first two derivatives at ``Γ1 = 0``, ``Γ2 > 0``)."""
    if not roots:
        return expr
    g1, g2 = GAMMA[0], GAMMA[1]
    rho = g2 + g1 ** 2 / (2 * g2)
    base = g1 ** 2 + g2 ** 2
    return sp.sympify(expr).replace(lambda e: e.is_Pow and e.base == base and not e.exp.is_Integer,
                                    lambda e: rho ** (2 * e.exp))


def _symmetric(body: BodyOnPlane, e) -> bool:
    """Whether turning the body's vectors about ``e`` maps the contact equations to themselves, from their
    ingredients: Newton–Euler in body components is built of cross products, ``I`` and ``r_P(Γ)``, so it is
    equivariant when ``I`` commutes with ``[e]×``, the rotor is along ``e``, the model has no torque of its own
    (the contact's resistances are covariant) and the contact point is: ``(∂r_P/∂Γ)(e × Γ) = e × r_P`` — shown
    exactly on the rational parametrisation ``(Γ1, Γ2) = r (2 s, 1 − s²)/(1 + s²)`` of the root ``r``. (Writing
    out the identity for the whole rows takes minutes where this takes milliseconds.)"""
    from eulersym.model.contact import contact_point

    mech = body.mechanics
    e = sp.Matrix(e)
    S = _skew(e)
    I = sp.Matrix(mech.inertia)
    if any(sp.expand(c) != 0 for c in (I * S - S * I)) or any(sp.expand(c) != 0 for c in
                                                              sp.Matrix(mech.rotor).cross(e)):
        return False
    if any(sp.sympify(c) != 0 for c in mech.torque) or sp.sympify(mech.potential) != 0:
        return False
    rp = sp.Matrix(contact_point(body.contact.surface))
    G = sp.Matrix(GAMMA)
    d = rp.jacobian(list(GAMMA)) * e.cross(G) - e.cross(rp)
    r, t = sp.Symbol("r", positive=True), sp.Symbol("s", real=True)
    base = GAMMA[0] ** 2 + GAMMA[1] ** 2
    circle = {GAMMA[0]: r * 2 * t / (1 + t ** 2), GAMMA[1]: r * (1 - t ** 2) / (1 + t ** 2)}
    for c in d:
        c = sp.sympify(c).replace(lambda p: p.is_Pow and p.base == base and not p.exp.is_Integer,
                                  lambda p: r ** (2 * p.exp)).xreplace(circle)
        if sp.cancel(sp.together(c)) != 0:
            return False
    return True


# ----------------------------------------------------------------------------------------------------------------
# The context handed to the solver


@functools.lru_cache(maxsize=16)
def _contact_context(body: BodyOnPlane):
    from eulersym.model.integrals import symmetry_axis

    red = _reduced(body)
    mech = body.mechanics
    notes = []
    supported = all(sp.expand(b - GAMMA[0] ** 2 - GAMMA[1] ** 2) == 0 for b in red.roots)
    x = list(OMEGA) + list(GAMMA)
    if body.sliding:
        # zero slip: friction does not act; ω̇ from the residual with u = 0
        E = sp.Matrix(red.residual).xreplace(dict(zip(VELOCITY_BODY, red.slip_free)))
        E = E.applyfunc(lambda e: _rational(sp.expand(e)))
        true_rows = None  # ω̇ is not written out: a steady motion has ω̇ = ν e × ω, put into E directly
        V = sp.Matrix(red.slip_free)
        extra_eqs = lambda e: [sp.expand(c) for c in (V.cross(sp.Matrix(OMEGA)) - DRIFT * e.cross(V))]  # noqa: E731
        notes.append("sliding: the steady motions with zero slip (u = 0, so friction does not act): "
                     "V = −(ω × r_P + ż Γ) and V × ω = ν e × V")
    else:
        true_rows = [_rational(e) for e in red.rates]
        extra_eqs = None
    if true_rows is not None and any(sp.sympify(e).has(*Q, sp.Symbol("t")) for e in true_rows):
        return None, ["the reduced equations hold the attitude about the vertical or t: not searched"]
    if not supported:
        return None, ["the contact point holds a square root other than √(Γ1² + Γ2²): not searched"]
    # symmetry axes, proven on the equations as they stand (with their roots)
    I = sp.Matrix(_rational(mech.inertia))
    candidates = []
    axis = symmetry_axis(I)
    if axis is not None:
        candidates.append([k for k in range(3) if axis[0][k] != 0][0])
    elif I.is_diagonal() and sp.expand(I[0, 0] - I[1, 1]) == 0 and sp.expand(I[1, 1] - I[2, 2]) == 0:
        candidates += [2, 0, 1]
    symmetries = []
    for k in candidates:
        e = sp.zeros(3, 1)
        e[k] = 1
        if _symmetric(body, e) if (red.roots or true_rows is None) else _equivariant(x, true_rows, e):
            symmetries.append((f"e{k + 1}", sp.ImmutableMatrix(e), k))
            break
    positive = ()
    if true_rows is None:
        # f − ν G x = 0 on the ω rows is E(x, ω̇ = ν e × ω) = 0: rows ν e × ω − E give it
        e = sp.Matrix(symmetries[0][1]) if symmetries else sp.zeros(3, 1)
        steady_wd = DRIFT * e.cross(sp.Matrix(OMEGA))
        E_steady = E.xreplace(dict(zip(_OMEGA_DOT, steady_wd)))
        true_rows = [sp.expand(a - b) for a, b in zip(steady_wd, E_steady)] + list(red.rates[3:6])
    rows = list(true_rows)
    if red.roots:
        if not symmetries or symmetries[0][2] != 2:
            return None, ["the contact point's root needs the symmetry about e3 (its gauge Γ1 = 0): not searched"]
        rows = [_local(e, red.roots) for e in true_rows]
        positive = (GAMMA[1],)
        notes.append("the contact point's √(Γ1² + Γ2²) solved on its branch Γ2 > 0 in the gauge Γ1 = 0 (the "
                     "half-turn about e3 maps Γ2 < 0 to it): members with Γ2 ≤ 0 filtered out")
    solving = [sp.cancel(sp.together(e)) for e in rows]
    if red.roots:  # in the gauge Γ1 = 0 (an equation of the solver) the root is Γ2 itself: rational
        pos = sp.Dummy("gamma2", positive=True)
        solving = [sp.cancel(sp.together(e.xreplace({GAMMA[0]: 0, GAMMA[1]: pos}).xreplace({pos: GAMMA[1]})))
                   for e in true_rows]
    denominators = []
    for e in solving:
        den = sp.denom(sp.together(e))
        if den.free_symbols & set(x):
            denominators.append(den)
    extra = ()
    if extra_eqs is not None:
        e = symmetries[0][1] if symmetries else sp.zeros(3, 1)
        extra = tuple(extra_eqs(sp.Matrix(e)))
    ctx = _Context(mech, tuple(x), tuple(rows), sp.ImmutableMatrix(sp.eye(3)), tuple(solving), tuple(symmetries),
                   tuple(denominators), tuple(notes), extra, positive, functools.partial(_stability, body), False)
    return ctx, notes


# ----------------------------------------------------------------------------------------------------------------
# Families: the wrong branch filtered, named in the words of the literature


def _named(fam: Family, body: BodyOnPlane) -> str:
    st = {k: sp.sympify(v) for k, v in fam.state.items()}
    w = [st[s.name] for s in OMEGA]
    G = [st[s.name] for s in GAMMA]
    disk = body.contact.surface.kind == "disk"
    if disk and fam.kind == "permanent rotation" and fam.closed_form and _is_zero(G[2]) and _is_zero(w[2]):
        return "spinning on the rim about a vertical diameter"
    if fam.kind == "relative equilibrium" and disk and _is_zero(w[2]) and _is_zero(w[0]):
        return "rolling in place (Moffatt)"
    if fam.kind == "relative equilibrium" and disk and _is_zero(w[0]) and _is_zero(w[1]) and _is_zero(G[2]):
        return "rolling in a straight line"
    if fam.kind == "relative equilibrium" and not disk and _is_zero(G[2]) and _is_zero(w[0]) and _is_zero(w[1]):
        return "rolling in a straight line"
    if not fam.closed_form:
        return "steady circular rolling (numeric members)" if disk else fam.name
    return fam.name


def _positive_symbols(body: BodyOnPlane) -> frozenset:
    """The parameters a body on a plane needs positive: those that alone make its mass, ``g``, a dimension of its
    surface or a principal moment (checked positive at their values by :class:`~eulersym.model.rolling.BodyOnPlane`)."""
    mech = body.mechanics
    out = set(positive_parameters(mech))
    widths = (body.contact.width,) if body.contact.width is not None else ()
    for value in (mech.mass, body.gravity, *body.contact.surface.dimensions, *widths):
        value = sp.sympify(value)
        if isinstance(value, sp.Symbol):
            out.add(value)
    return frozenset(out)


def _filter(families, ctx, body) -> list:
    from eulersym.model.stability import _sign_condition

    positive = _positive_symbols(body)
    out = []
    for fam in families:
        if ctx.positive and fam.closed_form:
            conds = []
            for sym in ctx.positive:
                value = _tidy(sp.sympify(fam.state[sym.name]))
                conds.append(_sign_condition(value, positive, strict=True))
            condition = sp.And(*conds)
            if condition is sp.false:
                continue  # the wrong branch of the root everywhere
            fam.exists = sp.And(fam.exists, condition)
        elif ctx.positive:
            fam._numeric_positive = ctx.positive
            _guard_numeric(fam)
        fam.name = _named(fam, body)
        out.append(fam)
    return out


def _guard_numeric(fam: Family) -> None:
    """A numeric family's members on the right branch only (``Γ2 > 0``)."""
    system = fam._numeric
    members = system.members

    def kept(point):
        return [m for m in members(point) if all(m[s.name] > 0 for s in fam._numeric_positive)]

    system.members = kept


def _closed_slice(fam: Family, ctx, body: BodyOnPlane) -> list:
    """A numeric family whose last equation is quadratic in one of its family symbols, solved for it (the unknown
    left becomes the family's rate ``s``): one closed-form family per root."""
    from eulersym.model.stability import _sign_condition
    from eulersym.model.steady import _square_part

    system = fam._numeric
    if len(system.equations) != 1 or len(system.unknowns) != 1:
        return []
    eq, u = sp.expand(system.equations[0]), system.unknowns[0]
    rate = sp.Symbol("s", real=True)
    positive = _positive_symbols(body)
    out = []
    for sym in fam.family:
        p = sp.Poly(eq, sym)
        if p.degree() != 2:
            continue
        a2, a1, a0 = (sp.expand(c.xreplace({u: rate})) for c in p.all_coeffs())
        f, rest = _square_part(sp.expand(a1 ** 2 - 4 * a2 * a0))
        others = tuple(x for x in fam.family if x is not sym)
        for sign in (-1, 1):
            root = (-a1 + sign * f * sp.sqrt(rest)) / (2 * a2)
            sub = {u: rate, sym: root}
            state = {k: _tidy(sp.sympify(v).xreplace(sub)) for k, v in fam.state.items()}
            exists = [_sign_condition(rest, positive, strict=False)]
            exists += [_sign_condition(_tidy(state[g.name]), positive, strict=True) for g in ctx.positive]
            if sp.And(*exists) is sp.false:
                continue
            e = sp.Matrix(ctx.symmetries[0][1])
            w = sp.Matrix([state[x.name] for x in OMEGA])
            G = sp.Matrix([state[x.name] for x in GAMMA])
            eG = e.cross(G)
            drift = _tidy((G.cross(w)).dot(eG) / eG.dot(eG))
            precession = _tidy((w + drift * e).dot(G))
            how = f"{fam.how}; its last equation solved for {sym} ({'-' if sign < 0 else '+'} root)"
            out.append(Family(f"{_named(fam, body)} ({'-' if sign < 0 else '+'} root)", "relative equilibrium",
                              (rate, *others), state, sp.And(*exists), (), {ctx.symmetries[0][0]: drift},
                              precession, True, how, sign, ctx, None, None))
        break
    for closed in out:
        closed.name = _named(closed, body) + closed.name[closed.name.rindex(" ("):]
    return out


def steady_motions(body: BodyOnPlane, *, budget: float = DEFAULT_BUDGET) -> SteadyMotions:
    """The families of steady motions of a body on a plane (module docstring), each with its stability from the
    contact equations (:meth:`Family.stability`).

    Parameters
    ----------
    body : eulersym.model.rolling.BodyOnPlane
        From :mod:`eulersym.model.contact_examples` or a model with ``[contact]`` (``Model.body_on_plane``).
    budget : float
        Seconds the exact solver may spend.

    Returns
    -------
    SteadyMotions
        The families; ``notes`` say what was solved (the root's branch, zero slip) or why nothing was searched.

    Raises
    ------
    eulersym.errors.InvalidInput
        ``body`` not a body on a plane; ``budget`` not a positive number.
    eulersym.model.steady.SteadyMotionUndecided
        The exact solver did not finish within ``budget``.

    Examples
    --------
    Euler's disk rolls in place at Moffatt's Ω² sin α = 4 g / a: ``ω`` along the diameter through the contact, the
    disk's tilt ``α`` from the table with ``sin α = Γ2``:

    >>> from eulersym.model.contact_examples import examples
    >>> moffatt = steady_motions(examples()["euler-disk"]).named("rolling in place (Moffatt) (+ root)")
    >>> moffatt.state["gamma2"]                                          # sin α, for ω = (0, s, 0)
    a*s**2/(4*g)
    >>> sp.cancel(moffatt.state["omega2"] ** 2 / moffatt.state["gamma2"])  # Ω² sin α with Ω = s / sin α
    4*g/a
    """
    if isinstance(budget, bool) or not isinstance(budget, (int, float)) or not budget > 0:
        raise InvalidInput("budget", budget, "a positive number of seconds")
    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane (a body on a plane)")
    return _steady_motions(body, float(budget))


@functools.lru_cache(maxsize=16)
def _steady_motions(body: BodyOnPlane, budget: float) -> SteadyMotions:
    start = time.monotonic()
    ctx, notes = _contact_context(body)
    if ctx is None:
        return SteadyMotions([], notes)
    found = _solve(ctx, body.name, start + budget, list(notes))
    families = _filter(list(found), ctx, body)
    notes = list(found.notes)
    if not ctx.positive:
        left = [f for f in families if not f.closed_form]
        if left:
            families = [f for f in families if f.closed_form]
            notes.append(f"{len(left)} branch(es) without a closed form left out (their polynomial systems are not "
                         "zero-dimensional at generic numbers: degenerate leftovers of the closed-form families)")
    if ctx.symmetries and any(not f.closed_form for f in families):
        # the closed-form slice of a numeric family without spin about the axis (Moffatt's rolling in place)
        k = ctx.symmetries[0][2]
        sliced = _solve(replace(ctx, extra=ctx.extra + (OMEGA[k],)), body.name, start + budget, [])
        for fam in _filter(list(sliced), ctx, body):
            for closed in ([fam] if fam.closed_form else _closed_slice(fam, ctx, body)):
                if closed.kind == "relative equilibrium" and not any(
                        f.closed_form and f.state == closed.state for f in families):
                    families.append(closed)
    for fam in families:
        if not fam.closed_form and ctx.symmetries:
            fam.kind = "relative equilibrium"
    order = {"equilibrium": 0, "permanent rotation": 1, "relative equilibrium": 2}
    families.sort(key=lambda f: (not f.closed_form, order[f.kind]))
    return SteadyMotions(families, notes)


# ----------------------------------------------------------------------------------------------------------------
# Stability from the contact equations


def _skew(e) -> sp.Matrix:
    e = sp.Matrix(e)
    return sp.Matrix([[0, -e[2], e[1]], [e[2], 0, -e[0]], [-e[1], e[0], 0]])


def _jacobian(body: BodyOnPlane, point: dict) -> sp.Matrix:
    """``∂ẋ/∂x`` of the reduced contact equations at an exact point (sliding: through the implicit ``ω̇``)."""
    red = _reduced(body)
    x = list(red.x)
    if not red.residual:
        rows = sp.Matrix([_local(_rational(e), red.roots) for e in red.rates])
        return rows.jacobian(x).xreplace(point).applyfunc(_cancel)
    E = sp.Matrix([_rational(e) for e in red.residual])
    F = sp.Matrix([_rational(e) for e in red.rates])
    JE = E.jacobian(list(_OMEGA_DOT)).xreplace(point).applyfunc(_cancel)
    b = -E.xreplace({a: 0 for a in _OMEGA_DOT}).xreplace(point).applyfunc(_cancel)
    wd = {a: _cancel(v) for a, v in zip(_OMEGA_DOT, JE.LUsolve(b))}
    at = {**point, **wd}
    dE = E.jacobian(x).xreplace(at).applyfunc(_cancel)
    d_omega = -(JE.LUsolve(dE)).applyfunc(_cancel)
    dF = F.jacobian(x).xreplace(at).applyfunc(_cancel)
    dW = F.jacobian(list(_OMEGA_DOT)).xreplace(at).applyfunc(_cancel)
    return (dF + dW * d_omega).applyfunc(_cancel)


class ContactStability(Stability):
    """The stability of a family of a body on a plane, from the contact equations' Jacobian (module docstring).

    :meth:`classify` and :meth:`eigenvalues` decide a member at numbers from the eigenvalues of ``J`` there (40
    digits; the trivial zero modes, numerically zero, dropped). ``characteristic_polynomial`` and ``conditions``
    (where the family is spectrally or asymptotically stable, proven) are written out on first use, within
    :data:`CONDITIONS_BUDGET` seconds (None beyond it). A numeric family has neither: it is decided member by member.
    """

    def __init__(self, family, body: BodyOnPlane, jacobian):
        self.family = family
        self._body = body
        self._jacobian_public = jacobian
        self.chart = None
        self._readable = None
        self._lyapunov_inputs = None

    def __repr__(self) -> str:
        return f"ContactStability({self.family.name!r})"

    @functools.cached_property
    def _analysis(self):
        if self._jacobian_public is None:
            return None
        return _analyse(self.family, self._body, self._jacobian_public)

    @property
    def _coefficients(self):
        return self._analysis[0] if self._analysis else ()

    @property
    def _removed(self):
        return self._analysis[1] if self._analysis else 0

    @property
    def conditions(self):
        """Where the family is stable (``dissipative``: asymptotically, Hurwitz; else spectrally), or None."""
        return self._analysis[2] if self._analysis else None

    @property
    def dissipative(self) -> bool:
        """Whether ``P(λ)`` is not even (friction): the conditions are Hurwitz's."""
        return self._analysis[3] if self._analysis else True

    @property
    def reduced(self) -> str:
        """What was divided out of ``det(λ − J)``."""
        return self._analysis[4] if self._analysis else "numeric: the zero modes removed at each member"

    @functools.cached_property
    def characteristic_polynomial(self):
        """``P(λ)``: ``det(λ − J)`` with its trivial factor ``λ^k`` divided out (None for a numeric family)."""
        from eulersym.model.stability import _pretty_poly

        return _pretty_poly(self._coefficients) if self._coefficients else None

    def _matrix_at(self, values):
        fam = self.family
        body = self._body
        point = fam.values(values)
        members = fam.members(values)
        if not members:
            raise InvalidInput("values", dict(values or {}), f"numbers where {fam.name!r} exists ({fam.exists})")
        if self._jacobian_public is not None:
            return self._jacobian_public.xreplace(point)
        at = dict(point)
        at.update({sp.Symbol(k, real=True): sp.Rational(repr(v)) for k, v in members[0].items()})
        red = _reduced(body)
        if body.sliding:
            at.update(dict(zip(VELOCITY_BODY, [sp.sympify(c).xreplace(at) for c in red.slip_free])))
        J = _jacobian(body, at)
        symmetries = fam._context.symmetries
        if symmetries:
            e = sp.Matrix(symmetries[0][1])
            w = sp.Matrix([at[x] for x in OMEGA])
            G = sp.Matrix([at[x] for x in GAMMA])
            eG = e.cross(G)
            drift = (G.cross(w)).dot(eG) / eG.dot(eG) if eG.dot(eG) != 0 else 0
            J = J - drift * sp.diag(*([_skew(e)] * (len(red.x) // 3)))
        return J

    def eigenvalues(self, values=None):
        """The eigenvalues of the reduced linearisation at numbers, the trivial zero modes dropped, sorted by real
        part then imaginary part.

        Examples
        --------
        >>> from eulersym.model.contact_examples import examples
        >>> line = steady_motions(examples()["euler-disk"]).named("rolling in a straight line")
        >>> line.stability().eigenvalues({"s": 20.0}).round(3)     # ± i √((12 a s² − 4 g)/(5 a)), a = 0.0375
        array([0.-27.399j, 0.+27.399j])
        """
        import mpmath
        import numpy as np

        J = self._matrix_at(values)
        with mpmath.workdps(40):
            M = mpmath.matrix([[mpmath.mpf(str(sp.N(e, 45))) for e in row] for row in J.tolist()])
            ev = [complex(v) for v in mpmath.eig(M, left=False, right=False)]
        scale = max([1.0] + [abs(v) for v in ev])
        # a closed-form member is exact, but its zero modes may form Jordan blocks (split to ~1e-20 at 40 digits);
        # a numeric member is known to double precision
        tol = 1e-12 if self._jacobian_public is not None else 1e-7
        out = np.array([v for v in ev if abs(v) > tol * scale], dtype=complex)
        out.real[np.abs(out.real) < tol * scale] = 0.0
        return out[np.lexsort((out.imag, out.real))]

    def classify(self, values=None) -> str:
        """``"unstable"``, ``"spectrally stable"`` or ``"asymptotically stable"`` at numbers (the eigenvalues).

        Examples
        --------
        >>> from eulersym.model.contact_examples import examples
        >>> line = steady_motions(examples()["euler-disk"]).named("rolling in a straight line")
        >>> line.stability().classify({"s": 20.0}), line.stability().classify({"s": 5.0})   # s² ≷ g/(3 a)
        ('spectrally stable', 'unstable')
        """
        roots = self.eigenvalues(values)
        tol = 1e-12 if self._jacobian_public is not None else 1e-7
        return _verdict(roots, tol * (1.0 + (max(abs(roots)) if len(roots) else 0.0)))


#: Seconds the conditions of one family may take before they are left to the eigenvalues at numbers.
CONDITIONS_BUDGET = 20.0


@functools.lru_cache(maxsize=64)
def _stability(body: BodyOnPlane, fam: Family) -> Stability:
    ctx = fam._context
    red = _reduced(body)
    if not fam.closed_form:
        return ContactStability(fam, body, None)
    x = list(red.x)
    point = {s: sp.sympify(fam.state[s.name]) for s in ctx.x}
    if body.sliding:
        point.update(dict(zip(VELOCITY_BODY, [_tidy(sp.sympify(c).xreplace(point)) for c in red.slip_free])))
    J = _jacobian(body, point)
    if fam.drift:
        drift = next(iter(fam.drift.values()))
        S = _skew(ctx.symmetries[0][1])
        J = (J - drift * sp.diag(*([S] * (len(x) // 3)))).applyfunc(_cancel)
    return ContactStability(fam, body, J)


def _analyse(fam: Family, body: BodyOnPlane, J):
    """``(coefficients, k, conditions, dissipative, reduced)`` of ``det(λ − J) = λ^k P(λ)``."""
    from eulersym._budget import BudgetExceeded, time_budget

    trig = sorted(J.atoms(sp.sin, sp.cos), key=str)
    plain = {f: sp.Dummy(f.func.__name__) for f in trig}
    back = {d: f for f, d in plain.items()}
    full = [_cancel(c.xreplace(back)) for c in J.xreplace(plain).charpoly(LAM).all_coeffs()]
    rng = random.Random(5)
    symbols = list(fam.family)
    k = 0
    for c in full[::-1]:
        if _vanishes(c, fam, symbols, rng):
            k += 1
        else:
            break
    coeffs = [_factor(c) for c in full[:len(full) - k]]
    n = len(coeffs) - 1
    even = all(_vanishes(coeffs[i], fam, symbols, rng) for i in range(1, n + 1, 2))
    positive = _positive_symbols(body)
    conditions = None
    try:
        with time_budget(CONDITIONS_BUDGET):
            if even:
                conditions = real_nonpositive_roots([coeffs[i] for i in range(0, n + 1, 2)], positive)
            else:
                conditions = hurwitz_conditions(coeffs, positive)
    except BudgetExceeded:
        conditions = None
    what = "|Γ|² = 1" + (", V·Γ = 0" if body.sliding else "") + ", the integrals and the orbit"
    return coeffs, k, conditions, not even, f"λ^{k} divided out (identically zero on the family: {what})"
