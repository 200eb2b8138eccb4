"""The conditioning of a motion: how much a small change of its start grows, from the variational equations.

Along a motion y(t) of ``y' = f(t, y)`` the state-transition matrix Φ(t) = ∂y(t)/∂y(0) solves
``Φ' = J(t, y(t)) Φ``, ``Φ(0) = 1``, with J the kernel's symbolic Jacobian (``jac_batched``; the same CSE pass as its
right-hand side). The growth of a change of the start is Φ's largest singular value σ(t) — computed here for the
state scaled so that its parts are comparable (ω divided by its size at the start, Γ and q as they are:
``Φ_s = D⁻¹ Φ D``, ``D = diag(|ω0|, |ω0|, |ω0|, 1, …)``). The finite-time Lyapunov exponent is ``ln σ(T) / T``.

This is also the amplification of round-off: an error committed at time s grows by about Φ(t) Φ(s)⁻¹ by time t, so a
motion whose σ reaches 10⁶ cannot be carried to better than ~10⁶ ε by any double-precision integrator
(:class:`eulersym.errors.AccuracyNotReached` uses it).

The augmented system (n + n² components per member) is integrated by eulersym's compiled DOP853 over the kernel's
``rhs_flat`` and ``jac_flat`` when numba is installed, else by the batched DOP853 in NumPy, at rtol 1e-9 (the
conditioning needs a few digits, not many); a system that combines kernels in Python (a space-fixed torque with the
attitude) uses J·Φ by forward differences of its right-hand side instead.

Examples
--------
A free body spun near its intermediate axis: a change of the start grows fast (the separatrix is near).

>>> import numpy as np
>>> from eulersym.numerics.methods import Problem
>>> p = Problem(name="p", regime="torque-free", t=np.linspace(0.0, 20.0, 5), batch=1, members={},
...             moments=np.array([[1.0, 2.0, 3.0]]), axes=np.eye(3), omega0=np.array([[1e-3, 1.0, 1e-3]]),
...             q0=np.array([[1.0, 0, 0, 0]]), gamma0=np.array([[0.0, 0, 1]]))
>>> sigma, lyapunov = sensitivity(p)
>>> float(sigma[0, 0]), bool(sigma[0, -1] > 100), bool(lyapunov[0] > 0)
(1.0, True, True)
"""

from __future__ import annotations

import numpy as np

__all__ = ["sensitivity", "RTOL"]

#: Tolerance of the variational integration.
RTOL = 1e-9


def _scaling(problem, n: int) -> np.ndarray:
    """D per member (batch, n): ω's components by the size of ω at the start, the rest by 1."""
    w = np.linalg.norm(problem.omega0, axis=1)
    d = np.ones((problem.batch, n))
    d[:, :3] = np.where(w > 0, w, 1.0)[:, None]
    return d


def sensitivity(problem, *, rtol: float = RTOL) -> tuple:
    """``(sigma, lyapunov)`` of every member of a prepared ``problem``: σ(t) (batch, len(t)), the largest singular
    value of the scaled state-transition matrix at each output time, and the finite-time Lyapunov exponent
    ``ln σ(t_end) / (t_end − t_0)`` (batch,).

    Raises
    ------
    eulersym.errors.IntegrationFailed
        The variational integration could not get the motion (it overflows: no finite conditioning).
    """
    from eulersym.numerics.methods._systems import system

    s = system(problem)
    n, batch = s.y0.shape
    D = _scaling(problem, n)  # (batch, n)
    Phi = _compiled(problem, s, rtol) if _compilable(s) else _numpy(problem, s, rtol)
    scaled = Phi * D[:, None, None, :] / D[:, None, :, None]  # D⁻¹ Φ D
    sigma = np.linalg.norm(scaled, ord=2, axis=(-2, -1))
    span = float(problem.t[-1] - problem.t[0]) if len(problem.t) > 1 else 0.0
    lyapunov = np.log(np.maximum(sigma[:, -1], 1e-300)) / span if span > 0 else np.zeros(batch)
    return sigma, lyapunov


def _compilable(s) -> bool:
    from eulersym.numerics.methods._base import numba_available

    return s.module is not None and hasattr(s.module, "jac_flat") and numba_available()


def _compiled(problem, s, rtol) -> np.ndarray:
    """Φ (batch, m, n, n) by eulersym's compiled DOP853 over the kernel's variational system."""
    from eulersym.errors import IntegrationFailed
    from eulersym.numerics.methods import _dop853

    n, batch = s.y0.shape
    Y0 = np.concatenate([s.y0.T, np.tile(np.eye(n).ravel(), (batch, 1))], axis=1)
    run = _dop853.integrate(s.module, Y0, problem.t, s.flat_params(), rtol=rtol, atol=rtol * 1e-3,
                            function=_dop853.variational_function(s.module), max_steps=50_000_000)
    if np.any(run.status != _dop853.OK):
        b = int(np.flatnonzero(run.status != _dop853.OK)[0])
        raise IntegrationFailed("sensitivity", f"the variational equations of member {b}: "
                                f"{_dop853.STATUS[int(run.status[b])]} at t = {run.reached[b]:.6g}", "a shorter t_end")
    return run.y[:, :, n:].reshape(batch, len(problem.t), n, n)


def _numpy(problem, s, rtol) -> np.ndarray:
    """Φ (batch, m, n, n) by the batched DOP853 in NumPy (J from ``jac_batched``, or by forward differences)."""
    from eulersym.numerics.methods._batched_dop853 import dop853_batched

    n, batch = s.y0.shape
    jac = getattr(s.module, "jac_batched", None) if s.module is not None else None
    params = s.params

    def fun(t, Y, *p, out=None):
        y = Y[:n]
        Phi = Y[n:].reshape(n, n, -1)
        dy = s.fun(t, y, *p) if not s.takes_out else s.fun(t, y, *p, out=None)
        if jac is not None:
            J = jac(t, y, *p)
            dPhi = np.einsum("ijb,jkb->ikb", J, Phi)
        else:  # J Φ column by column by forward differences, each column scaled to a small step
            dPhi = np.empty_like(Phi)
            for k in range(n):
                col = Phi[:, k]
                size = np.maximum(np.linalg.norm(col, axis=0), 1e-300)
                eps = 1e-7 * np.maximum(np.linalg.norm(y, axis=0), 1.0) / size
                dPhi[:, k] = (s.fun(t, y + eps * col, *p) - dy) / eps
        value = np.concatenate([dy, dPhi.reshape(n * n, -1)], axis=0)
        if out is None:
            return value
        out[...] = value
        return out

    Y0 = np.concatenate([s.y0, np.repeat(np.eye(n).reshape(n * n, 1), batch, axis=1)], axis=0)
    Y, _ = dop853_batched(fun, Y0, problem.t, params=params, rtol=rtol, atol=rtol * 1e-3)
    return np.moveaxis(Y[:, n:].reshape(len(problem.t), n, n, batch), -1, 0)  # (batch, m, n, n)
