"""Steady motions of a model, found by solving its own equations: permanent rotations, relative equilibria (Routh's
steady motions after reducing a cyclic angle) and equilibria, each a family with its existence condition.

The equations are the model's Newton–Euler equations (:func:`eulersym.model.derive.equations`) on the reduced state
``x = (ω, Γ)`` (``Γ`` only when the state carries the vertical; ``q`` only when a torque depends on the attitude):
``ẋ = f(x)``, with ``Γ̇ = Γ × ω``. A model whose equations depend on ``t`` has no steady motion in its frame.

Steady motions (the definitions)
    An *equilibrium of the reduced state* solves ``f(x) = 0``: with ``ω = 0`` the body is at rest; otherwise it turns
    steadily about a fixed axis — a *permanent rotation* (for a pivoted body about the vertical, since
    ``Γ × ω = 0``). A *relative equilibrium* moves only along a symmetry of the equations: when the rotation
    ``R_e(α)`` of the body's components about an axis ``e`` maps solutions to solutions (proven here: the identity
    ``Df(x)·Gx = G f(x)`` with ``Gx = (e × ω, e × Γ)`` holds exactly), the motions ``x(t) = R_e(ν t) x₀`` are steady
    modulo that symmetry; they solve ``f(x₀) = ν G x₀``. This is Routh's method: the angle about ``e`` (the spin
    ψ of a symmetric top) is cyclic, its momentum ``L·e`` is conserved, and the steady motion is an equilibrium of
    what is left. In space, ``Γ × (ω + ν e) = 0`` gives ``ω = φ̇ Γ − ν e``: the body axis ``e`` precesses about
    the vertical at ``φ̇ = (ω + ν e)·Γ`` (:attr:`Family.precession`) and spins at ``ψ̇ = −ν``.

How the system is solved (exactly, on polynomials)
    The unknowns are the state, the drift ``ν`` and, with a symmetry, one gauge condition (the vertical turned
    into the plane of ``e`` and one transverse axis; the other half-turn is the same motion). The equations are
    cleared of denominators and solved by splitting on factors (``a·b = 0``: ``a = 0`` or ``b = 0``), eliminating
    unknowns that appear linearly (branching on whether the coefficient vanishes), solving the linear homogeneous
    kinematic block ``Γ × ω = 0`` by its null space (``ω = s Γ``), and solving quadratics by the quadratic formula
    (one family per root, existing where the discriminant is ≥ 0). The components of ``ω`` and ``Γ`` along a
    symmetry axis are kept as the family's parameters (Routh: the cyclic momentum and the tilt); the vertical's
    remaining freedom on ``|Γ| = 1`` is written with angles — ``Γ·e = cos θ`` (a tilt ``θ``), the trigonometric
    substitution that turns the sphere into the family's parameter. Parameters are generic: a family that exists
    only when a combination of parameters vanishes is not listed unless the model has that structure exactly
    (``moments = ["I1", "I1", "I3"]``). A full tensor is first turned to its principal axes (exactly, by
    :func:`eulersym.inertia.principal_axes`); states are given back in the model's frame. Where the elimination
    meets a polynomial it cannot solve in closed form (a general offset pivot: Staude's cone, a sextic), the family is
    kept as its polynomial system and its members are found numerically at given numbers (:meth:`Family.members`).

Examples
--------
>>> from eulersym.model.cli import load
>>> families = steady_motions(load("lagrange-top"))
>>> [f.name for f in families]  # doctest: +NORMALIZE_WHITESPACE
['rotation about e3, e3 down', 'rotation about e3, e3 up', 'steady precession of e3 (- root)',
 'steady precession of e3 (+ root)', 'steady precession of e3, e3 horizontal']
>>> slow = families[2]
>>> slow.kind, slow.family
('relative equilibrium', (s, theta))
>>> slow.exists
-4*I1*M*g*l*cos(theta) + I3**2*s**2 >= 0
"""

from __future__ import annotations

import contextlib
import functools
import math
import random
import time
from dataclasses import dataclass, field, replace

import sympy as sp

from eulersym._budget import BudgetExceeded, time_budget
from eulersym.errors import EulersymError, InvalidInput
from eulersym.model.derive import equations
from eulersym.model.integrals import _as_mechanics
from eulersym.model._exact import DRIFT, PSI, THETA, _generator_on_values, _holds, _is_zero, _tidy, _trig
from eulersym.model.mechanics import GAMMA, OMEGA, Q, Mechanics, t

__all__ = ["Family", "SteadyMotions", "SteadyMotionUndecided", "steady_motions", "symmetry_axes", "DRIFT",
           "THETA", "PSI"]

#: Seconds the exact solver may spend on one model before it says what it tried.
DEFAULT_BUDGET = 20.0
#: Steps one branch may take before what is left is handed to the numeric members.
_MAX_STEPS = 60


class SteadyMotionUndecided(EulersymError):
    """The solver could not decide a model's steady motions within its time budget; the message names the family
    (the branch of the system being solved) and what was tried.

    Examples
    --------
    >>> print(SteadyMotionUndecided("model m: branch omega1 = 0 — undecided after 1 s (tried: factor splitting)"))
    model m: branch omega1 = 0 — undecided after 1 s (tried: factor splitting)
    """


# ----------------------------------------------------------------------------------------------------------------
# The families


@dataclass(eq=False)
class Family:
    """One family of steady motions of a model.

    Attributes
    ----------
    name : str
        In words, from its structure (``"rotation about e2"``, ``"steady precession of e3 (- root)"``).
    kind : str
        ``"permanent rotation"`` (ω ≠ 0 constant in the body; for a pivoted body about the vertical),
        ``"relative equilibrium"`` (steady modulo a symmetry: the state turns about a body axis ``e`` at the drift
        rate ν — Routh's steady motions, the steady precession of a top) or ``"equilibrium"`` (rest).
    family : tuple of sympy.Symbol
        The symbols that parametrise it: ``s`` (``s1``…) a rate — a component of ω kept free, or the rate about the
        vertical of ``ω = s Γ`` —, ``theta`` (``psi``) the vertical's angles.
    state : dict
        State name (``omega1..3``, ``gamma1..3``, ``q0..q3`` where fixed) → SymPy expression of the parameters and
        the family symbols, in the model's frame. For a numeric family (``closed_form`` False): the expressions
        of the state in the unknowns still to solve (``state_unknowns``).
    exists : sympy Boolean
        Where the family is real: each root's discriminant ≥ 0 (``True`` when always).
    where : tuple of sympy Boolean
        Where the formulas hold (``Ne(...)``): members excluded there belong to another family.
    drift : dict
        Symmetry axis label (``"e3"``) → ν; empty unless a relative equilibrium.
    precession : sympy.Expr or None
        With a vertical: the rate ``φ̇ = (ω + ν e)·Γ`` at which the body turns about the vertical.
    closed_form : bool
        False when the members must be found numerically (:meth:`members`).
    how : str
        How the family was found (the solver's steps).
    root : int
        −1 or +1: the family is the − or + root of the last quadratic the solver met; 0 when none.
    """

    name: str
    kind: str
    family: tuple
    state: dict
    exists: object = sp.true
    where: tuple = ()
    drift: dict = field(default_factory=dict)
    precession: object = None
    closed_form: bool = True
    how: str = ""
    root: int = 0
    _context: object = field(default=None, repr=False)
    _chart: object = field(default=None, repr=False)
    _numeric: object = field(default=None, repr=False)

    def __repr__(self) -> str:
        return f"Family({self.name!r}, kind={self.kind!r}, family={self.family})"

    @property
    def model(self) -> str:
        """The model's name."""
        return self._context.mech.name

    @property
    def parameters(self) -> tuple:
        """The model's parameter symbols, in order."""
        return self._context.mech.parameter_symbols

    @property
    def state_unknowns(self) -> tuple:
        """For a numeric family, the state components its members are solved for (empty otherwise)."""
        return tuple(self._numeric.unknowns) if self._numeric is not None else ()

    def stability(self):
        """Its linear stability, proven (:func:`eulersym.model.stability.stability`).

        Examples
        --------
        >>> from eulersym.model.cli import load
        >>> steady_motions(load("torque-free")).named("rotation about e2").stability().conditions
        Eq(s, 0) | (-(I1 - I2)*(I2 - I3) >= 0)
        """
        from eulersym.model.stability import stability

        return stability(self)

    def values(self, values=None) -> dict:
        """``{symbol: exact number}`` for the model's parameters (defaults filled in) and the family symbols.

        ``values`` maps names (or symbols) to numbers; every family symbol must be given. Unknown names are
        refused with a did-you-mean.

        Examples
        --------
        >>> from eulersym.model.cli import load
        >>> f = steady_motions(load("torque-free"))[0]
        >>> sorted((str(k), v) for k, v in f.values({"s": 2}).items())
        [('I1', 2), ('I2', 3), ('I3', 4), ('s', 2)]
        """
        return _values(self, values)

    def at(self, values=None) -> dict:
        """The member's state at numbers: ``{state name: float}`` (closed-form families; see :meth:`members`).

        Raises
        ------
        eulersym.errors.InvalidInput
            A family symbol not given, an unknown name, or numbers where the family does not exist.

        Examples
        --------
        >>> from eulersym.model.cli import load
        >>> steady_motions(load("torque-free"))[0].at({"s": 2.0})
        {'omega1': 2.0, 'omega2': 0.0, 'omega3': 0.0}
        """
        members = self.members(values)
        if not members:
            raise InvalidInput("values", _shown(values), f"numbers where {self.name!r} exists: {self.exists}")
        return members[0]

    def members(self, values=None) -> list:
        """The family's real members at numbers, each ``{state name: float}``.

        A closed-form family has one (its formulas evaluated at 30 digits), or none where it does not exist; a
        numeric family has the real solutions of its polynomial system at those numbers (exact Gröbner basis over
        the rationals, roots at 30 digits).

        Examples
        --------
        >>> from eulersym.model.cli import load
        >>> f = steady_motions(load("lagrange-top")).named("steady precession of e3 (- root)")   # the slow one
        >>> m = f.members({"s": 150.0, "theta": 0.5})[0]
        >>> round(m["omega2"] / 0.479425538604203, 4)    # φ̇ = ω2 / sin θ (M g l / (I3 ω3) = 3.27 to first order)
        3.4829
        >>> f.members({"s": 1.0, "theta": 0.5})                  # too slow a spin: no steady precession
        []
        """
        point = self.values(values)
        if self._numeric is not None:
            return self._numeric.members(point)
        if not _holds(self.exists, point):
            return []
        for cond in self.where:
            if _holds(cond, point) is False:
                return []
        out = {}
        for name, expr in self.state.items():
            value = sp.sympify(expr).xreplace(point).evalf(30)
            if not value.is_real:
                value = sp.re(value) if abs(sp.im(value)) < 1e-25 else value
            out[name] = float(value)
        return [out]


