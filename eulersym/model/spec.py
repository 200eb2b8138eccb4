"""A user's own rigid body, as written: :class:`Model` validates a model's sections and builds its mechanics.

A model is the physics part of a scene (a scene file is a model file plus ``[initial]``, ``[time]``,
``[output]``)::

    name = "gyroscope"
    [parameters]                  # name = default; every name may be swept in a scene
    m = 0.2
    [body]                        # exactly one of: moments | tensor | shape | parts
    moments = [1.2e-3, 1.2e-3, 4e-4]        # principal moments; about the pivot for a pivoted body
    # tensor = [[...], [...], [...]]        # a full tensor in the model frame
    # shape = "cone", mass = 0.5, R = 0.05, h = 0.2, origin = "apex"   (or dimensions = {R = .., h = ..})
    # [[body.parts]]                        # each: a shape with mass and dimensions, or moments/tensor + mass,
    # shape = "cylinder"  mass = 1.0  R = 0.1  h = 0.02
    # position = [0, 0, 0.1]                # where the part's origin sits (from the pivot, for a pivoted body)
    # orientation = {euler = [0, 1.5708, 0], convention = "zxz"}   # or {quaternion = [...]}, {axis, angle};
    #                                       # or on the part: euler = [...] (+ convention), quaternion = [...]
    mass = 0.5
    [pivot]                       # a fixed point; without it the body is free
    centre_of_mass = [0, 0, 0.04] # body frame, from the pivot (or l = 0.04 for [0, 0, l]); g = 9.81 by default
    [torque]                      # every torque other than gravity's, body and/or space components
    body = "-c*omega"             # a 3-vector expression, or three component expressions
    space = ["0", "0", "N0"]
    potential = "..."             # a scalar potential energy; its torque is derived
    [rotor]
    h = [0, 0, "h0"]              # constant angular momentum of an internal rotor, body components

Any number may be written as an expression of the parameters (``g = "g"``, ``centre_of_mass = ["a", 0, 0]``).
Validation of the structure, of the numbers and of the names in every expression is SymPy-free and happens at
construction; messages name the TOML key (``body.parts[1].mass``). The expressions are parsed (whitelist parser,
never ``eval``) and the body assembled when :attr:`Model.mechanics` is first used.

Shapes and their dimensions (:mod:`eulersym.inertia`): ``cube`` (a), ``cuboid`` (a, b, c), ``sphere`` (R),
``cylinder`` (R, h), ``cone`` (R, h), ``ellipsoid`` (a, b, c), ``rod`` (L), ``point`` (none: a point mass). A
shape's *origin* (``center``; cube/cuboid ``corner``; cylinder ``base``; cone ``apex`` (the default); rod
``end``) is the pivot for a pivoted shape, and the point placed at ``position`` for a part.

Orientation of a part (``orientation = {...}``, or the same keys written on the part; a 4-list is a quaternion, a
3-list zxz Euler angles): its axes are turned relative to the model frame as a body's axes relative to space by the
same attitude — ``v_model = R v_part`` with ``R = R(q)`` for ``quaternion = [q0, q1, q2, q3]`` (scalar first),
``R = Aᵀ`` with ``A = euler_matrix(φ, θ, ψ, convention)`` for ``euler = [φ, θ, ψ]`` (radians), and the turn by
``angle`` about ``axis`` for ``{axis, angle}``; the part's tensor becomes ``R I Rᵀ``.

Examples
--------
>>> model = Model.from_dict({
...     "parameters": {"a": 0.1},
...     "body": {"moments": [2, 2, 1], "mass": 1.0},
...     "pivot": {"centre_of_mass": ["a", 0, 0], "g": 9.81}})
>>> model.parameters, model.pivoted
({'a': 0.1}, True)
>>> model.centre_of_mass.T
Matrix([[a, 0, 0]])
>>> Model.from_dict({"body": {"moments": [1, 2, 3]}, "pivot": {"l": 0.1, "g": "gg"}})
Traceback (most recent call last):
...
eulersym.errors.InvalidInput: pivot.g='gg' is not valid: expected an expression of the parameters (none) and pi: 'gg' is unknown
"""

from __future__ import annotations

import math
import numbers
import tomllib
from functools import cached_property
from typing import Any, Mapping

from eulersym.attitude import SEQUENCES
from eulersym.errors import InvalidInput
from eulersym.validation import GENERATED_CODE_NAMES
from eulersym.model import names as N
from eulersym.shapes import SHAPE_ORIGINS, SHAPES

__all__ = ["Model", "MODEL_SECTIONS", "OPTIONAL_SECTIONS", "SCENE_KEYS", "SHAPES", "SHAPE_ORIGINS", "DEFAULT_G"]

#: The sections of a model (``frame`` and ``quantities`` only when given: :data:`OPTIONAL_SECTIONS`).
MODEL_SECTIONS = ("parameters", "body", "pivot", "torque", "rotor", "frame", "quantities", "contact")
#: Sections kept in the model's data (and digest) only when given, so that models without them keep their digest.
OPTIONAL_SECTIONS = ("frame", "quantities", "contact")
#: Top-level keys of a scene file that are not the model's (ignored by :meth:`Model.from_dict`), besides
#: any key that starts with ``sweep``.
SCENE_KEYS = ("description", "initial", "time", "output")
#: Gravity when a ``[pivot]`` gives no ``g``.
DEFAULT_G = 9.81
#: Euler / Tait–Bryan sequences an orientation may name (as :func:`eulersym.rotation.euler_matrix`).
CONVENTIONS = SEQUENCES
#: Limits that keep a model's work bounded.
MAX_PARTS = 256
MAX_PARAMETERS = 256
MAX_EXPRESSION = 2000
MAX_FILE_BYTES = 1 << 20

_BODY_KINDS = ("moments", "tensor", "shape", "parts")
_ORIENTATIONS = ("quaternion", "euler", "axis")
_ORIENTATION_KEYS = ("quaternion", "euler", "convention", "axis", "angle")


def _did_you_mean(key: str, valid) -> str:
    import difflib  # for a message only: a run that is not refused never loads it

    valid = sorted(valid)
    close = difflib.get_close_matches(str(key), valid, n=1, cutoff=0.5)
    return "one of " + ", ".join(repr(v) for v in valid) + (f" (did you mean {close[0]!r}?)" if close else "")


def _sequence(value: Any) -> list | None:
    """``value`` as a list when it is a list, tuple or array (not a string or a table), else None."""
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__") or not hasattr(value, "__iter__"):
        return None
    try:
        return list(value)
    except TypeError:
        return None


def _table(key: str, value: Any, valid) -> dict:
    if not isinstance(value, Mapping):
        raise InvalidInput(key, value, f"a table with keys among {', '.join(valid)}")
    for sub in value:
        if sub not in valid:
            raise InvalidInput(f"{key}.{sub}" if key else str(sub), value[sub],
                               f"a key of [{key}]: " + _did_you_mean(sub, valid) if key else
                               "a key: " + _did_you_mean(sub, valid))
    return dict(value)


