"""What the user asked: a :class:`Scene` — a :class:`~eulersym.model.Model` (the body: what it is and what acts on
it), its start, the time span and the outputs wanted.

A scene file is a model file (:mod:`eulersym.model.spec`: ``name``, ``[parameters]``, ``[body]``, ``[pivot]``,
``[torque]``, ``[rotor]``) plus the scene's own sections; one reader takes both halves, and the model validates the
body (its errors name the TOML key)::

    name = "my-scene"                    # and description = "..."
    [body]                               # the model's: moments | tensor | shape (+ mass and dimensions) | parts
    moments = [I1, I2, I3]
    mass = 0.5
    [pivot]                              # a heavy top: centre of mass at l e3 above the pivot (or centre_of_mass)
    l = 0.04
    g = 9.81
    [torque]                             # body = [..] or space = [..]: numbers, or formulas of the parameters
    [initial]
    omega = [w1, w2, w3]                 # required; or omega_space = [..]; or euler_rates = [..] with euler
    euler = [phi, theta, psi]            # and convention = "zxz"; or quaternion = [..]; or axis = [..], angle = ..
    [time]
    end = 10.0                           # required, > 0
    points = 1001
    [output]
    want = ["omega", "invariants"]       # omega, attitude, euler_angles, invariants, polhode; summary (per member)
    accuracy = 1e-8
    method = "auto"                      # auto, closed-form, splitting, DOP853, RK45, Radau, LSODA
    memory = "2 GiB"                     # budgets: refused beyond them, with the estimate (eulersym.scene.cost)
    work = 5e10                          # kernel evaluations summed over members

The keyword constructor takes the same body the short way (``Scene(moments=..., mass=..., l=..., g=...,
torque=...)``) and builds the same model from it. Any number of the scene's start, and the body's moments, mass,
``l``, ``g`` and torque components, may be a list or a range ``{start, stop, num}``: a sweep. A swept body number
becomes a parameter of the model (its first value the default), so the model's facts give every member's body at
once (:meth:`~eulersym.model.Model.facts`); a model's own parameters are swept in ``[parameters]``.

Validation raises :class:`~eulersym.errors.InvalidInput` naming the keyword (or the TOML key), the value and what
is valid; the body is validated by the model, every member of a sweep by its facts. :meth:`Scene.plan` asks the pure
:mod:`eulersym.scene.plan` what a run would do.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import numbers
import os
import tomllib
from typing import Any, Mapping

import numpy as np

from eulersym import shapes as _shapes, validation
from eulersym.attitude import SEQUENCES
from eulersym.errors import InvalidInput
from eulersym.model.spec import MODEL_SECTIONS, Model
from eulersym.scene.catalog import bundled
from eulersym.scene.cost import PHASE_LIMIT, rate_bound, rate_of, refuse_phase, spread_of
from eulersym.scene.plan import Plan, make_plan
from eulersym.scene.regime import Regime, classify
from eulersym.scene.values import Sweep, did_you_mean as _did_you_mean, number as _number, scalar as _scalar
from eulersym.scene.values import values_of as _values, vector as _vector
from eulersym.sweeps import cost as _sweep_cost

__all__ = ["Scene", "load", "OUTPUTS", "METHODS", "SHAPES", "SHAPE_ORIGINS", "CONVENTIONS", "ACCURACY_RANGE",
           "MAGNITUDE_LIMIT", "PHASE_LIMIT", "rate_bound", "SCENE_SECTIONS"]

#: The outputs a scene may ask for.
OUTPUTS = ("omega", "attitude", "euler_angles", "invariants", "polhode", "summary")
#: ``method`` values: ``auto`` lets the plan choose.
METHODS = ("auto", "closed-form", "splitting", "DOP853", "RK45", "Radau", "LSODA")
#: Named shapes a body may be → their dimension names (:data:`eulersym.shapes.SHAPES`).
SHAPES = dict(_shapes.SHAPES)
#: Shapes that take an ``origin`` and its valid values (first = default; :data:`eulersym.shapes.SHAPE_ORIGINS`).
SHAPE_ORIGINS = dict(_shapes.SHAPE_ORIGINS)
#: Euler / Tait–Bryan sequences (lower case: the text's passive, body-fixed sequence; A = A3(c) A2(b) A1(a)).
CONVENTIONS = SEQUENCES
#: Accuracies the plan accepts (relative error wanted on the outputs).
ACCURACY_RANGE = (1e-13, 1e-1)
#: TOML sections of a scene that are not the model's (a scene file is a model file plus these).
SCENE_SECTIONS = ("initial", "time", "output")
#: Magnitudes beyond which double precision cannot carry a scene: the methods multiply two quantities of the size of
#: |L|² or the energy, and the product must stay below the largest double (1.8e308).
MAGNITUDE_LIMIT = 1e150

#: The body's keywords: the short way to write a model (a scene with ``model=`` takes none of them).
_BODY_DEFAULTS = {"moments": None, "tensor": None, "shape": None, "mass": None, "dimensions": None, "origin": None,
                  "l": None, "g": 9.81, "torque": None, "torque_frame": "body"}
_DEFAULTS = {
    "name": "scene",
    "description": "",
    **_BODY_DEFAULTS,
    "euler": None,
    "convention": "zxz",
    "quaternion": None,
    "axis": None,
    "angle": None,
    "omega": None,
    "omega_frame": "body",
    "euler_rates": None,
    "position": None,
    "velocity": None,
    "t_end": None,
    "points": 1001,
    "outputs": ("omega", "invariants"),
    "accuracy": 1e-8,
    "method": "auto",
    "model": None,
    "parameters": None,
    "memory": None,
    "work": None,
    "quantities": None,
}

# TOML layout of the scene's own sections: section → key → Scene keyword (a tuple names a keyword and a frame).
_TOML_LAYOUT: dict[str, dict[str, Any]] = {
    "": {"name": "name", "description": "description"},
    "initial": {
        "omega": "omega",
        "omega_space": ("omega", "space"),
        "euler_rates": "euler_rates",
        "euler": "euler",
        "convention": "convention",
        "quaternion": "quaternion",
        "axis": "axis",
        "angle": "angle",
        "position": "position",
        "velocity": "velocity",
    },
    "time": {"end": "t_end", "points": "points"},
    "output": {"want": "outputs", "accuracy": "accuracy", "method": "method", "memory": "memory", "work": "work",
               "quantities": "quantities"},
}
#: Scene keyword → where it lives in a TOML file (for messages about keys a file lacks).
_TOML_PATHS = {target: (f"{section}.{key}" if section else key) for section, keys in _TOML_LAYOUT.items()
               for key, target in keys.items() if isinstance(target, str)}
#: Where a body number may be swept in a file or by a keyword: (section, key, components) → its label.
_SWEEPABLE = (("body", "moments", 3, "moments"), ("body", "mass", 0, "mass"), ("pivot", "l", 0, "l"),
              ("pivot", "g", 0, "g"), ("torque", "body", 3, "torque"), ("torque", "space", 3, "torque"))


@dataclasses.dataclass(frozen=True, init=False)
class Scene:
    """A rigid-body scene: a :class:`~eulersym.model.Model`, its start, the time span and the outputs wanted
    (validated at construction).

    Parameters (keyword only)
    -------------------------
    model : eulersym.model.Model, optional
        The body and what acts on it. Or, the short way, the body's keywords below (a scene takes one or the other):
    moments : 3 numbers, optional
        Principal moments (I1, I2, I3) about the centre of mass, or about the pivot for a pivoted body.
    tensor : 3×3 numbers, optional
        A full inertia tensor in the body frame; its principal axes are found and reported.
    shape : str, optional
        A named uniform body (:data:`SHAPES`: cube, cuboid, sphere, cylinder, cone, ellipsoid, rod) with ``mass``,
        ``dimensions`` (``a``, ``b``, ``c``, ``R``, ``h``, ``L`` as the shape needs) and ``origin`` (cube/cuboid:
        'center' or 'corner'; cone: 'apex' or 'center'; cylinder 'center' or 'base'; rod 'center' or 'end').
        Exactly one of ``moments``, ``tensor``, ``shape`` is required.
    mass : number, optional
        M; required for a shape and for a pivoted body (the gravity torque is M g l).
    l : number, optional
        A fixed pivot with the centre of mass at ``l * e3`` in the body frame (the heavy top); for a shape the
        pivot is its origin and ``l`` must be the distance its centre of mass derives. Omit for a free body.
    g : number, optional
        Gravity (default 9.81); acts only through a pivot.
    torque : 3 numbers, optional
        A constant torque, body-fixed (``torque_frame='body'``) or space-fixed (``'space'``).
    parameters : mapping name → number, list or range, optional
        Values of the model's parameters (lists and ranges: a sweep); the model's defaults fill the others.
    euler, convention : optional
        Initial Euler angles (phi, theta, psi) in one of :data:`CONVENTIONS` (default 'zxz', the text's).
    quaternion : 4 numbers, optional
        Initial attitude as a unit quaternion (normalised here). Or ``axis`` and ``angle`` (radians).
    omega : 3 numbers
        Initial angular velocity, body components (``omega_frame='space'`` for space components).
    euler_rates : 3 numbers, optional
        Instead of ``omega``: the initial Euler-angle rates (φ̇, θ̇, ψ̇) in the scene's ``convention``, with the
        angles ``euler``; converted to body ω by the derived kinematics (the committed kernel
        ``eulersym.generated.kinematics`` for 'zxz', the same composition of elementary rotations for the other
        sequences), numerically, without SymPy.
    position, velocity : 2 or 3 numbers, optional
        A body on a plane (a model with ``[contact]``; ``[initial] position``/``velocity`` in a file): its centre of
        mass's start in space, ``(x, y)`` (default the origin; ``(x, y, z)``: z must be the height at which it
        touches), and, sliding, its velocity ``(v_x, v_y)`` (default 0; rolling, it is fixed by ω and must equal
        it if given). Checked when the run starts: it touches the plane, presses on it (N > 0), and does not slip.
    t_end : number
        End time (> 0); outputs at ``points`` evenly spaced times from 0 to t_end (default 1001).
    outputs : sequence of str
        Any of :data:`OUTPUTS` (default ('omega', 'invariants')).
    accuracy : number
        Relative accuracy wanted (default 1e-8).
    method : str
        One of :data:`METHODS` (default 'auto': the plan chooses).
    memory, work : optional
        Budgets (:mod:`eulersym.scene.cost`): bytes (``"2 GiB"``; default the smaller of 2 GiB and half the memory
        available) and kernel evaluations (default 5e10); a sweep beyond one is refused before anything is
        allocated. With ``"summary"`` among the outputs, the others are kept as per-member summaries only.
    name, description : str
        For reports.

    Any number of the start (and the body's moments, mass, l, g and torque) may be a list or ``{start, stop, num}``
    range: a sweep (see :class:`Sweep`).

    A scene is frozen: ``dataclasses.replace(scene, t_end=..., omega=...)`` builds a validated new one that keeps the
    model; to change the body, give a new ``model=`` (or build the scene anew from the keywords). The body's keywords
    read back as properties (``scene.moments``, ``scene.mass``, ``scene.l``...) from the model.

    Examples
    --------
    >>> Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1).regime
    'torque-free'
    >>> Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1).model.to_dict()
    {'name': 'scene', 'body': {'moments': [1.0, 2.0, 3.0]}}
    >>> Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_ned=1)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: t_ned=1 is not valid: expected a Scene keyword: one of ... (did you mean 't_end'?)
    """

    name: str
    description: str
    model: Model
    parameters: tuple
    euler: tuple | None
    convention: str
    quaternion: tuple | None
    axis: tuple | None
    angle: Any
    omega: tuple
    omega_frame: str
    euler_rates: tuple | None
    position: tuple | None
    velocity: tuple | None
    t_end: float
    points: int
    outputs: tuple
    accuracy: float
    method: str
    memory: int | None = None
    work: float | None = None

    def __init__(self, **kwargs):
        for key in kwargs:
            if key not in _DEFAULTS:
                raise InvalidInput(key, kwargs[key], "a Scene keyword: " + _did_you_mean(key, _DEFAULTS))
        values = {**_DEFAULTS, **kwargs}
        for key in ("name", "description"):
            if not isinstance(values[key], str):
                raise InvalidInput(key, values[key], "a string")
        if values["model"] is not None:
            model = values["model"]
            if not isinstance(model, Model):
                raise InvalidInput("model", model, "an eulersym.model.Model (Model(...), Model.from_toml(path))")
            for key, default in _BODY_DEFAULTS.items():
                value = values[key]
                if value is not None and not (isinstance(value, (str, float, int)) and value == default):
                    raise InvalidInput(key, value, "no body keyword beside a model (the model is the body: its mass, "
                                                   "inertia, pivot, gravity and torques)")
            rename = None
        else:
            if values["parameters"] is not None and not _synthetic_only(values["parameters"]):
                raise InvalidInput("parameters", values["parameters"], "parameters only with a model "
                                                                       "(Scene(model=Model(...), parameters=...))")
            model, swept = _keyword_model(values)
            values["parameters"] = tuple(swept)
            kind = next((k for k in ("moments", "tensor", "shape") if values[k] is not None), None)
            rename = functools.partial(_keyword_name, body_kind=kind)
        if values["quantities"] is not None:
            try:
                model = _with_quantities(model, values["quantities"], values["convention"])
            except InvalidInput as exc:
                raise _renamed(exc, rename) from None
        object.__setattr__(self, "model", model)
        object.__setattr__(self, "name", values["name"])
        object.__setattr__(self, "description", values["description"])
        object.__setattr__(self, "parameters", _parameters(model, values["parameters"]))
        for key, value in _normalise(values).items():
            object.__setattr__(self, key, value)
        try:
            regime = self._regime  # every member's body, validated by the model's facts
        except InvalidInput as exc:
            raise _renamed(exc, rename) from None
        try:
            _check_consistency(self, regime)
            _check_scales(self, regime, values)
            if self.method == "closed-form":
                self.plan()  # a closed form asked for where none applies is refused now, with the reason
        except InvalidInput as exc:
            raise _renamed(exc, rename) from None

    # ---- constructors -------------------------------------------------------------------------------------
    @classmethod
    def from_toml(cls, path) -> "Scene":
        """Read a scene from a TOML file (a model file plus ``[initial]``, ``[time]``, ``[output]``; see
        ``eulersym simulate --list`` and ``--template``).

        Errors name the TOML key (``section.key``).

        Examples
        --------
        >>> scene = Scene.from_toml(bundled()["tennis-racket"])
        >>> scene.name, scene.regime
        ('tennis-racket', 'torque-free')
        """
        path = os.fspath(path)
        try:
            with open(path, "rb") as handle:
                data = tomllib.load(handle)
        except FileNotFoundError:
            raise InvalidInput("SCENE", path, "an existing TOML file or a bundled scene name: " + ", ".join(sorted(bundled()))) from None
        except tomllib.TOMLDecodeError as exc:
            raise InvalidInput("SCENE", path, f"valid TOML ({exc})") from None
        except (IsADirectoryError, PermissionError, UnicodeDecodeError) as exc:
            raise InvalidInput("SCENE", path, f"a readable TOML file ({exc.__class__.__name__})") from None
        except RecursionError:
            raise InvalidInput("SCENE", path, "TOML nested less deeply: arrays or tables nested beyond the reader's "
                                              "recursion limit (about 1000 levels); a scene needs 3") from None
        except OSError as exc:
            raise InvalidInput("SCENE", path, f"a readable TOML file ({exc.strerror or exc})") from None
        return cls.from_dict(data)

    @classmethod
    def from_dict(cls, data: Mapping) -> "Scene":
        """Build a scene from the nested mapping a TOML file holds: the model's sections (``name``,
        ``[parameters]``, ``[body]``, ``[pivot]``, ``[torque]``, ``[rotor]``) and the scene's (``description``,
        ``[initial]``, ``[time]``, ``[output]``).

        Examples
        --------
        >>> Scene.from_dict({"body": {"moments": [1, 1, 2]}, "initial": {"omega": [0.1, 0, 1]},
        ...                  "time": {"end": 5}}).regime
        'torque-free'
        >>> Scene.from_dict({"body": {"moments": [1, 1, 2]}, "intial": {}})
        Traceback (most recent call last):
        ...
        eulersym.errors.InvalidInput: intial={} is not valid: expected a TOML section or key: ... (did you mean 'initial'?)
        """
        if not isinstance(data, Mapping):
            raise InvalidInput("SCENE", data, "a mapping of TOML sections (body, pivot, torque, initial, time, output)")
        valid = {"name", "description", *MODEL_SECTIONS, *SCENE_SECTIONS}
        for key, value in data.items():
            if key not in valid:
                raise InvalidInput(str(key), value, "a TOML section or key: " + _did_you_mean(str(key), valid))
        sections = {key: _plain(value) for key, value in data.items() if key in ("name", *MODEL_SECTIONS)}
        sections, swept = _swept_numbers(sections, lambda label: label)
        given = sections.get("parameters")
        user = None
        if isinstance(given, Mapping):  # a list or range in [parameters]: a sweep of the model's parameter
            defaults, user = {}, {}
            for key, value in given.items():
                if isinstance(value, (list, tuple, Mapping)):
                    sweep = Sweep.of(f"parameters.{key}", value)
                    defaults[key], user[key] = sweep.values[0], sweep
                else:
                    defaults[key] = value
            sections["parameters"] = {**defaults, **{name: sweep.values[0] for name, sweep, _ in swept}}
        elif swept:
            sections["parameters"] = {name: sweep.values[0] for name, sweep, _ in swept}
        model = Model.from_dict(sections)
        kwargs: dict[str, Any] = {"model": model, "parameters": (*_user_entries(user), *swept)}
        where: dict[str, str] = {"parameters": "parameters"}
        if "description" in data:
            kwargs["description"], where["description"] = data["description"], "description"
        if "name" in data:
            kwargs["name"], where["name"] = data["name"], "name"
        for section in SCENE_SECTIONS:
            table = data.get(section)
            if table is None:
                continue
            if not isinstance(table, Mapping):
                raise InvalidInput(section, table, f"a [{section}] table with keys " + ", ".join(sorted(_TOML_LAYOUT[section])))
            layout = _TOML_LAYOUT[section]
            for sub, value in table.items():
                if sub not in layout:
                    raise InvalidInput(f"{section}.{sub}", value, f"a key of [{section}]: " + _did_you_mean(sub, layout))
                target = layout[sub]
                if isinstance(target, tuple):
                    kw, detail = target
                    if kw in kwargs:
                        raise InvalidInput(f"{section}.{sub}", value, f"only one of {where[kw]} and {section}.{sub}")
                    kwargs[kw], kwargs[f"{kw}_frame"] = value, detail
                    where[kw] = f"{section}.{sub}"
                else:
                    kwargs[target], where[target] = value, f"{section}.{sub}"
        return _construct(cls, kwargs, where)

    # ---- the body (read from the model) ---------------------------------------------------------------------
    @functools.cached_property
    def facts(self):
        """The model's :class:`~eulersym.model.facts.Facts` for every distinct body of the scene (one row per
        member of the grid of swept parameters, :meth:`body_index` maps members to rows), in NumPy.

        Examples
        --------
        >>> Scene(moments=(1, 2, [3, 2.5]), omega=(0, [1, 2], 0), t_end=1).facts.tensor[:, 2, 2].tolist()
        [3.0, 2.5]
        """
        grids = _grid([sweep.values for _, sweep, _ in self._swept_parameters])
        values = {name: value for name, value, _ in self.parameters if not isinstance(value, Sweep)}
        values.update({name: grid for (name, _, _), grid in zip(self._swept_parameters, grids)})
        return self.model.facts(values, batch=len(grids[0]) if grids else 1)

    @functools.cached_property
    def _regime(self) -> Regime:
        return classify(self.facts)

    @functools.cached_property
    def _rate(self) -> float:
        """The scene's one rate bound (:func:`eulersym.scene.cost.rate_bound`), computed once."""
        return rate_of(self)

    @functools.cached_property
    def _spread(self) -> tuple:
        """(smallest, largest) principal moment over the distinct bodies, computed once."""
        return spread_of(self)

    @property
    def regime(self) -> str:
        """'torque-free', 'heavy top', 'torque' (a constant torque) or 'model' (the model's own kernel integrates
        it) — what acts on the body, read from its facts (:func:`eulersym.scene.regime.classify`).

        A pivot with ``M g l = 0`` and gravity without a pivot exert no torque about the reference point.

        Examples
        --------
        >>> Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, 5), t_end=1).regime
        'heavy top'
        """
        return self._regime.regime

    @property
    def model_digest(self) -> str:
        """The model's digest (its kernel's key in the cache)."""
        return self.model.digest

    def body_index(self) -> np.ndarray | None:
        """For each member, its row of :attr:`facts` (None when every member has the one body).

        Examples
        --------
        >>> Scene(moments=(1, 2, [3, 2.5]), omega=(0, [1, 2], 0), t_end=1).body_index().tolist()
        [0, 0, 1, 1]
        """
        swept = self._swept_parameters
        if not swept:
            return None
        sizes = [len(s) for _, s in self.sweeps]
        index = np.indices(sizes).reshape(len(sizes), -1)
        labels = [label for label, _ in self.sweeps]
        rows = np.zeros(index.shape[1], dtype=np.intp)
        for _, sweep, label in swept:
            k = labels.index(label)
            rows = rows * len(sweep) + index[k]
        return rows

    @property
    def _swept_parameters(self) -> tuple:
        return tuple(entry for entry in self.parameters if isinstance(entry[1], Sweep))

    # the body's keywords, read back from the model (None where the model does not say it that way)
    @property
    def moments(self) -> tuple | None:
        """The principal moments as given (numbers, or a :class:`Sweep` where swept), or None."""
        return self._read("body", "moments")

    @property
    def tensor(self) -> tuple | None:
        """The tensor as given, or None."""
        rows = self.model.normalised["body"].get("tensor")
        return None if rows is None else tuple(tuple(row) for row in rows)

    @property
    def shape(self) -> str | None:
        """The named shape, or None."""
        return self.model.normalised["body"].get("shape")

    @property
    def dimensions(self) -> tuple | None:
        """The shape's dimensions as ``((name, value), ...)``, or None."""
        dims = self.model.normalised["body"].get("dimensions")
        return None if dims is None else tuple(dims.items())

    @property
    def origin(self) -> str | None:
        """The shape's origin, or None."""
        return self.model.normalised["body"].get("origin")

    @property
    def mass(self):
        """The body's mass as given (a number, a :class:`Sweep`), derived for parts; None for a free body given
        without one."""
        body = self.model.normalised["body"]
        if "parts" in body:
            return float(self.facts.mass[0])
        return self._read("body", "mass")

    @property
    def l(self):
        """The pivot–centre-of-mass distance along e3 (as given, or derived for a shape), or None without a pivot
        or with the centre of mass off e3."""
        pivot = self.model.normalised["pivot"]
        if pivot is None:
            return None
        if pivot.get("l"):
            return self._read("pivot", "l")
        c = self.facts.centre_of_mass[0]
        return float(c[2]) if c[0] == 0.0 and c[1] == 0.0 else None

    @property
    def g(self):
        """Gravity as given (9.81 without a pivot)."""
        pivot = self.model.normalised["pivot"]
        return 9.81 if pivot is None else self._read("pivot", "g")

    @property
    def torque(self) -> tuple | None:
        """The constant torque's components as given (body or space: :attr:`torque_frame`), or None."""
        torque = self.model.normalised["torque"]
        frame = self.torque_frame
        return None if torque[frame] is None else self._read("torque", frame)

    @property
    def torque_frame(self) -> str:
        """'space' for a space-fixed torque, else 'body'."""
        torque = self.model.normalised["torque"]
        return "space" if torque["space"] is not None and torque["body"] is None else "body"

    def _read(self, section: str, key: str):
        """A body keyword's value from the model's data: numbers as they are, a parameter by its value (the
        scene's sweep or number, else the model's default)."""
        table = self.model.normalised[section] or {}
        raw = (table.get("centre_of_mass") or [None] * 3)[2] if (section, key) == ("pivot", "l") else table.get(key)
        given = {name: value for name, value, _ in self.parameters}

        def one(x):
            return given.get(x, self.model.parameters.get(x, x)) if isinstance(x, str) else x

        return tuple(one(x) for x in raw) if isinstance(raw, list) else one(raw)

    # ---- sweeps, times ----------------------------------------------------------------------------------------
    @functools.cached_property
    def sweeps(self) -> tuple:
        """``((label, Sweep), ...)`` for every swept number: the body's first, then the start's, then the model's
        parameters.

        Examples
        --------
        >>> Scene(moments=(1, 1, 2), omega=(0, 0, [1, 2, 3]), t_end=1).sweeps
        (('omega[2]', Sweep(values=(1.0, 2.0, 3.0))),)
        """
        found = [(label, value) for name, value, label in self.parameters
                 if isinstance(value, Sweep) and not label.startswith("parameters.")]
        for name in _START_FIELDS:
            value = getattr(self, name)
            if isinstance(value, Sweep):
                found.append((name, value))
            elif isinstance(value, tuple):
                found.extend((f"{name}[{k}]", item) for k, item in enumerate(value) if isinstance(item, Sweep))
        found.extend((label, value) for name, value, label in self.parameters
                     if isinstance(value, Sweep) and label.startswith("parameters."))
        return tuple(found)

    @property
    def batch(self) -> int:
        """Number of members (1 without sweeps)."""
        return int(np.prod([len(s) for _, s in self.sweeps])) if self.sweeps else 1

    def members(self) -> dict:
        """``{label: array (batch,)}``: each swept number's value for every member (outer-product grid, 'ij').

        Examples
        --------
        >>> m = Scene(moments=(1, 1, 2), omega=([0.1, 0.2], 0, [1, 2, 3]), t_end=1).members()
        >>> m["omega[0]"].tolist(), m["omega[2]"].tolist()
        ([0.1, 0.1, 0.1, 0.2, 0.2, 0.2], [1.0, 2.0, 3.0, 1.0, 2.0, 3.0])
        """
        sweeps = self.sweeps
        if not sweeps:
            return {}
        grids = np.meshgrid(*[np.asarray(s.values) for _, s in sweeps], indexing="ij")
        return {label: g.ravel() for (label, _), g in zip(sweeps, grids)}

    @property
    def times(self) -> np.ndarray:
        """The output times, ``linspace(0, t_end, points)``.

        Examples
        --------
        >>> Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=2, points=5).times.tolist()
        [0.0, 0.5, 1.0, 1.5, 2.0]
        """
        return _evenly_spaced(self.t_end, self.points)

    def parameter_values(self) -> dict:
        """The model's parameter values the scene gives (its sweeps per member, the numbers it sets):
        ``{name: float or ndarray (batch,)}`` (the model's defaults fill the others).

        Examples
        --------
        >>> Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1).parameter_values()
        {}
        >>> Scene(moments=(1, 2, [3, 2.5]), omega=(0, 1, 0), t_end=1).parameter_values()["moments_2"].tolist()
        [3.0, 2.5]
        """
        if not self.parameters:
            return {}
        members = self.members()
        return {name: members.get(label, value) for name, value, label in self.parameters}

    # ---- the plan ------------------------------------------------------------------------------------------------
    def plan(self) -> Plan:
        """What :func:`simulate` will derive, emit, integrate and skip, and why (pure: runs nothing).

        Examples
        --------
        >>> print(Scene(moments=(2, 2, 1), omega=(0.3, 0, 5), t_end=1, outputs=("omega",)).plan())
        plan for 'scene' (torque-free, symmetric body)
          closed form  ω(t) by eulersym.numerics.free_rigid_body_exact — two equal moments (a symmetric top): ...
          skip         inertia derivation — principal moments are given
          skip         the heavy top (Lagrangian, equations of motion, its kernels) — no pivot under gravity: ...
          skip         integration — a closed form exists for torque-free motion
          skip         attitude propagation — no output needs the attitude; Euler's equations with N = 0 close on ω alone
          skip         Euler angles — not asked for
          skip         invariants — not asked for
        """
        if self.regime == "model":  # its plan reads the kernel cache on disk: made anew each time
            return make_plan(self)
        options = {k: dict(v) if isinstance(v, dict) else v for k, v in self._plan.options.items()}
        return dataclasses.replace(self._plan, options=options)  # a caller's change stays its own

    @functools.cached_property
    def _plan(self) -> Plan:
        """The plan of a scene whose model needs no kernel of its own: a pure function of the frozen scene, made once."""
        return make_plan(self)