class SteadyMotions(tuple):
    """The families of a model's steady motions (a tuple), with ``notes``: what the solver did, and why a model has
    none.

    Examples
    --------
    >>> SteadyMotions([], notes=("the equations depend on t",)).notes
    ('the equations depend on t',)
    """

    def __new__(cls, families=(), notes=()):
        obj = super().__new__(cls, families)
        obj.notes = tuple(notes)
        return obj

    def __getnewargs__(self):
        return (tuple(self), self.notes)

    def named(self, name: str) -> Family:
        """The family called ``name`` (did-you-mean when there is none).

        Examples
        --------
        >>> from eulersym.model.cli import load
        >>> steady_motions(load("torque-free")).named("rotation about e2").kind
        'permanent rotation'
        """
        for f in self:
            if f.name == name:
                return f
        import difflib

        names = [f.name for f in self]
        close = difflib.get_close_matches(name, names, n=1, cutoff=0.4)
        raise InvalidInput("family", name, "one of " + ", ".join(repr(n) for n in names)
                           + (f" (did you mean {close[0]!r}?)" if close else ""))


# ----------------------------------------------------------------------------------------------------------------
# Exact numbers and values


def _rational(expr):
    """Floats → the rationals they print as, so that the solver sees exact numbers."""
    expr = sp.sympify(expr)
    floats = expr.atoms(sp.Float)
    return expr.xreplace({f: sp.Rational(str(f)) for f in floats}) if floats else expr


def _exact(value):
    if isinstance(value, sp.Basic):
        return _rational(value)
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        return None
    if number != number or number in (float("inf"), float("-inf")):
        return None
    return sp.Rational(repr(number)) if isinstance(value, float) else sp.nsimplify(value, rational=True)


def _shown(values):
    return dict(values) if isinstance(values, dict) else values


def _values(fam: Family, values) -> dict:
    mech = fam._context.mech
    by_name = {s.name: s for s in (*mech.parameter_symbols, *fam.family)}
    point = {s: sp.Rational(str(v)) for s, v in mech.parameters}
    given = {} if values is None else values
    if not isinstance(given, dict):
        raise InvalidInput("values", given, "a mapping {name: number} of parameters and family symbols")
    for key, value in given.items():
        name = key.name if isinstance(key, sp.Symbol) else str(key)
        if name not in by_name:
            import difflib

            close = difflib.get_close_matches(name, list(by_name), n=1, cutoff=0.5)
            raise InvalidInput(name, value, "a parameter of the model or a symbol of the family "
                               f"{fam.name!r}: " + ", ".join(by_name)
                               + (f" (did you mean {close[0]!r}?)" if close else ""))
        number = _exact(value)
        if number is None or not number.is_real:
            raise InvalidInput(name, value, "a finite real number")
        point[by_name[name]] = number
    missing = [s.name for s in fam.family if s not in point]
    if missing:
        raise InvalidInput("values", _shown(values), f"a value for each symbol of the family {fam.name!r}: "
                           + ", ".join(missing) + " missing")
    return point


# ----------------------------------------------------------------------------------------------------------------
# The model's reduced equations, its frame and its symmetries


@dataclass(frozen=True, eq=False)
class _Context:
    """The reduced system of a model: state ``x``, rates ``f`` (model frame, exact numbers), the solving frame
    ``R`` (columns: its axes in the model frame) and the rates there, the verified symmetry axes."""

    mech: Mechanics
    x: tuple
    f: tuple
    R: sp.ImmutableMatrix
    f_solving: tuple
    symmetries: tuple  # of (label, axis in the model frame, coordinate index in the solving frame)
    denominators: tuple
    notes: tuple
    #: Equations the steady motions must satisfy beyond ``f(x) = ν G x`` (a contact's zero slip, in ``x``).
    extra: tuple = ()
    #: Sign conditions every member must meet (``Γ2 > 0``: the branch of a contact point's square root solved on).
    positive: tuple = ()
    #: ``family → Stability`` where the model's own linearisation is not :mod:`eulersym.model.stability`'s (contact
    #: bodies: :mod:`eulersym.model.rolling_steady`); None for the model's equations.
    linearise: object = None
    #: Whether a stuck branch is tried once more with ``ω × L = 0`` (the torque-free body's permanent rotations).
    trial: bool = True


def _blocks(x) -> list:
    return [x[i:i + 3] for i in range(0, 6 if GAMMA[0] in x else 3, 3)]


def _generator(x, e) -> list:
    """``G x``: the infinitesimal rotation of the body's vectors about ``e``, ``(e × ω, e × Γ)`` (q: fixed)."""
    e = sp.Matrix(e)
    out = []
    for block in _blocks(x):
        out += list(e.cross(sp.Matrix(block)))
    return out + [sp.Integer(0)] * (len(x) - len(out))


def _equivariant(x, f, e) -> bool:
    """``Df(x)·Gx − G f(x) ≡ 0``: rotating the state about ``e`` maps solutions to solutions."""
    Gx = _generator(x, e)
    n = len(x)
    rate = [sum(sp.diff(f[i], x[j]) * Gx[j] for j in range(n) if Gx[j] != 0) for i in range(n)]
    turned = _generator_on_values(x, f, e)
    return all(_is_zero(rate[i] - turned[i]) for i in range(n))


def symmetry_axes(mech: Mechanics) -> list:
    """The body axes ``e`` about which the model's reduced equations are symmetric, each proven: the rotation of
    ω and Γ about ``e`` commutes with the flow (``Df(x)·Gx = G f(x)`` exactly, ``Gx = (e × ω, e × Γ)``).

    Candidates: the symmetry axis of the inertia tensor (two equal principal moments), and for a spherical tensor
    the coordinate axes and the centre of mass's direction. A rotor, a centre of mass or a torque off the axis breaks
    the symmetry, and the identity fails.

    Returns
    -------
    list of 3×1 sympy.Matrix (unit vectors, model frame)

    Examples
    --------
    >>> from eulersym.model.cli import load
    >>> [list(e) for e in symmetry_axes(load("lagrange-top").mechanics)]
    [[0, 0, 1]]
    >>> symmetry_axes(load("kovalevskaya").mechanics)  # the centre of mass off the axis breaks it
    []
    """
    return [sp.Matrix(axis) for _, axis, _ in _context(mech).symmetries]


