"""A model's numbers per member, in NumPy: :class:`Facts` — mass, centre of mass, inertia tensor, rotor, gravity, the
constant torques, and what kind of body it is — for any parameter values, every member of a sweep at once.

:func:`facts` reads the normalised data of a :class:`~eulersym.model.spec.Model` (:meth:`Model.facts` is the entry
point). Numbers are taken as they are; an entry that names a parameter takes the parameter's values; a named shape's
tensor and centre come from the committed closed forms of :mod:`eulersym.shapes` (derived by :mod:`eulersym.inertia`,
no SymPy at run time); parts are turned into the model frame (``R I Rᵀ``, ``v_model = R v_part``) and moved to the
reference point by the parallel-axis theorem (``I + m (|d|² 1 − d dᵀ)``), as :mod:`eulersym.model.assemble` does
symbolically. SymPy comes in only where an entry is a formula beyond a number or a name (``"2*C"``): it is parsed by
the whitelist parser (never ``eval``) and evaluated on the members' arrays.

Conventions (those of :mod:`eulersym.model`): the model frame is the body frame; the tensor is about the pivot for a
pivoted body and about the centre of mass of a free one; the centre of mass is measured from the pivot (zeros for a
free body); the torques are constant when they name neither the state (``omega``, ``gamma``, ``q``) nor ``t``, body
components for ``torque.body``, space components for ``torque.space``.

Every member is checked with :mod:`eulersym.validation` (a positive mass and dimensions, ``g >= 0``, a body's tensor:
symmetric, positive definite, its principal moments obeying the triangle inequalities); messages name the model's
TOML key, the value and the member.

Examples
--------
>>> from eulersym.model import Model
>>> f = Model(parameters={"a": 0.1}, body={"moments": [1, 2, 3], "mass": 2}, pivot={"centre_of_mass": [0, 0, "a"]}
...           ).facts({"a": np.array([0.1, 0.2])})
>>> f.batch, f.regime_hint, f.centre_of_mass[:, 2].tolist(), f.tensor[0].diagonal().tolist()
(2, 'gravity', [0.1, 0.2], [1.0, 2.0, 3.0])
"""

from __future__ import annotations

import math
from typing import Any, Mapping, NamedTuple

import numpy as np

from eulersym import shapes, validation
from eulersym.errors import InvalidInput
from eulersym.model import names as N

__all__ = ["Facts", "facts", "BODY_FIELDS"]

#: The body numbers of a model's kernel ``body(*params)``, in order (what :attr:`Facts.body` holds).
BODY_FIELDS = ("M", "cx", "cy", "cz", "I11", "I12", "I13", "I21", "I22", "I23", "I31", "I32", "I33", "h1", "h2", "h3", "g")

_STATE_NAMES = frozenset({N.TIME, *N.STATE_NAMES, *N.VECTOR_NAMES, N.INERTIA})