class _Checker:
    """Checks numbers, vectors and the names in expressions, SymPy-free, against the model's parameters."""

    def __init__(self, parameters: Mapping[str, float]):
        self.parameters = tuple(parameters)

    # -- names
    def names(self, key: str, text: str, context: str) -> None:
        """Every name in ``text`` must mean something in ``context`` ("number", "rotor", "torque",
        "potential")."""
        allowed = {*self.parameters, *N.FUNCTION_NAMES, "pi"}
        if context in ("torque", "potential"):
            allowed |= {N.TIME, *N.GAMMA_NAMES, *N.Q_NAMES, "gamma", N.INERTIA}
        if context == "path":
            allowed |= {N.TIME}
        if context == "torque":
            allowed |= {*N.OMEGA_NAMES, "omega"}
        for name in N.names_in(text):
            if name in allowed:
                continue
            params = ", ".join(self.parameters) or "none"
            if context in ("number", "rotor", "frame") and (name in N.RESERVED):
                what = {"rotor": "a constant rotor momentum h", "frame": "a constant rate: the frame turns uniformly, "
                        "so Ω is"}.get(context, "a constant")
                raise InvalidInput(key, text, f"{what}: an expression of the parameters ({params}) and pi; "
                                   f"{name!r} varies with the motion")
            if context == "path":
                raise InvalidInput(key, text, f"a position of the pivot in space: an expression of t alone and the "
                                   f"parameters ({params}); {name!r} " + ("varies with the motion" if name in
                                   N.RESERVED else "is unknown"))
            if context == "potential" and name in (*N.OMEGA_NAMES, "omega"):
                raise InvalidInput(key, text, "a potential energy of the attitude (gamma, q0..q3), t and the "
                                   f"parameters ({params}); {name!r} is an angular velocity")
            what = {"number": f"an expression of the parameters ({params}) and pi",
                    "rotor": f"an expression of the parameters ({params}) and pi",
                    "frame": f"an expression of the parameters ({params}) and pi",
                    "torque": f"an expression of t, omega, omega1..3, gamma, gamma1..3, q0..q3, inertia, pi, "
                              f"the parameters ({params}) and the functions",
                    "potential": f"an expression of t, gamma, gamma1..3, q0..q3, inertia, pi, the parameters "
                                 f"({params}) and the functions"}[context]
            import difflib

            hint = difflib.get_close_matches(name, sorted(allowed), n=1, cutoff=0.6)
            raise InvalidInput(key, text, f"{what}: {name!r} is unknown"
                               + (f" (did you mean {hint[0]!r}?)" if hint else ""))

    def text(self, key: str, value: str, context: str) -> str:
        text = value.strip()
        if not text:
            raise InvalidInput(key, value, "a non-empty expression")
        if len(text) > MAX_EXPRESSION:
            raise InvalidInput(key, value[:40] + "...", f"an expression of at most {MAX_EXPRESSION} characters")
        self.names(key, text, context)
        return text

    # -- values
    def number(self, key: str, value: Any, *, context: str = "number", sign: str | None = None):
        """A float, or an expression string; ``sign`` ("positive", "nonnegative") is checked on numbers."""
        if isinstance(value, str):
            return self.text(key, value, context)
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            if _sequence(value) is not None:
                raise InvalidInput(key, value, "a number or an expression string, not a list (a vector where "
                                   "a scalar belongs)")
            raise InvalidInput(key, value, "a number or an expression string of the parameters")
        try:
            out = float(value)
        except OverflowError:
            out = math.inf
        if not math.isfinite(out):
            raise InvalidInput(key, value, "a finite number")
        if sign == "positive" and out <= 0:
            raise InvalidInput(key, value, "a positive number")
        if sign == "nonnegative" and out < 0:
            raise InvalidInput(key, value, "a number >= 0")
        return out

    def vector(self, key: str, value: Any, n: int = 3, *, context: str = "number", expression: bool = False,
               sign: str | None = None):
        """``n`` numbers or expressions; with ``expression``, also one string holding a vector expression."""
        if isinstance(value, str):
            if expression:
                return self.text(key, value, context)
            raise InvalidInput(key, value, f"{n} components [x, y, z] (numbers or expression strings), not one "
                               "string" if n == 3 else f"{n} components")
        items = _sequence(value)
        if items is None:
            raise InvalidInput(key, value, f"a list of {n} components" + (" (a scalar where a vector belongs)"
                                                                          if isinstance(value, numbers.Real)
                                                                          else ""))
        if len(items) != n:
            raise InvalidInput(key, value, f"a list of {n} components, not {len(items)}")
        return [self.number(f"{key}[{i}]", v, context=context, sign=sign) for i, v in enumerate(items)]


# ------------------------------------------------------------------------------------------------------------
# Sections


def _parameters(value: Any) -> dict:
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise InvalidInput("parameters", value, "a table of name = default value")
    if len(value) > MAX_PARAMETERS:
        raise InvalidInput("parameters", f"{len(value)} parameters", f"at most {MAX_PARAMETERS} parameters")
    out = {}
    for name, default in value.items():
        key = f"parameters.{name}"
        if not isinstance(name, str) or not name.isascii() or not name.isidentifier() or name.startswith("_"):
            raise InvalidInput(key, name, "a name of ASCII letters, digits and _ that starts with a letter")
        if name in N.RESERVED:
            raise InvalidInput(key, name, "a name that is not one of the model's own names (t, omega, omega1..3, "
                               "gamma, gamma1..3, q0..q3, inertia, pi, the functions)")
        if name in N.FORBIDDEN or name in GENERATED_CODE_NAMES:
            raise InvalidInput(key, name, "a name that is not a Python keyword or built-in, a name of math, or a "
                               "name the generated kernel uses (np, body, rhs_flat, STATE, ...): the kernel would "
                               "call it")
        if isinstance(default, bool) or not isinstance(default, numbers.Real):
            raise InvalidInput(key, default, "a default value: a finite number")
        try:
            number = float(default)
        except OverflowError:
            number = math.inf
        if not math.isfinite(number):
            raise InvalidInput(key, default, "a default value: a finite number")
        out[name] = number
    return out


def _shape_keys(key: str, table: dict, shape_key: str = "shape") -> dict:
    """shape, dimensions (direct keys or a ``dimensions`` table) and origin of a shape table."""
    shape = table.get(shape_key)
    if not isinstance(shape, str) or shape not in SHAPES:
        raise InvalidInput(f"{key}.shape", shape, "a shape: " + _did_you_mean(str(shape), SHAPES))
    wanted = SHAPES[shape]
    direct = {k: table[k] for k in ("a", "b", "c", "R", "h", "L") if k in table}
    if "dimensions" in table:
        if direct:
            raise InvalidInput(f"{key}.{next(iter(direct))}", next(iter(direct.values())),
                               f"the {shape}'s dimensions either as keys of the body or in {key}.dimensions, "
                               "not both")
        dims = _table(f"{key}.dimensions", table["dimensions"], wanted or ("(none)",))
        where = f"{key}.dimensions"
    else:
        dims, where = direct, key
    for k in dims:
        if k not in wanted:
            raise InvalidInput(f"{where}.{k}", dims[k], f"a dimension of a {shape}: "
                               + (_did_you_mean(k, wanted) if wanted else "none (a point has no dimensions)"))
    for k in wanted:
        if k not in dims:
            raise InvalidInput(f"{where}.{k}", None, f"the {shape}'s dimension {k} (a {shape} needs "
                               f"{', '.join(wanted)})")
    origin = table.get("origin")
    if shape in SHAPE_ORIGINS:
        origin = SHAPE_ORIGINS[shape][0] if origin is None else origin
        if origin not in SHAPE_ORIGINS[shape]:
            raise InvalidInput(f"{key}.origin", origin, f"an origin of a {shape}: "
                               + _did_you_mean(str(origin), SHAPE_ORIGINS[shape]))
    elif origin not in (None, "center"):
        raise InvalidInput(f"{key}.origin", origin, f"no origin for a {shape} but 'center' (its centre is its "
                           "origin)")
    else:
        origin = "center"
    return {"shape": shape, "dimensions": {k: dims[k] for k in wanted}, "origin": origin, "where": where}


