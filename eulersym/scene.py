"""Scenes: describe a body and what you want to know; eulersym derives, emits and integrates only that.

A :class:`Scene` says *what*: the body (principal moments, a full inertia tensor, or a named shape with mass and
dimensions), an optional fixed pivot with the centre of mass at distance ``l`` along body axis 3 (the heavy top),
gravity ``g``, an optional constant torque (body- or space-fixed), the initial attitude (Euler angles in a named
convention, a unit quaternion, or axis–angle) and angular velocity (body or space components), the end time, the
outputs wanted and the accuracy wanted. :meth:`Scene.plan` says *how* — which derivations and kernels are needed and
no others, a closed form wherever one exists, otherwise the integrator expected to meet the accuracy at least
cost — and what is skipped, and why. :func:`simulate` runs the plan and returns a :class:`Result`.

Conventions (as everywhere in eulersym). The attitude is the unit quaternion q = (q0, q1, q2, q3), scalar first,
whose active rotation R(q) maps body components to space components, ``v_space = R(q) @ v_body``; the text's
passive matrix is ``A = R(q).T`` so that ``r_body = A @ r_space``, and for the default convention ``"zxz"``
``A = B(psi) C(theta) D(phi)``. Angular velocity is in body components unless a name says ``space``. The body-frame
upward vertical is ``Gamma = A @ (0, 0, 1)``, and ``Gamma3 = cos(theta)``. A pivoted body has its centre of mass at
``l * e3`` in the body frame; its moments are about the pivot.

Sweeps: wherever a scene takes a number it may take a list of numbers or a range ``{start, stop, num}`` instead;
the members are the outer product of all swept values, run in one vectorised pass on the batched kernels.

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
    want = ["omega", "invariants"]       # omega, attitude, euler_angles, invariants, polhode
    accuracy = 1e-8
    method = "auto"                      # auto, closed-form, splitting, DOP853, RK45, Radau, LSODA

Examples
--------
>>> scene = Scene(moments=(1.0, 2.0, 3.0), omega=(0.01, 1.0, 0.01), t_end=10.0, outputs=("omega",))
>>> plan = scene.plan()
>>> plan.engine
'closed form: elliptic'
>>> plan.propagate
('omega',)
>>> result = simulate(scene)
>>> result.omega.shape, result.attitude is None
((1001, 3), True)
"""

from __future__ import annotations

import dataclasses
import difflib
import functools
import math
import numbers
import os
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from typing import Any, Mapping

import numpy as np

from eulersym.errors import InvalidInput
from eulersym import validation

__all__ = [
    "Scene",
    "Sweep",
    "Plan",
    "Step",
    "Result",
    "simulate",
    "bundled",
    "load",
    "cli",
    "OUTPUTS",
    "METHODS",
    "SHAPES",
    "CONVENTIONS",
]

#: The outputs a scene may ask for.
OUTPUTS = ("omega", "attitude", "euler_angles", "invariants", "polhode")
#: ``method`` values: ``auto`` lets the plan choose.
METHODS = ("auto", "closed-form", "splitting", "DOP853", "RK45", "Radau", "LSODA")
#: Named shapes → their dimension names, in the order of the ``eulersym.inertia`` function's arguments.
SHAPES = {
    "cube": ("a",),
    "cuboid": ("a", "b", "c"),
    "sphere": ("R",),
    "cylinder": ("R", "h"),
    "cone": ("R", "h"),
    "ellipsoid": ("a", "b", "c"),
}
#: Shapes that take ``origin=`` and its valid values (first = default).
SHAPE_ORIGINS = {"cube": ("center", "corner"), "cuboid": ("center", "corner"), "cone": ("apex", "center")}
#: Euler / Tait–Bryan sequences (lower case: the text's passive, body-fixed sequence; A = A3(c) A2(b) A1(a)).
CONVENTIONS = ("zxz", "xyx", "yzy", "zyz", "xzx", "yxy", "xyz", "yzx", "zxy", "xzy", "zyx", "yxz")
#: Accuracies the plan accepts (relative error wanted on the outputs).
ACCURACY_RANGE = (1e-13, 1e-1)
#: Relative tolerance under which two principal moments count as equal (symmetric top).
SYMMETRY_RTOL = 1e-12
#: Looser than this accuracy, a symmetric heavy top uses the second-order splitting (cheaper per step, conserves
#: |Γ| and L·Γ exactly); tighter, DOP853 on the Euler–Poisson kernel at rtol = accuracy.
SPLITTING_ACCURACY = 1e-5

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
    "t_end": None,
    "points": 1001,
    "outputs": ("omega", "invariants"),
    "accuracy": 1e-8,
    "method": "auto",
}

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
        "euler": "euler",
        "convention": "convention",
        "quaternion": "quaternion",
        "axis": "axis",
        "angle": "angle",
    },
    "time": {"end": "t_end", "points": "points"},
    "output": {"want": "outputs", "accuracy": "accuracy", "method": "method"},
}


