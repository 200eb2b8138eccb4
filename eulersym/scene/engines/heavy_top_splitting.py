"""Engine: the symmetric heavy top by the fourth-order Yoshida splitting in the Euler–Poisson form
(:func:`eulersym.numerics.integrate_heavy_top`): |Γ| and L·Γ conserved, never singular at θ = 0; one member."""

from __future__ import annotations

import importlib

import numpy as np

from eulersym.scene.trajectory import Trajectory

__all__ = ["run", "step"]


def step(I, M, g, l, omega0, t, accuracy: float) -> float:
    """Step for the 4th-order splitting: h = (30 · accuracy)^¼ / Ω, Ω the fastest of the nutation rate
    I3|ω3|/I1, the pendulum rate sqrt(M g l / I1) and the transverse spin (calibrated on the bundled heavy tops,
    the unstable sleeping top included: the error stays below the accuracy asked).

    Examples
    --------
    >>> step((1.0, 1.0, 0.5), 1.0, 9.81, 0.1, (0.0, 0.0, 20.0), np.linspace(0, 1, 11), 1e-4)  # Ω = I3 ω3 / I1 = 10
    0.02
    """
    I1, _, I3 = I
    rate = max(I3 * abs(omega0[2]) / I1, np.sqrt(M * g * l / I1), np.linalg.norm(omega0[:2]), 1e-12)
    dt = t[1] - t[0]
    h = min(dt, (30.0 * accuracy) ** 0.25 / rate)
    return float(dt / np.ceil(dt / h))


def run(problem, *, progress=None) -> Trajectory:
    """Integrate the first (only) member of ``problem`` (a symmetric top: the plan checked I1 = I2 to 1e-12)."""
    numerics = importlib.import_module("eulersym.numerics")
    I1, _, I3 = (float(x) for x in problem.moments[0])
    I = (I1, I1, I3)  # symmetric to round-off
    M, g, l = float(problem.mass[0]), float(problem.g[0]), float(problem.l[0])
    h = step(I, M, g, l, problem.omega0[0], problem.t, problem.accuracy)
    traj = numerics.integrate_heavy_top(I, M, g, l, problem.omega0[0], problem.q0[0], problem.t, h=h, method="yoshida4")
    return Trajectory(traj.omega[None], traj.q[None], np.asarray(traj.gamma)[None], traj.n_rhs_calls)
