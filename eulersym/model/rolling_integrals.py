"""Integrals of a body on a plane, proven along the flow of :func:`eulersym.model.rolling.newton_euler` — or refuted.

The rate of a candidate ``H(t, state)`` is ``dH/dt = ∂H/∂t + Σ_x ∂H/∂x · ẋ``. The accelerations ``ω̇`` are the
solution of ``J ω̇ = b`` (:meth:`~eulersym.model.rolling.ContactEquations.linear_system`), so the rate, written with
``ω̇`` as symbols, is linear in them: ``dH/dt = c·ω̇ + d``. Writing out ``ω̇ = adj(J) b / det J`` would make the
zero test a polynomial of high degree; instead the proof looks for the multiplier ``λ`` with ``Jᵀ λ = c`` among
the body's natural vectors (``ω``, ``Γ``, the contact point ``r_P``, ``L = I ω + h``, the angular momentum about
the contact point ``L_P``, and twice each), each tried numerically first and then proven exactly
(:func:`eulersym.compare.compare`). Then, along the flow, ``c·ω̇ = λᵀ J ω̇ = λᵀ b`` and

    ``dH/dt = λᵀ b + d``,

free of accelerations; its zero test is exact. A candidate for which no multiplier is found is decided at
random rational states only (not claimed conserved). A non-conserved candidate comes with a counterexample: a
rational state on the physical manifold (``|q| = 1``, ``Γ = A(q) ẑ``), the parameters at their values, where the
rate — the accelerations solved at 50 digits — is not zero.

Candidates (:func:`candidates`), whatever the body (the verdicts decide):

- ``E`` — the energy ``½ ωᵀ I ω + ½ M |v_G|² + M g z + V``. Its rate is proven equal to the power of the
  non-conservative forces (:func:`dissipation`): the torques other than the potential's (rolling resistance, spin
  friction, the model's) on ω, ``∂V/∂t``, and — sliding — the friction's ``−κ |u|²`` at the slipping contact;
- ``Gamma_norm2`` ``|Γ|²`` and ``q_norm2`` ``|q|²``;
- ``L_dot_Gamma`` — ``L·Γ``, the vertical angular momentum about the centre of mass;
- ``L_contact_vertical`` — ``L_P·Γ`` with ``L_P = L − M r_P × v_G`` (about the contact point);
- ``Jellett`` — ``L·r_P`` (the contact point from the centre of mass: Jellett's integral of the tippe top), for a
  sphere or a disk;
- ``L_contact2`` — ``|L_P|²`` (Chaplygin's ball), for a sphere;
- ``p_x``, ``p_y`` — the horizontal momentum ``M v``, sliding.

Examples
--------
>>> from eulersym.model.contact_examples import examples
>>> v = invariants(examples()["tippe-top"])["Jellett"]
>>> v.conserved, v.exact
(True, True)
"""

from __future__ import annotations

import functools
import random

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.model.derive import OMEGA_DOT
from eulersym.model.integrals import Verdict, _rational, _tidy
from eulersym.model.mechanics import GAMMA, OMEGA, Q, t
from eulersym.model.rolling import (KAPPA, VELOCITY, BodyOnPlane, _default_values, _kinematics, _numeric, _point,
                                    newton_euler, state_symbols)

__all__ = ["SLIP", "energy", "dissipation", "candidates", "prove", "invariants"]

#: Display symbols of the slip velocity in a rate (``κ`` is :data:`eulersym.model.rolling.KAPPA`).
SLIP: tuple = sp.symbols("u_x u_y", real=True)

_COUNTEREXAMPLE_POINTS = 6
#: Operations of J, b and ∂(dH/dt)/∂ω̇ up to which, when no multiplier is found, the rate's numerator
#: ``c·adj(J)·b + d·det J`` is written out and tested for zero.
_ADJUGATE_BUDGET = 1500
_DPS = 30


def _dot(a, b) -> sp.Expr:
    return (sp.Matrix(a).T * sp.Matrix(b))[0, 0]


def _velocity_body(body: BodyOnPlane) -> sp.Matrix:
    """The centre of mass's velocity, body components."""
    k = _kinematics(body)
    if not body.sliding:
        return k.r.cross(k.w)
    return VELOCITY[0] * k.X + VELOCITY[1] * k.Y + k.height_rate * k.G


