"""eulersym — rigid-body motion derived with SymPy, proven against the text, emitted as NumPy kernels.

``import eulersym`` is light: submodules load on first attribute access (PEP 562), and SymPy is imported only
by the symbolic layers. Generated kernels (``eulersym.generated``), numerics and scenes that need no derivation
run without SymPy.

Examples
--------
>>> import eulersym
>>> eulersym.rotation.D(0)
Matrix([
[1, 0, 0],
[0, 1, 0],
[0, 0, 1]])
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

#: The public submodules, loaded lazily.
_SUBMODULES = (
    "errors",
    "symbols",
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
    "generated",
)

__all__ = ["__version__", *_SUBMODULES]


def __getattr__(name: str):
    if name in _SUBMODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
