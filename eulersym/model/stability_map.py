"""Stability maps: a family's proven conditions evaluated over a grid of two of its symbols (parameters or family
symbols), and the same grid decided independently by the eigenvalues of the linearisation at every point.

:func:`condition_map` turns the conditions into one vectorised NumPy function (``sympy.lambdify``): a 400 × 400 map
is a few array operations. :func:`eigenvalue_map` is the independent check: the full Jacobian at each point, its
eigenvalues by ``numpy.linalg.eigvals`` (batched), the trivial zero modes (the integrals' level sets, the orbit)
dropped by modulus, and the class read from the largest real part. :func:`agreement` compares the two off the
boundary (a point whose four neighbours share its class).

Classes (integers in the grids): ``-1`` no member (the family does not exist there), ``0`` unstable, ``1``
spectrally stable, ``2`` asymptotically stable.

Examples
--------
>>> import numpy as np
>>> from eulersym.model.cli import load
>>> from eulersym.model.steady import steady_motions
>>> top = steady_motions(load("lagrange-top")).named("rotation about e3, e3 up")
>>> m = condition_map(top.stability(), ("s", np.linspace(0, 150, 4)), ("l", np.linspace(0.01, 0.05, 3)))
>>> m.classes
array([[0, 1, 1, 1],
       [0, 0, 1, 1],
       [0, 0, 1, 1]])
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from eulersym.errors import InvalidInput

__all__ = ["StabilityMap", "condition_map", "compile_condition_map", "eigenvalue_map", "compile_jacobian",
           "eigenvalue_classes", "agreement", "margin", "CLASS_NAMES"]

#: Class number → words.
CLASS_NAMES = {-1: "no member", 0: "unstable", 1: "spectrally stable", 2: "asymptotically stable"}


@dataclass(frozen=True)
class StabilityMap:
    """A grid of classes over two symbols.

    Attributes
    ----------
    x, y : tuple (name, 1-D array)
        The symbols and their values (``classes[i, j]`` is at ``y[i]``, ``x[j]``).
    classes : ndarray of int, shape (len(y), len(x))
        See the module docstring.
    margin : ndarray of float or None
        A function whose zero level set is the proven boundary (from the conditions; None for eigenvalue maps).
    """

    x: tuple
    y: tuple
    classes: np.ndarray
    margin: np.ndarray | None = None


def _symbol(stab, name: str):
    fam = stab.family
    for s in (*fam.parameters, *fam.family):
        if s.name == name:
            return s
    import difflib

    names = [s.name for s in (*fam.parameters, *fam.family)]
    close = difflib.get_close_matches(name, names, n=1, cutoff=0.5)
    raise InvalidInput("--map", name, f"a parameter of the model or a symbol of the family {fam.name!r}: "
                       + ", ".join(names) + (f" (did you mean {close[0]!r}?)" if close else ""))


def margin(condition):
    """A real function whose sign says whether ``condition`` holds and whose zero set is its boundary: ``a ≥ b`` →
    ``a − b``; ``And`` → min; ``Or`` → max; ``Eq(f, 0)`` → ``−|f|``; ``Ne`` → ``|f|``.

    Examples
    --------
    >>> x, y = sp.symbols("x y", real=True)
    >>> margin(sp.And(x >= 1, sp.Or(y > 0, sp.Eq(x, 2))))
    Min(x - 1, Max(y, -Abs(x - 2)))
    """
    condition = sp.sympify(condition)
    if condition is sp.true:
        return sp.Integer(1)
    if condition is sp.false:
        return sp.Integer(-1)
    if isinstance(condition, sp.And):
        return sp.Min(*[margin(a) for a in condition.args])
    if isinstance(condition, sp.Or):
        return sp.Max(*[margin(a) for a in condition.args])
    if isinstance(condition, sp.Eq):
        return -sp.Abs(condition.lhs - condition.rhs)
    if isinstance(condition, sp.Ne):
        return sp.Abs(condition.lhs - condition.rhs)
    if isinstance(condition, (sp.GreaterThan, sp.StrictGreaterThan)):
        return condition.lhs - condition.rhs
    if isinstance(condition, (sp.LessThan, sp.StrictLessThan)):
        return condition.rhs - condition.lhs
    raise InvalidInput("condition", condition, "relations joined by And / Or")


def _grid(stab, xspec, yspec, values):
    """The two symbols and the exact values of every other one (parameters at defaults unless given)."""
    fam = stab.family
    xs_name, xs = xspec
    ys_name, ys = yspec
    if xs_name == ys_name:
        raise InvalidInput("--map", ys_name, "two different symbols")
    sx, sy = _symbol(stab, xs_name), _symbol(stab, ys_name)
    fixed = dict(values or {})
    fixed.pop(xs_name, None)
    fixed.pop(ys_name, None)
    needed = [s for s in fam.family if s not in (sx, sy)]
    for s in needed:
        if s.name not in fixed:
            raise InvalidInput("--at", fixed, f"a value for {s.name} (a symbol of {fam.name!r} not on the map)")
    point = fam.values({**fixed, **{s.name: 1 for s in (sx, sy) if s in fam.family}})
    point.pop(sx, None)
    point.pop(sy, None)
    return sx, sy, point


def _vectorised(expr, sx, sy, point):
    expr = sp.sympify(expr).xreplace({k: sp.Float(v, 17) for k, v in point.items()})
    f = sp.lambdify((sx, sy), expr, modules="numpy")
    return f


def compile_condition_map(stab, xname: str, yname: str, values=None):
    """The proven conditions and the existence condition as one vectorised function ``f(X, Y) → (classes,
    margin)`` of two symbols (see :func:`condition_map`): compiled once (``sympy.lambdify``), then a map costs a few
    NumPy array operations.

    Examples
    --------
    >>> from eulersym.model.cli import load
    >>> from eulersym.model.steady import steady_motions
    >>> st = steady_motions(load("torque-free")).named("rotation about e2").stability()
    >>> f = compile_condition_map(st, "I2", "s")
    >>> f(np.array([1.0, 3.0, 5.0]), np.array([1.0, 1.0, 1.0]))[0]      # I2 below, between, above I1 = 2, I3 = 4
    array([1, 0, 1])
    """
    if stab.conditions is None:
        raise InvalidInput("--map", stab.family.name, "a family with proven conditions (this one has no closed form: "
                           "classify its members with --at)")
    sx, sy, point = _grid(stab, (xname, ()), (yname, ()), values)
    fam = stab.family
    existence = sp.And(fam.exists, *fam.where)
    f_exists = _vectorised(existence, sx, sy, point)
    f_held = _vectorised(stab.conditions, sx, sy, point)
    f_margin = _vectorised(margin(stab.conditions), sx, sy, point)
    stable = 2 if stab.dissipative else 1

    def evaluate(X, Y):
        X, Y = np.broadcast_arrays(np.asarray(X, dtype=float), np.asarray(Y, dtype=float))
        with np.errstate(all="ignore"):
            exists = np.broadcast_to(np.asarray(f_exists(X, Y), dtype=bool), X.shape)
            held = np.broadcast_to(np.asarray(f_held(X, Y), dtype=bool), X.shape)
            m = np.broadcast_to(np.asarray(f_margin(X, Y), dtype=float), X.shape)
        classes = np.where(held, stable, 0)
        classes[~exists] = -1
        return classes, m

    return evaluate


def condition_map(stab, xspec, yspec, values=None) -> StabilityMap:
    """The classes over a grid from the proven conditions (and the existence condition), vectorised.

    Parameters
    ----------
    stab : Stability
    xspec, yspec : (name, 1-D array)
        Two symbols — parameters of the model or symbols of the family — and their values.
    values : mapping, optional
        The other parameters (defaults otherwise) and family symbols.

    Raises
    ------
    eulersym.errors.InvalidInput
        A name that is neither a parameter nor a family symbol (did-you-mean), a family symbol left without a
        value, or a family without closed-form conditions.
    """
    evaluate = compile_condition_map(stab, xspec[0], yspec[0], values)
    X, Y = np.meshgrid(np.asarray(xspec[1], dtype=float), np.asarray(yspec[1], dtype=float))
    classes, m = evaluate(X, Y)
    return StabilityMap((xspec[0], X[0].copy()), (yspec[0], Y[:, 0].copy()), classes.astype(int), np.array(m))


def compile_jacobian(stab, xname: str, yname: str, values=None):
    """The family's full linearisation ``J`` as a vectorised function ``f(X, Y) → array (..., n, n)`` (complex:
    a member where a root is not real gives non-real entries)."""
    sx, sy, point = _grid(stab, (xname, ()), (yname, ()), values)
    J = stab._jacobian_public
    n = J.shape[0]
    exact = {k: sp.Float(v, 17) for k, v in point.items()}
    f = sp.lambdify((sx, sy), [sp.sympify(e).xreplace(exact) for e in J], "numpy")

    def evaluate(X, Y):
        X, Y = np.broadcast_arrays(np.asarray(X, dtype=complex), np.asarray(Y, dtype=complex))
        with np.errstate(all="ignore"):
            flat = f(X, Y)
        entries = [np.broadcast_to(np.asarray(e, dtype=complex), X.shape) for e in flat]
        return np.stack(entries, axis=-1).reshape(X.shape + (n, n))

    return evaluate


def eigenvalue_classes(stab, A, tol: float = 1e-7):
    """Classes from the eigenvalues of a stack of Jacobians ``A`` (..., n, n), NumPy, batched (see
    :func:`eigenvalue_map`)."""
    n = A.shape[-1]
    shape = A.shape[:-2]
    with np.errstate(all="ignore"):
        good = np.all(np.isfinite(A), axis=(-2, -1))
        A = np.where(good[..., None, None], A, 0.0)
        lam = np.linalg.eigvals(A.reshape(-1, n, n)).reshape(shape + (n,))
    order = np.argsort(np.abs(lam), axis=-1)
    lam = np.take_along_axis(lam, order, axis=-1)[..., stab._removed:]
    if lam.shape[-1] == 0:
        classes = np.ones(shape, dtype=int)
    else:
        scale = 1.0 + np.max(np.abs(lam), axis=-1)
        top = np.max(lam.real, axis=-1)
        classes = np.where(top > tol * scale, 0, np.where(top < -tol * scale, 2, 1))
        if not stab.dissipative:
            classes = np.where(classes == 2, 1, classes)
    classes = classes.astype(int)
    classes[~good] = -1
    return classes


def eigenvalue_map(stab, xspec, yspec, values=None, *, tol: float = 1e-7) -> StabilityMap:
    """The classes over a grid from the eigenvalues of the full linearisation at every point (NumPy, batched):
    the independent check of :func:`condition_map`.

    The ``k`` eigenvalues of least modulus are the trivial zero modes the reduction divides out (the integrals' level
    sets, the orbit); of the rest, a largest real part above ``tol·(1 + |λ|max)`` is unstable, below ``−tol·…``
    asymptotically stable, else spectrally stable.
    """
    X, Y = np.meshgrid(np.asarray(xspec[1], dtype=float), np.asarray(yspec[1], dtype=float))
    A = compile_jacobian(stab, xspec[0], yspec[0], values)(X, Y)
    classes = eigenvalue_classes(stab, A, tol)
    return StabilityMap((xspec[0], X[0].copy()), (yspec[0], Y[:, 0].copy()), classes, None)


def agreement(proven: StabilityMap, numeric: StabilityMap) -> tuple:
    """``(agree, compared, boundary)``: points off the boundary (all four neighbours of the same proven class, the
    family existing) where both maps give the same class, how many were compared, and how many were skipped as on
    the boundary.

    Examples
    --------
    >>> a = StabilityMap(("x", np.arange(3.0)), ("y", np.arange(3.0)), np.array([[0, 0, 1]] * 3))
    >>> agreement(a, a)
    (3, 3, 6)
    """
    c = proven.classes
    same = np.ones(c.shape, dtype=bool)
    same[1:, :] &= c[1:, :] == c[:-1, :]
    same[:-1, :] &= c[:-1, :] == c[1:, :]
    same[:, 1:] &= c[:, 1:] == c[:, :-1]
    same[:, :-1] &= c[:, :-1] == c[:, 1:]
    interior = same & (c >= 0)
    agree = int(np.sum(interior & (numeric.classes == c)))
    return agree, int(np.sum(interior)), int(np.sum(~same & (c >= 0)))
