"""Scene files for bodies on a plane (``[contact]``) and on a moving pivot (``[pivot] path``): read, checked, run.

A contact scene is a model file (``[parameters]``, ``[body]``, ``[torque]``, ``[rotor]``) plus

``[contact]``
    ``surface`` (``sphere``, ``ellipsoid``, ``disk``, ``paraboloid``) with its dimension (``radius``,
    ``semi_axes``, ``curvatures``), ``centre`` and ``axes`` (the shape from the centre of mass, body frame), ``mode``
    (``rolling`` | ``sliding``), ``friction`` (``none``, ``viscous``, ``coulomb``), ``mu``, ``width``,
    ``rolling_resistance``, ``spin_friction``, and ``g`` (default 9.81) — numbers or formulas of the parameters;

and ``[initial]`` (``omega`` body components; ``quaternion`` scalar first, or ``axis`` and ``angle``;
``position`` ``[x, y]``; ``velocity`` when sliding), ``[time]`` (``end``, ``points``), ``[output]`` (``accuracy``).
A pivot-path scene is a pivoted model file whose ``[pivot]`` has ``path = ["x(t)", "y(t)", "z(t)"]``, plus
``[initial]`` (``omega``, the attitude) and ``[time]``.

:func:`read_contact` and :func:`read_pivot_path` check the raw TOML values (what a model reader hooks in);
:func:`load` reads a whole file into a :class:`ContactScene`; :func:`run` derives (both routes are proven equal by
the kernel's module, :mod:`eulersym.model.rolling`), emits into the kernel cache (:mod:`eulersym.model.cache`,
keyed by the file's model sections and the versions), and integrates a contact with
:func:`eulersym.model.contact_motion.integrate` — eulersym's compiled DOP853 with the normal force sampled at least
as often as it steps, :func:`scipy.integrate.solve_ivp` with the lift-off event without numba — stopping at
lift-off with :class:`eulersym.model.contact_motion.LiftOff` at its time (a moving pivot: solve_ivp's DOP853).

Examples
--------
>>> scene = load("rolling-sphere")
>>> scene.kind, scene.body.contact.surface.kind
('contact', 'sphere')
>>> read_contact({"surface": "sphere", "radius": -1})
Traceback (most recent call last):
...
eulersym.errors.InvalidInput: contact.radius=-1 is not valid: expected a positive number
"""

from __future__ import annotations

import hashlib
import json
import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from eulersym.errors import InvalidInput
from eulersym.validation import choice, finite_array

__all__ = ["CONTACT_KEYS", "FOLDER", "bundled", "listing", "read_contact", "read_pivot_path", "ContactScene", "handles", "load",
           "kernel", "run", "ContactRun", "cli"]

#: The keys of ``[contact]``.
CONTACT_KEYS = ("surface", "radius", "semi_axes", "curvatures", "centre", "axes", "mode", "friction", "mu", "width",
                "rolling_resistance", "spin_friction", "g")

#: Where the bundled contact and moving-pivot scenes live (``eulersym/scenes/contact/*.toml``).
FOLDER = Path(__file__).resolve().parent.parent / "scenes" / "contact"

_INITIAL_KEYS = ("omega", "quaternion", "axis", "angle", "position", "velocity")
_TIME_KEYS = ("end", "points")
_OUTPUT_KEYS = ("accuracy",)


def bundled() -> dict:
    """``{name: path}`` of the bundled contact and moving-pivot scenes.

    Examples
    --------
    >>> sorted(bundled())[:2]
    ['chaplygin-ball', 'euler-disk']
    """
    return {p.stem: str(p) for p in sorted(FOLDER.glob("*.toml"))}


