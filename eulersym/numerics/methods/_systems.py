"""A problem's equations of motion as one batched ODE system over the committed kernels
(``eulersym.generated.*``) or a model's own kernel: the right-hand side, the initial state (state first, batch
after), the parameters per member, and how the state splits back into ω, q and Γ. Used by the integrating methods.

Frames: everything in the principal frame of the :class:`~eulersym.numerics.methods.Problem` (a model's own kernel:
the model frame).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from eulersym import quaternion as _quaternion
from eulersym.numerics.trajectory import Trajectory

__all__ = ["System", "system", "model_state", "model_system"]


@dataclass(frozen=True)
class System:
    """``y' = fun(t, y, *params)`` for y of shape (n_state, batch).

    Attributes
    ----------
    fun : callable
    y0 : ndarray (n_state, batch)
    params : tuple of ndarray (batch,)
    takes_out : bool
        ``fun`` accepts ``out=`` (the generated batched kernels do).
    layout : str
        'omega', 'omega+q', 'omega+gamma+q': how the state splits.
    normalize_q : bool
        Renormalise the quaternions of the output.
    module : module or None
        The one generated kernel whose ``rhs_flat(t, *y, *params)`` is the whole system (for eulersym's compiled
        DOP853); None when the system combines kernels in Python (a space-fixed torque with the attitude).

    Examples
    --------
    >>> from eulersym.numerics.methods import Problem
    >>> s = system(Problem(name="p", regime="torque-free", t=np.linspace(0, 1, 3), batch=1, members={},
    ...                    moments=np.array([[1.0, 2.0, 3.0]]), axes=np.eye(3), omega0=np.array([[0.0, 1.0, 0.0]]),
    ...                    q0=np.array([[1.0, 0, 0, 0]]), gamma0=np.array([[0.0, 0, 1]])))
    >>> s.layout, s.y0.shape
    ('omega', (3, 1))
    """

    fun: Callable
    y0: np.ndarray
    params: tuple
    takes_out: bool = False
    layout: str = "omega"
    normalize_q: bool = True
    module: object = None

    def flat_params(self) -> np.ndarray:
        """The parameters as one row per member (batch, k), as ``rhs_flat`` takes them after the state."""
        batch = self.y0.shape[1]
        out = np.empty((batch, len(self.params)))
        for k, p in enumerate(self.params):  # a column each (scalars broadcast): no stack of broadcast views
            out[:, k] = p
        return out

    def trajectory(self, t: np.ndarray, Y: np.ndarray, n_calls: int, method: str = "") -> Trajectory:
        """A batch-first :class:`Trajectory` at times ``t`` from the integrated states ``Y`` (n_times, n_state,
        batch)."""
        return self.members_trajectory(t, np.moveaxis(Y, (0, 1, 2), (1, 2, 0)), n_calls, method)

    def members_trajectory(self, t: np.ndarray, Y: np.ndarray, n_calls: int, method: str = "",
                           message: str = "") -> Trajectory:
        """The same from the states batch-first, ``Y`` (batch, n_times, n_state)."""
        if self.layout == "omega":
            return Trajectory(t=t, omega=Y, n_rhs_calls=n_calls, method=method, message=message)
        if self.layout == "omega+q":
            q = _quaternion.normalize(Y[..., 3:7]) if self.normalize_q else Y[..., 3:7]
            return Trajectory(t=t, omega=Y[..., :3], q=q, n_rhs_calls=n_calls, method=method, message=message)
        q = _quaternion.normalize(Y[..., 6:10]) if self.normalize_q else Y[..., 6:10]
        return Trajectory(t=t, omega=Y[..., :3], q=q, gamma=Y[..., 3:6], n_rhs_calls=n_calls, method=method,
                          message=message)


def _kernel(name: str):
    """The committed kernel module ``eulersym.generated.<name>`` (imported when a system needs it)."""
    if name == "free_body_quaternion":
        from eulersym.generated import free_body_quaternion as module
    elif name == "euler_principal":
        from eulersym.generated import euler_principal as module
    else:
        from eulersym.generated import heavy_top_euler_poisson as module
    return module


def system(problem) -> System:
    """The batched ODE system of ``problem`` (torque-free, heavy top or constant torque) on the committed kernels."""
    if problem.regime == "model":
        return model_system(problem)
    I = tuple(problem.moments[:, k] for k in range(3))
    if problem.regime == "torque-free":
        if problem.wants_attitude:
            gen = _kernel("free_body_quaternion")
            y0 = np.concatenate([problem.omega0, problem.q0], axis=1).T
            return System(gen.rhs_batched, y0, I, layout="omega+q", module=gen)
        gen = _kernel("euler_principal")
        zeros = np.zeros(problem.batch)
        return System(gen.rhs_batched, problem.omega0.T, (*I, zeros, zeros, zeros), module=gen)
    if problem.regime == "heavy top":
        gen = _kernel("heavy_top_euler_poisson")
        y0 = np.concatenate([problem.omega0, problem.gamma0, problem.q0], axis=1).T
        wants_q = any(o in problem.outputs for o in ("attitude", "euler_angles", "invariants"))
        return System(gen.rhs_batched, y0, (*I, problem.mass, problem.g, problem.l), takes_out=True,
                      layout="omega+gamma+q", normalize_q=wants_q, module=gen)
    return _torqued(problem, I)


def _torqued(problem, I) -> System:
    euler = _kernel("euler_principal")
    N = problem.torque
    params = (*I, N[:, 0], N[:, 1], N[:, 2])
    space = problem.torque_frame == "space"
    if not problem.wants_attitude:
        return System(euler.rhs_batched, problem.omega0.T, params, module=euler)
    free = _kernel("free_body_quaternion")

    def fun(tt, y, I1, I2, I3, N1, N2, N3):  # y (7, batch); a space-fixed torque turned to body components
        torque = _quaternion.rotate_back(y[3], y[4], y[5], y[6], N1, N2, N3) if space else (N1, N2, N3)
        dw = euler.rhs_batched(tt, y[:3], I1, I2, I3, torque[0], torque[1], torque[2])
        dq = free.rhs_batched(tt, y, I1, I2, I3)[3:7]
        return np.concatenate([dw, dq], axis=0)

    return System(fun, np.concatenate([problem.omega0, problem.q0], axis=1).T, params, layout="omega+q")


def model_state(problem) -> np.ndarray:
    """A model problem's initial state (n_state, batch) in its kernel's ``STATE`` order (model frame).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> p = NS(model=NS(state=("omega1", "omega2", "omega3", "q0", "q1", "q2", "q3")), omega0=np.array([[0.0, 1, 2]]),
    ...        gamma0=np.array([[0.0, 0, 1]]), q0=np.array([[1.0, 0, 0, 0]]))
    >>> model_state(p)[:, 0].tolist()
    [0.0, 1.0, 2.0, 1.0, 0.0, 0.0, 0.0]
    """
    values = {}
    for k in range(3):
        values[f"omega{k + 1}"] = problem.omega0[:, k]
        values[f"gamma{k + 1}"] = problem.gamma0[:, k]
    for k in range(4):
        values[f"q{k}"] = problem.q0[:, k]
    return np.stack([values[name] for name in problem.model.state])


def model_system(problem) -> System:
    """A model's own kernel as a batched system: ``rhs_batched(t, y, *params, out=)``, its state in ``STATE`` order."""
    facts = problem.model
    layout = "omega+gamma+q" if "gamma1" in facts.state else "omega+q"
    # q as integrated (not renormalised): the model's |q|² invariant reports its drift
    return System(facts.module.rhs_batched, model_state(problem), tuple(facts.params), takes_out=True, layout=layout,
                  normalize_q=False, module=facts.module if hasattr(facts.module, "rhs_flat") else None)