#: Scene keyword → where it lives in a TOML file (for messages about keys a file lacks).
_TOML_PATHS = {
    target: (f"{section}.{key}" if section else key)
    for section, keys in _TOML_LAYOUT.items()
    for key, target in keys.items()
    if isinstance(target, str)
}


def _did_you_mean(key: str, valid) -> str:
    valid = sorted(valid)
    close = difflib.get_close_matches(key, valid, n=1, cutoff=0.5)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    return "one of " + ", ".join(repr(v) for v in valid) + hint


# --------------------------------------------------------------------------------------------------------------
# Sweeps
# --------------------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Sweep:
    """A swept number: the scene runs once per value (all sweeps of a scene form an outer-product grid).

    Give a list ``[1, 2, 3]`` or a range ``{"start": 0, "stop": 1, "num": 11}`` (inclusive, evenly spaced)
    wherever a scene takes a number.

    Examples
    --------
    >>> Sweep.of("omega[2]", {"start": 10, "stop": 20, "num": 3}).values
    (10.0, 15.0, 20.0)
    >>> len(Sweep.of("mass", [1, 2]))
    2
    """

    values: tuple

    def __len__(self) -> int:
        return len(self.values)

    @classmethod
    def of(cls, argument: str, value) -> "Sweep":
        """Build a sweep from a list, tuple, 1-D array or ``{start, stop, num}`` mapping."""
        if isinstance(value, Mapping):
            keys = set(value)
            if keys != {"start", "stop", "num"}:
                extra = sorted(keys - {"start", "stop", "num"})
                if extra:
                    raise InvalidInput(f"{argument}.{extra[0]}", value[extra[0]], _did_you_mean(extra[0], ("start", "stop", "num")))
                raise InvalidInput(argument, dict(value), "a range {start, stop, num} with all three keys")
            start = _number(f"{argument}.start", value["start"])
            stop = _number(f"{argument}.stop", value["stop"])
            num = value["num"]
            if isinstance(num, bool) or not isinstance(num, numbers.Integral) or num < 1:
                raise InvalidInput(f"{argument}.num", num, "a positive integer number of values")
            values = np.linspace(start, stop, int(num))
        else:
            values = [_number(f"{argument}[{k}]", v) for k, v in enumerate(value)]
            if not values:
                raise InvalidInput(argument, value, "a non-empty list of numbers to sweep over")
        return cls(tuple(float(v) for v in values))


