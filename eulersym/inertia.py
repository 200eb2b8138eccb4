r"""The inertia tensor, derived from its integral (§4.3 of the text), and its principal axes.

Everything here comes from one definition,

.. math:: I_{jk} = \int \rho(\vec r)\,(r^2 \delta_{jk} - x_j x_k)\, dV ,

evaluated in the coordinates natural to the body (Cartesian for boxes, spherical for balls and ellipsoids,
cylindrical for cylinders and cones), so that every standard body's tensor derives in a fraction of a second.
No body's moments are typed in: :func:`cube`, :func:`sphere`, ... build a :class:`Region`, give it the uniform
density ``M / volume`` (the volume itself integrated over the same region) and call :func:`tensor`.

Conventions
-----------
- Components are taken along the Cartesian axes ``x, y, z`` of the frame in which the region is described; the
  tensor is about that frame's origin.
- ``L = I @ omega`` (:func:`angular_momentum`) and ``T = omega.T @ I @ omega / 2`` (:func:`kinetic_energy`).
- :func:`principal_axes` returns ``(moments, Q)`` with ``I = Q @ diag(moments) @ Q.T``: the columns of ``Q`` are the
  principal axes (unit vectors, in the components of the input frame), ``Q`` is a proper rotation (det Q = +1), and
  the body-frame components of a vector are ``v_body = Q.T @ v``.

Examples
--------
Example 4.1 of the text, the uniform cube about a corner:

>>> import sympy as sp
>>> M, a = sp.symbols("M a", positive=True)
>>> I = cube(M, a, origin="corner")
>>> I / (M * a**2)
Matrix([
[ 2/3, -1/4, -1/4],
[-1/4,  2/3, -1/4],
[-1/4, -1/4,  2/3]])
>>> moments, axes = principal_axes(I)
>>> moments
(M*a**2/6, 11*M*a**2/12, 11*M*a**2/12)
>>> axes[:, 0].T
Matrix([[sqrt(3)/3, sqrt(3)/3, sqrt(3)/3]])
"""

from __future__ import annotations

import functools
import math
import numbers
from dataclasses import dataclass
from typing import Any, Iterable, Sequence

from eulersym._numpy import np
import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.symbols import x, y, z
from eulersym.validation import choice, finite_array, positive

__all__ = [
    "Region",
    "x",
    "y",
    "z",
    "tensor",
    "mass",
    "center_of_mass",
    "cube",
    "cuboid",
    "sphere",
    "cylinder",
    "cone",
    "ellipsoid",
    "rod",
    "point_masses",
    "parallel_axis",
    "principal_axes",
    "kinetic_energy",
    "angular_momentum",
]

#: The Cartesian coordinates a density may depend on (matched by name: any symbol called x, y or z); x, y, z
#: themselves are :mod:`eulersym.symbols`'.
_CARTESIAN_NAMES = ("x", "y", "z")

# Integration variables, private to this module so they never collide with a user's symbols.
_u, _v, _w = sp.Dummy("u", real=True), sp.Dummy("v", real=True), sp.Dummy("w", real=True)
_r = sp.Dummy("r", nonnegative=True)
_polar = sp.Dummy("theta", real=True)
_azimuth = sp.Dummy("phi", real=True)
_rho = sp.Dummy("rho", nonnegative=True)

#: Relative slack for floating-point triangle inequalities of principal moments.
_SLACK = 1e-12
_NON_NEGATIVE = "moments of inertia >= 0 (a body's principal moments)"
_TRIANGLE = "principal moments obeying the triangle inequalities I1 + I2 >= I3 (and permutations), as every body's do"


# --------------------------------------------------------------------------------------------------- validation
# eulersym.validation does the scalar checks. Principal moments are checked here: a tensor may have zero moments
# (a rod, a point mass on an axis), which validation.moments refuses, and symbolic moments are refused here when a
# triangle inequality is provably violated (e.g. I3 = I1 + I2 + 1).


def _is_sympy(value: Any) -> bool:
    return isinstance(value, sp.Basic) or isinstance(value, sp.MatrixBase)


def _scalar(argument: str, value: Any) -> Any:
    """A real scalar as SymPy (numbers and SymPy expressions only; strings are refused, never parsed)."""
    if isinstance(value, sp.Basic):  # before numbers.*: SymPy registers Integer, Rational, Float there
        if not isinstance(value, sp.Expr) or value.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
            raise InvalidInput(argument, value, "a finite real number or SymPy expression")
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Number):
        raise InvalidInput(argument, value, "a real number or a SymPy expression")
    if isinstance(value, numbers.Complex) and not isinstance(value, numbers.Real):
        raise InvalidInput(argument, value, "a real number or a SymPy expression")
    if not math.isfinite(float(value)):
        raise InvalidInput(argument, value, "a finite real number")
    if isinstance(value, numbers.Integral):
        return sp.Integer(int(value))
    if isinstance(value, numbers.Rational):  # fractions.Fraction
        return sp.Rational(value.numerator, value.denominator)
    return sp.Float(float(value))


def _positive(argument: str, value: Any) -> Any:
    """``value`` as SymPy, refused when it is (provably) zero, negative, NaN or infinite."""
    return _scalar(argument, positive(argument, value))


def _flat(value: Any) -> bool:
    """A list or tuple of scalars (no component is a sequence or an array): a 1-D array to NumPy."""
    return isinstance(value, (list, tuple)) and not any(hasattr(c, "__len__") or hasattr(c, "__array__")
                                                         for c in value)


def _vector3(argument: str, value: Any) -> tuple:
    """Three components (SymPy, or floats when no component is SymPy)."""
    if isinstance(value, sp.MatrixBase):
        if value.shape not in ((3, 1), (1, 3)):
            raise InvalidInput(argument, value, "a vector of 3 components (3×1 or 1×3 Matrix, list or array)")
        return tuple(value)
    if _flat(value):
        items, flat = list(value), True  # what NumPy would make of it, without its import
    else:
        try:
            items = list(np.asarray(value, dtype=object).reshape(-1)) if not isinstance(value, str) else None
        except Exception:  # pragma: no cover - exotic containers
            items = None
        flat = items is not None and np.ndim(np.asarray(value, dtype=object)) == 1
    if items is None or len(items) != 3 or not flat:
        raise InvalidInput(argument, value, "a vector of 3 components (3×1 or 1×3 Matrix, list or array)")
    return tuple(_scalar(f"{argument}[{i}]", c) if _is_sympy(c) else _finite_keep(f"{argument}[{i}]", c)
                 for i, c in enumerate(items))