def _with_quantities(model: Model, quantities, convention) -> Model:
    """The scene's model with the scene's own quantities (``Scene(quantities=...)``, ``[output] quantities``) added to
    any the model defines: they are emitted into the model's kernel, so they belong to the model (its digest keys the
    cached kernel). ``phi``, ``theta``, ``psi`` follow the table's ``convention``, else the model's own quantities'
    (their meaning is kept), else the scene's; a table naming another than the model's own is refused by key."""
    if not isinstance(quantities, Mapping):
        raise InvalidInput("quantities", quantities, 'a table of name = "expression" (or {expression, unit})')
    if not quantities:
        return model  # nothing to add
    data = model.to_dict()
    own = dict(data.get("quantities", {}))
    taken = sorted(set(own) & set(quantities) - {"convention"})
    if taken:
        raise InvalidInput(f"quantities.{taken[0]}", quantities[taken[0]], "a name the model's [quantities] does not "
                                                                           "already define")
    if own:  # the model's quantities keep their convention (zxz unless they name one)
        theirs = own.get("convention", "zxz")
        asked = quantities.get("convention", theirs)
        if asked != theirs:
            raise InvalidInput("quantities.convention", asked, f"the convention of the model's own [quantities] "
                                                               f"({theirs!r}): phi, theta, psi have one meaning in a "
                                                               f"kernel")
    elif "convention" not in quantities and isinstance(convention, str):
        own["convention"] = convention
    own.update(quantities)
    return Model.from_dict({**data, "quantities": own})