@functools.lru_cache(maxsize=32)
def _context(mech: Mechanics) -> _Context:
    from eulersym.model.integrals import symmetry_axis

    eqs = equations(mech)
    rows = [_rational(e) for e in eqs.rhs]
    names = eqs.state
    x = [*OMEGA] + ([*GAMMA] if GAMMA[0] in names else [])
    notes = []
    f = [rows[names.index(s)] for s in x]
    if any(e.has(t) for e in f):
        return _Context(mech, tuple(x), tuple(f), sp.ImmutableMatrix(sp.eye(3)), tuple(f), (), (),
                        ("the equations depend on t explicitly (a torque that varies with time): nothing is steady "
                         "in this frame",))
    if any(e.has(*Q) for e in f):
        x += list(Q)
        f = [rows[names.index(s)] for s in x]
        notes.append("a torque depends on the attitude: q0..q3 are part of the state")
    denominators = []
    for e in f:
        den = sp.denom(sp.together(e))
        if den.free_symbols & set(x):
            denominators.append(den)
    # The solving frame: the tensor's principal axes (exact), so that symmetry axes are coordinate axes.
    I = sp.Matrix(_rational(mech.inertia))
    R = sp.eye(3)
    if not I.is_diagonal() and Q[0] not in x:
        try:
            with time_budget(5.0):
                from eulersym.inertia import principal_axes

                R = sp.Matrix(principal_axes(I, body=False)[1])
            notes.append("solved in the tensor's principal axes (columns of R in the model frame: "
                         f"{R.tolist()})")
        except (BudgetExceeded, InvalidInput, NotImplementedError):
            R = sp.eye(3)
            notes.append("the tensor's principal axes have no usable closed form: solved in the model frame")
    f_solving = _to_frame(x, f, R)
    # Symmetry axes, proven, as coordinate axes of the solving frame.
    symmetries = []
    if Q[0] not in x:
        Id = sp.Matrix(3, 3, lambda i, j: sp.expand(sp.simplify((R.T * I * R)[i, j]))) if R != sp.eye(3) else I
        candidates = []
        axis = symmetry_axis(Id)
        if axis is not None:
            candidates.append([k for k in range(3) if axis[0][k] != 0][0])
        elif Id.is_diagonal() and sp.expand(Id[0, 0] - Id[1, 1]) == 0 and sp.expand(Id[1, 1] - Id[2, 2]) == 0:
            candidates += [2, 0, 1]
        for k in candidates:
            e = sp.zeros(3, 1)
            e[k] = 1
            if _equivariant(x, f_solving, e):
                symmetries.append((f"e{k + 1}" if R == sp.eye(3) else f"R e{k + 1}", sp.ImmutableMatrix(R * e), k))
                break
    return _Context(mech, tuple(x), tuple(f), sp.ImmutableMatrix(R), tuple(f_solving), tuple(symmetries),
                    tuple(denominators), tuple(notes))


def _to_frame(x, f, R) -> list:
    """The rates in the solving frame: ``f'(x') = Rᵀ f(R x')`` for the vector blocks (ω, Γ)."""
    if R == sp.eye(3):
        return list(f)
    R = sp.Matrix(R)
    sub = {}
    for block in _blocks(x):
        v = R * sp.Matrix(block)
        sub.update({s: v[i] for i, s in enumerate(block)})
    g = [e.xreplace(sub) for e in f]
    out = []
    for k, block in enumerate(_blocks(x)):
        w = R.T * sp.Matrix(g[3 * k:3 * k + 3])
        out += [sp.expand(e) for e in w]
    return out + g[len(out):]


# ----------------------------------------------------------------------------------------------------------------
# The solver: branches of a polynomial system


@dataclass
class _Branch:
    eqs: list
    assigned: dict
    roots: list        # (unknown, a, b, c, sign)
    nonzero: list
    steps: list
    new: list          # unknowns introduced (null-space rates)
    trial: bool = False  # the trial branch ω × L = 0 has been added


@dataclass
class _Raw:
    assigned: dict
    roots: list
    nonzero: list
    steps: list
    free: list
    stuck: list        # remaining equations (numeric family) or []
    unknowns: list     # remaining unknowns of a numeric family
    trial: bool = False  # a stuck branch whose ω ∥ L part was solved on its own


