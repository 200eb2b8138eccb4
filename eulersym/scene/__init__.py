"""Scenes: describe a body and what you want to know; eulersym derives, emits and integrates only that.

A :class:`Scene` says *what*: the body (principal moments, a full inertia tensor, or a named shape with mass and
dimensions), an optional fixed pivot with the centre of mass at distance ``l`` along body axis 3 (the heavy top),
gravity ``g``, an optional constant torque (body- or space-fixed), the initial attitude (Euler angles in a named
convention, a unit quaternion, or axis–angle) and angular velocity (body or space components), the end time, the
outputs wanted and the accuracy wanted. :meth:`Scene.plan` says *how* — which derivations and kernels are needed and
no others, a closed form wherever one exists, otherwise the integrator expected to meet the accuracy at least
cost — and what is skipped, and why. :func:`simulate` runs the plan and returns a :class:`Result`.

The package reads in the direction data flows, no module importing a later one:
:mod:`~eulersym.scene.values` (numbers, sweeps) → :mod:`~eulersym.scene.plan` (pure: which engine, and why) →
:mod:`~eulersym.scene.spec` (:class:`Scene`, validated) → :mod:`~eulersym.scene.derive` (SymPy, only when a plan
lists a derivation) → :mod:`~eulersym.scene.problem` (the frozen prepared problem) →
:mod:`~eulersym.scene.engines` (one module per way of getting the motion) → :mod:`~eulersym.scene.result` →
:mod:`~eulersym.scene.run` (:func:`simulate`, the one driver) → :mod:`~eulersym.scene.io` (files, plots) →
:mod:`~eulersym.scene.cli`.

Conventions (as everywhere in eulersym). The attitude is the unit quaternion q = (q0, q1, q2, q3), scalar first,
whose active rotation R(q) maps body components to space components, ``v_space = R(q) @ v_body``; the text's
passive matrix is ``A = R(q).T`` so that ``r_body = A @ r_space``, and for the default convention ``"zxz"``
``A = B(psi) C(theta) D(phi)``. Angular velocity is in body components unless a name says ``space``. The body-frame
upward vertical is ``Gamma = A @ (0, 0, 1)``, and ``Gamma3 = cos(theta)``. A pivoted body has its centre of mass at
``l * e3`` in the body frame; its moments are about the pivot.

Sweeps: wherever a scene takes a number it may take a list of numbers or a range ``{start, stop, num}`` instead;
the members are the outer product of all swept values, run in one vectorised pass on the batched kernels.

The TOML layout is described in :mod:`eulersym.scene.spec`.

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

from eulersym.scene.catalog import bundled
from eulersym.scene.cli import cli
from eulersym.scene.plan import Plan, Step
from eulersym.scene.result import Result
from eulersym.scene.run import simulate
from eulersym.scene.spec import CONVENTIONS, METHODS, OUTPUTS, SHAPES, Scene, load
from eulersym.scene.values import Sweep

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
