"""What the user asked: a :class:`Scene` (the body, its start, the time span, the outputs), validated.

The TOML layout (every key optional unless marked; ``eulersym simulate --list`` names bundled examples to copy)::

    name = "my-scene"                    # and description = "..."
    [body]                               # exactly one of: moments | tensor | shape (+ mass and dimensions)
    moments = [I1, I2, I3]               # or tensor = [[..], [..], [..]]
    shape = "cone"                       # cube, cuboid, sphere, cylinder, cone, ellipsoid
    mass = 0.5                           # with a, b, c, R, h as the shape needs, and origin = "apex" ...
    [pivot]                              # a heavy top: centre of mass at l e3 above the pivot
    l = 0.04                             # required in [pivot]
    g = 9.81
    [torque]                             # a constant torque: body = [..] or space = [..]
    [initial]
    omega = [w1, w2, w3]                 # required; or omega_space = [..]
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

Validation raises :class:`~eulersym.errors.InvalidInput` naming the keyword (or the TOML key), the value and what
is valid. :meth:`Scene.plan` asks the pure :mod:`eulersym.scene.plan` what a run would do.
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
from eulersym.errors import InvalidInput
from eulersym.scene import model_kernel
from eulersym.scene.cost import PHASE_LIMIT, inertia_range, largest, rate_bound, refuse_phase
from eulersym.scene.catalog import bundled
from eulersym.scene.plan import SYMMETRY_RTOL, Plan, make_plan
from eulersym.scene.values import Sweep, did_you_mean as _did_you_mean, number as _number, scalar as _scalar
from eulersym.scene.values import values_of as _values, vector as _vector
from eulersym.sweeps import cost as _sweep_cost

__all__ = ["Scene", "load", "OUTPUTS", "METHODS", "SHAPES", "SHAPE_ORIGINS", "CONVENTIONS", "ACCURACY_RANGE",
           "MAGNITUDE_LIMIT", "PHASE_LIMIT", "rate_bound"]

#: The outputs a scene may ask for.
OUTPUTS = ("omega", "attitude", "euler_angles", "invariants", "polhode", "summary")
#: ``method`` values: ``auto`` lets the plan choose.
METHODS = ("auto", "closed-form", "splitting", "DOP853", "RK45", "Radau", "LSODA")
#: Named shapes a scene's body may be → their dimension names (:data:`eulersym.shapes.SHAPES`: its solids).
SHAPES = {name: _shapes.SHAPES[name] for name in ("cube", "cuboid", "sphere", "cylinder", "cone", "ellipsoid")}
#: Shapes that take ``origin=`` in a scene and its valid values (first = default; :data:`eulersym.shapes.SHAPE_ORIGINS`).
SHAPE_ORIGINS = {name: _shapes.SHAPE_ORIGINS[name] for name in ("cube", "cuboid", "cone")}
#: Euler / Tait–Bryan sequences (lower case: the text's passive, body-fixed sequence; A = A3(c) A2(b) A1(a)).
CONVENTIONS = ("zxz", "xyx", "yzy", "zyz", "xzx", "yxy", "xyz", "yzx", "zxy", "xzy", "zyx", "yxz")
#: Accuracies the plan accepts (relative error wanted on the outputs).
ACCURACY_RANGE = (1e-13, 1e-1)

_DEFAULTS = {
    "name": "scene",
    "description": "",
    "moments": None,
    "tensor": None,
    "shape": None,
    "mass": None,
    "dimensions": None,
    "origin": None,
    "l": None,
    "g": 9.81,
    "torque": None,
    "torque_frame": "body",
    "euler": None,
    "convention": "zxz",
    "quaternion": None,
    "axis": None,
    "angle": None,
    "omega": None,
    "omega_frame": "body",
    "euler_rates": None,
    "t_end": None,
    "points": 1001,
    "outputs": ("omega", "invariants"),
    "accuracy": 1e-8,
    "method": "auto",
    "model": None,
    "parameters": None,
    "memory": None,
    "work": None,
}

#: Scene keywords that describe the body the legacy way; a scene with a ``model`` takes none of them.
_BODY_KEYWORDS = ("moments", "tensor", "shape", "mass", "dimensions", "origin", "l", "g", "torque", "torque_frame")
#: TOML sections of a scene that are not the model's (a scene file is a model file plus these).
SCENE_SECTIONS = ("initial", "time", "output")
#: Sections and keys only a model expresses: their presence makes Scene.from_dict build a Model.
_MODEL_ONLY = {"": ("parameters", "rotor"), "body": ("parts", "dimensions", "L"), "pivot": ("centre_of_mass",),
               "torque": ("potential",)}

# TOML layout: section → key → Scene keyword (a tuple names a keyword and a sub-key).
_TOML_LAYOUT: dict[str, dict[str, Any]] = {
    "": {"name": "name", "description": "description"},
    "body": {
        "moments": "moments",
        "tensor": "tensor",
        "shape": "shape",
        "mass": "mass",
        "origin": "origin",
        **{d: ("dimensions", d) for d in ("a", "b", "c", "R", "h")},
    },
    "pivot": {"l": "l", "g": "g"},
    "torque": {"body": ("torque", "body"), "space": ("torque", "space")},
    "initial": {
        "omega": "omega",
        "omega_space": ("omega", "space"),
        "euler_rates": "euler_rates",
        "euler": "euler",
        "convention": "convention",
        "quaternion": "quaternion",
        "axis": "axis",
        "angle": "angle",
    },
    "time": {"end": "t_end", "points": "points"},
    "output": {"want": "outputs", "accuracy": "accuracy", "method": "method", "memory": "memory", "work": "work"},
}


#: Scene keyword → where it lives in a TOML file (for messages about keys a file lacks).
_TOML_PATHS = {
    target: (f"{section}.{key}" if section else key)
    for section, keys in _TOML_LAYOUT.items()
    for key, target in keys.items()
    if isinstance(target, str)
}


@dataclasses.dataclass(frozen=True, init=False)
class Scene:
    """A rigid-body scene: the body, its start, the time span and the outputs wanted (validated at construction).

    Parameters (keyword only)
    -------------------------
    moments : 3 numbers, optional
        Principal moments (I1, I2, I3) about the centre of mass, or about the pivot for a pivoted body.
    tensor : 3×3 numbers, optional
        A full inertia tensor in the body frame; its principal axes are found and reported.
    shape : {'cube', 'cuboid', 'sphere', 'cylinder', 'cone', 'ellipsoid'}, optional
        A named uniform body (:mod:`eulersym.inertia`) with ``mass``, ``dimensions`` (``a``, ``b``, ``c``,
        ``R``, ``h`` as the shape needs) and ``origin`` (cube/cuboid: 'center' or 'corner'; cone: 'apex' or
        'center'). Exactly one of ``moments``, ``tensor``, ``shape`` is required.
    mass : number, optional
        M; required for a shape and for a pivoted body (the gravity torque is M g l).
    l : number, optional
        A fixed pivot at distance l from the centre of mass, which sits at ``l * e3`` in the body frame
        (the heavy top). Omit for a free body.
    g : number, optional
        Gravity (default 9.81); acts only through a pivot.
    torque : 3 numbers, optional
        A constant torque, body-fixed (``torque_frame='body'``) or space-fixed (``'space'``).
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

    Any number may be a list or ``{start, stop, num}`` range: a sweep (see :class:`Sweep`).

    Examples
    --------
    >>> Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1).regime
    'torque-free'
    >>> Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_ned=1)
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: t_ned=1 is not valid: expected a Scene keyword: one of ... (did you mean 't_end'?)
    """

    name: str
    description: str
    moments: tuple | None
    tensor: tuple | None
    shape: str | None
    mass: Any
    dimensions: tuple | None
    origin: str | None
    l: Any
    g: Any
    torque: tuple | None
    torque_frame: str
    euler: tuple | None
    convention: str
    quaternion: tuple | None
    axis: tuple | None
    angle: Any
    omega: tuple
    omega_frame: str
    euler_rates: tuple | None
    t_end: float
    points: int
    outputs: tuple
    accuracy: float
    method: str
    model: Any = dataclasses.field(compare=False)
    parameters: tuple | None = None
    model_digest: str | None = dataclasses.field(init=False, default=None)
    memory: int | None = None
    work: float | None = None

    def __init__(self, **kwargs):
        for key in kwargs:
            if key not in _DEFAULTS:
                raise InvalidInput(key, kwargs[key], "a Scene keyword: " + _did_you_mean(key, _DEFAULTS))
        if kwargs.get("model") is not None:
            for key in _BODY_KEYWORDS:
                value = kwargs.get(key)
                if value is not None and not (isinstance(value, (str, float, int)) and value == _DEFAULTS[key]):
                    raise InvalidInput(key, value, "no body keyword beside a model (the model is the body: "
                                       "its mass, inertia, pivot, gravity and torques)")
        values = {**_DEFAULTS, **kwargs}
        for key, value in _normalise(values).items():
            object.__setattr__(self, key, value)
        object.__setattr__(self, "model_digest", self.model.digest if self.model is not None else None)

    # ---- constructors -------------------------------------------------------------------------------------
    @classmethod
    def from_toml(cls, path) -> "Scene":
        """Read a scene from a TOML file (the layout of the bundled scenes; see ``eulersym simulate --list``).

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
        """Build a scene from the nested mapping a TOML file holds (sections body, pivot, torque, initial, time,
        output).

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
        if _needs_model(data):
            return _model_scene(cls, data)
        kwargs: dict[str, Any] = {}
        where: dict[str, str] = {}
        top_valid = set(_TOML_LAYOUT[""]) | {s for s in _TOML_LAYOUT if s}
        for key, value in data.items():
            if key not in top_valid:
                raise InvalidInput(key, value, "a TOML section or key: " + _did_you_mean(key, top_valid))
            if key in _TOML_LAYOUT[""]:
                kwargs[_TOML_LAYOUT[""][key]] = value
                where[_TOML_LAYOUT[""][key]] = key
                continue
            if not isinstance(value, Mapping):
                raise InvalidInput(key, value, f"a [{key}] table with keys " + ", ".join(sorted(_TOML_LAYOUT[key])))
            layout = _TOML_LAYOUT[key]
            if key == "pivot":
                kwargs.setdefault("l", None)
            for sub, v in value.items():
                if sub not in layout:
                    raise InvalidInput(f"{key}.{sub}", v, f"a key of [{key}]: " + _did_you_mean(sub, layout))
                target = layout[sub]
                if isinstance(target, tuple):
                    kw, detail = target
                    if kw == "dimensions":
                        kwargs.setdefault("dimensions", {})[detail] = v
                        where[f"dimensions.{detail}"] = f"{key}.{sub}"
                        continue
                    if kw in kwargs:
                        raise InvalidInput(f"{key}.{sub}", v, f"only one of {where[kw]} and {key}.{sub}")
                    kwargs[kw] = v
                    kwargs[f"{kw}_frame"] = detail
                    where[kw] = f"{key}.{sub}"
                else:
                    kwargs[target] = v
                    where[target] = f"{key}.{sub}"
            if key == "pivot" and kwargs.get("l") is None:
                body = data.get("body")
                if isinstance(body, Mapping) and body.get("shape") is not None:
                    kwargs["l"] = FROM_SHAPE  # the pivot sits at the shape's origin: l from its centre of mass
                    where["l"] = "pivot.l"
                    continue
                raise InvalidInput("pivot.l", None, "the pivot–centre-of-mass distance l (a [pivot] table needs l, "
                                                    "unless the body is a shape: then l comes from the shape)")
        return _construct(cls, kwargs, where)

    # ---- derived facts (pure) -----------------------------------------------------------------------------
    @property
    def regime(self) -> str:
        """'torque-free', 'heavy top' or 'torque' — which equations of motion the scene needs; 'model' for a scene
        with a :class:`~eulersym.model.Model` (its plan decides, once the model's kernel is known, whether a closed
        form or the heavy top's engines apply).

        A pivot with ``M g l = 0`` and gravity without a pivot exert no torque about the reference point.

        Examples
        --------
        >>> Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, 5), t_end=1).regime
        'heavy top'
        """
        if self.model is not None:
            return "model"
        if self.l is not None and _nonzero(self.l) and _nonzero(self.g):
            return "heavy top"
        if self.torque is not None and any(_nonzero(c) for c in self.torque):
            return "torque"
        return "torque-free"

    @functools.cached_property
    def sweeps(self) -> tuple:
        """``((label, Sweep), ...)`` for every swept number, in field order.

        Examples
        --------
        >>> Scene(moments=(1, 1, 2), omega=(0, 0, [1, 2, 3]), t_end=1).sweeps
        (('omega[2]', Sweep(values=(1.0, 2.0, 3.0))),)
        """
        found = []
        for name in _FIELD_NAMES:
            value = getattr(self, name)
            if isinstance(value, Sweep):
                found.append((name, value))
            elif isinstance(value, tuple):
                for k, item in enumerate(value):
                    if isinstance(item, Sweep):
                        found.append((f"{name}[{k}]", item))
                    elif isinstance(item, tuple) and len(item) == 2 and isinstance(item[1], Sweep):
                        found.append((f"{name}.{item[0]}", item[1]))
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
        if self.model is not None:  # its plan reads the kernel cache on disk: made anew each time
            return make_plan(self, model=self.cached_model_facts())
        return dataclasses.replace(self._plan, options=dict(self._plan.options))  # a caller's change stays its own

    @functools.cached_property
    def _plan(self) -> Plan:
        """The plan of a scene without a model: a pure function of the frozen scene's fields, made once."""
        return make_plan(self)

    def parameter_values(self) -> dict:
        """A model scene's parameter values given in the scene: ``{name: float or ndarray (batch,)}`` (the kernel's
        defaults fill the others).

        Examples
        --------
        >>> Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1).parameter_values()
        {}
        """
        if not self.parameters:
            return {}
        members = self.members()
        return {name: members.get(f"parameters.{name}", value) for name, value in self.parameters}

    def cached_model_facts(self):
        """The :class:`~eulersym.scene.model_kernel.ModelFacts` of this model scene when its kernel is cached (read
        without SymPy), else None (also for a scene without a model).

        Examples
        --------
        >>> Scene(moments=(1, 2, 3), omega=(0, 1, 0), t_end=1).cached_model_facts() is None
        True
        """
        if self.model is None:
            return None
        found = model_kernel.cached(self.model_digest)
        if found is None:
            return None
        module, path = found
        return model_kernel.facts(self.model, module, path, False, self.parameter_values(), self.batch)