class _Solver:
    def __init__(self, ctx: _Context, unknowns, protected, priority, deadline, model_name):
        self.ctx = ctx
        self.unknowns = list(unknowns)
        self.protected = set(protected)
        self.priority = dict(priority)
        self.deadline = deadline
        self.model = model_name
        self.rng = random.Random(20)
        self.params = list(ctx.mech.parameter_symbols)
        self.counter = 0
        self.rates = set()  # the rates about an axis introduced by null spaces (ω = s Γ)

    # -- helpers ------------------------------------------------------------------------------------------
    def live(self, br: _Branch) -> list:
        roots = {r[0] for r in br.roots}
        return [u for u in [*self.unknowns, *br.new] if u not in br.assigned and u not in roots]

    def tick(self, br: _Branch) -> None:
        if time.monotonic() > self.deadline:
            raise SteadyMotionUndecided(
                f"model {self.model}: the branch [{'; '.join(br.steps) or 'the whole system'}] was not decided "
                f"within the time budget (tried: factor splitting, linear elimination, null spaces, the quadratic "
                f"formula on {len(br.eqs)} remaining equations in {', '.join(map(str, self.live(br)))})")

    def normalise(self, br: _Branch) -> bool:
        """Substitute, clear denominators, drop zeros; False when the branch is infeasible."""
        live = set(self.live(br))
        eqs = []
        for e in br.eqs:
            num = sp.expand(sp.numer(sp.together(e)))
            if num == 0:
                continue
            if not (num.free_symbols & live):
                return False  # a non-zero constant (generic parameters)
            eqs.append(num)
        seen, unique = set(), []
        for e in eqs:
            key = sp.srepr(e)
            if key not in seen:
                seen.add(key)
                unique.append(e)
        br.eqs = unique
        for n in br.nonzero:
            if _is_zero(n):
                return False
        return True

    def assign(self, br: _Branch, u, value, step: str) -> _Branch:
        value = sp.cancel(sp.together(value)) if not value.has(sp.Pow) or True else value
        sub = {u: value}
        new = _Branch([e.xreplace(sub) for e in br.eqs],
                      {k: sp.cancel(v.xreplace(sub)) for k, v in br.assigned.items()},
                      [(r, sp.expand(a.xreplace(sub)), sp.expand(b.xreplace(sub)), sp.expand(c.xreplace(sub)), s)
                       for r, a, b, c, s in br.roots],
                      [sp.numer(sp.together(n.xreplace(sub))) for n in br.nonzero],
                      br.steps + [step], list(br.new), br.trial)
        new.assigned[u] = value
        return new

    def with_eq(self, br: _Branch, eqs, step: str, replace=None) -> _Branch:
        base = [e for e in br.eqs if e is not replace] if replace is not None else list(br.eqs)
        return _Branch(base + list(eqs), dict(br.assigned), list(br.roots), list(br.nonzero), br.steps + [step],
                       list(br.new), br.trial)

    def known_nonzero(self, br: _Branch, f) -> bool:
        live = set(self.live(br))
        if not (f.free_symbols & live):
            return True
        for n in br.nonzero:
            if _is_zero(f - n) or _is_zero(f + n):
                return True
        return False

    # -- the steps ---------------------------------------------------------------------------------------
    def split(self, br: _Branch):
        live = set(self.live(br))
        for e in br.eqs:
            content, factors = sp.factor_list(e)
            keep = [f for f, _ in factors if (f.free_symbols & live) and not self.known_nonzero(br, f)]
            if not keep:
                return [None]  # infeasible: a product of non-zero factors
            if len(keep) == 1 and (sp.cancel(e / keep[0])).is_number:
                continue
            if len(keep) == 1:
                return [self.with_eq(br, [keep[0]], f"{keep[0]} = 0", replace=e)]
            return [self.with_eq(br, [f], f"{f} = 0", replace=e) for f in keep]
        return None

    def linear(self, br: _Branch, only=None, direct=False, single=False):
        live = self.live(br)
        options = []
        for e in br.eqs:
            inside = [u for u in live if e.has(u)]
            if single and len(inside) != 1:
                continue
            unprotected = [u for u in inside if u not in self.protected]
            for u in inside:
                if only is not None and u not in only:
                    continue
                if u in self.protected and unprotected:
                    continue
                if sp.degree(e, u) != 1:
                    continue
                a = sp.expand(e.coeff(u, 1))
                b = sp.expand(e - a * u)
                rest = a.free_symbols & set(live)
                score = 0 if not rest else (1 if len(sp.Add.make_args(a)) == 1 else 2)
                if direct and score:
                    continue
                options.append((score, self.priority.get(u, 9), sp.count_ops(a), sp.count_ops(e), str(u), e, u,
                                a, b))
        options.sort(key=lambda o: o[:5])
        for option in options:
            score, _, _, _, _, e, u, a, b = option
            if score and any(sp.cancel(a / o).is_number for o in br.eqs if o is not e):
                continue  # its coefficient is itself an equation of the branch: not a division
            if score and self.known_nonzero(br, a):
                score = 0
            break
        else:
            return None
        value = -b / a
        solved = self.assign(br, u, value, f"{u} from a linear equation" + (f" ({a} != 0)" if score else ""))
        solved.eqs = [x for x in solved.eqs if not _is_zero(x)]
        if score:
            solved.nonzero.append(a)
            return [solved, self.with_eq(br, [a], f"{a} = 0")]
        return [solved]

    def nullspace(self, br: _Branch):
        """The block of equations linear and homogeneous in ω: ``A(other unknowns) ω = 0`` → ``ω`` in its null
        space (``Γ × ω = 0`` → ``ω = s Γ``)."""
        live = self.live(br)
        ws = [w for w in OMEGA if w in live]
        if len(ws) < 2:
            return None
        rows, used = [], []
        for e in br.eqs:
            if not e.has(*ws):
                continue
            p = sp.Poly(e, *ws)
            if not all(sum(m) == 1 for m in p.monoms()):
                continue
            rows.append([sp.expand(p.coeff_monomial(w)) for w in ws])
            used.append(e)
        if len(rows) < 2:
            return None
        A = sp.Matrix(rows)
        point = {s: sp.Rational(self.rng.randint(2, 40), self.rng.randint(2, 9))
                 for s in A.free_symbols}
        rank = A.xreplace(point).rank()
        if rank != len(ws) - 1 or len(ws) != 3:
            return None  # only the kinematic block Γ × ω = 0: a line of rotations about one axis
        from sympy.polys.matrices import DomainMatrix

        dM = DomainMatrix.from_Matrix(A).to_field()
        rows_ns = dM.nullspace().to_Matrix()  # exact, over the rational functions of the other symbols
        basis = [rows_ns[i, :].T for i in range(rows_ns.shape[0])]
        if len(basis) != len(ws) - rank:
            return None
        new_symbols = []
        value = sp.zeros(len(ws), 1)
        for k, v in enumerate(basis):
            v = sp.Matrix([sp.cancel(sp.together(c)) for c in v])
            den = sp.lcm([sp.denom(c) for c in v])
            v = (v * den).applyfunc(sp.cancel)
            g = functools.reduce(sp.gcd, list(v))
            if g != 0:
                v = v.applyfunc(lambda c: sp.cancel(c / g))
            self.counter += 1
            s = sp.Symbol(f"s_{self.counter}", real=True)
            new_symbols.append(s)
            value += s * v
        nb = _Branch([e for e in br.eqs if e not in used], dict(br.assigned), list(br.roots), list(br.nonzero),
                     br.steps, list(br.new) + new_symbols, br.trial)
        for s in new_symbols:
            self.priority[s] = 7
            self.protected.add(s)
            self.rates.add(s)
        for w, val in zip(ws, value):
            nb = self.assign(nb, w, val, f"{w} from the null space of the kinematic equations")
        # the rows used are satisfied identically by the null space; keep the others
        return [nb]

    def quadratic(self, br: _Branch):
        live = self.live(br)
        options = []
        for e in br.eqs:
            inside = [u for u in live if e.has(u)]
            unprotected = [u for u in inside if u not in self.protected]
            for u in inside:
                if u in self.protected and unprotected:
                    continue
                if any(o is not e and o.has(u) for o in br.eqs):
                    continue
                p = sp.Poly(e, u)
                if p.degree() != 2:
                    continue
                a, b, c = (sp.expand(x) for x in p.all_coeffs())
                options.append((self.priority.get(u, 9), sp.count_ops(e), str(u), e, u, a, b, c))
        if not options:
            return None
        options.sort(key=lambda o: o[:3])
        _, _, _, e, u, a, b, c = options[0]
        out = []
        for sign in (-1, 1):
            nb = _Branch([x for x in br.eqs if x is not e], dict(br.assigned), list(br.roots) + [(u, a, b, c, sign)],
                         list(br.nonzero), br.steps + [f"{u} from a quadratic ({'-' if sign < 0 else '+'} root)"],
                         list(br.new), br.trial)
            if a.free_symbols & set(live):
                nb.nonzero.append(a)
            out.append(nb)
        if a.free_symbols & set(live) and not self.known_nonzero(br, a):
            out.append(self.with_eq(br, [a], f"{a} = 0"))
        return out

    # -- the search --------------------------------------------------------------------------------------
    def solve(self, branch: _Branch) -> list:
        done, work = [], [branch]
        while work:
            br = work.pop()
            self.tick(br)
            if not self.normalise(br):
                continue
            if not br.eqs:
                done.append(_Raw(br.assigned, br.roots, br.nonzero, br.steps, self.live(br), [], []))
                continue
            drift = [u for u in self.live(br) if u is DRIFT]
            if len(br.steps) > _MAX_STEPS:
                done.append(_Raw(br.assigned, br.roots, br.nonzero, br.steps, self.live(br), list(br.eqs),
                                 [u for u in self.live(br) if any(e.has(u) for e in br.eqs)]))
                continue
            # order matters for the form of the families: a drift first (Routh: the cyclic momentum stays the
            # family's parameter), else the kinematic null space (ω = s Γ: the rate about the vertical)
            steps = [lambda b: self.linear(b, direct=True, single=True)]
            steps += [lambda b: self.linear(b, only=drift)] if drift else [self.nullspace]
            steps += [lambda b: self.linear(b, direct=True), self.split, self.linear, self.quadratic]
            for step in steps:
                result = step(br)
                if result is not None:
                    work.extend(reversed([r for r in result if r is not None]))
                    break
            else:
                trial = self.trial(br)
                if trial is not None:
                    work.append(trial)
                done.append(_Raw(br.assigned, br.roots, br.nonzero, br.steps, self.live(br), list(br.eqs),
                                 [u for u in self.live(br) if any(e.has(u) for e in br.eqs)], trial is not None))
        return done

    def trial(self, br: _Branch):
        """A branch the elimination cannot finish, tried once more with ``ω × L = 0`` added (``L = I ω + h``): the
        permanent rotations of the torque-free body. Its solutions solve the branch (equations were only added);
        whatever else the branch holds stays a numeric family."""
        if br.trial or not self.ctx.trial:
            return None
        mech = self.ctx.mech
        R = sp.Matrix(self.ctx.R)
        I = R.T * sp.Matrix(_rational(mech.inertia)) * R
        h = R.T * sp.Matrix(_rational(mech.rotor))
        w = sp.Matrix([br.assigned.get(u, u) for u in OMEGA])
        cross = w.cross(I * w + h)
        eqs = [sp.numer(sp.together(e)) for e in cross]
        eqs = [sp.expand(e) for e in eqs if sp.expand(e) != 0]
        if not eqs:
            return None
        return _Branch(list(br.eqs) + eqs, dict(br.assigned), list(br.roots), list(br.nonzero),
                       br.steps + ["trial: ω × L = 0 (a permanent rotation of the torque-free body)"], list(br.new),
                       True)


# ----------------------------------------------------------------------------------------------------------------
# From raw solutions to families


def _square_part(expr):
    """``expr = f² · rest`` with ``f`` the product of the even powers among its factors: ``(f, rest)``."""
    expr = sp.factor(sp.together(expr))
    num, den = sp.fraction(expr)
    f_num, r_num = _square_split(num)
    f_den, r_den = _square_split(den)
    return f_num / f_den / r_den, sp.expand(r_num * r_den)