def listing() -> dict:
    """``{name: (description, path)}`` of the bundled contact and moving-pivot scenes, for ``eulersym simulate
    --list`` (:func:`eulersym.scene.cli.cli` prints them after the other bundled scenes). Reads each file's
    ``description`` only: nothing is derived.

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


@dataclass(frozen=True)
class ContactScene:
    """A scene file of a body on a plane (``kind = "contact"``, ``body`` a
    :class:`~eulersym.model.rolling.BodyOnPlane`) or on a moving pivot (``kind = "pivot-path"``, ``body`` the
    :class:`~eulersym.model.mechanics.Mechanics` with the apparent gravity's potential)."""

    name: str
    description: str
    kind: str
    body: object
    digest: str
    initial: dict = field(default_factory=dict)
    end: float = 1.0
    points: int = 101
    accuracy: float = 1e-8
    sweep: dict = field(default_factory=dict)

    @property
    def members(self) -> list:
        """``[{name: value}]``: one run per member, the outer product of the swept parameters (``[{}]`` if none)."""
        import itertools

        names = list(self.sweep)
        return [dict(zip(names, combo)) for combo in itertools.product(*(self.sweep[n] for n in names))] or [{}]


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


def handles(path_or_name) -> bool:
    """Whether a scene is a contact or moving-pivot scene (a bundled name here, or a TOML file with ``[contact]``
    or ``[pivot] path``): the hook :func:`eulersym.scene.cli.cli` asks before reading a scene.

    Examples
    --------
    >>> handles("tippe-top"), handles("tennis-racket")
    (True, False)
    """
    text = str(path_or_name)
    if text in bundled():
        return True
    if not text.endswith(".toml") or not os.path.isfile(text):
        return False
    try:
        data, _ = _read(text)
    except InvalidInput:  # the scene reader says what is wrong with the file, in its own words
        return False
    pivot = data.get("pivot")
    return "contact" in data or (isinstance(pivot, dict) and "path" in pivot)


def load(path_or_name) -> ContactScene:
    """Read and check a contact or moving-pivot scene file (or a bundled one, by name).

    Raises
    ------
    eulersym.errors.InvalidInput
        A bad key or value, naming it (``contact.radius``, ``pivot.path[2]``, ``initial.omega``); a contact on a
        pivoted body.

    Examples
    --------
    >>> load("kapitza-pendulum").kind
    'pivot-path'
    """
    from eulersym import __version__
    from eulersym.model.spec import Model

    data, stem = _read(path_or_name)
    data = dict(data)
    section = data.pop("contact", None)
    pivot = data.get("pivot")
    path = None
    if isinstance(pivot, dict) and "path" in pivot:
        pivot = dict(pivot)
        path = read_pivot_path(pivot.pop("path"))
        data["pivot"] = pivot
    if section is not None and pivot is not None:
        raise InvalidInput("contact", section.get("surface") if isinstance(section, dict) else section,
                           "a free body: a contact with the plane and a pivot both hold the body (remove [pivot], "
                           "or the contact)")
    if section is None and path is None:
        raise InvalidInput("SCENE", str(path_or_name), "a scene with [contact] or [pivot] path")
    table = read_contact(section) if section is not None else None
    initial = _table("initial", data.get("initial", {}), _INITIAL_KEYS)
    time = _table("time", data.get("time", {}), _TIME_KEYS)
    output = _table("output", data.get("output", {}), _OUTPUT_KEYS)
    model_data = {k: v for k, v in data.items() if k not in ("description", "initial", "time", "output")}
    sweep = {}
    if isinstance(model_data.get("parameters"), dict):
        first = {}
        for name, value in model_data["parameters"].items():
            if isinstance(value, list):
                values = finite_array(f"parameters.{name}", value, shape=(None,))
                if not 1 <= values.size <= 10_000:
                    raise InvalidInput(f"parameters.{name}", value, "a list of 1 to 10000 numbers (a sweep)")
                sweep[name] = tuple(values.tolist())
                value = sweep[name][0]
            first[name] = value
        model_data["parameters"] = first
    model_data.setdefault("name", stem)
    model = Model.from_dict(model_data)
    mech = model.mechanics
    if table is not None:
        from eulersym.model.rolling import BodyOnPlane

        body = BodyOnPlane(mech, contact(table, mech), gravity=expression("contact.g", table["g"], mech))
        kind = "contact"
    else:
        from eulersym.model.moving_pivot import moving_pivot

        body = moving_pivot(mech, [expression(f"pivot.path[{k}]", x, mech) if not isinstance(x, str) else x
                                   for k, x in enumerate(path)])
        kind = "pivot-path"
    import sympy as sp

    if len(ContactScene("", "", kind, None, "", sweep=sweep).members) > 10_000:
        raise InvalidInput("parameters", sorted(sweep), "a sweep of at most 10000 members (their outer product)")
    canonical = json.dumps({"model": model_data, "contact": section, "path": path, "eulersym": __version__,
                            "sympy": sp.__version__, "kind": kind}, sort_keys=True, default=str)
    end = time.get("end", 1.0)
    points = time.get("points", 101)
    accuracy = output.get("accuracy", 1e-8)
    if isinstance(end, bool) or not isinstance(end, (int, float)) or not 0 < end < np.inf:
        raise InvalidInput("time.end", end, "a positive finite end time")
    if isinstance(points, bool) or not isinstance(points, int) or not 2 <= points <= 10 ** 6:
        raise InvalidInput("time.points", points, "a whole number of output times, 2 to 10**6")
    if isinstance(accuracy, bool) or not isinstance(accuracy, (int, float)) or not 1e-13 <= accuracy <= 1e-1:
        raise InvalidInput("output.accuracy", accuracy, "a relative accuracy from 1e-13 to 1e-1")
    if "omega" not in initial:
        raise InvalidInput("initial.omega", None, "the body components of ω (rad/s) (it is missing)")
    return ContactScene(str(model_data["name"]), str(data.get("description", "")), kind, body,
                        hashlib.sha256(canonical.encode()).hexdigest(), dict(initial), float(end), int(points),
                        float(accuracy), sweep)


def _source(scene: ContactScene) -> str:
    """The kernel's module text with the cache's digest line in its header."""
    if scene.kind == "contact":
        from eulersym.model.rolling_kernels import source
    else:
        from eulersym.model.kernels import source
    lines = source(scene.body).split("\n")
    return "\n".join([lines[0], f"# Model digest: sha256:{scene.digest}", *lines[1:]])


def kernel(scene: ContactScene):
    """The scene's kernel module, from the kernel cache (:mod:`eulersym.model.cache`), derived and stored on a miss.

    Examples
    --------
    >>> kernel(load("rolling-sphere")).STATE[-2:]
    ('x_cm', 'y_cm')
    """
    from eulersym.model import cache

    found = cache.lookup(scene.digest)
    if found is not None:
        try:
            return cache.load(found, scene.digest, required=("rhs",))
        except cache.Damaged:
            cache.remove(scene.digest)
    text = _source(scene)
    name = "".join(c if c.isalnum() else "_" for c in scene.name).strip("_") or "model"

    def write(folder):
        target = folder / f"{name}.py"
        target.write_text(text, encoding="utf-8")
        return target

    return cache.load(cache.store(scene.digest, write), scene.digest, required=("rhs",))


def _attitude(initial: dict) -> np.ndarray:
    if "quaternion" in initial:
        if "axis" in initial or "angle" in initial:
            raise InvalidInput("initial.quaternion", initial["quaternion"], "one attitude: a quaternion, or an axis "
                               "and an angle")
        q = finite_array("initial.quaternion", initial["quaternion"], shape=(4,))
        if not np.linalg.norm(q) > 0:
            raise InvalidInput("initial.quaternion", q.tolist(), "a non-zero quaternion, scalar first")
        return q / np.linalg.norm(q)
    if "axis" in initial or "angle" in initial:
        axis = finite_array("initial.axis", initial.get("axis", [1, 0, 0]), shape=(3,))
        angle = finite_array("initial.angle", [initial.get("angle", 0.0)], shape=(1,))[0]
        if not np.linalg.norm(axis) > 0:
            raise InvalidInput("initial.axis", axis.tolist(), "a non-zero axis")
        axis = axis / np.linalg.norm(axis)
        return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])
    return np.array([1.0, 0.0, 0.0, 0.0])


