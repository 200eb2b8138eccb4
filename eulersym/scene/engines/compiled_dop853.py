"""Engine: a heavy-top sweep by Dormand–Prince 8(5,3) compiled with numba (the ``fast`` extra), one member per
iteration of a ``prange`` loop over the generated flat kernel ``heavy_top_euler_poisson.rhs_flat``.

Each member adapts its own step (scipy's DOP853 tableau, error norm and step control, steps clipped to land on the
output times, as :func:`eulersym.scene.dop853.dop853_batched` does for a group), so a member's numbers depend on
nothing but its own start: chunks and Dask workers give the same bits. No temporaries beyond the outputs: the
stages live in per-member scratch, and the loop runs at the speed of the kernel's arithmetic instead of the
memory traffic of batched NumPy.

Why it is the plan's default for sweeps without a closed form (``eulersym bench sweeps``): at the accuracies a
scene asks (1e-6 … 1e-10) the eighth-order method takes ~10× fewer steps than the fourth-order geometric
splitting (:mod:`eulersym.scene.engines.batched_splitting`, chosen with ``method = "splitting"`` for its
conserved |Γ| and L·Γ over long spans).
"""

from __future__ import annotations

import importlib
import importlib.util

import numpy as np

from eulersym.scene.trajectory import Trajectory

__all__ = ["run", "available", "TIGHTER"]

#: The members' tolerances are the plan's (:func:`eulersym.scene.plan.ivp_tolerances`: rtol = accuracy / 10) divided
#: by this, so rtol = accuracy / 100. Along a sensitive motion (an asymmetric heavy top: a start perturbed by 1e-10
#: moves ω by up to 1e-5 within T = 2) the global error of a few members is many times the tolerance, whatever the
#: integrator; the shared-step batched DOP853 (``method = "DOP853"``) is as accurate as the smallest step of each
#: chunk of 4096 members makes it. Every member of the bench's asymmetric sweep (T = 2, accuracy 1e-6) against the
#: same sweep at accuracy 1e-10 — 10⁵ members: beyond 1e-6 7.0 % here, 12.0 % batched DOP853; p99 1.2e-5 (1.8e-5),
#: max 2.2e-3 (3.0e-3), median 6.1e-8 (1.3e-7). With 4000 members (one chunk: every member takes the hardest
#: one's steps) batched DOP853 does better, 2.3 % beyond; matching that here takes ÷50 (2.1 %) at 1.2× the kernel
#: calls. ``eulersym bench sweeps --only dop853`` prints these counts for both engines.
TIGHTER = 10


def available() -> bool:
    """True when numba is installed (the plan chooses this engine only then).

    Examples
    --------
    >>> isinstance(available(), bool)
    True
    """
    return importlib.util.find_spec("numba") is not None


def run(problem, *, progress=None) -> Trajectory:
    """Integrate every member of a heavy-top ``problem`` (principal frame), each with its own adaptive step.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> from eulersym.scene.problem import member_moments, prepare
    >>> s = Scene(moments=(1, 1.5, 0.5), mass=1, l=0.1, omega=(0, 0, [5.0, 6.0]), euler=(0, 0.2, 0), t_end=1, points=3)
    >>> traj = run(prepare(s, s.plan(), member_moments(s), np.eye(3)))
    >>> traj.omega.shape, traj.q.shape
    ((2, 3, 3), (2, 3, 4))
    """
    from eulersym import quaternion as _quaternion
    from eulersym.errors import InvalidInput

    members = importlib.import_module("eulersym.sweeps.members_dop853").members
    y0 = np.ascontiguousarray(np.concatenate([problem.omega0, problem.gamma0, problem.q0], axis=1))
    params = np.ascontiguousarray(np.stack([problem.moments[:, 0], problem.moments[:, 1], problem.moments[:, 2],
                                            problem.mass, problem.g, problem.l], axis=1))
    t = np.ascontiguousarray(problem.t, dtype=float)
    out = np.empty((problem.batch, len(t), 10))
    calls = members(y0, params, t, float(problem.rtol) / TIGHTER, float(problem.atol) / TIGHTER, out)
    if np.any(calls == -1):
        raise InvalidInput("scene", "sweep", "a sweep whose members stay finite (a member's state overflowed)")
    if np.any(calls == -2):
        raise InvalidInput("accuracy", problem.rtol, "an accuracy the integrator can reach (the step size underflowed)")
    if progress is not None:
        progress(1.0)
    wants_q = any(o in problem.outputs for o in ("attitude", "euler_angles", "invariants"))
    q = _quaternion.normalize(out[..., 6:10]) if wants_q else out[..., 6:10]
    return Trajectory(out[..., :3], q, out[..., 3:6], int(calls.sum()))