def _finite_keep(argument: str, value: Any) -> Any:
    """``value`` itself (an int stays an int), checked to be a finite real number."""
    _finite(argument, value)
    return value


def _finite(argument: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InvalidInput(argument, value, "a finite real number or a SymPy expression")
    value = float(value)
    if not math.isfinite(value):
        raise InvalidInput(argument, value, "a finite real number")
    return value


def _violated(expr: Any, scale: Any) -> bool:
    """True when ``expr >= 0`` is provably false (with a small relative slack for floating-point numbers)."""
    expr = sp.sympify(expr)
    if expr.is_number:
        value = complex(expr.evalf())
        if abs(value.imag) > 1e-9 * (1 + abs(value.real)):
            return False
        slack = _SLACK * abs(complex(sp.sympify(scale).evalf())) if expr.has(sp.Float) else 0.0
        return value.real < -slack
    return bool(expr.is_negative)


def _check_moments(argument: str, values: Sequence[Any], given: Any) -> None:
    """Refuse principal moments no body can have: negative, or violating I1 + I2 >= I3 (and permutations)."""
    a, b, c = values
    scale = sp.Add(*[abs(v) if sp.sympify(v).is_number else 0 for v in values]) or 1
    if any(_violated(m, scale) for m in values):
        raise InvalidInput(argument, given, _NON_NEGATIVE)
    if any(_violated(sp.sympify(p) + q - r, scale) for p, q, r in ((a, b, c), (b, c, a), (c, a, b))):
        raise InvalidInput(argument, given, _TRIANGLE)


def _check_moments_numeric(argument: str, values: np.ndarray, given: Any) -> None:
    scale = float(np.sum(np.abs(values))) or 1.0
    slack = _SLACK * scale
    if np.any(values < -slack):
        raise InvalidInput(argument, given, _NON_NEGATIVE)
    a, b, c = values
    if min(a + b - c, b + c - a, c + a - b) < -slack:
        raise InvalidInput(argument, given, _TRIANGLE)


def _zero(expr: Any) -> bool:
    """Is ``expr`` exactly zero? Cheap strategies first, then eulersym.compare's."""
    expr = sp.expand(expr)
    if expr == 0:
        return True
    if expr.is_number:
        return bool(abs(complex(expr.evalf())) < 1e-12) if expr.has(sp.Float) else bool(expr.equals(0))
    from eulersym.compare import zero_exact

    return bool(zero_exact(expr)[0])


def _as_tensor(argument: str, value: Any, *, body: bool, allow_moments: bool = False):
    """Validate a 3×3 symmetric tensor; return ``("sympy", Matrix)`` or ``("numpy", ndarray)``.

    With ``allow_moments``, a flat sequence of 3 values is read as the principal moments, diag(I1, I2, I3).
    With ``body``, moments no body can have are refused.
    """
    if isinstance(value, str):
        raise InvalidInput(argument, value, "a 3×3 symmetric inertia tensor (Matrix, nested list or array)")
    if isinstance(value, sp.MatrixBase):
        kind, shape = "sympy", value.shape
    elif _flat(value):  # NumPy's shape and kind of a flat list or tuple, without its import
        shape = (len(value),)
        kind = "sympy" if any(_is_sympy(e) for e in value) else "numpy"
    else:
        try:
            arr = np.asarray(value, dtype=object)
        except Exception as exc:  # ragged lists
            raise InvalidInput(argument, value, "a 3×3 symmetric inertia tensor") from exc
        shape = arr.shape
        kind = "sympy" if any(_is_sympy(e) for e in arr.reshape(-1)) else "numpy"
    if allow_moments and shape in ((3,), (3, 1), (1, 3)):
        items = list(value) if isinstance(value, (list, tuple, sp.MatrixBase)) else list(np.asarray(value).reshape(-1))
        if kind == "sympy":
            moments = [_scalar(f"{argument}[{i}]", m) for i, m in enumerate(items)]
            _check_moments(argument, moments, value)
            return "sympy", sp.diag(*moments)
        moments_arr = np.array([_finite(f"{argument}[{i}]", m) for i, m in enumerate(items)])
        _check_moments_numeric(argument, moments_arr, value)
        return "numpy", np.diag(moments_arr)
    if shape != (3, 3):
        what = "a 3×3 symmetric inertia tensor" + (" or its 3 principal moments" if allow_moments else "")
        raise InvalidInput(f"{argument}.shape" if shape else argument, shape if shape else value, what)
    if kind == "sympy":
        mat = sp.Matrix(3, 3, [_scalar(f"{argument}[{j}, {k}]", value[j, k] if isinstance(value, sp.MatrixBase)
                                       else value[j][k]) for j in range(3) for k in range(3)])
        for j, k in ((0, 1), (0, 2), (1, 2)):
            if mat[j, k] != mat[k, j] and not _zero(mat[j, k] - mat[k, j]):
                raise InvalidInput(argument, value,
                                   f"a symmetric tensor (I[{j}, {k}] = {mat[j, k]} but I[{k}, {j}] = {mat[k, j]})")
        if body:
            diag = [mat[i, i] for i in range(3)]
            _check_moments(f"diagonal of {argument}", diag, value)
        return "sympy", mat
    arr = np.array([[_finite(f"{argument}[{j}, {k}]", arr[j, k]) for k in range(3)] for j in range(3)])
    scale = float(np.max(np.abs(arr))) or 1.0
    if np.max(np.abs(arr - arr.T)) > 1e-10 * scale:
        raise InvalidInput(argument, value, "a symmetric tensor (I[j, k] == I[k, j] to 1e-10 relative)")
    arr = (arr + arr.T) / 2
    if body:
        _check_moments_numeric(f"diagonal of {argument}", np.diag(arr).copy(), value)
    return "numpy", arr


# ------------------------------------------------------------------------------------------------------ regions


@dataclass(frozen=True)
class Region:
    r"""A region of space in coordinates natural to it, with the map to Cartesian ``x, y, z``.

    A point of the region has Cartesian position ``position`` (three expressions in ``coordinates``); the volume
    element is ``dV = jacobian · du dv dw``. ``limits`` are ``(coordinate, lower, upper)`` triples, innermost
    first (an inner limit may depend on outer coordinates), exactly as :func:`sympy.integrate` takes them.
    A one-dimensional region (:meth:`segment`) has a line element instead, and its "density" is per length.

    Use the constructors — :meth:`box`, :meth:`ball`, :meth:`cylinder`, :meth:`cone`, :meth:`ellipsoid`,
    :meth:`segment` — and :meth:`translated` to move a region. Regions are immutable and hashable, so derivations
    over them are cached.

    Attributes
    ----------
    coordinates : tuple of Symbol
    limits : tuple of (Symbol, Expr, Expr)
    position : tuple of 3 Expr
    jacobian : Expr
    name : str
        A short description, for printing.

    Examples
    --------
    >>> import sympy as sp
    >>> R = sp.Symbol("R", positive=True)
    >>> ball = Region.ball(R)
    >>> ball.name
    'ball(R)'
    >>> ball.volume()
    4*pi*R**3/3
    """

    coordinates: tuple
    limits: tuple
    position: tuple
    jacobian: Any
    name: str = "region"

    # ---- constructors

    @classmethod
    def box(cls, xlim: Sequence[Any], ylim: Sequence[Any], zlim: Sequence[Any]) -> "Region":
        """The box ``xlim[0] <= x <= xlim[1]``, and likewise for y and z (Cartesian coordinates).

        Examples
        --------
        >>> import sympy as sp
        >>> a = sp.Symbol("a", positive=True)
        >>> Region.box((0, a), (0, a), (0, a)).volume()
        a**3
        """
        lims = []
        for name, lim, var in (("xlim", xlim, _u), ("ylim", ylim, _v), ("zlim", zlim, _w)):
            if isinstance(lim, str) or not isinstance(lim, (tuple, list)) or len(lim) != 2:
                raise InvalidInput(name, lim, "a pair (lower, upper) of bounds")
            lo, hi = (_scalar(f"{name}[{i}]", b) for i, b in enumerate(lim))
            _positive(f"{name}[1] - {name}[0]", hi - lo)
            lims.append((var, lo, hi))
        return cls((_u, _v, _w), tuple(lims), (_u, _v, _w), sp.Integer(1),
                   f"box({tuple(xlim)}, {tuple(ylim)}, {tuple(zlim)})")

    @classmethod
    def ball(cls, R: Any) -> "Region":
        r"""The ball of radius ``R`` about the origin, in spherical coordinates ``(r, θ, φ)``, dV = r² sin θ.

        Examples
        --------
        >>> Region.ball(2).volume()
        32*pi/3
        """
        R = _positive("R", R)
        pos = (_r * sp.sin(_polar) * sp.cos(_azimuth), _r * sp.sin(_polar) * sp.sin(_azimuth), _r * sp.cos(_polar))
        return cls((_r, _polar, _azimuth), ((_r, 0, R), (_polar, 0, sp.pi), (_azimuth, 0, 2 * sp.pi)), pos,
                   _r**2 * sp.sin(_polar), f"ball({R})")

    @classmethod
    def ellipsoid(cls, a: Any, b: Any, c: Any) -> "Region":
        r"""The solid ellipsoid x²/a² + y²/b² + z²/c² <= 1: scaled spherical coordinates, dV = a b c r² sin θ.

        Examples
        --------
        >>> import sympy as sp
        >>> a, b, c = sp.symbols("a b c", positive=True)
        >>> Region.ellipsoid(a, b, c).volume()
        4*pi*a*b*c/3
        """
        a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
        pos = (a * _r * sp.sin(_polar) * sp.cos(_azimuth), b * _r * sp.sin(_polar) * sp.sin(_azimuth),
               c * _r * sp.cos(_polar))
        return cls((_r, _polar, _azimuth), ((_r, 0, 1), (_polar, 0, sp.pi), (_azimuth, 0, 2 * sp.pi)), pos,
                   a * b * c * _r**2 * sp.sin(_polar), f"ellipsoid({a}, {b}, {c})")

    @classmethod
    def cylinder(cls, R: Any, h: Any) -> "Region":
        r"""The solid circular cylinder of radius ``R`` and height ``h``, axis along z, centred on the origin
        (−h/2 <= z <= h/2); cylindrical coordinates ``(ρ, φ, z)``, dV = ρ.

        Examples
        --------
        >>> import sympy as sp
        >>> R, h = sp.symbols("R h", positive=True)
        >>> Region.cylinder(R, h).volume()
        pi*R**2*h
        """
        R, h = _positive("R", R), _positive("h", h)
        pos = (_rho * sp.cos(_azimuth), _rho * sp.sin(_azimuth), _w)
        return cls((_rho, _azimuth, _w), ((_rho, 0, R), (_azimuth, 0, 2 * sp.pi), (_w, -h / 2, h / 2)), pos, _rho,
                   f"cylinder({R}, {h})")

    @classmethod
    def cone(cls, R: Any, h: Any) -> "Region":
        r"""The solid right circular cone with its apex at the origin and its base (radius ``R``) at z = h;
        cylindrical coordinates with 0 <= ρ <= R z / h, dV = ρ.

        Examples
        --------
        >>> import sympy as sp
        >>> R, h = sp.symbols("R h", positive=True)
        >>> Region.cone(R, h).volume()
        pi*R**2*h/3
        """
        R, h = _positive("R", R), _positive("h", h)
        pos = (_rho * sp.cos(_azimuth), _rho * sp.sin(_azimuth), _w)
        return cls((_rho, _azimuth, _w), ((_rho, 0, R * _w / h), (_azimuth, 0, 2 * sp.pi), (_w, 0, h)), pos, _rho,
                   f"cone({R}, {h})")

    @classmethod
    def segment(cls, L: Any) -> "Region":
        """The straight segment of length ``L`` on the z axis, centred on the origin (a thin rod; line element).

        Examples
        --------
        >>> import sympy as sp
        >>> L = sp.Symbol("L", positive=True)
        >>> Region.segment(L).volume()
        L
        """
        L = _positive("L", L)
        return cls((_w,), ((_w, -L / 2, L / 2),), (sp.Integer(0), sp.Integer(0), _w), sp.Integer(1),
                   f"segment({L})")

    # ---- operations

    def translated(self, d: Sequence[Any]) -> "Region":
        """The same region moved by the vector ``d`` (every point's Cartesian position plus ``d``).

        The tensor of a body about a point ``P`` is the tensor of ``region.translated(-P)`` about the origin.

        Examples
        --------
        >>> import sympy as sp
        >>> a = sp.Symbol("a", positive=True)
        >>> Region.segment(a).translated((0, 0, a / 2)).position
        (0, 0, _w + a/2)
        """
        d = tuple(_scalar("d", c) for c in _vector3("d", d))
        pos = tuple(p + c for p, c in zip(self.position, d))
        return Region(self.coordinates, self.limits, pos, self.jacobian, f"{self.name} + {d}")

    def integrate(self, integrand: Any) -> Any:
        """∫ integrand dV over the region; ``integrand`` may use the Cartesian ``x, y, z`` (matched by name).

        Examples
        --------
        >>> import sympy as sp
        >>> a = sp.Symbol("a", positive=True)
        >>> Region.box((0, a), (0, a), (0, a)).integrate(x * y)
        a**5/4
        """
        return _integrate_cached(self._pull_back(_scalar("integrand", integrand)), self.limits)

    def volume(self) -> Any:
        """The region's volume ∫ dV (its length, for a segment).

        Examples
        --------
        >>> Region.cylinder(1, 2).volume()
        2*pi
        """
        return _integrate_cached(self.jacobian, self.limits)

    def _pull_back(self, expr: Any) -> Any:
        """``expr`` in Cartesian x, y, z → the integrand in the region's coordinates, times the Jacobian."""
        mapping = {s: self.position[_CARTESIAN_NAMES.index(s.name)]
                   for s in getattr(expr, "free_symbols", ()) if s.name in _CARTESIAN_NAMES}
        return sp.sympify(expr).xreplace(mapping) * self.jacobian


# ----------------------------------------------------------------------------------------------- the integrals


@functools.lru_cache(maxsize=4096)
def _definite(f: Any, var: Any, lo: Any, hi: Any) -> Any:
    """One-dimensional definite integral (cached: the same factors recur across the tensor's components).

    A polynomial in ``var`` by its antiderivative, ``F(hi) − F(lo)`` (what ``sympy.integrate`` does for one, without
    importing its heuristics); anything else by ``sympy.integrate``.
    """
    if f.is_polynomial(var):
        F = sp.Poly(f, var).integrate().as_expr()
        return F.xreplace({var: hi}) - F.xreplace({var: lo})
    return sp.integrate(f, (var, lo, hi))


@functools.lru_cache(maxsize=1024)
def _integrate_cached(expr: Any, limits: tuple) -> Any:
    """Iterated integral, innermost limit first, term by term: each expanded term splits into a factor that does
    not depend on the variable and one that does, and only the latter is integrated (cached by :func:`_definite`).
    """
    expr = sp.sympify(expr)
    for var, lo, hi in limits:
        terms = []
        for term in sp.Add.make_args(sp.expand(expr)):
            coeff, dep = term.as_independent(var, as_Add=False)
            terms.append(coeff * _definite(dep, var, lo, hi))
        expr = sp.Add(*terms)
    return sp.expand(expr)


def _density(density: Any) -> Any:
    density = _scalar("density", density)
    if density.is_negative:
        raise InvalidInput("density", density, "a density >= 0 (constant, or an expression in x, y, z)")
    return density


def mass(density: Any, region: Region) -> Any:
    """The mass ∫ ρ dV of a region.

    Parameters
    ----------
    density : number or sympy.Expr
        ρ: a constant or an expression in the Cartesian ``x, y, z`` (symbols matched by name).
    region : Region

    Examples
    --------
    >>> import sympy as sp
    >>> a = sp.Symbol("a", positive=True)
    >>> mass(x + y, Region.box((0, a), (0, a), (0, a)))
    a**4
    """
    _check_region(region)
    return region.integrate(_density(density))


def center_of_mass(density: Any, region: Region) -> sp.Matrix:
    """The centre of mass ∫ ρ r dV / ∫ ρ dV, a 3×1 Matrix.

    Examples
    --------
    >>> import sympy as sp
    >>> R, h = sp.symbols("R h", positive=True)
    >>> center_of_mass(1, Region.cone(R, h)).T
    Matrix([[0, 0, 3*h/4]])
    """
    _check_region(region)
    return _center_of_mass_cached(_density(density), region)


@functools.lru_cache(maxsize=256)
def _center_of_mass_cached(density: Any, region: Region) -> sp.Matrix:
    m = region.integrate(density)
    if m == 0:
        raise InvalidInput("density", density, "a density with non-zero mass over the region")
    return sp.Matrix([sp.cancel(region.integrate(density * c) / m) for c in (x, y, z)])


def _check_region(region: Any) -> None:
    if not isinstance(region, Region):
        raise InvalidInput("region", region, "an eulersym.inertia.Region (e.g. Region.ball(R))")


def tensor(density: Any, region: Region) -> sp.Matrix:
    r"""The inertia tensor about the origin, :math:`I_{jk} = \int \rho\,(r^2 \delta_{jk} - x_j x_k)\, dV`.

    By linearity of the integral, the six second moments :math:`S_{jk} = \int \rho\, x_j x_k\, dV` are integrated
    (in the region's own coordinates, term by term) and :math:`I = (\operatorname{tr} S)\,\mathbf 1 - S`.

    Parameters
    ----------
    density : number or sympy.Expr
        ρ: a constant, or an expression in the Cartesian ``x, y, z`` (any symbols named x, y, z).
    region : Region
        Where the body is, in the frame whose origin and axes the tensor refers to.

    Returns
    -------
    sympy.Matrix
        3×3, symmetric.

    Examples
    --------
    A ball of unit density:

    >>> import sympy as sp
    >>> R = sp.Symbol("R", positive=True)
    >>> tensor(1, Region.ball(R))
    Matrix([
    [8*pi*R**5/15,            0,            0],
    [           0, 8*pi*R**5/15,            0],
    [           0,            0, 8*pi*R**5/15]])

    A density that grows along x over the unit cube [0, 1]³:

    >>> tensor(x, Region.box((0, 1), (0, 1), (0, 1)))[0, 1]
    -1/6
    """
    _check_region(region)
    return sp.Matrix(_tensor_cached(_density(density), region))


@functools.lru_cache(maxsize=256)
def _tensor_cached(density: Any, region: Region) -> sp.ImmutableMatrix:
    S = sp.zeros(3, 3)
    for j in range(3):
        for k in range(j, 3):
            S[j, k] = S[k, j] = region.integrate(density * (x, y, z)[j] * (x, y, z)[k])
    trace = S.trace()
    return sp.ImmutableMatrix(3, 3, lambda j, k: sp.expand(trace * int(j == k) - S[j, k]))


# ------------------------------------------------------------------------------------------------------ bodies


def _uniform(M: Any, region: Region, origin_shift: Any = None) -> sp.Matrix:
    """The tensor of a uniform body of mass M over ``region`` (density M / volume), about the origin of the
    region translated by ``origin_shift`` (a callable region → vector, or None)."""
    density = M / region.volume()
    if origin_shift is not None:
        region = region.translated(origin_shift(region))
    return tensor(density, region)


#: Positive placeholders: each body is derived once in these (cached), then the caller's values are substituted,
#: so numbers stay exact (or are rounded once) and new symbols or numbers cost only a substitution.
_PLACEHOLDERS = tuple(sp.Dummy(f"p{i}", positive=True) for i in range(4))


def _instantiate(builder: Any, values: Sequence[Any], *options: Any) -> sp.Matrix:
    """``builder(*placeholders, *options)`` with the placeholders replaced by ``values``."""
    placeholders = _PLACEHOLDERS[: len(values)]
    return sp.Matrix(builder(*placeholders, *options).xreplace(dict(zip(placeholders, values))))


def _minus_center(region: Region) -> tuple:
    return tuple(-c for c in center_of_mass(1, region))


@functools.lru_cache(maxsize=256)
def _cuboid(M: Any, a: Any, b: Any, c: Any, origin: str) -> sp.ImmutableMatrix:
    if origin == "corner":
        region = Region.box((0, a), (0, b), (0, c))
    else:
        region = Region.box((-a / 2, a / 2), (-b / 2, b / 2), (-c / 2, c / 2))
    return sp.ImmutableMatrix(_uniform(M, region))


_BOX_ORIGINS = ("center", "corner")


def cuboid(M: Any, a: Any, b: Any, c: Any, origin: str = "center") -> sp.Matrix:
    """Uniform rectangular box of mass ``M`` and edges ``a, b, c`` along x, y, z.

    Parameters
    ----------
    M, a, b, c : positive number or sympy.Expr
    origin : {"center", "corner"}
        "center": the box is [−a/2, a/2] × [−b/2, b/2] × [−c/2, c/2]; "corner": it is [0, a] × [0, b] × [0, c].

    Examples
    --------
    >>> import sympy as sp
    >>> M, a, b, c = sp.symbols("M a b c", positive=True)
    >>> cuboid(M, a, b, c).diagonal()
    Matrix([[M*b**2/12 + M*c**2/12, M*a**2/12 + M*c**2/12, M*a**2/12 + M*b**2/12]])
    """
    args = (_positive("M", M), _positive("a", a), _positive("b", b), _positive("c", c))
    return _instantiate(_cuboid, args, choice("origin", origin, _BOX_ORIGINS))


def cube(M: Any, a: Any, origin: str = "center") -> sp.Matrix:
    """Uniform cube of mass ``M`` and edge ``a``, edges along x, y, z; ``origin`` "center" or "corner" (the cube
    then occupies [0, a]³, Example 4.1).

    Examples
    --------
    >>> import sympy as sp
    >>> M, a = sp.symbols("M a", positive=True)
    >>> cube(M, a)
    Matrix([
    [M*a**2/6,        0,        0],
    [       0, M*a**2/6,        0],
    [       0,        0, M*a**2/6]])
    >>> cube(M, a, origin="corner")[0, 1]
    -M*a**2/4
    """
    M, a = _positive("M", M), _positive("a", a)
    origin = choice("origin", origin, _BOX_ORIGINS)
    return _instantiate(lambda mass_, edge, o: _cuboid(mass_, edge, edge, edge, o), (M, a), origin)


@functools.lru_cache(maxsize=64)
def _sphere(M: Any, R: Any) -> sp.ImmutableMatrix:
    return sp.ImmutableMatrix(_uniform(M, Region.ball(R)))


def sphere(M: Any, R: Any) -> sp.Matrix:
    """Uniform solid sphere of mass ``M`` and radius ``R`` about its centre.

    Examples
    --------
    >>> import sympy as sp
    >>> M, R = sp.symbols("M R", positive=True)
    >>> sphere(M, R)[0, 0]
    2*M*R**2/5
    """
    return _instantiate(_sphere, (_positive("M", M), _positive("R", R)))


_CYLINDER_ORIGINS = ("center", "base")


@functools.lru_cache(maxsize=64)
def _cylinder(M: Any, R: Any, h: Any, origin: str) -> sp.ImmutableMatrix:
    shift = (lambda region: (0, 0, h / 2)) if origin == "base" else None
    return sp.ImmutableMatrix(_uniform(M, Region.cylinder(R, h), shift))


def cylinder(M: Any, R: Any, h: Any, origin: str = "center") -> sp.Matrix:
    """Uniform solid circular cylinder of mass ``M``, radius ``R``, height ``h``, symmetry axis along z.

    Parameters
    ----------
    origin : {"center", "base"}
        "center": centred on the origin; "base": the base's centre at the origin, the body in 0 <= z <= h.

    Examples
    --------
    >>> import sympy as sp
    >>> M, R, h = sp.symbols("M R h", positive=True)
    >>> cylinder(M, R, h).diagonal()
    Matrix([[M*R**2/4 + M*h**2/12, M*R**2/4 + M*h**2/12, M*R**2/2]])
    """
    M, R, h = _positive("M", M), _positive("R", R), _positive("h", h)
    return _instantiate(_cylinder, (M, R, h), choice("origin", origin, _CYLINDER_ORIGINS))


_CONE_ORIGINS = ("apex", "center")


@functools.lru_cache(maxsize=64)
def _cone(M: Any, R: Any, h: Any, origin: str) -> sp.ImmutableMatrix:
    return sp.ImmutableMatrix(_uniform(M, Region.cone(R, h), _minus_center if origin == "center" else None))


def cone(M: Any, R: Any, h: Any, origin: str = "apex") -> sp.Matrix:
    """Uniform solid right circular cone of mass ``M``, base radius ``R``, height ``h``, symmetry axis along z.

    Parameters
    ----------
    origin : {"apex", "center"}
        "apex": apex at the origin, base at z = h; "center": about the centre of mass (itself derived,
        :func:`center_of_mass`), same axes.

    Examples
    --------
    >>> import sympy as sp
    >>> M, R, h = sp.symbols("M R h", positive=True)
    >>> cone(M, R, h).diagonal()
    Matrix([[3*M*R**2/20 + 3*M*h**2/5, 3*M*R**2/20 + 3*M*h**2/5, 3*M*R**2/10]])
    >>> cone(M, R, h, origin="center")[0, 0]
    3*M*R**2/20 + 3*M*h**2/80
    """
    M, R, h = _positive("M", M), _positive("R", R), _positive("h", h)
    return _instantiate(_cone, (M, R, h), choice("origin", origin, _CONE_ORIGINS))


@functools.lru_cache(maxsize=64)
def _ellipsoid(M: Any, a: Any, b: Any, c: Any) -> sp.ImmutableMatrix:
    return sp.ImmutableMatrix(_uniform(M, Region.ellipsoid(a, b, c)))


def ellipsoid(M: Any, a: Any, b: Any, c: Any) -> sp.Matrix:
    """Uniform solid ellipsoid of mass ``M`` and semi-axes ``a, b, c`` along x, y, z, about its centre.

    Examples
    --------
    >>> import sympy as sp
    >>> M, a, b, c = sp.symbols("M a b c", positive=True)
    >>> ellipsoid(M, a, b, c)[0, 0]
    M*b**2/5 + M*c**2/5
    """
    return _instantiate(_ellipsoid, (_positive("M", M), _positive("a", a), _positive("b", b), _positive("c", c)))


_ROD_ORIGINS = ("center", "end")


@functools.lru_cache(maxsize=64)
def _rod(M: Any, L: Any, origin: str) -> sp.ImmutableMatrix:
    shift = (lambda region: (0, 0, L / 2)) if origin == "end" else None
    return sp.ImmutableMatrix(_uniform(M, Region.segment(L), shift))


def rod(M: Any, L: Any, origin: str = "center") -> sp.Matrix:
    """Uniform thin rod of mass ``M`` and length ``L`` along the z axis (no thickness: I_zz = 0).

    Parameters
    ----------
    origin : {"center", "end"}
        "center": −L/2 <= z <= L/2; "end": 0 <= z <= L.

    Examples
    --------
    >>> import sympy as sp
    >>> M, L = sp.symbols("M L", positive=True)
    >>> rod(M, L).diagonal()
    Matrix([[L**2*M/12, L**2*M/12, 0]])
    >>> rod(M, L, origin="end")[0, 0]
    L**2*M/3
    """
    M, L = _positive("M", M), _positive("L", L)
    return _instantiate(_rod, (M, L), choice("origin", origin, _ROD_ORIGINS))


def point_masses(masses: Iterable[tuple]) -> sp.Matrix:
    r"""The tensor of point masses, :math:`I_{jk} = \sum_i m_i (r_i^2 \delta_{jk} - x_{ij} x_{ik})` (the integral
    with ρ a sum of delta functions).

    Parameters
    ----------
    masses : iterable of (m, (x, y, z))
        Positive masses and their positions.

    Examples
    --------
    >>> point_masses([(1, (1, 0, 0)), (2, (0, 1, 1))])
    Matrix([
    [4,  0,  0],
    [0,  3, -2],
    [0, -2,  3]])
    """
    if isinstance(masses, (str, bytes)) or not isinstance(masses, Iterable):
        raise InvalidInput("masses", masses, "a list of (m, (x, y, z)) pairs")
    items = list(masses)
    if not items:
        raise InvalidInput("masses", masses, "at least one (m, (x, y, z)) pair")
    out = sp.zeros(3, 3)
    for i, item in enumerate(items):
        if not isinstance(item, (tuple, list)) or len(item) != 2:
            raise InvalidInput(f"masses[{i}]", item, "a pair (m, (x, y, z))")
        m = _positive(f"masses[{i}] mass", item[0])
        r = [_scalar(f"masses[{i}] position", c) for c in _vector3(f"masses[{i}] position", item[1])]
        r2 = sum(c**2 for c in r)
        out += m * (r2 * sp.eye(3) - sp.Matrix(r) * sp.Matrix(r).T)
    return out.applyfunc(sp.expand)


# ------------------------------------------------------------------------------------------ theorems and axes


def parallel_axis(I_cm: Any, M: Any, d: Any) -> Any:
    r"""Steiner's theorem: the tensor about the point displaced by ``d`` from the centre of mass,
    :math:`I = I_{cm} + M(|d|^2 \mathbf 1 - d\, d^T)` — the tensor of the mass ``M`` concentrated at ``d``.

    Parameters
    ----------
    I_cm : 3×3 Matrix or array
        The tensor about the centre of mass.
    M : positive number or sympy.Expr
    d : 3 components
        The new reference point minus the centre of mass.

    Returns
    -------
    sympy.Matrix, or ndarray when neither ``I_cm`` nor ``d`` holds SymPy objects.

    Examples
    --------
    The cube about a corner (Example 4.1) from the cube about its centre:

    >>> import sympy as sp
    >>> M, a = sp.symbols("M a", positive=True)
    >>> parallel_axis(cube(M, a), M, (-a/2, -a/2, -a/2)) == cube(M, a, origin="corner")
    True
    >>> parallel_axis([[1, 0, 0], [0, 1, 0], [0, 0, 1]], 2.0, [0, 0, 1])
    array([[3., 0., 0.],
           [0., 3., 0.],
           [0., 0., 1.]])
    """
    kind, I_cm = _as_tensor("I_cm", I_cm, body=True)
    d_items = _vector3("d", d)
    numeric = kind == "numpy" and not any(_is_sympy(c) for c in d_items) and not _is_sympy(M)
    M = _positive("M", M)
    # Σ m r = 0 about the centre of mass, so the cross terms of ∫ρ((r−d)²1 − (r−d)(r−d)ᵀ) vanish and what is left
    # is the tensor of the whole mass concentrated at d — the definition applied to one point mass.
    shift = point_masses([(M, d_items)])
    if numeric:
        return I_cm + np.array(shift, dtype=float)
    return (sp.Matrix(I_cm) + shift).applyfunc(sp.expand)


def principal_axes(I: Any, *, body: bool = True) -> tuple:
    r"""Principal moments and axes: ``I = Q @ diag(moments) @ Q.T``.

    Parameters
    ----------
    I : 3×3 symmetric sympy.Matrix, array or nested list
        SymPy in → SymPy out (exact); an array (or a list of plain numbers) → NumPy out
        (:func:`numpy.linalg.eigh`).
    body : bool, keyword-only
        True (default): ``I`` is a body's inertia tensor, so moments that no body has (negative, or violating
        I1 + I2 >= I3 and its permutations) are refused. False: any real symmetric matrix.

    Returns
    -------
    moments : tuple of 3 SymPy expressions, or ndarray (3,)
        Ascending. Exact: rationals and radicals where the characteristic polynomial factors; otherwise (an
        irreducible cubic, three real roots) ``sympy.CRootOf`` objects, real and exact, never complex radicals.
        For symbolic moments whose order cannot be decided, the order in which they were found (the diagonal's
        order for a diagonal tensor).
    axes : sympy.Matrix or ndarray (3, 3)
        Orthonormal columns, the principal axes, forming a proper rotation (det = +1; the third column's sign is
        chosen for that, or it is the cross product of the first two). A degenerate moment gets an orthonormal
        basis of its eigenspace; each of the first two columns has its first (SymPy) or largest (NumPy) non-zero
        component positive.

    Raises
    ------
    InvalidInput
        For a non-3×3 or non-symmetric ``I``; with ``body``, for impossible moments; for a symbolic tensor whose
        characteristic polynomial is an irreducible cubic (no useful closed form: substitute numbers first).

    Examples
    --------
    >>> import sympy as sp
    >>> M, a = sp.symbols("M a", positive=True)
    >>> moments, Q = principal_axes(cube(M, a, origin="corner"))
    >>> moments
    (M*a**2/6, 11*M*a**2/12, 11*M*a**2/12)
    >>> Q
    Matrix([
    [sqrt(3)/3,  sqrt(2)/2,  sqrt(6)/6],
    [sqrt(3)/3, -sqrt(2)/2,  sqrt(6)/6],
    [sqrt(3)/3,          0, -sqrt(6)/3]])
    >>> import numpy as np
    >>> m, Q = principal_axes(np.array([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 2.5]]))
    >>> m
    array([1. , 2.5, 3. ])
    >>> bool(np.isclose(np.linalg.det(Q), 1.0))
    True
    """
    if not isinstance(body, bool):
        raise InvalidInput("body", body, "True or False")
    kind, mat = _as_tensor("I", I, body=body)
    if kind == "numpy":
        return _principal_axes_numpy(mat, body)
    if mat.has(sp.Float) and not mat.free_symbols:
        moments, Q = _principal_axes_numpy(np.array(mat.evalf(), dtype=float), body)
        return tuple(sp.Float(m) for m in moments), sp.Matrix(Q)
    moments, Q = _principal_axes_sympy(sp.ImmutableMatrix(mat))
    if body:
        _check_moments("I (principal moments)", moments, I)
    return moments, sp.Matrix(Q)


def _principal_axes_numpy(mat: np.ndarray, body: bool) -> tuple:
    moments, Q = np.linalg.eigh(mat)
    if body:
        _check_moments_numeric("I (principal moments)", moments, mat)
    for col in (0, 1):
        if Q[np.argmax(np.abs(Q[:, col])), col] < 0:
            Q[:, col] = -Q[:, col]
    Q[:, 2] = np.cross(Q[:, 0], Q[:, 1])
    return moments, Q


def _decided_order(values: list, approx: dict | None = None) -> list:
    """Indices sorting ``values`` ascending where the comparisons can be decided; stable otherwise."""
    if all(v.is_number for v in values):
        return sorted(range(len(values)), key=lambda i: complex(values[i].xreplace(approx or {}).evalf(30)).real)

    def cmp(i: int, j: int) -> int:
        diff = values[i] - values[j]
        return -1 if diff.is_negative else 1 if diff.is_positive else 0

    return sorted(range(len(values)), key=functools.cmp_to_key(cmp))


def _first_nonzero_positive(v: sp.Matrix, approx: dict | None = None) -> sp.Matrix:
    for c in v:
        if c == 0 or c.is_zero:
            continue
        if c.is_number and c.is_negative is None:  # e.g. polynomials in CRootOf: 30 digits decide
            value = complex(c.xreplace(approx or {}).evalf(30)).real
            if abs(value) < 1e-25:
                continue
            return -v if value < 0 else v
        return -v if c.is_negative else v
    return v


def _simple_eigenvector(N: sp.MatrixBase, root: Any, approx: dict) -> sp.Matrix:
    """Unit eigenvector of ``N`` for a simple eigenvalue ``root`` (exact, e.g. a CRootOf): the cross product of
    two rows of N − root·1, the pair chosen with the largest cross product (evaluated with ``approx``, the roots
    to 30 digits)."""
    K = sp.Matrix(N) - root * sp.eye(3)
    candidates = [K[i, :].T.cross(K[j, :].T).applyfunc(sp.expand) for i, j in ((0, 1), (0, 2), (1, 2))]
    v = max(candidates, key=lambda u: float(sum(abs(complex(e.xreplace(approx).evalf(30))) ** 2 for e in u)))
    norm2 = sp.expand(v.dot(v))
    if isinstance(root, sp.CRootOf):  # reduce polynomials in the root modulo its minimal polynomial
        t = sp.Dummy("t")
        minimal = root.poly.as_expr(t)

        def reduce(e: Any) -> Any:
            return sp.rem(sp.expand(e.xreplace({root: t})), minimal, t).xreplace({t: root})

        v, norm2 = v.applyfunc(reduce), reduce(norm2)
    return v / sp.sqrt(norm2)


def _rational_denominator_lcm(v: sp.Matrix) -> sp.Integer:
    """The lcm of the denominators of the rational coefficients in ``v``'s entries (1 for symbolic entries)."""
    lcm = sp.Integer(1)
    for entry in v:
        for coeff in sp.expand(entry).as_coefficients_dict().values():
            if not isinstance(coeff, sp.Rational):
                return sp.Integer(1)
            lcm = sp.ilcm(lcm, coeff.q)
    return sp.Integer(lcm)


def _orthonormal_basis(vectors: list) -> list:
    """Gram–Schmidt, keeping every entry as (number-field element) / sqrt(squared norm), so that identities such
    as QᵀQ = 1 and I q = λ q expand to zero exactly (no rationalised, nested radicals)."""
    done = []  # (unnormalised vector, its squared norm)
    for v in vectors:
        u = v.applyfunc(sp.radsimp)
        for w, w2 in done:
            u = (u - sp.radsimp(sp.expand(u.dot(w)) / w2) * w).applyfunc(lambda e: sp.radsimp(sp.expand(e)))
        u = u * _rational_denominator_lcm(u)
        done.append((u, sp.factor_terms(sp.expand(u.dot(u)))))
    return [u / sp.sqrt(u2) for u, u2 in done]


@functools.lru_cache(maxsize=128)
def _principal_axes_sympy(mat: sp.ImmutableMatrix) -> tuple:
    # Diagonal: the coordinate axes are principal already.
    if all(mat[j, k] == 0 for j in range(3) for k in range(3) if j != k):
        diag = [mat[i, i] for i in range(3)]
        order = _decided_order(diag)
        Q = sp.Matrix.hstack(*[sp.eye(3)[:, i] for i in order])
        if Q.det() < 0:  # a permutation matrix: fix the orientation on the third column
            Q[:, 2] = -Q[:, 2]
        return tuple(diag[i] for i in order), sp.ImmutableMatrix(Q)
    # Factor out the common content (e.g. M a²), so that the eigenproblem is often a purely numeric one.
    entries = [e for e in mat if e != 0]
    scale = functools.reduce(sp.gcd, entries)
    if scale == 0 or not (scale.is_positive or scale.is_negative):
        scale = sp.Integer(1)
    unit = mat.applyfunc(lambda e: sp.cancel(e / scale))
    charpoly = sp.Matrix(unit).charpoly()  # a PurePoly in one variable
    if any(f.degree() == 3 for f, _ in sp.factor_list(charpoly)[1]):
        # Three distinct roots of an irreducible cubic: no useful radicals (casus irreducibilis).
        if unit.free_symbols:
            raise InvalidInput("I", mat, "a tensor whose principal moments have a closed form (a characteristic "
                                         "polynomial that factors, e.g. a symmetric body); for a general "
                                         "symbolic tensor substitute numbers, or pass a NumPy array")
        roots = [sp.CRootOf(charpoly, i, radicals=False) for i in range(3)]  # real, ascending
        approx = {root: root.evalf(30) for root in roots}
        pairs = [(root, [_simple_eigenvector(unit, root, approx)]) for root in roots]
    else:
        approx = {}
        pairs = []  # (eigenvalue of unit, orthonormal basis of its eigenspace)
        for value, _mult, basis in sp.Matrix(unit).eigenvects():
            pairs.append((sp.radsimp(value), _orthonormal_basis(basis)))
    values = [v for v, vecs in pairs for _ in vecs]
    vectors = [vec for _, vecs in pairs for vec in vecs]
    if len(values) != 3:  # pragma: no cover - sympy could not split the characteristic polynomial
        raise InvalidInput("I", mat, "a symmetric tensor whose eigenvectors SymPy can find exactly; "
                                     "pass a NumPy array for a numeric answer")
    moments = [sp.expand(scale * v) for v in values]
    order = _decided_order(values, approx) if scale.is_positive else _decided_order(moments, approx)
    e1, e2, e3 = (_first_nonzero_positive(vectors[i], approx) for i in order)
    Q = sp.Matrix.hstack(e1, e2, e3)
    if not Q.free_symbols:  # det Q is exactly ±1 (orthonormal columns), so 30 digits decide the sign
        if complex(Q.xreplace(approx).evalf(30).det()).real < 0:
            Q[:, 2] = -e3
    else:  # symbolic: the third axis as the cross product of the first two, proper by construction
        Q[:, 2] = e1.cross(e2).applyfunc(sp.radsimp)
    return tuple(moments[i] for i in order), sp.ImmutableMatrix(Q)


# ----------------------------------------------------------------------------------------- energy and momentum


def _as_omega(value: Any) -> tuple:
    """``("sympy", Matrix 3×1)`` or ``("numpy", array (..., 3))``."""
    if isinstance(value, sp.MatrixBase) or (
            not isinstance(value, np.ndarray) and isinstance(value, (list, tuple))
            and any(_is_sympy(c) for c in value)):
        return "sympy", sp.Matrix(_vector3("omega", value))
    if isinstance(value, str):
        raise InvalidInput("omega", value, "3 components (Matrix, list or array of shape (..., 3))")
    arr = finite_array("omega", value)
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise InvalidInput("omega.shape", arr.shape, "(..., 3): the angular velocity's 3 components last")
    return "numpy", arr


def angular_momentum(I: Any, omega: Any) -> Any:
    r"""The angular momentum :math:`L = I \omega`, i.e. :math:`L_j = \sum_k I_{jk} \omega_k`.

    Parameters
    ----------
    I : 3×3 tensor (Matrix, nested list or array), or the 3 principal moments (I1, I2, I3)
        Refused when no body could have it (non-symmetric, negative or triangle-violating moments).
    omega : 3 components (Matrix, list or array; NumPy arrays may be (..., 3), one ω per row)

    Returns
    -------
    sympy.Matrix 3×1 when either input holds SymPy objects, else ndarray of the shape of ``omega``.

    Examples
    --------
    >>> import sympy as sp
    >>> w1, w2, w3 = sp.symbols("omega1:4")
    >>> I1, I2, I3 = sp.symbols("I1:4", positive=True)
    >>> angular_momentum((I1, I2, I3), [w1, w2, w3]).T
    Matrix([[I1*omega1, I2*omega2, I3*omega3]])
    >>> angular_momentum([[2.0, 0, 0], [0, 3.0, 0], [0, 0, 4.0]], [1.0, 1.0, 0.5])
    array([2., 3., 2.])
    """
    kind_I, mat = _as_tensor("I", I, body=True, allow_moments=True)
    kind_w, w = _as_omega(omega)
    if kind_I == "numpy" and kind_w == "numpy":
        return w @ mat.T
    w = sp.Matrix(w.reshape(-1).tolist()) if kind_w == "numpy" else w
    if w.shape != (3, 1):
        raise InvalidInput("omega.shape", w.shape, "3 components when I or omega is symbolic")
    return sp.Matrix(mat) * w


def kinetic_energy(I: Any, omega: Any) -> Any:
    r"""The rotational kinetic energy (§4.3),
    :math:`T = \tfrac12 \omega^T I \omega = \tfrac12 \sum_{jk} I_{jk} \omega_j \omega_k`.

    Parameters
    ----------
    I : 3×3 tensor or the 3 principal moments, as for :func:`angular_momentum`
    omega : 3 components (NumPy arrays may be (..., 3))

    Returns
    -------
    SymPy expression when either input holds SymPy objects; else a float (or an array of shape ``omega[..., 0]``).

    Examples
    --------
    >>> import sympy as sp
    >>> w1, w2, w3 = sp.symbols("omega1:4")
    >>> I1, I2, I3 = sp.symbols("I1:4", positive=True)
    >>> kinetic_energy((I1, I2, I3), (w1, w2, w3))
    I1*omega1**2/2 + I2*omega2**2/2 + I3*omega3**2/2
    >>> kinetic_energy([[2.0, 0, 0], [0, 3.0, 0], [0, 0, 4.0]], [1.0, 1.0, 0.5])
    3.0
    """
    kind_I, mat = _as_tensor("I", I, body=True, allow_moments=True)
    kind_w, w = _as_omega(omega)
    if kind_I == "numpy" and kind_w == "numpy":
        energy = 0.5 * np.einsum("...j,jk,...k->...", w, mat, w)
        return float(energy) if np.ndim(energy) == 0 else energy
    w = list(w.reshape(-1)) if kind_w == "numpy" else list(w)
    if len(w) != 3:
        raise InvalidInput("omega.shape", np.shape(omega), "3 components when I or omega is symbolic")
    return sp.Add(*[sp.sympify(mat[j, k]) * w[j] * w[k] for j in range(3) for k in range(3)]) / 2