def energy(body: BodyOnPlane) -> sp.Expr:
    """``E = ½ ωᵀ I ω + ½ M |v_G|² + M g z + V`` (``z = −r_P·Γ``; ``V`` the model's potential).

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> energy(examples()["rolling-sphere"]).has(sp.Symbol("g", real=True))
    True
    """
    k = _kinematics(body)
    mech = body.mechanics
    T = _dot(k.w, k.I * k.w) / 2
    if body.sliding:
        T += mech.mass * (VELOCITY[0] ** 2 + VELOCITY[1] ** 2 + k.height_rate ** 2) / 2
    else:
        v = _velocity_body(body)
        T += mech.mass * _dot(v, v) / 2
    return T + mech.mass * body.gravity * k.height + sp.sympify(mech.potential)


def _torque_nc(body: BodyOnPlane) -> sp.Matrix:
    """The torques that no potential gives: the model's, rolling resistance, spin friction."""
    k = _kinematics(body)
    mech, c = body.mechanics, body.contact
    spin = _dot(k.w, k.G)
    return sp.Matrix(mech.torque) - c.rolling_resistance * (k.w - spin * k.G) - c.spin_friction * spin * k.G


def _dissipation(body: BodyOnPlane, kappa, slip) -> sp.Expr:
    k = _kinematics(body)
    power = _dot(_torque_nc(body), k.w) + sp.diff(sp.sympify(body.mechanics.potential), t)
    if body.sliding and body.contact.friction != "none":
        power += -kappa * (slip[0] ** 2 + slip[1] ** 2)
    return power


def dissipation(body: BodyOnPlane) -> sp.Expr:
    """The power of the non-conservative forces — ``dE/dt`` along the flow, as :func:`invariants` proves it: the
    torques no potential gives on ω, ``∂V/∂t``, and a sliding contact's friction ``−κ (u_x² + u_y²)``, written with
    ``κ`` (:data:`~eulersym.model.rolling.KAPPA`, the friction law's magnitude,
    :func:`eulersym.model.rolling.friction_law`) and the slip ``u`` (:data:`SLIP`) as symbols.

    Examples
    --------
    >>> from eulersym.model.contact_examples import euler_disk, tippe_top
    >>> dissipation(tippe_top())
    -kappa_friction*(u_x**2 + u_y**2)
    >>> upright = dict(zip(sp.symbols("gamma1:4", real=True), (0, 0, 1)))
    >>> sp.factor(dissipation(euler_disk(c_r=0.01)).subs(upright))       # against the rolling, not the spin
    -c_r*(omega1**2 + omega2**2)
    """
    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane")
    return _dissipation(body, KAPPA, SLIP)


def _momentum_about_contact(body: BodyOnPlane) -> sp.Matrix:
    k = _kinematics(body)
    return k.L - body.mechanics.mass * k.r.cross(_velocity_body(body))


def candidates(body: BodyOnPlane) -> dict:
    """``{name: expression}`` of the candidates (module docstring), in the state's names.

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> list(candidates(examples()["chaplygin-ball"]))
    ['E', 'Gamma_norm2', 'q_norm2', 'L_dot_Gamma', 'L_contact_vertical', 'Jellett', 'L_contact2']
    """
    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane")
    k = _kinematics(body)
    LP = _momentum_about_contact(body)
    out = {"E": energy(body), "Gamma_norm2": _dot(k.G, k.G), "q_norm2": sum(q ** 2 for q in Q),
           "L_dot_Gamma": _dot(k.L, k.G), "L_contact_vertical": _dot(LP, k.G)}
    kind = body.contact.surface.kind
    if kind in ("sphere", "disk"):
        out["Jellett"] = _dot(k.L, k.r)
    if kind == "sphere":
        out["L_contact2"] = _dot(LP, LP)
    if body.sliding:
        out["p_x"] = body.mechanics.mass * VELOCITY[0]
        out["p_y"] = body.mechanics.mass * VELOCITY[1]
    return out


# ----------------------------------------------------------------------------------------------------------------
# The rate along the flow


def _check_candidate(body: BodyOnPlane, expr) -> sp.Expr:
    if isinstance(expr, sp.MatrixBase) or not isinstance(expr, sp.Expr):
        raise InvalidInput("candidate", expr, "one scalar SymPy expression (a vector is not an integral)")
    allowed = {*state_symbols(body), t, *body.mechanics.parameter_symbols}
    extra = sorted(expr.free_symbols - allowed, key=sp.default_sort_key)
    if extra:
        names = ", ".join(sorted(s.name for s in allowed))
        raise InvalidInput("candidate", str(expr), f"an expression in the model's names only ({names}); "
                           f"unknown: {', '.join(map(str, extra))}")
    if expr.has(sp.Derivative) or expr.atoms(sp.core.function.AppliedUndef):
        raise InvalidInput("candidate", str(expr), "a function of the state, t and the parameters (no derivatives)")
    return expr