def _square_split(expr):
    content, factors = sp.factor_list(expr)
    f, rest = sp.Integer(1), sp.Integer(1)
    if content < 0:
        rest = -rest
        content = -content
    root = sp.sqrt(content)
    if root.is_Rational:
        f *= root
    else:
        rest *= content
    for base, k in factors:
        f *= base ** (k // 2)
        rest *= base ** (k % 2)
    return f, rest


def _present(ctx: _Context, raw: _Raw, sym) -> dict | None:
    """The state (solving frame), family symbols, existence and validity of one raw solution."""
    x_solve = list(ctx.x)
    assigned = dict(raw.assigned)
    free = [u for u in raw.free if u is not DRIFT]
    sub = {DRIFT: sp.Integer(0)} if DRIFT in raw.free else {}
    exists, where = [], []
    chart = None
    # The vertical: free components and the sphere's root → angles.
    gammas = [g for g in GAMMA if g in x_solve]
    free_g = [g for g in gammas if g in free]
    sphere_root = None
    for r in raw.roots:
        u, a, b, c, sign = r
        if u in gammas and a == 1 and b == 0 and _is_zero(c - (sum(g ** 2 for g in free_g) - 1)) and free_g:
            sphere_root = r
    if free_g and sphere_root is not None:
        if sphere_root[4] < 0:
            return None  # the other half of the same angles: θ → −θ
        axis = sym["axis_gamma"]
        if len(free_g) == 1:
            sub[free_g[0]] = sp.cos(THETA)
            sub[sphere_root[0]] = sp.sin(THETA)
            angles = [THETA]
        else:
            g1, g2 = free_g
            sub[g1], sub[g2] = sp.sin(THETA) * sp.sin(PSI), sp.sin(THETA) * sp.cos(PSI)
            sub[sphere_root[0]] = sp.cos(THETA)
            angles = [THETA, PSI]
        free = [u for u in free if u not in free_g]
        del axis
    else:
        angles = list(free_g)  # the sphere was used for another unknown: these components stay the family's
        free = [u for u in free if u not in free_g]
    # Rates kept free → family symbols s, s1, ...
    rates = [u for u in free if u not in gammas]
    names = {}
    if len(rates) == 1:
        names[rates[0]] = sp.Symbol("s", real=True)
    else:
        for u in rates:
            index = u.name[-1] if u.name[-1].isdigit() and u in OMEGA else str(rates.index(u) + 1)
            names[u] = sp.Symbol(f"s{index}", real=True)
    sub.update(names)
    # Roots other than the sphere's, in order: u = (−b ± f √rest)/(2a).
    root_values = {}
    for r in raw.roots:
        if r is sphere_root:
            continue
        u, a, b, c, sign = r
        a, b, c = (sp.expand(e.xreplace(sub).xreplace(root_values)) for e in (a, b, c))
        f, rest = _square_part(sp.expand(b ** 2 - 4 * a * c))
        rest = _trig(rest)
        value = (-b + sign * f * sp.sqrt(rest)) / (2 * a)
        if rest.free_symbols:
            exists.append(rest)
        elif rest < 0:
            return None
        root_values[u] = value
        # A chart without the root: the relation a u² + b u + c = 0 solved for a free rate it is linear in.
        rel = sp.expand(a * u ** 2 + b * u + c)
        for s in names.values():
            if chart is None and sp.Poly(rel, s).degree() == 1:
                p = sp.Poly(rel, s)
                chart = (u, s, sp.cancel(-p.all_coeffs()[1] / p.all_coeffs()[0]))
    full = dict(sub)
    full.update(root_values)
    state = {}
    for s in x_solve:
        if s in assigned:
            v = assigned[s]
        else:
            v = s
        state[s] = v
    # resolve: assigned values refer to roots, free unknowns and (already substituted) others
    out = {}
    for s, v in state.items():
        out[s] = _tidy(v.xreplace(full).xreplace(full))
    nonzero = []
    family_symbols = set(names.values()) | {THETA, PSI}
    for n in raw.nonzero:
        m = sp.numer(sp.together(n.xreplace(full).xreplace(full)))
        if _is_zero(m):
            return None
        if m.has(sp.sqrt):
            continue  # the root's own denominator: zero only where the quadratic degenerates
        for factor, _ in sp.factor_list(sp.expand(m))[1]:
            if factor.free_symbols & family_symbols and not any(_is_zero(factor - k) for k in nonzero):
                nonzero.append(factor)
    drift = None
    if DRIFT in ctx_unknowns(ctx) and DRIFT not in raw.free:
        drift = _tidy(assigned.get(DRIFT, sp.Integer(0)).xreplace(full).xreplace(full))
    # The chart's state (rational: the root kept as its own unknown, the free rate eliminated).
    chart_state = None
    if chart is not None:
        u, s, value = chart
        csub = dict(sub)
        csub[s] = value
        chart_state = {}
        for k, v in state.items():
            chart_state[k] = _tidy(v.xreplace(csub).xreplace(csub)) if k is not u else u
        if drift is not None:
            chart_state[DRIFT] = _tidy(assigned.get(DRIFT).xreplace(csub).xreplace(csub))
        chart = (u, s, value, chart_state)
    return {"state": out, "family": tuple(names.values()) + tuple(angles), "exists": exists, "nonzero": nonzero,
            "drift": drift, "chart": chart, "roots": root_values}


def ctx_unknowns(ctx) -> set:
    return {DRIFT} if ctx.symmetries else set()


# ----------------------------------------------------------------------------------------------------------------
# Deduplication: a family contained in another (or in its half-turn image about the symmetry axis)


def _random_point(symbols, rng, positive=()):
    return {s: sp.Rational(rng.randint(3, 60), rng.randint(7, 23)) * (1 if s in positive or rng.random() < 0.6
                                                                     else -1) for s in symbols}


def _numeric_state(fam_data, point):
    out = {}
    for s, v in fam_data["state"].items():
        val = sp.sympify(v).xreplace(point).evalf(30)
        if not val.is_number:
            return None
        out[s] = complex(val)
    return out


def _contains(big, small, ctx, rng, defaults) -> bool:
    """Whether every member of ``small`` is a member of ``big`` (tested at two random real members)."""
    for _ in range(2):
        for _ in range(20):
            point = dict(defaults)
            point.update({s: v for s, v in _random_point(small["family"], rng).items()})
            st = _numeric_state(small, point)
            if st is not None and all(abs(v.imag) < 1e-20 for v in st.values()):
                break
        else:
            return False
        if not _member_of(big, st, ctx, defaults):
            return False
    return True


def _member_of(fam, state, ctx, defaults) -> bool:
    """Whether a numeric state is a member of ``fam``: solve for its family symbols from the state and compare."""
    import mpmath

    point = dict(defaults)
    for sym in fam["family"]:
        value = _symbol_from_state(fam, sym, state)
        if value is None:
            return False
        point[sym] = value
    for n in fam["nonzero"]:
        v = sp.sympify(n).xreplace(point).evalf(30)
        if v.is_number and abs(complex(v)) < 1e-10:  # the state is known to double precision
            return False
    other = _numeric_state(fam, point)
    if other is None:
        return False
    scale = 1 + max(abs(v) for v in state.values())
    return all(abs(other[k] - state[k]) < 1e-15 * scale for k in state)


def _symbol_from_state(fam, sym, state):
    """The value of a family symbol at a given state: a rate is the state component it stands for; θ from the
    vertical's component along the axis and the one in the gauge plane."""
    import math

    src = fam.get("sources", {}).get(sym)
    if src is None:
        return None
    kind, data = src
    if kind == "component":
        v = state[data]
        return sp.Float(v.real, 30) if abs(v.imag) < 1e-20 else None
    if kind == "theta":
        c, s_ = state[data[0]], state[data[1]]
        return sp.Float(math.atan2(s_.real, c.real), 30)
    if kind == "along":
        # s in ω = s v(Γ): s = (ω·v)/(v·v) with v evaluated at the state
        at = {g: sp.Float(state[g].real, 30) for g in GAMMA if g in state}
        v = [sp.sympify(e).xreplace(at).evalf(30) for e in data]
        if any(not e.is_number for e in v):
            return None
        v = [complex(e) for e in v]
        den = sum(e * e for e in v)
        if abs(den) < 1e-25:
            return None
        num = sum(state[w] * v[i] for i, w in enumerate(OMEGA))
        return sp.Float((num / den).real, 30)
    return None


# ----------------------------------------------------------------------------------------------------------------
# Naming


def _axis_name(v) -> str | None:
    nonzero = [k for k in range(3) if not _is_zero(v[k])]
    return f"e{nonzero[0] + 1}" if len(nonzero) == 1 else None


def _describe(kind, state, x, symmetries, sign) -> str:
    """A family's name from its structure: what turns about what, where the vertical is, which root."""
    w = [state[s] for s in OMEGA]
    has_g = GAMMA[0] in x
    G = [state[s] for s in GAMMA] if has_g else None
    if kind == "equilibrium":
        name = "rest"
    elif kind == "permanent rotation":
        axis = _axis_name(w)
        if axis:
            name = f"rotation about {axis}"
        elif has_g:
            name = "rotation about the vertical"
        else:
            name = "rotation about an axis in the " + "–".join(f"e{k + 1}" for k in range(3) if not _is_zero(w[k])) \
                + " plane"
    else:
        label = symmetries[0][0] if symmetries else "the axis"
        name = f"steady precession of {label}" if has_g else f"regular precession about {label}"
    if has_g:
        axis = _axis_name(G)
        if kind == "relative equilibrium":
            k = symmetries[0][2]
            if _is_zero(G[k]):
                name += f", e{k + 1} horizontal"
        elif axis is not None:
            k = int(axis[1]) - 1
            name += f", {axis} " + {1: "up", -1: "down"}.get(int(sp.sign(G[k])), "vertical")
    return name + (f" ({sign} root)" if sign else "")


# ----------------------------------------------------------------------------------------------------------------
# The entry point


def steady_motions(model, *, budget: float = DEFAULT_BUDGET) -> SteadyMotions:
    """The families of steady motions of a model, found by solving its equations exactly (see the module docstring).

    Parameters
    ----------
    model : eulersym.model.Model or Mechanics
    budget : float
        Seconds the exact solver may spend; beyond it :class:`SteadyMotionUndecided` names the branch it was on
        and what it tried.

    Returns
    -------
    SteadyMotions
        A tuple of :class:`Family`, with ``.notes``; empty (with a note saying why) when the model has none —
        equations that depend on ``t``, or a system whose only solutions need special parameter values.

    Raises
    ------
    eulersym.errors.InvalidInput
        ``model`` is not a model; ``budget`` not a positive number.
    SteadyMotionUndecided
        The exact solver did not finish within ``budget``.

    Examples
    --------
    Example 4.2's body (free, three distinct moments) turns steadily about each principal axis:

    >>> from eulersym.model.cli import load
    >>> [(f.name, f.state) for f in steady_motions(load("torque-free"))]  # doctest: +NORMALIZE_WHITESPACE
    [('rotation about e1', {'omega1': s, 'omega2': 0, 'omega3': 0}),
     ('rotation about e2', {'omega1': 0, 'omega2': s, 'omega3': 0}),
     ('rotation about e3', {'omega1': 0, 'omega2': 0, 'omega3': s})]
    """
    if isinstance(budget, bool) or not isinstance(budget, (int, float)) or not budget > 0:
        raise InvalidInput("budget", budget, "a positive number of seconds")
    if type(model).__name__ == "BodyOnPlane" or getattr(model, "body_on_plane", None) is not None:
        raise InvalidInput("model", getattr(model, "name", model), "a body with a fixed point or free: a body on a "
                           "plane moves by its contact equations (eulersym.model.rolling_steady.steady_motions, or "
                           "Model.steady_motions)")
    mech = _as_mechanics(model, argument="model")
    return _steady_motions(mech, float(budget))


@functools.lru_cache(maxsize=32)
def _steady_motions(mech: Mechanics, budget: float) -> SteadyMotions:
    start = time.monotonic()
    ctx = _context(mech)
    notes = list(ctx.notes)
    if any(e.has(t) for e in ctx.f):
        return SteadyMotions([], notes)
    if mech.turning:
        return _frame_equilibria(ctx, notes)
    return _solve(ctx, mech.name, start + budget, notes)


#: The seed of SymPy's own random numbers while the solver runs (:func:`sympy_random`).
SYMPY_SEED = 20


@contextlib.contextmanager
def sympy_random(seed: int):
    """SymPy's random numbers (``sympy.core.random``) seeded with ``seed`` in the block, the caller's state restored
    after it. Multivariate factorization (Wang's algorithm) draws its evaluation points from that generator, which
    SymPy seeds anew in every process: the same steady-motion equations (Chaplygin's ball) were solved in 9 s in most
    processes and not within 300 s in others (1 in 12 here, stuck in ``dmp_zz_wang_hensel_lifting``), so the
    solver's run time — and whether it finishes within its budget — changed from one run to the next.

    Examples
    --------
    >>> from sympy.core.random import _randint
    >>> with sympy_random(7):
    ...     first = [_randint()(0, 10**9) for _ in range(3)]
    >>> with sympy_random(7):
    ...     first == [_randint()(0, 10**9) for _ in range(3)]
    True
    """
    from sympy.core import random as sympy_rng

    state = sympy_rng.rng.getstate()
    sympy_rng.rng.seed(seed)
    try:
        yield
    finally:
        sympy_rng.rng.setstate(state)


def _solve(ctx: _Context, name: str, deadline: float, notes: list) -> SteadyMotions:
    """The families of ``f(x) = ν G x`` (with ``ctx.extra``) for a reduced system, by the exact solver, before
    ``deadline`` (:func:`time.monotonic`)."""
    budget = max(deadline - time.monotonic(), 0.01)
    x = list(ctx.x)
    f = list(ctx.f_solving)
    unknowns = list(x)
    protected, priority = set(), {}
    for w in OMEGA:
        priority[w] = 2
    for g in GAMMA:
        priority[g] = 4
    for q in Q:
        priority[q] = 5
    eqs = []
    gauge = []
    if ctx.symmetries:
        label, _, k = ctx.symmetries[0]
        unknowns.append(DRIFT)
        priority[DRIFT] = 0
        e = sp.zeros(3, 1)
        e[k] = 1
        Gx = _generator(x, e)
        eqs = [fi - DRIFT * gi for fi, gi in zip(f, Gx)]
        protected |= {OMEGA[k]} | ({GAMMA[k]} if GAMMA[0] in x else set())
        priority[OMEGA[k]] = 8
        priority[GAMMA[k]] = 9
        u = (k + 1) % 3  # the gauge: the body turned about e until the vertical (else ω) has no u-component
        gauge = [GAMMA[u] if GAMMA[0] in x else OMEGA[u]]
    else:
        eqs = list(f)
        if GAMMA[0] in x:
            protected.add(GAMMA[2])
            priority[GAMMA[2]] = 9
    eqs = [sp.numer(sp.together(e)) for e in [*eqs, *ctx.extra]]
    if GAMMA[0] in x:
        eqs.append(sum(g ** 2 for g in GAMMA) - 1)
    if Q[0] in x:
        eqs.append(sum(q ** 2 for q in Q) - 1)
    for g in gauge:
        eqs.append(g)
    nonzero = [d for d in ctx.denominators]
    solver = _Solver(ctx, unknowns, protected, priority, deadline, name)
    try:
        with time_budget(budget), sympy_random(SYMPY_SEED):
            raws = solver.solve(_Branch(eqs, {}, [], nonzero, [], []))
            families = _families(ctx, raws, solver)
    except BudgetExceeded:
        raise SteadyMotionUndecided(
            f"model {name}: the steady motions were not decided within {budget:g} s (tried: factor splitting, "
            "linear elimination, null spaces and the quadratic formula on the equilibrium equations f(x) = ν G x)"
        ) from None
    if not families:
        notes.append("no steady motion found: the equilibrium equations have no solution for generic parameters")
    return SteadyMotions(families, notes)


def _exact_quaternion(R) -> list:
    """The unit quaternion (scalar first, q0 ≥ 0 where it can be) of an exact rotation matrix ``R`` (``v = R v_body``),
    by Shepperd's rule (the largest of 1 + tr R, 1 + 2 R_kk − tr R under the root)."""
    R = sp.Matrix(R)
    tr = R.trace()
    options = [1 + tr] + [1 + 2 * R[k, k] - tr for k in range(3)]
    k = max(range(4), key=lambda i: float(options[i]))
    root = sp.sqrt(options[k]) / 2
    if k == 0:
        q = [root, (R[2, 1] - R[1, 2]) / (4 * root), (R[0, 2] - R[2, 0]) / (4 * root), (R[1, 0] - R[0, 1]) / (4 * root)]
    else:
        i, j, m = k - 1, k % 3, (k + 1) % 3
        v = [0, 0, 0]
        v[i] = root
        v[j] = (R[j, i] + R[i, j]) / (4 * root)
        v[m] = (R[m, i] + R[i, m]) / (4 * root)
        q = [(R[m, j] - R[j, m]) / (4 * root), *v]
        if q[0] < 0:
            q = [-c for c in q]
    return [sp.radsimp(c) for c in q]


def _frame_equilibria(ctx: _Context, notes: list) -> SteadyMotions:
    """Equilibria in a uniformly turning frame (relative equilibria: a satellite at rest in its orbital frame).

    At rest in the frame, ``q̇ = 0`` gives ``ω = A Ω`` (``A = R(q)ᵀ``, ``r_body = A r_frame``) and the body must
    turn steadily with it: ``I ω̇ = N − ω × (I ω + h) = 0`` at ``ω = A Ω``, ``Γ = A ẑ``. The candidates are the 24
    attitudes that put the body's axes along the frame's (signed permutations, det +1); each is kept only where the
    model's own equations vanish there exactly. Attitudes that differ by a half-turn of the body about one of its axes
    that maps the equations to themselves (a diagonal tensor and an even potential: checked, all four members of
    the class steady) are one family, written with body axes e1 and e2 along + frame axes. Where a torque depends on
    the attitude, the rests off the frame's axes (a gyrocompass tilted by β) are one more family whose members are
    found at numbers (:class:`_FrameSystem`), its stability from the eigenvalues at each member."""
    import itertools

    mech = ctx.mech
    x = list(ctx.x)
    Omega = sp.Matrix(mech.frame)
    z = sp.Matrix([0, 0, 1])
    notes = notes + ["a turning frame: its equilibria (relative equilibria) among the attitudes that align the body's "
                     "axes with the frame's, each checked exactly in the model's equations; others are not searched"]
    rows = dict(zip(x, ctx.f))

    def state_of(A):
        q = _exact_quaternion(A.T)
        values = {**dict(zip(OMEGA, A * Omega)), **dict(zip(GAMMA, A * z)), **dict(zip(Q, q))}
        return {s: sp.nsimplify(values[s]) if not isinstance(values[s], sp.Basic) else values[s] for s in x}

    def steady(A):
        point = state_of(A)
        return all(_is_zero(sp.expand(sp.sympify(rows[s]).xreplace(point))) for s in x), point

    seen, families = set(), []
    frame_axes = ("x", "y", "z")
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1, -1), repeat=3):
            A = sp.zeros(3, 3)
            for row, (col, sign) in enumerate(zip(perm, signs)):
                A[row, col] = sign
            if A.det() != 1 or (perm, signs) in seen:
                continue
            ok, point = steady(A)
            if not ok:
                continue
            flips = ((1, -1, -1), (-1, 1, -1), (-1, -1, 1))
            images = [tuple(a * b for a, b in zip(signs, d)) for d in flips]
            matrices = [sp.diag(*d) * A for d in flips]
            if mech.inertia.is_diagonal() and all(steady(B)[0] for B in matrices):
                seen.update((perm, image) for image in images)  # the same configuration of the body: one family
                k = next(i for i, sg in enumerate([signs, *images]) if sg[0] > 0 and sg[1] > 0)
                A = [A, *matrices][k]
                ok, point = steady(A)
            seen.add((perm, signs))
            where = ", ".join(f"e{r + 1} along {'+' if A[r, perm[r]] > 0 else '-'}{frame_axes[perm[r]]}"
                              for r in range(3))
            state = {s.name: v for s, v in point.items()}
            families.append(Family(f"at rest in the turning frame: {where}", "equilibrium in the turning frame", (),
                                   state, sp.true, (), {}, None, True, "q̇ = 0 ⇒ ω = A Ω; I ω̇ = 0 checked exactly",
                                   0, ctx, None, None))
    if not families:
        notes.append("no attitude aligned with the frame's axes is at rest in it")
    if Q[0] in x:  # an attitude-dependent torque: equilibria off the frame's axes, found at numbers
        families.append(Family("at rest in the turning frame, off its axes (numeric members)",
                               "equilibrium in the turning frame", (), {s.name: s for s in x}, sp.true, (), {}, None,
                               False, "q̇ = 0 ⇒ ω = A(q) Ω, Γ = A(q) ẑ; I ω̇ = 0 and |q| = 1 solved for q by Newton's "
                               "method at 30 digits from the 24 aligned attitudes and their turns by ±π/6 about each "
                               "axis", 0, replace(ctx, linearise=_frame_stability), None, _FrameSystem(ctx)))
        notes[0] = notes[0].replace("; others are not searched", "; off the axes, members are found at numbers "
                                    "(Newton's method from the aligned attitudes and their turns)")
    return SteadyMotions(families, notes)


