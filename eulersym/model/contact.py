"""A body's contact with a horizontal plane: its surface near the contact, the contact point, and the contact's law.

The plane is ``z = 0`` of the space frame, ``ẑ`` up. ``Γ`` is the upward vertical in body components
(``Γ = A ẑ``, ``r_body = A r_space``, ``A = R(q)ᵀ``); every vector here is in body components and measured from the
body's centre of mass.

Surfaces (:func:`surface`)
    Each is described in its own *shape frame* — origin at the shape's centre, axes ``e1, e2, e3`` — placed in the
    body by ``centre`` (the shape's centre from the centre of mass, body components) and ``axes`` (a rotation:
    ``v_body = axes · v_shape``). Each has a support function ``h(n) = max_{x ∈ body} x·n`` (shape frame):

    - ``sphere`` of radius ``R``: ``h(n) = R |n|``;
    - ``ellipsoid`` of semi-axes ``a, b, c`` along ``e1, e2, e3``: ``h(n) = √(nᵀ B n)``, ``B = diag(a², b², c²)``;
    - ``disk`` of radius ``R`` in the plane ``e1 e2`` (the rim touches): ``h(n) = R √(n1² + n2²)``;
    - ``paraboloid`` ``x3 = (κ1 x1² + κ2 x2²)/2`` with curvatures ``κ1, κ2`` at its vertex (the body lies on the
      side ``x3 ≥``; only the neighbourhood of the vertex, facing ``−e3``, is meant to touch):
      ``h(n) = −(n1²/κ1 + n2²/κ2)/(2 n3)`` for ``n3 < 0``.

The contact point (:func:`contact_point`)
    The support-point construction: the point of a convex surface whose outward normal is ``n`` is ``∇h(n)``; the
    plane touches the body where the outward normal is ``n = −Γ``, so (body components, from the centre of mass)

    ``r_P(Γ) = centre + axes · ∇h(axesᵀ (−Γ))``.

    ``∇h`` is derived by SymPy from ``h``. The sphere's ``R n/|n|`` is written ``R n`` (the state keeps ``|Γ| = 1``,
    an integral of ``Γ̇ = Γ × ω``); the other gradients are homogeneous of degree 0 as they stand. Either way the
    Hessian maps ``n`` to a multiple of ``n``, so the contact point slides along the surface's tangent plane:
    ``Γ · dr_P/dt = 0`` identically along ``Γ̇ = Γ × ω``, and the material point at the contact has no vertical
    velocity once the centre of mass's height is ``z = −r_P · Γ``.

The law (:class:`Contact`)
    ``mode = "rolling"``: no slip, ``v_P = v_G + ω × r_P = 0`` (a nonholonomic constraint);
    ``mode = "sliding"``: the normal force holds the body on the plane, and a friction law acts against the slip
    ``u`` (the velocity of the material point at the contact, horizontal): ``"none"`` (a frictionless plane),
    ``"viscous"`` ``F = −μ u`` (``μ`` in N s/m), or ``"coulomb"`` regularised with width ``ε`` (m/s):
    ``F = −μ N u / √(|u|² + ε²)`` (Coulomb's ``μ N`` once ``|u| ≫ ε``, viscous ``μ N/ε`` near rest).
    Optional torques about the centre of mass, either mode: rolling resistance ``−c_r (ω − (ω·Γ) Γ)`` (against the
    rolling, the horizontal part of ω) and spin friction ``−c_s (ω·Γ) Γ`` (against the spin about the vertical).

Every dimension and coefficient may be a number or a SymPy expression of the model's parameters. Numbers are
checked here (positive dimensions, non-negative coefficients); expressions at the parameters' values by
:class:`eulersym.model.rolling.BodyOnPlane`. Errors name the key as a model file writes it (``contact.radius``).

Examples
--------
>>> import sympy as sp
>>> from eulersym.model.mechanics import GAMMA
>>> top = surface("sphere", radius=sp.Rational(1, 40), centre=(0, 0, sp.Rational(1, 200)))
>>> contact_point(top).T
Matrix([[-gamma1/40, -gamma2/40, 1/200 - gamma3/40]])
>>> Contact(top, mode="sliding", friction="coulomb", mu=sp.Rational(3, 10), width=sp.Rational(1, 100)).mode
'sliding'
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import sympy as sp

from eulersym.errors import InvalidInput
from eulersym.model.mechanics import GAMMA
from eulersym.validation import choice

__all__ = ["SURFACES", "MODES", "FRICTION_LAWS", "Surface", "surface", "support_function", "support_point",
           "contact_point", "Contact"]

#: Surface kind → its dimension key (the TOML key under ``[contact]``) and the number of values it takes.
SURFACES: dict[str, tuple[str, int]] = {
    "sphere": ("radius", 1),
    "ellipsoid": ("semi_axes", 3),
    "disk": ("radius", 1),
    "paraboloid": ("curvatures", 2),
}
#: The contact's modes.
MODES = ("rolling", "sliding")
#: Friction laws of a sliding contact.
FRICTION_LAWS = ("none", "viscous", "coulomb")

_N = sp.symbols("n1:4", real=True)


def _number(key: str, value, expected: str):
    """``value`` as an exact SymPy number (floats as the rationals they print as) or expression; refuse the rest."""
    if isinstance(value, bool) or value is None:
        raise InvalidInput(key, value, expected)
    if isinstance(value, sp.Basic):
        if isinstance(value, sp.MatrixBase) or not isinstance(value, sp.Expr):
            raise InvalidInput(key, value, expected)
        out = value
    elif isinstance(value, int):
        out = sp.Integer(value)
    elif isinstance(value, float):
        if value != value or value in (float("inf"), float("-inf")):
            raise InvalidInput(key, value, expected)
        out = sp.Rational(repr(value))
    else:
        raise InvalidInput(key, value, expected)
    if out.has(sp.oo, -sp.oo, sp.zoo, sp.nan) or out.is_real is False:
        raise InvalidInput(key, value, expected)
    return out


def _positive(key: str, value):
    out = _number(key, value, "a positive number (or an expression of the parameters)")
    if out.is_number and not out.is_positive:
        raise InvalidInput(key, value, "a positive number (or an expression of the parameters)")
    return out


def _non_negative(key: str, value):
    out = _number(key, value, "a number >= 0 (or an expression of the parameters)")
    if out.is_number and out.is_negative:
        raise InvalidInput(key, value, "a number >= 0 (or an expression of the parameters)")
    return out


def _vector(key: str, value) -> sp.ImmutableMatrix:
    if isinstance(value, sp.MatrixBase):
        items = list(value)
    elif isinstance(value, (list, tuple)):
        items = list(value)
    else:
        raise InvalidInput(key, value, "three components [x, y, z] (numbers or expressions of the parameters)")
    if len(items) != 3:
        raise InvalidInput(key, value, f"three components [x, y, z], got {len(items)}")
    return sp.ImmutableMatrix([_number(f"{key}[{k}]", x, "a number or an expression of the parameters")
                               for k, x in enumerate(items)])


def _rotation(key: str, value) -> sp.ImmutableMatrix:
    expected = "a 3×3 rotation matrix (v_body = axes · v_shape; orthonormal, det +1)"
    if value is None:
        return sp.ImmutableMatrix(sp.eye(3))
    try:
        R = sp.Matrix(value)
    except (TypeError, ValueError, sp.SympifyError):
        raise InvalidInput(key, value, expected) from None
    if R.shape != (3, 3):
        raise InvalidInput(key, value, expected)
    R = sp.Matrix(3, 3, [_number(key, x, expected) for x in R])
    if not R.free_symbols:
        defect = (R.T * R - sp.eye(3)).applyfunc(lambda x: abs(sp.N(x, 30)))
        if max(defect) > 1e-12 or sp.N(R.det(), 30) < 0:
            raise InvalidInput(key, value, expected)
    return sp.ImmutableMatrix(R)


@dataclass(frozen=True)
class Surface:
    """The body's surface near the contact, placed in the body (see the module docstring).

    Attributes
    ----------
    kind : str
        One of :data:`SURFACES`.
    dimensions : tuple of sympy.Expr
        ``(R,)`` sphere and disk, ``(a, b, c)`` ellipsoid, ``(κ1, κ2)`` paraboloid.
    centre : 3×1 ImmutableMatrix
        The shape's centre (the paraboloid's vertex) from the centre of mass, body components.
    axes : 3×3 ImmutableMatrix
        ``v_body = axes · v_shape``.

    Examples
    --------
    >>> surface("disk", radius=2).dimensions
    (2,)
    """

    kind: str
    dimensions: tuple
    centre: sp.ImmutableMatrix
    axes: sp.ImmutableMatrix

    @property
    def key(self) -> str:
        """The dimension's key (``radius``, ``semi_axes``, ``curvatures``)."""
        return SURFACES[self.kind][0]


