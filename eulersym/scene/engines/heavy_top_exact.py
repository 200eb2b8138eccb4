"""Engine: the heavy symmetric top in closed form — ω(t), Γ(t), q(t) and the zxz Euler angles from
:func:`eulersym.numerics.heavy_top_exact` (u = cos θ from Jacobi's sn, φ ± ψ from elliptic integrals of the third
kind), every sweep member in one call, vectorised over the times. Integrates nothing: imports no
``scipy.integrate``."""

from __future__ import annotations

import importlib

import numpy as np

from eulersym.scene.trajectory import Trajectory

__all__ = ["run"]

#: The columns of the principal moments a symmetric top's closed form takes: (I1, I1, I3).
_SYMMETRIC = [0, 0, 2]


def run(problem, *, progress=None) -> Trajectory:
    """The exact motion of every member of ``problem`` (symmetric tops: the plan checked I1 = I2 to 1e-12).

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> from eulersym.scene.problem import member_moments, prepare
    >>> scene = Scene(moments=(1, 1, 0.5), mass=1, l=0.1, omega=(0, 0, 20), euler=(0, 0.5, 0), t_end=1, points=3)
    >>> traj = run(prepare(scene, scene.plan(), member_moments(scene), np.eye(3)))
    >>> traj.omega.shape, traj.n_calls
    ((1, 3, 3), 0)
    """
    numerics = importlib.import_module("eulersym.numerics")
    I = np.asarray(problem.moments, dtype=float)[:, _SYMMETRIC]  # (I1, I1, I3): symmetric to round-off
    motion = numerics.heavy_top_exact(I, problem.mass, problem.g, problem.l, problem.omega0, problem.q0, problem.t,
                                      accuracy=problem.accuracy)  # below a tenth of it: double where it suffices
    if progress is not None:
        progress(1.0)
    state = None if motion.rows is None else motion.rows.reshape(-1, 13, len(problem.t))[:, :10]
    return Trajectory(motion.omega, motion.q, motion.gamma, 0, euler=motion.euler,
                      turning=np.reshape(motion.turning_points, (-1, 2)), state=state, q_unit=True)
