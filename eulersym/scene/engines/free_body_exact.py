"""Engine: the torque-free body in closed form — ω(t) (and q(t)) from :mod:`eulersym.numerics`' exact oracle
(Jacobi elliptic functions, or trigonometric for a symmetric top), one evaluation per member, vectorised over times.
Integrates nothing: imports no ``scipy.integrate``."""

from __future__ import annotations

import importlib

import numpy as np

from eulersym.scene.trajectory import Trajectory

__all__ = ["run"]


def run(problem, *, progress=None) -> Trajectory:
    """The exact torque-free motion of every member of ``problem``.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> from eulersym.scene.problem import member_moments, prepare
    >>> scene = Scene(moments=(2, 2, 1), omega=(0, 0, 3), t_end=1, points=3)
    >>> run(prepare(scene, scene.plan(), member_moments(scene), np.eye(3))).omega[0, -1].tolist()
    [0.0, 0.0, 3.0]
    """
    numerics = importlib.import_module("eulersym.numerics")  # looked up per call: tests may stand in for it
    batch, n = problem.batch, len(problem.t)
    omega = np.empty((batch, n, 3))
    q = np.empty((batch, n, 4)) if problem.wants_attitude else None
    for b in range(batch):
        I = tuple(problem.moments[b])
        if q is not None:
            omega[b], q[b] = numerics.free_rigid_body_attitude_exact(I, problem.omega0[b], problem.q0[b], problem.t)
        else:
            omega[b] = numerics.free_rigid_body_exact(I, problem.omega0[b], problem.t)
        if progress is not None and batch > 1:
            progress((b + 1) / batch)
    return Trajectory(omega, q, None, 0)