#: The fields of a scene's start that may be swept, in order (what :attr:`Scene.sweeps` reads after the body's).
_START_FIELDS = ("euler", "convention", "quaternion", "axis", "angle", "omega", "omega_frame", "euler_rates",
                 "t_end", "points")


def _grid(values: list) -> list:
    """The 'ij' outer-product grid of the value lists, flattened (one array per list)."""
    if not values:
        return []
    return [g.ravel() for g in np.meshgrid(*[np.asarray(v) for v in values], indexing="ij")]


def _evenly_spaced(t_end: float, points: int) -> np.ndarray:
    """``np.linspace(0.0, t_end, points)``, bit for bit, without its general machinery (array conversions, dtype
    and axis handling): ``k · (t_end / (points − 1))`` for k < points − 1, then ``t_end`` itself — NumPy's own
    arithmetic for a positive scalar span; linspace itself where its step underflows to 0 or points < 2.

    Examples
    --------
    >>> _evenly_spaced(1.0, 3).tolist(), _evenly_spaced(0.3, 4).tolist() == np.linspace(0.0, 0.3, 4).tolist()
    ([0.0, 0.5, 1.0], True)
    """
    end = float(t_end)
    if points < 2 or not end > 0.0:
        return np.linspace(0.0, end, points)
    step = end / (points - 1)
    if step == 0.0:  # a subnormal span: linspace divides first (NumPy gh-5437)
        return np.linspace(0.0, end, points)
    times = np.arange(points, dtype=np.float64)
    times *= step
    times[-1] = end
    return times


