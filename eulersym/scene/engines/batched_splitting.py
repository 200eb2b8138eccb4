"""Engine: every member at once by the exact-flow splitting of a pivoted body (Yoshida 4, batched over members,
compiled by numba when the ``fast`` extra is installed: :func:`eulersym.numerics.batched.integrate_pivoted_batch`),
each member with its own step from the accuracy asked — so a member's numbers do not depend on which chunk, or
which Dask worker, it runs in. |Γ| and L·Γ are kept, and the Euler–Poisson form is never singular at θ = 0."""

from __future__ import annotations

import importlib

import numpy as np

from eulersym.scene.trajectory import Trajectory

__all__ = ["run", "METHOD"]

#: The composition: fourth order (the plan's choice for sweeps without a closed form).
METHOD = "yoshida4"


def run(problem, *, progress=None) -> Trajectory:
    """Integrate all members of a heavy-top ``problem`` (principal frame, centre of mass at l e3).

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> from eulersym.scene.problem import member_moments, prepare
    >>> s = Scene(moments=(1, 1.5, 0.5), mass=1, l=0.1, omega=(0, 0, [5.0, 6.0]), euler=(0, 0.2, 0), t_end=1, points=3)
    >>> traj = run(prepare(s, s.plan(), member_moments(s), np.eye(3)))
    >>> traj.omega.shape, bool(np.allclose(np.linalg.norm(traj.gamma, axis=-1), 1.0, atol=1e-12))
    ((2, 3, 3), True)
    """
    batched = importlib.import_module("eulersym.numerics.batched")
    c = np.zeros((problem.batch, 3))
    c[:, 2] = problem.l
    tensors = problem.moments[:, :, None] * np.eye(3)  # (B, 3, 3): the principal frame's diagonal tensors
    bt = batched.integrate_pivoted_batch(tensors, problem.mass, problem.g, c, problem.omega0, problem.q0,
                                         problem.t, method=METHOD, accuracy=problem.accuracy, max_bytes=np.inf)
    if progress is not None:
        progress(1.0)
    return Trajectory(bt.omega, bt.q, bt.gamma, bt.n_kicks)