@dataclass(frozen=True)
class ContactRun:
    """What :func:`run` returns: ``t``, the state ``y`` (points × len(names)), its ``names``, the plan line, and
    for a contact the trace of the contact point ``trace`` (points × 2) and the normal force ``normal``."""

    t: np.ndarray
    y: np.ndarray
    names: tuple
    plan: str
    trace: np.ndarray | None = None
    normal: np.ndarray | None = None
    invariants: dict = field(default_factory=dict)


def run(scene: ContactScene, values: dict | None = None) -> ContactRun:
    """Integrate the scene (DOP853 at ``rtol = accuracy``: compiled for a contact where numba is installed, else
    solve_ivp's), stopping at lift-off; ``values`` sets parameters (a
    sweep's member, :attr:`ContactScene.members`), the others at the file's values.

    Raises
    ------
    eulersym.model.contact_motion.LiftOff
        The normal force fell to zero at ``err.t``.

    Examples
    --------
    >>> result = run(load("rolling-sphere"))
    >>> round(float(result.y[-1, result.names.index("x_cm")]), 9)        # v = a ω = 0.1 m × 10 rad/s, 2 s
    2.0
    """
    from eulersym.model.contact_motion import integrate, start

    module = kernel(scene)
    params = dict(zip(module.PARAMETERS, module.DEFAULTS))
    for name, value in (values or {}).items():
        if name not in params:
            raise InvalidInput("values", name, "a parameter: one of " + ", ".join(module.PARAMETERS))
        params[name] = float(value)
    times = np.linspace(0.0, scene.end, scene.points)
    q = _attitude(scene.initial)
    plan = _plan_line(scene)
    if scene.kind == "contact":
        y0 = start(module, omega=scene.initial["omega"], q=q, position=scene.initial.get("position", (0.0, 0.0)),
                   velocity=scene.initial.get("velocity"), params=params)
        motion = integrate(module, y0, times, params=params, rtol=scene.accuracy, atol=scene.accuracy * 1e-2)
        invariants = {n: motion.invariants[:, k] for k, n in enumerate(module.INVARIANTS)}
        return ContactRun(motion.t, motion.y, motion.names, plan, np.stack([motion["x_P"], motion["y_P"]], axis=1),
                          motion["N"], invariants)
    from scipy.integrate import solve_ivp

    omega = finite_array("initial.omega", scene.initial["omega"], shape=(3,))
    q0, q1, q2, q3 = q
    gamma = [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3]
    y0 = np.concatenate([omega, gamma, q])
    sol = solve_ivp(module.rhs, (0.0, scene.end), y0, method="DOP853", t_eval=times, args=tuple(params.values()),
                    rtol=scene.accuracy, atol=scene.accuracy * 1e-2)
    if not sol.success:
        from eulersym.errors import CheckFailed

        raise CheckFailed(f"solve_ivp (DOP853) failed: {sol.message}")
    return ContactRun(sol.t, sol.y.T, tuple(module.STATE), plan)