# ---- the body's keywords → a model ------------------------------------------------------------------------------


def _synthetic_only(raw) -> bool:
    """True for the normalised parameters of a keyword scene (every entry a swept body number)."""
    return isinstance(raw, tuple) and all(isinstance(e, tuple) and len(e) == 3 and not e[2].startswith("parameters.")
                                          for e in raw)


def _parameter_name(label: str) -> str:
    """The model parameter a swept body number becomes: ``moments[2]`` → ``moments_2``, ``mass`` → ``mass``."""
    return label.replace("[", "_").replace("]", "")


def _plain(value):
    """A copy of nested TOML data (mappings and lists), so that sweeps can be taken out of it."""
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_plain(v) for v in value]
    return value


def _swept_numbers(sections: dict, label_of) -> tuple:
    """``(sections, [(parameter, Sweep, label), ...])``: every list or range at a place a body number may be swept
    (:data:`_SWEEPABLE`) replaced by a parameter's name."""
    swept = []
    for section, key, n, label in _SWEEPABLE:
        table = sections.get(section)
        if not isinstance(table, dict) or key not in table:
            continue
        value = table[key]
        if n == 0:
            if isinstance(value, (list, tuple, Mapping, Sweep)):
                sweep = value if isinstance(value, Sweep) else Sweep.of(f"{section}.{key}", value)
                name = _parameter_name(label)
                table[key] = name
                swept.append((name, sweep, label_of(label)))
            continue
        if isinstance(value, (list, tuple)) and len(value) == n:
            items = list(value)
            for k, item in enumerate(items):
                if isinstance(item, (list, tuple, Mapping, Sweep)):
                    sweep = item if isinstance(item, Sweep) else Sweep.of(f"{section}.{key}[{k}]", item)
                    name = _parameter_name(f"{label}[{k}]")
                    items[k] = name
                    swept.append((name, sweep, label_of(f"{label}[{k}]")))
            table[key] = items
    return sections, swept