#: The Scene's fields, in order (what :attr:`Scene.sweeps` reads).
_FIELD_NAMES = tuple(f.name for f in dataclasses.fields(Scene))


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


def _nonzero(x) -> bool:
    """True when a (possibly swept) number is non-zero for some member."""
    if isinstance(x, (int, float)):  # one number (the common case)
        return x != 0
    return bool(np.any(_values(x) != 0))


def _needs_model(data: Mapping) -> bool:
    """True when a scene file says something only a model expresses: [parameters], [rotor], body parts, a centre
    of mass off the legacy axis, a potential, or an expression (a string where the legacy keys take numbers)."""
    if any(key in data for key in _MODEL_ONLY[""]):
        return True
    body = data.get("body")
    if isinstance(body, Mapping):
        shape, origin = body.get("shape"), body.get("origin")
        if isinstance(shape, str) and (shape not in SHAPES or (isinstance(origin, str) and origin not in SHAPE_ORIGINS.get(shape, ("center",)))):
            return shape in ("rod", "point", "cylinder")  # a model's shapes and origins (a rod, a cylinder on its base)
    for section in ("body", "pivot", "torque"):
        table = data.get(section)
        if not isinstance(table, Mapping):
            continue
        if any(key in table for key in _MODEL_ONLY[section]):
            return True
        for key, value in table.items():
            if key in ("shape", "origin"):
                continue
            if isinstance(value, str) or (isinstance(value, (list, tuple)) and any(
                    isinstance(x, str) or (isinstance(x, (list, tuple)) and any(isinstance(y, str) for y in x)) for x in value)):
                return True
    return False


