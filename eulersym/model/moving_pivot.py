"""A pivot that moves along a prescribed path: its acceleration as a time-dependent apparent gravity.

A body turns about a pivot whose position in space is ``r(t)`` (three expressions of ``t`` and the parameters). In
the frame that translates with the pivot (not inertial), every mass element feels, besides gravity ``−g ẑ``, the
fictitious force ``−r̈(t)`` per unit mass: the apparent gravity is ``g_eff(t) = g ẑ + r̈(t)`` (up), and its
potential energy, ``V = M g_eff(t) · R(q) c`` (``c`` the centre of mass from the pivot, body frame), is

    ``V = M g c·Γ + M c·to_body(r̈(t))``,   ``to_body(v) = v_x X + v_y Y + v_z Γ``,

``X, Y`` the space axes in body components (columns of ``A = R(q)ᵀ``, in ``q``), ``Γ`` the upward vertical.
:func:`moving_pivot` derives ``r̈`` from the path with SymPy and returns the model with this potential added
(:class:`~eulersym.model.mechanics.Mechanics` ``potential``): its equations, both routes and the proof of their
equality, its integrals (the energy is not conserved: ``dE/dt = ∂V/∂t``) and its kernel are every model's
(:mod:`eulersym.model.derive`, :mod:`eulersym.model.integrals`, :mod:`eulersym.model.kernels`).

Kapitza's pendulum (:func:`kapitza_threshold`). A body swinging in a plane about a principal axis ``e`` through
the pivot, ``c ⟂ e``, obeys (derived by :func:`eulersym.model.derive.equations`) ``θ̈ = k (g + z̈(t)) sin θ`` with
``θ`` the tilt of ``c`` from the upward vertical and ``k = M |c| / I_e`` — the point pendulum's equation with the
reduced length ``l_eq = 1/k = I_e/(M |c|)`` (Huygens). For a vertical drive ``z = a cos Ωt`` fast against the
slow motion, Kapitza's averaging (Landau & Lifshitz, *Mechanics* §30: the effective potential of a fast force
``f = −k a Ω² cos Ωt sin θ`` is ``U + ⟨f²⟩/(2Ω²)``) gives ``U_eff = k g cos θ + (k a Ω sin θ)²/4``, whose
minimum at ``θ = 0`` (upright) needs ``U_eff''(0) = −k g + k² a² Ω²/2 > 0``:

    ``a² Ω² > 2 g / k = 2 g I_e / (M |c|)``  (the point pendulum's ``2 g l``, with ``l → l_eq``).

Examples
--------
>>> import sympy as sp
>>> from eulersym.model.mechanics import Mechanics
>>> a, W = sp.symbols("a Omega", positive=True)
>>> pendulum = Mechanics(name="pendulum", inertia=sp.ImmutableMatrix(sp.diag(2, 2, 1)), mass=sp.Integer(3),
...                      centre_of_mass=sp.ImmutableMatrix([0, 0, 1]), gravity=sp.Rational(981, 100), pivoted=True,
...                      parameters=((a, 0.05), (W, 100.0)))
>>> driven = moving_pivot(pendulum, [0, 0, a * sp.cos(W * t)])
>>> driven.potential
-3*Omega**2*a*gamma3*cos(Omega*t)
>>> kapitza_threshold(pendulum)                       # a²Ω² > 2 g I/(M l) = 2 · 9.81 · 2/3
327/25
"""

from __future__ import annotations

import dataclasses

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.model.mechanics import GAMMA, OMEGA, Q, Mechanics, t

__all__ = ["pivot_path", "apparent_gravity", "moving_pivot", "kapitza_threshold"]


