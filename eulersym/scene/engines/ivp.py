"""Engine: one member by ``scipy.integrate.solve_ivp`` (the method the plan names) on a committed kernel —
:func:`eulersym.numerics.integrate_ivp` over the scalar kernel where one kernel holds the whole state, else
``solve_ivp`` over the batched system of :mod:`eulersym.scene.systems` with a batch of one."""

from __future__ import annotations

import importlib

import numpy as np

from eulersym import quaternion as _quaternion
from eulersym.errors import InvalidInput
from eulersym.scene.trajectory import Trajectory

__all__ = ["run"]


def run(problem, *, progress=None) -> Trajectory:
    """Integrate the first (only) member of ``problem``.

    Examples
    --------
    >>> from eulersym.scene import Scene
    >>> from eulersym.scene.problem import member_moments, prepare
    >>> scene = Scene(moments=(2, 2, 1), omega=(0, 0, 3), t_end=1, points=3, outputs=("omega",), method="RK45")
    >>> run(prepare(scene, scene.plan(), member_moments(scene), np.eye(3))).omega[0, -1].tolist()
    [0.0, 0.0, 3.0]
    """
    numerics = importlib.import_module("eulersym.numerics")
    I = tuple(float(x) for x in problem.moments[0])
    w0, method = problem.omega0[0], problem.ivp_method
    tol = dict(method=method, rtol=problem.rtol, atol=problem.atol)
    if problem.regime == "model":  # the model's own kernel: rhs and jac, state (ω, [Γ,] q)
        systems = importlib.import_module("eulersym.scene.systems")
        y0 = systems.model_state(problem)[:, 0]
        params = tuple(float(p[0]) for p in problem.model.params)
        layout = "omega_gamma_q" if "gamma1" in problem.model.state else "omega_q"
        traj = numerics.integrate_ivp(problem.model.module, y0, problem.t, params, layout=layout, **tol)
        gamma = np.asarray(traj.gamma)[None] if traj.gamma is not None else None
        return Trajectory(traj.omega[None], traj.q[None], gamma, traj.n_rhs_calls)  # q as integrated
    if problem.regime == "torque-free":
        if problem.wants_attitude:
            gen = importlib.import_module("eulersym.generated.free_body_quaternion")
            traj = numerics.integrate_ivp(gen, np.concatenate([w0, problem.q0[0]]), problem.t, I, **tol)
            q = _quaternion.normalize(traj.q)[None] if traj.q is not None else None
            return Trajectory(traj.omega[None], q, None, traj.n_rhs_calls)
        gen = importlib.import_module("eulersym.generated.euler_principal")
        traj = numerics.integrate_ivp(gen, w0, problem.t, I + (0.0, 0.0, 0.0), **tol)
        return Trajectory(traj.omega[None], None, None, traj.n_rhs_calls)
    if problem.regime == "heavy top":
        gen = importlib.import_module("eulersym.generated.heavy_top_euler_poisson")
        y0 = np.concatenate([w0, problem.gamma0[0], problem.q0[0]])
        params = I + (float(problem.mass[0]), float(problem.g[0]), float(problem.l[0]))
        traj = numerics.integrate_ivp(gen, y0, problem.t, params, **tol)
        return Trajectory(traj.omega[None], _quaternion.normalize(traj.q)[None], np.asarray(traj.gamma)[None], traj.n_rhs_calls)
    if not problem.wants_attitude:  # a body-fixed torque, ω only: Euler's equations with N on the scalar kernel
        gen = importlib.import_module("eulersym.generated.euler_principal")
        traj = numerics.integrate_ivp(gen, w0, problem.t, I + tuple(float(x) for x in problem.torque[0]), **tol)
        return Trajectory(traj.omega[None], None, None, traj.n_rhs_calls)
    return _solve_system(problem)


def _solve_system(problem) -> Trajectory:
    from scipy.integrate import solve_ivp

    systems = importlib.import_module("eulersym.scene.systems")
    s = systems.system(problem)
    params = s.params
    t = problem.t
    sol = solve_ivp(lambda tt, y: s.fun(tt, y[:, None], *params)[:, 0], (t[0], t[-1]), s.y0[:, 0],
                    method=problem.ivp_method, t_eval=t, rtol=problem.rtol, atol=problem.atol)
    if not sol.success:
        raise InvalidInput("accuracy", problem.accuracy, f"an accuracy {problem.ivp_method} can reach ({sol.message})")
    return s.trajectory(sol.y[None].transpose(2, 1, 0), sol.nfev)