def surface(kind: str, *, radius=None, semi_axes=None, curvatures=None, centre=(0, 0, 0), axes=None,
            section: str = "contact") -> Surface:
    """A contact surface: ``kind`` with its dimension, placed by ``centre`` and ``axes``.

    Parameters
    ----------
    kind : {"sphere", "ellipsoid", "disk", "paraboloid"}
    radius : number or sympy.Expr
        Sphere and disk.
    semi_axes : 3 numbers or expressions
        Ellipsoid ``(a, b, c)`` along the shape's axes.
    curvatures : 2 numbers or expressions
        Paraboloid ``(κ1, κ2)`` (1/m) at its vertex.
    centre : 3 numbers or expressions
        The shape's centre from the centre of mass, body components.
    axes : 3×3 matrix, optional
        ``v_body = axes · v_shape`` (default: the body's axes).
    section : str
        The prefix of the keys in messages (``contact``).

    Raises
    ------
    eulersym.errors.InvalidInput
        An unknown kind, a missing, extra, non-positive or non-numeric dimension, a bad centre or rotation — the
        message names the key (``contact.radius``) and the value.

    Examples
    --------
    >>> surface("ellipsoid", semi_axes=(0.2, 0.03, 0.02)).dimensions
    (1/5, 3/100, 1/50)
    >>> surface("sphere", radius=-1)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: contact.radius=-1 is not valid: expected a positive number (or an expression of the parameters)
    """
    choice(f"{section}.surface", kind, tuple(SURFACES))
    key, count = SURFACES[kind]
    given = {"radius": radius, "semi_axes": semi_axes, "curvatures": curvatures}
    for other, value in given.items():
        if other != key and value is not None:
            raise InvalidInput(f"{section}.{other}", value, f"no {other} for a {kind} (it takes {key})")
    value = given[key]
    if value is None:
        raise InvalidInput(f"{section}.{key}", value, f"the {kind}'s {key.replace('_', ' ')} (it is missing)")
    if count == 1:
        if isinstance(value, (list, tuple)):
            raise InvalidInput(f"{section}.{key}", value, "one positive number (or an expression of the parameters)")
        dims = (_positive(f"{section}.{key}", value),)
    else:
        if not isinstance(value, (list, tuple)) or len(value) != count:
            raise InvalidInput(f"{section}.{key}", value, f"{count} positive numbers")
        dims = tuple(_positive(f"{section}.{key}[{k}]", x) for k, x in enumerate(value))
    return Surface(kind, dims, _vector(f"{section}.centre", centre), _rotation(f"{section}.axes", axes))


