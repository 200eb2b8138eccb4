"""A user's own rigid body: specification (``Model``), derivations by two routes, integrals, kernels.

See :mod:`eulersym.model.mechanics` for the symbolic contract between the specification and the derivations.
"""

from __future__ import annotations

__all__: list[str] = []