def _model_scene(cls, data: Mapping):
    """A Scene with a :class:`~eulersym.model.Model` built from the file's model sections; swept parameters
    (a list or ``{start, stop, num}`` in [parameters]) stay in the scene, their first value is the model's default."""
    try:
        from eulersym.model import Model
    except ImportError as exc:  # pragma: no cover - the model package ships with eulersym
        raise InvalidInput("SCENE", dict(data), f"eulersym.model to read a model scene ({exc})") from None
    model_data = {k: v for k, v in data.items() if k not in SCENE_SECTIONS and k != "description"}
    swept = None
    params = data.get("parameters")
    if isinstance(params, Mapping):
        defaults, swept = {}, {}
        for key, value in params.items():
            if isinstance(value, (list, tuple, Mapping)):
                sweep = Sweep.of(f"parameters.{key}", value)
                defaults[key], swept[key] = sweep.values[0], sweep
            else:
                defaults[key] = value
        model_data["parameters"] = defaults
        swept = swept or None
    model = Model.from_dict(model_data)
    kwargs: dict[str, Any] = {"model": model, "parameters": swept}
    where: dict[str, str] = {"parameters": "parameters"}
    for key in ("name", "description"):
        if key in data:
            kwargs[key], where[key] = data[key], key
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


def _construct(cls, kwargs: dict, where: dict):
    """``cls(**kwargs)``, with errors renamed to the TOML keys they came from (``where``)."""
    try:
        return cls(**kwargs)
    except InvalidInput as exc:
        base = exc.argument.split("[")[0].split(".")[0]
        rest = exc.argument[len(base):]
        if exc.argument.startswith("dimensions.") and exc.argument in where:
            raise InvalidInput(where[exc.argument], exc.value, exc.expected) from None
        if exc.argument.startswith("dimensions."):  # a dimension the file lacks: it goes in [body]
            raise InvalidInput("body." + exc.argument[len("dimensions."):], exc.value, exc.expected) from None
        if base in where:
            raise InvalidInput(where[base] + rest, exc.value, exc.expected) from None
        if base in _TOML_PATHS:  # a key the file lacks: name where it would go
            raise InvalidInput(_TOML_PATHS[base] + rest, exc.value, exc.expected) from None
        raise