def _number(argument: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise InvalidInput(argument, value, "a real number")
    out = float(value)
    if not math.isfinite(out):
        raise InvalidInput(argument, value, "a finite number (no NaN or infinity)")
    return out


def _scalar(argument: str, value, *, sweepable: bool = True):
    """A float, or a :class:`Sweep` where a list/range is given and sweeping is allowed."""
    if isinstance(value, Sweep):
        return value
    if isinstance(value, (list, tuple, np.ndarray, Mapping)):
        if not sweepable:
            raise InvalidInput(argument, value, "a single number (this value cannot be swept)")
        return Sweep.of(argument, value)
    return _number(argument, value)


def _vector(argument: str, value, n: int, *, sweepable: bool = True) -> tuple:
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__"):
        raise InvalidInput(argument, value, f"a list of {n} numbers")
    if len(value) != n:
        raise InvalidInput(argument, value, f"a list of {n} numbers, got {len(value)}")
    return tuple(_scalar(f"{argument}[{k}]", v, sweepable=sweepable) for k, v in enumerate(value))


def _values(x) -> np.ndarray:
    """All values a (possibly swept) scalar takes."""
    return np.asarray(x.values if isinstance(x, Sweep) else (x,), dtype=float)


# --------------------------------------------------------------------------------------------------------------
# Scene
# --------------------------------------------------------------------------------------------------------------


@dataclass(frozen=True, init=False)
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
    t_end : number
        End time (> 0); outputs at ``points`` evenly spaced times from 0 to t_end (default 1001).
    outputs : sequence of str
        Any of :data:`OUTPUTS` (default ('omega', 'invariants')).
    accuracy : number
        Relative accuracy wanted (default 1e-8).
    method : str
        One of :data:`METHODS` (default 'auto': the plan chooses).
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
    t_end: float
    points: int
    outputs: tuple
    accuracy: float
    method: str

    def __init__(self, **kwargs):
        for key in kwargs:
            if key not in _DEFAULTS:
                raise InvalidInput(key, kwargs[key], "a Scene keyword: " + _did_you_mean(key, _DEFAULTS))
        values = {**_DEFAULTS, **kwargs}
        for key, value in _normalise(values).items():
            object.__setattr__(self, key, value)

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
                raise InvalidInput("pivot.l", None, "the pivot–centre-of-mass distance l (a [pivot] table needs l)")
        try:
            return cls(**kwargs)
        except InvalidInput as exc:
            base = exc.argument.split("[")[0].split(".")[0]
            rest = exc.argument[len(base):]
            if exc.argument.startswith("dimensions.") and exc.argument in where:
                raise InvalidInput(where[exc.argument], exc.value, exc.expected) from None
            if base in where:
                raise InvalidInput(where[base] + rest, exc.value, exc.expected) from None
            if base in _TOML_PATHS:  # a key the file lacks: name where it would go
                raise InvalidInput(_TOML_PATHS[base] + rest, exc.value, exc.expected) from None
            raise

    # ---- derived facts (pure) -----------------------------------------------------------------------------
    @property
    def regime(self) -> str:
        """'torque-free', 'heavy top' or 'torque' — which equations of motion the scene needs.

        A pivot with ``M g l = 0`` and gravity without a pivot exert no torque about the reference point.

        Examples
        --------
        >>> Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, 5), t_end=1).regime
        'heavy top'
        """
        if self.l is not None and np.any(_values(self.l) != 0) and np.any(_values(self.g) != 0):
            return "heavy top"
        if self.torque is not None and any(np.any(_values(c) != 0) for c in self.torque):
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
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, Sweep):
                found.append((f.name, value))
            elif isinstance(value, tuple):
                for k, item in enumerate(value):
                    if isinstance(item, Sweep):
                        found.append((f"{f.name}[{k}]", item))
                    elif isinstance(item, tuple) and len(item) == 2 and isinstance(item[1], Sweep):
                        found.append((f"{f.name}.{item[0]}", item[1]))
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
        """The output times, ``linspace(0, t_end, points)``."""
        return np.linspace(0.0, self.t_end, self.points)

    def plan(self) -> "Plan":
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
        from eulersym._scene_plan import make_plan

        return make_plan(self)


def _normalise(v: dict) -> dict:
    """Validate and normalise the keyword values of a Scene (raises InvalidInput naming the key)."""
    out = dict(v)
    for key in ("name", "description"):
        if not isinstance(v[key], str):
            raise InvalidInput(key, v[key], "a string")
    # ---- body -----------------------------------------------------------------------------------------------
    given = [k for k in ("moments", "tensor", "shape") if v[k] is not None]
    if not given:
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
    if v["l"] is not None:
        out["l"] = _scalar("l", v["l"])
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
    if v["omega"] is None:
        raise InvalidInput("omega", None, "the initial angular velocity (omega = [w1, w2, w3], body components)")
    out["omega"] = _vector("omega", v["omega"], 3)
    out["omega_frame"] = validation.choice("omega_frame", v["omega_frame"], ("body", "space"))
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
    _check_consistency(out)
    return out


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
    if heavy and out["method"] == "splitting":
        if out["moments"] is not None and isinstance(out["moments"][0], float) and isinstance(out["moments"][1], float):
            i1, i2 = out["moments"][0], out["moments"][1]
            if abs(i1 - i2) > SYMMETRY_RTOL * max(i1, i2):
                raise InvalidInput("method", "splitting", "the splitting needs a symmetric top (I1 = I2); use 'auto'")