class Facts(NamedTuple):
    """A model's numbers for every member (batch-first NumPy arrays; model frame): an immutable record (a
    NamedTuple, made at import in a tenth of a frozen dataclass's time: every scene imports it).

    Attributes
    ----------
    mass : ndarray (batch,)
        Total mass M (0 for a free body given by its moments or tensor without a mass).
    centre_of_mass : ndarray (batch, 3)
        From the pivot (zeros for a free body).
    tensor : ndarray (batch, 3, 3)
        The inertia tensor about the pivot (pivoted) or the centre of mass (free), model frame.
    rotor : ndarray (batch, 3)
        The constant angular momentum h of an internal rotor, body components (zeros without one).
    g : ndarray (batch,)
        Gravity (0 without a pivot).
    torque_body, torque_space : ndarray (batch, 3) or None
        Constant torques, body and space components (None where the model gives none, or gives one that varies).
    pivoted : bool
    torque : str
        ``"none"``, ``"constant"`` (``torque_body``/``torque_space`` hold it) or ``"varying"`` (it names the state or
        ``t``: only the model's own equations carry it).
    potential : bool
        A potential energy besides gravity's.
    given : str
        How the body is described: ``"moments"``, ``"tensor"``, ``"shape"`` or ``"parts"``.
    turning : bool
        The reference frame turns (``[frame] rate``): its kinematics live only in the model's own equations.
    contact : bool
        The body rolls or slides on the plane (``[contact]``): its own regime, the contact kernel integrates it.

    Examples
    --------
    >>> from eulersym.model import Model
    >>> f = Model(body={"shape": "cone", "mass": 1.0, "R": 0.1, "h": 0.4}, pivot={}).facts()
    >>> f.centre_of_mass.tolist(), f.given  # 3h/4 above the apex
    ([[0.0, 0.0, 0.30000000000000004]], 'shape')
    """

    mass: np.ndarray
    centre_of_mass: np.ndarray
    tensor: np.ndarray
    rotor: np.ndarray
    g: np.ndarray
    torque_body: np.ndarray | None
    torque_space: np.ndarray | None
    pivoted: bool
    torque: str
    potential: bool
    given: str
    turning: bool = False
    contact: bool = False

    @property
    def batch(self) -> int:
        """The number of members."""
        return len(self.mass)

    @property
    def has_rotor(self) -> bool:
        """True when some member has a rotor momentum h ≠ 0."""
        return bool(np.any(self.rotor != 0))

    @property
    def weight(self) -> np.ndarray:
        """M g |c| per member: the largest gravity torque about the pivot (0 for a free body)."""
        return self.mass * self.g * np.linalg.norm(self.centre_of_mass, axis=1)

    @property
    def regime_hint(self) -> str:
        """What acts on the body, read from the facts alone: ``"free"`` (nothing), ``"gravity"`` (gravity through
        the pivot alone), ``"constant torque"`` (a constant torque alone, body- or space-fixed) or ``"other"`` (a
        varying torque, a potential, a rotor, gravity with a torque, body- and space-fixed torques together).

        Examples
        --------
        >>> from eulersym.model import Model
        >>> Model(body={"moments": [1, 2, 3]}, torque={"body": [0, 0, 0.5]}).facts().regime_hint
        'constant torque'
        """
        if self.torque == "varying" or self.potential or self.has_rotor or self.turning or self.contact:
            return "other"
        heavy = self.pivoted and bool(np.any(self.weight != 0))
        given = [v for v in (self.torque_body, self.torque_space) if v is not None and bool(np.any(v != 0))]
        torqued = self.torque == "constant" and bool(given)
        if (heavy and torqued) or len(given) == 2:  # gravity and a torque, or body- and space-fixed torques at once
            return "other"
        return "gravity" if heavy else ("constant torque" if torqued else "free")

    @property
    def body(self) -> dict:
        """``{name: ndarray (batch,)}`` for :data:`BODY_FIELDS` (the layout of a model kernel's ``body()``).

        Examples
        --------
        >>> from eulersym.model import Model
        >>> Model(body={"moments": [1, 2, 3]}).facts().body["I33"].tolist()
        [3.0]
        """
        T = self.tensor.reshape(-1, 9)
        out = {"M": self.mass, "cx": self.centre_of_mass[:, 0], "cy": self.centre_of_mass[:, 1],
               "cz": self.centre_of_mass[:, 2]}
        out.update({name: T[:, k] for k, name in enumerate(BODY_FIELDS[4:13])})
        out.update({"h1": self.rotor[:, 0], "h2": self.rotor[:, 1], "h3": self.rotor[:, 2], "g": self.g})
        return out

    def take(self, lo: int, hi: int) -> "Facts":
        """The facts of members ``lo:hi``.

        Examples
        --------
        >>> from eulersym.model import Model
        >>> Model(parameters={"m": 1.0}, body={"moments": [1, 2, 3], "mass": "m"}).facts(
        ...     {"m": np.array([1.0, 2.0, 3.0])}).take(1, 3).mass.tolist()
        [2.0, 3.0]
        """
        return self._replace(**{name: value[lo:hi] for name, value in self._asdict().items()
                                if isinstance(value, np.ndarray)})


# ---- entries: a number, a parameter's name, or a formula ------------------------------------------------------------