def _frame_stability(fam):
    from eulersym.model.stability import _frame_stability as linearise

    return linearise(fam)


class _FrameSystem:
    """The equilibria of a turning frame off its axes, at numbers: ``I ω̇ = 0`` at ``ω = A(q) Ω``, ``Γ = A(q) ẑ``
    with ``|q| = 1`` (``A = R(q)ᵀ``), by Newton's method (mpmath, 30 digits) from the 24 attitudes aligned with the
    frame and each turned by ±π/6 about each of its axes; roots kept where every row vanishes to 1e-25 of its scale,
    ``q`` and ``−q`` one member, aligned attitudes left to the closed-form families. Not proven to be every member."""

    unknowns = ()

    def __init__(self, ctx: _Context):
        from eulersym.rotation import from_quaternion

        self.ctx = ctx
        A = sp.Matrix(from_quaternion(list(Q)))
        Omega = sp.Matrix(ctx.mech.frame)
        sub = {**dict(zip(OMEGA, A * Omega)), **dict(zip(GAMMA, A * sp.Matrix([0, 0, 1])))}
        rows = dict(zip(ctx.x, ctx.f))
        self.rows = [sp.sympify(rows[w]).xreplace(sub) for w in OMEGA]

    def members(self, point) -> list:
        import itertools

        import mpmath
        import numpy as np

        from eulersym.attitude import hamilton

        params = {k: sp.Float(v, 40) for k, v in point.items()}
        exprs = [sp.sympify(e).xreplace(params) for e in self.rows] + [sum(q ** 2 for q in Q) - 1]
        fns = [sp.lambdify(list(Q), e, modules="mpmath") for e in exprs]
        starts = []
        for perm in itertools.permutations(range(3)):
            for signs in itertools.product((1, -1), repeat=3):
                A = sp.zeros(3, 3)
                for row, (col, sign) in enumerate(zip(perm, signs)):
                    A[row, col] = sign
                if A.det() != 1:
                    continue
                q0 = [float(c) for c in _exact_quaternion(A.T)]
                starts.append(q0)
                for axis in range(3):
                    for angle in (math.pi / 6, -math.pi / 6):
                        turn = [math.cos(angle / 2), 0.0, 0.0, 0.0]
                        turn[axis + 1] = math.sin(angle / 2)
                        starts.append([float(c) for c in hamilton(q0, turn)])
        from scipy.optimize import root as solve

        numeric = sp.lambdify(list(Q), exprs, modules="numpy")
        candidates = []
        for q_start in starts:  # in doubles first (fast), then each distinct root polished at 30 digits
            with np.errstate(all="ignore"):
                sol = solve(lambda q: np.array(numeric(*q), dtype=float), q_start, method="hybr", tol=1e-14)
            if not np.all(np.isfinite(sol.x)) or np.max(np.abs(numeric(*sol.x))) > 1e-9:
                continue
            q = sol.x / np.linalg.norm(sol.x)
            q = -q if q[np.argmax(np.abs(q))] < 0 else q  # q and −q: one attitude
            if not any(np.max(np.abs(q - other)) < 1e-7 for other in candidates):
                candidates.append(q)
        found = []
        with mpmath.workdps(30):
            for q_start in candidates:
                try:
                    root = mpmath.findroot(lambda *q: [f(*q) for f in fns], [float(c) for c in q_start],
                                           tol=mpmath.mpf(10) ** -50, maxsteps=8, verify=False)
                except (ValueError, ZeroDivisionError, TypeError, IndexError):  # a singular Jacobian on the way
                    continue
                if max(abs(f(*root)) for f in fns) > mpmath.mpf(10) ** -20:
                    continue
                q = [float(c) for c in root]
                if q[max(range(4), key=lambda k: abs(q[k]))] < 0:
                    q = [-c for c in q]
                if all(min(abs(abs(c) - k) for k in (0.0, 0.5, 2 ** -0.5, 1.0)) < 1e-12 for c in q):
                    continue  # an aligned attitude: a closed-form family's member
                if any(max(abs(a - b) for a, b in zip(q, other)) < 1e-9 for other in found):
                    continue
                found.append(q)
        from eulersym.rotation import from_quaternion

        out = []
        for q in sorted(found):
            A = sp.Matrix(from_quaternion([sp.Float(c, 30) for c in q]))
            values = {**dict(zip(OMEGA, A * sp.Matrix(self.ctx.mech.frame).xreplace(params))),
                      **dict(zip(GAMMA, A * sp.Matrix([0, 0, 1]))), **dict(zip(Q, q))}
            out.append({s.name: float(values[s]) for s in self.ctx.x})
        return out




