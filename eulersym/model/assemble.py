"""Assemble a model's mechanics from its validated sections: exact numbers, parsed expressions, one body.

:func:`assemble` takes the normalised data of a :class:`~eulersym.model.spec.Model` (numbers as floats,
expressions as strings) and builds the :class:`~eulersym.model.mechanics.Mechanics`:

- numbers become exact rationals as written (``0.1`` → ``1/10``), strings are read by
  :func:`eulersym.model.expressions.parse` in the parameters (real symbols);
- a shape's tensor comes from :mod:`eulersym.inertia` (the integral), its centre of mass from the region's
  :func:`~eulersym.inertia.center_of_mass` measured from the shape's origin;
- parts: each part's tensor about its own centre of mass, turned into the model frame (``R I Rᵀ``,
  ``v_model = R v_part``), and moved to the reference point by :func:`~eulersym.inertia.parallel_axis` — the
  pivot (the model frame's origin) for a pivoted body, the total centre of mass for a free one;
- the torques: ``body`` plus ``to_body(space)``; gravity is *not* among them (the derivations take it from M, g and
  the centre of mass).

Physical checks that need the expressions (a tensor that is not symmetric, a mass or a tensor that is not
positive at the parameters' defaults, a pivot whose given centre of mass contradicts the shape's) are refused
here, naming the TOML key, before any derivation.

Examples
--------
>>> a = assemble({"name": "cone", "parameters": [], "rotor": None,
...               "body": {"shape": "cone", "mass": 1.0, "dimensions": {"R": 1.0, "h": 4.0}, "origin": "apex"},
...               "pivot": {"centre_of_mass": None, "l": False, "g": 9.81},
...               "torque": {"body": None, "space": None, "potential": None}})
>>> a.centre_of_mass.T
Matrix([[0, 0, 3]])
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import sympy as sp

from eulersym import inertia
from eulersym.errors import InvalidInput
from eulersym.validation import inertia_tensor
from eulersym.model.expressions import namespace, parse, to_body
from eulersym.model.mechanics import Mechanics
from eulersym.rotation import euler_matrix, from_axis_angle, from_quaternion, to_quaternion

__all__ = ["Assembly", "assemble", "shape_centre", "shape_tensor"]

_ZERO = sp.ImmutableMatrix([0, 0, 0])


@dataclass(frozen=True)
class Assembly:
    """What :func:`assemble` derives: the mechanics, and the model's own view of mass and centre of mass.

    Attributes
    ----------
    mechanics : Mechanics
    mass : sympy.Expr or None
        None for a free body given by moments or a tensor without a mass (``mechanics.mass`` is then 0: the mass
        plays no part in a free body's rotation).
    centre_of_mass : 3×1 ImmutableMatrix
        From the pivot; for a free body, in the model frame (where the shape or the parts put it).
    """

    mechanics: Mechanics
    mass: object
    centre_of_mass: sp.ImmutableMatrix


def _exact(x: float) -> sp.Rational:
    """The float as written: ``0.1`` → 1/10 (its shortest repr, read exactly)."""
    return sp.Rational(repr(float(x)))


class _Values:
    """Numbers and expressions of one model → SymPy, with checks at the parameters' defaults."""

    def __init__(self, parameters: list):
        self.symbols = {name: sp.Symbol(name, real=True) for name, _ in parameters}
        self.defaults = {self.symbols[name]: _exact(value) for name, value in parameters}
        self.constants = namespace(self.symbols, state=False, time=False)

    def scalar(self, key: str, value):
        if isinstance(value, str):
            return parse(value, self.constants, argument=key, shape="scalar")
        return _exact(value)

    def vector(self, key: str, value, ns=None) -> sp.ImmutableMatrix:
        ns = self.constants if ns is None else ns
        if isinstance(value, str):
            return parse(value, ns, argument=key, shape="vector")
        return sp.ImmutableMatrix([parse(v, ns, argument=f"{key}[{i}]", shape="scalar") if isinstance(v, str)
                                   else _exact(v) for i, v in enumerate(value)])

    def at_defaults(self, expr) -> complex:
        try:
            return complex(sp.sympify(expr).xreplace(self.defaults).evalf(30))
        except (TypeError, ValueError):
            return complex("nan")

    def positive(self, key: str, raw, expr, what: str = "a positive number") -> None:
        if isinstance(raw, str):
            v = self.at_defaults(expr)
            if not (np.isfinite(v.real) and abs(v.imag) <= 1e-12 * max(1.0, abs(v.real)) and v.real > 0):
                raise InvalidInput(key, raw, f"{what} (at the parameters' defaults it is {_show(v)})")

    def body_tensor(self, key: str, raw, I) -> None:
        """Symmetric (exactly), positive definite and obeying the triangle inequality (at the defaults)."""
        for i in range(3):
            for j in range(i + 1, 3):
                if sp.expand(I[i, j] - I[j, i]) != 0:
                    raise InvalidInput(key, raw, f"a symmetric tensor: {key}[{i}][{j}] = {I[i, j]} but "
                                       f"{key}[{j}][{i}] = {I[j, i]}")
        if not I.free_symbols:
            values = [[complex(I[i, j].evalf(30)) for j in range(3)] for i in range(3)]
        elif I.free_symbols <= set(self.defaults):
            values = [[self.at_defaults(I[i, j]) for j in range(3)] for i in range(3)]
        else:
            return
        arr = np.array(values)
        if not np.all(np.isfinite(arr)) or np.any(np.abs(arr.imag) > 1e-12 * max(1.0, np.max(np.abs(arr)))):
            raise InvalidInput(key, raw, "a real, finite tensor at the parameters' defaults")
        arr = arr.real
        if raw is None:  # a derived tensor: show it
            raw = [[float(f"{x:.6g}") for x in row] for row in arr]
        try:
            inertia_tensor(key, (arr + arr.T) / 2, shown=raw)
        except InvalidInput as exc:
            raise InvalidInput(key, raw, exc.expected + " at the parameters' defaults" + (
                "; a thin rod, or point masses on one line, have no moment about that line, and the equations of "
                "motion need all three" if "positive-definite" in exc.expected else "")) from None


def _show(v: complex) -> str:
    return f"{v.real:.6g}" if v.imag == 0 else f"{v:.6g}"


# ------------------------------------------------------------------------------------------------------------
# Shapes: tensors (eulersym.inertia) and centres of mass from the shape's origin

_PLACEHOLDERS = tuple(sp.Dummy(f"d{i}", positive=True) for i in range(3))


def _region(shape: str, origin: str, dims: tuple) -> inertia.Region:
    """The shape's region placed as :mod:`eulersym.inertia` places it for ``origin``."""
    if shape in ("cube", "cuboid"):
        a, b, c = dims * 3 if shape == "cube" else dims
        if origin == "corner":
            return inertia.Region.box((0, a), (0, b), (0, c))
        return inertia.Region.box((-a / 2, a / 2), (-b / 2, b / 2), (-c / 2, c / 2))
    if shape == "sphere":
        return inertia.Region.ball(dims[0])
    if shape == "ellipsoid":
        return inertia.Region.ellipsoid(*dims)
    if shape == "cylinder":
        region = inertia.Region.cylinder(*dims)
        return region.translated((0, 0, dims[1] / 2)) if origin == "base" else region
    if shape == "cone":
        return inertia.Region.cone(*dims)  # apex at the origin
    region = inertia.Region.segment(dims[0])  # rod
    return region.translated((0, 0, dims[0] / 2)) if origin == "end" else region


@functools.lru_cache(maxsize=64)
def _centre_placeholder(shape: str, origin: str, n: int) -> sp.ImmutableMatrix:
    if shape == "point" or origin == "center":
        return _ZERO  # a "center" origin is, by definition, the centre of mass
    return sp.ImmutableMatrix(inertia.center_of_mass(1, _region(shape, origin, _PLACEHOLDERS[:n])))


def shape_centre(shape: str, origin: str, dims) -> sp.ImmutableMatrix:
    """The centre of mass of a uniform shape, from its origin, in its own axes (derived from the region).

    Examples
    --------
    >>> import sympy as sp
    >>> h = sp.Symbol("h", positive=True)
    >>> shape_centre("cone", "apex", (1, h)).T
    Matrix([[0, 0, 3*h/4]])
    """
    dims = tuple(dims)
    centre = _centre_placeholder(shape, origin, len(dims))
    return sp.ImmutableMatrix(centre.xreplace(dict(zip(_PLACEHOLDERS, dims))))


_BUILDERS = {
    "cube": inertia.cube, "cuboid": inertia.cuboid, "sphere": inertia.sphere, "cylinder": inertia.cylinder,
    "cone": inertia.cone, "ellipsoid": inertia.ellipsoid, "rod": inertia.rod,
}
_NO_ORIGIN = ("sphere", "ellipsoid")


def shape_tensor(shape: str, origin: str, mass, dims) -> sp.ImmutableMatrix:
    """The tensor of a uniform shape about its ``origin`` (:mod:`eulersym.inertia`), in its own axes.

    Examples
    --------
    >>> shape_tensor("rod", "end", 3, (2,)).diagonal()
    Matrix([[4, 4, 0]])
    """
    if shape == "point":
        return sp.ImmutableMatrix(sp.zeros(3, 3))
    builder = _BUILDERS[shape]
    if shape in _NO_ORIGIN:
        return sp.ImmutableMatrix(builder(mass, *dims))
    return sp.ImmutableMatrix(builder(mass, *dims, origin=origin))


# ------------------------------------------------------------------------------------------------------------
# Parts


def _rotation(values: _Values, key: str, orientation) -> sp.Matrix | None:
    """R with ``v_model = R v_part`` (the active turn of the part), or None for an unturned part."""
    if orientation is None:
        return None
    if "quaternion" in orientation:
        q = [values.scalar(f"{key}.quaternion[{i}]", c) for i, c in enumerate(orientation["quaternion"])]
        norm2 = sp.expand(sum(c**2 for c in q))
        if norm2 == 0:
            raise InvalidInput(f"{key}.quaternion", orientation["quaternion"], "a non-zero quaternion")
        if norm2 != 1:
            q = [c / sp.sqrt(norm2) for c in q]
        return from_quaternion(q).T
    if "euler" in orientation:
        angles = values.vector(f"{key}.euler", orientation["euler"])
        return euler_matrix(*angles, convention=orientation["convention"]).T
    axis = values.vector(f"{key}.axis", orientation["axis"])
    if all(c == 0 for c in axis):
        raise InvalidInput(f"{key}.axis", orientation["axis"], "a non-zero axis")
    return from_axis_angle(list(axis), values.scalar(f"{key}.angle", orientation["angle"])).T


def _rational_rotation(R: sp.Matrix) -> sp.Matrix:
    """An exactly orthogonal rational matrix within round-off of the numeric rotation ``R``.

    A turn by numeric angles carries transcendental constants (cos(3/10), ...) into every tensor entry, and exact
    proofs over those do not finish. The rotation of the rational quaternion q nearest ``R`` in double precision,
    ``q ⊗ (0, v) ⊗ q* / |q|²``, is exactly orthogonal with rational entries, so a symmetric part stays exactly
    symmetric and every later derivation stays in the rationals; it differs from ``R`` by round-off (the angles
    were doubles to begin with).
    """
    q = [sp.Rational(float(c)) for c in to_quaternion(np.array(R.T.evalf(30).tolist(), dtype=float))]
    return from_quaternion(q).T / sum(c**2 for c in q)


def _part(values: _Values, key: str, part: dict):
    """(mass, tensor about its centre of mass in the model frame, position of its centre of mass)."""
    m = values.scalar(f"{key}.mass", part["mass"])
    values.positive(f"{key}.mass", part["mass"], m, "a positive mass")
    if "shape" in part:
        dims = tuple(values.scalar(f"{key}.{k}", v) for k, v in part["dimensions"].items())
        for (k, raw), d in zip(part["dimensions"].items(), dims):
            values.positive(f"{key}.{k}", raw, d, "a positive length")
        I_cm = shape_tensor(part["shape"], "center", m, dims)
        offset = shape_centre(part["shape"], part["origin"], dims)
    elif "moments" in part:
        moments = values.vector(f"{key}.moments", part["moments"])
        I_cm = sp.ImmutableMatrix(sp.diag(*moments))
        values.body_tensor(f"{key}.moments", part["moments"], I_cm)
        offset = _ZERO
    else:
        I_cm = sp.ImmutableMatrix([list(values.vector(f"{key}.tensor[{i}]", row)) for i, row in
                                   enumerate(part["tensor"])])
        values.body_tensor(f"{key}.tensor", part["tensor"], I_cm)
        offset = _ZERO
    R = _rotation(values, f"{key}.orientation", part.get("orientation"))
    position = values.vector(f"{key}.position", part.get("position", [0.0, 0.0, 0.0]))
    if R is None:
        return m, I_cm, sp.ImmutableMatrix(position + offset)
    R = sp.Matrix(R)
    if not R.free_symbols and not all(x.is_Rational for x in R):
        R = _rational_rotation(R)
    turned = (R * I_cm * R.T).applyfunc(sp.expand)
    return m, sp.ImmutableMatrix(turned), sp.ImmutableMatrix((position + R * offset).applyfunc(sp.expand))


def _combine(parts: list, pivoted: bool):
    """Total mass, centre of mass and tensor about the reference point (origin if pivoted, else the centre)."""
    M = sp.expand(sum(m for m, _, _ in parts))
    centre = sp.ImmutableMatrix((sum((m * p for m, _, p in parts), sp.zeros(3, 1)) / M).applyfunc(sp.simplify))
    reference = _ZERO if pivoted else centre
    total = sp.zeros(3, 3)
    for m, I_cm, p in parts:
        total += inertia.parallel_axis(I_cm, m, list(reference - p))
    return M, centre, sp.ImmutableMatrix(total.applyfunc(sp.expand))


# ------------------------------------------------------------------------------------------------------------
# The model


def assemble(data: dict) -> Assembly:
    """Build the mechanics of a model from its normalised data (:meth:`Model.to_dict`).

    See the module docstring; raises :class:`~eulersym.errors.InvalidInput` naming the TOML key.
    """
    values = _Values(data["parameters"])
    body, pivot = data["body"], data["pivot"]
    pivoted = pivot is not None
    given_mass = None
    if "parts" in body:
        parts = [_part(values, f"body.parts[{i}]", part) for i, part in enumerate(body["parts"])]
        mass, centre, I = _combine(parts, pivoted)
        derived_centre = True
    elif "shape" in body:
        m, I_cm, offset = _part(values, "body", {**body, "position": [0.0, 0.0, 0.0], "orientation": None})
        mass, centre = m, offset
        dims = tuple(values.scalar(f"body.{k}", v) for k, v in body["dimensions"].items())
        I = shape_tensor(body["shape"], body["origin"], m, dims) if pivoted else I_cm
        derived_centre = True
    else:
        kind = "moments" if "moments" in body else "tensor"
        if kind == "moments":
            I = sp.ImmutableMatrix(sp.diag(*values.vector("body.moments", body["moments"])))
        else:
            I = sp.ImmutableMatrix([list(values.vector(f"body.tensor[{i}]", row))
                                    for i, row in enumerate(body["tensor"])])
        values.body_tensor(f"body.{kind}", body[kind], I)
        if body.get("mass") is not None:
            given_mass = values.scalar("body.mass", body["mass"])
            values.positive("body.mass", body["mass"], given_mass, "a positive mass")
        mass = given_mass
        centre = _ZERO
        derived_centre = False
    if derived_centre:
        values.body_tensor("body", None, I)
    gravity = sp.Integer(0)
    if pivoted:
        key = "pivot.l" if pivot.get("l") else "pivot.centre_of_mass"
        given = pivot["centre_of_mass"]
        if given is not None:
            stated = values.vector(key, given)
            if derived_centre:
                if any(sp.expand(c) != 0 for c in (stated - centre)):
                    raw = given[2] if pivot.get("l") else given
                    raise InvalidInput(key, raw, f"the centre of mass the body derives, {list(centre)} from the "
                                       "pivot (a shape's or the parts' centre of mass is derived: leave "
                                       f"{key} out)")
            else:
                centre = stated
        gravity = values.scalar("pivot.g", pivot["g"])
        if isinstance(pivot["g"], str):
            v = values.at_defaults(gravity)
            if not (np.isfinite(v.real) and v.real >= 0 and v.imag == 0):
                raise InvalidInput("pivot.g", pivot["g"], f"g >= 0 (at the parameters' defaults it is {_show(v)})")
    full = namespace(values.symbols, inertia=I)
    torque = sp.ImmutableMatrix(_ZERO)
    if data["torque"]["body"] is not None:
        torque = torque + values.vector("torque.body", data["torque"]["body"], full)
    if data["torque"]["space"] is not None:
        torque = torque + to_body(values.vector("torque.space", data["torque"]["space"], full))
    potential = sp.Integer(0)
    if data["torque"]["potential"] is not None:
        raw = data["torque"]["potential"]
        potential = parse(raw, namespace(values.symbols, inertia=I, omega=False), argument="torque.potential",
                          shape="scalar") if isinstance(raw, str) else _exact(raw)
    rotor = _ZERO if data["rotor"] is None else values.vector("rotor.h", data["rotor"])
    mech = Mechanics(
        name=data["name"],
        inertia=sp.ImmutableMatrix(I),
        mass=mass if mass is not None else sp.Integer(0),
        centre_of_mass=sp.ImmutableMatrix(centre) if pivoted else _ZERO,
        gravity=gravity,
        pivoted=pivoted,
        torque=sp.ImmutableMatrix(torque),
        rotor=sp.ImmutableMatrix(rotor),
        potential=potential,
        parameters=tuple((values.symbols[name], float(value)) for name, value in data["parameters"]),
    )
    return Assembly(mechanics=mech, mass=mass, centre_of_mass=sp.ImmutableMatrix(centre))