class _Reader:
    """Evaluates a model's entries for every member: ``values`` maps each parameter to a float or an array (batch,)."""

    def __init__(self, parameters: list, values: Mapping, batch: int):
        self.parameters = [name for name, _ in parameters]
        self.values = {name: values.get(name, default) for name, default in parameters}
        self.batch = batch
        self._sympy = None

    def scalar(self, key: str, value) -> Any:
        """A float or an array (batch,)."""
        if not isinstance(value, str):
            return float(value)
        text = value.strip()
        if text in self.values:  # a parameter by its name: its values
            return self.values[text]
        return self._formula(key, text)

    def vector(self, key: str, value) -> list:
        """Three entries (each a float or an array)."""
        if isinstance(value, str):
            return self._formula(key, value.strip(), vector=True)
        return [self.scalar(f"{key}[{i}]", v) for i, v in enumerate(value)]

    def _formula(self, key: str, text: str, vector: bool = False):
        """A formula of the parameters, parsed by the whitelist parser (SymPy) and evaluated on the members."""
        import sympy as sp

        from eulersym.model.expressions import namespace, parse

        if self._sympy is None:
            self._sympy = {name: sp.Symbol(name, real=True) for name in self.parameters}
        expr = parse(text, namespace(self._sympy, state=False, time=False), argument=key,
                     shape="vector" if vector else "scalar")
        values = {self._sympy[name]: self.values[name] for name in self.parameters}
        try:
            if vector:
                return [_numeric(e, values) for e in expr]
            return _numeric(expr, values)
        except _NotNumeric as exc:  # named by the TOML key, as the user wrote it
            raise InvalidInput(key, text, f"a real formula of +, -, *, /, powers and the parser's functions (here "
                                          f"{exc.args[0]})") from None


_FUNCTIONS = {
    "sin": np.sin, "cos": np.cos, "tan": np.tan, "asin": np.arcsin, "acos": np.arccos, "atan": np.arctan,
    "sinh": np.sinh, "cosh": np.cosh, "tanh": np.tanh, "exp": np.exp, "log": np.log, "Abs": np.abs,
    "sign": np.sign, "cot": lambda x: 1.0 / np.tan(x), "sec": lambda x: 1.0 / np.cos(x),
    "csc": lambda x: 1.0 / np.sin(x),
}


def _numeric(expr, values: Mapping):
    """A SymPy expression of the parameter symbols evaluated on floats or arrays, by its tree (no code is made)."""
    if expr.is_Number or expr.is_NumberSymbol:
        return float(expr)
    if expr.is_Symbol:
        return values[expr]
    args = [_numeric(a, values) for a in expr.args]
    if expr.is_Add:
        total = args[0]
        for a in args[1:]:
            total = total + a
        return total
    if expr.is_Mul:
        product = args[0]
        for a in args[1:]:
            product = product * a
        return product
    if expr.is_Pow:
        return np.power(args[0], args[1])
    name = type(expr).__name__
    if name in _FUNCTIONS:
        return _FUNCTIONS[name](*args)
    if name == "atan2":
        return np.arctan2(*args)
    if name in ("Min", "Max"):
        out = args[0]
        for a in args[1:]:
            out = (np.minimum if name == "Min" else np.maximum)(out, a)
        return out
    raise _NotNumeric("the imaginary unit" if name == "ImaginaryUnit" else str(expr))


class _NotNumeric(Exception):
    """A part of a formula that has no real value on floats (the caller names the key)."""


def _column(x, batch: int) -> np.ndarray:
    """A float or an array as an array (batch,)."""
    if isinstance(x, float):  # a number (the common case): one member, or the same for all
        return np.array([x]) if batch == 1 else np.full(batch, x)
    return np.broadcast_to(np.asarray(x, dtype=float), (batch,)).copy() if np.ndim(x) else np.full(batch, float(x))


def _positive(key: str, raw, x, batch: int, what: str = "a positive number", zero: bool = False) -> np.ndarray:
    if isinstance(x, float) and math.isfinite(x) and (x >= 0 if zero else x > 0):  # a valid number: no array check
        return _column(x, batch)
    values = _column(x, batch)
    bad = ~np.isfinite(values) | ((values < 0) if zero else (values <= 0))
    if bad.any():
        member = int(np.argmax(bad))
        where = f" (member {member}: {values[member]:g})" if batch > 1 or isinstance(raw, str) else ""
        raise InvalidInput(key, raw, what + where)
    return values


# ---- rotations of parts (active: v_model = R v_part) -----------------------------------------------------------------