def _orientation(key: str, value: Any, check: _Checker):
    if value is None:
        return None
    if _sequence(value) is not None:
        value = _sequence(value)
        if len(value) == 3:
            return {"euler": check.vector(key, value), "convention": "zxz"}
        if len(value) != 4:
            raise InvalidInput(key, value, "a quaternion [q0, q1, q2, q3] (scalar first), Euler angles "
                               "[phi, theta, psi] (zxz, radians), or a table {euler, convention}, {quaternion}, "
                               "{axis, angle}")
        return {"quaternion": _quaternion(key, value, check)}
    table = _table(key, value, ("quaternion", "euler", "convention", "axis", "angle"))
    given = [k for k in _ORIENTATIONS if k in table]
    if len(given) != 1:
        raise InvalidInput(key, value, "one of {quaternion = [q0, q1, q2, q3]}, {euler = [phi, theta, psi], "
                           "convention = 'zxz'} or {axis = [x, y, z], angle = a}")
    kind = given[0]
    extra = {"quaternion": (), "euler": ("convention",), "axis": ("angle",)}[kind]
    for k in table:
        if k != kind and k not in extra:
            raise InvalidInput(f"{key}.{k}", table[k], f"no {k} with {kind}")
    if kind == "quaternion":
        return {"quaternion": _quaternion(f"{key}.quaternion", table["quaternion"], check)}
    if kind == "euler":
        convention = table.get("convention", "zxz")
        if not isinstance(convention, str) or convention not in CONVENTIONS:
            raise InvalidInput(f"{key}.convention", convention, "a sequence: "
                               + _did_you_mean(str(convention), CONVENTIONS))
        return {"euler": check.vector(f"{key}.euler", table["euler"]), "convention": convention}
    if "angle" not in table:
        raise InvalidInput(f"{key}.angle", None, "the angle of the turn about the axis (radians)")
    axis = check.vector(f"{key}.axis", table["axis"])
    if all(isinstance(c, float) for c in axis) and not any(axis):
        raise InvalidInput(f"{key}.axis", table["axis"], "a non-zero axis")
    return {"axis": axis, "angle": check.number(f"{key}.angle", table["angle"])}


def _quaternion(key: str, value: Any, check: _Checker) -> list:
    q = check.vector(key, value, 4)
    if all(isinstance(c, float) for c in q) and not any(q):
        raise InvalidInput(key, value, "a non-zero quaternion [q0, q1, q2, q3], scalar first")
    return q


def _moments(key: str, value: Any, check: _Checker) -> list:
    moments = check.vector(key, value)
    numbers = [m for m in moments if isinstance(m, float)]
    if len(numbers) == 3:
        from eulersym.validation import moments as valid_moments

        valid_moments(key, moments, shown=value)
    elif any(m <= 0 for m in numbers):
        raise InvalidInput(key, value, "positive principal moments (an expression is checked at the parameters' "
                           "values)")
    return moments


def _tensor(key: str, value: Any, check: _Checker) -> list:
    rows = _sequence(value)
    if rows is None or len(rows) != 3:
        raise InvalidInput(key, value, "a 3×3 symmetric inertia tensor [[I11, I12, I13], [I21, ...], [...]]")
    rows = [check.vector(f"{key}[{i}]", row) for i, row in enumerate(rows)]
    for i in range(3):
        for j in range(i + 1, 3):
            a, b = rows[i][j], rows[j][i]
            if isinstance(a, float) and isinstance(b, float) and a != b and \
                    abs(a - b) > 1e-12 * max(abs(a), abs(b)):
                raise InvalidInput(key, value, f"a symmetric tensor: {key}[{i}][{j}] = {a:g} but "
                                   f"{key}[{j}][{i}] = {b:g}")
    # expressions are compared exactly when the mechanics is built
    if all(isinstance(x, float) for row in rows for x in row):
        _check_tensor(key, value, rows)
    return rows


def _check_tensor(key: str, raw: Any, rows: list) -> None:
    """Positive definite, and its principal moments obey the triangle inequalities (numbers: NumPy)."""
    from eulersym.validation import inertia_tensor

    inertia_tensor(key, rows, shown=raw)


def _body(value: Any, check: _Checker, weighed: bool) -> dict:
    if value is None:
        raise InvalidInput("body", None, "a [body] table (it is missing): one of body.moments (I1, I2, I3), "
                           "body.tensor (3×3), body.shape (with mass and dimensions) or [[body.parts]]")
    table = _table("body", value, ("moments", "tensor", "shape", "parts", "mass", "origin", "dimensions",
                                   "a", "b", "c", "R", "h", "L"))
    given = [k for k in _BODY_KINDS if k in table]
    if not given:
        raise InvalidInput("body", value, "one of body.moments (I1, I2, I3), body.tensor (3×3), body.shape (with "
                           "mass and dimensions) or [[body.parts]]")
    if len(given) > 1:
        raise InvalidInput(f"body.{given[1]}", table[given[1]], f"one body description; body.{given[0]} is given too")
    kind = given[0]
    if kind == "parts":
        for k in table:
            if k != "parts":
                raise InvalidInput(f"body.{k}", table[k], "no body-wide " + k + " with [[body.parts]]: each part "
                                   "has its own (the total mass, centre of mass and tensor are derived)")
        return {"parts": _parts(table["parts"], check)}
    if kind != "shape":
        for k in table:
            if k not in (kind, "mass"):
                raise InvalidInput(f"body.{k}", table[k], f"no {k} with body.{kind} (only a shape has dimensions "
                                   "and an origin)")
        out = {kind: (_moments if kind == "moments" else _tensor)(f"body.{kind}", table[kind], check)}
        if "mass" in table:
            out["mass"] = check.number("body.mass", table["mass"], sign="positive")
        elif weighed:
            raise InvalidInput("body.mass", None, "the body's mass M: a pivoted body under gravity feels the torque "
                               "M g l (M g c × gamma; or pivot.g = 0)")
        else:
            out["mass"] = None
        return out
    shape = _shape_keys("body", table)
    if "mass" not in table:
        raise InvalidInput("body.mass", None, f"the mass of the {shape['shape']}")
    dims = {k: check.number(f"{shape['where']}.{k}", v, sign="positive") for k, v in shape["dimensions"].items()}
    return {"shape": shape["shape"], "mass": check.number("body.mass", table["mass"], sign="positive"),
            "dimensions": dims, "origin": shape["origin"]}


