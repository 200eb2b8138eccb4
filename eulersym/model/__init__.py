"""A user's own rigid body: specification (``Model``), derivations by two routes, integrals, kernels.

``import eulersym.model`` is light (no SymPy): :class:`Model` validates a model SymPy-free, and SymPy comes in
when its mechanics is first used. See :mod:`eulersym.model.spec` for the model's sections,
:mod:`eulersym.model.mechanics` for the symbolic contract between the specification and the derivations.

Examples
--------
>>> from eulersym.model import Model
>>> Model(body={"moments": [1, 2, 3]}, torque={"body": "[0, 0, 0.1]"}).name
'model'
"""

from __future__ import annotations

import importlib

__all__ = ["Model", "Mechanics"]


def __getattr__(name: str):
    if name == "Model":
        from eulersym.model.spec import Model

        return Model
    if name == "Mechanics":
        return importlib.import_module("eulersym.model.mechanics").Mechanics
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