# --------------------------------------------------------------------------------------------------------------
# Plan and Result (the plan logic lives in eulersym._scene_plan, the runners in eulersym._scene_run)
# --------------------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Step:
    """One line of a plan: ``action`` ('derive', 'kernel', 'closed form', 'integrate', 'compute' or 'skip'),
    ``what`` and ``reason``.

    Examples
    --------
    >>> print(Step("skip", "attitude", "only ω is asked for"))
      skip         attitude — only ω is asked for
    """

    action: str
    what: str
    reason: str

    def __str__(self) -> str:
        return f"  {self.action:<12} {self.what} — {self.reason}"


@dataclass(frozen=True)
class Plan:
    """What a scene's run derives, emits, integrates and skips, each with a reason.

    Attributes
    ----------
    scene : str
        The scene's name.
    regime : str
        'torque-free', 'heavy top' or 'torque'.
    body : str
        'spherical', 'symmetric', 'asymmetric' or 'derived' (decided after the inertia derivation).
    engine : str
        How the motion is obtained, e.g. 'closed form: elliptic', 'integrate: DOP853 on heavy_top_euler_poisson'.
    derive : tuple of str
        Derivations that will run (SymPy), e.g. 'inertia.cube', 'inertia.principal_axes'.
    kernels : tuple of str
        Generated kernels (``eulersym.generated.<name>``) used; committed, so nothing is emitted at run time.
    propagate : tuple of str
        State propagated in time: 'omega', and 'attitude' only when an output or the torque needs it.
    steps, skipped : tuple of Step
        What will be done and what is skipped, with reasons.
    batch : int
        Number of sweep members (1 without a sweep).

    Examples
    --------
    >>> plan = Scene(moments=(1, 1, 2), mass=1, l=0.1, omega=(0, 0, 50), euler=(0, 0.3, 0), t_end=1).plan()
    >>> plan.regime, plan.kernels
    ('heavy top', ('heavy_top_euler_poisson',))
    """

    scene: str
    regime: str
    body: str
    engine: str
    derive: tuple
    kernels: tuple
    propagate: tuple
    steps: tuple
    skipped: tuple
    batch: int = 1
    method: str = ""
    options: Mapping = field(default_factory=dict, compare=False)

    def __str__(self) -> str:
        head = f"plan for {self.scene!r} ({self.regime}, {self.body} body"
        head += f", sweep of {self.batch} members)" if self.batch > 1 else ")"
        return "\n".join([head, *map(str, self.steps), *map(str, self.skipped)])