def _plot(result: ContactRun, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (top, bottom) = plt.subplots(1, 2, figsize=(10, 4.5))
    top.plot(result.trace[:, 0], result.trace[:, 1], lw=0.8)
    top.set_aspect("equal", adjustable="datalim")
    top.set(title="the contact point's trace, from above", xlabel="x (m)", ylabel="y (m)")
    bottom.plot(result.t, result.normal, lw=0.8)
    bottom.set(title="the normal force", xlabel="t (s)", ylabel="N (N)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def cli(args) -> int:
    """``eulersym simulate SCENE`` for a contact or moving-pivot scene: ``args`` as
    :func:`eulersym.scene.cli.cli` parsed them (``scene``, ``explain``, ``output`` — ``.npz`` —, ``plot``).

    Examples
    --------
    >>> import argparse
    >>> cli(argparse.Namespace(scene="rolling-sphere", explain=True, output=None, plot=None))  # doctest: +ELLIPSIS
    integrate: DOP853 (..., rtol 1e-10) on the contact kernel 'rolling-sphere' — Newton–Euler ...
    0
    """
    scene = load(args.scene)
    if getattr(args, "output", None) and not str(args.output).endswith(".npz"):
        raise InvalidInput("-o", args.output, "a .npz file (a contact scene's columns: t, state, trace, normal)")
    if getattr(args, "plot", None) and scene.kind != "contact":
        raise InvalidInput("--plot", args.plot, "a contact scene (the figure is the contact point's trace)")
    if args.explain:
        print(_plan_line(scene))
        return 0
    print(f"scene {scene.name!r}" + (f" — {scene.description}" if scene.description else ""))
    print(_plan_line(scene))
    members = scene.members
    runs = []
    for values in members:
        if values:  # named before it runs: a member that lifts off is the one printed last
            print("member " + ", ".join(f"{k} = {v:g}" for k, v in values.items()), flush=True)
        runs.append(run(scene, values))
        _summary(runs[-1])
    if getattr(args, "output", None):
        stack = (lambda a: a[0]) if len(runs) == 1 else np.stack
        extra = {} if runs[0].normal is None else {"trace": stack([r.trace for r in runs]),
                                                   "normal": stack([r.normal for r in runs])}
        extra.update({f"sweep_{k}": np.array([m[k] for m in members]) for k in scene.sweep})
        np.savez(args.output, t=runs[0].t, state=stack([r.y for r in runs]), names=np.array(runs[0].names), **extra)
        print(f"wrote {args.output}")
    if getattr(args, "plot", None):
        _plot(runs[0], args.plot)
        print(f"wrote {args.plot}" + (" (the first member)" if len(runs) > 1 else ""))
    return 0


def _summary(result: ContactRun) -> None:
    print(f"  {len(result.t)} output times, t = 0 .. {result.t[-1]:g}")
    if result.normal is not None:
        print(f"  normal force N: min {result.normal.min():.6g}, max {result.normal.max():.6g}")
    if "gamma3" in result.names:
        tilt = np.arccos(np.clip(result.y[:, result.names.index("gamma3")], -1.0, 1.0))
        print(f"  tilt of body axis e3 from the upward vertical: start {tilt[0]:.6g}, max {tilt.max():.6g}, "
              f"end {tilt[-1]:.6g} rad")
    for name, values in result.invariants.items():
        scale = max(abs(values[0]), 1e-300)
        print(f"  {name}: {values[0]:.12g}, relative drift {np.ptp(values) / scale:.2e}")


def _plan_line(scene: ContactScene) -> str:
    what = (f"Newton–Euler with the contact force a multiplier ({scene.body.contact.surface.kind}, "
            f"{scene.body.contact.mode}), proven equal to Gibbs–Appell; no closed form or splitting applies to a "
            "body on a plane; stops at lift-off (N = 0)" if scene.kind == "contact" else
            "the pivot's prescribed acceleration as a time-dependent apparent gravity (derived from [pivot] path)")
    from eulersym.numerics.methods._base import numba_available

    engine = ("eulersym's compiled DOP853 (numba), the normal force sampled at least as often as it steps"
              if scene.kind == "contact" and numba_available() else "scipy solve_ivp" +
              (" with the lift-off event; numba, the fast extra, is not installed" if scene.kind == "contact" else ""))
    return (f"integrate: DOP853 ({engine}, rtol {scene.accuracy:g}) on the {scene.kind} kernel "
            f"{scene.name!r} — {what}")
