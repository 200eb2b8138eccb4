"""The checked sections of a body on a plane (``[contact]``) and on a moving pivot (``[pivot] path``): what
:class:`eulersym.model.Model` reads (:func:`read_contact`, :func:`read_pivot_path`), the contact in the model's
parameters (:func:`contact`), and where the bundled scenes of such bodies live (:data:`FOLDER`, :func:`listing`).

``[contact]``
    ``surface`` (``sphere``, ``ellipsoid``, ``disk``, ``paraboloid``) with its dimension (``radius``,
    ``semi_axes``, ``curvatures``), ``centre`` and ``axes`` (the shape from the centre of mass, body frame), ``mode``
    (``rolling`` | ``sliding``), ``friction`` (``none``, ``viscous``, ``coulomb``), ``mu``, ``width``,
    ``rolling_resistance``, ``spin_friction``, and ``g`` (default 9.81) — numbers or formulas of the parameters.
``[pivot] path = ["x(t)", "y(t)", "z(t)"]``
    The pivot's prescribed position in space, formulas of ``t`` and the parameters.

A scene of such a body is a scene like any other (:class:`eulersym.scene.Scene`, ``eulersym simulate NAME``): its
``[initial]`` may also give ``position = [x, y]`` (and, sliding, ``velocity = [v_x, v_y]``) of the centre of mass;
the plan integrates a contact with :class:`eulersym.numerics.methods.ContactDOP853` and a moving pivot with the
model's own kernel.

Examples
--------
>>> sorted(listing())[:2]
['chaplygin-ball', 'euler-disk']
>>> read_contact({"surface": "sphere", "radius": -1})
Traceback (most recent call last):
...
eulersym.errors.InvalidInput: contact.radius=-1 is not valid: expected a positive number
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.validation import choice

__all__ = ["CONTACT_KEYS", "FOLDER", "bundled", "listing", "read_contact", "read_pivot_path", "expression", "contact"]

#: The keys of ``[contact]``.
CONTACT_KEYS = ("surface", "radius", "semi_axes", "curvatures", "centre", "axes", "mode", "friction", "mu", "width",
                "rolling_resistance", "spin_friction", "g")

#: Where the bundled contact and moving-pivot scenes live (``eulersym/scenes/contact/*.toml``).
FOLDER = Path(__file__).resolve().parent.parent / "scenes" / "contact"



def bundled() -> dict:
    """``{name: path}`` of the bundled contact and moving-pivot scenes.

    Examples
    --------
    >>> sorted(bundled())[:2]
    ['chaplygin-ball', 'euler-disk']
    """
    return {p.stem: str(p) for p in sorted(FOLDER.glob("*.toml"))}


def listing() -> dict:
    """``{name: (description, path)}`` of the bundled contact and moving-pivot scenes (``eulersym simulate --list``
    lists them with every bundled scene: :func:`eulersym.scene.catalog.bundled`). Reads each file's ``description``
    only: nothing is derived.

    Examples
    --------
    >>> description, path = listing()["tippe-top"]
    >>> description.startswith("a tippe top"), path.endswith("tippe-top.toml")
    (True, True)
    """
    found = {}
    for name, path in bundled().items():
        data, _ = _read(path)
        found[name] = (str(data.get("description", "")), path)
    return found


def _table(key: str, value, valid) -> dict:
    if not isinstance(value, dict):
        raise InvalidInput(key, value, "a table of " + ", ".join(valid))
    for k in value:
        if k not in valid:
            raise InvalidInput(f"{key}.{k}", value[k], "a key of [" + key + "]: one of " + ", ".join(valid))
    return value


def _entry(key: str, value):
    """A number or a formula (a string, checked later against the parameters); never a bool."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise InvalidInput(key, value, "a number or a formula of the parameters (a string)")
    if isinstance(value, float) and not np.isfinite(value):
        raise InvalidInput(key, value, "a finite number")
    return value