def _user_entries(user) -> tuple:
    return tuple((name, sweep, f"parameters.{name}") for name, sweep in (user or {}).items())


def _keyword_model(v: dict) -> tuple:
    """``(Model, [(parameter, Sweep, label), ...])`` of the body keywords, errors naming the keyword."""
    given = [k for k in ("moments", "tensor", "shape") if v[k] is not None]
    if not given:
        raise InvalidInput("moments", None, "a body: one of moments (I1, I2, I3), tensor (3×3) or shape (with mass "
                                            "and dimensions)")
    if len(given) > 1:
        raise InvalidInput(given[1], v[given[1]], f"only one body description; {given[0]} is given too")
    body: dict = {}
    if v["moments"] is not None:
        body["moments"] = list(_vector("moments", v["moments"], 3))
    if v["tensor"] is not None:
        body["tensor"] = _rows(v["tensor"])
    if v["shape"] is not None:
        body["shape"] = v["shape"]
        dims = v["dimensions"]
        if dims is not None:
            if isinstance(dims, Mapping):
                body.update({str(k): d for k, d in dims.items()})
            else:
                body.update({str(k): d for k, d in dims})
        if v["origin"] is not None:
            body["origin"] = v["origin"]
    else:
        for key in ("dimensions", "origin"):
            if v[key] is not None:
                raise InvalidInput(key, v[key], "no shape dimensions or origin unless a shape is given")
    if v["mass"] is not None:
        body["mass"] = _scalar("mass", v["mass"])
    sections: dict = {"name": v["name"] if isinstance(v["name"], str) and v["name"].strip() else "scene",
                      "body": body}
    if v["l"] is not None:
        sections["pivot"] = {"l": _scalar("l", v["l"]), "g": _scalar("g", v["g"])}
    elif v["shape"] in _shapes.SHAPES and (body.get("origin") or _shapes.origins(v["shape"])[0]) != "center":
        # a shape measured from another origin, without a pivot: it turns about that point, weightless
        sections["pivot"] = {"g": 0.0}
        _scalar("g", v["g"])
    elif v["g"] is not None:
        _scalar("g", v["g"])  # validated even without a pivot (where it acts on nothing)
    frame = validation.choice("torque_frame", v["torque_frame"], ("body", "space"))
    if v["torque"] is not None:
        sections["torque"] = {frame: list(_vector("torque", v["torque"], 3))}
    sections, swept = _swept_numbers(sections, lambda label: label)
    if v["l"] is None and isinstance(v["g"], (list, tuple, Mapping, Sweep)):  # a swept g without a pivot: no effect
        swept.append(("g", _scalar("g", v["g"]), "g"))
    if swept:
        sections["parameters"] = {name: sweep.values[0] for name, sweep, _ in swept}
    try:
        model = Model(**sections)
    except InvalidInput as exc:
        kind = next(k for k in ("moments", "tensor", "shape") if v[k] is not None)
        raise _renamed(exc, functools.partial(_keyword_name, body_kind=kind)) from None
    return model, swept