@functools.lru_cache(maxsize=64)
def _flow(body: BodyOnPlane) -> tuple:
    """``(state, rates, J, b)`` with ``κ`` a symbol (:meth:`~eulersym.model.rolling.ContactEquations.friction_system`)."""
    eqs = newton_euler(body)
    J, b, rates = eqs.friction_system()
    return eqs.state, tuple(_rational(e) for e in rates), _rational(J), _rational(b)


@functools.lru_cache(maxsize=64)
def _true_flow(body: BodyOnPlane) -> tuple:
    """``(J, b, κ(ω̇))`` of the body's own friction law (Coulomb's ``κ`` holds ``N(ω̇)``)."""
    eqs = newton_euler(body)
    J, b = eqs.linear_system()
    return _rational(J), _rational(b), _rational(eqs.free_friction())


def _rate(body: BodyOnPlane, H) -> sp.Expr:
    state, rates, _, _ = _flow(body)
    out = sp.diff(H, t)
    for x, xdot in zip(state, rates):
        d = sp.diff(H, x)
        if d != 0:
            out += d * xdot
    return out


def _multipliers(body: BodyOnPlane) -> list:
    k = _kinematics(body)
    LP = _momentum_about_contact(body)
    vectors = [("ω", k.w), ("Γ", k.G), ("r_P", k.r), ("L", k.L), ("L_P", LP)]
    return [(f"{factor}·{name}" if factor != 1 else name, factor * sp.Matrix(v))
            for name, v in vectors for factor in (1, 2)]


@functools.lru_cache(maxsize=32)
def _states(body: BodyOnPlane, seed: int) -> tuple:
    """Seeded states on the physical manifold (``|q| = 1``, ``Γ = A(q) ẑ``), the first half with the parameters at
    their values, each with ``ω̇`` solved from the body's own equations and ``κ`` its friction law's value, at 30
    and 50 digits: ``((point, {30: values, 50: values}), ...)``."""
    import mpmath

    state = _flow(body)[0]
    J, b, law = _true_flow(body)
    solvers = {dps: _numeric([*J, *b], dps) for dps in (_DPS, 50)}
    rng = random.Random(seed)
    defaults = _default_values(body.mechanics)
    symbols = sorted({*state, t, *body.mechanics.parameter_symbols}, key=sp.default_sort_key)
    out = []
    for attempt in range(_COUNTEREXAMPLE_POINTS):
        physical = attempt < _COUNTEREXAMPLE_POINTS // 2
        point = _point(symbols, rng, defaults if physical else {})
        point.update(defaults if physical else {s: sp.Rational(rng.randint(5, 20), 10) for s in defaults})
        values = {}
        try:
            for dps in (_DPS, 50):
                with mpmath.workdps(dps + 10):
                    numbers = [mpmath.mpf(str(v)) for v in solvers[dps](point)]
                    A = mpmath.matrix([[numbers[3 * i + j] for j in range(3)] for i in range(3)])
                    x = mpmath.lu_solve(A, mpmath.matrix(numbers[9:]))
                full = {**point, **{s: sp.Float(str(x[i]), dps + 10) for i, s in enumerate(OMEGA_DOT)}}
                full[KAPPA] = law.xreplace(full).evalf(dps + 10)
                values[dps] = full
        except (ZeroDivisionError, ValueError, TypeError):  # a singular J at this point: skip it
            continue
        out.append((point, values))
    return tuple(out)


def _counterexample(body: BodyOnPlane, rate, seed: int, first: int | None = None) -> dict | None:
    """A state where ``rate`` (in the state, ``ω̇`` and ``κ``) is not zero along the flow, or None (the first
    ``first`` states only, if given)."""
    if rate == 0:
        return None
    rate = sp.sympify(rate)
    for point, values in _states(body, seed)[:first]:
        low = rate.xreplace(values[_DPS]).evalf(_DPS)
        if not (low.is_number and low.is_finite and abs(low) > 1e-20):
            continue
        high = rate.xreplace(values[50]).evalf(50)
        if abs(high - low) <= 1e-6 * abs(low):
            return {str(k): float(v) for k, v in sorted(point.items(), key=lambda kv: sp.default_sort_key(kv[0]))}
    return None


