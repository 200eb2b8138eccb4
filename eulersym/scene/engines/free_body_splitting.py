"""Engine: the torque-free body by the fourth-order Moser–Veselov splitting with modified moments
(:func:`eulersym.numerics.integrate_free_body`, method 'dmv4'); one member."""

from __future__ import annotations

import importlib

import numpy as np

from eulersym.scene.trajectory import Trajectory

__all__ = ["run", "step"]


def step(I, omega0, t, accuracy: float) -> float:
    """Step for the 4th-order splitting: (Ω h)^4 ≈ accuracy, Ω = |ω0| · max|I_j − I_k| / min I, rounded so whole
    steps fit between output times.

    Examples
    --------
    >>> step((1.0, 2.0, 3.0), (0.0, 1.0, 0.0), np.linspace(0, 1, 11), 1e-8)
    0.005
    """
    spread = (max(I) - min(I)) / min(I)
    rate = max(np.linalg.norm(omega0) * max(spread, 1e-3), 1e-12)
    dt = t[1] - t[0]
    h = min(dt, accuracy ** 0.25 / rate)
    return float(dt / np.ceil(dt / h))


def run(problem, *, progress=None) -> Trajectory:
    """Integrate the first (only) member of ``problem`` by the splitting."""
    numerics = importlib.import_module("eulersym.numerics")
    I = tuple(problem.moments[0])
    h = step(I, problem.omega0[0], problem.t, problem.accuracy)
    traj = numerics.integrate_free_body(I, problem.omega0[0], problem.q0[0], problem.t, method="dmv4", h=h)
    return Trajectory(traj.omega[None], traj.q[None] if traj.q is not None else None, None, traj.n_rhs_calls)
