"""A body on a plane in motion: its start checked, its kernel integrated, lift-off caught (NumPy and SciPy only).

:func:`start` builds the initial state ``y0`` of a contact kernel (:mod:`eulersym.model.rolling_kernels`) from the
angular velocity, the attitude and the horizontal position (and, sliding, velocity), and refuses a start that does
not touch the plane or does not press on it. :func:`integrate` runs :func:`scipy.integrate.solve_ivp` on the
kernel's ``rhs`` (its ``jac`` for the implicit methods) with the kernel's lift-off event, and raises
:class:`LiftOff` — with the time, the state and the normal force — when the body leaves the plane: the equations
hold only while it touches (eulersym models no flight and no impact), so the run stops there instead of
continuing as a wrong motion.

Examples
--------
>>> from eulersym.model.contact_examples import examples
>>> from eulersym.model.rolling_kernels import compile
>>> kernel = compile(examples()["rolling-sphere"])
>>> y0 = start(kernel, omega=(0.0, 10.0, 0.0))
>>> motion = integrate(kernel, y0, [0.0, 0.5, 1.0])
>>> [round(float(v), 9) for v in motion["x_cm"]]              # v = a ω = 1 m/s, a straight line
[0.0, 0.5, 1.0]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from eulersym.errors import CheckFailed, EulersymError, InvalidInput
from eulersym.numerics.methods._base import numba_available
from eulersym.validation import finite_array

__all__ = ["LiftOff", "ContactMotion", "start", "integrate", "integrate_members"]

#: The most samples of the normal force the compiled engine takes in one run, all members together
#: (:func:`integrate_members`).
MAX_SAMPLES = 1_000_000

_IMPLICIT = ("Radau", "BDF", "LSODA")
_METHODS = ("DOP853", "RK45", "RK23", *_IMPLICIT)


class LiftOff(EulersymError):
    """The body left the plane: its normal force fell to zero at time ``t`` (the contact equations stop holding).

    Attributes
    ----------
    t : float
        The time of lift-off (located by the integrator's event to its tolerance).
    state : ndarray
        The state there, in the kernel's ``STATE`` order.
    names : tuple of str
        ``STATE``.
    members : str or None
        In a sweep: the members that left the plane, earliest first, each by its index in the sweep (also when run
        in chunks) and its time (the earliest's is ``t``).

    Examples
    --------
    >>> err = LiftOff(0.25, [1.0, 2.0], ("a", "b"))
    >>> print(err)
    the body left the plane at t = 0.25: its normal force fell to 0 (lift-off); the contact equations hold only while it touches — eulersym models no flight and no impact
    """

    def __init__(self, t, state, names=(), members=None):
        self.t = float(t)
        self.state = np.asarray(state, dtype=float)
        self.names = tuple(names)
        self.members = members
        where = f"{members}: the earliest" if members else "the body"
        super().__init__(f"{where} left the plane at t = {self.t:.10g}: its normal force fell to 0 (lift-off); the "
                         "contact equations hold only while it touches — eulersym models no flight and no impact")

    def __reduce__(self):
        return (type(self), (self.t, self.state, self.names, self.members))


@dataclass(frozen=True)
class ContactMotion:
    """The motion of a body on a plane: ``t`` (points,), ``y`` (points, state), and by name (``motion["x_cm"]``).

    Attributes
    ----------
    t, y : ndarray
    names : tuple of str
        The kernel's ``STATE``.
    contact : ndarray
        ``(points, 5)``: the kernel's ``contact`` outputs (``x_P, y_P, N, u_x, u_y``) at each point.
    invariants : ndarray
        ``(points, k)``: the kernel's proven invariants at each point (``INVARIANTS``).
    nfev : int
        Right-hand-side evaluations.

    Examples
    --------
    >>> m = ContactMotion(np.zeros(1), np.zeros((1, 2)), ("a", "b"), np.zeros((1, 5)), np.zeros((1, 0)), 0)
    >>> m["b"].shape
    (1,)
    """

    t: np.ndarray
    y: np.ndarray
    names: tuple
    contact: np.ndarray
    invariants: np.ndarray
    nfev: int

    def __getitem__(self, name: str) -> np.ndarray:
        outputs = ("x_P", "y_P", "N", "u_x", "u_y")
        if name in self.names:
            return self.y[:, self.names.index(name)]
        if name in outputs:
            return self.contact[:, outputs.index(name)]
        raise InvalidInput("name", name, f"one of {', '.join(self.names + outputs)}")


def _params(kernel, params) -> tuple:
    if params is None:
        return tuple(kernel.DEFAULTS)
    if isinstance(params, dict):
        unknown = sorted(set(params) - set(kernel.PARAMETERS))
        if unknown:
            raise InvalidInput("params", unknown[0], f"one of the parameters {', '.join(kernel.PARAMETERS)}")
        values = dict(zip(kernel.PARAMETERS, kernel.DEFAULTS))
        values.update(params)
        return tuple(float(values[p]) for p in kernel.PARAMETERS)
    values = tuple(finite_array("params", params, shape=(len(kernel.PARAMETERS),)).tolist())
    return values


def _vertical(q) -> np.ndarray:
    """``Γ = A(q) ẑ``: the third column of ``A = R(q)ᵀ`` (q unit, scalar first)."""
    q0, q1, q2, q3 = q
    return np.array([2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3])


def start(kernel, *, omega, q=(1.0, 0.0, 0.0, 0.0), position=(0.0, 0.0), velocity=None, params=None,
          t: float = 0.0) -> np.ndarray:
    """The initial state of a contact kernel, checked: the body touches the plane and presses on it.

    Parameters
    ----------
    kernel : module
        A kernel of :mod:`eulersym.model.rolling_kernels`.
    omega : 3 floats
        The angular velocity, body components (rad/s).
    q : 4 floats
        The attitude quaternion, scalar first, ``v_space = R(q) v_body`` (normalised here); ``Γ = A(q) ẑ``.
    position : 2 or 3 floats
        The centre of mass's position in space: ``(x, y)``, or ``(x, y, z)`` — then ``z`` must be the height at
        which the body touches the plane (``z = −r_P·Γ``, from the kernel's ``contact``).
    velocity : 2 or 3 floats, optional
        The centre of mass's velocity in space. Sliding: ``(v_x, v_y)`` (default 0). Rolling: the no-slip velocity
        is fixed by ω and the attitude; a velocity, if given, must be it.
    params : sequence or dict, optional
        The parameters (default: the kernel's ``DEFAULTS``).
    t : float
        The start time (for a torque that depends on time).

    Returns
    -------
    ndarray
        ``y0`` in the kernel's ``STATE`` order.

    Raises
    ------
    eulersym.errors.InvalidInput
        A start that does not touch the plane (``initial.position``), a rolling velocity that slips
        (``initial.velocity``), a normal force ``N ≤ 0`` there (``initial.omega``: the body would leave the plane
        at once), or a bad shape.

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> from eulersym.model.rolling_kernels import compile
    >>> kernel = compile(examples()["rolling-sphere"])
    >>> start(kernel, omega=(0, 0, 0), position=(0, 0, 0.2))
    Traceback (most recent call last):
    ...
    eulersym.errors.InvalidInput: initial.position=[0.0, 0.0, 0.2] is not valid: expected a centre of mass at the height where the body touches the plane: z = 0.1 (here z = 0.2)
    """
    params = _params(kernel, params)
    omega = finite_array("initial.omega", omega, shape=(3,))
    q = finite_array("initial.q", q, shape=(4,))
    if not np.linalg.norm(q) > 0:
        raise InvalidInput("initial.q", q.tolist(), "a non-zero quaternion (scalar first)")
    q = q / np.linalg.norm(q)
    position = finite_array("initial.position", position, shape=(None,))
    if position.size not in (2, 3):
        raise InvalidInput("initial.position", position.tolist(), "(x, y) or (x, y, z) of the centre of mass")
    sliding = kernel.FLAGS["contact"] == "sliding"
    if velocity is not None:
        v = finite_array("initial.velocity", velocity, shape=(None,))
        if v.size == 3 and v[2] != 0:  # the vertical velocity follows from the contact: not the user's to give
            raise InvalidInput("initial.velocity", v.tolist(), "(v_x, v_y) of the centre of mass, or (v_x, v_y, 0): "
                               "its vertical velocity is fixed by the contact with the plane")
    y = np.concatenate([omega, _vertical(q), q, position[:2], np.zeros(2 if sliding else 0)])
    if sliding and velocity is not None:
        v = finite_array("initial.velocity", velocity, shape=(None,))
        if v.size not in (2, 3):
            raise InvalidInput("initial.velocity", v.tolist(), "(v_x, v_y) of the centre of mass (space)")
        y[-2:] = v[:2]
    try:
        rates = kernel.rhs(t, y, *params)
    except ZeroDivisionError:  # the contact point is not one point at this attitude
        if kernel.FLAGS.get("surface") == "disk":
            raise InvalidInput("initial.q", q.tolist(), "an attitude with the rim down: the disk lies flat, its rim "
                               "does not touch at one point (give [initial] axis and angle, or q, that tilt it)") from None
        raise InvalidInput("initial.q", q.tolist(), "an attitude where the body touches the plane at one point (its "
                           "contact point is not defined here)") from None
    if position.size == 3:
        height = kernel.height(t, y, *params)[0]
        if abs(position[2] - height) > 1e-9 * max(1.0, abs(height)):
            raise InvalidInput("initial.position", position.tolist(), "a centre of mass at the height where the body "
                               f"touches the plane: z = {height:.10g} (here z = {position[2]:.10g})")
    if not sliding and velocity is not None:
        v = finite_array("initial.velocity", velocity, shape=(None,))
        rolling = np.array(rates[10:12])
        if v.size not in (2, 3) or np.max(np.abs(v[:2] - rolling)) > 1e-9 * max(1.0, np.max(np.abs(rolling))):
            raise InvalidInput("initial.velocity", v.tolist(), "the rolling velocity r_P × ω that no slip fixes: "
                               f"(v_x, v_y) = ({rolling[0]:.10g}, {rolling[1]:.10g})")
    normal = kernel.normal_force(t, y, *params)[0]
    if not normal > 0:
        raise InvalidInput("initial.omega", omega.tolist(), f"a start that presses on the plane: the normal force "
                           f"there is N = {normal:.6g} <= 0 (the body would leave the plane at once)")
    return y


def integrate(kernel, y0, t_eval, *, params=None, method: str = "DOP853", rtol: float = 1e-10,
              atol: float = 1e-12, max_step: float = np.inf, compiled: bool | None = None) -> ContactMotion:
    """Integrate a contact kernel, stopping at lift-off: on eulersym's compiled DOP853, else
    :func:`scipy.integrate.solve_ivp`.

    With ``method = "DOP853"``, no ``max_step`` and numba installed (the ``fast`` extra), the kernel runs on
    :func:`eulersym.numerics.methods._dop853.integrate` (:func:`integrate_members`): the normal force is checked on a
    grid at least as fine as the accepted steps (as solve_ivp's event checks it once a step), and where it falls
    to 0 the time is located by Brent's method on re-runs from the last sample that pressed on the plane. Otherwise
    (or ``compiled=False``) solve_ivp runs with the kernel's ``lift_off`` event.

    Parameters
    ----------
    kernel : module
        A kernel of :mod:`eulersym.model.rolling_kernels`.
    y0 : array of floats
        The initial state (:func:`start`).
    t_eval : array of floats
        The output times, increasing; the run spans ``t_eval[0] .. t_eval[-1]``.
    params : sequence or dict, optional
        The parameters (default: the kernel's ``DEFAULTS``).
    method : str
        ``DOP853`` (default), ``RK45``, ``RK23``, or an implicit method (``Radau``, ``BDF``, ``LSODA``: the
        kernel's Jacobian is used).
    rtol, atol, max_step : float
        The tolerances (SciPy's norm: local error per step ≤ atol + rtol |y|) and solve_ivp's largest step.
    compiled : bool or None
        Run on the compiled DOP853 (True: refused, naming what is missing, where it cannot), on solve_ivp
        (False), or the compiled one where it applies (None).

    Returns
    -------
    ContactMotion

    Raises
    ------
    LiftOff
        The normal force fell to zero: the body left the plane at ``err.t``.
    eulersym.errors.CheckFailed
        The integrator failed (its message says why).

    Examples
    --------
    >>> from eulersym.model.contact_examples import examples
    >>> from eulersym.model.rolling_kernels import compile
    >>> kernel = compile(examples()["chaplygin-ball"])
    >>> motion = integrate(kernel, start(kernel, omega=(1.0, 2.0, 3.0)), np.linspace(0, 2, 5))
    >>> bool(np.ptp(motion.invariants[:, 0]) < 1e-9 * motion.invariants[0, 0])   # the energy
    True
    """
    from scipy.integrate import solve_ivp

    params = _params(kernel, params)
    y0 = finite_array("y0", y0, shape=(len(kernel.STATE),))
    t_eval = finite_array("t_eval", t_eval, shape=(None,))
    if t_eval.size < 1 or np.any(np.diff(t_eval) < 0):
        raise InvalidInput("t_eval", t_eval.tolist(), "increasing output times (at least one)")
    if method not in _METHODS:
        raise InvalidInput("method", method, "one of " + ", ".join(_METHODS))
    if not kernel.normal_force(float(t_eval[0]), y0, *params)[0] > 0:
        raise InvalidInput("y0", y0.tolist(), "a state that presses on the plane (normal force N > 0)")
    applies = method == "DOP853" and not np.isfinite(max_step) and numba_available()
    if compiled and not applies:
        raise InvalidInput("compiled", compiled, "False or None here: the compiled DOP853 needs method = 'DOP853', "
                           "no max_step and numba installed (the fast extra)")
    if applies and compiled is not False:
        return _compiled_run(kernel, y0, t_eval, params, rtol, atol)
    options = {"jac": kernel.jac} if method in _IMPLICIT else {}
    span = (float(t_eval[0]), float(t_eval[-1]))
    sol = solve_ivp(kernel.rhs, span, y0, method=method, t_eval=t_eval, args=params, events=kernel.lift_off,
                    rtol=rtol, atol=atol, max_step=max_step, **options)
    if sol.status == 1 and len(sol.t_events[0]):
        raise LiftOff(sol.t_events[0][0], sol.y_events[0][0], kernel.STATE)
    if not sol.success:
        raise CheckFailed(f"solve_ivp ({method}) failed: {sol.message}")
    return _finish(kernel, sol.t, sol.y.T, params, sol.nfev)


def _finish(kernel, t, y, params, nfev) -> ContactMotion:
    contact = kernel.contact_batched(t, y.T, *params).T if len(t) else np.zeros((0, 5))
    invariants = (kernel.invariants_batched(t, y.T, *params).T if len(t)
                  else np.zeros((0, len(kernel.INVARIANTS))))
    return ContactMotion(t, y, tuple(kernel.STATE), contact, invariants, int(nfev))


def integrate_members(kernel, y0, t_eval, params, *, rtol, atol, steps=None) -> tuple:
    """Every member of a contact kernel at once on eulersym's compiled DOP853 (each member its own step, the members
    over the cores), lift-off caught per member (arguments checked by the caller).

    One run over ``t_eval`` (cut for ``steps`` when given) gives the motions and each member's number of accepted
    steps; where the steps outnumber the samples it is run again with each interval cut into
    ``ceil(steps / intervals)`` equal parts (the largest member's count, shared) — the same steps (dense output
    changes no step), so the same motion at ``t_eval`` — and the normal force is evaluated at every sample. At a member's first sample where ``N ≤ 0`` the
    lift-off time is located between it and the sample before by :func:`scipy.optimize.brentq` on ``N(s)``, the
    state at ``s`` integrated from that earlier sample (to the solver's own tolerance, ``4 ε``, as solve_ivp's
    event). A dip of ``N`` below 0 and back inside one sample interval (shorter than a step, on average) is not
    seen — nor by solve_ivp's event, which checks once a step. The samples of all members are at most
    :data:`MAX_SAMPLES` (their states are held at once: ~112 MB for 14 components); a run of more steps is sampled
    that finely, no finer.

    Parameters
    ----------
    kernel : module
    y0 : ndarray (batch, n)
    t_eval : ndarray (m,)
    params : ndarray (batch, k)
    rtol, atol : ndarray (batch,)
    steps : int, optional
        The accepted steps the members are expected to take at most (a run at a nearby tolerance): the samples are
        then cut for that many at once, in one run — and the run is made again finer only if a member took more.

    Returns
    -------
    tuple
        ``(y, calls, lifted, steps)``: the states at ``t_eval`` (batch, m, n) (a member that lifted off:
        unspecified), the right-hand-side evaluations per member, ``[(member, LiftOff), ...]``, and the accepted
        steps per member.

    Raises
    ------
    eulersym.errors.CheckFailed
        A member the integrator could not carry (its reason), that did not lift off.
    """
    import eulersym.numerics.methods._dop853 as _dop853

    y0 = np.atleast_2d(np.asarray(y0, dtype=float))
    params = np.asarray(params, dtype=float).reshape(len(y0), -1)
    rtol = np.broadcast_to(np.asarray(rtol, dtype=float), (len(y0),))
    atol = np.broadcast_to(np.asarray(atol, dtype=float), (len(y0),))
    batch, intervals = len(y0), t_eval.size - 1
    cap = max(1, MAX_SAMPLES // max(1, intervals * batch))

    def cut(most):  # output intervals cut into equal parts, at least as many as the steps (within the cap)
        return min(int(-(-int(most) // intervals)), cap) if intervals else 1

    def sampled(sub):
        if sub <= 1:
            return t_eval
        cuts = t_eval[:-1, None] + np.diff(t_eval)[:, None] * (np.arange(sub) / sub)  # [:, 0] is t_eval exactly
        return np.concatenate([cuts.ravel(), t_eval[-1:]])

    sub = cut(steps) if steps is not None else 1
    run = _dop853.integrate(kernel, y0, sampled(sub), params, rtol=rtol, atol=atol, parallel=batch > 1)
    calls = run.calls
    need = cut(np.max(run.steps)) if batch else 1
    if need > sub:  # a member stepped more often than it was sampled: again, as finely as it steps
        sub = need
        run = _dop853.integrate(kernel, y0, sampled(sub), params, rtol=rtol, atol=atol, parallel=batch > 1)
        calls = calls + run.calls
    grid = sampled(sub)
    ok = run.status == _dop853.OK
    written = np.where(ok, grid.size, np.searchsorted(grid, run.reached, side="right"))
    n, G = y0.shape[1], grid.size
    normal = kernel.normal_force_batched(np.tile(grid, batch), np.moveaxis(run.y, 2, 0).reshape(n, batch * G),
                                         *np.repeat(params, G, axis=0).T)[0].reshape(batch, G)
    pressing = (normal > 0) | (np.arange(G)[None, :] >= written[:, None])
    lifted = []
    for b in range(batch):
        P = tuple(params[b].tolist())
        try:
            if not pressing[b].all():
                j = int(np.argmin(pressing[b]))  # the first sample that does not press (j ≥ 1: y0 was checked)
                _lift_off(kernel, grid[j - 1], run.y[b, j - 1], grid[j], P, rtol[b], atol[b])
            if not ok[b]:
                reached = float(run.reached[b])
                if not kernel.normal_force(reached, run.last[b], *P)[0] > 0:
                    _lift_off(kernel, grid[written[b] - 1], run.y[b, written[b] - 1], reached, P, rtol[b], atol[b])
                raise CheckFailed(f"the compiled DOP853 stopped at t = {reached:.10g}"
                                  + (f" (member {b})" if batch > 1 else "") + f": {_dop853.STATUS[int(run.status[b])]}")
        except LiftOff as exc:
            lifted.append((b, exc))
    return run.y[:, ::sub], calls, lifted, run.steps


def _compiled_run(kernel, y0, t_eval, params, rtol, atol) -> ContactMotion:
    """:func:`integrate` on eulersym's compiled DOP853 (:func:`integrate_members` with one member)."""
    y, calls, lifted, _ = integrate_members(kernel, [y0], t_eval, [params], rtol=rtol, atol=atol)
    if lifted:
        raise lifted[0][1]
    return _finish(kernel, t_eval, y[0], params, int(calls[0]))


def _lift_off(kernel, ta, ya, tb, params, rtol, atol):
    """Raise :class:`LiftOff` at the root of the normal force in ``(ta, tb]`` (``N(ta) > 0 ≥ N(tb)``)."""
    from scipy.optimize import brentq

    import eulersym.numerics.methods._dop853 as _dop853

    def state(s):
        return _dop853.integrate(kernel, [ya], [ta, s], [params], rtol=rtol, atol=atol, parallel=False).y[0, -1]

    def normal(s):
        return kernel.normal_force(s, state(s), *params)[0] if s > ta else kernel.normal_force(ta, ya, *params)[0]

    if normal(tb) == 0.0:
        t = tb
    else:
        eps = 4 * np.finfo(float).eps
        t = brentq(normal, ta, tb, xtol=eps, rtol=eps)
    raise LiftOff(t, state(t), kernel.STATE)
