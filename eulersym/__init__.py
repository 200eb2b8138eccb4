"""eulersym — rigid-body motion derived with SymPy, proven against the text, emitted as NumPy kernels.

The front door: :class:`Model` (a body: moments, a tensor, a shape or parts; a pivot; torques; a rotor;
parameters), :class:`Scene` (a model, its start, the time span, the outputs wanted) and :func:`simulate` (the motion,
by the first method that applies: a closed form where one exists). The submodules hold the rest (``eulersym.rotation``,
``eulersym.top``, ``eulersym.numerics``, ...).

``import eulersym`` is light: every name loads on first access (PEP 562), and SymPy is imported only by the
symbolic layers. Generated kernels (``eulersym.generated``), numerics and scenes that need no derivation run
without SymPy.

Examples
--------
>>> import eulersym
>>> eulersym.rotation.D(0)
Matrix([
[1, 0, 0],
[0, 1, 0],
[0, 0, 1]])
>>> from eulersym import Model, Scene, simulate
>>> scene = Scene(model=Model(body={"moments": [1, 2, 3]}), omega=(0.01, 1.0, 0.01), t_end=10.0)
>>> simulate(scene).plan.engine
'closed form: elliptic'
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

#: The public submodules, loaded lazily.
_SUBMODULES = (
    "errors",
    "symbols",
    "attitude",
    "quaternion",
    "rotation",
    "kinematics",
    "inertia",
    "dynamics",
    "top",
    "text",
    "compare",
    "verify",
    "parsing",
    "codegen",
    "numerics",
    "model",
    "scene",
    "figures",
    "animation",
    "generated",
)

#: The names of the front door, each loaded with its module on first access.
_NAMES = ("Model", "Scene", "simulate", "Result", "Plan", "Sweep", "Trajectory")

__all__ = ["__version__", *_NAMES, *_SUBMODULES]


def __getattr__(name: str):
    if name == "Model":
        from eulersym.model.spec import Model

        return Model
    if name in ("Scene", "Sweep"):
        from eulersym.scene import spec

        return getattr(spec, name)
    if name == "simulate":
        from eulersym.scene.run import simulate

        return simulate
    if name in ("Result", "Plan"):
        from eulersym.scene import result

        return getattr(result, name)
    if name == "Trajectory":
        from eulersym.numerics.trajectory import Trajectory

        return Trajectory
    if name in _SUBMODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
