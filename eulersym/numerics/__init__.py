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
* :class:`Trajectory` — what every integrator and method returns (one motion, or batch-first for many);
  :mod:`eulersym.numerics.invariants` — conserved quantities.
* :mod:`eulersym.numerics.methods` — the ways of getting a motion as one family (a class each: whether it applies to
  a problem, what it costs, its run), in one registry in order of preference, with one driver: what a scene's plan
  loops over. The functions above are what the methods call.

Nothing here imports SymPy; the generated kernels it uses are plain NumPy modules. Each name loads its own module on
first use (PEP 562), so ``free_rigid_body_exact`` costs neither SciPy nor the integrators' imports.

Examples
--------
>>> from eulersym.numerics import free_rigid_body_exact
>>> free_rigid_body_exact((1.0, 2.0, 3.0), (0.0, 0.0, 1.0), [0.0, 1.0])
array([[0., 0., 1.],
       [0., 0., 1.]])
"""

from __future__ import annotations

import importlib

#: public name → the submodule of eulersym.numerics that defines it (loaded on first access).
_WHERE = {
    "invariants": None,
    "methods": None,
    "free_rigid_body_exact": "exact",
    "free_rigid_body_attitude_exact": "exact",
    "jacobi_sncndn": "elliptic",
    "complete_elliptic_k": "elliptic",
    "quaternion_multiply": "exact",
    "integrate_heavy_top": "heavy_top",
    "sleeping_top_threshold_numeric": "heavy_top",
    "heavy_top_exact": "heavy_top_exact",
    "HeavyTopMotion": "heavy_top_exact",
    "euler_to_quaternion": "heavy_top_exact",
    "integrate_ivp": "ivp",
    "integrate_pivoted": "pivoted",
    "PIVOTED_METHODS": "pivoted",
    "BatchTrajectory": "batched",
    "integrate_free_bodies": "batched",
    "integrate_heavy_tops": "batched",
    "integrate_pivoted_batch": "batched",
    "integrate_torqued": "lie_group",
    "FREE_BODY_METHODS": "splitting",
    "integrate_free_body": "splitting",
    "step_free_bodies": "splitting",
    "Trajectory": "trajectory",
}

__all__ = list(_WHERE)


def __getattr__(name: str):
    if name not in _WHERE:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    module = _WHERE[name]
    if module is None:  # a submodule exported by its own name
        return importlib.import_module(f"{__name__}.{name}")
    value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(__all__)


# ``heavy_top_exact`` names both a function and its module: bind the function now, or importing the submodule
# (which sets the package attribute) would shadow it.
from eulersym.numerics.heavy_top_exact import heavy_top_exact  # noqa: E402