def _eliminate(body: BodyOnPlane, rate, seed: int) -> tuple:
    """``(rate free of ω̇, how)`` by a multiplier ``λ`` with ``Jᵀ λ = c`` (module docstring), or ``(None, why)``."""
    from eulersym.compare import compare

    _, _, J, b = _flow(body)
    c = sp.Matrix([sp.diff(rate, a) for a in OMEGA_DOT])
    d = rate.xreplace({a: 0 for a in OMEGA_DOT})
    if all(x == 0 for x in c):
        return d, "no accelerations in the rate"
    probe = dict(_states(body, seed)[0][1][_DPS])
    c_at = [complex(x.xreplace(probe).evalf(20)) for x in c]
    scale = max(map(abs, c_at)) or 1.0
    for name, v in _multipliers(body):
        w = J.T * v
        w_at = [complex(x.xreplace(probe).evalf(20)) for x in w]
        if max(abs(p - q) for p, q in zip(c_at, w_at)) > 1e-12 * scale:
            continue
        if compare(list(c), list(w), seed=seed).exact is True:
            return _dot(v, b) + d, f"multiplier λ = {name} (Jᵀλ = ∂(dH/dt)/∂ω̇ proven exactly)"
    if sp.count_ops(J) + sp.count_ops(b) + sp.count_ops(c) <= _ADJUGATE_BUDGET:
        # Small enough to write out: along the flow dH/dt = (c·adj(J)·b + d det J)/det J, and det J ≠ 0.
        adj = J.adjugate()
        det = sum((J[0, k] * adj[k, 0] for k in range(3)), sp.Integer(0))
        return (c.T * adj * b)[0, 0] + d * det, ("no multiplier λ among ω, Γ, r_P, L, L_P: the numerator "
                                                "c·adj(J)·b + d·det J of dH/dt along the flow (det J ≠ 0)")
    return None, "no multiplier λ among ω, Γ, r_P, L, L_P (and twice each) satisfies Jᵀλ = ∂(dH/dt)/∂ω̇"


def prove(body: BodyOnPlane, expr, *, name: str = "H", rate=None, seed: int = 0) -> Verdict:
    """Whether ``expr`` is conserved along the body's flow (or, with ``rate``, whether ``dH/dt = rate``).

    Parameters
    ----------
    body : BodyOnPlane
    expr : sympy.Expr
        The candidate, in the state's names (:func:`eulersym.model.rolling.state_symbols`), ``t`` and the
        parameters.
    name : str
        For reports.
    rate : sympy.Expr, optional
        A claimed rate, in the same names and ``omega1dot..3``; the verdict then says whether ``dH/dt − rate``
        vanishes along the flow, and ``conserved`` is whether the proven rate is zero.
    seed : int
        Seeds the random points.

    Returns
    -------
    eulersym.model.integrals.Verdict

    Raises
    ------
    eulersym.errors.InvalidInput
        A candidate with a name the body does not know, a vector, or a derivative.

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> from eulersym.model.mechanics import OMEGA
    >>> prove(examples()["rolling-sphere"], OMEGA[0]).conserved      # a homogeneous ball: ω constant
    True
    >>> v = prove(examples()["chaplygin-ball"], OMEGA[0])
    >>> v.conserved, v.counterexample is not None
    (False, True)
    """
    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane")
    expr = _check_candidate(body, sp.sympify(expr))
    H = _rational(expr)
    claim = sp.Integer(0) if rate is None else _rational(sp.sympify(rate))
    g = _rate(body, H) - claim
    reduced, how = _eliminate(body, g, seed)
    # Refute first (cheap): a rational state where the rate, the accelerations solved at 50 digits, is not zero —
    # one state before an exact zero test (which is slow on a rate that is not zero), all of them after it.
    cx = _counterexample(body, g if reduced is None else reduced, seed, first=1)
    if cx is not None:
        if rate is not None:
            return Verdict(name, expr, False, g + claim, "dH/dt differs from the claimed rate along "
                           f"the flow (exact evaluation at a rational state); {how}", cx, True)
        if reduced is None:
            return Verdict(name, expr, False, g, "dH/dt is not zero along the flow (exact evaluation at a rational "
                           "state, the accelerations solved at 50 digits); the rate is shown with omega1dot..3 the "
                           f"solved accelerations; {how}", cx, True)
        return Verdict(name, expr, False, _tidy_small(reduced), f"dH/dt is not zero along the flow: {how}; exact "
                       "evaluation at a rational state", cx, True)
    if reduced is None:
        return Verdict(name, expr, False, g + claim, "undecided: the rate vanished at every random state but no "
                       f"exact proof was found ({how}); not claimed conserved", None, False)
    proven, method = _zero(reduced, seed)
    if not proven:
        cx = _counterexample(body, reduced, seed)
        if cx is not None:
            return Verdict(name, expr, False, _tidy_small(reduced + claim), f"dH/dt is not zero along the flow: "
                           f"{how}; exact evaluation at a rational state", cx, True)
        return Verdict(name, expr, False, _tidy_small(reduced + claim), f"undecided: {method}; {how}; not claimed "
                       "conserved", None, False)
    if rate is None:
        return Verdict(name, expr, True, sp.Integer(0), f"{method}; {how}", None, True)
    zero, _ = _zero(claim, seed)
    if zero:
        return Verdict(name, expr, True, sp.Integer(0), f"dH/dt = the claimed rate = 0: {method}; {how}", None, True)
    return Verdict(name, expr, False, claim, f"dH/dt = the claimed rate: {method}; {how}",
                   _counterexample(body, claim, seed), True)