def read_contact(value) -> dict:
    """The ``[contact]`` table, checked: known keys, a known surface with its one dimension, numbers or formulas.

    Dimensions that are numbers are checked here (positive); formulas once the parameters are known
    (:func:`contact`). Returns the table with ``g`` filled in (9.81) and lists as tuples.

    Raises
    ------
    eulersym.errors.InvalidInput
        Naming the key (``contact.radius``) and the value.

    Examples
    --------
    >>> read_contact({"surface": "disk", "radius": 0.03})["mode"]
    'rolling'
    >>> read_contact({"surface": "disk", "radius": 0.03, "friction": "stribeck"})
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: contact.friction='stribeck' is not valid: expected one of 'none', 'viscous', 'coulomb'
    """
    from eulersym.model.contact import FRICTION_LAWS, MODES, SURFACES

    table = dict(_table("contact", value, CONTACT_KEYS))
    if "surface" not in table:
        raise InvalidInput("contact.surface", None, "one of " + ", ".join(SURFACES) + " (it is missing)")
    choice("contact.surface", table["surface"], tuple(SURFACES))
    table.setdefault("mode", "rolling")
    table.setdefault("friction", "none")
    choice("contact.mode", table["mode"], MODES)
    choice("contact.friction", table["friction"], FRICTION_LAWS)
    for key in ("radius", "mu", "width", "rolling_resistance", "spin_friction", "g"):
        if key in table:
            _entry(f"contact.{key}", table[key])
            if not isinstance(table[key], str) and (table[key] < 0 or (table[key] == 0 and key in ("radius", "width", "g"))):
                raise InvalidInput(f"contact.{key}", table[key], "a positive number" if key in ("radius", "width", "g")
                                   else "a number >= 0")
    for key, n in (("semi_axes", 3), ("curvatures", 2), ("centre", 3)):
        if key in table:
            items = table[key]
            if not isinstance(items, list) or len(items) != n:
                raise InvalidInput(f"contact.{key}", items, f"{n} numbers or formulas [..]")
            table[key] = tuple(_entry(f"contact.{key}[{k}]", x) for k, x in enumerate(items))
            if key != "centre":
                for k, x in enumerate(table[key]):
                    if not isinstance(x, str) and not x > 0:
                        raise InvalidInput(f"contact.{key}[{k}]", x, "a positive number")
    if "axes" in table:
        rows = table["axes"]
        if not isinstance(rows, list) or len(rows) != 3 or any(not isinstance(r, list) or len(r) != 3 for r in rows):
            raise InvalidInput("contact.axes", rows, "a 3×3 rotation matrix [[..], [..], [..]]")
        table["axes"] = tuple(tuple(_entry("contact.axes", x) for x in r) for r in rows)
    table.setdefault("g", 9.81)
    return table


def read_pivot_path(value) -> tuple:
    """``[pivot] path``, checked: three formulas (strings) or numbers; that they use ``t`` and the parameters only
    is checked against the model (:func:`eulersym.model.moving_pivot.pivot_path`).

    Examples
    --------
    >>> read_pivot_path(["0", "0", "a*cos(w*t)"])
    ('0', '0', 'a*cos(w*t)')
    >>> read_pivot_path("a*cos(w*t)")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: pivot.path='a*cos(w*t)' is not valid: expected three components ["x(t)", "y(t)", "z(t)"] (formulas of t and the parameters)
    """
    if not isinstance(value, list) or len(value) != 3:
        raise InvalidInput("pivot.path", value, 'three components ["x(t)", "y(t)", "z(t)"] (formulas of t and the '
                           "parameters)")
    return tuple(_entry(f"pivot.path[{k}]", x) for k, x in enumerate(value))


def expression(key: str, value, mech):
    """A checked entry as SymPy: numbers exact, formulas read by the whitelist parser in the parameters' names."""
    import sympy as sp

    from eulersym.model.expressions import namespace, parse

    if isinstance(value, str):
        names = namespace({s.name: s for s in mech.parameter_symbols}, state=False, time=False)
        return parse(value, names, argument=key)
    return sp.Rational(repr(value)) if isinstance(value, float) else sp.Integer(value)


def contact(table: dict, mech):
    """The :class:`~eulersym.model.contact.Contact` of a checked ``[contact]`` table, in the model's parameters."""
    from eulersym.model.contact import Contact, surface

    def get(key):
        value = table.get(key)
        if value is None:
            return None
        if isinstance(value, (tuple, list)):
            if value and isinstance(value[0], (tuple, list)):
                return [[expression(f"contact.{key}", x, mech) for x in row] for row in value]
            return tuple(expression(f"contact.{key}[{k}]", x, mech) for k, x in enumerate(value))
        return expression(f"contact.{key}", value, mech)

    shape = surface(table["surface"], radius=get("radius"), semi_axes=get("semi_axes"),
                    curvatures=get("curvatures"), centre=get("centre") or (0, 0, 0), axes=get("axes"))
    friction = {} if table["friction"] == "none" else {"mu": get("mu"), "width": get("width")}
    if table["friction"] == "none":
        for key in ("mu", "width"):
            if key in table:
                raise InvalidInput(f"contact.{key}", table[key], 'no coefficient without a friction law (friction = '
                                   '"viscous" or "coulomb")')
    return Contact(shape, mode=table["mode"], friction=table["friction"], **friction,
                   rolling_resistance=get("rolling_resistance") or 0, spin_friction=get("spin_friction") or 0)


def _read(path_or_name) -> tuple[dict, str]:
    text = str(path_or_name)
    names = bundled()
    path = names.get(text, text)
    try:
        with open(path, "rb") as f:
            return tomllib.load(f), Path(path).stem
    except FileNotFoundError:
        raise InvalidInput("SCENE", text, "a TOML file or a bundled scene: " + ", ".join(names)) from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InvalidInput("SCENE", text, f"valid TOML ({exc})") from None
    except RecursionError:
        raise InvalidInput("SCENE", text, "TOML nested less deeply: arrays or tables nested beyond the reader's "
                                          "recursion limit (about 1000 levels); a scene needs 3") from None
    except OSError as exc:
        raise InvalidInput("SCENE", text, f"a readable TOML file ({exc.strerror or exc})") from None