def _normalise(v: dict) -> dict:
    """Validate and normalise the keyword values of a Scene (raises InvalidInput naming the key)."""
    out = dict(v)
    for key in ("name", "description"):
        if not isinstance(v[key], str):
            raise InvalidInput(key, v[key], "a string")
    # ---- a model, or a body -------------------------------------------------------------------------------------
    out["parameters"] = _parameters(v["model"], v["parameters"])
    given = [k for k in ("moments", "tensor", "shape") if v[k] is not None]
    if v["model"] is not None:
        if not (hasattr(v["model"], "digest") and hasattr(v["model"], "generate")):
            raise InvalidInput("model", v["model"], "an eulersym.model.Model (Model(...), Model.from_toml(path))")
    elif not given:
        raise InvalidInput("moments", None, "a body: one of moments (I1, I2, I3), tensor (3×3) or shape (with mass and dimensions)")
    if len(given) > 1:
        raise InvalidInput(given[1], v[given[1]], f"only one body description; {given[0]} is given too")
    if v["mass"] is not None:
        out["mass"] = _scalar("mass", v["mass"], sweepable=v["shape"] is None)
        if np.any(_values(out["mass"]) <= 0):
            raise InvalidInput("mass", v["mass"], "a positive mass")
    if v["moments"] is not None:
        moments = _vector("moments", v["moments"], 3)
        _check_moments("moments", moments, v["moments"])
        out["moments"] = moments
    if v["tensor"] is not None:
        out["tensor"] = _tensor(v["tensor"])
    if v["shape"] is not None:
        out["shape"], out["dimensions"], out["origin"] = _shape(v)
    else:
        for key in ("dimensions", "origin"):
            if v[key] is not None:
                raise InvalidInput(key, v[key], "no shape dimensions or origin unless a shape is given")
    # ---- pivot, gravity, torque -----------------------------------------------------------------------------
    out["g"] = _scalar("g", v["g"])
    if np.any(_values(out["g"]) < 0):
        raise InvalidInput("g", v["g"], "gravity g >= 0 (it points down, along -z in space)")
    if v["l"] is not None and v["shape"] is not None:
        out["l"] = _pivot_on_shape(v, out)
    elif v["l"] is FROM_SHAPE:
        raise InvalidInput("l", None, "a number: the pivot–centre-of-mass distance (only a shape gives its own)")
    elif v["l"] is not None:
        out["l"] = _scalar("l", v["l"])
    if v["l"] is not None:
        if np.any(_values(out["l"]) < 0):
            raise InvalidInput("l", v["l"], "a distance l >= 0 from the pivot to the centre of mass (along +e3)")
        if out["mass"] is None:
            raise InvalidInput("mass", None, "the body's mass M: a pivoted body under gravity feels the torque M g l")
    out["torque_frame"] = validation.choice("torque_frame", v["torque_frame"], ("body", "space"))
    if v["torque"] is not None:
        out["torque"] = _vector("torque", v["torque"], 3)
    # ---- initial attitude and angular velocity ----------------------------------------------------------------
    out["convention"] = _choice("convention", v["convention"], CONVENTIONS)
    attitude = [k for k in ("euler", "quaternion", "axis") if v[k] is not None]
    if len(attitude) > 1:
        raise InvalidInput(attitude[1], v[attitude[1]], f"one attitude description; {attitude[0]} is given too")
    if v["euler"] is not None:
        out["euler"] = _vector("euler", v["euler"], 3)
    if v["quaternion"] is not None:
        q = _vector("quaternion", v["quaternion"], 4, sweepable=False)
        if math.sqrt(sum(c * c for c in q)) < 1e-12:
            raise InvalidInput("quaternion", v["quaternion"], "a non-zero quaternion (q0, q1, q2, q3), scalar first")
        out["quaternion"] = q
    if (v["axis"] is None) != (v["angle"] is None):
        missing = "angle" if v["angle"] is None else "axis"
        raise InvalidInput(missing, None, "both axis and angle for an axis–angle attitude")
    if v["axis"] is not None:
        axis = _vector("axis", v["axis"], 3, sweepable=False)
        if math.sqrt(sum(c * c for c in axis)) < 1e-12:
            raise InvalidInput("axis", v["axis"], "a non-zero rotation axis")
        out["axis"] = axis
        out["angle"] = _scalar("angle", v["angle"])
    out["omega_frame"] = validation.choice("omega_frame", v["omega_frame"], ("body", "space"))
    if v["euler_rates"] is not None:
        out["euler_rates"], out["omega"] = _omega_from_euler_rates(v, out)
    elif v["omega"] is None:
        raise InvalidInput("omega", None, "the initial angular velocity (omega = [w1, w2, w3], body components; or "
                                          "euler_rates = [phidot, thetadot, psidot] with euler = [...])")
    else:
        out["omega"] = _vector("omega", v["omega"], 3)
    # ---- time, outputs, accuracy -------------------------------------------------------------------------------
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
    if v["model"] is None:
        _check_consistency(out)  # a model's plan checks what its kernel can give
        _check_scales(out, v)
    return out