def _rotation(reader: _Reader, key: str, orientation, batch: int) -> np.ndarray | None:
    """R (batch, 3, 3) of a part's orientation, or None for an unturned part."""
    if orientation is None:
        return None
    from scipy.spatial.transform import Rotation  # only for turned parts

    if "quaternion" in orientation:
        q = np.stack([_column(reader.scalar(f"{key}.quaternion[{i}]", c), batch)
                      for i, c in enumerate(orientation["quaternion"])], axis=1)
        norm = np.linalg.norm(q, axis=1)
        if np.any(norm == 0):
            raise InvalidInput(f"{key}.quaternion", orientation["quaternion"], "a non-zero quaternion")
        return Rotation.from_quat(q[:, [1, 2, 3, 0]] / norm[:, None]).as_matrix()
    if "euler" in orientation:
        angles = np.stack([_column(a, batch) for a in reader.vector(f"{key}.euler", orientation["euler"])], axis=1)
        return Rotation.from_euler(orientation["convention"].upper(), angles).as_matrix()
    axis = np.stack([_column(a, batch) for a in reader.vector(f"{key}.axis", orientation["axis"])], axis=1)
    norm = np.linalg.norm(axis, axis=1)
    if np.any(norm == 0):
        raise InvalidInput(f"{key}.axis", orientation["axis"], "a non-zero axis")
    angle = _column(reader.scalar(f"{key}.angle", orientation["angle"]), batch)
    return Rotation.from_rotvec(axis / norm[:, None] * angle[:, None]).as_matrix()


def _diagonal(entries, batch: int) -> np.ndarray:
    T = np.zeros((batch, 3, 3))
    for k in range(3):
        T[:, k, k] = entries[k]
    return T


def _matrix(reader: _Reader, key: str, rows, batch: int) -> np.ndarray:
    T = np.empty((batch, 3, 3))
    for i, row in enumerate(rows):
        for j, x in enumerate(reader.vector(f"{key}[{i}]", row)):
            T[:, i, j] = x
    return T


def _shape(reader: _Reader, key: str, table: dict, batch: int, origin: str):
    """(mass (batch,), tensor about ``origin`` (batch, 3, 3), centre from the shape's own origin (batch, 3))."""
    mass = _positive(f"{key}.mass", table["mass"], reader.scalar(f"{key}.mass", table["mass"]), batch,
                     "a positive mass")
    dims = [_positive(f"{key}.{d}", raw, reader.scalar(f"{key}.{d}", raw), batch, "a positive length")
            for d, raw in table["dimensions"].items()]
    T = np.broadcast_to(shapes.tensor(table["shape"], origin, mass, dims), (batch, 3, 3))
    c = np.broadcast_to(shapes.centre(table["shape"], table["origin"], dims), (batch, 3))
    return mass, np.array(T), np.array(c)


def _part(reader: _Reader, key: str, part: dict, batch: int):
    """(mass, tensor about its centre of mass in the model frame, position of its centre of mass) of one part."""
    if "shape" in part:
        m, I_cm, offset = _shape(reader, key, part, batch, "center")
    else:
        m = _positive(f"{key}.mass", part["mass"], reader.scalar(f"{key}.mass", part["mass"]), batch, "a positive mass")
        kind = "moments" if "moments" in part else "tensor"
        I_cm = (_diagonal(reader.vector(f"{key}.moments", part["moments"]), batch) if kind == "moments"
                else _matrix(reader, f"{key}.tensor", part["tensor"], batch))
        validation.inertia_tensor(f"{key}.{kind}", I_cm, shown=part[kind])
        offset = np.zeros((batch, 3))
    position = np.stack([_column(x, batch) for x in reader.vector(f"{key}.position",
                                                                  part.get("position", [0.0, 0.0, 0.0]))], axis=1)
    R = _rotation(reader, f"{key}.orientation", part.get("orientation"), batch)
    if R is None:
        return m, I_cm, position + offset
    return m, np.einsum("bij,bjk,blk->bil", R, I_cm, R), position + np.einsum("bij,bj->bi", R, offset)