def _tidy_small(expr) -> sp.Expr:
    """:func:`eulersym.model.integrals._tidy` for a rate of moderate size; a large one as it stands."""
    return _tidy(expr) if sp.count_ops(expr) <= 300 else expr


def _zero(expr, seed: int) -> tuple[bool, str]:
    """Exact zero test: :func:`eulersym.compare.compare` against 0, then (square roots) the radicals made symbols
    ``s`` with ``s² = base`` and the numerator reduced modulo those relations."""
    from eulersym.compare import compare

    verdict = compare(expr, sp.Integer(0), seed=seed)
    if verdict.exact is True:
        return True, verdict.method
    if verdict.exact is False or not verdict.numeric:
        return False, verdict.method
    if _radical_zero(expr):
        numeric = f"numeric ({verdict.points} points at {verdict.dps} digits)"
        return True, f"exact (square roots as symbols s with s² = base, the numerator reduced modulo them) + {numeric}"
    return False, verdict.method


def _radical_zero(expr) -> bool:
    """Whether ``expr`` is zero as a rational function of its symbols and the square roots ``√B`` it holds, each
    root a symbol ``s`` subject to ``s² = B`` (the numerator's remainder modulo ``s² − B``, as a polynomial in
    ``s``, is zero).

    Examples
    --------
    >>> x = sp.Symbol("x", positive=True)
    >>> root = sp.sqrt(x**2 + 1)
    >>> sp.expand(x**2 / root + 1 / root - root) == 0, _radical_zero(x**2 / root + 1 / root - root)
    (False, True)
    >>> _radical_zero(sp.sqrt(x) - x)
    False
    """
    if sp.sympify(expr) == 0:
        return True
    roots = {}
    for p in sp.sympify(expr).atoms(sp.Pow):
        if p.exp.is_Rational and p.exp.q == 2 and p.base.free_symbols:
            roots.setdefault(p.base, sp.Dummy("s", positive=True))
    if not roots:
        return False
    mapping = {}
    for p in sp.sympify(expr).atoms(sp.Pow):
        if p.base in roots and p.exp.is_Rational and p.exp.q == 2:
            mapping[p] = roots[p.base] ** p.exp.p
    num = sp.expand(sp.fraction(sp.together(sp.sympify(expr).xreplace(mapping)))[0])
    for base, s in sorted(roots.items(), key=lambda kv: sp.default_sort_key(kv[0])):
        if num == 0:
            return True
        try:
            num = sp.expand(sp.rem(num, s ** 2 - base, s))
        except (sp.PolynomialError, sp.GeneratorsNeeded):
            return False
    return num == 0


@functools.lru_cache(maxsize=32)
def _invariants(body: BodyOnPlane) -> tuple:
    out = []
    for name, expr in candidates(body).items():
        if name == "E":
            claim = _dissipation(body, KAPPA, newton_euler(body).slip)
            verdict = prove(body, expr, name=name, rate=claim)
            if not verdict.conserved:
                verdict = Verdict(name, expr, False, dissipation(body), verdict.how, verdict.counterexample,
                                  verdict.exact)
        else:
            verdict = prove(body, expr, name=name)
        out.append((name, verdict))
    return tuple(out)


def invariants(body: BodyOnPlane) -> dict:
    """``{name: Verdict}`` for every candidate of :func:`candidates`, each proven or refuted.

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> {name: v.conserved for name, v in invariants(examples()["chaplygin-ball"]).items()}
    {'E': True, 'Gamma_norm2': True, 'q_norm2': True, 'L_dot_Gamma': True, 'L_contact_vertical': True, 'Jellett': True, 'L_contact2': True}
    """
    if not isinstance(body, BodyOnPlane):
        raise InvalidInput("body", body, "an eulersym.model.rolling.BodyOnPlane")
    return dict(_invariants(body))