def _parameters(model, raw):
    """A model scene's parameter values: ``((name, float or Sweep), ...)`` in the given order, or None."""
    if raw is None:
        return None
    if model is None:
        raise InvalidInput("parameters", raw, "parameters only with a model (Scene(model=Model(...), parameters=...))")
    if isinstance(raw, tuple) and all(isinstance(p, tuple) and len(p) == 2 for p in raw):
        raw = dict(raw)  # the normalised form, as dataclasses.replace passes it back
    if not isinstance(raw, Mapping):
        raise InvalidInput("parameters", raw, "a mapping of parameter names to values (numbers, lists or ranges to sweep)")
    known = tuple(getattr(model, "parameters", {}) or {})
    out = []
    for name, value in raw.items():
        if not isinstance(name, str) or name not in known:
            raise InvalidInput(f"parameters.{name}", value, "a parameter of the model: " + (_did_you_mean(str(name), known) if known else "the model has none"))
        out.append((name, _scalar(f"parameters.{name}", value)))
    return tuple(out)


def _choice(argument, value, valid):
    if not isinstance(value, str) or value not in valid:
        raise InvalidInput(argument, value, _did_you_mean(str(value), valid))
    return value


def _check_moments(argument, moments, raw):
    """Every member's moments must be those of a body: positive and the triangle inequalities."""
    arrays = np.meshgrid(*[_values(m) for m in moments], indexing="ij")
    i1, i2, i3 = (a.ravel() for a in arrays)
    if np.any(i1 <= 0) or np.any(i2 <= 0) or np.any(i3 <= 0):
        raise InvalidInput(argument, raw, "three positive principal moments (I1, I2, I3)")
    scale = np.maximum(np.maximum(i1, i2), i3) * validation.TRIANGLE_SLACK
    if np.any(i1 + i2 < i3 - scale) or np.any(i2 + i3 < i1 - scale) or np.any(i3 + i1 < i2 - scale):
        raise InvalidInput(argument, raw, "principal moments of a body: I1 + I2 >= I3, I2 + I3 >= I1, I3 + I1 >= I2")