def _rows(raw) -> list:
    try:
        rows = [list(r) for r in raw]
    except TypeError:
        raise InvalidInput("tensor", raw, "a 3×3 symmetric inertia tensor") from None
    if len(rows) != 3 or any(len(r) != 3 for r in rows):
        raise InvalidInput("tensor", raw, "a 3×3 symmetric inertia tensor")
    return [[_number(f"tensor[{i}][{j}]", x) for j, x in enumerate(r)] for i, r in enumerate(rows)]


#: A model's TOML key → the Scene keyword that wrote it.
_KEYWORD_OF = {"body.moments": "moments", "body.tensor": "tensor", "body.shape": "shape", "body.origin": "origin",
               "body.mass": "mass", "body.dimensions": "dimensions", "pivot.l": "l", "pivot.centre_of_mass": "l",
               "pivot.g": "g", "torque.body": "torque", "torque.space": "torque", "pivot": "l", "torque": "torque"}


def _keyword_name(argument: str, body_kind: str | None = None) -> str:
    """The Scene keyword of a model key (``body.moments[1]`` → ``moments[1]``, ``body.a`` → ``dimensions.a``)."""
    base, _, rest = argument.partition("[")
    rest = "[" + rest if rest else ""
    if base in _KEYWORD_OF:
        return _KEYWORD_OF[base] + rest
    if base.startswith("body.dimensions."):
        return "dimensions." + base[len("body.dimensions."):]
    if base.startswith("body.") and base[5:] in ("a", "b", "c", "R", "h", "L"):
        return "dimensions." + base[5:]
    if base == "body":
        return (body_kind or "moments") + rest
    return argument


def _renamed(exc: InvalidInput, rename) -> InvalidInput:
    """``exc`` with its argument renamed (a keyword scene's errors name its keywords, not the model's keys)."""
    if rename is None or type(exc) is not InvalidInput:
        return exc
    return InvalidInput(rename(exc.argument), exc.value, exc.expected)