@dataclass(frozen=True, eq=False)
class Result:
    """The outcome of :func:`simulate`.

    Attributes
    ----------
    t : ndarray (n,)
        Output times.
    omega : ndarray (n, 3), or (batch, n, 3) for a sweep
        Body angular velocity in the scene's body frame.
    attitude : ndarray (n, 4) or None
        Unit quaternions (scalar first), ``v_space = R(q) v_body``; None when no output needs the attitude.
    euler_angles : ndarray (n, 3) or None
        Angles of the scene's convention (phi, theta, psi for 'zxz'), phi and psi unwrapped.
    polhode : ndarray (n, 3) or None
        ω in the principal frame: the polhode on the energy ellipsoid ω·Iω = 2E.
    invariants : mapping name → ndarray (n,) or (batch, n)
    drift : mapping name → float
        max |I(t) − I(0)| / |I(0)| (absolute where I(0) = 0), the maximum over members.
    plan : Plan
        The plan that ran (resolved: derived moments known).
    derivations : tuple of str
        The derivations that ran (SymPy), in order; empty when none was needed.
    propagated : tuple of str
        What was propagated in time ('omega', 'attitude', 'gamma').
    timings : mapping stage → seconds
    sweep : mapping label → ndarray (batch,)
        Swept values per member (empty without a sweep).
    moments, axes : ndarray
        Principal moments and the principal axes (columns, in the scene's body frame, det +1).
    n_rhs_calls : int
        Kernel evaluations (0 for a closed form).
    notes : tuple of str
        Facts for the report (turning points, the sleeping-top threshold, ...).
    gamma : ndarray (n, 3) or None
        The body-frame upward vertical Γ (heavy top), Γ3 = cos θ.
    turning_points : (θ1, θ2) or None
        Heavy top with Euler-angle output: the nutation's turning points (radians), derived by eulersym.top.

    Examples
    --------
    >>> r = simulate(Scene(moments=(1, 2, 3), omega=(0.1, 1, 0.2), t_end=4, points=5, outputs=("omega", "polhode")))
    >>> r.t.tolist(), r.omega.shape, r.attitude is None, r.propagated
    ([0.0, 1.0, 2.0, 3.0, 4.0], (5, 3), True, ('omega',))
    >>> bool(np.allclose(r.polhode, r.omega))  # principal moments given: the body frame is the principal frame
    True
    """

    t: np.ndarray
    omega: np.ndarray
    attitude: np.ndarray | None
    euler_angles: np.ndarray | None
    polhode: np.ndarray | None
    invariants: Mapping
    drift: Mapping
    plan: Plan
    derivations: tuple
    propagated: tuple
    timings: Mapping
    sweep: Mapping
    moments: np.ndarray
    axes: np.ndarray
    n_rhs_calls: int = 0
    notes: tuple = ()
    gamma: np.ndarray | None = None
    turning_points: tuple | None = None

    def report(self) -> str:
        """A short text report: the plan, the invariants' drift, the timings and notes.

        Examples
        --------
        >>> r = simulate(Scene(moments=(1, 2, 3), omega=(0.01, 1, 0), t_end=5, points=11))
        >>> "drift" in r.report()
        True
        """
        from eulersym._scene_io import report

        return report(self)


def simulate(scene: Scene, *, progress: bool = False) -> Result:
    """Run a scene's plan and return its :class:`Result`.

    Parameters
    ----------
    scene : Scene
    progress : bool
        Draw a progress bar on standard error (the command line turns it on for a terminal only).

    Examples
    --------
    Torque-free symmetric top: ω3 is constant and (ω1, ω2) turns at Ω = (I1 − I3)/I1 · ω3, from the closed form.

    >>> r = simulate(Scene(moments=(2, 2, 1), omega=(0.3, 0, 5), t_end=2, outputs=("omega", "invariants")))
    >>> r.plan.engine, r.derivations, round(r.drift["energy"], 12)
    ('closed form: trigonometric', (), 0.0)
    """
    if not isinstance(scene, Scene):
        raise InvalidInput("scene", scene, "an eulersym.scene.Scene (Scene(...) or Scene.from_toml(path))")
    from eulersym._scene_run import run

    return run(scene, progress=progress)


# --------------------------------------------------------------------------------------------------------------
# Bundled scenes and the command line
# --------------------------------------------------------------------------------------------------------------


def bundled() -> dict:
    """``{name: path}`` of the scenes shipped with eulersym (``eulersym/scenes/*.toml``).

    Examples
    --------
    >>> sorted(bundled())[:3]
    ['cube-diagonal', 'heavy-top-nutation', 'sleeping-top-above']
    """
    folder = resources.files("eulersym.scenes")
    return {p.name[:-5]: str(p) for p in sorted(folder.iterdir(), key=lambda p: p.name) if p.name.endswith(".toml")}


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


def cli(argv: list) -> int:
    """``eulersym simulate SCENE [--explain] [-o out.npz|out.csv] [--plot out.png] [--list]``.

    Examples
    --------
    >>> cli(["--list"])  # doctest: +ELLIPSIS
    bundled scenes (eulersym simulate NAME; copy the TOML to start your own):
    ...
    0
    """
    from eulersym._scene_io import main

    return main(argv)
