"""A rigid body — the one description of a body in eulersym: specification (``Model``), its numbers per member
(``Model.facts``, NumPy), derivations by two routes, integrals, kernels.

``import eulersym.model`` is light (no SymPy): :class:`Model` validates a model SymPy-free, its facts
(:mod:`eulersym.model.facts`) need no SymPy for numbers, parameters and named shapes, and SymPy comes in when its
mechanics is first used. See :mod:`eulersym.model.spec` for the model's sections, :mod:`eulersym.model.mechanics`
for the symbolic contract between the specification and the derivations. Every scene holds one
(:class:`eulersym.scene.Scene`).

Examples
--------
>>> from eulersym.model import Model
>>> Model(body={"moments": [1, 2, 3]}, torque={"body": "[0, 0, 0.1]"}).name
'model'
"""

from __future__ import annotations

__all__ = ["Model", "Mechanics", "Facts"]


def __getattr__(name: str):
    if name == "Model":
        from eulersym.model.spec import Model

        return Model
    if name == "Mechanics":  # imports SymPy
        from eulersym.model.mechanics import Mechanics

        return Mechanics
    if name == "Facts":
        from eulersym.model.facts import Facts

        return Facts
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