def _families(ctx: _Context, raws, solver) -> list:
    mech = ctx.mech
    rng = random.Random(7)
    defaults = {s: sp.Rational(str(v)) for s, v in mech.parameters}
    k_axis = ctx.symmetries[0][2] if ctx.symmetries else 2
    closed, numeric = [], []
    for raw in raws:
        if raw.stuck:
            numeric.append(raw)
            continue
        data = _present(ctx, raw, {"axis_gamma": k_axis})
        if data is None:
            continue
        data["raw"] = raw
        data["sources"] = _sources(ctx, raw, data)
        closed.append(data)
    # drop duplicates and families contained in others (or in their half-turn images)
    def inside(small, big):
        return _contains(big, small, ctx, rng, defaults) or bool(
            ctx.symmetries and _contains(_half_turn(big, ctx), small, ctx, rng, defaults))

    kept = []
    for i, fam in enumerate(closed):
        redundant = False
        for j, other in enumerate(closed):
            if i == j or len(other["family"]) < len(fam["family"]) or not inside(fam, other):
                continue
            if j > i and len(other["family"]) == len(fam["family"]) and inside(other, fam):
                continue  # the same family twice: the first is kept
            redundant = True
            break
        if not redundant:
            kept.append(fam)
    order = {"equilibrium": 0, "permanent rotation": 1, "relative equilibrium": 2}
    families = sorted((_family(ctx, data) for data in kept),
                      key=lambda f: (order[f.kind], f.name.replace("(- root)", "(0)").replace("(+ root)", "(1)")))
    families += [_numeric_family(ctx, raw, solver) for raw in numeric]
    # names: unique
    seen = {}
    for fam in families:
        if fam.name in seen:
            seen[fam.name] += 1
            fam.name = f"{fam.name} [{seen[fam.name]}]"
        else:
            seen[fam.name] = 1
    return families


def _half_turn(data, ctx):
    """The family turned by a half turn about the symmetry axis (the same motions, the gauge's other side)."""
    k = ctx.symmetries[0][2]
    flip = {}
    for block in _blocks(ctx.x):
        for i, s in enumerate(block):
            if i != k:
                flip[s] = -data["state"][s]
    out = dict(data)
    out["state"] = {s: flip.get(s, v) for s, v in data["state"].items()}
    return out


def _sources(ctx, raw, data) -> dict:
    """How each family symbol is read back from a state (for containment tests)."""
    out = {}
    gammas = [g for g in GAMMA if g in ctx.x]
    for sym in data["family"]:
        if sym is THETA:
            free_g = [g for g in gammas if g in raw.free]
            root = [r[0] for r in raw.roots if r[0] in gammas]
            if len(free_g) == 1 and root:
                out[sym] = ("theta", (free_g[0], root[0]))
            continue
    rates = [u for u in raw.free if u not in gammas and u is not DRIFT]
    names = [s for s in data["family"] if s not in (THETA, PSI)]
    for u, sym in zip(rates, names):
        if u in OMEGA:
            out[sym] = ("component", u)
        else:  # a null-space rate: ω = s v(Γ)
            v = [sp.diff(raw.assigned.get(w, w), u) for w in OMEGA]
            out[sym] = ("along", v)
    return out


