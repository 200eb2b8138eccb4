"""Numerics for rigid-body motion (SymPy-free): the exact free-body oracle, geometric integrators, invariants.

Nothing here imports SymPy; the generated kernels it uses are plain NumPy modules.

Examples
--------
>>> from eulersym.numerics import free_rigid_body_exact
>>> free_rigid_body_exact((1.0, 2.0, 3.0), (0.0, 0.0, 1.0), [0.0, 1.0])
array([[0., 0., 1.],
       [0., 0., 1.]])
"""

from __future__ import annotations

from eulersym.numerics.exact import (
    complete_elliptic_k,
    free_rigid_body_attitude_exact,
    free_rigid_body_exact,
    jacobi_sncndn,
    quaternion_multiply,
)

__all__ = [
    "free_rigid_body_exact",
    "free_rigid_body_attitude_exact",
    "jacobi_sncndn",
    "complete_elliptic_k",
    "quaternion_multiply",
]