def _parameters(model, raw) -> tuple:
    """A scene's parameter values: ``((name, float or Sweep, label), ...)`` in the given order."""
    if raw is None:
        return ()
    if isinstance(raw, tuple) and all(isinstance(p, tuple) and len(p) in (2, 3) for p in raw):
        entries = [(p[0], p[1], p[2] if len(p) == 3 else f"parameters.{p[0]}") for p in raw]  # the normalised form
    elif isinstance(raw, Mapping):
        entries = [(name, value, f"parameters.{name}") for name, value in raw.items()]
    else:
        raise InvalidInput("parameters", raw, "a mapping of parameter names to values (numbers, lists or ranges to sweep)")
    known = tuple(model.parameters)
    out = []
    for name, value, label in entries:
        if not isinstance(name, str) or name not in known:
            raise InvalidInput(f"parameters.{name}", value, "a parameter of the model: " + (
                _did_you_mean(str(name), known) if known else "the model has none"))
        argument = label if not label.startswith("parameters.") else f"parameters.{name}"
        out.append((name, _scalar(argument, value), label))
    return tuple(out)


def _construct(cls, kwargs: dict, where: dict):
    """``cls(**kwargs)``, with errors renamed to the TOML keys they came from (``where``)."""
    try:
        return cls(**kwargs)
    except InvalidInput as exc:
        base = exc.argument.split("[")[0].split(".")[0]
        rest = exc.argument[len(base):]
        if base in where:
            raise InvalidInput(where[base] + rest, exc.value, exc.expected) from None
        if base in _TOML_PATHS:  # a key the file lacks: name where it would go
            raise InvalidInput(_TOML_PATHS[base] + rest, exc.value, exc.expected) from None
        raise


def _choice(argument, value, valid):
    if not isinstance(value, str) or value not in valid:
        raise InvalidInput(argument, value, _did_you_mean(str(value), valid))
    return value


def _normalise(v: dict) -> dict:
    """Validate and normalise the scene's own keyword values: the start, the times, the outputs (InvalidInput
    naming the key)."""
    out = {}
    out["convention"] = _choice("convention", v["convention"], CONVENTIONS)
    attitude = [k for k in ("euler", "quaternion", "axis") if v[k] is not None]
    if len(attitude) > 1:
        raise InvalidInput(attitude[1], v[attitude[1]], f"one attitude description; {attitude[0]} is given too")
    out["euler"] = _vector("euler", v["euler"], 3) if v["euler"] is not None else None
    out["quaternion"] = None
    if v["quaternion"] is not None:
        q = _vector("quaternion", v["quaternion"], 4, sweepable=False)
        if math.sqrt(sum(c * c for c in q)) < 1e-12:
            raise InvalidInput("quaternion", v["quaternion"], "a non-zero quaternion (q0, q1, q2, q3), scalar first")
        out["quaternion"] = q
    if (v["axis"] is None) != (v["angle"] is None):
        missing = "angle" if v["angle"] is None else "axis"
        raise InvalidInput(missing, None, "both axis and angle for an axis–angle attitude")
    out["axis"] = out["angle"] = None
    if v["axis"] is not None:
        axis = _vector("axis", v["axis"], 3, sweepable=False)
        if math.sqrt(sum(c * c for c in axis)) < 1e-12:
            raise InvalidInput("axis", v["axis"], "a non-zero rotation axis")
        out["axis"] = axis
        out["angle"] = _scalar("angle", v["angle"])
    out["omega_frame"] = validation.choice("omega_frame", v["omega_frame"], ("body", "space"))
    for key in ("position", "velocity"):  # a body on a plane: its centre of mass in space, (x, y) or (x, y, z)
        value = v[key]
        if value is not None and (isinstance(value, (str, Mapping)) or not hasattr(value, "__len__")
                                  or len(value) not in (2, 3)):
            raise InvalidInput(key, value, f"the centre of mass's {key} in space: [x, y] or [x, y, z] (a body on a "
                               "plane)")
        out[key] = None if value is None else tuple(_vector(key, list(value), len(value), sweepable=False))
    out["euler_rates"] = None
    if v["euler_rates"] is not None:
        out["euler_rates"], out["omega"] = _omega_from_euler_rates(v, out)
    elif v["omega"] is None:
        raise InvalidInput("omega", None, "the initial angular velocity (omega = [w1, w2, w3], body components; or "
                                          "euler_rates = [phidot, thetadot, psidot] with euler = [...])")
    else:
        out["omega"] = _vector("omega", v["omega"], 3)
    if v["t_end"] is None:
        raise InvalidInput("t_end", None, "the end time t_end > 0")
    out["t_end"] = _scalar("t_end", v["t_end"], sweepable=False)
    if out["t_end"] <= 0:
        raise InvalidInput("t_end", v["t_end"], "an end time t_end > 0")
    points = v["points"]
    if isinstance(points, bool) or not isinstance(points, numbers.Integral) or not 2 <= points <= 10_000_000:
        raise InvalidInput("points", points, "an integer number of output times, 2 <= points <= 10**7")
    out["points"] = int(points)
    outputs = v["outputs"]
    if isinstance(outputs, str):
        outputs = (outputs,)
    if not isinstance(outputs, (list, tuple)) or not outputs:
        raise InvalidInput("outputs", outputs, "a non-empty list of: " + ", ".join(OUTPUTS))
    for name in outputs:
        if name not in OUTPUTS:
            raise InvalidInput("outputs", name, "an output: " + _did_you_mean(str(name), OUTPUTS))
    out["outputs"] = tuple(dict.fromkeys(outputs))
    accuracy = _scalar("accuracy", v["accuracy"], sweepable=False)
    if not ACCURACY_RANGE[0] <= accuracy <= ACCURACY_RANGE[1]:
        raise InvalidInput("accuracy", v["accuracy"], f"a relative accuracy between {ACCURACY_RANGE[0]:g} and {ACCURACY_RANGE[1]:g}")
    out["accuracy"] = accuracy
    out["method"] = _choice("method", v["method"], METHODS)
    out["memory"] = None if v["memory"] is None else _sweep_cost.parse_size("memory", v["memory"])
    out["work"] = None if v["work"] is None else _sweep_cost.parse_work("work", v["work"])
    return out


