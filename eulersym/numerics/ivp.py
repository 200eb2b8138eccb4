"""The SciPy route: ``scipy.integrate.solve_ivp`` over a generated kernel module (or any look-alike).

A *module* is anything with ``rhs(t, y, *params)`` (returning a new sequence each call) and optionally
``jac(t, y, *params)``; the generated modules ``eulersym.generated.<name>`` are the intended ones. The Jacobian is
passed to the implicit methods (Radau, BDF, LSODA). This route handles torques and any system the splittings do
not cover, and is the baseline the benchmarks compare the geometric methods with.

State layouts (by the module's last dotted name, or ``layout=``):

========================== ===============================================
``euler_principal``        (ω1, ω2, ω3)
``euler_full``             (ω1, ω2, ω3)
``free_body_quaternion``   (ω1, ω2, ω3, q0, q1, q2, q3)
``heavy_top_euler_poisson`` (ω1, ω2, ω3, Γ1, Γ2, Γ3, q0, q1, q2, q3)
``heavy_top_euler_angles`` (φ, θ, ψ, φ̇, θ̇, ψ̇) → ω from the zxz kinematics
========================== ===============================================
"""

from __future__ import annotations

import math

import numpy as np

from eulersym.errors import IntegrationFailed, InvalidInput
from eulersym.numerics.trajectory import Trajectory
from eulersym.validation import choice, finite_array

__all__ = ["integrate_ivp", "IVP_METHODS", "LAYOUTS"]

IVP_METHODS = ("RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA")
_IMPLICIT = ("Radau", "BDF", "LSODA")
#: Known state layouts: name → (slice of ω, slice of q, slice of Γ, state length).
LAYOUTS = {
    "omega": (slice(0, 3), None, None, 3),
    "omega_q": (slice(0, 3), slice(3, 7), None, 7),
    "omega_gamma_q": (slice(0, 3), slice(6, 10), slice(3, 6), 10),
    "euler_angles": (None, None, None, 6),
}
_MODULE_LAYOUT = {
    "euler_principal": "omega",
    "euler_full": "omega",
    "free_body_quaternion": "omega_q",
    "heavy_top_euler_poisson": "omega_gamma_q",
    "heavy_top_euler_angles": "euler_angles",
}
#: Smallest relative tolerance a double-precision solver can honour.
MIN_RTOL = 100 * np.finfo(float).eps


class _TooMany(Exception):
    """More evaluations than ``max_calls``."""


def _omega_from_euler_angles(y):
    """Body ω from zxz angles and rates, rows = times, with the generated kinematics kernel."""
    from eulersym.generated import kinematics

    return np.asarray(kinematics.omega_body_batched(*y.T)).T.reshape(-1, 3)