def _tensor(raw) -> tuple:
    try:
        rows = [list(r) for r in raw]
    except TypeError:
        raise InvalidInput("tensor", raw, "a 3×3 symmetric inertia tensor") from None
    if len(rows) != 3 or any(len(r) != 3 for r in rows):
        raise InvalidInput("tensor", raw, "a 3×3 symmetric inertia tensor")
    arr = np.array([[_number(f"tensor[{i}][{j}]", x) for j, x in enumerate(r)] for i, r in enumerate(rows)])
    scale = np.max(np.abs(arr))
    if not np.allclose(arr, arr.T, rtol=0, atol=1e-12 * scale):
        raise InvalidInput("tensor", raw, "a symmetric tensor (I_jk = I_kj)")
    eig = np.linalg.eigvalsh(arr)
    if eig[0] <= 1e-14 * scale:
        raise InvalidInput("tensor", raw, f"a positive-definite tensor (its principal moments are {eig.tolist()})")
    if eig[0] + eig[1] < eig[2] * (1 - validation.TRIANGLE_SLACK):
        raise InvalidInput("tensor", raw, f"the tensor of a body: principal moments {eig.tolist()} must satisfy I1 + I2 >= I3")
    return tuple(tuple(float(x) for x in r) for r in arr)


def _shape(v) -> tuple:
    shape = _choice("shape", v["shape"], tuple(SHAPES))
    if v["mass"] is None:
        raise InvalidInput("mass", None, f"the mass M of the {shape}")
    dims = dict(v["dimensions"] or {})
    wanted = SHAPES[shape]
    for key in dims:
        if key not in wanted:
            raise InvalidInput(f"dimensions.{key}", dims[key], f"a dimension of a {shape}: " + _did_you_mean(key, wanted))
    for key in wanted:
        if key not in dims:
            raise InvalidInput(f"dimensions.{key}", None, f"the {shape}'s dimension {key} (it needs {', '.join(wanted)})")
    clean = []
    for key in wanted:
        value = _scalar(f"dimensions.{key}", dims[key], sweepable=False)
        if value <= 0:
            raise InvalidInput(f"dimensions.{key}", dims[key], "a positive length")
        clean.append((key, value))
    origin = v["origin"]
    if shape in SHAPE_ORIGINS:
        origin = _choice("origin", origin if origin is not None else SHAPE_ORIGINS[shape][0], SHAPE_ORIGINS[shape])
    elif origin not in (None, "center"):
        raise InvalidInput("origin", origin, f"no origin for a {shape} (its centre is the origin)")
    else:
        origin = None
    return shape, tuple(clean), origin