def _parts(value: Any, check: _Checker) -> list:
    if _sequence(value) is None or not _sequence(value):
        raise InvalidInput("body.parts", value, "a non-empty list of parts ([[body.parts]] tables)")
    if len(value) > MAX_PARTS:
        raise InvalidInput("body.parts", f"{len(value)} parts", f"at most {MAX_PARTS} parts")
    parts = []
    for i, part in enumerate(_sequence(value)):
        key = f"body.parts[{i}]"
        table = _table(key, part, ("shape", "moments", "tensor", "mass", "origin", "dimensions", "a", "b", "c",
                                   "R", "h", "L", "position", "orientation", *_ORIENTATION_KEYS))
        inline = {k: table.pop(k) for k in _ORIENTATION_KEYS if k in table}
        if inline:  # quaternion = [...], euler = [...] + convention, axis + angle written on the part itself
            if "orientation" in table:
                k = next(iter(inline))
                raise InvalidInput(f"{key}.{k}", inline[k], f"one orientation: {key}.orientation is given too")
            table["orientation"] = inline
        given = [k for k in ("moments", "tensor", "shape") if k in table]
        if len(given) != 1:
            raise InvalidInput(key, part, "one of shape (with mass and dimensions), moments or tensor (with mass)"
                               + (f"; {given[0]} and {given[1]} are both given" if len(given) > 1 else ""))
        if "mass" not in table:
            raise InvalidInput(f"{key}.mass", None, "the part's mass (every part has one)")
        out = {"mass": check.number(f"{key}.mass", table["mass"], sign="positive")}
        if given[0] == "shape":
            shape = _shape_keys(key, table)
            out.update(shape=shape["shape"], origin=shape["origin"],
                       dimensions={k: check.number(f"{shape['where']}.{k}", v, sign="positive")
                                   for k, v in shape["dimensions"].items()})
        else:
            kind = given[0]
            for k in ("origin", "dimensions", "a", "b", "c", "R", "h", "L"):
                if k in table:
                    raise InvalidInput(f"{key}.{k}", table[k], f"no {k} with {kind} (about the part's centre of "
                                       "mass, which sits at its position)")
            out[kind] = (_moments if kind == "moments" else _tensor)(f"{key}.{kind}", table[kind], check)
        out["position"] = check.vector(f"{key}.position", table.get("position", [0.0, 0.0, 0.0]))
        out["orientation"] = _orientation(f"{key}.orientation", table.get("orientation"), check)
        parts.append(out)
    return parts


def _pivot(value: Any, check: _Checker) -> dict | None:
    if value is None:
        return None
    table = _table("pivot", value, ("centre_of_mass", "l", "g", "path"))
    if "centre_of_mass" in table and "l" in table:
        raise InvalidInput("pivot.l", table["l"], "one of pivot.centre_of_mass = [x, y, z] and pivot.l "
                           "(= centre_of_mass [0, 0, l]), not both")
    com = None
    if "centre_of_mass" in table:
        com = check.vector("pivot.centre_of_mass", table["centre_of_mass"])
    elif "l" in table:
        com = [0.0, 0.0, check.number("pivot.l", table["l"])]
    out = {"centre_of_mass": com, "l": "l" in table,
           "g": check.number("pivot.g", table.get("g", DEFAULT_G), sign="nonnegative")}
    if "path" in table:  # a pivot that moves: kept only when given (a fixed pivot keeps its digest)
        from eulersym.model.contact_scene import read_pivot_path

        path = read_pivot_path(table["path"])
        out["path"] = [check.number(f"pivot.path[{k}]", x, context="path") for k, x in enumerate(path)]
    return out


def _contact(value: Any, check: _Checker, pivot, body: dict) -> dict | None:
    """``[contact]``: the body on the horizontal plane z = 0 (:func:`eulersym.model.contact_scene.read_contact`),
    every formula's names checked against the parameters."""
    if value is None:
        return None
    from eulersym.model.contact_scene import read_contact

    if pivot is not None:
        raise InvalidInput("contact", value.get("surface") if isinstance(value, Mapping) else value,
                           "a free body: a contact with the plane and a pivot both hold the body (remove [pivot], "
                           "or the contact)")
    table = read_contact(dict(value) if isinstance(value, Mapping) else value)

    def checked(key, x):
        if isinstance(x, tuple):
            return [checked(f"{key}[{k}]", item) for k, item in enumerate(x)]
        return check.number(key, x) if isinstance(x, str) else (float(x) if not isinstance(x, str) else x)

    out = {k: checked(f"contact.{k}", v) for k, v in table.items() if k not in ("surface", "mode", "friction")}
    out.update(surface=table["surface"], mode=table["mode"], friction=table["friction"])
    if body.get("mass", 0) is None:
        raise InvalidInput("body.mass", None, "the body's mass M: a body on a plane feels its weight M g and the "
                           "contact force")
    return out


def _torque(value: Any, check: _Checker) -> dict:
    if value is None:
        return {"body": None, "space": None, "potential": None}
    table = _table("torque", value, ("body", "space", "potential"))
    out = {}
    for frame in ("body", "space"):
        v = table.get(frame)
        out[frame] = None if v is None else check.vector(f"torque.{frame}", v, context="torque", expression=True)
    potential = table.get("potential")
    out["potential"] = None if potential is None else check.number("torque.potential", potential,
                                                                   context="potential")
    return out


def _frame(value: Any, check: _Checker):
    """``[frame] rate = [Ω1, Ω2, Ω3]``: the frame's constant angular velocity, its own components."""
    if value is None:
        return None
    table = _table("frame", value, ("rate",))
    if "rate" not in table:
        raise InvalidInput("frame.rate", None, "the frame's angular velocity rate = [Ω1, Ω2, Ω3] (its own "
                           "components, numbers or expressions of the parameters)")
    return check.vector("frame.rate", table["rate"], context="frame")


def _quantities(value: Any, check: _Checker):
    """``[quantities] name = "expression"`` (and ``convention`` for phi, theta, psi): see
    :mod:`eulersym.model.quantities`."""
    if value is None:
        return None
    from eulersym.model.quantities import validate

    return validate(value, check.parameters)


def _rotor(value: Any, check: _Checker):
    if value is None:
        return None
    table = _table("rotor", value, ("h",))
    if "h" not in table:
        raise InvalidInput("rotor.h", None, "the rotor's constant angular momentum h = [h1, h2, h3] (body "
                           "components)")
    return check.vector("rotor.h", table["h"], context="rotor", expression=True)


# ------------------------------------------------------------------------------------------------------------
# The model


def _drop_none(table: dict) -> dict:
    return {k: v for k, v in table.items() if v is not None}


def _distribution_version(name: str) -> str:
    from importlib import metadata  # only for a digest: not paid by a scene that needs none

    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "unknown"