def pivot_path(mech: Mechanics, path) -> tuple:
    """The pivot's path ``r(t)`` as three SymPy expressions, checked: functions of ``t`` and the parameters only.

    Strings are read by the model's whitelist parser (:func:`eulersym.model.expressions.parse`, never ``eval``)
    with ``t`` and the parameters as the only names.

    Raises
    ------
    eulersym.errors.InvalidInput
        A body without a pivot, not three components, or a component that uses the state (``omega``, ``gamma``,
        ``q``) or an unknown name — naming the key ``pivot.path[k]`` and the value.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> w = sp.Symbol("w", real=True)
    >>> m = Mechanics(name="p", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1), pivoted=True,
    ...               centre_of_mass=sp.ImmutableMatrix([0, 0, 1]), gravity=sp.Integer(10), parameters=((w, 3.0),))
    >>> pivot_path(m, ["0", "0", "cos(w*t)/100"])
    (0, 0, cos(t*w)/100)
    >>> pivot_path(m, ["0", "0", "gamma3"])
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: pivot.path[2]='gamma3' is not valid: expected a known name: pi, t, w
    """
    from eulersym.model.expressions import namespace, parse

    if not isinstance(mech, Mechanics):
        raise InvalidInput("mechanics", mech, "an eulersym.model.mechanics.Mechanics")
    if not mech.pivoted:
        raise InvalidInput("pivot.path", path, "a pivoted body (a [pivot] whose position the path prescribes)")
    if isinstance(path, (str, bytes)) or not hasattr(path, "__len__") or len(path) != 3:
        raise InvalidInput("pivot.path", path, "three components [x(t), y(t), z(t)] (expressions of t)")
    names = namespace({s.name: s for s in mech.parameter_symbols}, state=False)
    allowed = {t, *mech.parameter_symbols}
    out = []
    for k, item in enumerate(path):
        key = f"pivot.path[{k}]"
        if isinstance(item, str):
            value = parse(item, names, argument=key)
        elif isinstance(item, bool) or not isinstance(item, (int, float, sp.Expr)):
            raise InvalidInput(key, item, "an expression of t and the parameters (a string or a SymPy expression)")
        else:
            value = sp.Rational(repr(item)) if isinstance(item, float) else sp.sympify(item)
        extra = sorted(value.free_symbols - allowed, key=str)
        if extra or value.has(sp.Derivative) or value.atoms(sp.core.function.AppliedUndef):
            raise InvalidInput(key, str(item), "a function of t and the parameters only (the pivot's prescribed "
                               f"position; unknown: {', '.join(map(str, extra)) or 'a function'})")
        out.append(value)
    return tuple(out)


def apparent_gravity(mech: Mechanics, path) -> sp.ImmutableMatrix:
    """``g_eff(t) = g ẑ + r̈(t)``, space components: the upward apparent gravity in the pivot's frame.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> m = Mechanics(name="p", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(1), pivoted=True,
    ...               centre_of_mass=sp.ImmutableMatrix([0, 0, 1]), gravity=sp.Integer(10))
    >>> apparent_gravity(m, [t**2, 0, 0]).T
    Matrix([[2, 0, 10]])
    """
    r = pivot_path(mech, path)
    return sp.ImmutableMatrix([sp.diff(x, t, 2) for x in r]) + sp.ImmutableMatrix([0, 0, mech.gravity])


def moving_pivot(mech: Mechanics, path) -> Mechanics:
    """The model on a pivot moving along ``path``: ``potential += M c·to_body(r̈(t))`` (module docstring).

    Parameters
    ----------
    mech : Mechanics
        A pivoted body.
    path : three expressions (SymPy, numbers or strings) of ``t`` and the parameters
        The pivot's position in space.

    Returns
    -------
    Mechanics
        The same body with the apparent gravity's time-dependent part as a potential; unchanged when the path
        has no acceleration.

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> m = Mechanics(name="p", inertia=sp.ImmutableMatrix(sp.eye(3)), mass=sp.Integer(2), pivoted=True,
    ...               centre_of_mass=sp.ImmutableMatrix([1, 0, 0]), gravity=sp.Integer(10))
    >>> moving_pivot(m, [t**2 / 2, 0, 0]).potential       # r̈ = x̂: 2 c·to_body(x̂) = 2 X_1
    2*q0**2 + 2*q1**2 - 2*q2**2 - 2*q3**2
    """
    from eulersym.rotation import from_quaternion

    r = pivot_path(mech, path)
    acceleration = [sp.diff(x, t, 2) for x in r]
    if all(a == 0 for a in acceleration):
        return mech
    A = from_quaternion(list(Q))  # r_body = A r_space: columns X, Y and (here) Γ
    axes = (A[:, 0], A[:, 1], sp.Matrix(GAMMA))
    c = sp.Matrix(mech.centre_of_mass)
    V = sum((mech.mass * a * (c.T * axis)[0, 0] for a, axis in zip(acceleration, axes) if a != 0), sp.Integer(0))
    return dataclasses.replace(mech, potential=sp.sympify(mech.potential) + sp.expand(V))