def _check_consistency(out: dict) -> None:
    """Outputs and methods the scene cannot give."""
    l_vals, g_vals = (_values(out["l"]) if out["l"] is not None else np.zeros(1)), _values(out["g"])
    heavy = out["l"] is not None and np.any(l_vals != 0) and np.any(g_vals != 0)
    torqued = out["torque"] is not None and any(np.any(_values(c) != 0) for c in out["torque"])
    if heavy and torqued:
        raise InvalidInput("torque", out["torque"], "no extra torque on a pivoted heavy top (gravity is its torque)")
    if heavy or torqued:
        why = "the heavy top" if heavy else "a torqued body"
        if "polhode" in out["outputs"]:
            raise InvalidInput("outputs", "polhode", f"outputs a torque-free body has; {why} has no polhode (Poinsot's construction needs N = 0)")
        if out["method"] == "closed-form":
            raise InvalidInput("method", "closed-form", f"an integrator: eulersym has no closed form for {why}; use 'auto'")
    if torqued:
        if "invariants" in out["outputs"]:
            raise InvalidInput("outputs", "invariants", "outputs a torqued body has: a constant torque conserves neither energy nor |L|")
        if out["method"] == "splitting":
            raise InvalidInput("method", "splitting", "an integrator for a torqued body: 'auto' or a solve_ivp method")


#: ``[pivot]`` without ``l`` on a shape: the pivot is the shape's origin and l comes from its centre of mass.
FROM_SHAPE = type("FromShape", (), {"__repr__": lambda self: "<l from the shape>"})()


def _pivot_on_shape(v, out) -> float:
    """l for a shape on a pivot: the pivot is the shape's origin, and the centre of mass must lie on body axis 3
    at distance l from it (derived by :func:`eulersym.inertia.center_of_mass`); a given l must agree."""
    shape, dims, origin = out["shape"], dict(out["dimensions"]), out["origin"]
    if isinstance(v["l"], (list, tuple, Mapping, Sweep)):
        raise InvalidInput("l", v["l"], f"one number: the {shape}'s centre of mass fixes l (it cannot be swept)")
    if origin in (None, "center"):
        derived, where = 0.0, "at the origin: the shape's origin is its centre of mass"
    else:
        import sympy as sp  # a shape is derived with SymPy anyway (the plan's first step)

        from eulersym.inertia import Region, center_of_mass

        if shape == "cone":
            region = Region.cone(sp.Float(dims["R"]), sp.Float(dims["h"]))
        else:  # cube / cuboid about a corner
            a, b, c = (dims.get(k, dims.get("a")) for k in ("a", "b", "c"))
            region = Region.box((0, sp.Float(a)), (0, sp.Float(b)), (0, sp.Float(c)))
        com = [float(x) for x in center_of_mass(1, region)]
        if abs(com[0]) > 1e-12 * abs(com[2]) or abs(com[1]) > 1e-12 * abs(com[2]):
            raise InvalidInput("l", None if v["l"] is FROM_SHAPE else v["l"],
                               f"no pivot at the {origin} of a {shape}: its centre of mass "
                               f"({', '.join(f'{x:g}' for x in com)}) is not on body axis 3, and the heavy top "
                               "needs it there; give moments about the pivot instead")
        derived, where = com[2], f"{com[2]:g} from the {origin} along e3, derived from the shape"
    if v["l"] is FROM_SHAPE:
        return derived
    given = _scalar("l", v["l"], sweepable=False)
    if abs(given - derived) > 1e-9 * max(abs(derived), max(dims.values())):
        raise InvalidInput("l", v["l"], f"l = {derived:g} or no l: a {shape} pivoted at its {origin or 'center'} has "
                                        f"its centre of mass {where}; a different l contradicts the shape (for "
                                        "another body give moments about the pivot, and l)")
    return derived


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