class Model:
    """A rigid body of one's own — body (moments, tensor, shape or parts), pivot, torques, rotor, parameters.

    Parameters
    ----------
    name : str, optional
        For reports and generated headers (default ``"model"``).
    parameters : mapping name → float, optional
        The model's parameters and their defaults, in order (the order generated functions take them).
    body : mapping
        Exactly one of ``moments`` (with an optional ``mass``), ``tensor`` (idem), ``shape`` (with ``mass``,
        its dimensions and ``origin``) or ``parts`` (a list of parts, each a shape with its ``mass`` and
        dimensions, or ``moments``/``tensor`` with a ``mass``; each at a ``position``, optionally turned by an
        ``orientation``).
    pivot : mapping, optional
        ``centre_of_mass`` = [x, y, z] (body frame, from the pivot) or ``l`` (= [0, 0, l]) — derived, and only
        checked when given, for a shape or parts — and ``g`` (default 9.81).
    torque : mapping, optional
        ``body`` and/or ``space``: a vector expression or three component expressions; ``potential``: a scalar
        potential energy.
    rotor : mapping, optional
        ``h``: the constant angular momentum of an internal rotor, body components.
    frame : mapping, optional
        ``rate = [Ω1, Ω2, Ω3]``: the reference frame turns uniformly at Ω (its own components; numbers or
        expressions of the parameters, never of the state or t). ω stays the body's angular velocity relative to
        inertial space (body components); the attitude q, ``to_body``/``to_space`` and ``gamma`` (the frame's up)
        refer to the frame.
    quantities : mapping, optional
        ``name = "expression"``: quantities to output, emitted into the model's kernel
        (:mod:`eulersym.model.quantities`); ``convention`` names the sequence of ``phi``, ``theta``, ``psi``.

    Attributes
    ----------
    name : str
    parameters : dict name → float (file order)
    digest : str
        Hex SHA-256 of the normalised model, eulersym.__version__ and SymPy's version (SymPy-free).
    pivoted : bool
    mechanics : Mechanics
        The symbolic content (built on first use; imports SymPy).
    mass, centre_of_mass, inertia
        Derived (SymPy): the total mass (None for a free body given by its moments without a mass); the centre of
        mass (from the pivot; for a free body, where the shape or the parts put it in the model frame); the
        tensor in the model frame, about the pivot for a pivoted body and about the centre of mass of a free one.

    Examples
    --------
    A gyroscope: a disc on an axle, on a pivot at the axle's end.

    >>> gyro = Model(name="gyroscope", body={"parts": [
    ...     {"shape": "cylinder", "mass": 1.0, "R": 0.05, "h": 0.01, "position": [0, 0, 0.1]},
    ...     {"shape": "rod", "mass": 0.1, "L": 0.2, "origin": "end"}]}, pivot={"g": 9.81})
    >>> gyro.mass
    11/10
    >>> gyro.centre_of_mass.T
    Matrix([[0, 0, 1/10]])
    >>> Model(body={"moments": [1, 1, 3]})
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: body.moments=[1, 1, 3] is not valid: expected principal moments of a body: ...
    """

    def __init__(self, **kwargs: Any):
        valid = ("name", *MODEL_SECTIONS)
        for key in kwargs:
            if key not in valid:
                raise InvalidInput(key, kwargs[key], "a model section or name: " + _did_you_mean(key, valid))
        name = kwargs.get("name", "model")
        if not isinstance(name, str) or not name.strip() or len(name) > 200:
            raise InvalidInput("name", name, "a non-empty string of at most 200 characters")
        parameters = _parameters(kwargs.get("parameters"))
        check = _Checker(parameters)
        pivot = _pivot(kwargs.get("pivot"), check)
        weighed = pivot is not None and pivot["g"] != 0.0
        body = _body(kwargs.get("body"), check, weighed)
        if pivot is not None and pivot["centre_of_mass"] is None and ("moments" in body or "tensor" in body):
            if not weighed:  # no gravity: the centre of mass plays no part
                pivot["centre_of_mass"] = [0.0, 0.0, 0.0]
            else:
                raise InvalidInput("pivot.centre_of_mass", None, "the centre of mass from the pivot, body "
                                   "frame: centre_of_mass = [x, y, z] (or l = ... for [0, 0, l]; [0, 0, 0] for a "
                                   "pivot at the centre of mass)")
        self._data = {
            "name": name,
            "parameters": [[k, v] for k, v in parameters.items()],
            "body": body,
            "pivot": pivot,
            "torque": _torque(kwargs.get("torque"), check),
            "rotor": _rotor(kwargs.get("rotor"), check),
        }
        for key, read in (("frame", _frame), ("quantities", _quantities)):
            section = read(kwargs.get(key), check)
            if section is not None:
                self._data[key] = section
        contact = _contact(kwargs.get("contact"), check, pivot, body)
        if contact is not None:
            for key in ("frame", "quantities"):  # the contact kernel emits its own outputs, in the inertial frame
                if key in self._data:
                    raise InvalidInput(key, kwargs[key], f"no [{key}] with [contact] (a body on a plane outputs its "
                                       "contact point, normal force, slip and height itself)")
            self._data["contact"] = contact
        if pivot is not None and pivot["centre_of_mass"] is not None and ("shape" in body or "parts" in body):
            self._check_centre()  # a shape's centre of mass is derived: a contradictory one is refused now

    # ---- construction ---------------------------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: Mapping) -> "Model":
        """A model from the nested mapping a TOML file holds; a scene file's other keys (``description``,
        ``[initial]``, ``[time]``, ``[output]``, ``[sweep...]``) are ignored.

        Examples
        --------
        >>> Model.from_dict({"body": {"moments": [1, 2, 3]}, "initial": {"omega": [0, 0, 1]}}).pivoted
        False
        >>> Model.from_dict({"bdy": {"moments": [1, 2, 3]}})
        Traceback (most recent call last):
        ...
        eulersym.errors.InvalidInput: bdy={'moments': [1, 2, 3]} is not valid: expected a model section or key: ... (did you mean 'body'?)
        """
        if not isinstance(data, Mapping):
            raise InvalidInput("model", data, "a mapping of sections (parameters, body, pivot, torque, rotor)")
        valid = ("name", *MODEL_SECTIONS, *SCENE_KEYS)
        kwargs = {}
        for key, value in data.items():
            if key in ("name", *MODEL_SECTIONS):
                kwargs[key] = value
            elif key in SCENE_KEYS or (isinstance(key, str) and key.startswith("sweep")):
                continue
            else:
                raise InvalidInput(str(key), value, "a model section or key: " + _did_you_mean(str(key), valid))
        return cls(**kwargs)

    @classmethod
    def from_toml(cls, path) -> "Model":
        """A model from a TOML file (a model file, or a scene file: its scene sections are ignored). Without a
        ``name`` key the model takes the file's stem.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> with tempfile.TemporaryDirectory() as d:
        ...     p = pathlib.Path(d, "spinner.toml")
        ...     _ = p.write_text('[body]\\nmoments = [1, 2, 3]\\n[torque]\\nbody = "-0.1*omega"\\n')
        ...     Model.from_toml(p).name
        'spinner'
        """
        from pathlib import Path  # a model file's path only (a scene file is read by eulersym.scene.spec)

        try:
            p = Path(path)
            size = p.stat().st_size
        except (TypeError, ValueError, OSError) as exc:
            raise InvalidInput("path", str(path), f"a readable model file ({type(exc).__name__})") from None
        if size > MAX_FILE_BYTES:
            raise InvalidInput("path", str(path), f"a model file of at most {MAX_FILE_BYTES} bytes (this one has "
                               f"{size})")
        try:
            data = tomllib.loads(p.read_bytes().decode("utf-8"))
        except (OSError, UnicodeDecodeError) as exc:
            raise InvalidInput("path", str(path), f"a readable UTF-8 model file ({exc})") from None
        except tomllib.TOMLDecodeError as exc:
            raise InvalidInput(str(path), str(exc), "valid TOML") from None
        except RecursionError:
            raise InvalidInput(str(path), "arrays or tables nested too deep", "a model file of plain tables and "
                               "lists") from None
        data.setdefault("name", p.stem)
        return cls.from_dict(data)

    # ---- plain facts (SymPy-free) --------------------------------------------------------------------------
    @property
    def name(self) -> str:
        """The model's name.

        Examples
        --------
        >>> Model(name="spinner", body={"moments": [1, 2, 3]}).name
        'spinner'
        """
        return self._data["name"]

    @property
    def parameters(self) -> dict:
        """name → default value, in the file's order.

        Examples
        --------
        >>> Model(parameters={"c": 0.1, "k": 2}, body={"moments": [1, 2, 3]}).parameters
        {'c': 0.1, 'k': 2.0}
        """
        return {k: v for k, v in self._data["parameters"]}

    @property
    def pivoted(self) -> bool:
        """Whether the body turns about a fixed pivot.

        Examples
        --------
        >>> Model(body={"moments": [1, 1, 2], "mass": 1}, pivot={"l": 0.1}).pivoted
        True
        """
        return self._data["pivot"] is not None

    @property
    def contact(self) -> Mapping | None:
        """The checked ``[contact]`` table (read-only; numbers as floats, formulas as strings, lists for vectors), or
        None: the body rolls or slides on the horizontal plane z = 0 (:mod:`eulersym.model.contact`).

        Examples
        --------
        >>> m = Model(body={"moments": [2, 2, 2], "mass": 5}, contact={"surface": "sphere", "radius": 0.1})
        >>> m.contact["surface"], m.contact["mode"], m.contact["radius"], m.pivoted
        ('sphere', 'rolling', 0.1, False)
        >>> Model(body={"moments": [2, 2, 2], "mass": 5}, contact={"surface": "sphere", "radius": 0}).contact
        Traceback (most recent call last):
        ...
        eulersym.errors.InvalidInput: contact.radius=0 is not valid: expected a positive number
        """
        from types import MappingProxyType

        contact = self._data.get("contact")
        return None if contact is None else MappingProxyType(contact)

    @property
    def pivot_path(self) -> tuple | None:
        """``[pivot] path``: the pivot's prescribed position in space (three formulas of ``t`` and the parameters, or
        numbers), or None for a fixed pivot (:mod:`eulersym.model.moving_pivot`).

        Examples
        --------
        >>> Model(parameters={"a": 0.01, "w": 100}, body={"moments": [1, 1, 0.1], "mass": 1},
        ...       pivot={"l": 0.2, "path": [0, 0, "a*cos(w*t)"]}).pivot_path
        (0.0, 0.0, 'a*cos(w*t)')
        >>> Model(body={"moments": [1, 1, 0.1], "mass": 1}, pivot={"l": 0.2, "path": [0, 0, "omega1"]})
        Traceback (most recent call last):
        ...
        eulersym.errors.InvalidInput: pivot.path[2]='omega1' is not valid: expected a position of the pivot in space: an expression of t alone and the parameters (none); 'omega1' varies with the motion
        """
        pivot = self._data["pivot"]
        return None if pivot is None or "path" not in pivot else tuple(pivot["path"])

    @property
    def normalised(self) -> Mapping:
        """The validated sections as the model keeps them (read-only view): ``name``, ``parameters`` (``[[name,
        default], ...]``), ``body``, ``pivot`` (None, or ``centre_of_mass``/``l``/``g``), ``torque`` (``body``,
        ``space``, ``potential``), ``rotor`` — numbers as floats, formulas as strings; what :meth:`facts` reads.

        Examples
        --------
        >>> Model(body={"moments": [1, 2, 3]}, pivot={"l": 0.1, "g": 0}).normalised["pivot"]
        {'centre_of_mass': [0.0, 0.0, 0.1], 'l': True, 'g': 0.0}
        """
        from types import MappingProxyType

        return MappingProxyType(self._data)

    def to_dict(self) -> dict:
        """The normalised model as a mapping :meth:`from_dict` reads back (numbers as floats, expressions as
        stripped strings, defaults filled in): what :attr:`digest` hashes.

        Examples
        --------
        >>> m = Model(body={"moments": [1, 2, 3], "mass": 2}, pivot={"l": 0.1})
        >>> m.to_dict()
        {'name': 'model', 'body': {'moments': [1.0, 2.0, 3.0], 'mass': 2.0}, 'pivot': {'g': 9.81, 'l': 0.1}}
        >>> Model.from_dict(m.to_dict()) == m
        True
        """
        import json  # here and in digest, __hash__: a scene's run reads none of them

        data = json.loads(json.dumps(self._data))
        out: dict = {"name": data["name"]}
        if data["parameters"]:
            out["parameters"] = {k: v for k, v in data["parameters"]}
        body = _drop_none(data["body"])
        if "parts" in body:
            body["parts"] = [_drop_none(part) for part in body["parts"]]
        out["body"] = body
        pivot = data["pivot"]
        if pivot is not None:
            com, by_l = pivot.pop("centre_of_mass"), pivot.pop("l")
            if com is not None:
                pivot.update({"l": com[2]} if by_l else {"centre_of_mass": com})
            out["pivot"] = pivot
        torque = _drop_none(data["torque"])
        if torque:
            out["torque"] = torque
        if data["rotor"] is not None:
            out["rotor"] = {"h": data["rotor"]}
        if "frame" in data:
            out["frame"] = {"rate": data["frame"]}
        if "contact" in data:
            out["contact"] = data["contact"]
        if "quantities" in data:
            q = data["quantities"]
            units = q.get("units", {})
            out["quantities"] = {**{name: {"expression": text, "unit": units[name]} if name in units else text
                                    for name, text in q["names"]},
                                 **({"convention": q["convention"]} if q["convention"] != "zxz" else {})}
        return out

    @cached_property
    def digest(self) -> str:
        """Hex SHA-256 of the normalised model, eulersym's version (``eulersym.__version__``: the same however it is
        installed) and SymPy's distribution version (read without importing SymPy).

        Examples
        --------
        >>> a = Model(body={"moments": [1, 2, 3]})
        >>> a.digest == Model(body={"moments": [1.0, 2.0, 3.0]}).digest, len(a.digest)
        (True, 64)
        """
        import json

        data = json.loads(json.dumps(self._data))
        if data["pivot"] is not None:
            del data["pivot"]["l"]  # l = 0.1 is centre_of_mass = [0, 0, 0.1]; the flag only names the key
        from eulersym import __version__  # the package's own: the same for an editable and an installed copy

        payload = {"model": data, "eulersym": __version__, "sympy": _distribution_version("sympy")}
        text = json.dumps(payload, sort_keys=True, separators=(",", ":"), ensure_ascii=True)
        import hashlib

        return hashlib.sha256(text.encode("ascii")).hexdigest()

    def __repr__(self) -> str:
        return f"Model(name={self.name!r}, digest={self.digest[:12]!r})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Model) and other._data == self._data

    def __hash__(self) -> int:  # of the data alone (the digest also reads installed versions: slower)
        import json

        return hash(json.dumps(self._data, sort_keys=True))

    # ---- numbers (NumPy) -------------------------------------------------------------------------------------
    def facts(self, values: Mapping | None = None, *, batch: int | None = None):
        """The body's numbers for parameter ``values``, every member at once, in NumPy
        (:class:`~eulersym.model.facts.Facts`: mass, centre of mass, tensor, rotor, g, the constant torques, flags).

        Parameters
        ----------
        values : mapping name → float or ndarray (batch,), optional
            Parameter values (the defaults fill the others); arrays give one member per entry.
        batch : int, optional
            The number of members (default: the arrays' length, 1 without arrays).

        Numbers and entries that name a parameter need no SymPy; a named shape's tensor and centre come from the
        committed closed forms (:mod:`eulersym.shapes`); only a formula such as ``"2*C"`` is parsed (SymPy).
        Every member is validated (:mod:`eulersym.validation`), errors naming the TOML key.

        Examples
        --------
        >>> import numpy as np
        >>> m = Model(parameters={"I3": 1.0}, body={"moments": [2, 2, "I3"]})
        >>> m.facts({"I3": np.array([1.0, 3.0])}).tensor[:, 2, 2].tolist()
        [1.0, 3.0]
        >>> m.facts({"I3": np.array([1.0, 5.0])})
        Traceback (most recent call last):
        ...
        eulersym.errors.InvalidInput: body.moments=[2.0, 2.0, 'I3'] is not valid: expected principal moments of a body: positive and I1 + I2 >= I3, I2 + I3 >= I1, I3 + I1 >= I2 (here I1 + I2 = 4 < I3 = 5, member 1)
        """
        from eulersym.model.facts import facts

        out = facts(self._data, values, batch)
        if "contact" in self._data:  # a body on a plane: its own regime (the contact kernel integrates it)
            _check_contact(self._data, values, out.batch)
            out = out._replace(contact=True)
        if self.pivot_path is not None:  # the pivot's acceleration: a time-dependent potential (the model's kernel)
            out = out._replace(potential=True)
        if "frame" in self._data:  # a turning frame's kinematics live only in the model's own equations
            out = out._replace(turning=True)
        return out

    def _check_centre(self) -> None:
        """A centre of mass given for a shape or parts must be the one they derive (at the defaults, NumPy)."""
        import numpy as np

        pivot = self._data["pivot"]
        key = "pivot.l" if pivot.get("l") else "pivot.centre_of_mass"
        derived = self.facts(batch=1)
        given = dict(self._data, body={"moments": [1.0, 1.0, 1.0]})
        from eulersym.model.facts import facts

        stated = facts(given, batch=1).centre_of_mass[0]
        centre = derived.centre_of_mass[0]
        scale = max(float(np.max(np.abs(centre))), float(np.max(np.abs(stated))), 1e-300)
        if np.max(np.abs(stated - centre)) > 1e-9 * scale:
            raw = pivot["centre_of_mass"][2] if pivot.get("l") else pivot["centre_of_mass"]
            along = f"l = {centre[2]:.6g}, " if pivot.get("l") and centre[0] == 0 and centre[1] == 0 else ""
            raise InvalidInput(key, raw, f"the centre of mass the body derives, {along}"
                               f"{[float(f'{c:.6g}') for c in centre]} from the pivot (a shape's or the parts' centre "
                               f"of mass is derived: leave {key} out)")

    def __getstate__(self) -> dict:  # pickles (Dask, multiprocessing) carry the data, not the derived SymPy
        return {"_data": self._data}

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)

    # ---- derived (SymPy) -------------------------------------------------------------------------------------
    @cached_property
    def _assembly(self):
        from eulersym.model.assemble import assemble

        assembly = assemble(self._data)
        if self.pivot_path is not None:  # r̈(t) of the pivot as a derived apparent gravity (a potential in t)
            import dataclasses

            from eulersym.model.moving_pivot import moving_pivot

            assembly = dataclasses.replace(assembly, mechanics=moving_pivot(assembly.mechanics, self.pivot_path))
        if not any(key in self._data for key in OPTIONAL_SECTIONS):
            return assembly
        import dataclasses

        from eulersym.model.quantities import frame_rate

        mech = assembly.mechanics
        extra = {}
        if "frame" in self._data:
            extra["frame"] = frame_rate(mech, self._data["frame"])
        if "quantities" in self._data:
            q = self._data["quantities"]
            extra.update(quantities=tuple(tuple(pair) for pair in q["names"]), convention=q["convention"])
        return dataclasses.replace(assembly, mechanics=dataclasses.replace(mech, **extra))

    @cached_property
    def body_on_plane(self):
        """The body on the plane (:class:`eulersym.model.rolling.BodyOnPlane`: the mechanics, the contact in the
        parameters' symbols, gravity), or None without ``[contact]``; built on first use (SymPy).

        Examples
        --------
        >>> m = Model(body={"moments": [2, 2, 2], "mass": 5}, contact={"surface": "sphere", "radius": 0.1})
        >>> m.body_on_plane.contact.surface.kind, m.body_on_plane.gravity
        ('sphere', 981/100)
        """
        if "contact" not in self._data:
            return None
        from eulersym.model.contact_scene import contact, expression
        from eulersym.model.rolling import BodyOnPlane

        mech = self.mechanics
        table = self._data["contact"]
        return BodyOnPlane(mech, contact(table, mech), gravity=expression("contact.g", table["g"], mech))

    @property
    def mechanics(self):
        """The symbolic content of the model (:class:`~eulersym.model.mechanics.Mechanics`), built on first use.

        Examples
        --------
        >>> m = Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"})
        >>> m.mechanics.torque.T
        Matrix([[-c*omega1, -c*omega2, -c*omega3]])
        """
        return self._assembly.mechanics

    @property
    def mass(self):
        """The total mass (SymPy), derived for a shape or parts; None for a free body given without one.

        Examples
        --------
        >>> Model(body={"parts": [{"shape": "sphere", "mass": 1, "R": 1},
        ...                       {"shape": "point", "mass": 0.5, "position": [2, 0, 0]}]}).mass
        3/2
        """
        return self._assembly.mass

    @property
    def centre_of_mass(self):
        """The centre of mass (3×1, SymPy): from the pivot for a pivoted body; for a free body, where the shape
        (from its origin) or the parts put it in the model frame (zero for moments or a tensor).

        Examples
        --------
        A cone on its apex: 3h/4 up the axis, derived from the region.

        >>> Model(body={"shape": "cone", "mass": 1, "R": 0.05, "h": 0.2}, pivot={}).centre_of_mass.T
        Matrix([[0, 0, 3/20]])
        """
        return self._assembly.centre_of_mass

    @property
    def inertia(self):
        """The inertia tensor (3×3, SymPy) in the model frame: about the pivot, or the centre of mass of a free
        body (never silently in principal axes).

        Examples
        --------
        Two point masses on the x axis and a small sphere, about their centre of mass:

        >>> Model(body={"parts": [{"shape": "point", "mass": 1, "position": [1, 0, 0]},
        ...                       {"shape": "point", "mass": 1, "position": [-1, 0, 0]},
        ...                       {"shape": "sphere", "mass": 5, "R": 0.1}]}).inertia.diagonal()
        Matrix([[1/50, 101/50, 101/50]])
        """
        return self.mechanics.inertia

    # ---- derivations (eulersym.model.derive / integrals / kernels) --------------------------------------------
    def equations(self):
        """The equations of motion, Newton–Euler route (:func:`eulersym.model.derive.equations`).

        Examples
        --------
        >>> eqs = Model(body={"moments": [1, 1, 2]}, torque={"body": "[0, 0, 0.5]"}).equations()
        >>> eqs.omega_dot[2]
        1/4
        """
        if self.body_on_plane is not None:  # the contact force a multiplier (eulersym.model.rolling)
            from eulersym.model import rolling

            return rolling.newton_euler(self.body_on_plane)
        from eulersym.model import derive

        return derive.equations(self.mechanics)

    def lagrangian(self, convention: str = "zxz"):
        """The Lagrangian in Euler angles of ``convention`` (:func:`eulersym.model.derive.lagrangian`).

        Examples
        --------
        >>> from eulersym.symbols import phi, psi
        >>> L = Model(body={"moments": [1, 1, 2]}).lagrangian()
        >>> L.diff(phi), L.diff(psi)  # a free symmetric body: precession and spin angles are cyclic
        (0, 0)
        """
        if self.contact is not None:
            raise InvalidInput("model", self.name, "a model without [contact] for a Lagrangian: a body on a plane "
                               "has none that gives its motion (the contact constraint is nonholonomic, and "
                               "Lagrange's equations without multipliers would be wrong); its two routes are "
                               "Newton–Euler with the contact force a multiplier and Gibbs–Appell (model.check())")
        from eulersym.model import derive

        return derive.lagrangian(self.mechanics, convention)

    def check(self):
        """The two routes proven identical (:func:`eulersym.model.derive.check`).

        Examples
        --------
        >>> Model(body={"moments": [1, 1, 2], "mass": 1}, pivot={"l": 0.1}).check().ok
        True
        """
        if self.body_on_plane is not None:  # Newton–Euler with the contact force a multiplier = Gibbs–Appell
            from eulersym.model import rolling

            return rolling.check(self.body_on_plane)
        from eulersym.model import derive

        return derive.check(self.mechanics)

    def invariants(self):
        """The integrals of motion the structure implies, each with a proven verdict
        (:func:`eulersym.model.integrals.invariants`).

        Examples
        --------
        >>> verdicts = Model(body={"moments": [1, 2, 3]}).invariants()
        >>> all(v.conserved for v in verdicts.values())
        True
        """
        if self.body_on_plane is not None:  # energy, Jellett's, Chaplygin's, L about the contact...
            from eulersym.model import rolling_integrals

            return rolling_integrals.invariants(self.body_on_plane)
        from eulersym.model import integrals

        return integrals.invariants(self.mechanics)

    def prove(self, candidate: str, on=None):
        """Whether ``candidate`` (a string in the model's names) is conserved — everywhere, or on the level set
        ``on`` of the model's integrals (``"L_dot_Gamma = 0"``) — (:func:`eulersym.model.integrals.prove`).

        Examples
        --------
        >>> import sympy as sp
        >>> damped = Model(parameters={"c": 0.1}, body={"moments": [1, 2, 3]}, torque={"body": "-c*omega"})
        >>> verdict = damped.prove("dot(omega, inertia*omega)/2")
        >>> verdict.conserved, sp.expand(verdict.rate)
        (False, -c*omega1**2 - c*omega2**2 - c*omega3**2)
        """
        if not isinstance(candidate, str):
            raise InvalidInput("candidate", candidate, "a string: an expression in the model's names")
        from eulersym.model import integrals
        from eulersym.model.expressions import parse

        mech = self.mechanics
        expr = parse(candidate, mech, argument="candidate", shape="scalar")
        if self.body_on_plane is not None:
            if on is not None:
                raise InvalidInput("on", on, "None for a body on a plane (a level set of its integrals is not "
                                   "supported there)")
            from eulersym.model import rolling_integrals

            return rolling_integrals.prove(self.body_on_plane, expr)
        return integrals.prove(mech, expr, on=on)

    def steady_motions(self, **options):
        """Its steady motions, each family with its stability (:func:`eulersym.model.steady.steady_motions`; a body
        on a plane, ``[contact]``: :func:`eulersym.model.rolling_steady.steady_motions`, on its contact equations).

        Examples
        --------
        >>> [f.name for f in Model(body={"moments": [1, 2, 3]}).steady_motions()]
        ['rotation about e1', 'rotation about e2', 'rotation about e3']
        """
        if self.body_on_plane is not None:  # a body on a plane: its contact equations, never the free body's
            from eulersym.model.rolling_steady import steady_motions as on_a_plane

            return on_a_plane(self.body_on_plane, **options)
        from eulersym.model.steady import steady_motions

        return steady_motions(self, **options)

    def generate(self, directory):
        """Write the model's kernel module into ``directory`` (:func:`eulersym.model.kernels.generate`).

        Examples
        --------
        >>> import tempfile, pathlib
        >>> with tempfile.TemporaryDirectory() as d:
        ...     path = Model(name="spinner", body={"moments": [1, 2, 3]}).generate(d)
        ...     pathlib.Path(path).suffix
        '.py'
        """
        if self.body_on_plane is not None:
            from eulersym.model import rolling_kernels

            return rolling_kernels.generate(self.body_on_plane, directory)
        from eulersym.model import kernels

        return kernels.generate(self.mechanics, directory, digest=self.digest)

    def compile(self):
        """The model's kernel functions in memory (:func:`eulersym.model.kernels.compile`).

        Examples
        --------
        >>> kernel = Model(body={"moments": [1, 2, 3]}).compile()
        >>> kernel.STATE[:3], [float(x) for x in kernel.rhs(0.0, [0, 0, 1, 1, 0, 0, 0])[:3]]
        (('omega1', 'omega2', 'omega3'), [0.0, 0.0, 0.0])
        """
        if self.body_on_plane is not None:
            from eulersym.model import rolling_kernels

            return rolling_kernels.compile(self.body_on_plane)
        from eulersym.model import kernels

        return kernels.compile(self.mechanics)