def kapitza_threshold(mech: Mechanics, axis: int = 1) -> sp.Expr:
    """The bound on ``a² Ω²`` above which a vertical drive ``z = a cos Ωt`` of the pivot keeps the body upright.

    Derived from the model's equations (:func:`eulersym.model.derive.equations`, the pivot at rest): for a swing
    about the body axis ``axis`` (a principal axis through the pivot, ``c ⟂ e``), ``θ̈ = k g sin θ`` with ``k``
    read off the derived ``ω̇`` at ``Γ(θ) = cos θ ĉ + sin θ (ĉ × e)``; the vertical drive turns ``g`` into
    ``g + z̈(t)`` (:func:`moving_pivot`) and Kapitza's averaging gives ``a² Ω² > 2 g / k`` (module docstring).

    Parameters
    ----------
    mech : Mechanics
        A pivoted body under gravity, at rest pivot (the drive is the threshold's subject).
    axis : {1, 2, 3}
        The body axis of the swing.

    Raises
    ------
    eulersym.errors.InvalidInput
        Not a pivoted body under gravity, an axis that is not principal or not perpendicular to the centre of
        mass, or a model whose planar swing is not ``θ̈ = k g sin θ`` (other torques).

    Examples
    --------
    >>> import sympy as sp
    >>> from eulersym.model.mechanics import Mechanics
    >>> M, g, l, C = sp.symbols("M g l C", positive=True)
    >>> point = Mechanics(name="point", inertia=sp.ImmutableMatrix(sp.diag(M * l**2, M * l**2, C)), mass=M,
    ...                   centre_of_mass=sp.ImmutableMatrix([0, 0, l]), gravity=g, pivoted=True)
    >>> kapitza_threshold(point)                          # the point pendulum's a²Ω² > 2 g l
    2*g*l
    """
    from eulersym.model.derive import equations

    if not isinstance(mech, Mechanics) or not mech.pivoted or mech.gravity == 0:
        raise InvalidInput("mechanics", getattr(mech, "name", mech), "a pivoted body under gravity")
    if axis not in (1, 2, 3):
        raise InvalidInput("axis", axis, "1, 2 or 3 (the body axis of the swing)")
    e = sp.Matrix([1 if k == axis - 1 else 0 for k in range(3)])
    I = sp.Matrix(mech.inertia)
    c = sp.Matrix(mech.centre_of_mass)
    if any(sp.simplify(x) != 0 for x in (I * e - I[axis - 1, axis - 1] * e)) or sp.simplify((c.T * e)[0, 0]) != 0:
        raise InvalidInput("axis", axis, "a principal axis through the pivot perpendicular to the centre of mass "
                           "(a swing in one plane)")
    theta = sp.Symbol("theta", real=True)
    length = sp.sqrt((c.T * c)[0, 0])
    u = c / length
    Gamma = sp.cos(theta) * u + sp.sin(theta) * u.cross(e)
    state = {**dict(zip(GAMMA, Gamma)), **dict(zip(OMEGA, (0, 0, 0)))}
    # the statics of the swing: θ̈ = ω̇·e at rest (ω = 0), q unused without a q-potential
    acceleration = (equations(mech).omega_dot.T * e)[0, 0].xreplace(state)
    k = sp.simplify(acceleration / (mech.gravity * sp.sin(theta)))
    if k.has(theta, t, *Q) or k == 0:
        raise InvalidInput("mechanics", mech.name, "a pendulum whose swing obeys θ̈ = k g sin θ (no torque but "
                           f"gravity's; here θ̈ = {acceleration})")
    return sp.simplify(2 * mech.gravity / k)