def _omega_from_euler_rates(v, out) -> tuple:
    """(euler_rates, body ω) from the initial angles and their rates, by the derived kinematics (no SymPy)."""
    if v["omega"] is not None:
        raise InvalidInput("euler_rates", v["euler_rates"], "one initial angular velocity: euler_rates or omega, "
                                                            "not both")
    if out["omega_frame"] != "body":
        raise InvalidInput("euler_rates", v["euler_rates"], "one initial angular velocity: euler_rates or "
                                                            "omega_space, not both")
    if out.get("euler") is None:
        raise InvalidInput("euler_rates", v["euler_rates"], "initial Euler angles too (euler = [phi, theta, psi]): "
                                                            "the rates give ω only together with the angles")
    rates = _vector("euler_rates", v["euler_rates"], 3, sweepable=False)
    if any(isinstance(a, Sweep) for a in out["euler"]):
        raise InvalidInput("euler_rates", v["euler_rates"], "single Euler angles (not swept) with euler_rates; "
                                                            "sweep omega instead")
    from eulersym.scene.rates import omega_body

    omega = omega_body(out["euler"], rates, out["convention"])
    return rates, tuple(float(w) for w in omega)


def _check_consistency(scene, regime: Regime) -> None:
    """Methods the scene's regime cannot give (read from its facts)."""
    kind = regime.regime
    for key in ("position", "velocity"):
        if getattr(scene, key) is not None and kind != "contact":
            raise InvalidInput(key, list(getattr(scene, key)), f"no {key} for a body without [contact] (the centre of "
                               "mass of a body on a plane)")
    if kind == "contact" and scene.method not in ("auto", "DOP853"):
        raise InvalidInput("method", scene.method, "'auto' or 'DOP853' for a body on a plane (eulersym's DOP853 on "
                           "the contact kernel, watching the normal force for lift-off)")
    if kind == "torque-free":
        return
    why = {"heavy top": "the heavy top", "torque": "a torqued body"}.get(kind, f"the model {scene.model.name!r}")
    if scene.method == "closed-form" and kind != "heavy top":
        raise InvalidInput("method", "closed-form", f"an integrator: eulersym has no closed form for {why} (it is not "
                                                    "torque-free); use 'auto'")
    if scene.method == "splitting" and kind in ("torque", "model"):
        raise InvalidInput("method", "splitting", f"an integrator {why} allows: 'auto' or a solve_ivp method (no "
                                                  "splitting for its torques)")


def _size(x: float) -> str:
    return f"≈ {x:.3g}" if math.isfinite(x) else "beyond the largest double"


def _check_scales(scene, regime: Regime, raw: dict) -> None:
    """Refuse numbers whose motion double precision cannot carry, naming the real cause: an energy or |L|² beyond
    :data:`MAGNITUDE_LIMIT`, a gravity or applied torque that large, or more than :data:`PHASE_LIMIT` radians of
    rotation by t_end. (A scene in other units is the same motion: rescale time or inertia.)"""
    facts = scene.facts
    i_max = scene._spread[1]
    spin = _largest(scene.omega)
    why = ("double precision (largest 1.8e308) cannot carry the products the motion needs; the same motion in "
           "other units (a larger unit of time, a smaller one of inertia) can")
    body = scene.model.normalised["body"]
    key = next((f"body.{k}" for k in ("moments", "tensor") if k in body), "body.mass" if "mass" in body else "body")
    if i_max * i_max > MAGNITUDE_LIMIT:
        raise InvalidInput(key, body.get(key[5:]), f"moments of inertia below {math.sqrt(MAGNITUDE_LIMIT):.0e} (here "
                                                   f"up to {i_max:.3g}): {why}")
    worst = max((i_max * spin) * (i_max * spin), i_max * spin * spin)
    if worst > MAGNITUDE_LIMIT:
        key_w = "euler_rates" if scene.euler_rates is not None else "omega"
        raise InvalidInput(key_w, raw[key_w], f"an angular velocity whose |L|² = (I ω)² and energy I ω² stay below "
                                              f"{MAGNITUDE_LIMIT:.0e} (here {_size(worst)} with |ω| = {spin:.3g} and I "
                                              f"up to {i_max:.3g}): {why}")
    weight = float(np.max(facts.weight))
    if weight * i_max > MAGNITUDE_LIMIT:
        raise InvalidInput("body.mass", body.get("mass"), f"a gravity torque M g l below {MAGNITUDE_LIMIT / i_max:.3g} "
                                                          f"(here M g l ≈ {weight:.3g}): {why}")
    torque = max((float(np.max(np.abs(t))) for t in (facts.torque_body, facts.torque_space) if t is not None),
                 default=0.0)
    if torque * max(i_max, 1.0) > MAGNITUDE_LIMIT:
        frame = "body" if facts.torque_body is not None else "space"
        raise InvalidInput(f"torque.{frame}", scene.model.normalised["torque"][frame],
                           f"a torque below {MAGNITUDE_LIMIT / max(i_max, 1.0):.3g} (here up to {torque:.3g}): {why}")
    rate = rate_bound(scene)
    if i_max * rate * rate > MAGNITUDE_LIMIT or (i_max * rate) * (i_max * rate) > MAGNITUDE_LIMIT:
        key_r = "torque.body" if torque else "body.mass"
        raise InvalidInput(key_r, raw.get(key_r[key_r.index(".") + 1:]) if torque else body.get("mass"),
                           f"a motion whose energy stays below {MAGNITUDE_LIMIT:.0e}: |ω| reaches ≈ {rate:.3g} by "
                           f"t_end = {scene.t_end:g}, so I ω² is {_size(i_max * rate * rate)}: {why}")
    refuse_phase("t_end", raw["t_end"], rate, scene.t_end)


def _largest(x) -> float:
    if x is None:
        return 0.0
    if isinstance(x, (int, float)):
        return abs(float(x))
    if isinstance(x, tuple):
        return max((_largest(c) for c in x), default=0.0)
    return float(np.max(np.abs(_values(x))))


def load(scene) -> Scene:
    """A Scene from a Scene, a TOML path, or a bundled scene's name.

    Examples
    --------
    >>> load("tennis-racket").regime
    'torque-free'
    >>> load("tenis-racket")
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: SCENE='tenis-racket' is not valid: expected a TOML file or a bundled scene: ... (did you mean 'tennis-racket'?)
    """
    if isinstance(scene, Scene):
        return scene
    text = os.fspath(scene)
    names = bundled()
    if text in names:
        return Scene.from_toml(names[text])
    if os.path.exists(text) or text.endswith(".toml"):
        return Scene.from_toml(text)
    raise InvalidInput("SCENE", text, "a TOML file or a bundled scene: " + _did_you_mean(text, names))