def _check_contact(data: dict, values, batch: int) -> None:
    """A body on a plane's dimensions and coefficients at every member's parameter values (NumPy): positive radius,
    semi-axes, curvatures, g and width; mu, rolling_resistance and spin_friction >= 0 — refused by key, naming the
    member and its value (the SymPy check of :class:`~eulersym.model.rolling.BodyOnPlane` sees the defaults only)."""
    from eulersym.model.contact import SURFACES
    from eulersym.model.facts import _positive, _Reader

    contact = data["contact"]
    reader = _Reader(data["parameters"], dict(values or {}), batch)
    key, count = SURFACES[contact["surface"]]
    raw = contact.get(key)
    entries = [(f"contact.{key}", raw)] if count == 1 else [(f"contact.{key}[{k}]", x) for k, x in enumerate(raw)]
    if contact.get("g") is not None:
        entries.append(("contact.g", contact["g"]))
    if contact.get("width") is not None:
        entries.append(("contact.width", contact["width"]))
    for name, value in entries:
        if value is not None:
            _positive(name, value, reader.scalar(name, value), batch, "a positive value at every member's parameters")
    for name in ("mu", "rolling_resistance", "spin_friction"):
        value = contact.get(name)
        if value is not None:
            _positive(f"contact.{name}", value, reader.scalar(f"contact.{name}", value), batch,
                      "a value >= 0 at every member's parameters", zero=True)