def integrate_ivp(module, y0, t, params, *, method="DOP853", rtol=1e-10, atol=1e-12, layout=None, max_calls=None):
    """Integrate a kernel module's ``rhs`` with ``scipy.integrate.solve_ivp`` and sample it at ``t``.

    Parameters
    ----------
    module : module or object
        Has ``rhs(t, y, *params)``; ``jac(t, y, *params)`` is used by the implicit methods when present.
    y0 : array_like, shape (n_state,)
        Initial state in the module's order.
    t : array_like, shape (n,)
        Strictly increasing output times; integration runs from ``t[0]`` to ``t[-1]``.
    params : sequence of floats
        The module's parameters, in its documented order.
    method : {"RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA"}
    rtol, atol : float
        Tolerances; ``rtol`` below 100 ε (≈ 2.2e-14) cannot be honoured and is refused.
    layout : {"omega", "omega_q", "omega_gamma_q", "euler_angles"}, optional
        How to read ω, q and Γ from the state; default from the module name (see the module docstring).
    max_calls : int, optional
        Stop (:class:`~eulersym.errors.IntegrationFailed`) after this many evaluations of ``rhs``: no endless run.

    Returns
    -------
    Trajectory
        One motion (``omega`` of shape (n, 3)), with ``y`` holding the full state and ``n_rhs_calls`` every call of
        ``rhs`` (finite-difference Jacobians included).

    Raises
    ------
    eulersym.errors.InvalidInput
        Unknown method or layout, non-finite inputs, bad times, tolerances no double-precision solver can honour.
    eulersym.errors.IntegrationFailed
        The integration itself failed (``solve_ivp``'s status, a state that left the finite numbers, a right-hand side
        that raised — ``math.log`` of a negative number — or more than ``max_calls`` evaluations), with the time.

    Examples
    --------
    >>> import types, numpy as np
    >>> decay = types.SimpleNamespace(__name__="euler_principal",
    ...     rhs=lambda t, y, k: [-k * y[0], -k * y[1], -k * y[2]])
    >>> tr = integrate_ivp(decay, [1.0, 2.0, 3.0], [0.0, 1.0], (0.5,))
    >>> bool(abs(tr.omega[-1, 0] - np.exp(-0.5)) < 1e-9)
    True
    """
    method = choice("method", method, IVP_METHODS)
    if not hasattr(module, "rhs"):
        raise InvalidInput("module", module, "a kernel module with rhs(t, y, *params)")
    y0 = finite_array("y0", y0, shape=(None,))
    tt = finite_array("t", t, shape=(None,))
    if tt.size < 2 or np.any(np.diff(tt) <= 0):
        raise InvalidInput("t", t, "at least two strictly increasing output times")
    params = tuple(float(p) for p in finite_array("params", params, shape=(None,)))
    for name, value, low in (("rtol", rtol, MIN_RTOL), ("atol", atol, 0.0)):
        if not isinstance(value, (int, float)) or not math.isfinite(value) or value < low or (name == "rtol" and value >= 1):
            raise InvalidInput(name, value, f"a tolerance the solver can reach: {low:g} <= {name}" + (" < 1" if name == "rtol" else ""))
    if layout is None:
        layout = _MODULE_LAYOUT.get(str(getattr(module, "__name__", "")).rsplit(".", 1)[-1])
        if layout is None:
            layout = {3: "omega", 7: "omega_q", 10: "omega_gamma_q"}.get(y0.size)
    layout = choice("layout", layout, tuple(LAYOUTS))
    w_sl, q_sl, g_sl, n_state = LAYOUTS[layout]
    if y0.size != n_state:
        raise InvalidInput("y0", y0, f"{n_state} state components for the {layout!r} layout")
    rhs = module.rhs
    calls = 0
    where = [float(tt[0]), y0]

    def f(time, y):
        nonlocal calls
        calls += 1
        if max_calls is not None and calls > max_calls:
            raise _TooMany()
        where[0], where[1] = time, y
        return rhs(time, y, *params)

    first = np.asarray(f(tt[0], y0), dtype=np.float64)
    if first.shape != y0.shape or not np.all(np.isfinite(first)):
        raise InvalidInput("y0", y0, "a state at which the right-hand side is finite, of the same length")
    kwargs = {}
    if method in _IMPLICIT and hasattr(module, "jac"):
        jac = module.jac
        kwargs["jac"] = lambda time, y: np.asarray(jac(time, y, *params), dtype=np.float64)
    from scipy.integrate import solve_ivp  # imported here: closed-form and splitting runs never need it

    def state():
        return ", ".join(f"{v:.6g}" for v in np.asarray(where[1], dtype=float).tolist())

    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(f, (tt[0], tt[-1]), y0, method=method, t_eval=tt, rtol=rtol, atol=atol, **kwargs)
    except _TooMany:
        raise IntegrationFailed("ivp", f"{method} took more than {max_calls} evaluations by t = {where[0]:.6g} (the "
                                "motion is too fast for the span, or the tolerance too tight)",
                                "a shorter t_end or a looser accuracy") from None
    except (ValueError, OverflowError, ZeroDivisionError, FloatingPointError) as exc:
        raise IntegrationFailed("ivp", f"the right-hand side failed at t = {where[0]:.6g} from y = ({state()}) "
                                f"({type(exc).__name__}: {exc}): it left its domain or the finite numbers",
                                "a start and parameters that keep the right-hand side in its domain (or a shorter "
                                "t_end)") from None
    if sol.status != 0 or not np.all(np.isfinite(sol.y)) or sol.y.shape[1] != tt.size:
        why = sol.message if sol.status != 0 else "the state left the finite numbers"
        raise IntegrationFailed("ivp", f"{method} at rtol = {rtol:g}: {why} (at t = {where[0]:.6g}, from y = "
                                f"({state()}))", "a looser rtol, or a shorter t_end (before a singularity)")
    Y = sol.y.T.copy()
    omega = _omega_from_euler_angles(Y) if w_sl is None else Y[:, w_sl]
    return Trajectory(
        t=tt,
        omega=omega,
        q=None if q_sl is None else Y[:, q_sl],
        gamma=None if g_sl is None else Y[:, g_sl],
        n_rhs_calls=calls,
        method=f"solve_ivp:{method}",
        y=Y,
        message=str(sol.message),
    )