#: Magnitudes beyond which double precision cannot carry a scene: the engines multiply two quantities of the size of
#: |L|² or the energy, and the product must stay below the largest double (1.8e308).
MAGNITUDE_LIMIT = 1e150
# the one rate bound of a scene and the phase limit live with its cost (eulersym.scene.cost: the layer below)
_largest, _inertia_range = largest, inertia_range


def _size(x: float) -> str:
    return f"≈ {x:.3g}" if math.isfinite(x) else "beyond the largest double"


def _check_scales(out: dict, raw: dict) -> None:
    """Refuse numbers whose motion double precision cannot carry, naming the real cause: an energy or |L|² beyond
    :data:`MAGNITUDE_LIMIT`, a gravity or applied torque that large, or more than :data:`PHASE_LIMIT` radians of
    rotation by t_end. (A scene in other units is the same motion: rescale time or inertia.)"""
    i_min, i_max = _inertia_range(out)
    spin = _largest(out["omega"])
    why = ("double precision (largest 1.8e308) cannot carry the products the motion needs; the same motion in "
           "other units (a larger unit of time, a smaller one of inertia) can")
    if i_max * i_max > MAGNITUDE_LIMIT:
        key = "moments" if out["moments"] is not None else ("tensor" if out["tensor"] is not None else "mass")
        raise InvalidInput(key, raw[key], f"moments of inertia below {math.sqrt(MAGNITUDE_LIMIT):.0e} (here up to "
                                          f"{i_max:.3g}): {why}")
    worst = max((i_max * spin) * (i_max * spin), i_max * spin * spin)
    if worst > MAGNITUDE_LIMIT:
        key = "euler_rates" if out.get("euler_rates") is not None else "omega"
        raise InvalidInput(key, raw[key], f"an angular velocity whose |L|² = (I ω)² and energy I ω² stay below "
                                          f"{MAGNITUDE_LIMIT:.0e} (here {_size(worst)} with |ω| = {spin:.3g} and I up "
                                          f"to {i_max:.3g}): {why}")
    if out["l"] is not None and out["mass"] is not None:
        weight = _largest(out["mass"]) * _largest(out["g"]) * _largest(out["l"])
        if weight * i_max > MAGNITUDE_LIMIT:
            raise InvalidInput("mass", raw["mass"], f"a gravity torque M g l below {MAGNITUDE_LIMIT / i_max:.3g} "
                                                    f"(here M g l ≈ {weight:.3g}): {why}")
    if out["torque"] is not None and _largest(out["torque"]) * max(i_max, 1.0) > MAGNITUDE_LIMIT:
        raise InvalidInput("torque", raw["torque"], f"a torque below {MAGNITUDE_LIMIT / max(i_max, 1.0):.3g} (here "
                                                    f"up to {_largest(out['torque']):.3g}): {why}")
    rate = rate_bound(out)
    if i_max * rate * rate > MAGNITUDE_LIMIT or (i_max * rate) * (i_max * rate) > MAGNITUDE_LIMIT:
        key = "torque" if out["torque"] is not None else "mass"
        raise InvalidInput(key, raw[key], f"a motion whose energy stays below {MAGNITUDE_LIMIT:.0e}: |ω| reaches "
                                          f"≈ {rate:.3g} by t_end = {out['t_end']:g}, so I ω² is "
                                          f"{_size(i_max * rate * rate)}: {why}")
    refuse_phase("t_end", raw["t_end"], rate, out["t_end"])


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
