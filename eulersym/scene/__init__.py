"""Scenes: describe a body and what you want to know; eulersym derives, emits and integrates only that.

A :class:`Scene` says *what*: a :class:`~eulersym.model.Model` — the body (principal moments, a full inertia
tensor, a named shape with mass and dimensions, or parts), an optional fixed pivot, gravity, torques, a rotor, its
parameters — written as a model file or, the short way, with the body's keywords (``Scene(moments=..., mass=...,
l=..., g=..., torque=...)`` builds the same model); the initial attitude (Euler angles in a named convention, a
unit quaternion, or axis–angle) and angular velocity (body or space components), the end time, the outputs wanted
and the accuracy wanted. :meth:`Scene.plan` says *how* — the model's facts (NumPy: mass, centre of mass, tensor,
torques per member) classified into a regime and a principal frame, and the first method of
:mod:`eulersym.numerics.methods` that applies: a closed form wherever one exists, otherwise the integrator expected
to meet the accuracy at least cost — and what is skipped, and why. :func:`simulate` runs the plan and returns a
:class:`Result`.

The package reads in the direction data flows, no module importing a later one:
:mod:`~eulersym.scene.values` (numbers, sweeps) → :mod:`~eulersym.scene.regime` (what acts on the body, its frame:
from the facts) → :mod:`~eulersym.scene.plan` (pure: the loop over the methods) → :mod:`~eulersym.scene.spec`
(:class:`Scene`: a model, its start, validated) → :mod:`~eulersym.scene.problem` (the prepared problem) →
:mod:`eulersym.numerics.methods` (the motion) → :mod:`~eulersym.scene.result` → :mod:`~eulersym.scene.run`
(:func:`simulate`, the one driver) → :mod:`~eulersym.scene.io` (files, plots) → :mod:`~eulersym.scene.cli`.
SymPy comes in only with :mod:`~eulersym.scene.symbolic` (the sleeping-top bound, turning points) and a model's own
kernel when first emitted.

Conventions (as everywhere in eulersym). The attitude is the unit quaternion q = (q0, q1, q2, q3), scalar first,
whose active rotation R(q) maps body components to space components, ``v_space = R(q) @ v_body``; the text's
passive matrix is ``A = R(q).T`` so that ``r_body = A @ r_space``, and for the default convention ``"zxz"``
``A = B(psi) C(theta) D(phi)``. Angular velocity is in body components unless a name says ``space``. The body-frame
upward vertical is ``Gamma = A @ (0, 0, 1)``, and ``Gamma3 = cos(theta)``. A pivoted body has its centre of mass at
``l * e3`` in the body frame; its moments are about the pivot.

Sweeps: wherever a scene takes a number it may take a list of numbers or a range ``{start, stop, num}`` instead
(a swept body number becomes a parameter of the model); the members are the outer product of all swept values, run
in one vectorised pass on the batched kernels.

The TOML layout is described in :mod:`eulersym.scene.spec` (a model file plus the scene's sections).

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