def _family(ctx: _Context, data) -> Family:
    raw = data["raw"]
    R = sp.Matrix(ctx.R)
    x = list(ctx.x)
    st = data["state"]
    model_state = {}
    for block in _blocks(x):
        v = R * sp.Matrix([st[s] for s in block])
        for s, e in zip(block, v):
            model_state[s.name] = _tidy(e) if R != sp.eye(3) else e
    for s in x[len(model_state):]:
        model_state[s.name] = st[s]
    w = [model_state[s.name] for s in OMEGA]
    drift = data["drift"]
    if all(_is_zero(e) for e in w):
        kind = "equilibrium"
    elif drift is None or _is_zero(drift):
        kind = "permanent rotation"
    else:
        kind = "relative equilibrium"
    signs = [r[4] for r in raw.roots if r[0] in data["roots"]]
    sign = ("-" if signs[-1] < 0 else "+") if signs else ""
    if R != sp.eye(3):  # named in the principal axes (R e_k, columns of R in the model frame)
        name = _describe(kind, dict(st), x, ctx.symmetries, sign).replace("about e", "about R e").replace(
            "plane", "principal plane").replace(", e", ", R e")
    else:
        name = _describe(kind, {s: model_state[s.name] for s in x}, x, ctx.symmetries, sign)
    exists = sp.And(*[sp.GreaterThan(e, 0) for e in data["exists"]]) if data["exists"] else sp.true
    where = tuple(sp.Ne(n, 0) for n in data["nonzero"])
    drifts = {ctx.symmetries[0][0]: drift} if (ctx.symmetries and kind == "relative equilibrium") else {}
    precession = None
    if GAMMA[0] in x:
        wv = sp.Matrix(w)
        if drifts:
            wv = wv + drift * sp.Matrix(ctx.symmetries[0][1])
        precession = _tidy((wv.T * sp.Matrix([model_state[g.name] for g in GAMMA]))[0, 0])
    how = "; ".join(raw.steps) if raw.steps else "the equations hold identically"
    chart = data["chart"]
    if chart is not None and R != sp.eye(3):
        chart = None  # the chart lives in the solving frame; stability then uses the state itself
    return Family(name, kind, data["family"], model_state, exists, where, drifts, precession, True, how,
                  signs[-1] if signs else 0, ctx, chart, None)


# ----------------------------------------------------------------------------------------------------------------
# Numeric families


@dataclass(eq=False)
class _NumericSystem:
    ctx: _Context
    equations: list        # polynomials in unknowns, family symbols and parameters
    unknowns: list
    family: list           # free rates (symbols)
    state: dict            # solving-frame state component → expression in unknowns and family symbols
    exclude_parallel: bool = False  # members with ω ∥ L belong to the closed-form families

    def members(self, point) -> list:
        eqs = [sp.expand(e.xreplace(point)) for e in self.equations]
        eqs = [e for e in eqs if e != 0]
        try:
            with time_budget(10.0):
                solutions = _solve_numeric(eqs, list(self.unknowns))
        except BudgetExceeded:
            raise SteadyMotionUndecided(
                f"model {self.ctx.mech.name}: the numeric members were not found within 10 s (tried: a Gröbner "
                f"basis of {len(eqs)} equations in {', '.join(map(str, self.unknowns))})") from None
        except (NotImplementedError, sp.PolynomialError) as exc:
            raise SteadyMotionUndecided(
                f"model {self.ctx.mech.name}: the numeric members could not be found ({exc})") from None
        R = sp.Matrix(self.ctx.R)
        out = []
        for sol in solutions:
            values = dict(zip(self.unknowns, sol))
            if any(abs(sp.im(v)) > 1e-20 for v in values.values()):
                continue
            values = {k: sp.re(v) for k, v in values.items()}
            full = {**point, **values}
            st = {s: sp.sympify(v).xreplace(full).evalf(30) for s, v in self.state.items()}
            if self.exclude_parallel and _parallel(self.ctx, st, point):
                continue
            member = {}
            for block in _blocks(self.ctx.x):
                v = R * sp.Matrix([st[s] for s in block])
                member.update({s.name: float(sp.re(e.evalf(30))) for s, e in zip(block, v)})
            out.append(member)
        out.sort(key=lambda m: tuple(m.values()))
        return out


def _solve_numeric(eqs, unknowns, dps: int = 30) -> list:
    """Every complex solution of a zero-dimensional polynomial system with exact coefficients, at ``dps`` digits: a
    lexicographic Gröbner basis (exact), then its triangular structure — the last polynomial is univariate; each of
    its roots is substituted, the next variable's polynomials solved, and so on — keeping the candidates at which
    every basis polynomial vanishes (relative residual below 10^(−dps/2))."""
    if not eqs:
        return []
    G = sp.groebner(eqs, *unknowns, order="lex")
    if list(G.exprs) == [1]:
        return []
    basis = list(G.exprs)
    tol = sp.Float(10, dps) ** (-(dps // 2))

    def solve(level: int, point: dict) -> list:
        if level < 0:
            return [dict(point)]
        v = unknowns[level]
        later = set(unknowns[:level])
        polys = [sp.expand(p.xreplace(point)) for p in basis if p.has(v) and not (p.free_symbols & later)]
        polys = [p for p in polys if p != 0]
        if not polys:
            return []  # a free variable: not zero-dimensional here
        best = min(polys, key=lambda p: sp.Poly(p, v).degree())
        poly = sp.Poly(best, v)
        if poly.degree() == 0:
            return []
        out = []
        for r in poly.nroots(n=dps, maxsteps=200):
            cand = dict(point)
            cand[v] = r
            if all(abs(sp.N(p.xreplace(cand), dps)) <= tol * (1 + max(abs(c) for c in sp.Poly(p, v).coeffs()))
                   for p in polys):
                out += solve(level - 1, cand)
        return out

    solutions = solve(len(unknowns) - 1, {})
    return [[sol[u] for u in unknowns] for sol in solutions]


def _parallel(ctx, st, point) -> bool:
    """Whether ω ∥ L = I ω + h at a numeric state (solving frame)."""
    R = sp.Matrix(ctx.R)
    I = (R.T * sp.Matrix(_rational(ctx.mech.inertia)) * R).xreplace(point)
    h = (R.T * sp.Matrix(_rational(ctx.mech.rotor))).xreplace(point)
    w = sp.Matrix([st[s] for s in OMEGA])
    c = w.cross(I * w + h).evalf(30)
    scale = 1 + sum(abs(x) for x in w) ** 2
    return all(abs(x) < 1e-20 * scale for x in c)


def _numeric_family(ctx: _Context, raw: _Raw, solver: _Solver) -> Family:
    rng = random.Random(11)
    unknowns = list(raw.unknowns)
    free = [u for u in raw.free if u not in unknowns and u is not DRIFT]
    # promote unknowns to family symbols until the system is zero-dimensional at generic numbers
    params = list(ctx.mech.parameter_symbols)
    # promoted first: a rate about the vertical (null space), then what the solver protects, then the rest
    order = sorted(unknowns, key=lambda u: (u not in solver.rates, u not in solver.protected,
                                            -solver.priority.get(u, 9), str(u)))
    while unknowns:
        point = {s: sp.Rational(rng.randint(3, 30), rng.randint(2, 7)) for s in (*params, *free)}
        eqs = [sp.expand(e.xreplace(point)) for e in raw.stuck]
        try:
            with time_budget(5.0):
                G = sp.groebner(eqs, *unknowns, order="grevlex")
                zero_dim = G.is_zero_dimensional
        except BudgetExceeded:
            zero_dim = True
        if zero_dim:
            break
        u = next(v for v in order if v in unknowns)
        unknowns.remove(u)
        free.append(u)
    names = {}
    for u in free:
        names[u] = sp.Symbol("s" if len(free) == 1 else f"s{free.index(u) + 1}", real=True)
    state = {}
    for s in ctx.x:
        v = raw.assigned.get(s, s)
        state[s] = v.xreplace(names)
    system = _NumericSystem(ctx, [e.xreplace(names) for e in raw.stuck], unknowns, list(names.values()), state)
    how = "; ".join(raw.steps + [f"no closed form: {len(raw.stuck)} polynomial equations in "
                                 f"{', '.join(map(str, unknowns))} left, solved numerically at given numbers"])
    kind = "permanent rotation"
    name = "permanent rotations (numeric members)"
    if raw.trial:
        name = "other permanent rotations (numeric members, ω not along L)"
        system.exclude_parallel = True
    model_state = {s.name: v for s, v in state.items()}
    return Family(name, kind, tuple(names.values()), model_state, sp.true, (), {}, None, False, how, 0, ctx, None,
                  system)