def _parallel(I: np.ndarray, m: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The tensor about a point at ``-d`` from the centre of mass: ``I + m (|d|² 1 − d dᵀ)``."""
    return I + m[:, None, None] * (np.einsum("bi,bi->b", d, d)[:, None, None] * np.eye(3) - d[:, :, None] * d[:, None, :])


# ---- the facts ----------------------------------------------------------------------------------------------------------


def _batch(values: Mapping) -> int:
    sizes = {len(v) for v in values.values() if np.ndim(v) == 1}
    if len(sizes) > 1:
        raise InvalidInput("values", {k: np.shape(v) for k, v in values.items()},
                           "parameter values of one length (the members of one sweep)")
    return sizes.pop() if sizes else 1


def facts(data: dict, values: Mapping | None = None, batch: int | None = None) -> Facts:
    """The :class:`Facts` of a model's normalised data for parameter ``values`` (name → float or array (batch,);
    the defaults fill the others). See :meth:`eulersym.model.Model.facts`."""
    values = dict(values or {})
    known = {name for name, _ in data["parameters"]}
    for name in values:
        if name not in known:
            raise InvalidInput(f"parameters.{name}", values[name], "a parameter of the model: "
                               + (", ".join(sorted(known)) or "the model has none"))
    batch = _batch(values) if batch is None else int(batch)
    reader = _Reader(data["parameters"], values, batch)
    body, pivot = data["body"], data["pivot"]
    pivoted = pivot is not None
    if "parts" in body:
        parts = [_part(reader, f"body.parts[{i}]", part, batch) for i, part in enumerate(body["parts"])]
        mass = sum(m for m, _, _ in parts)
        centre = sum(m[:, None] * p for m, _, p in parts) / mass[:, None]
        reference = np.zeros((batch, 3)) if pivoted else centre
        tensor = sum(_parallel(I, m, p - reference) for m, I, p in parts)
        validation.inertia_tensor("body", tensor)
        given = "parts"
    elif "shape" in body:
        mass, tensor, centre = _shape(reader, "body", body, batch, body["origin"] if pivoted else "center")
        validation.inertia_tensor("body", tensor)
        given = "shape"
    else:
        given = "moments" if "moments" in body else "tensor"
        if given == "moments":
            entries = [_column(x, batch) for x in reader.vector("body.moments", body["moments"])]
            if batch == 1:  # one body: the check on floats
                validation.moments("body.moments", tuple(float(e[0]) for e in entries), shown=body["moments"])
            else:
                validation.moments("body.moments", np.stack(entries, axis=1), shown=body["moments"])
            tensor = _diagonal(entries, batch)
        else:
            tensor = _matrix(reader, "body.tensor", body["tensor"], batch)
            validation.inertia_tensor("body.tensor", tensor, shown=body["tensor"])
        raw = body.get("mass")
        mass = (np.zeros(batch) if raw is None else
                _positive("body.mass", raw, reader.scalar("body.mass", raw), batch, "a positive mass"))
        centre = np.zeros((batch, 3))
    if pivoted:
        if given in ("moments", "tensor") and pivot["centre_of_mass"] is not None:
            key = "pivot.l" if pivot.get("l") else "pivot.centre_of_mass"
            centre = np.stack([_column(x, batch) for x in reader.vector(key, pivot["centre_of_mass"])], axis=1)
        g = _positive("pivot.g", pivot["g"], reader.scalar("pivot.g", pivot["g"]), batch, "g >= 0", zero=True)
    else:
        centre, g = np.zeros((batch, 3)), np.zeros(batch)
    rotor = (np.zeros((batch, 3)) if data["rotor"] is None else
             np.stack([_column(x, batch) for x in reader.vector("rotor.h", data["rotor"])], axis=1))
    torque, constant = "none", {}
    for frame in ("body", "space"):
        raw = data["torque"][frame]
        if raw is None:
            continue
        texts = [raw] if isinstance(raw, str) else [x for x in raw if isinstance(x, str)]
        if any(name in _STATE_NAMES for text in texts for name in N.names_in(text)):
            torque = "varying"
            continue
        constant[frame] = np.stack([_column(x, batch) for x in reader.vector(f"torque.{frame}", raw)], axis=1)
    if torque != "varying" and constant:
        torque = "constant"
    return Facts(
        mass=mass,
        centre_of_mass=centre,
        tensor=tensor,
        rotor=rotor,
        g=g,
        torque_body=constant.get("body") if torque == "constant" else None,
        torque_space=constant.get("space") if torque == "constant" else None,
        pivoted=pivoted,
        torque=torque,
        potential=data["torque"]["potential"] is not None,
        given=given,
    )