def support_function(s: Surface, n=_N) -> sp.Expr:
    """The support function ``h(n) = max_{x ∈ body} x·n`` of the shape, in its own frame (see the module docstring).

    Examples
    --------
    >>> import sympy as sp
    >>> n = sp.symbols("n1:4", real=True)
    >>> support_function(surface("ellipsoid", semi_axes=(1, 2, 3)), n)
    sqrt(n1**2 + 4*n2**2 + 9*n3**2)
    """
    n1, n2, n3 = n
    d = s.dimensions
    if s.kind == "sphere":
        return d[0] * sp.sqrt(n1 ** 2 + n2 ** 2 + n3 ** 2)
    if s.kind == "ellipsoid":
        return sp.sqrt(d[0] ** 2 * n1 ** 2 + d[1] ** 2 * n2 ** 2 + d[2] ** 2 * n3 ** 2)
    if s.kind == "disk":
        return d[0] * sp.sqrt(n1 ** 2 + n2 ** 2)
    return -(n1 ** 2 / d[0] + n2 ** 2 / d[1]) / (2 * n3)  # paraboloid, n3 < 0


def support_point(s: Surface, n=_N) -> sp.Matrix:
    """``∇h(n)``: the point of the shape whose outward normal is ``n`` (shape frame, from the shape's centre).

    Derived by differentiating :func:`support_function`; for the sphere ``R n/|n|`` is written ``R n`` (unit
    ``n``, see the module docstring).

    Examples
    --------
    >>> import sympy as sp
    >>> n = sp.symbols("n1:4", real=True)
    >>> support_point(surface("paraboloid", curvatures=(2, 8)), n).T
    Matrix([[-n1/(2*n3), -n2/(8*n3), -(-n1**2/2 - n2**2/8)/(2*n3**2)]])
    """
    h = support_function(s, _N)
    grad = sp.Matrix([sp.diff(h, x) for x in _N])
    if s.kind == "sphere":  # R n/|n| on |n| = 1
        norm2 = sum(x ** 2 for x in _N)
        grad = grad.xreplace({sp.Pow(norm2, sp.Rational(-1, 2)): sp.Integer(1), sp.sqrt(norm2): sp.Integer(1)})
    return grad.xreplace(dict(zip(_N, n)))


