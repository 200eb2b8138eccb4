"""Numerics for rigid-body motion (SymPy-free): the exact free-body oracle, geometric integrators, invariants.

* :func:`free_rigid_body_exact`, :func:`free_rigid_body_attitude_exact` — the exact torque-free motion.
* :func:`integrate_free_body` — geometric integrators ("strang", "yoshida4", "dmv2", "dmv4", "dmv6").
* :func:`integrate_heavy_top` — the heavy symmetric top by Strang splitting in the Euler–Poisson form.
* :func:`heavy_top_exact` — the heavy symmetric top in closed form (elliptic functions, any start).
* :func:`integrate_pivoted` — any pivoted body (full tensor, centre of mass anywhere, rotor) by exact-flow splitting;
  :func:`integrate_pivoted_batch`, :func:`integrate_free_bodies`, :func:`integrate_heavy_tops` — the splittings over
  many members (NumPy or numba), a step per member from the accuracy asked; :func:`integrate_torqued` — any torque,
  a Lie-group method that keeps |q| = 1.
* :func:`integrate_ivp` — ``solve_ivp`` over a generated kernel module.
* :class:`Trajectory` — what the integrators return; :mod:`eulersym.numerics.invariants` — conserved quantities.

Nothing here imports SymPy; the generated kernels it uses are plain NumPy modules.

Examples
--------
>>> from eulersym.numerics import free_rigid_body_exact
>>> free_rigid_body_exact((1.0, 2.0, 3.0), (0.0, 0.0, 1.0), [0.0, 1.0])
array([[0., 0., 1.],
       [0., 0., 1.]])
"""

from __future__ import annotations

from eulersym.numerics import invariants
from eulersym.numerics.exact import (
    complete_elliptic_k,
    free_rigid_body_attitude_exact,
    free_rigid_body_exact,
    jacobi_sncndn,
    quaternion_multiply,
)
from eulersym.numerics.heavy_top import integrate_heavy_top, sleeping_top_threshold_numeric
from eulersym.numerics.heavy_top_exact import HeavyTopMotion, euler_to_quaternion, heavy_top_exact
from eulersym.numerics.ivp import integrate_ivp
from eulersym.numerics.pivoted import PIVOTED_METHODS, integrate_pivoted  # splitting: pivoted bodies
from eulersym.numerics.batched import (  # splitting: batched over members
    BatchTrajectory,
    integrate_free_bodies,
    integrate_heavy_tops,
    integrate_pivoted_batch,
)
from eulersym.numerics.lie_group import integrate_torqued  # splitting: any torque, |q| = 1
from eulersym.numerics.splitting import FREE_BODY_METHODS, integrate_free_body, step_free_bodies
from eulersym.numerics.trajectory import Trajectory

__all__ = [
    "free_rigid_body_exact",
    "free_rigid_body_attitude_exact",
    "integrate_free_body",
    "integrate_heavy_top",
    "integrate_ivp",
    "Trajectory",
    "invariants",
    "step_free_bodies",
    "sleeping_top_threshold_numeric",
    "FREE_BODY_METHODS",
    "jacobi_sncndn",
    "complete_elliptic_k",
    "quaternion_multiply",
    "heavy_top_exact",
    "HeavyTopMotion",
    "euler_to_quaternion",
    # splitting: pivoted bodies, batched members, any torque
    "integrate_pivoted",
    "PIVOTED_METHODS",
    "integrate_pivoted_batch",
    "integrate_free_bodies",
    "integrate_heavy_tops",
    "BatchTrajectory",
    "integrate_torqued",
]