@functools.lru_cache(maxsize=64)
def _contact_point(s: Surface) -> sp.ImmutableMatrix:
    G = sp.Matrix(GAMMA)
    n = s.axes.T * (-G)
    return sp.ImmutableMatrix(sp.Matrix(s.centre) + s.axes * support_point(s, tuple(n)))


def contact_point(s: Surface) -> sp.ImmutableMatrix:
    """``r_P(Γ) = centre + axes · ∇h(axesᵀ (−Γ))``: the contact point from the centre of mass, body components.

    Examples
    --------
    >>> contact_point(surface("disk", radius=1)).T
    Matrix([[-gamma1/sqrt(gamma1**2 + gamma2**2), -gamma2/sqrt(gamma1**2 + gamma2**2), 0]])
    """
    if not isinstance(s, Surface):
        raise InvalidInput("surface", s, "an eulersym.model.contact.Surface (from surface(...))")
    return _contact_point(s)


@dataclass(frozen=True)
class Contact:
    """A contact with the plane: the surface, the mode and its friction.

    Parameters
    ----------
    surface : Surface
    mode : {"rolling", "sliding"}
    friction : {"none", "viscous", "coulomb"}
        Sliding only (a rolling contact takes whatever friction force the constraint needs).
    mu : number or sympy.Expr
        The friction coefficient: N s/m for ``viscous``, dimensionless for ``coulomb``.
    width : number or sympy.Expr
        Coulomb's regularisation width ``ε`` (m/s).
    rolling_resistance, spin_friction : number or sympy.Expr
        ``c_r``, ``c_s`` (N m s) of the torques ``−c_r (ω − (ω·Γ) Γ)`` and ``−c_s (ω·Γ) Γ``.

    Raises
    ------
    eulersym.errors.InvalidInput
        An unknown mode or friction law, a coefficient a law does not take or lacks, a negative coefficient.

    Examples
    --------
    >>> Contact(surface("sphere", radius=1), friction="viscous", mu=0.5)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: contact.friction='viscous' is not valid: expected no friction law for a rolling contact (no slip: the constraint force takes its place); mode = "sliding" for a friction law
    >>> Contact(surface("sphere", radius=1), mode="sliding", friction="dry")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: contact.friction='dry' is not valid: expected one of 'none', 'viscous', 'coulomb'
    """

    surface: Surface
    mode: str = "rolling"
    friction: str = "none"
    mu: object = 0
    width: object = None
    rolling_resistance: object = 0
    spin_friction: object = 0

    def __post_init__(self):
        if not isinstance(self.surface, Surface):
            raise InvalidInput("contact.surface", self.surface, "a Surface (eulersym.model.contact.surface(...))")
        choice("contact.mode", self.mode, MODES)
        choice("contact.friction", self.friction, FRICTION_LAWS)
        if self.mode == "rolling" and self.friction != "none":
            raise InvalidInput("contact.friction", self.friction, "no friction law for a rolling contact (no slip: "
                               "the constraint force takes its place); mode = \"sliding\" for a friction law")
        set_ = object.__setattr__
        if self.friction == "none":
            if self.mu not in (0, None) or self.width is not None:
                key = "contact.mu" if self.mu not in (0, None) else "contact.width"
                raise InvalidInput(key, self.mu if key == "contact.mu" else self.width,
                                   "no friction coefficient without a friction law (friction = \"viscous\" or "
                                   "\"coulomb\")")
            set_(self, "mu", sp.Integer(0))
        else:
            if self.mu is None:
                raise InvalidInput("contact.mu", None, f"the {self.friction} friction coefficient (it is missing)")
            set_(self, "mu", _non_negative("contact.mu", self.mu))
            if self.friction == "coulomb":
                if self.width is None:
                    raise InvalidInput("contact.width", None, "the width ε (m/s) of the regularised Coulomb law "
                                       "F = −μ N u/√(|u|² + ε²) (it is missing)")
                set_(self, "width", _positive("contact.width", self.width))
            elif self.width is not None:
                raise InvalidInput("contact.width", self.width, "no width for viscous friction (only for "
                                   "\"coulomb\")")
        set_(self, "rolling_resistance", _non_negative("contact.rolling_resistance", self.rolling_resistance))
        set_(self, "spin_friction", _non_negative("contact.spin_friction", self.spin_friction))

    def expressions(self) -> list:
        """Every dimension and coefficient (for checks of their symbols)."""
        out = [*self.surface.dimensions, *self.surface.centre, *self.surface.axes, self.mu,
               self.rolling_resistance, self.spin_friction]
        return out + ([self.width] if self.width is not None else [])
